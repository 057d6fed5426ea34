# shellcheck shell=sh
# tests/common/kill.sh - sourced by the kill-loop tests (tests/reliability/
# test_kill_*.sh): a job is SIGKILLed at points spread over its run and the
# output name must then hold the complete old file or the complete new one.
# What those tests share:
#   kill_workdir NAME      a temporary folder (removed at exit) made and entered
#   bad MESSAGE            records a failure (the test goes on, ends nonzero)
#   now_ms                 wall clock in milliseconds
#   sleep_ms MS            sleep MS milliseconds
#   spread I N T           the I-th of N kill points spread evenly over T ms
#                          (the middles of N equal slices)
#   check_old_new OUT OLD NEW WHAT
#                          OUT must equal OLD (saw_old += 1) or NEW
#                          (saw_new += 1); otherwise a failure naming WHAT
#   tmp_files OUT          OUT's temporary files (OUT*.tmp*), space-separated
#   kill_end SUMMARY       prints SUMMARY, "ok" when nothing failed, and exits
kill_fail=0
saw_old=0
saw_new=0
kill_workdir() {
    W=$(mktemp -d "${TMPDIR:-/tmp}/$1.XXXXXX") || exit 1
    # shellcheck disable=SC2064 # the folder is known now
    trap "rm -rf '$W'" EXIT
    cd "$W" || exit 1
}
bad() {
    echo "FAIL: $*"
    kill_fail=1
}
now_ms() { echo $(($(date +%s%N) / 1000000)); }
sleep_ms() { sleep "$(awk -v ms="$1" 'BEGIN { printf "%.3f", ms / 1000 }')"; }
spread() { echo $((($1 * 2 + 1) * $3 / (2 * $2))); }
check_old_new() {
    if [ ! -f "$1" ]; then
        bad "$4: $1 missing"
    elif cmp -s "$1" "$2"; then
        saw_old=$((saw_old + 1))
    elif cmp -s "$1" "$3"; then
        saw_new=$((saw_new + 1))
    else
        bad "$4: $1 is neither the old nor the new file ($(wc -c <"$1") bytes)"
    fi
}
tmp_files() { for f in "$1"*.tmp*; do [ -e "$f" ] && printf '%s ' "$f"; done; }
kill_end() {
    echo "$1"
    [ $kill_fail -eq 0 ] && echo "ok"
    exit $kill_fail
}
