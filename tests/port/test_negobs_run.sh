#!/bin/sh
# negobs_run as a black box: argument errors, exit codes, replay runs,
# recording, the sysfs PWM output, the no-fresh-pair path and SIGTERM.
# Usage: test_negobs_run.sh PATH/TO/negobs_run
set -u
RUN=$1
T=$(mktemp -d "${TMPDIR:-/tmp}/negobs-run-XXXXXX")
trap 'rm -rf "$T"' EXIT
. "$(dirname "$0")/run_expect.sh"

# PGM pairs: 64x48, noisy texture (from a fixed byte pattern), and a dark set.
mkpair() { # DIR INDEX FILLER-COMMAND
    for side in left right; do
        { printf 'P5\n64 48\n255\n'; eval "$3"; } >"$1/${side}_$(printf %04d "$2").pgm"
    done
}
mkdir "$T/rp" "$T/dark" "$T/bad"
i=0
while [ $i -lt 4 ]; do
    mkpair "$T/rp" $i "awk 'BEGIN{s=$i+7; for(k=0;k<3072;k++){s=(s*1103515245+12345)%2147483648; printf \"%c\", 40+int(s/65536)%160}}'"
    mkpair "$T/dark" $i "head -c 3072 /dev/zero"
    i=$((i + 1))
done
mkpair "$T/bad" 0 "head -c 100 /dev/zero"   # truncated raster

expect "help names the geometry keys" 0 "cam_height_mm" --help
expect "help lists config keys" 0 "watchdog_ms" --help
expect "version" 0 "negobs_run 0" --version
expect "no camera arguments is a usage error" 2 "missing camera" --alert none
expect "unknown option" 2 "unknown option '--bogus'" --bogus replay:"$T/rp"
expect "option without value" 2 "needs a value" replay:"$T/rp" --fps
expect "non-numeric width" 2 "not an integer" --width abc replay:"$T/rp"
expect "width out of range" 2 "outside" --width 5 replay:"$T/rp"
expect "bad alert spec" 2 "bad alert" --alert pwm:x:1 replay:"$T/rp"
expect "bad log level" 2 "bad log level" --log-level loud replay:"$T/rp"
# One V4L2 node alone is a side-by-side camera (both eyes in each frame).
expect "one V4L2 node is side by side" 4 "open /nonexistent/v0" --alert none v4l2:/nonexistent/v0
printf 'capture_width = 1280\ncapture_height = 360\nwidth = 640\nheight = 480\n' >"$T/cap.conf"
expect "capture size smaller than the processing size" 2 "cannot give 640x480" --config "$T/cap.conf" --alert none v4l2:/nonexistent/v0
printf 'capture_width = 2560\n' >"$T/cap1.conf"
expect "capture width without height" 2 "set both capture_width and capture_height" --config "$T/cap1.conf" --alert none v4l2:/nonexistent/v0
printf 'capture_width = 2560\ncapture_height = 720\nwidth = 640\nheight = 360\n' >"$T/cap2.conf"
expect "binned side-by-side capture opens the node" 4 "open /nonexistent/v0" --config "$T/cap2.conf" --alert none v4l2:/nonexistent/v0
printf 'pixel_format = Y16BE\n' >"$T/pf.conf"
expect "pixel_format longer than a fourcc" 2 "pixel_format 'Y16BE' is not a fourcc" --config "$T/pf.conf" --alert none v4l2:/nonexistent/v0
printf 'pixel_format = Y16\n' >"$T/pf2.conf"
expect "pixel_format Y16 opens the node" 4 "open /nonexistent/v0" --config "$T/pf2.conf" --alert none v4l2:/nonexistent/v0
# Discovery: a missing node, a file that is not a V4L2 device.
expect "list a missing node" 4 "/nonexistent/v9: cannot open" --list-cameras /nonexistent/v9
expect "list a non-video file" 4 "not a V4L2 device" --list-cameras "$T/cap.conf"
expect "list says when nothing is usable" 4 "no usable camera found" --list-cameras "$T/cap.conf"
expect "mixed sources rejected" 2 "V4L2 device too" /dev/video0 replay:"$T/rp"
expect "extra argument" 2 "unexpected argument" /dev/video0 /dev/video1 x
expect "missing config file" 3 "nope.conf" --config "$T/nope.conf" replay:"$T/rp"
printf 'fps = 0\nwatchdgo_ms = 300\n' >"$T/typo.conf"
expect "config typo names its line" 3 "line 2: unknown key 'watchdgo_ms'" --config "$T/typo.conf" replay:"$T/rp"
expect "missing replay folder" 4 "no left_0000.pgm" --alert none replay:"$T/none"
expect "missing V4L2 device" 4 "open /nonexistent" --alert none v4l2:/nonexistent/v0 v4l2:/nonexistent/v1
expect "replay runs to the end" 0 "end of replay after 4 pairs" --fps 0 --alert none replay:"$T/rp"
printf 'vertical_align = true\n' >"$T/va.conf"
expect "vertical alignment stage runs" 0 "vertical alignment stage on" --config "$T/va.conf" --fps 0 --alert none replay:"$T/rp"
expect "vertical alignment replay ends" 0 "end of replay after 4 pairs" --config "$T/va.conf" --fps 0 --alert none replay:"$T/rp"
printf 'vertical_align = maybe\n' >"$T/vabad.conf"
expect "vertical_align wants a boolean" 3 "vertical_align" --config "$T/vabad.conf" replay:"$T/rp"
expect "threads out of range" 2 "outside" --threads 65 replay:"$T/rp"
expect "threads named in the log" 0 "matcher threads: 3" --threads 3 --fps 0 --alert none replay:"$T/rp"
expect "threads runs to the end" 0 "end of replay after 4 pairs" --threads 2 --fps 0 --alert none replay:"$T/rp"
printf 'threads = 2\n' >"$T/thr.conf"
expect "threads config key" 0 "matcher threads: 2" --config "$T/thr.conf" --fps 0 --alert none replay:"$T/rp"
expect "frames N stops early" 0 "2 pairs processed" --fps 0 --frames 2 --alert none replay:"$T/rp" replay:"$T/rp"
# Unrelated random images pass the quality gate, but no ground is seen:
# the detector, not the gate, must answer no-info (never "clear").
expect "unmatchable images reach the detector" 0 "clear=0 caution=0 imminent=0 last_reason=detector" --fps 0 --alert none --log-level debug replay:"$T/rp"
expect "dark images give no-info" 0 "no-info=4 clear=0 caution=0 imminent=0 last_reason=dark" --fps 0 --alert none --log-level debug replay:"$T/dark"
expect "truncated replay file is a runtime error" 1 "truncated" --fps 0 --alert none replay:"$T/bad"
expect "record a session" 0 "recording to" --fps 0 --alert none --record "$T/rec" replay:"$T/rp"
expect "replay the recorded session" 0 "end of replay after 4 pairs" --fps 0 --alert none replay:"$T/rec"
if cmp -s "$T/rec/left.y" /dev/null || [ "$(wc -c <"$T/rec/left.y")" -ne 12288 ]; then
    echo "     | left.y has $(wc -c <"$T/rec/left.y") bytes, want 12288" >"$T/err"; bad "session size"
