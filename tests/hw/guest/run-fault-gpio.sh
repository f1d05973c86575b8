# Section run-fault-gpio: the motor's GPIO chip disappears under the running
# negobs_run and comes back: gpio-sim's configfs "live" goes to 0 (the chip
# is unregistered; writes on the held line fail with ENODEV) and, HOLD_S
# later, to 1 (a new chip, same /dev/gpiochipN).  negobs_run's motor thread
# rewrites the current level every second, so the loss is seen while the
# motor is silent (verdict clear).
# Pass: a first clear verdict; "motor: output failing" logged within
# FAIL_LIMIT_S of the removal; "motor: output back" within BACK_LIMIT_S of the
# return (the line requested again, with back-off); the line then plays the
# no-information entry burst (400 ms pulses) and nothing else, and falls
# silent again (clear) without a restart; exit 0 on SIGINT.
set -u
SECTION=run-fault-gpio
. /tests/lib.sh
. /tests/negobs_lib.sh
. /tests/run-fault-lib.sh
negobs_prereq
FAIL_LIMIT_S=10
HOLD_S=3
BACK_LIMIT_S=15
negobs_vivid_load || exit 1
hw_gpio_sim_setup negobs-gfault 8 || { echo "gpio-sim not in the image: no motor observer"; exit 77; }
fault_conf /tmp/gfault.conf
fault_start /tmp/gfault.conf "gpio:$HW_GPIOCHIP:0" "$HW_GPIO_SIM/sim_gpio0/value" || exit 1
TC=$(wait_clear 0 60)
TF="" TL="" TB="" TK=""
if [ -z "$TC" ]; then
    fail "no clear verdict within 60 s"
else
    hw_sleep 2
    TF=$(now); echo 0 > "$G/live" || fail "cannot take the chip down"
    say "gpio chip removed at boot $TF (negobs_run $(sec_of $TF)s); /dev: $(ls /dev | grep gpiochip | tr '\n' ' ')"
    TL=$(wait_log 'motor: output failing' "$(fault_after $TF)" $FAIL_LIMIT_S)
    hw_sleep $HOLD_S
    # the observer follows the new chip's simulated pin (same edge file);
    # it runs before the chip returns, because the line plays the 2 s
    # recovery burst from the first write that works, which can come
    # before a watcher started afterwards has read its first sample
    kill "$WATCH_PID" 2>/dev/null; wait "$WATCH_PID" 2>/dev/null
    motor_watch -i 5 -c "$G" >> /tmp/edges &
    WATCH_PID=$!
    hw_sleep 1
    TB=$(now); echo 1 > "$G/live" || fail "cannot bring the chip back"
    chip=$(cat "$G/bank0/chip_name")
    say "gpio chip back at boot $TB as /dev/$chip (negobs_run $(sec_of $TB)s)"
    [ "/dev/$chip" = "$HW_GPIOCHIP" ] || say "note: the chip came back under another name (negobs_run finds it by its label)"
    TK=$(wait_log 'motor: output back' "$(back_after $TB)" $BACK_LIMIT_S)
    # let the no-info hold (2 s) and a few pairs pass
    hw_sleep 9
fi
fault_end
[ -n "$TC" ] || exit 1
motor_fault_report "the removal" "the return"
