#!/bin/sh
# negobs_run fail-safe runtime (issue 23): recording failures never stop
# the warnings, sessions are never recorded over, damaged sessions say what
# they recovered, every terminating signal leaves the motor off with a
# summary, --motor-off, and config values refused with file and line.
# Usage: test_negobs_run_failsafe.sh PATH/TO/negobs_run
set -u
RUN=$1
T=$(mktemp -d "${TMPDIR:-/tmp}/negobs-failsafe-XXXXXX")
trap 'rm -rf "$T"' EXIT
. "$(dirname "$0")/run_expect.sh"
has() { # NAME NEEDLE: NEEDLE in the last run's output
    if grep -q -- "$2" "$T/err"; then ok "$1"; else echo "     | missing: $2" >>"$T/err"; bad "$1"; fi
}
hasnt() {
    if grep -q -- "$2" "$T/err"; then echo "     | unwanted: $2" >>"$T/err"; bad "$1"; else ok "$1"; fi
}

# 4 PGM pairs, 64x48, random texture; dark ones (no-info: the motor pulses).
mkdir "$T/rp" "$T/dark"
i=0
while [ $i -lt 4 ]; do
    for side in left right; do
        { printf 'P5\n64 48\n255\n'; awk "BEGIN{s=$i+7; for(k=0;k<3072;k++){s=(s*1103515245+12345)%2147483648; printf \"%c\", 40+int(s/65536)%160}}"; } >"$T/rp/${side}_000$i.pgm"
        { printf 'P5\n64 48\n255\n'; head -c 3072 /dev/zero; } >"$T/dark/${side}_000$i.pgm"
    done
    i=$((i + 1))
done
printf 'replay_loop = true\nfps = 0\n' >"$T/loop.conf"

# ---- 1. a recorder failure stops the recording, not the device --------
# The file size limit (as a small or full card): the write of pair ~13
# fails (EFBIG; the kernel's SIGXFSZ must not kill the process).
( ulimit -f 40 && exec "$RUN" --config "$T/loop.conf" --frames 60 --alert none \
      --record "$T/full" replay:"$T/rp" ) >"$T/out" 2>"$T/err"
rc=$?
cat "$T/out" >>"$T/err"
if [ $rc -eq 0 ]; then ok "full card: exit 0"; else echo "     | exit $rc" >>"$T/err"; bad "full card: exit 0"; fi
has "full card: all 60 pairs processed" "60 pairs processed"
has "full card: logged once" "record: stopped: write failed"
if [ "$(grep -c 'error: record: stopped' "$T/err")" -eq 1 ]; then ok "full card: logged only once"; else bad "full card: logged only once"; fi
has "full card: in the summary" "summary pairs=60 .*record=failed written="
# Unwritable folder (a path under a regular file): recording off, 60 pairs.
: >"$T/afile"
expect "unwritable folder: detection goes on" 0 "60 pairs processed" \
    --config "$T/loop.conf" --frames 60 --alert none --record "$T/afile/sub" replay:"$T/rp"
has "unwritable folder: said why" "record: stopped: mkdir $T/afile/sub"
has "unwritable folder: in the summary" "record=failed"

# ---- 3. never record over a session ----------------------------------
# The summary may come while the writer still drains its queue; the line
# after it counts the pairs on the card.
expect "record a session" 0 "record: closed, record=.* written=4" --fps 0 --alert none --record "$T/rec" replay:"$T/rp"
sum_before=$(cat "$T/rec/session.txt" "$T/rec/frames.txt" "$T/rec/left.y" "$T/rec/right.y" | cksum)
expect "record over the session being replayed: refused, replay runs" 0 \
    "end of replay after 4 pairs" --fps 0 --alert none --record "$T/rec" replay:"$T/rec"
has "refusal says why" "already holds a session"
has "refusal in the summary" "record=refused"
expect "record over an earlier session: refused" 0 "refusing to record over it" \
    --fps 0 --alert none --record "$T/rec" replay:"$T/rp"
sum_after=$(cat "$T/rec/session.txt" "$T/rec/frames.txt" "$T/rec/left.y" "$T/rec/right.y" | cksum)
if [ "$sum_before" = "$sum_after" ]; then ok "the session is untouched"; else bad "the session is untouched"; fi

# ---- 2. damaged sessions -----------------------------------------------
cp -r "$T/rec" "$T/noidx"
: >"$T/noidx/frames.txt"
expect "empty frames.txt: all pairs recovered, exit 1" 1 "summary pairs=4 " \
    --fps 0 --alert none replay:"$T/noidx"
has "empty frames.txt: says what it recovered" "4 with synthesised timestamps"
hasnt "empty frames.txt: never a clean end" "end of replay"
cp -r "$T/rec" "$T/cut"
head -c 5000 "$T/rec/right.y" >"$T/cut/right.y"
expect "truncated right.y: complete pairs replayed, exit 1" 1 "summary pairs=1 " \
    --fps 0 --alert none replay:"$T/cut"
has "truncated right.y: says so" "right.y 1 complete frames"
head -c 100 "$T/rec/left.y" >"$T/cut/left.y"
expect "no complete pair: fails at open" 4 "no complete pair" --fps 0 --alert none replay:"$T/cut"
rm "$T/cut/left.y"
expect "missing left.y: named" 4 "left.y: No such file or directory (not found)" \
    --fps 0 --alert none replay:"$T/cut"
hasnt "missing left.y: no checksum talk" "memory guard"

