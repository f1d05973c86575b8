#!/bin/sh
# A log reader that stops reading never stops the warnings: negobs_run's
# stderr and its --log-json FIFO, each held open by a reader that never
# reads (its pipe shrunk to one page), while 200 replayed pairs are judged
# as fast as they come. Every pair must be judged, the run must end by
# itself with exit 0, and the lost lines must be counted. Before
# firmware_app/app_logout.c the JSON case stopped after 6 pairs until it
# was killed. The same for systemd's notify socket (case 3). Frames from negobs_synth (skipped, exit 77, when tools/ is
# not built). Usage: test_negobs_run_stall.sh NEGOBS_RUN NEGOBS_SYNTH PNG2RAW
set -u
RUN=$1
SYNTH=$2
PNG2RAW=$3
if [ ! -x "$SYNTH" ]; then
    echo "SKIP: $SYNTH not built (tools/ needs OpenCV)"; exit 77
fi
T=$(mktemp -d "${TMPDIR:-/tmp}/negobs-stall-XXXXXX")
READER=""
trap '[ -n "$READER" ] && kill $READER 2>/dev/null; rm -rf "$T"' EXIT
. "$(dirname "$0")/run_expect.sh"
flat_pairs 10 1200
# The reader: opens the FIFO, shrinks its pipe to one page (Linux;
# elsewhere the default 64 KiB fills later), never reads.
cat >"$T/reader.py" <<'PY'
import os, sys, fcntl, time
fd = os.open(sys.argv[1], os.O_RDONLY | os.O_NONBLOCK)
try:
    fcntl.fcntl(fd, 1031, 4096)  # F_SETPIPE_SZ
except OSError:
    pass
open(sys.argv[1] + ".ready", "w").close()
time.sleep(120)
PY
wait_ready() { # FILE: up to 10 s for the reader's FILE.ready
    i=0
    while [ ! -f "$1.ready" ] && [ $i -lt 100 ]; do sleep 0.1; i=$((i + 1)); done
    [ -f "$1.ready" ]
}
stall_reader() { # FIFO: a reader that never reads, running when this returns
    rm -f "$1" "$1.ready"
    mkfifo "$1" || return 1
    python3 "$T/reader.py" "$1" &
    READER=$!
    wait_ready "$1"
}
ARGS="--fps 0 --frames 200 --set replay_loop=true --set alert=none
      --set focal_px=175 --set baseline_mm=120 --set max_disp=23"

# 1. --log-json into a FIFO nobody reads; stderr to a file
stall_reader "$T/json.fifo" || { echo "FAIL: reader"; exit 1; }
# shellcheck disable=SC2086
timeout 120 "$RUN" $ARGS --log-json "$T/json.fifo" replay:"$T/raw/pgm" >"$T/err" 2>&1
rc=$?
kill $READER 2>/dev/null; READER=""
if [ $rc -eq 0 ]; then ok "stalled JSON reader: the run ends by itself, exit 0"; else
    echo "     | exit $rc (124: still waiting when killed)" >>"$T/err"; bad "stalled JSON reader: the run ends by itself, exit 0"; fi
if grep -q "summary pairs=200 .*json_dropped=[1-9]" "$T/err"; then ok "stalled JSON reader: 200 pairs judged, lost lines counted"; else
    bad "stalled JSON reader: 200 pairs judged, lost lines counted"; fi
if grep -q "log-json: .* line(s) dropped: the reader was not taking them" "$T/err"; then ok "stalled JSON reader: the loss is said"; else
    bad "stalled JSON reader: the loss is said"; fi

# 2. stderr into a FIFO nobody reads (debug: many lines); the JSON log to
#    a file shows what was judged
stall_reader "$T/err.fifo" || { echo "FAIL: reader"; exit 1; }
# shellcheck disable=SC2086
timeout 120 "$RUN" $ARGS --log-level debug --log-json "$T/pairs.jsonl" \
    replay:"$T/raw/pgm" 2>"$T/err.fifo" >"$T/out"
