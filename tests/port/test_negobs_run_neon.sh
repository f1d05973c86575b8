#!/bin/sh
# A 32-bit ARM negobs_run built with -Darm_neon=true on a CPU without NEON
# (qemu-arm's Cortex-A15 with NEON switched off) must refuse at start-up
# with a message and exit 1, not die with SIGILL; with NEON it goes on to
# its usual argument check (exit 2).
# Usage: test_negobs_run_neon.sh QEMU_ARM NEGOBS_RUN
set -u
RUN=$1
BIN=$2
T=$(mktemp -d "${TMPDIR:-/tmp}/negobs-neon-XXXXXX")
trap 'rm -rf "$T"' EXIT
. "$(dirname "$0")/run_expect.sh"

SYSROOT="-L /usr/arm-linux-gnueabihf -E LD_LIBRARY_PATH=/usr/lib/arm-linux-gnueabihf"
# shellcheck disable=SC2086
expect "refused on a CPU without NEON" 1 "built with NEON" \
    -cpu cortex-a15,neon=off $SYSROOT "$BIN"
# shellcheck disable=SC2086
expect "runs on a CPU with NEON" 2 "missing camera arguments" \
    -cpu cortex-a15 $SYSROOT "$BIN"

echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
