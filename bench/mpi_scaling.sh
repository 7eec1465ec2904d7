#!/usr/bin/env bash
# Distributed render scaling: one render of SCENE alone, then under `mpirun -np N` for N in
# RANKS (one thread per rank), as JSON lines: wall seconds, speed-up against the lone process of
# the same run, bytes sent to rank 0 per frame, tiles and band-claim seconds per rank (from the
# EXR attributes clrender.mpi.*). Loopback only (btl self,vader); beyond the machine's cores the
# ranks are oversubscribed, so that figure is an overhead check, not a speed-up.
# usage: bench/mpi_scaling.sh BUILD_DIR [SCENE] [SPP] [RANKS...]
set -euo pipefail
build=${1:?usage: bench/mpi_scaling.sh BUILD_DIR [SCENE] [SPP] [RANKS...]}
scene=${2:-$(dirname "$0")/../scenes/cornell-box.pbrt}
spp=${3:-16}
shift $(( $# < 3 ? $# : 3 ))
ranks=("$@")
[ ${#ranks[@]} -gt 0 ] || ranks=(1 2 4)
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_btl=self,vader
# No core binding: a pinned rank shares its core with its own threads and with other work.
export OMPI_MCA_hwloc_base_binding_policy=none
export OMPI_MCA_plm=isolated # this machine only
out=$(mktemp -d "$build/mpi_bench_XXXXXX")
trap 'rm -rf "$out"' EXIT
flags=(--spp "$spp" --nthreads 1 --quiet)

seconds() { local t0 t1; t0=$(date +%s.%N); "$@"; t1=$(date +%s.%N); awk "BEGIN{print $t1 - $t0}"; }
attr() { exrheader "$1" | sed -n "s/^$2 (type string): \"\(.*\)\"/\1/p"; }

alone=$(seconds "$build/clrender" render "$scene" "${flags[@]}" --outfile "$out/alone.exr")
printf '{"ranks":0,"mpirun":false,"seconds":%.3f,"speedup":1.000}\n' "$alone"
for n in "${ranks[@]}"; do
  t=$(seconds mpirun --oversubscribe -np "$n" "$build/clrender" render "$scene" "${flags[@]}" \
        --outfile "$out/np$n.exr")
  printf '{"ranks":%d,"mpirun":true,"seconds":%.3f,"speedup":%.3f,"bytes_to_rank0":%s,' \
    "$n" "$t" "$(awk "BEGIN{print $alone / $t}")" "$(attr "$out/np$n.exr" clrender.mpi.bytes_to_rank0)"
  printf '"rank_tiles":"%s","rank_seconds":"%s","rank_claims":"%s","rank_claim_seconds":"%s"}\n' \
    "$(attr "$out/np$n.exr" clrender.mpi.rank_tiles)" \
    "$(attr "$out/np$n.exr" clrender.mpi.rank_seconds)" \
    "$(attr "$out/np$n.exr" clrender.mpi.rank_claims)" \
    "$(attr "$out/np$n.exr" clrender.mpi.rank_claim_seconds)"
done
