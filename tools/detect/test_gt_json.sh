#!/bin/sh
# gt.json is read as JSON (OpenCV's reader), not as negobs_synth's line
# layout: a compacted and a re-indented copy of a rendered walk's gt.json
# must give negobs_png the same output as the original (timings aside);
# NaN (as Python writes it), null for a required number and a fractional
# frame index are refused with exit 1 and the field named.
# usage: test_gt_json.sh NEGOBS_SYNTH NEGOBS_PNG WORKDIR
set -u
synth=$1 png=$2 w=$3
command -v python3 >/dev/null || { echo "skipped: python3 absent"; exit 77; }
rm -rf "$w" && mkdir -p "$w" || exit 1
fail=0
ok() { echo "ok - $*"; }
bad() { echo "FAIL - $*"; fail=1; }

"$synth" --scene curb --drop-mm 150 --edge-mm 4000 --frames 5 --fps 10 \
    --noise 2 --seed 3 --threads 1 --quiet --out "$w/orig" ||
    { echo "FAIL - negobs_synth"; exit 1; }
"$png" --seq "$w/orig" --no-overlay --json "$w/orig.jsonl" ||
    { echo "FAIL - negobs_png on the original gt.json"; exit 1; }

# variant NAME PYTHON-EXPRESSION-ON-d -> a copy of the walk with gt.json
# rewritten by json.dump(EXPR)
variant() {
    mkdir -p "$w/$1" && for f in "$w"/orig/*.png; do
        ln -sf "$f" "$w/$1/$(basename "$f")"; done
    python3 -c '
import json, sys
d = json.load(open(sys.argv[1]))
mode = sys.argv[3]
if mode == "compact":
    s = json.dumps(d, separators=(",", ":"))
elif mode == "indent":
    s = json.dumps(d, indent=7, sort_keys=True)
elif mode == "nan_f":
    d["camera"]["f"] = float("nan"); s = json.dumps(d, indent=1)
elif mode == "null_cx":
    d["camera"]["cx"] = None; s = json.dumps(d)
elif mode == "frac_i":
    d["frames"][2]["i"] = 1.5; s = json.dumps(d)
open(sys.argv[2], "w").write(s)
' "$w/orig/gt.json" "$w/$1/gt.json" "$1"
}

for v in compact indent; do
    variant $v
    if "$png" --seq "$w/$v" --no-overlay --json "$w/$v.jsonl" 2>"$w/$v.err"; then
        # the JSON lines must not differ but for the stage times ("ms")
        sed 's/"ms":{[^}]*}//g' "$w/orig.jsonl" > "$w/orig.cmp"
        sed 's/"ms":{[^}]*}//g' "$w/$v.jsonl" > "$w/$v.cmp"
        cmp -s "$w/orig.cmp" "$w/$v.cmp" && ok "$v gt.json reads the same" ||
            bad "$v gt.json gives other output"
    else
        bad "$v gt.json refused: $(cat "$w/$v.err")"
    fi
done

check_refused() {
    variant "$1"
    err=$("$png" --seq "$w/$1" --no-overlay --quiet 2>&1 >/dev/null)
    rc=$?
    if [ $rc -eq 1 ] && printf '%s\n' "$err" | grep -Eq "$2"; then
        ok "$1 refused: $err"
    else
        bad "$1: exit $rc, message '$err' (want 1 and /$2/)"
    fi
}
check_refused nan_f 'camera f = nan is not a finite number'
check_refused null_cx 'camera lacks a number for f/B_mm/cx'
check_refused frac_i 'frame 2: i is not an integer'
exit $fail
