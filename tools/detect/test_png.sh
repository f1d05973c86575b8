#!/bin/sh
# negobs_png on sequences rendered at test time by negobs_synth.
#  1. 15 cm curb, 14 frames from 5 m at 1.2 m/s, f=250, B=120, 320x240:
#     some frame must hold a confirmed hazard whose range is within 10 % of
#     the ground truth of that frame; every confirmed hazard is typed DROP
#     and the median drop height is within 3 cm of 150 mm.
#  2. flat ground, 8 frames, and flat ground with painted distractors, 25
#     frames: no frame may hold a hazard (state HAZARD).
#  3. a right image of another size: exit 1 with "size mismatch".
#  4. --bin 2: the curb rendered at 640x480, f=500, processed at 320x240
#     with f, cx, cy binned: a confirmed hazard within 10 % of the truth
#     (an unscaled f or cy puts it far off); --bin 5 is exit 2.
# usage: test_png.sh NEGOBS_SYNTH NEGOBS_PNG WORKDIR
set -eu
synth=$1
png=$2
work=$3
rm -rf "$work"
mkdir -p "$work"

"$synth" --scene curb --drop-mm 150 --edge-mm 5000 --frames 14 --fps 10 \
    --speed 1.2 --noise 2 --blur 0.5 --seed 11 --threads 1 --quiet --out "$work/curb"
"$png" --seq "$work/curb" --out "$work/curb_out" --json "$work/curb.jsonl" --summary \
    --no-overlay
