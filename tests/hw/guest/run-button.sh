# Section run-button: the push button on a gpio-sim input line.  The real
# negobs_run runs on the flat pair with the motor on gpio-sim line 0 and
# `button = gpio:CHIP:1` (pressed = low, the default: a button to ground
# with a pull-up).  The script presses the button by setting the simulated
# line's pull through sysfs (sim_gpio1/pull: pull-down = pressed, pull-up
# = released), as a finger would, and checks negobs_run's reaction in its
# log and on the motor line read from outside (motor_watch):
#   short press (400 ms)  "button: short press: sensitivity preset 1 (near)"
#                         and two ~120 ms pulses 300 ms apart (start to start)
#   long press (2.5 s)    "button: long press: paused", one ~700 ms pulse
#   long press again      "button: long press: resumed", two ~300 ms pulses
#                         500 ms apart
# each press counted once, exit 0 on SIGINT.  button_long_ms is 1500 (the
# default 1000 is kept apart from the short press by more than TCG's
# scheduling jitter either way; 1500 leaves more).
set -u
SECTION=run-button
. /tests/lib.sh
. /tests/negobs_lib.sh
. /tests/run-fault-lib.sh
negobs_prereq
TOL_MS=60
negobs_vivid_load || exit 1
hw_gpio_sim_setup negobs-button 8 || { echo "gpio-sim not in the image: no button line"; exit 77; }
PULL=$HW_GPIO_SIM/sim_gpio1/pull
echo pull-up > "$PULL" || { fail "cannot set $PULL"; exit 1; }
fault_conf /tmp/button.conf "button = gpio:$HW_GPIOCHIP:1" "button_long_ms = 1500"
fault_start /tmp/button.conf "gpio:$HW_GPIOCHIP:0" "$HW_GPIO_SIM/sim_gpio0/value" || exit 1

# press MS: the line low for MS ms of guest time; prints the boot time
press() {
    t=$(now)
    echo pull-down > "$PULL"
    hw_sleep "$1"
    echo pull-up > "$PULL"
    echo "$t"
}

# confirmation KIND T0 T1: the confirmation pattern KIND among the pulses
# starting in [T0, T1) (boot clock); prints its start, empty if none
confirmation() {
    pulses | awk -v kind="$1" -v t0="$2" -v t1="$3" -v tol="$TOL_MS" '
        function near(x, want) { return x >= want - tol && x <= want + tol }
        $1 >= t0 && $1 < t1 { n++; s[n] = $1; w[n] = $2 }
        END {
            for (i = 1; i <= n; i++) {
                g = (i < n) ? (s[i + 1] - s[i]) * 1000 : -1
                if ((kind == "preset1" && i < n && near(w[i], 120) && near(w[i + 1], 120) && near(g, 300)) ||
                    (kind == "pause" && near(w[i], 700)) ||
                    (kind == "resume" && i < n && near(w[i], 300) && near(w[i + 1], 300) && near(g, 500))) {
                    print s[i]; exit
                }
            }
        }'
}

# step NAME MS PATTERN KIND: one press of MS ms, then negobs_run's log line
# (PATTERN, within 20 s: presses are applied between pairs, 1-5 s each
# under TCG) and the confirmation KIND on the line within 5 s of it
step() {
    tp=$(press "$2")
    tl=$(wait_log "$3" "$(sec_of "$tp")" 20)
    if [ -z "$tl" ]; then
        fail "$1: no '$3' within 20 s of the press"
        return
    fi
    say "$1: pressed at boot $tp, logged $(awk -v l="$tl" -v p="$(sec_of "$tp")" 'BEGIN { printf "%.1f", l - p }') s after the press began"
    hw_sleep 5
    tc=$(confirmation "$4" "$tp" "$(awk -v b="$(boot_of "$tl")" 'BEGIN { printf "%.3f", b + 5 }')")
    if [ -z "$tc" ]; then
        fail "$1: no $4 confirmation on the motor line"
    else
        say "$1: $4 confirmation on the line at boot $tc, $(awk -v c="$tc" -v l="$(boot_of "$tl")" 'BEGIN { printf "%.0f", (c - l) * 1000 }') ms after the log line"
    fi
}

TC=$(wait_clear 0 60)
if [ -z "$TC" ]; then
    fail "no clear verdict within 60 s"
else
    hw_sleep 1
    step "short press" 0.4 'button: short press: sensitivity preset 1 .near.' preset1
    step "long press" 2.5 'button: long press: paused' pause
    step "long press again" 2.5 'button: long press: resumed' resume
fi
fault_end
[ -n "$TC" ] || exit 1
ns=$(grep -c 'button: short press' /tmp/negobs.log)
nl=$(grep -c 'button: long press' /tmp/negobs.log)
[ "$ns" -eq 1 ] || fail "$ns short presses logged (1 pressed)"
[ "$nl" -eq 2 ] || fail "$nl long presses logged (2 pressed)"
[ "$NEGOBS_RC" -eq 0 ] || fail "negobs_run exit status $NEGOBS_RC"
exit $RC
