# Helpers for the sections that run the real negobs_run (run-curb,
# run-camera-loss).  Source after /tests/lib.sh.  The host side
# (tests/hw/build_negobs.sh) put into /negobs: negobs_run (static aarch64),
# rig.conf, curb/{left,right}.raw, flat/{left,right}.raw (640x480 GREY).

NEGOBS=/negobs

# negobs_prereq: exit 77 (skip) with a reason when the image has no firmware
negobs_prereq() {
    [ -x $NEGOBS/negobs_run ] || { echo "no /negobs/negobs_run in the image (host build failed or skipped)"; exit 77; }
}

# negobs_vivid_load: vivid in loopback like hw_vivid_load, but with the
# error-injection controls ("Percentage of Dropped Buffers" stops a camera's
# frames) and capture crop/compose/scaler on (ccs 7: what no_error_inj=1
# gives by default).  Reloads vivid if an earlier section loaded it.
negobs_vivid_load() {
    if grep -q '^vivid ' /proc/modules; then
        rmmod vivid || { echo "cannot unload vivid"; return 1; }
    fi
    modprobe vivid n_devs=2 node_types=0x101,0x101 vid_cap_nr=0,1 vid_out_nr=2,3 \
        no_error_inj=0 ccs_cap_mode=7,7 ccs_out_mode=7,7 || return 1
    for i in 0 1 2 3; do
        d=$(hw_deadline 5)
        while [ ! -e /dev/video$i ] && hw_before "$d"; do sleep 0.1; done
        [ -e /dev/video$i ] || { echo "vivid: /dev/video$i did not appear"; return 1; }
    done
    echo "vivid: loopback, error-injection controls on, capture scaler on"
}

now() { motor_watch now; }

# negobs_watch_start FILE: outside observer of the motor (edges, 5 ms)
negobs_watch_start() {
    motor_watch -i 5 "$1" > /tmp/edges &
    WATCH_PID=$!
}
negobs_watch_stop() {
    kill "$WATCH_PID" 2>/dev/null; wait "$WATCH_PID" 2>/dev/null
    tail -n 1 /tmp/edges | sed 's/^# /motor_watch: /'
}

# negobs_start CONF ALERT: negobs_run in the background, log /tmp/negobs.log;
# sets NEGOBS_PID and T_START (boot clock, just before exec)
negobs_start() {
    T_START=$(now)
    $NEGOBS/negobs_run --config "$1" --alert "$2" /dev/video0 /dev/video1 2> /tmp/negobs.log &
    NEGOBS_PID=$!
    echo "negobs_run started at boot clock $T_START: --config $1 --alert $2"
}
# negobs_stop: SIGINT; returns 0 when it ended cleanly (exit 0). A
# negobs_run that has not exited STOP_LIMIT_S after SIGINT is a failure of
# its own (a hang on shutdown): it is killed, so the section fails with its
# log instead of the whole guest hanging until qemu's timeout.
negobs_stop() {
    local d
    kill -INT "$NEGOBS_PID" 2>/dev/null
    d=$(hw_deadline "${STOP_LIMIT_S:-20}")
    while kill -0 "$NEGOBS_PID" 2>/dev/null && hw_before "$d"; do
        sleep 0.1
    done
    if kill -0 "$NEGOBS_PID" 2>/dev/null; then
        echo "negobs_run: FAIL: still running ${STOP_LIMIT_S:-20} s after SIGINT; killed"
        kill -KILL "$NEGOBS_PID" 2>/dev/null
    fi
    wait "$NEGOBS_PID"
    NEGOBS_RC=$?
    sed 's/^/negobs_run| /' /tmp/negobs.log
    echo "negobs_run exit status $NEGOBS_RC"
    [ "$NEGOBS_RC" -eq 0 ]
}

# log_time PATTERN [AFTER]: negobs_run's own time (s since its start) of the
# first log line matching PATTERN (ERE) at or after AFTER seconds; empty if none
log_time() {
    # lines look like "[   12.345] info: ..." (the time is right-aligned)
    awk -v pat="$1" -v after="${2:-0}" '
        match($0, /^\[ *[0-9]+\.[0-9]+\]/) {
            t = substr($0, 2, RLENGTH - 2) + 0
            if ($0 ~ pat && t >= after + 0) { print t; exit }
        }' /tmp/negobs.log
}

# pulses: the on-pulses seen on the motor line, "START_BOOT WIDTH_MS" per
# line (a pulse still on at the end has width -1)
pulses() {
    awk '$1 !~ /^#/ {
            if ($2 == 1) { on = $1 }
            else if (on != "") { printf "%.3f %.0f\n", on, ($1 - on) * 1000; on = "" }
         }
         END { if (on != "") printf "%.3f -1\n", on }' /tmp/edges
}

# patterns T0 T1: classifies the pulses starting in [T0, T1) (boot clock) by
# the library's alert patterns (lib/src/alert/alert.c), one "CLASS START" line
# per recognised pair of pulses (TOL_MS of slack on every width and gap for
# the emulator's scheduling):
#   caution  two ~80 ms pulses 160 ms apart (start to start)
#   imminent three ~300 ms pulses 400 ms apart (the pattern is continuous
#            and held >= imminent_hold_ms = 1 s, so a real one always has
#            three; two ~300-355 ms fragments 460 ms apart are what a no-info
#            burst restarted mid-pulse left on a loaded TCG guest, and read
#            as "imminent" they failed run-fault-pwm once)
#   noinfo   a ~400 ms pulse followed 600 ms later by another (entry burst)
#            or a ~600 ms pulse (the repeating part)
patterns() {
    pulses | awk -v t0="$1" -v t1="$2" -v tol="${TOL_MS:-60}" '
        function near(x, want) { return x >= want - tol && x <= want + tol }
        $1 >= t0 && $1 < t1 { n++; s[n] = $1; w[n] = $2 }
        END {
            for (i = 1; i <= n; i++) {
                g = (i < n) ? (s[i + 1] - s[i]) * 1000 : -1
                g2 = (i + 1 < n) ? (s[i + 2] - s[i + 1]) * 1000 : -1
                if (i < n && near(w[i], 80) && near(w[i + 1], 80) && near(g, 160))
                    print "caution", s[i]
                else if (i + 1 < n && near(w[i], 300) && near(w[i + 1], 300) &&
                         near(w[i + 2], 300) && near(g, 400) && near(g2, 400))
                    print "imminent", s[i]
                else if ((i < n && near(w[i], 400) && near(g, 600)) || near(w[i], 600))
                    print "noinfo", s[i]
            }
        }'
}
