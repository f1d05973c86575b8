#!/bin/sh
# Recordings the host tools read (issue 24): a session recorded by
# negobs_run (with meta.txt) read by negobs_png --seq, and --calib on
# negobs_png and negobs_stereo with tables written by the library API.
# Usage: test_session_tools.sh negobs_run app_rect_table negobs_png negobs_stereo
# Exit 77 (skipped) when the OpenCV tools are not built.
set -u
RUN=$1
TABLE=$2
PNG=$3
STEREO=$4
[ -x "$PNG" ] && [ -x "$STEREO" ] || { echo "skip: tools not built"; exit 77; }
T=$(mktemp -d "${TMPDIR:-/tmp}/negobs-session-XXXXXX")
trap 'rm -rf "$T"' EXIT
. "$(dirname "$0")/run_expect.sh"
has() {
    if grep -q -- "$2" "$T/err"; then ok "$1"; else echo "     | missing: $2" >>"$T/err"; bad "$1"; fi
}
run_tool() { # NAME WANT_RC NEEDLE PROGRAM ARGS...
    name=$1; want=$2; needle=$3; prog=$4; shift 4
    "$prog" "$@" >"$T/out" 2>"$T/err"
    rc=$?
    cat "$T/out" >>"$T/err"
    if [ "$rc" -ne "$want" ]; then echo "     | exit $rc, want $want" >>"$T/err"; bad "$name"; return; fi
    if [ -n "$needle" ] && ! grep -q -- "$needle" "$T/err"; then echo "     | missing: $needle" >>"$T/err"; bad "$name"; return; fi
    ok "$name"
}

# 6 textured PGM pairs, 96x72 (the right one the left moved 3 px).
mkdir "$T/rp"
i=0
while [ $i -lt 6 ]; do
    awk -v seed=$((i + 3)) 'BEGIN{s=seed; printf "P5\n99 72\n255\n"; for(k=0;k<99*72;k++){s=(s*1103515245+12345)%2147483648; printf "%c", 40+int(s/65536)%160}}' >"$T/wide.pgm"
    python3 - "$T/wide.pgm" "$T/rp/left_000$i.pgm" "$T/rp/right_000$i.pgm" <<'PY'
import sys
d = open(sys.argv[1], "rb").read()
hdr = b"P5\n99 72\n255\n"
px = d[len(hdr):]
rows = [px[r * 99:(r + 1) * 99] for r in range(72)]
open(sys.argv[2], "wb").write(b"P5\n96 72\n255\n" + b"".join(r[3:] for r in rows))
open(sys.argv[3], "wb").write(b"P5\n96 72\n255\n" + b"".join(r[:96] for r in rows))
PY
    i=$((i + 1))
done

"$TABLE" "$T/id.tbl" 96 72 180 90 0 >/dev/null 2>&1 || bad "identity table written"
"$TABLE" "$T/other.tbl" 64 48 180 90 0 >/dev/null 2>&1 || bad "64x48 table written"

# ---- a recorded session, read back --------------------------------------
expect "record a session with its table" 0 "record: closed" --fps 0 --alert none \
    --calib "$T/id.tbl" --record "$T/rec" replay:"$T/rp"
cp "$T/rec/meta.txt" "$T/err"
has "meta: calibration identity" "^calib_crc32 = 0x[0-9a-f]\{8\}$"
has "meta: geometry from the table" "^geometry_source = calib$"
has "meta: focal from the table" "^focal_q4 = 2880$"
run_tool "negobs_png --seq SESSION --calib" 0 "" "$PNG" --seq "$T/rec" --calib "$T/id.tbl" --no-overlay --json "$T/s.jsonl"
if [ "$(wc -l <"$T/s.jsonl")" -eq 6 ] && grep -q '"file":"pair_000005"' "$T/s.jsonl"; then ok "negobs_png read all 6 recorded pairs"; else cp "$T/s.jsonl" "$T/err"; bad "negobs_png read all 6 recorded pairs"; fi
run_tool "negobs_png --seq SESSION without the table: warned" 0 "give it with --calib" "$PNG" --seq "$T/rec" --no-overlay --quiet
"$TABLE" "$T/id2.tbl" 96 72 181 90 0 >/dev/null 2>&1
run_tool "negobs_png --seq SESSION, another table: warned" 0 "not the table the session was recorded with" "$PNG" --seq "$T/rec" --calib "$T/id2.tbl" --no-overlay --quiet
# a session without meta.txt (recorded before it existed) still reads
cp -r "$T/rec" "$T/old" && rm "$T/old/meta.txt"
run_tool "negobs_png --seq SESSION without meta.txt" 0 "" "$PNG" --seq "$T/old" --no-overlay --quiet
: >"$T/bad_session.txt"
mkdir "$T/badrec" && printf 'negobs-session 9\n' >"$T/badrec/session.txt"
run_tool "negobs_png --seq: a bad session header" 1 "not a negobs-session 1 header" "$PNG" --seq "$T/badrec" --no-overlay --quiet