# ---- 4. signals and --motor-off ----------------------------------------
mkdir -p "$T/pwm/pwmchip0/pwm1"
: >"$T/pwm/pwmchip0/export"; : >"$T/pwm/pwmchip0/unexport"
for f in period duty_cycle enable; do echo 0 >"$T/pwm/pwmchip0/pwm1/$f"; done
printf 'pwm_sysfs_root = %s\npwm_period_ns = 50000\nreplay_loop = true\nfps = 30\n' "$T/pwm" >"$T/pwm.conf"
duty() { cat "$T/pwm/pwmchip0/pwm1/duty_cycle"; }
# signal SIG WANT_RC: negobs_run plays no-info on the fake PWM, gets SIG
# while the motor is on; it must end with the motor off and a summary.
signal() {
    "$RUN" --config "$T/pwm.conf" --alert pwm:0:1 replay:"$T/dark" >"$T/out" 2>"$T/err" &
    pid=$!
    n=0
    while [ "$(duty)" != 50000 ] && [ $n -lt 200 ]; do sleep 0.01; n=$((n + 1)); done
    was=$(duty)
    kill -s "$1" $pid 2>/dev/null || kill -TERM $pid
    n=0  # a signal it ignores must fail the check, not hang the test
    while kill -0 $pid 2>/dev/null && [ $n -lt 500 ]; do sleep 0.01; n=$((n + 1)); done
    kill -0 $pid 2>/dev/null && { kill -KILL $pid; echo "     | still running after SIG$1" >>"$T/err"; }
    wait $pid
    rc=$?
    if [ "$was" = 50000 ] && [ "$(duty)" = 0 ] && [ $rc -eq "$2" ] &&
       grep -q "summary pairs=" "$T/err"; then
        ok "$1: motor off, summary, exit $2"
    else
        echo "     | duty before $was, after $(duty), exit $rc (want $2)" >>"$T/err"; bad "$1: motor off, summary, exit $2"
    fi
}
# Linux signal numbers (x86-64, aarch64, armhf share them); exit 128 + N
# for an unexpected signal, 0 for a request to stop.
signal HUP 0
signal QUIT 0
signal USR1 138
signal USR2 140
signal ALRM 142
signal XCPU 152
signal XFSZ 153    # sent by another process: stops (its own write's: ignored)
signal PIPE 141
signal VTALRM 154
signal PROF 155
signal IO 157
signal PWR 158
signal 16 144     # SIGSTKFLT (not every shell knows its name)
signal 37 165      # SIGRTMIN + 3 under glibc

# --motor-off: a channel left on (as after SIGKILL) is switched off.
echo 50000 >"$T/pwm/pwmchip0/pwm1/duty_cycle"; echo 1 >"$T/pwm/pwmchip0/pwm1/enable"
expect "--motor-off pwm" 0 "motor off: pwm:0:1" --config "$T/pwm.conf" --motor-off pwm:0:1
if [ "$(duty)" = 0 ] && [ "$(cat "$T/pwm/pwmchip0/pwm1/enable")" = 0 ]; then
    ok "--motor-off left the PWM at duty 0, disabled"
else
    bad "--motor-off left the PWM at duty 0, disabled"
fi
expect "--motor-off needs a good spec" 2 "bad motor output" --motor-off pwm:x
expect "--motor-off takes no camera" 2 "no camera argument" --motor-off none replay:"$T/rp"
expect "--motor-off on a missing chip" 5 "no PWM chip" --config "$T/pwm.conf" --motor-off pwm:3:0
expect "--motor-off console" 0 "motor off: console" --motor-off console

# ---- 5. config values and the alert spec --------------------------------
printf 'fps = 0\nalert = buzzer\n' >"$T/alert.conf"
expect "bad alert in a config file: exit 3 with file and line" 3 \
    "alert.conf: line 2: alert: bad alert 'buzzer'" --config "$T/alert.conf" replay:"$T/rp"
printf 'log_level = loud\n' >"$T/level.conf"
expect "bad log_level in a config file: exit 3 with file and line" 3 \
    "level.conf: line 1: log_level: bad log level 'loud'" --config "$T/level.conf" replay:"$T/rp"
printf 'fps = 0\nwatch\000dog_ms = 300\n' >"$T/nul.conf"
expect "NUL byte in a config line: said as such" 3 "line 2: NUL byte" --config "$T/nul.conf" replay:"$T/rp"
hasnt "NUL byte: not called over-long" "longer than"
printf 'heartbeat_period_ms = 500\n' >"$T/hb.conf"
expect "heartbeat period below 1 s refused" 3 "heartbeat_period_ms 0 or 1000..60000" --config "$T/hb.conf" replay:"$T/rp"
# An alert kind of 16+ characters: refused without reading unfilled
# memory (valgrind reports it when it is installed).
LONG=abcdefghijklmnopqrstuvwxyz:0:0
expect "long alert kind refused" 2 "bad alert" --alert $LONG replay:"$T/rp"
# valgrind cannot run a sanitizer build (ASan maps its shadow memory
# first), and ASan does not see uninitialised reads: the plain host build's
# run of this script is the one that checks them.
if nm "$RUN" 2>/dev/null | grep -q __asan_init; then
    echo "skip - sanitizer build: valgrind check left to the plain build"
elif command -v valgrind >/dev/null 2>&1; then
    valgrind -q --error-exitcode=99 "$RUN" --alert $LONG replay:"$T/rp" >"$T/out" 2>"$T/err"
    rc=$?
    if [ $rc -eq 2 ]; then ok "long alert kind: no uninitialised read (valgrind)"; else echo "     | exit $rc" >>"$T/err"; bad "long alert kind: no uninitialised read (valgrind)"; fi
else
    echo "skip - valgrind not installed"
fi

echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
