#!/bin/sh
# End-to-end: the real negobs_run, a replay whose left.y is a FIFO that
# stops delivering (tests/port/app_noinfo_run.c); the no-information
# pattern must start watchdog_ms (300) after the last fresh verdict, within
# a scheduling tolerance. The frames are a flat walk from negobs_synth
# (224x168, judged "clear"); without negobs_synth (tools/ not built) the
# test is skipped (exit 77).
# Usage: test_negobs_run_noinfo.sh NEGOBS_RUN APP_NOINFO_RUN NEGOBS_SYNTH PNG2RAW [STALLS] [TOL_MS]
set -u
RUN=$1
HARNESS=$2
SYNTH=$3
PNG2RAW=$4
STALLS=${5:-8}
TOL_MS=${6:-50}
if [ ! -x "$SYNTH" ]; then
    echo "SKIP: $SYNTH not built (tools/ needs OpenCV)"; exit 77
fi
T=$(mktemp -d "${TMPDIR:-/tmp}/negobs-noinfo-run-XXXXXX")
trap 'rm -rf "$T"' EXIT
# 224x168 keeps one pair well under 300 ms in a debug build; the flat
# ground is judged "clear", so the motor is silent before each stall.
"$SYNTH" --scene flat --frames 10 --speed 1.2 --fps 10 --bob-mm 0 \
    --sway-deg 0 --roll-sway-deg 0 --f 175 --baseline-mm 120 \
    --height-mm 1200 --pitch-deg 20 --width 224 --height 168 --seed 7 \
    --out "$T/png" >/dev/null || { echo "FAIL: negobs_synth"; exit 1; }
python3 "$PNG2RAW" "$T/png" "$T/raw" --pgm >/dev/null || { echo "FAIL: png2raw"; exit 1; }
# The stalls: the same walk, continued for 30 pairs a batch, fed at its
# 10 fps. A stall of STALL_MS (1.3 s) is a camera hang during which the
# wearer may have walked past the floor that was checked for 5 cm drops:
# after it the detector says no-info until that floor is walked over (about
# 14 pairs, docs/DETECTION.md 10.2), so a batch must be longer than that to
# end clear, and paced, so that the walk is measured as on a camera.
BATCH=30
NWALK=$((BATCH * (STALLS + 1)))
"$SYNTH" --scene flat --frames "$NWALK" --speed 1.2 --fps 10 --bob-mm 0 \
    --sway-deg 0 --roll-sway-deg 0 --f 175 --baseline-mm 120 \
    --height-mm 1200 --pitch-deg 20 --width 224 --height 168 --seed 7 \
    --out "$T/pngwalk" >/dev/null || { echo "FAIL: negobs_synth (walk)"; exit 1; }
python3 "$PNG2RAW" "$T/pngwalk" "$T/rawwalk" >/dev/null || { echo "FAIL: png2raw (walk)"; exit 1; }
cat >"$T/rig.conf" <<CONF
# negobs_synth's rig at 224x168
focal_px = 175
baseline_mm = 120
cam_height_mm = 1200
cam_pitch_mdeg = 20000
max_disp = 23
watchdog_ms = 300
# the stalls are measured here, not the processing time (an ASan build
# can take longer than the default 250 ms budget for a pair)
latency_budget_ms = 0
# the first motor-on after a stall must be the no-info pulse: a heartbeat
# beat (every 5 s while clear) falling into the 300 ms would be taken for
# it; the heartbeat has its own tests (test_alert.c, test_app_alert.c)
heartbeat_period_ms = 0
CONF
echo "== $HARNESS $RUN $T/rig.conf $T/rawwalk 224 168 $NWALK $STALLS $TOL_MS $BATCH 100"
"$HARNESS" "$RUN" "$T/rig.conf" "$T/rawwalk" 224 168 "$NWALK" "$STALLS" "$TOL_MS" "$BATCH" 100
RC=$?
[ $RC -eq 0 ] || [ $RC -eq 77 ] || exit $RC

# The latency gate end to end: the same flat walk replayed at full speed is
# judged clear without a budget; with a 1 ms budget (no pair is processed
# that fast) not one clear verdict may come out, and the reason is "late".
{ cat "$T/rig.conf"; echo "latency_budget_ms = 1"; } >"$T/late.conf"
"$RUN" --config "$T/rig.conf" --fps 0 --alert none replay:"$T/raw/pgm" \
    >"$T/free.log" 2>&1 || { echo "FAIL: negobs_run (no budget)"; cat "$T/free.log"; exit 1; }
"$RUN" --config "$T/late.conf" --fps 0 --alert none replay:"$T/raw/pgm" \
    >"$T/late.log" 2>&1 || { echo "FAIL: negobs_run (1 ms budget)"; cat "$T/late.log"; exit 1; }
grep "summary" "$T/free.log"
grep "summary" "$T/late.log"
grep -q "summary .* clear=[1-9]" "$T/free.log" ||
    { echo "FAIL: the flat walk is never clear without a budget"; exit 1; }
grep -q "summary .* clear=0 .*last_reason=late" "$T/late.log" ||
    { echo "FAIL: a clear verdict over the latency budget"; exit 1; }
echo "latency gate: ok"

# The row crop (config key row_crop, on by default): once the walk's ground
# is known, the matcher starts below the top of the image; switched off, it
# reads every row of every pair.
{ cat "$T/rig.conf"; echo "row_crop = false"; } >"$T/nocrop.conf"
"$RUN" --config "$T/rig.conf" --fps 0 --alert none --log-level debug \
    replay:"$T/raw/pgm" >"$T/crop.log" 2>&1 || { echo "FAIL: negobs_run (crop)"; cat "$T/crop.log"; exit 1; }
"$RUN" --config "$T/nocrop.conf" --fps 0 --alert none --log-level debug \
    replay:"$T/raw/pgm" >"$T/nocrop.log" 2>&1 || { echo "FAIL: negobs_run (no crop)"; cat "$T/nocrop.log"; exit 1; }
CROPPED=$(grep -c "verdict .* first_row [1-9]" "$T/crop.log")
FULL=$(grep -c "verdict .* first_row 0$" "$T/nocrop.log")
echo "row crop: $CROPPED of 10 pairs cropped with row_crop on; $FULL of 10 full with it off"
[ "$CROPPED" -ge 8 ] || { echo "FAIL: row_crop on, but fewer than 8 of 10 pairs cropped"; exit 1; }
[ "$FULL" -eq 10 ] || { echo "FAIL: row_crop = false, but a pair was cropped"; exit 1; }
# --log-level debug times the matcher's stages on the device (one line per
# pair, microseconds; the growth is never free)
TIMED=$(grep -c "stereo_us [1-9][0-9]* (gcs [1-9][0-9]* dp [0-9]* other [0-9]*)" "$T/crop.log")
[ "$TIMED" -eq 10 ] || { echo "FAIL: $TIMED of 10 pairs have stage times in the debug log"; exit 1; }
grep -q "summary .* clear=[1-9]" "$T/nocrop.log" ||
    { echo "FAIL: the flat walk is never clear without the crop"; exit 1; }
exit $RC
