#!/bin/sh
# tests/reliability/test_kill_write.sh - crash-safe writes (issue 17).
# Usage: test_kill_write.sh BINDIR MAKE_NOISE_VOX [KILLS]
#
# vox2svo converts a generated scene (make_noise_vox: random cells, so the
# .svo is large and the write takes a good part of the run) over an existing
# output and is SIGKILLed at KILLS points (default 20): half spread over the
# whole run, half over its write phase (from the tool's own read/convert/
# write times). After each kill the output name must hold the complete old
# file or the complete new one (byte-identical to runs that were not
# killed), never a partial file; the next successful run must leave no
# temporary file (OUT.tmp*) behind. The input is scaled so one run takes
# about 0.3 s in the build under test (ASan builds are slower).
set -u
BIN=$1
GEN=$2
KILLS=${3:-20}
# shellcheck source=../common/kill.sh
. "$(dirname "$0")/../common/kill.sh"
kill_workdir vx_kill

"$BIN/vox2svo" --write-demo demo.vox >/dev/null || exit 1
"$BIN/vox2svo" -q demo.vox old.svo || exit 1

# calibrate: the largest noise scene (2 models, SIZE^3) whose run stays near 0.3 s
size=80
while :; do
    "$GEN" noise.vox 2 $size || exit 1
    t0=$(now_ms)
    "$BIN/vox2svo" noise.vox new.svo >run.log 2>&1 || { cat run.log; exit 1; }
    T=$(($(now_ms) - t0))
    [ "$T" -le 600 ] || [ $size -le 24 ] || { size=$((size * 3 / 4)); continue; }
    break
done
# "time  404.2 ms (read 5.9, convert 222.0, write 176.3)": the write starts at
# (read + convert) / total of the run
wstart=$(awk -v T="$T" '/time .*write/ {
    gsub(/[(),]/, " "); for (i = 1; i <= NF; i++) { if ($i == "ms") tot = $(i - 1); if ($i == "read") r = $(i + 1); if ($i == "convert") c = $(i + 1) }
    if (tot > 0) printf "%d", T * (r + c) / tot }' run.log)
[ -n "$wstart" ] || wstart=$((T / 2))
echo "scene 2 x ${size}^3 cells, run $T ms, write from about $wstart ms, $(wc -c <new.svo) bytes (old: $(wc -c <old.svo))"
cmp -s old.svo new.svo && { echo "old and new outputs are the same bytes"; exit 1; }

# temporary files of writers that were killed earlier: a dead pid's are
# removed by the next write of the same name, a live process's are kept
dead=$(sh -c 'echo $$')
echo partial >"out.svo.tmp$dead"
echo partial >"out.svo.tmp$dead.sections"
echo partial >"out.svo.tmp$$"
echo partial >"other.svo.tmp$dead"
"$BIN/vox2svo" -q demo.vox out.svo || bad "run over stale temporary files failed"
if [ -e "out.svo.tmp$dead" ] || [ -e "out.svo.tmp$dead.sections" ]; then bad "a dead writer's temporary files were kept"; fi
[ -e "out.svo.tmp$$" ] || bad "a live writer's temporary file was removed"
[ -e "other.svo.tmp$dead" ] || bad "another output's temporary file was removed"
rm -f "out.svo.tmp$$" "other.svo.tmp$dead"

killed=0 finished=0 tmp_after_kill=0
i=0
while [ $i -lt "$KILLS" ]; do
    half=$((KILLS / 2))
    if [ $i -lt $half ]; then
        at=$(spread $i $half "$T")
    else
        at=$((wstart + $(spread $((i - half)) $((KILLS - half)) $((T - wstart)))))
    fi
    cp old.svo out.svo
    "$BIN/vox2svo" -q noise.vox out.svo &
    pid=$!
    sleep_ms "$at"
    if kill -KILL $pid 2>/dev/null; then killed=$((killed + 1)); else finished=$((finished + 1)); fi
    wait $pid 2>/dev/null
    check_old_new out.svo old.svo new.svo "kill $i at ${at} ms"
    n=$(tmp_files out.svo | wc -w)
    tmp_after_kill=$((tmp_after_kill + n))
    # the next successful run: the new file, and no temporary file left
    "$BIN/vox2svo" -q noise.vox out.svo || bad "run after kill $i failed"
    cmp -s out.svo new.svo || bad "run after kill $i: out.svo differs from an uninterrupted run"
    left=$(tmp_files out.svo)
    [ -z "$left" ] || bad "after kill $i and a successful run, temporary files remain: $left"
    rm -f out.svo.tmp*
    i=$((i + 1))
done
kill_end "$KILLS kill points: $killed killed mid-run ($saw_old left the old file, $((killed - saw_old)) the new one), $finished ran to the end first; $tmp_after_kill temporary files seen right after the kills"
