#!/bin/sh
# tests/reliability/test_kill_view.sh - svo_view's save killed (issue 17).
# Usage: test_kill_view.sh BINDIR MAKE_NOISE_VOX [KILLS]
#
# svo_view runs headless (--hidden --script, under Xvfb: the script re-runs
# itself under xvfb-run -a when DISPLAY is not set; exit 77, skipped, when
# neither is there) on a generated noise scene and saves it over an existing
# output: the script grabs the frame to mark.png, then saves (the same call
# as Ctrl+S) and quits. The save starts right after mark.png appears; its
# length is measured in a run that is not killed (until the output is newer
# than mark.png; the shortest of a few runs), and the scene is grown until it
# lasts at least 100 ms.
# Then KILLS runs (default 12) are SIGKILLed at points spread evenly over the
# save and a little past it. After each kill the output name must hold the complete old file or
# the complete new one, never a partial file, and the next run (not killed)
# must give the new bytes and leave no temporary file (OUT.tmp*).
set -u
BIN=$1
GEN=$2
KILLS=${3:-12}
if [ -z "${DISPLAY:-}" ]; then
    if [ -z "${VX_KILL_VIEW_XVFB:-}" ] && command -v xvfb-run >/dev/null 2>&1; then
        VX_KILL_VIEW_XVFB=1 exec xvfb-run -a sh "$0" "$@"
    fi
    echo "SKIP: no display (xvfb-run not found)"
    exit 77
fi
# shellcheck source=../common/kill.sh
. "$(dirname "$0")/../common/kill.sh"
kill_workdir vx_kill_view
view() { "$BIN/svo_view" noise.svo --hidden --size 64x64 --script save.txt; }

"$BIN/vox2svo" --write-demo demo.vox >/dev/null || exit 1
"$BIN/vox2svo" -q demo.vox old.svo || exit 1
printf 'grab mark.png\nsave out.svo\nquit\n' >save.txt

# One run, not killed: sets D (ms from mark.png to the saved output) and
# leaves the output in out.svo. Polls every few milliseconds.
measure() {
    rm -f mark.png
    cp old.svo out.svo
    touch -d '2000-01-01' out.svo
    view >run.log 2>&1 &
    pid=$!
    t_mark=0 D=0
    while kill -0 $pid 2>/dev/null; do
        if [ "$t_mark" -eq 0 ]; then
            [ -e mark.png ] && t_mark=$(now_ms)
        elif [ out.svo -nt mark.png ]; then
            D=$(($(now_ms) - t_mark))
            break
        fi
        sleep 0.002
    done
    wait $pid || { cat run.log; return 1; }
    [ "$t_mark" -gt 0 ] && [ "$D" -eq 0 ] && D=1 # saved between two polls
    return 0
}

size=80
while :; do
    "$GEN" noise.vox 2 $size || exit 1
    "$BIN/vox2svo" -q noise.vox noise.svo || exit 1
    measure || exit 1
    [ "$D" -lt 100 ] && [ $size -lt 200 ] && { size=$((size * 5 / 4)); continue; }
    break
done
cp out.svo new.svo
# the shortest of three saves: on a loaded machine one run's length varies by
# 2x, and kills placed past a save's end only see the new file
for _ in 1 2 3; do
    d=$D
    measure || exit 1
    cmp -s out.svo new.svo || { echo "two saves of the same scene differ"; exit 1; }
    [ "$d" -lt "$D" ] && D=$d
done
cmp -s old.svo new.svo && { echo "old and new outputs are the same bytes"; exit 1; }
echo "scene 2 x ${size}^3 cells, the save takes about $D ms, $(wc -c <new.svo) bytes (old: $(wc -c <old.svo))"

killed=0 finished=0 tmp_after_kill=0 early=0
i=0
while [ $i -lt "$KILLS" ]; do
    at=$(spread $i "$KILLS" $((D * 11 / 10))) # over 110% of the save: its end is the rename
    rm -f mark.png
    cp old.svo out.svo
    view >run.log 2>&1 &
    pid=$!
    while [ ! -e mark.png ] && kill -0 $pid 2>/dev/null; do sleep 0.002; done
    [ -e mark.png ] || early=$((early + 1))
    sleep_ms "$at"
    if kill -KILL $pid 2>/dev/null; then killed=$((killed + 1)); else finished=$((finished + 1)); fi
    wait $pid 2>/dev/null
    check_old_new out.svo old.svo new.svo "kill $i at ${at} ms into the save"
    n=$(tmp_files out.svo | wc -w)
    tmp_after_kill=$((tmp_after_kill + n))
    # the next run: the new file, and no temporary file left
    view >run.log 2>&1 || { cat run.log; bad "run after kill $i failed"; }
    cmp -s out.svo new.svo || bad "run after kill $i: out.svo differs from an uninterrupted save"
    left=$(tmp_files out.svo)
    [ -z "$left" ] || bad "after kill $i and a run, temporary files remain: $left"
    rm -f out.svo.tmp*
    i=$((i + 1))
done
[ "$early" -eq 0 ] || bad "$early runs ended before mark.png appeared"
kill_end "$KILLS kill points over the save: $killed killed ($saw_old left the old file, $saw_new the new one), $finished had exited first; $tmp_after_kill temporary files seen right after the kills"
