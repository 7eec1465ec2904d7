/* Distributed rendering over MPI: the ranks of `mpirun -np N clrender render ...` share one
 * frame. Ranks claim bands of tiles from a counter on rank 0 (one MPI_Fetch_and_op per band, so
 * a slow rank simply claims fewer), keep their finished film tiles serialized, and send them to
 * rank 0, which merges every tile in tile order: the film is bit-identical to a single-process
 * render. Without MPI (or not started by mpirun) every call is a no-op and clr_dist_world()
 * returns NULL. Only the thread that called clr_dist_init may call these. */
#ifndef CLR_DISTRIBUTED_H
#define CLR_DISTRIBUTED_H

#include <stdint.h>
#include "clrender/film.h"

typedef struct clr_dist clr_dist;

/* Per-rank figures rank 0 receives with the tiles. */
typedef struct clr_dist_rank_stats {
  uint64_t samples, rays, tiles;
  double seconds;       /* wall time of the rank's tile loop */
  double claim_seconds; /* of it, waiting for band claims (filled by clr_dist_end_frame) */
  uint64_t claims;
} clr_dist_rank_stats;

/* Starts MPI when this process was launched by mpirun (Open MPI's or a PMI launcher's
 * environment), else does nothing. Returns 0 on success. */
int clr_dist_init(int *argc, char ***argv);
/* Ends MPI (collective: every rank calls it once); exit_status non-zero on this rank aborts the
 * whole job with that status instead, so no rank waits for a failed one. */
void clr_dist_finalize(int exit_status);
/* The started world, or NULL when this process runs alone. */
clr_dist *clr_dist_world(void);
int clr_dist_rank(const clr_dist *d);
int clr_dist_size(const clr_dist *d);
int clr_dist_local_rank(const clr_dist *d); /* rank among the ranks on this node */

/* Collective: every rank agrees on the frame's band count (a mismatch fails on every rank) and
 * creates the claim counter. */
clr_result clr_dist_begin_frame(clr_dist *d, int32_t nbands, int32_t ntiles);
/* Claims the next band: *band = its index, or -1 when every band is taken. */
clr_result clr_dist_claim_band(clr_dist *d, int32_t *band);
/* Keeps a finished film tile (serialized) for rank 0; the caller still releases the tile. */
clr_result clr_dist_keep_tile(clr_dist *d, int32_t tile_index, clr_film_tile tile);
/* Collective: ranks send their tiles and figures to rank 0, which merges every tile into `film`
 * in tile order. `status` is this rank's result so far (a failed rank sends no tiles and rank 0
 * fails naming it and its message). On rank 0 *missing is the number of tiles no rank rendered
 * (a cancelled rank). */
clr_result clr_dist_end_frame(clr_dist *d, clr_film film, clr_result status,
                              const clr_dist_rank_stats *mine, int32_t *missing);
/* Collective: every rank gets rank 0's *value (a decision all ranks must share). */
void clr_dist_share(clr_dist *d, int32_t *value);
/* Collective: every rank gets rank 0's `size` bytes at p. */
void clr_dist_share_bytes(clr_dist *d, void *p, size_t size);
/* Rank 0, after clr_dist_end_frame: the EXR attributes of the frames so far (a render's passes) (clrender.mpi.ranks, per-rank
 * samples, tiles, seconds, claims and claim seconds as comma lists, bytes sent to rank 0) into keys/values (at most
 * `max`; the strings belong to d until the next frame). Returns the count. */
int clr_dist_metadata(clr_dist *d, const char **keys, const char **values, int max);

#endif
