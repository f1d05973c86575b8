# Section run-fault-drift: left and right timestamps further apart than
# pair_tolerance_ms.  vivid stamps capture buffers itself, one clock per
# instance, and offers no way to delay one by a chosen amount; its "Wrap
# Timestamp" control (32 Bit) moves an instance's clock about 68 years ahead
# from the next stream start.  It is set on the RIGHT camera before
# negobs_run starts, so the cameras are out of step from the first frame
# (the pairing path is the same for any offset above the limit; a 16 ms
# drift is a unit test, test_v4l2_wrap.c).  To end the drift the control
# goes back to None and the right camera's stream has to restart: its
# frames are stopped ("Percentage of Dropped Buffers" 100) until negobs_run
# reopens it (3 timeouts), then let through again.
# Pass: negobs_run logs "left/right out of sync" (frames dropped) within
# DRIFT_LIMIT_S; the line carries only no-information meanwhile; after the
# drift a clear verdict within RESUME_LIMIT_S, without a restart; exit 0.
set -u
SECTION=run-fault-drift
. /tests/lib.sh
. /tests/negobs_lib.sh
WDOG_MS=2500   # three get_pair timeouts make the reopen: keep them short
. /tests/run-fault-lib.sh
negobs_prereq
DRIFT_LIMIT_S=30
HOLD_S=3
REOPEN_LIMIT_S=40
RESUME_LIMIT_S=40
negobs_vivid_load || exit 1
hw_gpio_sim_setup negobs-drift 8 || { echo "gpio-sim not in the image: no motor observer"; exit 77; }
fault_conf /tmp/drift.conf
negobs_watch_start "$HW_GPIO_SIM/sim_gpio0/value"
hw_inject_start -f GREY -W 640 -H 480 -L $NEGOBS/flat/left.raw -R $NEGOBS/flat/right.raw || exit 1
v4l2_loop ctrl /dev/video1 "Wrap Timestamp" 2 || { fail "cannot set Wrap Timestamp"; exit 1; }
rm -f /tmp/negobs.log
negobs_start /tmp/drift.conf "gpio:$HW_GPIOCHIP:0"
TL=$(wait_log 'out of sync' 0 $DRIFT_LIMIT_S)
TE="" TO="" TR=""
if [ -n "$TL" ]; then
    hw_sleep $HOLD_S
    # end of the drift: clock back to normal, stream restarted by negobs_run
    TE=$(now)
    v4l2_loop ctrl /dev/video1 "Wrap Timestamp" 0 || fail "cannot clear Wrap Timestamp"
    v4l2_loop ctrl /dev/video1 "Percentage of Dropped Buffers" 100 || fail "cannot stop /dev/video1"
    say "drift ends at boot $TE (negobs_run $(sec_of $TE)s): right stream stopped until reopened"
    d=$(hw_deadline $REOPEN_LIMIT_S)
    while ! grep -q 'reopens=[1-9]' /tmp/negobs.log && hw_before "$d"; do
        sleep 0.5
    done
    v4l2_loop ctrl /dev/video1 "Percentage of Dropped Buffers" 0 || fail "cannot restart /dev/video1"
    TO=$(now)
    grep -q 'reopens=[1-9]' /tmp/negobs.log || fail "right camera not reopened within $REOPEN_LIMIT_S s"
    say "right stream reopened and let through at boot $TO (negobs_run $(sec_of $TO)s)"
    TR=$(wait_clear "$(sec_of $TO)" $RESUME_LIMIT_S)
fi
fault_end
if [ -z "$TL" ]; then
    fail "no 'left/right out of sync' within $DRIFT_LIMIT_S s"
    exit 1
fi
say "logged at ${TL}s: $(grep -m1 'out of sync' /tmp/negobs.log)"
FC=$(log_time 'verdict .* -> clear')
if [ -n "$FC" ] && awk -v c="$FC" -v e="$(sec_of $TE)" 'BEGIN { exit !(c < e) }'; then
    fail "a clear verdict at ${FC}s while out of sync"
fi
D=$(awk '/ status fps=/ && $0 ~ /dropped=/ { sub(/.*dropped=/, ""); sub(/ .*/, ""); d = $0 } END { print d + 0 }' /tmp/negobs.log)
say "dropped pairs counted by negobs_run: $D"
[ "$D" -ge 1 ] || fail "no dropped pairs in the status lines"
# the line from the first out-of-sync log to the end of the drift
check_noinfo_only "$(boot_of "$TL")" "$TE"
if [ -z "$TR" ]; then
    fail "no clear verdict within $RESUME_LIMIT_S s after the drift ended"
else
    say "clear again $(awk -v r="$TR" -v b="$(sec_of $TO)" 'BEGIN { printf "%.1f", r - b }') s after the stream was let through"
fi
exit $RC
