#!/usr/bin/env bash
# For a borrowed machine with a GPU but none of this project's packages (no cmake build there):
# packs the binaries built here with every library they load (the dynamic loader included), and a
# run script that checks the kernels on that machine's vendor OpenCL driver. Never needed by the
# test suite.
#
#   scripts/device-bundle.sh [DIR]      # default DIR: build/device-bundle (build first)
#   # copy DIR (bundle.tar.xz and run.sh; the bench scenes are inside) to the GPU machine, then:
#   DIR/run.sh                          # CLR_ICD_LIBRARY=/path/libvendor-opencl.so to choose
#
# run.sh registers the vendor's ICD library in a private folder (OCL_ICD_VENDORS), runs
# `test_devices --child` in both kernel shapes on device 0, renders the bench scenes on the device
# in both shapes and with `--device host`, prints whether each render's bytes agree, then runs
# `clrender_bench --only samples` and `--quick --only film`. Exit status: 0 when the tests passed
# and every render agreed.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${CLR_BUILD_DIR:-build}
out=${1:-$build/device-bundle}
bins=("$build/clrender" "$build/clrender_bench" "$build/tests/test_devices")
for b in "${bins[@]}"; do
  [ -x "$b" ] || { echo "device-bundle: $b not found (build first)" >&2; exit 1; }
done
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
mkdir -p "$stage/bin" "$stage/lib" "$out"
cp "${bins[@]}" "$stage/bin/"
cp -r bench/scenes "$stage/scenes"
ldd "${bins[@]}" | awk '/=>/ && $3 ~ /^\// {print $3} /ld-linux/ && $1 ~ /^\// {print $1}' |
  sort -u | while read -r lib; do cp -L "$lib" "$stage/lib/"; done
tar -C "$stage" -cJf "$out/bundle.tar.xz" bin lib scenes
cat > "$out/run.sh" <<'EOF'
#!/usr/bin/env bash
# Written by scripts/device-bundle.sh: the kernels on this machine's vendor OpenCL driver.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d)
tar -C "$work" -xJf "$here/bundle.tar.xz"
icd=${CLR_ICD_LIBRARY:-}
for c in /usr/local/nvidia/lib64/libnvidia-opencl.so.1 /usr/lib/x86_64-linux-gnu/libnvidia-opencl.so.1 \
  /usr/lib64/libnvidia-opencl.so.1 /opt/rocm/lib/libamdocl64.so /usr/lib/x86_64-linux-gnu/intel-opencl/libigdrcl.so; do
  [ -z "$icd" ] && [ -e "$c" ] && icd=$c
done
[ -n "$icd" ] || { echo "run.sh: no vendor OpenCL library found; set CLR_ICD_LIBRARY" >&2; exit 2; }
mkdir -p "$work/icd" "$work/home"
echo "$icd" > "$work/icd/vendor.icd"
export OCL_ICD_VENDORS=$work/icd OPENCL_VENDOR_PATH=$work/icd HOME=$work/home
run() { "$work/lib/ld-linux-x86-64.so.2" --library-path "$work/lib:$(dirname "$icd")" "$@"; }
status=0
run "$work/bin/clrender" devices || status=1
for shape in portable simd; do
  CLRENDER_DEVICE=0 CLRENDER_KERNELS=$shape run "$work/bin/test_devices" --child >"$work/td.txt" 2>&1
  rc=$?
  echo "test_devices $shape: exit $rc, $(grep -c identical "$work/td.txt") identical, $(tail -1 "$work/td.txt")"
  [ $rc = 0 ] || { grep -E 'FAIL' "$work/td.txt" | head -20; status=1; }
done
scenes=$work/scenes
for scene in cornell sphere star; do
  for setup in 'halton|Integrator "path" "integer maxdepth" [5]' 'sobol|Integrator "directlighting"'; do
    file=$work/$scene-${setup%%|*}.pbrt
    printf 'Film "image" "integer xresolution" [256] "integer yresolution" [256] "string filename" "x.pfm"\nSampler "%s" "integer pixelsamples" [16]\n%s\nInclude "%s/%s.pbrt"\n' \
      "${setup%%|*}" "${setup#*|}" "$scenes" "$scene" > "$file"
    hashes=""
    for dev in "host auto" "0 portable" "0 simd"; do
      set -- $dev
      run "$work/bin/clrender" render "$file" --device "$1" --kernels "$2" --quiet --outfile "$work/o.pfm" || status=1
      hashes="$hashes $(sha256sum "$work/o.pfm" | cut -c1-16)"
    done
    same=$(echo $hashes | tr ' ' '\n' | sort -u | wc -l)
    echo "render $(basename "$file" .pbrt) host/portable/simd:$hashes $([ "$same" = 1 ] && echo same || echo DIFFERENT)"
    [ "$same" = 1 ] || status=1
  done
done
run "$work/bin/clrender_bench" --device 0 --only samples
CLR_BENCH_FILM_SPP=8 run "$work/bin/clrender_bench" --device 0 --quick --only film
rm -rf "$work"
exit $status
EOF
chmod +x "$out/run.sh"
echo "device-bundle: $out/bundle.tar.xz ($(du -h "$out/bundle.tar.xz" | cut -f1)) and $out/run.sh"
