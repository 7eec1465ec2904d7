#!/usr/bin/env bash
# Every C source, header and kernel file of the repository follows .clang-format.
# Usage: check_format.sh SOURCE_DIR
set -euo pipefail
cd "$1"
if ! command -v clang-format > /dev/null; then
  echo "check_format: clang-format is missing: install the Debian package clang-format" \
       "(scripts/install-deps.sh)" >&2
  exit 1
fi
if git rev-parse --is-inside-work-tree > /dev/null 2>&1; then
  mapfile -t files < <(git ls-files '*.c' '*.h' '*.cl')
else
  mapfile -t files < <(find host include kernels tests bench tools examples \
                         -name '*.c' -o -name '*.h' -o -name '*.cl')
fi
[ "${#files[@]}" -gt 50 ] || { echo "check_format: only ${#files[@]} files found" >&2; exit 1; }
bad=()
for f in "${files[@]}"; do
  clang-format --dry-run -Werror "$f" > /dev/null 2>&1 || bad+=("$f")
done
if [ "${#bad[@]}" -gt 0 ]; then
  echo "check_format: not clang-formatted (run clang-format -i on them):" >&2
  printf '  %s\n' "${bad[@]}" >&2
  exit 1
fi
echo "check_format: ${#files[@]} files formatted"
