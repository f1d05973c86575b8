# Helpers for the guest sections and for payload scripts (/tests/lib.sh).
# Source it: . /tests/lib.sh
# Every helper prints what it set up and returns non-zero on failure.

# Waits and holds are bounded by the guest's clock, never by counting
# sleeps: under TCG a plain `sleep` can return early (the kernel logged
# "schedule_timeout: wrong timeout value" once, and a 60 s wait made of
# 120 x `sleep 0.5` ended after a few seconds, failing run-camera-loss).
# hw_deadline S: the boot-clock time S seconds from now (/proc/uptime)
hw_deadline() { awk -v s="$1" '{ printf "%.2f\n", $1 + s }' /proc/uptime; }
# hw_before DEADLINE: true while the boot clock is before DEADLINE
hw_before() { awk -v d="$1" '{ exit !($1 < d + 0) }' /proc/uptime; }
# hw_sleep S: at least S seconds of the boot clock, however often sleep
# returns early
hw_sleep() {
    local d r
    d=$(hw_deadline "$1")
    while r=$(awk -v d="$d" '{ if (d - $1 > 0) printf "%.2f\n", d - $1; else print 0 }' /proc/uptime) && [ "$r" != 0 ]; do
        sleep "$r"
    done
}

# hw_vivid_load: two vivid instances in loopback mode.
#   /dev/video0 capture <- /dev/video2 output   (left eye)
#   /dev/video1 capture <- /dev/video3 output   (right eye)
hw_vivid_load() {
    modprobe vivid n_devs=2 node_types=0x101,0x101 vid_cap_nr=0,1 vid_out_nr=2,3 no_error_inj=1 || return 1
    for i in 0 1 2 3; do
        d=$(hw_deadline 5)
        while [ ! -e /dev/video$i ] && hw_before "$d"; do sleep 0.1; done
        [ -e /dev/video$i ] || { echo "vivid: /dev/video$i did not appear"; return 1; }
    done
    echo "vivid: capture /dev/video0 /dev/video1, output /dev/video2 /dev/video3 (loopback)"
}

# hw_inject_start [v4l2_loop inject options]: configures /dev/video0 and
# /dev/video1 for loopback and keeps feeding frames into /dev/video2 and
# /dev/video3 in the background (generated stereo pairs by default, or
# -L left.raw -R right.raw).  Sets HW_INJECT_PID.  The consumer must use the
# same format and size (default 640x480 GREY; -f YUYV for YUYV).
hw_inject_start() {
    rm -f /tmp/inject.ready
    v4l2_loop inject -q -r /tmp/inject.ready "$@" /dev/video0 /dev/video1 /dev/video2 /dev/video3 &
    HW_INJECT_PID=$!
    export HW_INJECT_PID
    # the consumer must not start before the injector has configured the
    # capture nodes and started the output (TCG on a busy host is slow)
    d=$(hw_deadline 30)
    while [ ! -e /tmp/inject.ready ] && hw_before "$d"; do
        kill -0 $HW_INJECT_PID 2>/dev/null || { echo "injector died"; return 1; }
        sleep 0.1
    done
    [ -e /tmp/inject.ready ] || { echo "injector not ready after 30 s"; hw_inject_stop; return 1; }
}
hw_inject_stop() {
    if [ -n "${HW_INJECT_PID:-}" ]; then
        kill "$HW_INJECT_PID" 2>/dev/null || true
        wait "$HW_INJECT_PID" 2>/dev/null || true   # 143: ended by SIGTERM
    fi
    HW_INJECT_PID=""
    return 0
}

# hw_gpio_sim_setup [NAME] [LINES]: a gpio-sim chip labelled NAME (default
# negobs-sim) with LINES lines (default 8), line 0 named "motor".  Sets
#   HW_GPIOCHIP=/dev/gpiochipN   (what negobs_run --alert gpio:... is given)
#   HW_GPIO_SIM=<sysfs dir>      (outside observer: $HW_GPIO_SIM/sim_gpio0/value)
hw_gpio_sim_setup() {
    name=${1:-negobs-sim}
    modprobe gpio-sim || { echo "gpio-sim.ko not available"; return 1; }
    grep -q configfs /proc/mounts || mount -t configfs none /sys/kernel/config || return 1
    G=/sys/kernel/config/gpio-sim/$name
    mkdir "$G" "$G/bank0" || return 1
    echo "${2:-8}" > "$G/bank0/num_lines"
    echo "$name" > "$G/bank0/label"
    mkdir "$G/bank0/line0"
    echo motor > "$G/bank0/line0/name"
    echo 1 > "$G/live" || return 1
    chip=$(cat "$G/bank0/chip_name")
    HW_GPIOCHIP=/dev/$chip
    HW_GPIO_SIM=/sys/devices/platform/$(cat "$G/dev_name")/$chip
    export HW_GPIOCHIP HW_GPIO_SIM
    echo "gpio-sim: $HW_GPIOCHIP label $name, observer $HW_GPIO_SIM/sim_gpioN/value"
}

# hw_pwm_sim_load [NPWM]: pwm-sim.ko with NPWM channels (default 2).  Sets
#   HW_PWMCHIP=N   (index: /sys/class/pwm/pwmchipN)
hw_pwm_sim_load() {
    modprobe pwm-sim npwm="${1:-2}" || { echo "pwm-sim.ko not available"; return 1; }
    HW_PWMCHIP=""
    for c in /sys/class/pwm/pwmchip*; do
        case "$(readlink "$c/device")" in
            */pwm-sim) HW_PWMCHIP=${c#/sys/class/pwm/pwmchip} ;;
        esac
    done
    [ -n "$HW_PWMCHIP" ] || { echo "no pwmchip for pwm-sim"; return 1; }
    export HW_PWMCHIP
    echo "pwm-sim: /sys/class/pwm/pwmchip$HW_PWMCHIP ($(cat /sys/class/pwm/pwmchip$HW_PWMCHIP/npwm) channels)"
}
