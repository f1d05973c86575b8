#!/bin/sh
# Renders the synthetic approach set of docs/SYNTH.md ("Evaluation set"),
# modelled on the test course of docs/REQUIREMENTS.md: curbs of 5/10/15/20 cm,
# descending stairs, a hole, and the negatives (up-step, wall, flat ground
# with distractors), at 0.8/1.1/1.4 m/s and 0/30/60 degree approach angles.
# Every sequence starts 8 m before the edge and ends 0.5 m before it.
#
# usage: make_eval_set.sh NEGOBS_SYNTH OUT_DIR [SETS] [--dry-run]
# SETS (default 3) repeats the whole grid with other seeds: 69 sequences
# per set.
# Writes OUT_DIR/<name>/ per sequence and OUT_DIR/manifest.tsv
# (name, scene, drop_mm, speed, yaw_deg, seed, frames).
set -eu

if [ $# -lt 2 ]; then
    echo "usage: $0 NEGOBS_SYNTH OUT_DIR [SETS] [--dry-run]" >&2
    exit 2
fi
synth=$1
out=$2
seeds=${3:-3}
dry=${4:-}
case $seeds in
    ''|*[!0-9]*) echo "$0: error: SETS must be a positive integer" >&2; exit 2 ;;
esac
[ "$seeds" -ge 1 ] || { echo "$0: error: SETS must be >= 1" >&2; exit 2; }
if [ -z "$dry" ] && [ ! -x "$synth" ]; then
    echo "$0: error: '$synth' is not an executable" >&2
    exit 2
fi

mkdir -p "$out"
manifest=$out/manifest.tsv
printf 'name\tscene\tdrop_mm\tspeed_mps\tyaw_deg\tseed\tframes\n' > "$manifest"
count=0

# frames SPEED YAW: 10 fps from 8 m to 0.5 m perpendicular range.
frames() {
    awk -v v="$1" -v y="$2" 'BEGIN {
        c = cos(y * 3.14159265358979 / 180); n = int((8.0 - 0.5) / (v * c) * 10 + 1);
        print n }'
}

render() { # name scene drop speed yaw set extra...
    name=$1 scene=$2 drop=$3 speed=$4 yaw=$5
    # A seed of its own per sequence: texture, motion phases and noise differ.
    seed=$(($6 * 1000 + count))
    shift 6
    n=$(frames "$speed" "$yaw")
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$name" "$scene" "$drop" "$speed" "$yaw" "$seed" "$n" \
        >> "$manifest"
    count=$((count + 1))
    if [ -n "$dry" ]; then
        return 0
    fi
    "$synth" --scene "$scene" --drop-mm "$drop" --edge-mm 8000 --frames "$n" --fps 10 \
        --speed "$speed" --yaw-deg "$yaw" --seed "$seed" --noise 2 --blur 0.5 \
        --gt-disparity --quiet --out "$out/$name" "$@"
}

s=1
while [ "$s" -le "$seeds" ]; do
    for speed in 0.8 1.1 1.4; do
        for yaw in 0 30 60; do
            for drop in 50 100 150 200; do
                render "curb_${drop}_v${speed}_y${yaw}_s$s" curb "$drop" "$speed" "$yaw" "$s"
            done
            render "stairs_v${speed}_y${yaw}_s$s" stairs 170 "$speed" "$yaw" "$s" \
                --steps 4 --rise-mm 170 --run-mm 300
            render "hole_v${speed}_y${yaw}_s$s" hole 300 "$speed" "$yaw" "$s" \
                --hole-width-mm 1200 --hole-length-mm 1000 --texture-kind paving
            render "upstep_v${speed}_y${yaw}_s$s" upstep 150 "$speed" "$yaw" "$s"
        done
        render "wall_v${speed}_s$s" wall 150 "$speed" 0 "$s"
        render "flat_v${speed}_s$s" flat 150 "$speed" 0 "$s" --distractors 12
    done
    s=$((s + 1))
done
echo "$count sequences listed in $manifest"
