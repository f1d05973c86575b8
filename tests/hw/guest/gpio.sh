# Section gpio: drive a line through the GPIO character device (uAPI v2)
# and read it back through the chardev and through the kernel as an outside
# observer.
#  a) QEMU virt's PL061 (in-tree driver), lines 0 and 2 (line 3 is wired to
#     the power button on virt); observer /sys/kernel/debug/gpio, where
#     gpiolib reads the controller's data register.
#  b) gpio-sim (built out of tree, when present); observer its sysfs
#     sim_gpio0/value, the simulated pin level.
set -e
. /tests/lib.sh
gpio_test -l 9030000.pl061 -o 0
gpio_test -l 9030000.pl061 -o 2
if [ -n "$(modinfo -F filename gpio-sim 2>/dev/null)" ] || [ -n "$(find /lib/modules -name gpio-sim.ko)" ]; then
    hw_gpio_sim_setup negobs-sim 8
    gpio_test -l negobs-sim -o 0 -s "$HW_GPIO_SIM/sim_gpio0/value"
else
    echo "gpio-sim.ko not in this image: PL061 only"
fi
