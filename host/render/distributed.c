/* Distributed rendering over MPI (see distributed.h); stubs when built without MPI. */
#include "distributed.h"
#include <stdlib.h>
#include <string.h>
#include "render_error.h"

#if CLR_HAVE_MPI
#include <mpi.h>
#include <stdio.h>

#define META 7 /* EXR attributes: ranks, five per-rank lists, bytes */

struct clr_dist {
  int rank, size, local_rank;
  MPI_Win win;      /* the band counter, on rank 0 */
  int32_t *counter; /* its memory (rank 0) */
  int32_t nbands, ntiles;
  double claim_seconds; /* this frame's band claims */
  uint64_t claims;
  char *kept; /* records {int32 tile, uint32 bytes, tile bytes} */
  size_t kept_size, kept_cap;
  clr_dist_rank_stats *stats; /* rank 0: per rank, summed over the frames (passes) */
  uint64_t bytes;             /* rank 0: bytes received, summed over the frames */
  char *meta[META];           /* rank 0: the attribute values */
};

/* What each rank sends rank 0 before its tiles. */
typedef struct rank_header {
  int32_t status, reserved;
  uint64_t bytes;
  clr_dist_rank_stats stats;
  char message[512];
} rank_header;

#define RECORD_HEAD (2 * sizeof(int32_t))
#define CHUNK_BYTES ((size_t)1 << 30)

static clr_dist world;
static int started;

/* Open MPI's launcher, PMIx or a PMI launcher (MPICH's Hydra) started this process. */
static int launched_by_mpirun(void) {
  return getenv("OMPI_COMM_WORLD_SIZE") || getenv("PMIX_RANK") || getenv("PMI_SIZE");
}

int clr_dist_init(int *argc, char ***argv) {
  if (started || !launched_by_mpirun()) return 0;
  int provided = 0;
  if (MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS) return -1;
  MPI_Comm node;
  MPI_Comm_rank(MPI_COMM_WORLD, &world.rank);
  MPI_Comm_size(MPI_COMM_WORLD, &world.size);
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, world.rank, MPI_INFO_NULL, &node);
  MPI_Comm_rank(node, &world.local_rank);
  MPI_Comm_free(&node);
  world.win = MPI_WIN_NULL;
  started = 1;
  return 0;
}

void clr_dist_finalize(int exit_status) {
  if (!started) return;
  if (exit_status != 0) MPI_Abort(MPI_COMM_WORLD, exit_status);
  free(world.kept);
  free(world.stats);
  for (int i = 0; i < META; ++i) free(world.meta[i]);
  memset(&world, 0, sizeof world);
  MPI_Finalize();
  started = 0;
}

clr_dist *clr_dist_world(void) { return started ? &world : NULL; }
int clr_dist_rank(const clr_dist *d) { return d ? d->rank : 0; }
int clr_dist_size(const clr_dist *d) { return d ? d->size : 1; }
int clr_dist_local_rank(const clr_dist *d) { return d ? d->local_rank : 0; }

