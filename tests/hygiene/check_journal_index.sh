#!/bin/sh
# Fails when a journal file is missing from the journal's index
# (DIR/README.md) or the index links a file that does not exist: the
# reference docs point readers to the journal for history, and an entry
# nobody can find is history lost.
# usage: check_journal_index.sh DIR
set -u
dir=$1
index=$dir/README.md
[ -f "$index" ] || { echo "no index: $index"; exit 2; }
bad=0
n=0
for f in "$dir"/*.md; do
  b=$(basename "$f")
  [ "$b" = README.md ] && continue
  n=$((n + 1))
  if ! grep -q "($b)" "$index"; then
    echo "not in $index: $b"
    bad=1
  fi
done
for b in $(grep -o '([^()]*\.md)' "$index" | tr -d '()'); do
  if [ ! -f "$dir/$b" ]; then
    echo "$index links a missing file: $b"
    bad=1
  fi
done
[ "$bad" -eq 0 ] && echo "$index: all $n journal files indexed"
exit "$bad"
