# Helpers of the run-fault-* sections (issue 6: runtime faults).  Source
# after /tests/lib.sh and /tests/negobs_lib.sh.  Each section runs the real
# negobs_run on one flat-ground pair (verdict clear = motor silent), waits
# for a first "clear", injects one fault, checks that negobs_run logs it and
# that the motor line (read from outside, motor_watch) carries only the
# no-information pattern while it lasts, removes the fault and checks that
# pairs are judged clear again without a restart; exit 0 on SIGINT.

# 300 ms is the product's watchdog; under TCG a pair takes 1-5 s to judge,
# so the sections use a limit above that (docs/EMULATION_TESTS.md)
WDOG_MS=${WDOG_MS:-4000}
TOL_MS=80
RC=0
fail() { echo "$SECTION: FAIL: $*"; RC=1; }
say() { echo "$SECTION: $*"; }
sec_of() { awk -v a="$1" -v s="$T_START" 'BEGIN { printf "%.3f", a - s }'; }  # boot -> negobs time
boot_of() { awk -v a="$1" -v s="$T_START" 'BEGIN { printf "%.3f", s + a }'; } # negobs -> boot

# fault_conf FILE [key = value lines]: the rig, the emulator's watchdog and
# frame age, pair_tolerance_ms 20 (two vivid instances, own clocks), extras
fault_conf() {
    f=$1; shift
    { cat $NEGOBS/rig.conf; echo "watchdog_ms = $WDOG_MS"; echo "max_frame_age_ms = ${AGE_MS:-$WDOG_MS}"
      echo "pair_tolerance_ms = 20"; for l in "$@"; do echo "$l"; done; } > "$f"
}

# wait_log PATTERN AFTER LIMIT_S: negobs time of the first log line matching
# PATTERN at or after AFTER (negobs seconds), waiting up to LIMIT_S
wait_log() {
    local d
    d=$(hw_deadline "$3")
    t=$(log_time "$1" "$2")
    while [ -z "$t" ] && hw_before "$d" && kill -0 $NEGOBS_PID 2>/dev/null; do
        sleep 0.5
        t=$(log_time "$1" "$2")
    done
    echo "$t"
}

# check_noinfo_only A B [WHAT]: the line in [A, B) (boot clock) carries the
# no-information pattern and nothing else: at least one long pulse (>= 330
# ms: no-info's 400 / 600 ms) and no caution or imminent pattern
# (patterns() of negobs_lib.sh).  Single short fragments are not counted:
# a schedule restarted mid-pulse (the motor thread's watchdog and the main
# loop both play no-info) cuts one, and motor_watch's samples are up to a
# few hundred ms apart under a loaded TCG.
check_noinfo_only() {
    NI=$(pulses | awk -v a="$1" -v b="$2" '$1 >= a && $1 < b && $2 >= 330' | wc -l)
    HZ=$(patterns "$1" "$2" | grep -cE '^(caution|imminent) ')
    what=${3:-during the fault}
    say "line $what (boot $1 .. $2): $NI no-info pulses, $HZ caution/imminent patterns; $(pulses | awk -v a="$1" -v b="$2" '$1 >= a && $1 < b { printf "%s/%s ", $1, $2 }')"
    [ "$NI" -ge 1 ] || fail "no no-info pulse on the line $what"
    [ "$HZ" -eq 0 ] || fail "$HZ hazard patterns on the line $what"
}

# slack_after T FLOOR: where to look for a line logged on an event at
# boot time T (negobs seconds). T_START is taken just before negobs_run is
# started, so a boot time converted with sec_of reads late by negobs_run's
# start-up time (tens to hundreds of ms under TCG): a line logged at once
# then reads "before" the event (run-fault-pwm saw 7.604 s against 7.609 s,
# run-fault-gpio 3.174 s against 3.178 s, and waited in vain). 0.5 s of
# slack, never before FLOOR.
slack_after() {
    awk -v b="$(sec_of "$1")" -v l="$2" \
        'BEGIN { a = b - 0.5; if (a < l) a = l; printf "%.3f", a }'
}

