# Default payload script (/payload/run.sh in the guest), used by the
# "payload" section when the --payload directory brings no run.sh of its own.
#
# With /payload/negobs_run (a static aarch64 build dropped in with
# `tests/hw/run.sh --payload-file path/to/negobs_run`): loads vivid in
# loopback, gpio-sim (motor line) and pwm-sim, starts the injector feeding
# /dev/video2 + /dev/video3, runs
#     negobs_run /dev/video0 /dev/video1 $NEGOBS_ARGS
# for RUN_SECONDS, samples the motor line from outside (gpio-sim's sysfs
# value) the whole time, and reports what the motor did.
# Without negobs_run: the same arrangement with the stand-in consumer
# (v4l2_loop capture) and gpio_test driving the motor line, so the section
# still proves the plumbing.
#
# Knobs, from /payload/env when present (a sh fragment):
#   FORMAT=GREY|YUYV W=640 H=480  injector format; must be what negobs_run sets
#   LEFT=left.raw RIGHT=right.raw raw frames to inject (W*H*bpp bytes each,
#                                 concatenated, cycled); default: generated
#   RUN_SECONDS=20                how long negobs_run runs before SIGINT
#   NEGOBS_ARGS="..."             arguments after the two device paths;
#                                 default "--alert gpio:$HW_GPIOCHIP:0"
#   EXPECT_MOTOR=any|on|off       on: the motor line must have been seen high;
#                                 off: never high; any: no check
set -u
. /tests/lib.sh
FORMAT=GREY W=640 H=480 LEFT="" RIGHT="" RUN_SECONDS=20 EXPECT_MOTOR=any NEGOBS_ARGS=""
[ -f ./env ] && . ./env

hw_vivid_load || exit 1
if ! hw_gpio_sim_setup negobs-motor 8; then
    echo "gpio-sim not in the image (built with --no-gpio-sim?): no motor observer"
    exit 77
fi
hw_pwm_sim_load 2 || echo "(no pwm-sim: PWM alert backend cannot be tried)"
MOTOR=$HW_GPIO_SIM/sim_gpio0/value

if [ -n "$LEFT" ]; then
    hw_inject_start -f "$FORMAT" -W "$W" -H "$H" -L "$LEFT" -R "$RIGHT" || exit 1
else
    hw_inject_start -f "$FORMAT" -W "$W" -H "$H" || exit 1
fi

# outside observer: one motor sample every 50 ms into /tmp/motor.samples
: > /tmp/motor.samples
( while :; do cat "$MOTOR" >> /tmp/motor.samples; sleep 0.05; done ) &
SAMPLER=$!

if [ -x ./negobs_run ]; then
    [ -n "$NEGOBS_ARGS" ] || NEGOBS_ARGS="--alert gpio:$HW_GPIOCHIP:0"
    echo "payload: negobs_run /dev/video0 /dev/video1 $NEGOBS_ARGS (for ${RUN_SECONDS}s)"
    # busybox timeout execs the program and kills it from a child: the exit
    # status is 128 + signal when it had to be stopped
    timeout -s INT "$RUN_SECONDS" ./negobs_run /dev/video0 /dev/video1 $NEGOBS_ARGS
    rc=$?
    case $rc in 0|124|130|143) echo "payload: negobs_run ended with $rc (ok)"; rc=0 ;;
        *) echo "payload: negobs_run failed with $rc" ;; esac
else
    echo "payload: no /payload/negobs_run; stand-in consumer + gpio_test"
    if [ -n "$LEFT" ]; then x=-x; else x=""; fi
    v4l2_loop capture -q $x -f "$FORMAT" -W "$W" -H "$H" -n 10 /dev/video0 /dev/video1
    rc=$?
    gpio_test -l negobs-motor -o 0 -s "$MOTOR" -c negobs-standin || rc=1
fi

sleep 0.2
kill $SAMPLER 2>/dev/null; wait $SAMPLER 2>/dev/null
hw_inject_stop
hi=$(grep -c '^1' /tmp/motor.samples)
all=$(wc -l < /tmp/motor.samples)
echo "payload: motor line high in $hi of $all samples (50 ms apart)"
cat /sys/kernel/debug/pwm 2>/dev/null | sed 's/^/payload: pwm: /'
case $EXPECT_MOTOR in
    on) [ "$hi" -gt 0 ] || { echo "payload: expected the motor on at least once"; rc=1; } ;;
    off) [ "$hi" -eq 0 ] || { echo "payload: expected the motor never on"; rc=1; } ;;
esac
exit $rc
