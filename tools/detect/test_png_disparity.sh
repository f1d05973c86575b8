#!/bin/sh
# negobs_png --disparity writes the map the detector read, frame by frame,
# in negobs_stereo's png16. Checked against the generator's own ground
# truth: a two-frame curb walk, each written map scored by negobs_eval
# against the GT of its own frame (RMS below 0.3 px, bad1 below 2 %) and
# frame 0's map against frame 1's GT (the camera moved 12 cm: must be
# worse, or the maps are not per frame). --disparity without --out is
# exit 2.
# usage: test_png_disparity.sh NEGOBS_SYNTH NEGOBS_PNG NEGOBS_EVAL WORKDIR
set -eu
synth=$1
png=$2
eval=$3
work=$4
rm -rf "$work"
mkdir -p "$work"
"$synth" --scene curb --frames 2 --gt-disparity --noise 2 --seed 5 --threads 1 \
    --quiet --out "$work/seq"
"$png" --seq "$work/seq" --out "$work/out" --no-overlay --disparity --quiet
score() { # MAP GT -> "rms bad1"
    "$eval" --score "$1" --gt "$2" --gt-scale 16 --format png16 --json "$work/s.json" \
        >/dev/null
    sed -n 's/.*"bad1_pct": \([0-9.]*\),.*"rms_px": \([0-9.]*\),.*/\2 \1/p' "$work/s.json"
}
for k in 0000 0001; do
    [ -f "$work/out/disp_$k.png" ] || { echo "FAIL: no disp_$k.png"; exit 1; }
    set -- $(score "$work/out/disp_$k.png" "$work/seq/disp_$k.png")
    echo "frame $k against its own GT: rms $1 px, bad1 $2 %"
    if ! awk -v r="$1" -v b="$2" 'BEGIN { exit !(r < 0.3 && b < 2) }'; then
        echo "FAIL: frame $k's written map is not the frame's disparity"
        exit 1
    fi
done
set -- $(score "$work/out/disp_0000.png" "$work/seq/disp_0001.png")
echo "frame 0000 against frame 0001's GT: rms $1 px"
if ! awk -v r="$1" 'BEGIN { exit !(r >= 0.3) }'; then
    echo "FAIL: frame 0's map matches frame 1's GT: not written per frame"
    exit 1
fi
rc=0
"$png" --seq "$work/seq" --no-overlay --disparity --quiet 2>"$work/err" || rc=$?
if [ "$rc" -ne 2 ] || ! grep -q "needs --out" "$work/err"; then
    echo "FAIL: --disparity without --out gave exit $rc"
    exit 1
fi
echo "PASS"
