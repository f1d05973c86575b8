# Section run-curb-pwm: run-curb with the motor on a pwm-sim channel
# (negobs_run --alert pwm:N:0), observed through its sysfs duty_cycle.
ALERT_KIND=pwm
. /tests/run-curb.sh
