#!/usr/bin/env bash
# Adaptive sampling at equal time: relative RMSE against a high-spp reference of uniform
# sampling and of --noise-threshold E, each stopped by the same --time-limit, as JSON lines.
# relRMSE = sqrt(mean over pixels and channels of (x - ref)^2 / (ref^2 + 1e-2)).
# usage: bench/adaptive_rmse.sh BUILD_DIR [SCENE] [SECONDS] [THRESHOLD] [REFERENCE_SPP]
set -euo pipefail
build=${1:?usage: bench/adaptive_rmse.sh BUILD_DIR [SCENE] [SECONDS] [THRESHOLD] [REFERENCE_SPP]}
scene=${2:-$(dirname "$0")/../scenes/cornell-box.pbrt}
seconds=${3:-4}
threshold=${4:-0.05}
ref_spp=${5:-256}
out=$(mktemp -d "$build/adaptive_bench_XXXXXX")
trap 'rm -rf "$out"' EXIT
flags=(--quiet --nthreads 2 ${CROP:+--cropwindow $CROP})
"$build/clrender" render "$scene" "${flags[@]}" --spp "$ref_spp" --seed 99 --outfile "$out/ref.pfm"
timed=(--spp 4096 --pass-spp "${PASS_SPP:-2}" --time-limit "$seconds")
"$build/clrender" render "$scene" "${flags[@]}" "${timed[@]}" --outfile "$out/uniform.pfm" \
  --stats 2> "$out/uniform.json"
"$build/clrender" render "$scene" "${flags[@]}" "${timed[@]}" --noise-threshold "$threshold" \
  --outfile "$out/adaptive.pfm" --stats 2> "$out/adaptive.json"
python3 - "$out" "$seconds" "$threshold" <<'PY'
import json, math, struct, sys
d, seconds, threshold = sys.argv[1], float(sys.argv[2]), sys.argv[3]
def pfm(path):
    with open(path, 'rb') as f:
        assert f.readline().strip() == b'PF'
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        n = w * h * 3
        return struct.unpack(('<' if scale < 0 else '>') + 'f' * n, f.read(4 * n))
ref = pfm(d + '/ref.pfm')
def rel_rmse(x):
    return math.sqrt(sum((a - r) ** 2 / (r * r + 1e-2) for a, r in zip(x, ref)) / len(ref))
for name in ('uniform', 'adaptive'):
    st = json.loads(open(d + '/' + name + '.json').read().strip().splitlines()[-1])
    print(json.dumps({'mode': name, 'threshold': threshold if name == 'adaptive' else None,
                      'time_limit_s': seconds, 'render_s': round(st['seconds']['render'], 3),
                      'spp': st['spp'], 'samples': st['samples'],
                      'rel_rmse': round(rel_rmse(pfm(d + '/' + name + '.pfm')), 5)}))
PY
