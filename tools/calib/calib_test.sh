#!/bin/sh
# End-to-end calibration test on Debian opencv-doc's chessboard pairs:
# calibrate, write the table, rectify every pair with the library's integer
# remap, require matching corners to share a row (RMS < 0.5 px). Also the
# YAML path (same calibration through --save-yaml/--yaml gives the same
# table) and the too-few-boards refusal.
# usage: calib_test.sh NEGOBS_CALIB NEGOBS_RECTIFY_CHECK DATA_DIR WORK_DIR
set -u
calib=$1
check=$2
data=$3
work=$4
list=$data/stereo_calib.xml

if [ ! -f "$list" ] || [ ! -f "$data/left01.jpg" ] || [ ! -f "$data/right01.jpg" ]; then
    echo "SKIP: opencv-doc chessboard pairs not found in $data" \
         "(apt-get install opencv-doc)"
    exit 77
fi
mkdir -p "$work" || exit 1

echo "== $calib --list $list --out $work/table.bin --save-yaml $work/calib.yml"
"$calib" --list "$list" --out "$work/table.bin" --save-yaml "$work/calib.yml" \
    || { echo "FAIL: calibration"; exit 1; }

echo "== $check --table $work/table.bin --list $list --max-rms 0.5 --yaml $work/calib.yml"
"$check" --table "$work/table.bin" --list "$list" --max-rms 0.5 \
    --yaml "$work/calib.yml" \
    || { echo "FAIL: row alignment"; exit 1; }

echo "== same calibration through --yaml"
"$calib" --yaml "$work/calib.yml" --out "$work/table_yaml.bin" \
    || { echo "FAIL: --yaml"; exit 1; }
cmp "$work/table.bin" "$work/table_yaml.bin" \
    || { echo "FAIL: --yaml gives a different table"; exit 1; }

echo "== too few boards must fail"
if "$calib" --list "$list" --out "$work/never.bin" --min-boards 100; then
    echo "FAIL: --min-boards 100 accepted"
    exit 1
fi
echo "PASS"
exit 0
