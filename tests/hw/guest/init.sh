#!/bin/sh
# /init of the negobs emulated-hardware test initramfs (tests/hw/run.sh).
# Mounts the kernel filesystems, runs the sections named on the kernel
# command line (negobs.sections=vivid,gpio,pwm,payload) from /tests/SECTION.sh
# and prints, on the serial console, one line per section:
#   SECTION <name>: PASS | FAIL | SKIPPED: <reason>
# then "GUEST-RESULT: PASS|FAIL" and powers off.  A section script exits 0
# for pass, 77 for skip (reason = its last output line), anything else fails.
/bin/busybox --install -s /bin
export PATH=/bin:/sbin:/usr/bin:/payload
mount -t proc proc /proc
mount -t sysfs sysfs /sys
mount -t devtmpfs devtmpfs /dev
mount -t debugfs debugfs /sys/kernel/debug
mount -t tmpfs tmpfs /tmp
echo "GUEST: up $(cut -d' ' -f1 /proc/uptime)s, kernel $(uname -r) $(uname -m)"

SECTIONS=vivid
for arg in $(cat /proc/cmdline); do
    case "$arg" in
        negobs.sections=*) SECTIONS=$(echo "${arg#negobs.sections=}" | tr ',' ' ') ;;
    esac
done

result=PASS
for s in $SECTIONS; do
    echo "GUEST: section $s start $(cut -d' ' -f1 /proc/uptime)s"
    if [ ! -f "/tests/$s.sh" ]; then
        echo "SECTION $s: FAIL (no /tests/$s.sh in the initramfs)"
        result=FAIL
        continue
    fi
    # A section that hangs must not take the later ones down with it (the
    # whole guest would otherwise run into qemu's timeout with no output):
    # it gets SECTION_LIMIT_S, then it and whatever it started are killed
    # and it fails with the log it wrote so far.
    timeout -s KILL "${SECTION_LIMIT_S:-150}" sh "/tests/$s.sh" > "/tmp/$s.log" 2>&1
    rc=$?
    if [ $rc -eq 137 ] || [ $rc -eq 124 ]; then
        echo "section did not finish within ${SECTION_LIMIT_S:-150} s: killed" >> "/tmp/$s.log"
        killall -KILL negobs_run v4l2_loop motor_watch lc_capture gpio_test pwm_test 2>/dev/null
        sleep 1
    fi
    sed "s/^/[$s] /" "/tmp/$s.log"
    t=$(cut -d' ' -f1 /proc/uptime)
    if [ $rc -eq 0 ]; then
        echo "SECTION $s: PASS (guest uptime ${t}s)"
    elif [ $rc -eq 77 ]; then
        echo "SECTION $s: SKIPPED: $(tail -n 1 "/tmp/$s.log")"
    else
        echo "SECTION $s: FAIL (rc $rc, guest uptime ${t}s)"
        result=FAIL
    fi
done
echo "GUEST-RESULT: $result"
sync
poweroff -f
