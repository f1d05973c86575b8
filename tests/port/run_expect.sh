# Shared checks of the negobs_run black-box scripts (sourced, not run).
# The caller sets RUN (the program) and T (a scratch folder) first; the
# last run's stdout+stderr land in $T/err, which a failure prints.
pass=0
fail=0

ok() { pass=$((pass + 1)); echo "ok   - $1"; }
bad() { fail=$((fail + 1)); echo "FAIL - $1"; sed 's/^/     | /' "$T/err" | tail -20; }

# expect NAME RC NEEDLE ARGS...: exit code RC and NEEDLE in stdout+stderr.
expect() {
    name=$1; want=$2; needle=$3; shift 3
    "$RUN" "$@" >"$T/out" 2>"$T/err"
    rc=$?
    cat "$T/out" >>"$T/err"
    if [ "$rc" -ne "$want" ]; then
        echo "     | exit $rc, want $want" >>"$T/err"; bad "$name"; return
    fi
    if [ -n "$needle" ] && ! grep -q -- "$needle" "$T/err"; then
        echo "     | missing: $needle" >>"$T/err"; bad "$name"; return
    fi
    ok "$name"
}

# flat_pairs N HEIGHT_MM: N pairs of negobs_synth's flat walk (1.2 m/s at
# 10 fps, 224x168, f 175, B 120 mm, pitch 20 deg, camera HEIGHT_MM high)
# in $T/raw/pgm for replay:$T/raw/pgm. The caller sets SYNTH and PNG2RAW
# (tests/hw/png2raw.py); the script stops on a failure.
flat_pairs() {
    "$SYNTH" --scene flat --edge-mm 9000 --frames "$1" --speed 1.2 --fps 10 \
        --f 175 --baseline-mm 120 --height-mm "$2" --pitch-deg 20 \
        --width 224 --height 168 --noise 2 --seed 11 --out "$T/png" \
        >/dev/null || { echo "FAIL: negobs_synth"; exit 1; }
    python3 "$PNG2RAW" "$T/png" "$T/raw" --pgm >/dev/null ||
        { echo "FAIL: png2raw"; exit 1; }
}