clr_result clr_dist_begin_frame(clr_dist *d, int32_t nbands, int32_t ntiles) {
  int32_t mine[2] = {nbands, ntiles}, lo[2], hi[2];
  MPI_Allreduce(mine, lo, 2, MPI_INT32_T, MPI_MIN, MPI_COMM_WORLD);
  MPI_Allreduce(mine, hi, 2, MPI_INT32_T, MPI_MAX, MPI_COMM_WORLD);
  if (lo[0] != hi[0] || lo[1] != hi[1])
    return clr_set_last_error(CLR_ERROR_INVALID_ARGUMENT,
                              "MPI ranks disagree on the frame (%d..%d bands, %d..%d tiles): every "
                              "rank must render the same scene with the same options",
                              lo[0], hi[0], lo[1], hi[1]);
  d->nbands = nbands;
  d->ntiles = ntiles;
  d->kept_size = 0;
  MPI_Aint bytes = d->rank == 0 ? (MPI_Aint)sizeof(int32_t) : 0;
  if (MPI_Win_allocate(bytes, sizeof(int32_t), MPI_INFO_NULL, MPI_COMM_WORLD, &d->counter,
                       &d->win) != MPI_SUCCESS)
    return clr_set_last_error(CLR_ERROR_INTERNAL, "MPI_Win_allocate failed");
  if (d->rank == 0) {
    MPI_Win_lock(MPI_LOCK_EXCLUSIVE, 0, 0, d->win);
    *d->counter = 0;
    MPI_Win_unlock(0, d->win);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  return CLR_SUCCESS;
}

clr_result clr_dist_claim_band(clr_dist *d, int32_t *band) {
  int32_t one = 1, got = 0;
  double t0 = MPI_Wtime();
  MPI_Win_lock(MPI_LOCK_SHARED, 0, 0, d->win);
  MPI_Fetch_and_op(&one, &got, MPI_INT32_T, 0, 0, MPI_SUM, d->win);
  MPI_Win_unlock(0, d->win);
  *band = got < d->nbands ? got : -1;
  d->claim_seconds += MPI_Wtime() - t0;
  d->claims++;
  return CLR_SUCCESS;
}

clr_result clr_dist_keep_tile(clr_dist *d, int32_t tile_index, clr_film_tile tile) {
  size_t n = film_tile_serialized_size(tile), need = d->kept_size + RECORD_HEAD + n;
  if (n > UINT32_MAX) return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "film tile of %zu B", n);
  if (need > d->kept_cap) {
    size_t cap = d->kept_cap ? d->kept_cap : 1 << 20;
    while (cap < need) cap *= 2;
    char *grown = realloc(d->kept, cap);
    if (!grown) return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "kept tiles (%zu B)", cap);
    d->kept = grown;
    d->kept_cap = cap;
  }
  int32_t head[2] = {tile_index, (int32_t)(uint32_t)n};
  memcpy(d->kept + d->kept_size, head, RECORD_HEAD);
  CLR_CHECK(film_tile_serialize(tile, d->kept + d->kept_size + RECORD_HEAD, n));
  d->kept_size = need;
  return CLR_SUCCESS;
}

static void send_bytes(const char *p, size_t n) {
  for (size_t off = 0; off < n; off += CHUNK_BYTES) {
    size_t k = n - off < CHUNK_BYTES ? n - off : CHUNK_BYTES;
    MPI_Send(p + off, (int)k, MPI_BYTE, 0, 2, MPI_COMM_WORLD);
  }
}

