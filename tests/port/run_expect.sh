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
