#!/bin/sh
# tests/reliability/test_kill_bake.sh - svo_bake survives SIGKILL (issue 17).
# Usage: test_kill_bake.sh BINDIR [KILLS]
#
# A small CPU bake (the demo scene, 4x4x4 probes at res 16, one thread) over
# an existing output is SIGKILLed at KILLS points (default 10) spread over
# its run. After each kill: OUT.probes holds the complete old file or the
# complete new one, never a partial file; OUT.probes.partial, when there, is a
# checkpoint the next run accepts ("resuming", never "not a checkpoint");
# that next run gives the same bytes as an uninterrupted bake, removes the
# checkpoint and leaves no temporary file.
set -u
BIN=$1
KILLS=${2:-10}
# shellcheck source=../common/kill.sh
. "$(dirname "$0")/../common/kill.sh"
kill_workdir vx_kill_bake

"$BIN/vox2svo" --write-demo demo.vox >/dev/null || exit 1
"$BIN/vox2svo" -q demo.vox demo.svo || exit 1
spp=8
while :; do
    O="--cpu --res 16 --spp $spp --threads 1 --grid 4,4,4 -q"
    t0=$(now_ms)
    # shellcheck disable=SC2086
    "$BIN/svo_bake" demo.svo ref.probes $O >run.log 2>&1 || { cat run.log; exit 1; }
    T=$(($(now_ms) - t0))
    [ "$T" -le 1500 ] || [ $spp -le 1 ] || { spp=$((spp / 4)); [ $spp -ge 1 ] || spp=1; continue; }
    break
done
# shellcheck disable=SC2086
"$BIN/svo_bake" demo.svo old.probes $O --seed 2 >/dev/null 2>&1 || exit 1
cmp -s old.probes ref.probes && { echo "old and new bakes are the same bytes"; exit 1; }
echo "bake: $spp spp, run $T ms, $(wc -c <ref.probes) bytes"

# a checkpoint after every step (the default is one per 20 s, more than this
# whole bake), so that kills land while checkpoints are written and read back
export VX_BAKE_CHECKPOINT_S=0
killed=0 finished=0 resumed=0
i=0
while [ $i -lt "$KILLS" ]; do
    at=$(spread $i "$KILLS" "$T")
    cp old.probes out.probes
    rm -f out.probes.partial
    # shellcheck disable=SC2086
    "$BIN/svo_bake" demo.svo out.probes $O >/dev/null 2>&1 &
    pid=$!
    sleep_ms "$at"
    if kill -KILL $pid 2>/dev/null; then killed=$((killed + 1)); else finished=$((finished + 1)); fi
    wait $pid 2>/dev/null
    check_old_new out.probes old.probes ref.probes "kill $i at $at ms"
    # resume (or start over when no checkpoint was written yet)
    # shellcheck disable=SC2086
    "$BIN/svo_bake" demo.svo out.probes $O >resume.log 2>&1 || bad "run after kill $i failed: $(cat resume.log)"
    grep -q "not a checkpoint" resume.log && bad "kill $i at $at ms: the checkpoint was not readable: $(cat resume.log)"
    grep -q "resuming" resume.log && resumed=$((resumed + 1))
    cmp -s out.probes ref.probes || bad "run after kill $i at $at ms: differs from an uninterrupted bake"
    [ ! -e out.probes.partial ] || bad "run after kill $i: checkpoint left behind"
    left=$(tmp_files out.probes)
    [ -z "$left" ] || bad "after kill $i and a successful run, temporary files remain: $left"
    i=$((i + 1))
done
kill_end "$KILLS kill points: $killed killed mid-run ($saw_new after the output was renamed into place), $finished ran to the end first; $resumed resumed from a checkpoint"
