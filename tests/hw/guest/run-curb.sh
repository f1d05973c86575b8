# Section run-curb: the real negobs_run (static aarch64, built from the
# tree) watches a synthetic walk toward a 150 mm curb that arrives through
# vivid's loopback, and drives a gpio-sim line; the line is observed from
# outside (gpio-sim's sim_gpio0/value, 5 ms sampling, motor_watch).
# Pass: negobs_run logs a hazard verdict (caution or imminent), the motor
# line shows that hazard's pattern (lib/src/alert/alert.c) within HAZARD_LAG_S of
# the logged change, no hazard pattern appears before the first hazard
# verdict, the first hazard comes before the walk ends (edge >= 1.24 m), and
# negobs_run exits 0 on SIGINT.
# ALERT_KIND=pwm (section run-curb-pwm): the motor is a pwm-sim channel
# (--alert pwm:N:0) and the observer reads its duty_cycle (> 0 = on); the
# channel must be enabled with period 1000000 while negobs_run runs.
set -u
. /tests/lib.sh
. /tests/negobs_lib.sh
negobs_prereq
HOLD_MS=${HOLD_MS:-1000}      # each synth frame (0.1 s of walk) shown this long
FRAMES=24                     # build_negobs.sh: edge 4000 mm - 120 mm/frame
RUN_S=$((FRAMES * HOLD_MS / 1000 + 6))
WDOG_MS=${WDOG_MS:-5000}      # see docs/EMULATION_TESTS.md: TCG is slower than a pair per 300 ms
HAZARD_LAG_S=3
TOL_MS=60

negobs_vivid_load || exit 1
S=${ALERT_KIND:-gpio}
if [ "$S" = pwm ]; then
    hw_pwm_sim_load 2 || { echo "pwm-sim.ko not in the image"; exit 77; }
    ALERT="pwm:$HW_PWMCHIP:0"
    PWMD=/sys/class/pwm/pwmchip$HW_PWMCHIP/pwm0
    WATCH=$PWMD/duty_cycle      # exported by negobs_run; motor_watch waits for it
else
    hw_gpio_sim_setup negobs-curb 8 || { echo "gpio-sim not in the image: no motor observer"; exit 77; }
    ALERT="gpio:$HW_GPIOCHIP:0"
    WATCH=$HW_GPIO_SIM/sim_gpio0/value
fi
{ cat $NEGOBS/rig.conf; echo "watchdog_ms = $WDOG_MS"; echo "max_frame_age_ms = $WDOG_MS"; echo "pair_tolerance_ms = 20"
  echo "record = /tmp/rec"; } > /tmp/curb.conf
negobs_watch_start "$WATCH"
hw_inject_start -f GREY -W 640 -H 480 -L $NEGOBS/curb/left.raw -R $NEGOBS/curb/right.raw -P "$HOLD_MS" || exit 1
T_INJ=$(now)
negobs_start /tmp/curb.conf "$ALERT"
PWMSTATE=""
d5=$(hw_deadline 5) d=$(hw_deadline $RUN_S)
while hw_before "$d" && kill -0 $NEGOBS_PID 2>/dev/null; do
    sleep 1
    [ "$S" = pwm ] && [ -z "$PWMSTATE" ] && ! hw_before "$d5" && PWMSTATE="enable=$(cat $PWMD/enable 2>&1) period=$(cat $PWMD/period 2>&1)"
done
rc=0
if [ "$S" = pwm ]; then
    echo "run-curb: pwm channel 5 s into the run: $PWMSTATE"
    [ "$PWMSTATE" = "enable=1 period=1000000" ] || { echo "run-curb: FAIL: pwm channel not enabled at 1 ms period"; rc=1; }
fi
negobs_stop || { echo "run-curb: negobs_run did not end cleanly"; rc=1; }
if [ "$S" = pwm ]; then
    [ -e "$PWMD" ] && { echo "run-curb: FAIL: pwm0 still exported after exit"; rc=1; }
    grep -A2 pwm-sim /sys/kernel/debug/pwm 2>/dev/null | sed 's/^/run-curb: after exit: /'
    # the motor is left off: pwm-sim's recorded state for channel 0
    grep -A2 pwm-sim /sys/kernel/debug/pwm 2>/dev/null | grep -q ' pwm-0 .*duty: 0 ns' ||
        { echo "run-curb: FAIL: pwm channel 0 not at duty 0 after exit"; rc=1; }
fi
T_END=$(now)
negobs_watch_stop
hw_inject_stop

