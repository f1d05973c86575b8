#!/bin/sh
# The remembered mounting end to end (mount_file, firmware_app/app_mount.h):
# a camera at 1.45 m told 1.2 m walks over flat ground. The first run is
# NO_INFO until the walk verifies the start, then keeps the measured
# mounting; the second run starts from it and is clear from its first
# pairs. A file that cannot be written or read never changes a verdict.
# Frames from negobs_synth (skipped, exit 77, when tools/ is not built).
# Usage: test_negobs_run_mount.sh NEGOBS_RUN NEGOBS_SYNTH PNG2RAW
set -u
RUN=$1
SYNTH=$2
PNG2RAW=$3
if [ ! -x "$SYNTH" ]; then
    echo "SKIP: $SYNTH not built (tools/ needs OpenCV)"; exit 77
fi
T=$(mktemp -d "${TMPDIR:-/tmp}/negobs-mount-XXXXXX")
trap 'rm -rf "$T"' EXIT
. "$(dirname "$0")/run_expect.sh"
# 30 pairs paced at 10 fps (the walk is measured between timestamps),
# 3.6 m walked: the view starts 1.4 m ahead, so the walk
# verifies the start after about 1.9 m (16 pairs).
flat_pairs 30 1450
cat >"$T/rig.conf" <<CONF
focal_px = 175
baseline_mm = 120
cam_height_mm = 1200
cam_pitch_mdeg = 20000
max_disp = 23
latency_budget_ms = 0
fps = 10
alert = none
CONF
clears() { sed -n 's/.*summary .* clear=\([0-9]*\) .*/\1/p' "$1"; }
# Two runs of the same pairs judged alike: clear counts within 2. The
# detector reads time from the processing clock and the replay stamps a
# pair it delivers late (a loaded machine) at delivery, as a live camera
# would; so the walk that verifies the start can end a pair or two apart
# between runs. The remembered mounting moves the count by 10 or more.
alike() { [ -n "$1" ] && [ -n "$2" ] && [ $(($1 - $2)) -le 2 ] && [ $(($2 - $1)) -le 2 ]; }
run() { # NAME LOG ARGS...
    name=$1; log=$2; shift 2
    if "$RUN" --config "$T/rig.conf" "$@" replay:"$T/raw/pgm" >"$log" 2>&1; then
        ok "$name runs"
    else
        cp "$log" "$T/err"; bad "$name runs"
    fi
}
check() { # NAME CONDITION LOG
    if eval "$2"; then ok "$1"; else cp "$3" "$T/err"; bad "$1"; fi
}

run "no mount file" "$T/plain.log"
PLAIN=$(clears "$T/plain.log")
run "first run with a mount file" "$T/first.log" --set mount_file="$T/mount"
FIRST=$(clears "$T/first.log")
check "first run: no remembered mounting yet" 'grep -q "no remembered mounting in" "$T/first.log"' "$T/first.log"
check "first run: verdicts as without the file ($FIRST clear, $PLAIN without)" 'alike "$FIRST" "$PLAIN"' "$T/first.log"
check "first run: kept after the walk verified the start" 'grep -q "mounting remembered (walk)" "$T/first.log"' "$T/first.log"
H=$(sed -n 's/^cam_height_mm = \([0-9]*\)$/\1/p' "$T/mount" 2>/dev/null)
check "the file holds the measured height (${H:-none} mm for 1450)" '[ -n "$H" ] && [ "$H" -ge 1400 ] && [ "$H" -le 1500 ]' "$T/first.log"
run "second run" "$T/second.log" --set mount_file="$T/mount"
SECOND=$(clears "$T/second.log")
check "second run: starts from the remembered mounting" 'grep -q "mounting hint from" "$T/second.log"' "$T/second.log"
echo "clear pairs of 30: first run $FIRST, second run $SECOND"
check "second run: clear from its first pairs ($SECOND of 30, first run $FIRST)" '[ "$SECOND" -ge 27 ] && [ "$SECOND" -ge $((FIRST + 10)) ]' "$T/second.log"

# Fail-safe: an unwritable place and a damaged file.
run "unwritable mount file" "$T/nowrite.log" --set mount_file="$T/nodir/mount"
check "unwritable: warned once" '[ "$(grep -c "cannot remember the mounting" "$T/nowrite.log")" -eq 1 ]' "$T/nowrite.log"
check "unwritable: verdicts unchanged ($(clears "$T/nowrite.log") clear, $PLAIN without)" 'alike "$(clears "$T/nowrite.log")" "$PLAIN"' "$T/nowrite.log"
printf 'cam_height_mm = 99999\ncam_pitch_mdeg = 20000\n' >"$T/bad"
run "damaged mount file" "$T/bad.log" --set mount_file="$T/bad"
check "damaged: ignored with a reason" 'grep -q "remembered mounting ignored: .*outside" "$T/bad.log"' "$T/bad.log"
check "damaged: verdicts as without it ($(clears "$T/bad.log") clear, $PLAIN without)" 'alike "$(clears "$T/bad.log")" "$PLAIN"' "$T/bad.log"
check "damaged: replaced by the measured mounting" 'grep -q "^cam_height_mm = 1[45][0-9][0-9]$" "$T/bad"' "$T/bad.log"

# A save that never finishes (a FIFO nobody reads in the place of the
# temporary file: fopen waits for a reader, as a stalled card would hold
# the write) holds up no verdict and, 2 s after the last pair, not the exit.
mkdir -p "$T/stall" && mkfifo "$T/stall/mount.tmp"
timeout 60 "$RUN" --config "$T/rig.conf" --set mount_file="$T/stall/mount" \
    replay:"$T/raw/pgm" >"$T/stall.log" 2>&1
rc=$?
check "stalled save: the run ends by itself, exit 0 (exit $rc)" '[ $rc -eq 0 ]' "$T/stall.log"
check "stalled save: every pair judged ($(clears "$T/stall.log") clear, $PLAIN without)" 'grep -q "summary pairs=30 " "$T/stall.log" && alike "$(clears "$T/stall.log")" "$PLAIN"' "$T/stall.log"
check "stalled save: said at the end" 'grep -q "still not written after 2000 ms; the old one stays" "$T/stall.log"' "$T/stall.log"

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
