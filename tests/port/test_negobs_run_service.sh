#!/bin/sh
# negobs_run as a service (issue 24): --set for every config key, the
# default-geometry warnings, journald priorities, sd_notify (READY,
# WATCHDOG, STOPPING), --motor-off config, cameras from the config, the
# --log-json lines (fields, and failures that never stop the warnings) and
# the recorded session's meta.txt.
# Usage: test_negobs_run_service.sh PATH/TO/negobs_run SYSTEMD(0|1)
set -u
RUN=$1
SYSTEMD=${2:-0}
T=$(mktemp -d "${TMPDIR:-/tmp}/negobs-service-XXXXXX")
trap 'kill "$LISTENER" 2>/dev/null; rm -rf "$T"' EXIT
LISTENER=
. "$(dirname "$0")/run_expect.sh"
has() { # NAME NEEDLE: NEEDLE in the last run's output
    if grep -q -- "$2" "$T/err"; then ok "$1"; else echo "     | missing: $2" >>"$T/err"; bad "$1"; fi
}
hasnt() {
    if grep -q -- "$2" "$T/err"; then echo "     | unwanted: $2" >>"$T/err"; bad "$1"; else ok "$1"; fi
}

mkdir "$T/rp"
i=0
while [ $i -lt 4 ]; do
    for side in left right; do
        { printf 'P5\n64 48\n255\n'; awk "BEGIN{s=$i+7; for(k=0;k<3072;k++){s=(s*1103515245+12345)%2147483648; printf \"%c\", 40+int(s/65536)%160}}"; } >"$T/rp/${side}_000$i.pgm"
    done
    i=$((i + 1))
done

# ---- --set: every key of the settings table ----------------------------
# Each key gets a value other than its default, through --set alone, and
# --print-config must show it; the keys come from --print-config itself,
# so a key added to the table is covered without editing this test.
"$RUN" --print-config >"$T/defaults" 2>"$T/err" || bad "--print-config runs"
nkeys=0
nbad=0
while IFS= read -r line; do
    key=${line%% =*}
    val=${line#*=}
    val=${val# }
    case $key in
        alert) new=none ;;
        log_level) new=debug ;;
        record | calib | camera_left | camera_right | log_json | pwm_sysfs_root) new="$T/x_$key" ;;
        button) new=gpio:gpiochip9:3 ;;
        pixel_format) new=Y16 ;;
        *)
            case $val in
                true) new=false ;;
                false) new=true ;;
                *) # an integer: one up, or one down at the top of the range
                    new=$((val + 1))
                    "$RUN" --set "$key=$new" --print-config >/dev/null 2>&1 || new=$((val - 1)) ;;
            esac ;;
    esac
    "$RUN" --set "$key=$new" --print-config >"$T/set" 2>"$T/err"
    nkeys=$((nkeys + 1))
    if ! grep -qx -- "$key = $new" "$T/set"; then
        nbad=$((nbad + 1))
        echo "     | --set $key=$new not applied" >>"$T/log"
    fi
done <"$T/defaults"
if [ "$nkeys" -ge 40 ] && [ "$nbad" -eq 0 ]; then
    ok "--set reaches all $nkeys config keys"
else
    cat "$T/log" >"$T/err" 2>/dev/null; echo "     | $nkeys keys, $nbad not applied" >>"$T/err"; bad "--set reaches every config key"
fi
expect "--set: unknown key" 2 "unknown key 'fsp'" --set fsp=3 replay:"$T/rp"
expect "--set: no '='" 2 "wants KEY=VALUE" --set fps replay:"$T/rp"
expect "--set: out of range" 2 "outside" --set watchdog_ms=1 replay:"$T/rp"
expect "--set: alert vetted as in the config" 2 "bad alert" --set alert=pwm:x replay:"$T/rp"
expect "--set: button vetted" 2 "bad button" --set button=gpio:chip replay:"$T/rp"
printf 'fps = 7\n' >"$T/fps.conf"
expect "--set overrides the config file" 0 "^fps = 9$" --set fps=9 --config "$T/fps.conf" --print-config

# ---- warnings about built-in geometry --------------------------------
expect "defaults: runs" 0 "end of replay" --fps 0 --alert none replay:"$T/rp"
has "default focal_px warned" "warn: geometry: focal_px 250 is the built-in default"
has "default baseline_mm warned" "warn: geometry: baseline_mm 120 is the built-in default"
has "no calibration warned" "warn: geometry: no calibration table"
printf 'focal_px = 400\nbaseline_mm = 60\n' >"$T/geom.conf"
expect "rig geometry set: runs" 0 "end of replay" --config "$T/geom.conf" --fps 0 --alert none replay:"$T/rp"
hasnt "rig focal not warned" "focal_px .* is the built-in default"
hasnt "rig baseline not warned" "baseline_mm .* is the built-in default"
expect "--set focal_px counts as set" 0 "end of replay" --set focal_px=250 --fps 0 --alert none replay:"$T/rp"
hasnt "--set focal_px not warned" "focal_px .* is the built-in default"

