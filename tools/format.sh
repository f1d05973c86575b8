#!/usr/bin/env bash
# Formats the C and C++ sources of lib/ port/ firmware_app/ tests/ tools/
# in place with clang-format and the repository's .clang-format files
# (nested ones: tools/detect, tools/synth, tests/hw/guest).
#
#   tools/format.sh           format every source in place
#   tools/format.sh --check   change nothing; list the files that differ and
#                             exit 1 if there are any (CI, pre-commit)
#   tools/format.sh [--check] FILE...   only these files
#
# Formatting must not change behaviour: after a formatting commit the
# tests and the cross-target digest (tools/negobs test --only digest, with
# the trees built) stay equal.
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
CLANG_FORMAT=${CLANG_FORMAT:-clang-format}

die() { printf 'format.sh: %s\n' "$*" >&2; exit 2; }

check=0
if [[ ${1:-} == --check ]]; then check=1; shift; fi
case ${1:-} in -h|--help) sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;; esac
command -v "$CLANG_FORMAT" >/dev/null ||
  die "$CLANG_FORMAT not found (Debian package clang-format; tools/negobs setup installs it)"

cd "$ROOT"
files=()
if (($#)); then
  files=("$@")
else
  # Tracked files only: build trees and generated files stay untouched.
  mapfile -t files < <(git ls-files -- 'lib/*.[ch]' 'port/*.[ch]' 'port/*.cpp' \
    'port/*.hpp' 'firmware_app/*.[ch]' 'tests/*.[ch]' 'tests/*.cpp' 'tests/*.hpp' \
    'tools/*.[ch]' 'tools/*.cpp' 'tools/*.hpp')
fi
((${#files[@]})) || die "no source files found"

if ((check == 0)); then
  "$CLANG_FORMAT" -i -- "${files[@]}"
  exit 0
fi

differ=0
for f in "${files[@]}"; do
  [[ -f $f ]] || die "no such file: $f"
  if ! "$CLANG_FORMAT" -- "$f" | cmp -s - "$f"; then
    printf '%s\n' "$f"
    differ=$((differ + 1))
  fi
done
if ((differ)); then
  printf 'format.sh: %d of %d files differ from .clang-format\n' "$differ" "${#files[@]}" >&2
  exit 1
fi
