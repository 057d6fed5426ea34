#!/bin/sh
# tests/reliability/test_kill_bake_mpi.sh - an MPI bake killed whole (issue 17).
# Usage: test_kill_bake_mpi.sh BINDIR [MPIEXEC [KILLS]]; exits 77 (skipped)
# without an mpirun that can start processes here.
#
# `mpirun -n 2 svo_bake --cpu` (the demo scene, 4x3x3 probes at res 16) over
# an existing output, started in a session of its own, and the whole session
# (mpirun and every rank) SIGKILLed at KILLS points (default 8) spread over
# its run, as a power cut or a scheduler's kill would. After each kill: no
# process of the job is left; the output name holds the complete old file or
# the complete new one; the next run (mpirun -n 3, so the checkpoints are
# taken by another number of ranks) accepts what the killed job left (never
# "not a checkpoint"), gives the single-process bake's bytes, and leaves no
# checkpoint (OUT.probes.partial, OUT.probes.ckpt/) and no temporary file.
# (The first runs found a rank's batch file half-written when the job was
# killed, OUT.probes.ckpt/bA-B.rR.probes.tmpPID, kept for good with the
# folder: the next run now removes such files of dead writers.)
set -u
BIN=$1
MPIRUN=${2:-mpirun}
KILLS=${3:-8}
. "$(dirname "$0")/../common/mpi.sh"
command -v setsid >/dev/null 2>&1 || { echo "SKIP: no setsid"; exit 77; }
# shellcheck source=../common/kill.sh
. "$(dirname "$0")/../common/kill.sh"
cd "$T" || exit 1

"$BIN/vox2svo" --write-demo demo.vox >/dev/null || exit 1
"$BIN/vox2svo" -q demo.vox demo.svo || exit 1
# (the MPI bake's checkpoints are the ranks' batch files; the single
# process's prefix checkpoint after every batch)
export VX_BAKE_CHECKPOINT_S=0
# calibrate: the most samples (up to 64) whose job stays near 4 s, so the
# baking, not mpirun's start, is most of the run
spp=64
while :; do
    O="--cpu --res 16 --spp $spp --threads 1 --grid 4,3,3 -q"
    t0=$(now_ms)
    # shellcheck disable=SC2086
    run 2 "$BIN/svo_bake" demo.svo ref2.probes $O >run.log 2>&1 || { cat run.log; exit 1; }
    T=$(($(now_ms) - t0))
    [ "$T" -le 4500 ] || [ $spp -le 1 ] || { spp=$((spp / 2)); continue; }
    break
done
# shellcheck disable=SC2086
"$BIN/svo_bake" demo.svo ref.probes $O >/dev/null 2>&1 || exit 1
cmp -s ref.probes ref2.probes || { echo "the MPI bake differs from the single-process one"; exit 1; }
# shellcheck disable=SC2086
"$BIN/svo_bake" demo.svo old.probes $O --seed 2 >/dev/null 2>&1 || exit 1
cmp -s old.probes ref.probes && { echo "old and new bakes are the same bytes"; exit 1; }
echo "bake on 2 ranks: $spp spp, run $T ms (mpirun included), $(wc -c <ref.probes) bytes"

# SIGKILL to every process of session $1 (mpirun moves itself and the ranks
# into process groups of their own, so a group kill misses some), repeated
# until none is left; false when there was none
kill_session() {
    any=1 k=0
    while [ $k -lt 50 ]; do
        pids=$(ps -eo pid=,sid= | awk -v s="$1" '$2 == s { print $1 }')
        [ -z "$pids" ] && break
        any=0
        # shellcheck disable=SC2086
        kill -KILL $pids 2>/dev/null
        sleep 0.05
        k=$((k + 1))
    done
    return $any
}
left_files() { for f in out.probes.partial out.probes.ckpt out.probes*.tmp* out.probes.ckpt/*.tmp*; do [ -e "$f" ] && printf '%s ' "$f"; done; }
# a batch file's temporary file left by a killed writer (a dead pid) goes
# with the next run; a live process's is kept
mkdir out.probes.ckpt
dead=$(sh -c 'echo $$')
echo partial >"out.probes.ckpt/b0-3.r1.probes.tmp$dead"
echo partial >"out.probes.ckpt/b3-5.r0.probes.tmp$$"
# shellcheck disable=SC2086
run 2 "$BIN/svo_bake" demo.svo out.probes $O >run.log 2>&1 || { cat run.log; bad "run over planted temporary files"; }
[ -e "out.probes.ckpt/b0-3.r1.probes.tmp$dead" ] && bad "a dead writer's batch temporary file was kept"
[ -e "out.probes.ckpt/b3-5.r0.probes.tmp$$" ] || bad "a live writer's batch temporary file was removed"
rm -rf out.probes.ckpt

killed=0 finished=0 resumed=0 ckpt_after_kill=0
i=0
while [ $i -lt "$KILLS" ]; do
    at=$(spread $i "$KILLS" "$T")
    cp old.probes out.probes
    rm -rf out.probes.partial out.probes.ckpt
    # a session of its own, whose id is the pid: every rank is in it
    # shellcheck disable=SC2086
    setsid $MPIRUN $MPIFLAGS -n 2 "$BIN/svo_bake" demo.svo out.probes $O >/dev/null 2>&1 &
    pid=$!
    sleep_ms "$at"
    if kill_session $pid; then killed=$((killed + 1)); else finished=$((finished + 1)); fi
    wait $pid 2>/dev/null
    ps -eo sid= | awk -v s="$pid" '$1 == s { f = 1 } END { exit !f }' && bad "kill $i at $at ms: processes of the job are still running"
    check_old_new out.probes old.probes ref.probes "kill $i at $at ms"
    [ -n "$(left_files)" ] && ckpt_after_kill=$((ckpt_after_kill + 1))
    # shellcheck disable=SC2086
    run 3 "$BIN/svo_bake" demo.svo out.probes $O >resume.log 2>&1 || bad "run after kill $i failed: $(cat resume.log)"
    grep -q "not a checkpoint\|not a batch" resume.log && bad "kill $i at $at ms: a checkpoint was refused: $(cat resume.log)"
    grep -q "resuming" resume.log && resumed=$((resumed + 1))
    cmp -s out.probes ref.probes || bad "run after kill $i at $at ms: differs from an uninterrupted bake"
    l=$(left_files)
    [ -z "$l" ] || bad "after kill $i and a successful run, left behind: $l"
    i=$((i + 1))
done
kill_end "$KILLS kill points: $killed jobs killed ($saw_old left the old file, $saw_new the new one), $finished ended first; $ckpt_after_kill left checkpoints or temporary files, $resumed reruns resumed from checkpoints"
