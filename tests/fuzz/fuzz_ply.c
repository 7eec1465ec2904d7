/* Fuzz target: PLY meshes (ASCII, binary little/big endian) through clr_ply_read. */
#include "fuzz_common.h"
#include "ply_reader.h"

static fuzz_file input;

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  clr_mesh mesh;
  clr_result r = clr_ply_read(fuzz_file_write(&input, data, size), &mesh);
  fuzz_report("clr_ply_read", r);
  if (r == CLR_SUCCESS) clr_mesh_free(&mesh);
  return 0;
}