else
    ok "session holds 4 raw 64x48 frames"
fi
# Starved pipeline (2 fps, 300 ms watchdog): no-info pattern plays.
expect "no fresh pair -> no-info pattern" 0 "timed out" --fps 2 --frames 2 --alert console replay:"$T/rp"
if grep -q "ON  1000" "$T/out"; then ok "motor pulses while starved"; else bad "motor pulses while starved"; fi

# Sysfs PWM output into a fake tree; the motor must end off and disabled.
mkdir -p "$T/pwm/pwmchip0/pwm1"
: >"$T/pwm/pwmchip0/export"; : >"$T/pwm/pwmchip0/unexport"
for f in period duty_cycle enable; do echo 0 >"$T/pwm/pwmchip0/pwm1/$f"; done
printf 'pwm_sysfs_root = %s\npwm_period_ns = 50000\nfps = 0\n' "$T/pwm" >"$T/pwm.conf"
expect "pwm output runs" 0 "motor output: pwm:0:1" --config "$T/pwm.conf" --alert pwm:0:1 replay:"$T/dark"
if [ "$(cat "$T/pwm/pwmchip0/pwm1/period")" = 50000 ] &&
   [ "$(cat "$T/pwm/pwmchip0/pwm1/duty_cycle")" = 0 ] &&
   [ "$(cat "$T/pwm/pwmchip0/pwm1/enable")" = 0 ]; then
    ok "pwm left off and disabled"
else
    bad "pwm left off and disabled"
fi
expect "missing pwm chip" 5 "no PWM chip" --config "$T/pwm.conf" --alert pwm:3:0 replay:"$T/rp"

# A crash while the motor runs: the fault handler must switch it off
# (sysfs PWM keeps its last duty after the process dies otherwise).
printf 'replay_loop = true\nfps = 30\n' >>"$T/pwm.conf"
"$RUN" --config "$T/pwm.conf" --alert pwm:0:1 replay:"$T/dark" >"$T/out" 2>"$T/err" &
pid=$!
n=0
while [ "$(cat "$T/pwm/pwmchip0/pwm1/duty_cycle")" != 50000 ] && [ $n -lt 100 ]; do
    sleep 0.02; n=$((n + 1))
done
was=$(cat "$T/pwm/pwmchip0/pwm1/duty_cycle")
kill -SEGV $pid
wait $pid
rc=$?
now=$(cat "$T/pwm/pwmchip0/pwm1/duty_cycle")
if [ "$was" = 50000 ] && [ "$now" = 0 ] && [ $rc -eq 139 ]; then
    ok "motor off after a crash (SIGSEGV)"
else
    echo "     | duty before $was, after $now, exit $rc" >>"$T/err"; bad "motor off after a crash (SIGSEGV)"
fi

# SIGTERM: clean shutdown with exit 0.
"$RUN" --fps 30 --alert none --config /dev/null replay:"$T/rp" >"$T/out" 2>"$T/err" &
pid=$!
printf 'replay_loop = true\n' >"$T/loop.conf"
kill $pid 2>/dev/null; wait $pid 2>/dev/null
"$RUN" --fps 30 --alert none --config "$T/loop.conf" replay:"$T/rp" >"$T/out" 2>"$T/err" &
pid=$!
sleep 1
kill -TERM $pid
wait $pid
rc=$?
if [ $rc -eq 0 ] && grep -q "stop requested" "$T/err"; then ok "SIGTERM stops cleanly"; else echo "     | exit $rc" >>"$T/err"; bad "SIGTERM stops cleanly"; fi

echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
