#!/usr/bin/env bash
# For a machine with a real GPU and its vendor OpenCL driver (NVIDIA, AMD, Intel register their
# own ICDs in /etc/OpenCL/vendors): builds clrender, lists the OpenCL devices, and on every GPU
# runs the device-vs-host tests in both kernel shapes and the benchmark. Unattended; never needed
# by the test suite. Prints JSON Lines on stdout (one object per step, then the benchmark's own
# lines); logs go to $CLR_BUILD_DIR/device-check/. Exit status: 0 when every step passed.
#
#   scripts/device-check.sh            # build in build-device-check/, full benchmark
#   CLR_QUICK=1 scripts/device-check.sh   # the benchmark's --quick sizes
#   CLR_BUILD_DIR=build scripts/device-check.sh
#   CLR_CHECK_SIMULATORS=1 ...        # also treat Oclgrind as a GPU (to try the script without one)
#   CLR_CHECK_TESTS="test_devices" ... # only these device tests (default: all three)
set -uo pipefail
cd "$(dirname "$0")/.."
build=${CLR_BUILD_DIR:-build-device-check}
logs="$build/device-check"
quick=${CLR_QUICK:+--quick}
status=0

json_string() { # JSON string of $1
  local s=${1//\\/\\\\}
  s=${s//\"/\\\"}
  s=${s//$'\t'/ }
  s=${s//$'\n'/ }
  printf '"%s"' "$s"
}

step() { # step NAME OK SECONDS [key json-value]...
  local name=$1 ok=$2 seconds=$3
  shift 3
  local line="{\"step\":$(json_string "$name"),\"ok\":$ok,\"seconds\":$seconds"
  while [ $# -ge 2 ]; do
    line+=",\"$1\":$2"
    shift 2
  done
  printf '%s}\n' "$line"
  [ "$ok" = true ] || status=1
}

run_logged() { # run_logged LOG CMD...: runs CMD with output to LOG; sets $elapsed, returns rc
  local log=$1
  shift
  local t0
  t0=$(date +%s.%N)
  "$@" >"$log" 2>&1
  local rc=$?
  elapsed=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.2f", b - a }')
  return $rc
}

mkdir -p "$logs"
elapsed=0
if run_logged "$logs/build.log" bash -c "cmake -S . -B '$build' -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    && cmake --build '$build' -j \"\$(nproc)\""; then
  step build true "$elapsed" log "$(json_string "$logs/build.log")"
else
  step build false "$elapsed" log "$(json_string "$logs/build.log")" \
    tail "$(json_string "$(tail -5 "$logs/build.log")")"
  exit 1
fi

cli="$build/clrender"
devices=$("$cli" devices 2>"$logs/devices.log")
gpus=()
while IFS= read -r line; do
  # "* 0  Platform: Device  [GPU, 80 compute units, 79.1 GiB, OpenCL 3.0 CUDA, driver 550.54]"
  if [[ $line =~ ^[*\ ]\ ([0-9]+)\ \ (.*)\ \ \[(GPU|CPU),\ (.*)\]$ ]]; then
    index=${BASH_REMATCH[1]} name=${BASH_REMATCH[2]} kind=${BASH_REMATCH[3]} rest=${BASH_REMATCH[4]}
    printf '{"step":"device","index":%s,"name":%s,"type":"%s","details":%s}\n' \
      "$index" "$(json_string "$name")" "$kind" "$(json_string "$rest")"
    if [ "$kind" = GPU ] && { [[ $name != *Oclgrind* ]] || [ -n "${CLR_CHECK_SIMULATORS:-}" ]; }; then
      gpus+=("$index")
    fi
  fi
done <<<"$devices"
if [ ${#gpus[@]} -eq 0 ]; then
  step gpus false 0 error '"no GPU among the OpenCL devices: is the vendor driver (ICD) installed?"'
  exit "$status"
fi

for gpu in "${gpus[@]}"; do
  for shape in portable simd; do
    for t in ${CLR_CHECK_TESTS:-test_devices test_sampler_device test_film}; do
      args=()
      [ "$t" = test_devices ] && args=(--child) # the cross-check itself, on this device only
      log="$logs/gpu$gpu-$shape-$t.log"
      if run_logged "$log" env CLRENDER_DEVICE="$gpu" CLRENDER_KERNELS="$shape" \
          CMOCKA_MESSAGE_OUTPUT=STDOUT "$build/tests/$t" "${args[@]}"; then
        step "$t" true "$elapsed" device "$gpu" kernels "\"$shape\"" log "$(json_string "$log")"
      else
        step "$t" false "$elapsed" device "$gpu" kernels "\"$shape\"" log "$(json_string "$log")" \
          tail "$(json_string "$(grep -E 'FAIL|ERROR|differ' "$log" | head -5)")"
      fi
    done
  done
  log="$logs/gpu$gpu-bench.log"
  t0=$(date +%s.%N)
  "$build/clrender_bench" $quick --device "$gpu" --kernels both 2>"$log"
  rc=$?
  elapsed=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.2f", b - a }')
  if [ $rc -eq 0 ]; then ok=true; else ok=false; fi
  step clrender_bench "$ok" "$elapsed" device "$gpu" log "$(json_string "$log")"
done
exit "$status"
