#!/bin/sh
# Fails when a static library needs heap, stdio, process-exit or
# floating-point helper symbols: the core must run with none of them.
# usage: check_symbols.sh NM LIBRARY
set -u
nm_tool=$1
lib=$2
[ -f "$lib" ] || { echo "no such library: $lib"; exit 2; }
undef=$("$nm_tool" -u "$lib" 2>/dev/null | awk 'NF { print $NF }' | sed 's/@.*//' | sort -u)
bad=$(printf '%s\n' "$undef" | grep -E -x \
  'malloc|calloc|realloc|free|aligned_alloc|posix_memalign|valloc|memalign|strdup|printf|fprintf|sprintf|snprintf|vprintf|vfprintf|vsnprintf|puts|putchar|fputs|fputc|fopen|fclose|fread|fwrite|fflush|stdout|stderr|exit|abort|__assert_fail|__aeabi_[df].*|__(add|sub|mul|div)[sd]f3|__float.*[sd]f|__fix[sd]f.*|__extendsfdf2|__truncdfsf2|sqrt|sqrtf|pow|exp|log|floor|ceil' || true)
if [ -n "$bad" ]; then
  echo "forbidden symbols referenced by $lib:"
  printf '  %s\n' $bad
  exit 1
fi
echo "$lib: no heap, stdio or floating-point symbols ($(printf '%s\n' "$undef" | grep -c .) undefined symbols checked)"
exit 0
