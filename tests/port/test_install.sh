#!/bin/sh
# `meson install --destdir` gives a tree whose service files work: the
# unit (paths filled in, Type=notify, watchdog, non-root user, hardening,
# ExecStopPost), the udev rule, the service account, the example config
# (which the installed negobs_run accepts) and the programs.
# Usage: test_install.sh BUILD_DIR PREFIX SYSCONFDIR
set -u
B=$1
PREFIX=$2
SYSCONF=$3
case $SYSCONF in /*) ;; *) SYSCONF=$PREFIX/$SYSCONF ;; esac
T=$(mktemp -d "${TMPDIR:-/tmp}/negobs-install-XXXXXX")
trap 'rm -rf "$T"' EXIT
pass=0
fail=0
ok() { pass=$((pass + 1)); echo "ok   - $1"; }
bad() { fail=$((fail + 1)); echo "FAIL - $1"; [ -f "$T/err" ] && sed 's/^/     | /' "$T/err" | tail -20; }
need() { # NAME FILE REGEX
    if grep -Eq -- "$3" "$2" 2>/dev/null; then ok "$1"; else echo "     | $2 lacks: $3" >"$T/err"; bad "$1"; fi
}

D=$T/root
if meson install -C "$B" --destdir "$D" --no-rebuild --quiet >"$T/err" 2>&1; then
    ok "meson install --destdir"
else
    bad "meson install --destdir"
    echo "$pass passed, $fail failed"
    exit 1
fi
U=$D$PREFIX/lib/systemd/system/negobs.service
R=$D$PREFIX/lib/udev/rules.d/60-negobs.rules
S=$D$PREFIX/lib/sysusers.d/negobs.conf
C=$D$SYSCONF/negobs.conf
RUN=$D$PREFIX/bin/negobs_run
for f in "$U" "$R" "$S" "$C"; do
    if [ -s "$f" ]; then ok "installed ${f#"$D"}"; else echo "     | missing $f" >"$T/err"; bad "installed ${f#"$D"}"; fi
done
if [ -x "$RUN" ]; then ok "installed negobs_run"; else bad "installed negobs_run"; fi

need "unit: Type=notify" "$U" '^Type=notify$'
need "unit: watchdog" "$U" '^WatchdogSec=[0-9]+'
need "unit: ExecStart with the installed paths" "$U" "^ExecStart=$PREFIX/bin/negobs_run --config $SYSCONF/negobs.conf\$"
need "unit: motor off after every stop" "$U" "^ExecStopPost=$PREFIX/bin/negobs_run --config $SYSCONF/negobs.conf --motor-off config\$"
need "unit: non-root user" "$U" '^User=negobs$'
need "unit: device groups" "$U" '^SupplementaryGroups=video gpio$'
for h in 'NoNewPrivileges=yes' 'ProtectSystem=strict' 'ProtectHome=yes' \
         'PrivateTmp=yes' 'DevicePolicy=closed' 'DeviceAllow=char-video4linux rw' \
         'DeviceAllow=char-gpiochip rw' 'CapabilityBoundingSet=$'; do
    need "unit: $h" "$U" "^$h"
done
if grep -v '^SystemCallFilter' "$U" | grep -q '@[A-Z_]*@'; then bad "unit: every @VAR@ substituted"; else ok "unit: every @VAR@ substituted"; fi
if command -v systemd-analyze >/dev/null 2>&1; then
    # the unit's syntax, with the installed program in place
    # (the programs are not at their installed paths on this machine:
    # only the unit's own lines are judged)
    systemd-analyze verify "$U" >"$T/err" 2>&1
    if ! grep -Eq 'Unknown (key|section|lvalue)|Invalid|Failed to parse' "$T/err"; then
        ok "unit: systemd-analyze finds no bad keys"
    else
        bad "unit: systemd-analyze finds no bad keys"
    fi
fi
need "udev: gpiochip group gpio" "$R" 'KERNEL=="gpiochip\*", GROUP="gpio", MODE="0660"'
need "udev: pwm chip events" "$R" '^SUBSYSTEM=="pwm", KERNEL=="pwmchip\*", ACTION=="add\|change"'
need "udev: pwm files to group gpio" "$R" "chgrp -R gpio /sys%p && chmod -R g\+w /sys%p"
need "sysusers: user negobs" "$S" '^u negobs '
need "sysusers: in group gpio" "$S" '^m negobs gpio$'
need "sysusers: in group video" "$S" '^m negobs video$'

# The example config is what the installed program runs with.
"$RUN" --config "$C" --print-config >"$T/cfg" 2>"$T/err"
if [ $? -eq 0 ]; then ok "example config accepted by the installed negobs_run"; else bad "example config accepted by the installed negobs_run"; fi
need "example config: cameras set" "$T/cfg" '^camera_left = /dev/video'
"$RUN" --version >"$T/err" 2>&1 && ok "installed negobs_run --version" || bad "installed negobs_run --version"

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
