# tests/common/expect.sh - shared by the shell tests (sourced): a temporary
# folder $T removed at exit, pass/fail counters, ok/bad and
# expect_status EXPECTED DESCRIPTION COMMAND... (stdout in $T/out, stderr in $T/err).
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
pass=0
fail=0
ok() { pass=$((pass + 1)); echo "[  ok  ] $1"; }
bad() { fail=$((fail + 1)); echo "[ FAIL ] $1"; }
expect_status() { # expected description command...
    want=$1; what=$2; shift 2
    "$@" >"$T/out" 2>"$T/err"
    got=$?
    if [ "$got" = "$want" ]; then ok "$what"; else bad "$what (exit $got, wanted $want)"; cat "$T/err"; fi
}