static void recv_bytes(char *p, size_t n, int from) {
  for (size_t off = 0; off < n; off += CHUNK_BYTES) {
    size_t k = n - off < CHUNK_BYTES ? n - off : CHUNK_BYTES;
    MPI_Recv(p + off, (int)k, MPI_BYTE, from, 2, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  }
}

/* Indexes one rank's records by tile: where[t] points at tile t's bytes, size[t] their count. */
static clr_result index_records(const char *buf, size_t n, int rank, int32_t ntiles,
                                const char **where, uint32_t *size) {
  size_t off = 0;
  while (off < n) {
    int32_t head[2];
    if (n - off < RECORD_HEAD)
      return clr_set_last_error(CLR_ERROR_INTERNAL, "rank %d sent a truncated tile", rank);
    memcpy(head, buf + off, RECORD_HEAD);
    uint32_t bytes = (uint32_t)head[1];
    if (head[0] < 0 || head[0] >= ntiles || where[head[0]] || bytes > n - off - RECORD_HEAD)
      return clr_set_last_error(CLR_ERROR_INTERNAL, "rank %d sent a bad or duplicate tile %d", rank,
                                head[0]);
    where[head[0]] = buf + off + RECORD_HEAD;
    size[head[0]] = bytes;
    off += RECORD_HEAD + bytes;
  }
  return CLR_SUCCESS;
}

static void add_stats(clr_dist_rank_stats *sum, const clr_dist_rank_stats *s) {
  sum->samples += s->samples;
  sum->rays += s->rays;
  sum->tiles += s->tiles;
  sum->seconds += s->seconds;
  sum->claim_seconds += s->claim_seconds;
  sum->claims += s->claims;
}

/* Rank 0: receives every rank's tiles, then merges all of them in tile order. */
static clr_result gather_and_merge(clr_dist *d, clr_film film, clr_result status,
                                   const clr_dist_rank_stats *mine, clr_dist_rank_stats *stats,
                                   int32_t *missing, uint64_t *total) {
  *missing = d->ntiles;
  char **bufs = calloc((size_t)d->size, sizeof *bufs);
  const char **where = calloc((size_t)d->ntiles + 1, sizeof *where);
  uint32_t *size = calloc((size_t)d->ntiles + 1, sizeof *size);
  clr_result r =
      bufs && where && size ? status : clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "tile index");
  if (stats) add_stats(&stats[0], mine); /* summed over the render's passes */
  for (int k = 1; k < d->size; ++k) {    /* receive from everyone, even after a failure */
    rank_header h;
    MPI_Recv(&h, (int)sizeof h, MPI_BYTE, k, 1, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (stats) add_stats(&stats[k], &h.stats);
    char *buf = h.status == CLR_SUCCESS ? malloc(h.bytes ? h.bytes : 1) : NULL;
    if (h.status == CLR_SUCCESS) recv_bytes(buf ? buf : NULL, buf ? h.bytes : 0, k);
    *total += h.bytes + sizeof h;
    if (bufs) bufs[k] = buf;
    h.message[sizeof h.message - 1] = 0;
    if (r == CLR_SUCCESS && h.status != CLR_SUCCESS)
      r = clr_set_last_error((clr_result)h.status, "MPI rank %d failed: %s", k, h.message);
    else if (r == CLR_SUCCESS && !buf && h.bytes)
      r = clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "tiles of rank %d (%llu B)", k,
                             (unsigned long long)h.bytes);
    else if (r == CLR_SUCCESS)
      r = index_records(buf, h.bytes, k, d->ntiles, where, size);
  }
  if (r == CLR_SUCCESS) r = index_records(d->kept, d->kept_size, 0, d->ntiles, where, size);
  *missing = 0;
  for (int32_t t = 0; r == CLR_SUCCESS && t < d->ntiles; ++t) {
    if (!where[t]) {
      ++*missing;
      continue;
    }
    clr_film_tile tile = NULL;
    r = film_tile_deserialize(film, where[t], size[t], &tile);
    if (r == CLR_SUCCESS) r = film_merge_tile(film, tile);
    film_tile_release(tile);
  }
  for (int k = 0; bufs && k < d->size; ++k) free(bufs[k]);
  free(bufs);
  free(where);
  free(size);
  return r;
}

clr_result clr_dist_end_frame(clr_dist *d, clr_film film, clr_result status,
                              const clr_dist_rank_stats *mine_in, int32_t *missing) {
  clr_dist_rank_stats own = *mine_in, *mine = &own;
  own.claim_seconds = d->claim_seconds;
  own.claims = d->claims;
  d->claim_seconds = 0.0;
  d->claims = 0;
  MPI_Win_free(&d->win);
  d->counter = NULL;
  *missing = 0;
  clr_result r;
  if (d->rank == 0) {
    if (!d->stats) d->stats = calloc((size_t)d->size, sizeof *d->stats);
    r = gather_and_merge(d, film, status, mine, d->stats, missing, &d->bytes);
  } else {
    rank_header h;
    memset(&h, 0, sizeof h);
    h.status = status;
    h.bytes = status == CLR_SUCCESS ? d->kept_size : 0;
    h.stats = *mine;
    if (status != CLR_SUCCESS)
      snprintf(h.message, sizeof h.message, "%s", clr_last_error_message());
    MPI_Send(&h, (int)sizeof h, MPI_BYTE, 0, 1, MPI_COMM_WORLD);
    if (status == CLR_SUCCESS) send_bytes(d->kept, d->kept_size);
    r = status;
  }
  d->kept_size = 0;
  return r;
}

void clr_dist_share(clr_dist *d, int32_t *value) {
  (void)d;
  MPI_Bcast(value, 1, MPI_INT32_T, 0, MPI_COMM_WORLD);
}

void clr_dist_share_bytes(clr_dist *d, void *p, size_t size) {
  (void)d;
  for (size_t off = 0; off < size; off += CHUNK_BYTES) {
    size_t k = size - off < CHUNK_BYTES ? size - off : CHUNK_BYTES;
    MPI_Bcast((char *)p + off, (int)k, MPI_BYTE, 0, MPI_COMM_WORLD);
  }
}