echo "run-curb: walk started at $T_INJ, frame i shown from T+i*${HOLD_MS}ms, edge = 4000-120*i mm"
echo "run-curb: verdict changes (negobs_run time):"
grep 'verdict ' /tmp/negobs.log | sed 's/^/run-curb:   /'
echo "run-curb: motor pulses (boot clock, width ms):"
pulses | tr '\n' ';' | sed 's/^/run-curb:   /'; echo
TV=$(log_time 'verdict .* -> (caution|imminent)')
if [ -z "$TV" ]; then
    echo "run-curb: FAIL: negobs_run never logged a hazard verdict"
    exit 1
fi
VB=$(awk -v a="$T_START" -v b="$TV" 'BEGIN { printf "%.3f", a + b }')
IDX=$(awk -v v="$VB" -v i="$T_INJ" -v h="$HOLD_MS" 'BEGIN { k = int((v - i) * 1000 / h); if (k > 23) k = 23; print k }')
echo "run-curb: first hazard verdict at ${TV}s of negobs_run (boot $VB), frame $IDX shown, edge $((4000 - 120 * IDX)) mm ahead"
# READY (100/100/100 ms) plays in the first ~0.5 s and looks like caution:
# hazard patterns are looked for after it
T_READY=$(awk -v a="$T_START" 'BEGIN { print a + 1.0 }')
FIRST=$(patterns "$(awk -v a="$VB" 'BEGIN { print a - 0.1 }')" "$T_END" | awk '$1 == "caution" || $1 == "imminent"' | head -n 1)
PRE=$(patterns "$T_READY" "$(awk -v a="$VB" 'BEGIN { print a - 0.1 }')" |
      awk '$1 == "caution" || $1 == "imminent"' | head -n 1)
echo "run-curb: patterns recognised on the line after READY: $(patterns "$T_READY" "$T_END" | awk '{ c[$1]++ } END { for (k in c) printf "%s=%d ", k, c[k] }')"
if [ -z "$FIRST" ]; then
    echo "run-curb: FAIL: no caution/imminent pattern on the motor line"; rc=1
else
    set -- $FIRST
    LAG=$(awk -v p="$2" -v v="$VB" 'BEGIN { printf "%.0f", (p - v) * 1000 }')
    echo "run-curb: first hazard pattern on the line: $1 at boot $2, ${LAG} ms after the logged verdict"
    awk -v l="$LAG" -v m="$HAZARD_LAG_S" 'BEGIN { exit !(l >= -100 && l <= m * 1000) }' ||
        { echo "run-curb: FAIL: pattern not within -0.1..${HAZARD_LAG_S} s of the verdict"; rc=1; }
fi
[ -z "$PRE" ] || { echo "run-curb: FAIL: hazard pattern ($PRE) before any hazard verdict"; rc=1; }
[ "$IDX" -lt 23 ] || { echo "run-curb: FAIL: hazard only confirmed after the walk ended"; rc=1; }
grep 'status ' /tmp/negobs.log | tail -n 1 | sed 's/^/run-curb: last /'
# what negobs_run got = what was injected, pixel for pixel (its --record
# copy of every pair against the md5 of every original 320x240 frame)
np=$(grep -vc '^#' /tmp/rec/frames.txt 2>/dev/null)
exact=0 same=0 i=0
while [ "$i" -lt "${np:-0}" ]; do
    l=$(dd if=/tmp/rec/left.y bs=76800 skip=$i count=1 2>/dev/null | md5sum | cut -d' ' -f1)
    r=$(dd if=/tmp/rec/right.y bs=76800 skip=$i count=1 2>/dev/null | md5sum | cut -d' ' -f1)
    li=$(awk -v m="$l" '$1 == m { print $2; exit }' $NEGOBS/curb/left.md5)
    ri=$(awk -v m="$r" '$1 == m { print $2; exit }' $NEGOBS/curb/right.md5)
    [ -n "$li" ] && [ -n "$ri" ] && exact=$((exact + 1))
    [ -n "$li" ] && [ "$li" = "$ri" ] && same=$((same + 1))
    echo "run-curb: pair $i: left = synth frame ${li:-NONE}, right = synth frame ${ri:-NONE}"
    i=$((i + 1))
done
echo "run-curb: $exact of ${np:-0} recorded pairs pixel-identical to injected synth frames, $same of them left/right from the same frame"
[ "${np:-0}" -gt 0 ] && [ "$exact" -eq "$np" ] || { echo "run-curb: FAIL: negobs_run did not get the injected pixels"; rc=1; }
exit $rc
