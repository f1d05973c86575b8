# Section pwm: pwm-sim.ko (tests/hw/kmod/pwm-sim.c) registers a PWM chip with
# the real 6.1 PWM core; pwm_test drives channel 0 through sysfs (export,
# period, duty_cycle, enable, unexport) and checks the read-back, the core's
# EINVAL for duty > period, and /sys/kernel/debug/pwm.
set -e
if ! modprobe pwm-sim npwm=2; then
    echo "pwm-sim.ko missing or failed to load"
    exit 1
fi
ls /sys/class/pwm
pwm_test -d pwm-sim -n 0
pwm_test -d pwm-sim -n 1
dmesg | grep 'pwm-sim:' | tail -n 4