/* A comma list of one figure per rank (malloc'ed). */
static char *rank_list(const clr_dist *d, int which) {
  size_t cap = (size_t)d->size * 24 + 1, len = 0;
  char *s = malloc(cap);
  if (!s) return NULL;
  s[0] = 0;
  for (int k = 0; k < d->size; ++k) {
    const clr_dist_rank_stats *st = &d->stats[k];
    const char *sep = k ? "," : "";
    if (which == 0)
      len += (size_t)snprintf(s + len, cap - len, "%s%llu", sep, (unsigned long long)st->samples);
    else if (which == 1)
      len += (size_t)snprintf(s + len, cap - len, "%s%llu", sep, (unsigned long long)st->tiles);
    else if (which == 2)
      len += (size_t)snprintf(s + len, cap - len, "%s%.3f", sep, st->seconds);
    else if (which == 3)
      len += (size_t)snprintf(s + len, cap - len, "%s%llu", sep, (unsigned long long)st->claims);
    else
      len += (size_t)snprintf(s + len, cap - len, "%s%.6f", sep, st->claim_seconds);
  }
  return s;
}

int clr_dist_metadata(clr_dist *d, const char **keys, const char **values, int max) {
  static const char *names[META] = {"clrender.mpi.ranks",         "clrender.mpi.rank_samples",
                                    "clrender.mpi.rank_tiles",    "clrender.mpi.rank_seconds",
                                    "clrender.mpi.rank_claims",   "clrender.mpi.rank_claim_seconds",
                                    "clrender.mpi.bytes_to_rank0"};
  if (!d || d->rank != 0 || !d->stats) return 0;
  for (int i = 0; i < META; ++i) free(d->meta[i]);
  d->meta[0] = malloc(16);
  if (d->meta[0]) snprintf(d->meta[0], 16, "%d", d->size);
  for (int i = 0; i < 5; ++i) d->meta[1 + i] = rank_list(d, i);
  d->meta[6] = malloc(24);
  if (d->meta[6]) snprintf(d->meta[6], 24, "%llu", (unsigned long long)d->bytes);
  int n = 0;
  for (int i = 0; i < META && n < max; ++i)
    if (d->meta[i]) {
      keys[n] = names[i];
      values[n++] = d->meta[i];
    }
  return n;
}

#else /* built without MPI: one process */

int clr_dist_init(int *argc, char ***argv) {
  (void)argc;
  (void)argv;
  return 0;
}
void clr_dist_finalize(int exit_status) { (void)exit_status; }
clr_dist *clr_dist_world(void) { return NULL; }
int clr_dist_rank(const clr_dist *d) { return (void)d, 0; }
int clr_dist_size(const clr_dist *d) { return (void)d, 1; }
int clr_dist_local_rank(const clr_dist *d) { return (void)d, 0; }
clr_result clr_dist_begin_frame(clr_dist *d, int32_t nbands, int32_t ntiles) {
  (void)d, (void)nbands, (void)ntiles;
  return clr_set_last_error(CLR_ERROR_INTERNAL, "built without MPI");
}
clr_result clr_dist_claim_band(clr_dist *d, int32_t *band) {
  (void)d;
  *band = -1;
  return CLR_SUCCESS;
}
clr_result clr_dist_keep_tile(clr_dist *d, int32_t tile_index, clr_film_tile tile) {
  (void)d, (void)tile_index, (void)tile;
  return clr_set_last_error(CLR_ERROR_INTERNAL, "built without MPI");
}
clr_result clr_dist_end_frame(clr_dist *d, clr_film film, clr_result status,
                              const clr_dist_rank_stats *mine, int32_t *missing) {
  (void)d, (void)film, (void)mine;
  *missing = 0;
  return status;
}
void clr_dist_share(clr_dist *d, int32_t *value) { (void)d, (void)value; }
void clr_dist_share_bytes(clr_dist *d, void *p, size_t size) { (void)d, (void)p, (void)size; }
int clr_dist_metadata(clr_dist *d, const char **keys, const char **values, int max) {
  (void)d, (void)keys, (void)values, (void)max;
  return 0;
}
#endif