# ---- cameras from the config (the unit's command line names none) ----
printf 'camera_left = replay:%s\nfps = 0\nalert = none\n' "$T/rp" >"$T/cam.conf"
expect "cameras from the config" 0 "end of replay after 4 pairs" --config "$T/cam.conf"
expect "no cameras anywhere" 2 "camera_left/camera_right" --alert none

# ---- --motor-off config ------------------------------------------------
printf 'alert = console\n' >"$T/console.conf"
expect "--motor-off config: the config's output" 0 "motor off: console" --config "$T/console.conf" --motor-off config

# ---- journald priorities -----------------------------------------------
# systemd sets JOURNAL_STREAM to stderr's device:inode; a stderr that is
# not that stream keeps plain lines.
: >"$T/journal"
JOURNAL_STREAM=$(stat -L -c '%d:%i' "$T/journal") "$RUN" --fps 0 --alert none replay:"$T/rp" 2>>"$T/journal" >/dev/null
cp "$T/journal" "$T/err"
has "journal: warnings at priority 4" "^<4>\[.*warn: geometry"
has "journal: info at priority 6" "^<6>\[.*info: end of replay"
JOURNAL_STREAM=1:1 "$RUN" --fps 0 --alert none replay:"$T/rp" >/dev/null 2>"$T/err"
hasnt "another stream: no prefixes" "^<[0-9]>"

# ---- sd_notify -----------------------------------------------------------
if [ "$SYSTEMD" = 1 ] && command -v python3 >/dev/null; then
    python3 - "$T/notify.sock" "$T/notify.log" <<'PY' &
import socket, sys
s = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
s.bind(sys.argv[1])
s.settimeout(30)
with open(sys.argv[2], "w") as f:
    while True:
        try:
            m = s.recv(4096).decode()
        except OSError:
            break
        f.write(m.replace("\n", " ") + "\n")
        f.flush()
PY
    LISTENER=$!
    n=0
    while [ ! -S "$T/notify.sock" ] && [ $n -lt 50 ]; do sleep 0.1; n=$((n + 1)); done
    # 2 s of pairs at 30 fps, watchdog asked every 200 ms (keep-alives
    # every 50 ms)
    printf 'replay_loop = true\nfps = 30\nalert = none\n' >"$T/loop.conf"
    NOTIFY_SOCKET="$T/notify.sock" WATCHDOG_USEC=200000 "$RUN" --config "$T/loop.conf" --frames 60 replay:"$T/rp" >/dev/null 2>"$T/err"
    sleep 0.3
    kill "$LISTENER" 2>/dev/null
    LISTENER=
    cat "$T/notify.log" >>"$T/err"
    has "sd_notify: READY=1 once a pair is judged" "^READY=1"
    if [ "$(grep -c '^WATCHDOG=1' "$T/notify.log")" -ge 10 ]; then ok "sd_notify: WATCHDOG=1 while pairs are judged"; else bad "sd_notify: WATCHDOG=1 while pairs are judged"; fi
    has "sd_notify: STOPPING=1 at the end" "^STOPPING=1"
    if [ "$(sed -n 1p "$T/notify.log" | cut -c1-7)" = READY=1 ]; then ok "sd_notify: nothing before READY"; else bad "sd_notify: nothing before READY"; fi

    # A camera that stops delivering while the loop lives on: a recorded
    # session with a 2.9 s hole in its timestamps, replayed at its pace,
    # gives the main loop camera timeouts (as a stalled driver does) between
    # 4 pairs 33 ms apart and 8 pairs 100 ms apart. No keep-alive may come
    # in the hole (systemd restarts the service), and they come back with
    # the pairs.
    mkdir "$T/stall"
    printf 'negobs-session 1\nwidth 64\nheight 48\n' >"$T/stall/session.txt"
    : >"$T/stall/right.y"
    : >"$T/stall/left.y"
    { echo "# index left_ns right_ns sequence"; k=0; while [ $k -lt 12 ]; do
          if [ $k -lt 4 ]; then ts=$((k * 33000000)); else ts=$((3000000000 + (k - 4) * 100000000)); fi
          echo "$k $ts $ts $k"; k=$((k + 1)); done; } >"$T/stall/frames.txt"
    for k in 0 1 2 3 0 1 2 3 0 1 2 3; do
        tail -c 3072 "$T/rp/right_000$k.pgm" >>"$T/stall/right.y"
        tail -c 3072 "$T/rp/left_000$k.pgm" >>"$T/stall/left.y"
    done
    python3 - "$T/notify2.sock" "$T/notify2.log" <<'PY' &
import socket, sys, time
s = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
s.bind(sys.argv[1])
s.settimeout(30)
t0 = time.monotonic()
with open(sys.argv[2], "w") as f:
    while True:
        try:
            m = s.recv(4096).decode()
        except OSError:
            break
        f.write("%d %s\n" % ((time.monotonic() - t0) * 1000, m.replace("\n", " ")))
        f.flush()
