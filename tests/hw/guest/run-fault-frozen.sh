# Section run-fault-frozen: a camera keeps delivering frames whose content
# no longer changes.  The injector adds sensor-like noise to the held flat
# pair (v4l2_loop -N: real sensors never repeat a frame) until
# /tmp/noise.off exists; from then on vivid loops byte-identical frames.
# negobs_run runs with frozen_frames 6 (identical frames in a row, counted
# as dequeued).  Pass: a first clear verdict; after the freeze negobs_run
# logs "camera: ... frozen" within FROZEN_LIMIT_S and the motor line plays
# only no-information until the noise returns; then a clear verdict again
# within RESUME_LIMIT_S, without a reopen; exit 0 on SIGINT.
set -u
SECTION=run-fault-frozen
. /tests/lib.sh
. /tests/negobs_lib.sh
. /tests/run-fault-lib.sh
negobs_prereq
FROZEN_LIMIT_S=30
HOLD_S=4
RESUME_LIMIT_S=40
negobs_vivid_load || exit 1
hw_gpio_sim_setup negobs-frozen 8 || { echo "gpio-sim not in the image: no motor observer"; exit 77; }
fault_conf /tmp/frozen.conf "frozen_frames = 6"
rm -f /tmp/noise.off
fault_start /tmp/frozen.conf "gpio:$HW_GPIOCHIP:0" "$HW_GPIO_SIM/sim_gpio0/value" -N /tmp/noise.off || exit 1
TC=$(wait_clear 0 60)
TF="" TL="" TB="" TR=""
if [ -z "$TC" ]; then
    fail "no clear verdict within 60 s"
else
    hw_sleep 1
    TF=$(now); touch /tmp/noise.off
    say "stream frozen at boot $TF (negobs_run $(sec_of $TF)s)"
    TL=$(wait_log 'camera: .*frozen' "$(sec_of $TF)" $FROZEN_LIMIT_S)
    [ -n "$TL" ] && hw_sleep $HOLD_S
    TB=$(now); rm -f /tmp/noise.off
    say "stream alive again at boot $TB (negobs_run $(sec_of $TB)s)"
    TR=$(wait_clear "$(sec_of $TB)" $RESUME_LIMIT_S)
fi
fault_end
[ -n "$TC" ] || exit 1
if [ -z "$TL" ]; then
    fail "no 'camera: ... frozen' within $FROZEN_LIMIT_S s of the freeze"
else
    say "'frozen' logged $(awk -v l="$TL" -v f="$(sec_of $TF)" 'BEGIN { printf "%.1f", l - f }') s after the freeze: $(grep -m1 'frozen' /tmp/negobs.log)"
    check_noinfo_only "$(boot_of "$TL")" "$TB"
fi
if [ -z "$TR" ]; then
    fail "no clear verdict within $RESUME_LIMIT_S s after the stream came alive"
else
    say "clear again $(awk -v r="$TR" -v b="$(sec_of $TB)" 'BEGIN { printf "%.1f", r - b }') s after the stream came alive"
fi
grep -q 'reopens=[1-9]' /tmp/negobs.log && fail "a camera was reopened (frozen must not need it)"
exit $RC
