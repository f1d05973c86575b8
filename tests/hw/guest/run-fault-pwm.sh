# Section run-fault-pwm: every PWM write fails for a while: pwm-sim's
# fail_apply parameter makes its .apply return -EIO, so negobs_run's writes
# to duty_cycle fail with EIO (the PWM core keeps the old state).  The motor
# thread rewrites the level every second, so the failure is seen while the
# motor is silent (verdict clear) - for GPIO.  The PWM core skips a write
# that changes nothing, so a PWM fault shows at the next level change: the
# section runs with the product's watchdog_ms 300, far below the emulated
# pair time (0.5-1.7 s), so the no-information switch 300 ms after each
# verdict changes the level between every two pairs (1500 left the motor
# silent for a whole run when the host happened to be fast enough; frames
# may still be 4 s old).  The observer reads the channel's sysfs
# duty_cycle (> 0 = on).
# Pass: a first clear verdict; "motor: output failing" logged within
# FAIL_LIMIT_S; after fail_apply goes back to 0, "motor: output back" within
# BACK_LIMIT_S, then the no-information entry burst on the channel and
# nothing else; no restart; exit 0 on SIGINT.
set -u
SECTION=run-fault-pwm
. /tests/lib.sh
. /tests/negobs_lib.sh
WDOG_MS=300 AGE_MS=4000
. /tests/run-fault-lib.sh
negobs_prereq
FAIL_LIMIT_S=20
HOLD_S=3
BACK_LIMIT_S=10
KNOB=/sys/module/pwm_sim/parameters/fail_apply
negobs_vivid_load || exit 1
hw_pwm_sim_load 2 || { echo "pwm-sim not in the image"; exit 77; }
[ -w $KNOB ] || { echo "pwm-sim has no fail_apply parameter"; exit 1; }
fault_conf /tmp/pfault.conf
fault_start /tmp/pfault.conf "pwm:$HW_PWMCHIP:0" "/sys/class/pwm/pwmchip$HW_PWMCHIP/pwm0/duty_cycle" || exit 1
TC=$(wait_clear 0 60)
TF="" TL="" TB="" TK=""
if [ -z "$TC" ]; then
    fail "no clear verdict within 60 s"
else
    hw_sleep 2
    TF=$(now); echo 1 > $KNOB
    say "PWM writes failing from boot $TF (negobs_run $(sec_of $TF)s)"
    TL=$(wait_log 'motor: output failing' "$(fault_after $TF)" $FAIL_LIMIT_S)
    hw_sleep $HOLD_S
    TB=$(now); echo 0 > $KNOB
    say "PWM writes work again from boot $TB (negobs_run $(sec_of $TB)s)"
    TK=$(wait_log 'motor: output back' "$(back_after $TB)" $BACK_LIMIT_S)
    hw_sleep 9
fi
fault_end
[ -n "$TC" ] || exit 1
motor_fault_report "the knob" "the knob was cleared"
