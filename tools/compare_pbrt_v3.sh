#!/bin/bash
# Compares clrender with a pbrt-v3 build on tests/data/scenes/v3_*.pbrt (issue #11): for each
# scene a pbrt-v3 reference at REF_SPP (default 1024), pbrt-v3 and clrender at the scene's 16 spp;
# prints relative RMSE (RMSE / reference mean) of both against the reference and clrender's mean
# ratio. Usage: tools/compare_pbrt_v3.sh PBRT [CLRENDER] [OUTDIR]; SCENES (a glob, default v3_*)
# picks scenes. Not used by the tests.
set -euo pipefail
pbrt=${1:?usage: $0 /path/to/pbrt-v3/pbrt [clrender] [outdir]}
here=$(cd "$(dirname "$0")/.." && pwd)
clr=${2:-$here/build/clrender}
out=${3:-$(mktemp -d)}
ref_spp=${REF_SPP:-1024}
mkdir -p "$out"
cp "$here"/tests/data/scenes/*.png "$out"/  # images the scenes name, beside the reference copies
printf '%-14s %12s %12s %10s\n' scene rmse_clr16 rmse_pbrt16 mean_ratio
for scene in "$here"/tests/data/scenes/${SCENES:-v3_*}.pbrt; do
  name=$(basename "$scene" .pbrt)
  sed "s/\"integer pixelsamples\" \[16\]/\"integer pixelsamples\" [$ref_spp]/" "$scene" > "$out/$name.ref.pbrt"
  "$pbrt" --quiet --outfile "$out/$name.ref.pfm" "$out/$name.ref.pbrt" > /dev/null
  "$pbrt" --quiet --outfile "$out/$name.pbrt16.pfm" "$scene" > /dev/null
  "$clr" render "$scene" --outfile "$out/$name.clr16.pfm" > /dev/null 2>&1
  python3 - "$out/$name" "$name" <<'PY'
import struct, sys
def read(p):
    f = open(p, 'rb'); f.readline(); w, h = map(int, f.readline().split()); s = float(f.readline())
    n = w * h * 3
    return struct.unpack(('<' if s < 0 else '>') + '%df' % n, f.read(4 * n))
base, name = sys.argv[1], sys.argv[2]
ref, p16, c16 = read(base + '.ref.pfm'), read(base + '.pbrt16.pfm'), read(base + '.clr16.pfm')
m = sum(ref) / len(ref)
rmse = lambda a: (sum((x - y) ** 2 for x, y in zip(a, ref)) / len(ref)) ** 0.5 / m
print('%-14s %12.4f %12.4f %10.4f' % (name, rmse(c16), rmse(p16), sum(c16) / len(c16) / m))
PY
done
