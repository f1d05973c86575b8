# Section pwm: pwm-sim.ko (tests/hw/kmod/pwm-sim.c) registers a PWM chip with
# the real 6.1 PWM core; pwm_test drives channels 0 and 1 through sysfs
# (export, period, duty_cycle, enable, unexport) and checks the read-back,
# the core's EINVAL for duty > period, and /sys/kernel/debug/pwm.
set -e
. /tests/lib.sh
hw_pwm_sim_load 2
pwm_test -d pwm-sim -n 0
pwm_test -d pwm-sim -n 1
dmesg | grep 'pwm-sim:' | tail -n 4