# One JSON object per line; hazards[] come before candidates[] and "gt" is
# last. For each frame print: gt range and the ranges of confirmed hazards.
ok=$(awk '
{
    line = $0
    gt = line; sub(/.*"gt":\{[^}]*"edge_range_mm":/, "", gt); sub(/[,}].*/, "", gt)
    hz = line; sub(/.*"hazards":\[/, "", hz); sub(/\],"candidates".*/, "", hz)
    n = split(hz, parts, /\{"type":/)
    for (k = 2; k <= n; k++) {
        p = parts[k]
        if (p !~ /CONFIRMED/) continue
        r = p; sub(/.*"range_mm":/, "", r); sub(/,.*/, "", r)
        if (gt != "null" && gt > 0) {
            e = (r - gt) / gt; if (e < 0) e = -e
            printf "frame %d: confirmed at %d mm, true %d mm, error %.1f %%\n", NR - 1, r, gt, 100 * e > "/dev/stderr"
            if (e <= 0.10) good++
        }
    }
}
END { print good + 0 }' "$work/curb.jsonl")
if [ "$ok" -lt 1 ]; then
    echo "FAIL: no confirmed hazard within 10 % of the true range on the curb sequence"
    exit 1
fi
echo "curb: $ok frames with a confirmed hazard within 10 % of the true range"
# The curb must be called a drop (not stairs) and its height read within
# 3 cm: the first rows past an edge are blurred by the matcher, and a
# plateau taken from them alone typed 15 cm curbs STAIRS at 8-9 cm.
types=$(awk '
{
    hz = $0; sub(/.*"hazards":\[/, "", hz); sub(/\],"candidates".*/, "", hz)
    n = split(hz, parts, /\{"type":/)
    for (k = 2; k <= n; k++) {
        t = parts[k]; sub(/,.*/, "", t); gsub(/"/, "", t)
        d = parts[k]; sub(/.*"drop_mm":/, "", d); sub(/,.*/, "", d)
        print t, d
    }
}' "$work/curb.jsonl")
echo "curb hazards (type, drop mm): $(echo "$types" | sort | uniq -c | tr '\n' ' ')"
if [ -z "$types" ] || echo "$types" | grep -qv '^DROP '; then
    echo "FAIL: the 15 cm curb is not typed DROP on every confirmed frame"
    exit 1
fi
med=$(echo "$types" | awk '{print $2}' | sort -n | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}')
if [ "$med" -lt 120 ] || [ "$med" -gt 180 ]; then
    echo "FAIL: median drop height $med mm, truth 150 mm"
    exit 1
fi
echo "curb: typed DROP, median drop height $med mm (truth 150)"
# stereo_roi: the first frame matches every row; once the ground is known
# the matcher starts lower (rows above the 5 m ground are not matched)
rows=$(sed 's/.*"first_row":\([0-9]*\).*/\1/' "$work/curb.jsonl" | tr '\n' ' ')
echo "curb: first matched row per frame: $rows"
set -- $rows
if [ "$1" -ne 0 ] || [ "$(echo "$rows" | awk '{n = 0; for (i = 2; i <= NF; i++) if ($i > 0) n++; print n}')" -lt $(( $# - 2 )) ]; then
    echo "FAIL: the matcher does not skip the rows above the ground's far range"
    exit 1
fi

"$synth" --scene flat --frames 8 --fps 10 --speed 1.2 --noise 2 --blur 0.5 \
    --seed 12 --threads 1 --quiet --out "$work/flat"
"$png" --seq "$work/flat" --out "$work/flat_out" --json "$work/flat.jsonl" --summary
if grep -q '"state":"HAZARD"' "$work/flat.jsonl"; then
    echo "FAIL: hazard reported on flat ground:"
    grep '"state":"HAZARD"' "$work/flat.jsonl" | head -3
    exit 1
fi
[ -f "$work/flat_out/overlay_0000.png" ] || { echo "FAIL: no overlay written"; exit 1; }
echo "flat: no hazard in $(wc -l < "$work/flat.jsonl") frames"

# Flat ground with painted stripes and dark patches (seed 258): the matcher
# pulls the disparity of a bright, nearly textureless stripe about 1 px
# low, which used to be confirmed as a HOLE at 1.7 m and then held as
# IMMINENT for 3 s (DETECTION.md, open finding 1). No hazard may be
# reported on any of the 25 frames.
"$synth" --scene flat --frames 25 --fps 10 --speed 1.2 --noise 2 --blur 0.5 \
    --distractors 12 --seed 258 --threads 1 --quiet --out "$work/stripes"
"$png" --seq "$work/stripes" --out "$work/stripes_out" --json "$work/stripes.jsonl" \
    --summary --no-overlay
if grep -q '"state":"HAZARD"' "$work/stripes.jsonl"; then
    echo "FAIL: hazard reported on flat ground with painted stripes:"
    grep '"state":"HAZARD"' "$work/stripes.jsonl" | head -3
    exit 1
fi
echo "stripes: no hazard in $(wc -l < "$work/stripes.jsonl") frames"

# Size mismatch: 320x240 left against a 160x120 right.
"$synth" --single --scene flat --width 160 --height 120 --f 125 --threads 1 --quiet \
    --out "$work/small"
set +e
"$png" "$work/flat/left_0000.png" "$work/small/right_0000.png" --out "$work/mm" \
    2> "$work/mm.err" > /dev/null
rc=$?
set -e
if [ $rc -ne 1 ] || ! grep -q "size mismatch" "$work/mm.err"; then
    echo "FAIL: size mismatch gave exit $rc:"; cat "$work/mm.err"; exit 1
fi
echo "size mismatch: exit 1 ($(cat "$work/mm.err"))"

# --bin 2: the same curb at 640x480 / f = 500, binned as the device does.
"$synth" --scene curb --drop-mm 150 --edge-mm 5000 --frames 14 --fps 10 \
    --speed 1.2 --noise 2 --blur 0.5 --seed 11 --threads 1 --quiet \
    --width 640 --height 480 --f 500 --out "$work/curb640"
"$png" --seq "$work/curb640" --bin 2 --no-overlay --json "$work/curb640.jsonl" \
    --out "$work/curb640_out"
ok=$(awk '
{
    gt = $0; sub(/.*"gt":\{[^}]*"edge_range_mm":/, "", gt); sub(/[,}].*/, "", gt)
    hz = $0; sub(/.*"hazards":\[/, "", hz); sub(/\],"candidates".*/, "", hz)
    n = split(hz, parts, /\{"type":/)
    for (k = 2; k <= n; k++) {
        if (parts[k] !~ /CONFIRMED/) continue
        r = parts[k]; sub(/.*"range_mm":/, "", r); sub(/,.*/, "", r)
        if (gt != "null" && gt > 0) {
            e = (r - gt) / gt; if (e < 0) e = -e
            if (e <= 0.10) good++
        }
    }
}
END { print good + 0 }' "$work/curb640.jsonl")
if [ "$ok" -lt 1 ]; then
    echo "FAIL: --bin 2: no confirmed hazard within 10 % of the true range"
    exit 1
fi
echo "--bin 2: $ok frames with a confirmed hazard within 10 % of the true range"
set +e
"$png" "$work/flat/left_0000.png" "$work/flat/right_0000.png" --bin 5 \
    --out "$work/bin5" > /dev/null 2>&1
rc=$?
set -e
if [ $rc -ne 2 ]; then
    echo "FAIL: --bin 5 gave exit $rc, not 2"; exit 1
fi
echo "--bin 5: exit 2"
