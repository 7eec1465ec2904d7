/* PLY mesh reader (ASCII, binary little and big endian) for pbrt-v3's "plymesh" shape. */
#ifndef CLR_PLY_READER_H
#define CLR_PLY_READER_H

#include "mesh.h"

/* Reads the "vertex" element's x,y,z (required), nx,ny,nz (all three or none) and the first
 * complete uv pair among u,v / s,t / texture_u,texture_v / texture_s,texture_t, and the "face"
 * element's "vertex_indices" (or "vertex_index") lists. As in pbrt-v3's plymesh.cpp, quads
 * (a,b,c,d) become triangles (a,b,c) and (d,a,c), and faces with other vertex counts are
 * skipped. Any PLY scalar or list-count type is accepted; other elements and properties are
 * skipped. A missing or unreadable file is CLR_ERROR_IO; a malformed header, truncated data,
 * non-finite positions or an out-of-range index is CLR_ERROR_FILE_FORMAT naming the file and
 * the element, instance and property. `out` is zeroed on failure. */
clr_result clr_ply_read(const char *path, clr_mesh *out);

#endif
