#!/bin/sh
# negobs_run --calib: a table written with the library API is loaded, its
# f/B reported and its remap applied to every pair; corrupt, truncated,
# foreign and size-mismatched tables are refused with exit code 6 and a
# message saying why; with negobs_calib and Debian's opencv-doc chessboards
# present, a real calibration table is run too.
# Usage: test_negobs_run_calib.sh NEGOBS_RUN APP_RECT_TABLE [NEGOBS_CALIB DATA_DIR]
set -u
RUN=$1
MKTAB=$2
CALIB=${3:-}
DATA=${4:-/usr/share/doc/opencv-doc/examples/data}
T=$(mktemp -d "${TMPDIR:-/tmp}/negobs-calib-XXXXXX")
trap 'rm -rf "$T"' EXIT
. "$(dirname "$0")/run_expect.sh"

# mkreplay DIR W H N: N textured PGM pairs (deterministic bytes).
mkreplay() {
    mkdir -p "$1"
    i=0
    while [ "$i" -lt "$4" ]; do
        for side in left right; do
            { printf 'P5\n%d %d\n255\n' "$2" "$3"
              awk -v n=$(($2 * $3)) -v s=$((i + 7)) 'BEGIN {
                  for (k = 0; k < n; k++) {
                      s = (s * 1103515245 + 12345) % 2147483648
                      printf "%c", 40 + int(s / 65536) % 160 } }'
            } >"$1/${side}_$(printf %04d "$i").pgm"
        done
        i=$((i + 1))
    done
}

# flip_byte FILE OFFSET: XOR one byte with 0x01 in place.
flip_byte() {
    b=$(od -An -tu1 -j "$2" -N1 "$1" | tr -d ' ')
    printf "\\$(printf %03o $((b ^ 1)))" |
        dd of="$1" bs=1 seek="$2" conv=notrunc 2>/dev/null
}

mkreplay "$T/rp" 64 48 3
"$MKTAB" "$T/id.bin" 64 48 300 100 0 || { echo "FAIL - app_rect_table"; exit 1; }
"$MKTAB" "$T/out.bin" 64 48 300 100 5000 || exit 1
"$MKTAB" "$T/w80.bin" 80 48 300 100 0 || exit 1

# 1. A good table: loaded, its geometry reported, the run completes.
expect "table loaded and its f/B reported" 0 \
    "f_px=300.00 baseline_mm=100.000 cx=31.50 cy=23.50 (replace focal_px=250 baseline_mm=120)" \
    --fps 0 --alert none --calib "$T/id.bin" replay:"$T/rp"
grep -q "end of replay after 3 pairs" "$T/err" && ok "calibrated replay runs to the end" ||
    bad "calibrated replay runs to the end"
# An identity remap changes nothing: the detector still judges (and finds
# no ground in random texture), exactly as without --calib.
grep -q "last_reason=detector" "$T/err" && ok "identity table: pairs reach the detector" ||
    bad "identity table: pairs reach the detector"
# 2. The remap is really applied: a table whose sources all lie outside
# the frame gives border-black images, which the quality gate calls dark.
expect "remap applied to every pair" 0 "no-info=3 clear=0 caution=0 imminent=0 last_reason=dark" \
    --fps 0 --alert none --calib "$T/out.bin" replay:"$T/rp"
# 3. The config key does the same as the option.
printf 'calib = %s\n' "$T/id.bin" >"$T/c.conf"
expect "config key calib" 0 "f_px=300.00 baseline_mm=100.000" \
    --config "$T/c.conf" --fps 0 --alert none replay:"$T/rp"

# 4. Refusals: exit code 6, a reason, and nothing run.
cp "$T/id.bin" "$T/flip.bin"; flip_byte "$T/flip.bin" 200
expect "flipped map byte refused" 6 "refused: corrupt: checksum" \
    --fps 0 --alert none --calib "$T/flip.bin" replay:"$T/rp"
