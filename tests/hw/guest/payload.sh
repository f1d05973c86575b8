# Section payload: runs /payload/run.sh, copied into the initramfs from the
# directory given to `tests/hw/run.sh --payload DIR` (e.g. a static
# negobs_run, recorded frames and a script; see docs/EMULATION_TESTS.md).
# The same tools as the other sections are on PATH (v4l2_loop, gpio_test,
# pwm_test, busybox), pwm-sim/gpio-sim modules are available to modprobe.
if [ ! -f /payload/run.sh ]; then
    echo "no /payload/run.sh in the initramfs"
    exit 77
fi
cd /payload
sh ./run.sh
