#!/bin/sh
# Run a command that must fail cleanly: exit with exactly CODE (a crash,
# abort or sanitizer report has another code) and print a line matching
# the extended regular expression MESSAGE on stderr.
# usage: expect_fail.sh CODE MESSAGE COMMAND [ARGS...]
set -u
code=$1
msg=$2
shift 2
err=$("$@" 2>&1 >/dev/null)
rc=$?
printf '%s\n' "$err"
if [ "$rc" -ne "$code" ]; then
    echo "FAIL: exit $rc, expected $code"
    exit 1
fi
if ! printf '%s\n' "$err" | grep -Eq -- "$msg"; then
    echo "FAIL: no message matching '$msg'"
    exit 1
fi
echo "PASS: exit $rc with '$msg'"
exit 0
