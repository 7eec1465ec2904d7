#!/usr/bin/env bash
# Builds the libFuzzer targets of tests/fuzz with clang (CLR_FUZZ=ON: ASan + UBSan + libFuzzer)
# and runs each for a bounded time. Fails on the first crash, leak, timeout or out-of-memory, and
# names the input that caused it (keep it in tests/fuzz/regressions/<target>/ once fixed).
#   scripts/fuzz.sh [TARGET...]        targets: scene ply exr png cli film sampler tile (default: all)
#   CLR_FUZZ_SECONDS=N                 seconds per target (default 30)
#   CLR_FUZZ_SEED=N                    libFuzzer's -seed (default 0: random; test.sh uses 1)
#   CLR_FUZZ_BUILD_DIR=DIR             build folder (default build-fuzz)
#   CLR_FUZZ_POCL_CACHE_DIR=DIR        PoCL's kernel cache (default: the build folder's; test.sh shares
#                                      the first build's, so no fuzz time goes to cold compiles)
# New inputs the fuzzer finds go to DIR/fuzz-corpus/<target> (kept between runs), crashes to
# DIR/fuzz-artifacts/<target>/. Extra libFuzzer flags: CLR_FUZZ_FLAGS="-max_len=65536".
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${CLR_FUZZ_SECONDS:-30}
build=${CLR_FUZZ_BUILD_DIR:-build-fuzz}
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then targets=(scene ply exr png cli film sampler tile); fi

fail() { echo "fuzz: $*" >&2; exit 1; }
command -v clang >/dev/null || fail "clang not found: the fuzzers need clang and libFuzzer (scripts/install-deps.sh installs clang and libclang-rt-14-dev)"
probe=$(mktemp -d)
trap 'rm -rf "$probe"' EXIT
printf '#include <stddef.h>\n#include <stdint.h>\nint LLVMFuzzerTestOneInput(const uint8_t *d, size_t n) { (void)d; (void)n; return 0; }\n' > "$probe/probe.c"
clang -fsanitize=fuzzer,address,undefined "$probe/probe.c" -o "$probe/probe" 2> "$probe/log" ||
  { cat "$probe/log" >&2; fail "clang cannot link libFuzzer: install libclang-rt-14-dev (scripts/install-deps.sh)"; }

mkdir -p "$build"
cmake -S . -B "$build" -DCMAKE_C_COMPILER=clang -DCLR_FUZZ=ON -DCLR_WERROR=ON -DCLR_BUILD_BENCH=OFF \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo > "$build/configure.log" 2>&1 ||
  { cat "$build/configure.log" >&2; fail "configure failed"; }
cmake --build "$build" -j "$(nproc)" --target clr_fuzzers

sanitizers=tests/sanitizers
# OpenCL program binaries stay in the build tree, never in the user's ~/.cache.
export CLRENDER_CACHE_DIR="$PWD/$build/program-cache"
export POCL_CACHE_DIR="${CLR_FUZZ_POCL_CACHE_DIR:-$PWD/$build/pocl-cache}"
# intercept_tls_get_addr=0: see tests/sanitizers/sanitizers.cmake (LeakSanitizer and PoCL's TLS).
export ASAN_OPTIONS="detect_leaks=1:intercept_tls_get_addr=0:suppressions=$PWD/$sanitizers/asan.supp"
export LSAN_OPTIONS="suppressions=$PWD/$sanitizers/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:suppressions=$PWD/$sanitizers/ubsan.supp"

for t in "${targets[@]}"; do
  exe="$build/tests/fuzz/fuzz_$t"
  [ -x "$exe" ] || fail "no fuzz target '$t' ($exe)"
  corpus="$build/fuzz-corpus/$t"
  artifacts="$build/fuzz-artifacts/$t"
  mkdir -p "$corpus" "$artifacts"
  log="$build/fuzz-$t.log"
  echo "fuzz: $t for ${seconds}s (log $log)"
  # shellcheck disable=SC2086 # CLR_FUZZ_FLAGS is a list of flags
  if ! "$exe" -max_total_time="$seconds" -rss_limit_mb=2048 -malloc_limit_mb=2048 -timeout=60 \
      -close_fd_mask=3 -print_final_stats=1 -seed="${CLR_FUZZ_SEED:-0}" \
      -artifact_prefix="$artifacts/" ${CLR_FUZZ_FLAGS:-} \
      "$corpus" "tests/fuzz/corpus/$t" "tests/fuzz/regressions/$t" > "$log" 2>&1; then
    tail -n 60 "$log" >&2
    fail "$t: the fuzzer found a problem; input in $artifacts/ (reproduce: $exe FILE)"
  fi
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
  echo "fuzz: $t ok, ${runs:-?} executions"
done
