#!/usr/bin/env bash
# Installs the build into a temporary prefix inside the build tree, then builds and runs
# examples/sobol_film against it through find_package(clrender) and through pkg-config, and
# checks the installed shared library exports only public names.
# Usage: test_install.sh SOURCE_DIR BUILD_DIR C_COMPILER
set -euo pipefail
src=$1 build=$2 cc=$3
work="$build/install-test"
rm -rf "$work"
mkdir -p "$work"
prefix="$work/prefix"
fail() { echo "test_install: FAILED: $*" >&2; exit 1; }

cmake --install "$build" --prefix "$prefix" > "$work/install.log"
for f in include/clrender.h include/clrender/film.h include/clrender/version.h \
         lib/pkgconfig/clrender.pc lib/cmake/clrender/clrenderConfig.cmake bin/clrender; do
  [ -e "$prefix/$f" ] || fail "$f not installed"
done
lib=$(ls "$prefix"/lib/libclrender.so.* 2>/dev/null | head -n 1)
[ -n "$lib" ] || fail "no shared libclrender in $prefix/lib"

# Exported symbols: only clr_* and the user's film_* family.
nm -D --defined-only "$lib" | awk '$2 ~ /^[TDBRVW]$/ {print $3}' | sort > "$work/exports.txt"
exported=$(wc -l < "$work/exports.txt")
[ "$exported" -ge 40 ] || fail "only $exported exported symbols"
bad=$(grep -Ev '^(clr_|film_)' "$work/exports.txt" || true)
[ -z "$bad" ] || fail "non-public symbols exported: $bad"
for internal in clr_fail clr_exr_read clr_png_read clr_film_add_block clr_context_program \
  film_set_bin_threads clr_halton_host_batch; do
  ! grep -qx "$internal" "$work/exports.txt" || fail "internal $internal exported"
done
for public in film_add_samples clr_sampler_create clr_version clr_image_read \
  clr_sample_fetch_create clr_sample_fetch_values clr_sample_fetch_release; do
  grep -qx "$public" "$work/exports.txt" || fail "public $public not exported"
done

# Every installed header compiles alone, silently (no CL_TARGET_OPENCL_VERSION message).
for h in "$prefix"/include/clrender/*.h "$prefix"/include/clrender.h; do
  name=${h#"$prefix/include/"}
  msgs=$(printf '#include <%s>\n' "$name" | "$cc" -std=c11 -Wall -Wextra -Werror -fsyntax-only \
    -I"$prefix/include" -xc - 2>&1) || fail "$name does not compile alone: $msgs"
  [ -z "$msgs" ] || fail "$name prints: $msgs"
done

check_run() { # binary, output exr
  local out
  out=$("$1" "$2") || fail "$1 exited $?"
  echo "$out"
  # 64x48 film, mitchell radius 2: 68x52 sample bounds x 16 spp sobol, constant radiance (0.5, 0.25, 0.125): the image mean equals it.
  # a here-string, not a pipe: grep -q stops reading at the match, and under pipefail the echo's
  # SIGPIPE would fail the check now and then
  grep -q "samples: 56576," <<< "$out" || fail "$1: wrong sample count"
  echo "$out" | awk '/mean RGB/ { d = ($5 - 0.5)^2 + ($6 - 0.25)^2 + ($7 - 0.125)^2;
                                   exit !(d < 1e-10) }' || fail "$1: wrong mean"
  [ -s "$2" ] || fail "$2 not written"
  if grep -qi embree <<< "$(ldd "$1")"; then fail "$1 links Embree"; fi
}

# 1. CMake package.
cmake -S "$src/examples/sobol_film" -B "$work/cmake-build" -DCMAKE_C_COMPILER="$cc" \
  -DCMAKE_PREFIX_PATH="$prefix" > "$work/cmake-config.log" || fail "configure (see $work)"
cmake --build "$work/cmake-build" > "$work/cmake-build.log" || fail "build (see $work)"
check_run "$work/cmake-build/sobol_film" "$work/cmake.exr"

# 2. pkg-config.
export PKG_CONFIG_PATH="$prefix/lib/pkgconfig"
flags=$(pkg-config --cflags --libs clrender) || fail "pkg-config clrender"
echo "pkg-config: $flags"
case "$flags" in *embree*) fail "pkg-config flags mention Embree" ;; esac
"$cc" -std=c11 -Wall -Wextra -Werror "$src/examples/sobol_film/main.c" -o "$work/pkg-sobol_film" \
  $flags -Wl,-rpath,"$prefix/lib" || fail "pkg-config build"
check_run "$work/pkg-sobol_film" "$work/pkg.exr"

cmp -s "$work/cmake.exr" "$work/pkg.exr" || fail "the two builds wrote different images"

# 3. A static library-only build (no renderer, no tests: needs neither Embree nor cmocka),
#    installed and linked with find_package and with pkg-config --static.
static_prefix="$work/static-prefix"
cmake -S "$src" -B "$work/static-build" -DCMAKE_C_COMPILER="$cc" -DBUILD_SHARED_LIBS=OFF   -DCLR_BUILD_TESTS=OFF -DCLR_BUILD_RENDERER=OFF > "$work/static-config.log" || fail "static configure"
cmake --build "$work/static-build" -j 2 > "$work/static-build.log" || fail "static build (see $work)"
cmake --install "$work/static-build" --prefix "$static_prefix" > /dev/null
[ -f "$static_prefix/lib/libclrender.a" ] || fail "no static libclrender.a"
cmake -S "$src/examples/sobol_film" -B "$work/static-cmake" -DCMAKE_C_COMPILER="$cc"   -DCMAKE_PREFIX_PATH="$static_prefix" > /dev/null || fail "static example configure"
cmake --build "$work/static-cmake" > /dev/null || fail "static example build"
check_run "$work/static-cmake/sobol_film" "$work/static-cmake.exr"
export PKG_CONFIG_PATH="$static_prefix/lib/pkgconfig"
flags=$(pkg-config --static --cflags --libs clrender) || fail "pkg-config --static clrender"
"$cc" -std=c11 "$src/examples/sobol_film/main.c" -o "$work/static-pkg" $flags || fail "static pkg-config build"
check_run "$work/static-pkg" "$work/static-pkg.exr"
cmp -s "$work/cmake.exr" "$work/static-pkg.exr" || fail "static and shared builds wrote different images"
echo "test_install: passed ($exported exported symbols)"