cp "$T/id.bin" "$T/fliph.bin"; flip_byte "$T/fliph.bin" 33
expect "flipped header byte refused" 6 "refused: corrupt" \
    --fps 0 --alert none --calib "$T/fliph.bin" replay:"$T/rp"
head -c 1000 "$T/id.bin" >"$T/trunc.bin"
expect "truncated table refused" 6 "refused: truncated: 1000 of the" \
    --fps 0 --alert none --calib "$T/trunc.bin" replay:"$T/rp"
head -c 20 "$T/id.bin" >"$T/short.bin"
expect "table shorter than its header refused" 6 "refused: truncated: 20 bytes" \
    --fps 0 --alert none --calib "$T/short.bin" replay:"$T/rp"
head -c 4000 "$T/rp/left_0000.pgm" >"$T/foreign.bin"
expect "not a table refused" 6 "bad magic" \
    --fps 0 --alert none --calib "$T/foreign.bin" replay:"$T/rp"
expect "missing table refused" 6 "nope.bin: No such file" \
    --fps 0 --alert none --calib "$T/nope.bin" replay:"$T/rp"
expect "table for another size refused at start" 6 \
    "size mismatch: the table is for 80x48, the capture size is 64x48" \
    --fps 0 --alert none --width 64 --height 48 --calib "$T/w80.bin" replay:"$T/rp"
expect "table for another size refused at the first pair" 6 \
    "size mismatch: the table is for 80x48, the camera delivers 64x48" \
    --fps 0 --alert none --calib "$T/w80.bin" replay:"$T/rp"
if grep -q "verdict \|summary " "$T/err"; then bad "no pair judged with a mismatched table"
else ok "no pair judged with a mismatched table"; fi
expect "help documents exit code 6" 0 "6 calibration table refused" --help

# 5. A real table: negobs_calib on opencv-doc's chessboard pairs (640x480).
if [ -n "$CALIB" ] && [ -x "$CALIB" ] && [ -f "$DATA/stereo_calib.xml" ]; then
    if "$CALIB" --list "$DATA/stereo_calib.xml" --out "$T/chess.bin" >"$T/calib.txt" 2>&1; then
        ok "negobs_calib wrote a table"
        # "rectified: f = 518.856 px, B = 83.453 mm, ..."
        F=$(sed -n 's/^rectified: f = \([0-9.]*\) px, B = \([0-9.]*\) mm.*/\1/p' "$T/calib.txt")
        B=$(sed -n 's/^rectified: f = \([0-9.]*\) px, B = \([0-9.]*\) mm.*/\2/p' "$T/calib.txt")
        mkreplay "$T/rp640" 640 480 2
        expect "chessboard table: replay runs" 0 "end of replay after 2 pairs" \
            --fps 0 --alert none --calib "$T/chess.bin" replay:"$T/rp640"
        LF=$(sed -n 's/.* f_px=\([0-9.]*\) baseline_mm=\([0-9.]*\) .*/\1/p' "$T/err")
        LB=$(sed -n 's/.* f_px=\([0-9.]*\) baseline_mm=\([0-9.]*\) .*/\2/p' "$T/err")
        echo "     | negobs_calib: f=$F B=$B; negobs_run: f_px=$LF baseline_mm=$LB"
        if [ -n "$F" ] && [ -n "$LF" ] &&
           awk -v a="$F" -v b="$LF" -v c="$B" -v d="$LB" \
               'BEGIN { exit !((a - b < 0.01 && b - a < 0.01) && (c - d < 0.002 && d - c < 0.002)) }'; then
            ok "negobs_run reports the chessboard table's f and B"
        else
            bad "negobs_run reports the chessboard table's f and B"
        fi
    else
        cp "$T/calib.txt" "$T/err"; bad "negobs_calib wrote a table"
    fi
else
    echo "skip - chessboard table (negobs_calib or $DATA/stereo_calib.xml missing)"
fi

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
