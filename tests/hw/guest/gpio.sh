# Section gpio: drive a line through the GPIO character device and read it
# back through the chardev and through the kernel as an outside observer.
#  a) QEMU virt's PL061 (in-tree driver), observer /sys/kernel/debug/gpio
#     (gpiolib reads the controller's data register); line 0 (line 3 is the
#     power button on virt).
#  b) gpio-sim (built out of tree, when present), observer its sysfs
#     sim_gpioN/value (the simulated pin level).
set -e
gpio_test -l 9030000.pl061 -o 0
gpio_test -l 9030000.pl061 -o 2

if modprobe gpio-sim 2>/dev/null; then
    mount -t configfs none /sys/kernel/config 2>/dev/null || true
    G=/sys/kernel/config/gpio-sim/negobs
    mkdir $G $G/bank0
    echo 8 > $G/bank0/num_lines
    echo negobs-sim > $G/bank0/label
    mkdir $G/bank0/line0
    echo motor > $G/bank0/line0/name
    echo 1 > $G/live
    CHIP=$(cat $G/bank0/chip_name)
    S=/sys/devices/platform/$(cat $G/dev_name)/$CHIP
    echo "gpio-sim: $CHIP at $S"
    gpio_test -l negobs-sim -o 0 -s $S/sim_gpio0/value
else
    echo "gpio-sim.ko not in this image: PL061 only"
fi