# back_after TB: the recovery line, never before the failure line TL:
# there is no "back" without a failure.
back_after() { slack_after "$1" "${TL:-0}"; }

# fault_after TF: the failure line, never before the first clear TC.
fault_after() { slack_after "$1" "${TC:-0}"; }

# wait_clear AFTER LIMIT_S: a clear verdict after AFTER (negobs seconds)
wait_clear() { wait_log 'verdict .* -> clear' "$1" "$2"; }

# fault_start CONF ALERT OBSERVER [inject options]: observer, injector
# (flat pair), negobs_run; then waits for the first clear verdict (TC)
fault_start() {
    conf=$1 alert=$2 obs=$3; shift 3
    rm -f /tmp/negobs.log   # an earlier section's log must not be read
    negobs_watch_start "$obs"
    hw_inject_start -f GREY -W 640 -H 480 -L $NEGOBS/flat/left.raw -R $NEGOBS/flat/right.raw "$@" || return 1
    negobs_start "$conf" "$alert"
}

# fault_end: stop everything, print the log and the pulses, final checks
fault_end() {
    negobs_stop || fail "negobs_run did not end cleanly (or was restarted)"
    negobs_watch_stop
    hw_inject_stop
    say "motor pulses (boot clock, width ms):"
    pulses | tr '\n' ';' | sed "s/^/$SECTION:   /"; echo
    grep 'summary ' /tmp/negobs.log | sed "s/^/$SECTION: /"
}

# motor_fault_report FAIL_EVENT BACK_EVENT: the verdict of a motor-output
# fault section (run-fault-gpio, run-fault-pwm) from TF/TL (fault injected,
# failure logged), TB/TK (fault removed, recovery logged) and
# FAIL_LIMIT_S/BACK_LIMIT_S; FAIL_EVENT/BACK_EVENT name the two moments in
# the messages ("the removal", "the return"). Exits with the section's rc.
motor_fault_report() {
    if [ -z "$TL" ]; then
        fail "no 'motor: output failing' within $FAIL_LIMIT_S s of $1"
    else
        say "failure logged $(awk -v l="$TL" -v f="$(sec_of $TF)" 'BEGIN { printf "%.1f", l - f }') s after $1: $(grep -m1 'motor: output failing' /tmp/negobs.log | sed 's/^.*warn: //')"
    fi
    if [ -z "$TK" ]; then
        fail "no 'motor: output back' within $BACK_LIMIT_S s of $2"
    else
        say "recovery logged $(awk -v k="$TK" -v b="$(sec_of $TB)" 'BEGIN { printf "%.1f", k - b }') s after $2"
        # the motor thread plays no-info from the first write that works
        # (negobs_run logs it at its next loop turn, seconds later under
        # TCG): from the return on, the entry burst and nothing but no-info
        # The window ends 8 s after the return, or 3 s (the 2 s burst and
        # a margin) after the recovery line when the back-off (up to 2 s)
        # and a slow TCG logged it later than 5 s: BACK_LIMIT_S allows that
        TE=$(awk -v b="$TB" -v k="$(boot_of "$TK")" \
            'BEGIN { e = b + 8; if (k + 3 > e) e = k + 3; printf "%.3f", e }')
        check_noinfo_only "$TB" "$TE" "from the return to boot $TE"
        FP=$(pulses | awk -v b="$TB" '$1 >= b && NF == 2 { print; exit }')
        say "first pulse after the return: ${FP:-none} (boot start, ms): $(awk -v p="${FP%% *}" -v b="$TB" 'BEGIN { printf "%.0f", (p - b) * 1000 }') ms after it"
    fi
    [ "$NEGOBS_RC" -eq 0 ] || fail "negobs_run exit status $NEGOBS_RC"
    exit $RC
}
