/* LD_PRELOAD shim for test_mpi: with CLR_FAULT_MPI_EXIT_RANK=R the MPI rank R exits (status 3)
 * at its first band claim (MPI_Fetch_and_op), as a rank that dies in the middle of a frame. The
 * renderer has no test switch; the call goes on to the MPI library through its profiling
 * interface (PMPI_) otherwise. */
#include <mpi.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

int MPI_Fetch_and_op(const void *origin, void *result, MPI_Datatype type, int target,
                     MPI_Aint displacement, MPI_Op op, MPI_Win win) {
  const char *die = getenv("CLR_FAULT_MPI_EXIT_RANK"), *me = getenv("OMPI_COMM_WORLD_RANK");
  if (die && me && strcmp(die, me) == 0) _exit(3);
  return PMPI_Fetch_and_op(origin, result, type, target, displacement, op, win);
}