PY
    LISTENER=$!
    n=0
    while [ ! -S "$T/notify2.sock" ] && [ $n -lt 50 ]; do sleep 0.1; n=$((n + 1)); done
    printf 'fps = 30\nalert = none\nwatchdog_ms = 300\n' >"$T/stall.conf"
    NOTIFY_SOCKET="$T/notify2.sock" WATCHDOG_USEC=200000 "$RUN" --config "$T/stall.conf" replay:"$T/stall" >/dev/null 2>"$T/err"
    sleep 0.3
    kill "$LISTENER" 2>/dev/null
    LISTENER=
    cat "$T/notify2.log" >>"$T/err"
    # the longest gap between keep-alives, and keep-alives after it
    gap=$(awk '$2 == "WATCHDOG=1" { if (last != "" && $1 - last > g) { g = $1 - last; after = 0 } else if (last != "") after++; last = $1 } END { printf "%d %d", g, after }' "$T/notify2.log")
    echo "     | longest keep-alive gap, keep-alives after it: $gap" >>"$T/err"
    if [ "${gap% *}" -ge 2000 ]; then ok "sd_notify: no WATCHDOG=1 while the camera stalls"; else bad "sd_notify: no WATCHDOG=1 while the camera stalls"; fi
    if [ "${gap#* }" -ge 3 ]; then ok "sd_notify: WATCHDOG=1 again once pairs come back"; else bad "sd_notify: WATCHDOG=1 again once pairs come back"; fi
else
    echo "skip - sd_notify (built without libsystemd)"
fi

# ---- --log-json ------------------------------------------------------------
expect "log-json: run" 0 "end of replay after 4 pairs" --fps 0 --alert none --log-json "$T/pairs.jsonl" replay:"$T/rp"
if [ "$(wc -l <"$T/pairs.jsonl")" -eq 4 ]; then ok "log-json: one line per pair"; else bad "log-json: one line per pair"; fi
if command -v python3 >/dev/null; then
    # negobs_png's fields (tools/detect/detect_common.cpp json_line)
    if python3 - "$T/pairs.jsonl" >"$T/err" 2>&1 <<'PY'; then ok "log-json: valid JSON with negobs_png's fields"; else bad "log-json: valid JSON with negobs_png's fields"; fi
import json, sys
png = ["frame", "file", "stereo_status", "state", "reasons", "level",
       "nearest_range_mm", "clear_to_mm", "short_sight", "noise_vouch_mm",
       "pattern", "motor_on", "duty_permille", "hazards", "candidates",
       "stereo", "ground", "mount", "ms"]
for n, line in enumerate(open(sys.argv[1])):
    d = json.loads(line)
    missing = [k for k in png if k not in d]
    assert not missing, (n, missing)
    assert d["frame"] == n
    for k in ["valid", "valid_pct", "seeds", "range", "vertical_offset", "first_row"]:
        assert k in d["stereo"], k
    for k in ["height_mm", "pitch_mdeg", "roll_mdeg", "source"]:
        assert k in d["mount"], k
PY
fi
expect "log-json appends" 0 "end of replay" --fps 0 --alert none --log-json "$T/pairs.jsonl" replay:"$T/rp"
if [ "$(wc -l <"$T/pairs.jsonl")" -eq 8 ]; then ok "log-json: a restart appends"; else bad "log-json: a restart appends"; fi
printf 'replay_loop = true\nfps = 0\nalert = none\n' >"$T/loop0.conf"
expect "log-json unopenable: the warnings go on" 0 "40 pairs processed" --config "$T/loop0.conf" --frames 40 --log-json "$T/nodir/x.jsonl" replay:"$T/rp"
has "log-json unopenable: said why" "error: log-json: $T/nodir/x.jsonl: No such file"
if [ -w /dev/full ]; then
    expect "log-json write failure: the warnings go on" 0 "40 pairs processed" --config "$T/loop0.conf" --frames 40 --log-json /dev/full replay:"$T/rp"
    if [ "$(grep -c 'log-json: /dev/full: write failed' "$T/err")" -eq 1 ]; then ok "log-json write failure: logged once"; else bad "log-json write failure: logged once"; fi
fi

# ---- meta.txt of a recorded session ------------------------------------
expect "record with meta" 0 "record: closed" --fps 0 --alert none --set focal_px=333 --record "$T/rec" replay:"$T/rp"
cp "$T/rec/meta.txt" "$T/err"
has "meta: version" "^negobs_version = [0-9]"
has "meta: geometry used" "^focal_q4 = 5328$"
has "meta: baseline" "^baseline_um = 120000$"
has "meta: geometry source" "^geometry_source = default$"
has "meta: no calibration" "^calib_file =$"
has "meta: the config" "^config.focal_px = 333$"

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