rc=$?
kill $READER 2>/dev/null; READER=""
echo "exit $rc, $(wc -l <"$T/pairs.jsonl" 2>/dev/null) JSON lines" >"$T/err"
if [ $rc -eq 0 ]; then ok "stalled stderr reader: the run ends by itself, exit 0"; else
    bad "stalled stderr reader: the run ends by itself, exit 0"; fi
if [ "$(wc -l <"$T/pairs.jsonl" 2>/dev/null)" = 200 ]; then ok "stalled stderr reader: 200 pairs judged and logged"; else
    bad "stalled stderr reader: 200 pairs judged and logged"; fi

# 3. systemd's notify socket not read (a busy or stopped PID 1): the
#    reader takes the first datagram (READY=1), then reads nothing more.
#    WATCHDOG_USEC=4000 asks for a keep-alive every millisecond, so a
#    queue of net.unix.max_dgram_qlen datagrams (10 on some machines, 512
#    by default) fills within the run. sd_notify() waited there for good.
#    Only in builds with libsystemd (the notifications exist only there).
cat >"$T/notify.py" <<'PY'
import socket, sys, time
addr = sys.argv[1]
s = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
s.bind("\0" + addr[1:] if addr.startswith("@") else addr)
open(sys.argv[2] + ".ready", "w").close()
s.settimeout(60)
try:
    msg = s.recv(4096)
    open(sys.argv[2], "wb").write(msg)
except socket.timeout:
    pass
time.sleep(120)
PY
notify_reader() { # ADDR OUT: the reader bound, running when this returns
    rm -f "$2" "$2.ready"
    python3 "$T/notify.py" "$1" "$2" &
    READER=$!
    wait_ready "$2"
}
# (the string is in the program only when it sends notifications)
if grep -aq NOTIFY_SOCKET "$RUN"; then
    QLEN=$(cat /proc/sys/net/unix/max_dgram_qlen 2>/dev/null || echo 512)
    notify_reader "$T/notify.sock" "$T/first" || { echo "FAIL: notify reader"; exit 1; }
    # shellcheck disable=SC2086
    NOTIFY_SOCKET="$T/notify.sock" WATCHDOG_USEC=4000 timeout 120 "$RUN" \
        --fps 0 --frames 600 --set replay_loop=true --set alert=none \
        --set focal_px=175 --set baseline_mm=120 --set max_disp=23 \
        replay:"$T/raw/pgm" >"$T/err" 2>&1
    rc=$?
    kill $READER 2>/dev/null; READER=""
    echo "     | exit $rc; first datagram: $(cat "$T/first" 2>/dev/null | tr '\n' ' '); max_dgram_qlen $QLEN" >>"$T/err"
    if [ $rc -eq 0 ] && grep -q "summary pairs=600 " "$T/err"; then
        ok "notify socket not read: 600 pairs judged, exit 0"; else
        bad "notify socket not read: 600 pairs judged, exit 0"; fi
    if grep -q "READY=1" "$T/first" 2>/dev/null; then ok "notify socket: READY=1 arrives"; else
        bad "notify socket: READY=1 arrives"; fi
    if [ "$QLEN" -le 500 ]; then
        if grep -q "notify_dropped=[1-9]" "$T/err"; then ok "notify socket full: dropped keep-alives counted"; else
            bad "notify socket full: dropped keep-alives counted"; fi
    fi
    # the abstract namespace ("@name"), as a container's supervisor may give
    notify_reader "@negobs-stall-$$" "$T/first2" || { echo "FAIL: notify reader"; exit 1; }
    # shellcheck disable=SC2086
    NOTIFY_SOCKET="@negobs-stall-$$" timeout 60 "$RUN" --fps 0 --frames 3 \
        --set alert=none --set focal_px=175 --set baseline_mm=120 \
        --set max_disp=23 replay:"$T/raw/pgm" >"$T/err" 2>&1
    kill $READER 2>/dev/null; READER=""
    if grep -q "READY=1" "$T/first2" 2>/dev/null; then ok "abstract notify socket: READY=1 arrives"; else
        bad "abstract notify socket: READY=1 arrives"; fi
else
    echo "SKIP (part): negobs_run built without libsystemd: no notifications"
fi

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
