#!/usr/bin/env bash
# Static analysis of lib/ and port/ with the checked-in configurations:
# cppcheck (options below) and clang-tidy (.clang-tidy). Zero findings
# pass.
# usage: tools/static_analysis.sh cppcheck|clang-tidy BUILD_DIR [FILES...]
# With FILES, analyses those instead (the negative fixture uses this).
# BUILD_DIR/lib/include holds the generated negobs/version.h.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
tool=$1 build=$2; shift 2
if (($#)); then files=("$@"); else
  mapfile -t files < <(cd "$ROOT" && find lib port -name '*.c' | sort)
  files=("${files[@]/#/$ROOT/}")
fi
case $tool in
  cppcheck)
    # 'style' is left out: it is taste (variable scope), not defects.
    cppcheck --enable=warning,performance,portability --std=c99 \
      --error-exitcode=1 --inline-suppr --quiet \
      --suppressions-list="$ROOT/tools/cppcheck-suppressions.txt" \
      -I "$ROOT/lib/include" -I "$build/lib/include" -I "$ROOT/lib/src" \
      -I "$ROOT/port/include" \
      -D__linux__ -U__cplusplus "${files[@]}"
    ;;
  clang-tidy)
    out=$(clang-tidy --quiet -p "$build" "${files[@]}" -- -std=c99 \
      -I"$ROOT/lib/include" -I"$build/lib/include" -I"$ROOT/lib/src" \
      -I"$ROOT/port/include" 2>&1) || {
      # Findings only: clang-tidy's "N warnings generated." lines (one per
      # file, about headers it does not report) would fill the 40 lines.
      printf '%s\n' "$out" | grep -E ': (warning|error): ' | head -40; exit 1; }
    ;;
  *) echo "usage: $0 cppcheck|clang-tidy BUILD_DIR [FILES...]" >&2; exit 2 ;;
esac