# ---- chessboard pairs for negobs_calib from a recording -----------------
SP=$(dirname "$0")/../../tools/calib/session_pairs.py
if python3 "$SP" "$T/rec" "$T/pairs" --every 2 >"$T/err" 2>&1 &&
   [ "$(grep -c '\.pgm"$' "$T/pairs/stereo_calib.xml")" -eq 6 ] &&
   cmp -s "$T/pairs/left_0002.pgm" "$T/rp/left_0002.pgm"; then
    ok "session_pairs.py: every 2nd pair, the recorded pixels, listed left/right"
else
    bad "session_pairs.py: every 2nd pair, the recorded pixels, listed left/right"
fi
python3 "$SP" "$T/badrec" "$T/p2" >"$T/err" 2>&1
if [ $? -eq 1 ] && grep -q "not a negobs-session 1" "$T/err"; then ok "session_pairs.py: a bad session"; else bad "session_pairs.py: a bad session"; fi

# ---- --calib on the tools --------------------------------------------------
run_tool "negobs_png --calib: table of another size" 1 "size mismatch: the calibration table is for 64x48" "$PNG" "$T/rp/left_0000.pgm" "$T/rp/right_0000.pgm" --calib "$T/other.tbl" --no-overlay --quiet
head -c 100 "$T/id.tbl" >"$T/cut.tbl"
run_tool "negobs_png --calib: truncated table" 1 "refused" "$PNG" "$T/rp/left_0000.pgm" "$T/rp/right_0000.pgm" --calib "$T/cut.tbl" --no-overlay --quiet
# A real rectified pair (opencv-doc's aloe, 1282x1110), so that the maps
# carry matches: an identity table must change nothing, a shifting one must.
O=/usr/share/doc/opencv-doc/examples/data
if [ -f "$O/aloeL.jpg" ] && [ -f "$O/aloeR.jpg" ]; then
    "$TABLE" "$T/aloe_id.tbl" 1282 1110 500 90 0 >/dev/null 2>&1
    "$TABLE" "$T/aloe_shift.tbl" 1282 1110 500 90 2 >/dev/null 2>&1
    run_tool "negobs_stereo without --calib" 0 "" "$STEREO" "$O/aloeL.jpg" "$O/aloeR.jpg" "$T/plain.png"
    run_tool "negobs_stereo --calib identity" 0 "" "$STEREO" "$O/aloeL.jpg" "$O/aloeR.jpg" "$T/rect.png" --calib "$T/aloe_id.tbl"
    if cmp -s "$T/plain.png" "$T/rect.png"; then ok "negobs_stereo: an identity table changes nothing"; else bad "negobs_stereo: an identity table changes nothing"; fi
    run_tool "negobs_stereo --calib shifted" 0 "" "$STEREO" "$O/aloeL.jpg" "$O/aloeR.jpg" "$T/shift.png" --calib "$T/aloe_shift.tbl"
    if cmp -s "$T/plain.png" "$T/shift.png"; then bad "negobs_stereo: a shifting table is applied"; else ok "negobs_stereo: a shifting table is applied"; fi
else
    echo "skip - negobs_stereo --calib on a real pair (no opencv-doc)"
fi
run_tool "negobs_stereo --calib: other size" 3 "size mismatch" "$STEREO" "$T/rp/left_0000.pgm" "$T/rp/right_0000.pgm" "$T/x.png" --calib "$T/other.tbl"
run_tool "negobs_stereo --calib: corrupt" 1 "refused" "$STEREO" "$T/rp/left_0000.pgm" "$T/rp/right_0000.pgm" "$T/x.png" --calib "$T/cut.tbl"

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
