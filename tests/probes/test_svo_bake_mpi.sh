#!/bin/sh
# svo_bake under MPI (issue 22): mpirun -n 1, 2 and 3 bakes equal the
# single-process bake byte for byte, and so does --shard + --merge; the same
# on the GPU (lavapipe) where a Vulkan device exists, also --load models (the
# model reader on every rank); a rank killed after its
# first batch (or failing with an error) ends the job nonzero with no output
# file, and the rerun continues from the checkpoint to the same bytes; the
# same from the ranks' batch checkpoints (OUT.probes.ckpt/), also on another
# number of ranks; a single-process checkpoint is resumed by an MPI run.
# Usage: test_svo_bake_mpi.sh BIN_DIR [MPIEXEC]; exits 77 (skipped) without mpirun.
set -u
BIN=$1
MPIRUN=${2:-mpirun}
. "$(dirname "$0")/../common/mpi.sh"
"$BIN/vox2svo" --write-demo "$T/demo.vox" >/dev/null || fail "write demo"
"$BIN/vox2svo" "$T/demo.vox" "$T/demo.svo" >/dev/null || fail "vox2svo"
O="--grid 4,3,3 --res 16 --spp 2 --seed 5 -q --cpu"
"$BIN/svo_bake" "$T/demo.svo" "$T/full.probes" $O --threads 1 >/dev/null || fail "single bake"
for n in 1 ${VX_MPI_RANKS:-2 3}; do
  t0=$(date +%s.%N)
  run $n "$BIN/svo_bake" "$T/demo.svo" "$T/m$n.probes" $O -v >"$T/m$n.out" 2>&1 || { cat "$T/m$n.out"; fail "mpirun -n $n"; }
  t1=$(date +%s.%N)
  cmp -s "$T/full.probes" "$T/m$n.probes" || fail "mpirun -n $n differs from the single bake"
  grep -q "on $n ranks" "$T/m$n.out" || fail "mpirun -n $n: no summary line"
  check_timeline "$T/m$n.out" $n "$t0" "$t1" || { cat "$T/m$n.out"; fail "mpirun -n $n: the ranks' timelines"; }
done
# more ranks than probes: idle ranks, the same single probe
"$BIN/svo_bake" "$T/demo.svo" "$T/one.probes" --grid 1,1,1 --res 16 --spp 1 --cpu -q >/dev/null || fail "1-probe bake"
run 3 "$BIN/svo_bake" "$T/demo.svo" "$T/one3.probes" --grid 1,1,1 --res 16 --spp 1 --cpu -q >/dev/null 2>&1 || fail "1 probe on 3 ranks"
cmp -s "$T/one.probes" "$T/one3.probes" || fail "1 probe on 3 ranks differs"
"$BIN/svo_bake" "$T/demo.svo" "$T/p0.probes" $O --shard 0/2 >/dev/null || fail "shard 0"
"$BIN/svo_bake" "$T/demo.svo" "$T/p1.probes" $O --shard 1/2 >/dev/null || fail "shard 1"
"$BIN/svo_bake" --merge "$T/merged.probes" "$T/p1.probes" "$T/p0.probes" >/dev/null || fail "merge"
cmp -s "$T/full.probes" "$T/merged.probes" || fail "shards + merge differ from the single and MPI bakes"
# usage errors: once, exit 2
run 2 "$BIN/svo_bake" "$T/demo.svo" "$T/x.probes" $O --shard 0/2 >"$T/u.out" 2>&1; [ $? -ne 0 ] || fail "--shard under mpirun must fail"
[ "$(grep -c "under mpirun" "$T/u.out")" = 1 ] || { cat "$T/u.out"; fail "usage error not printed once"; }
# a rank killed after its first batch: nonzero, nothing under the output name
VX_BAKE_CHECKPOINT_S=0 VX_BAKE_MPI_FAIL=1:1 run 2 "$BIN/svo_bake" "$T/demo.svo" "$T/k.probes" $O >"$T/k.out" 2>&1
[ $? -ne 0 ] || fail "a killed rank must fail the job"
[ ! -e "$T/k.probes" ] || fail "killed job left an output file"
ls "$T" | grep -q "^k.probes.tmp" && fail "killed job left a temporary file"
had_checkpoint=0
[ -e "$T/k.probes.partial" ] && had_checkpoint=1
run 2 "$BIN/svo_bake" "$T/demo.svo" "$T/k.probes" $O >"$T/k2.out" 2>&1 || { cat "$T/k2.out"; fail "rerun after the kill"; }
# the MPI bake writes no prefix checkpoint (the ranks' batch files are its
# checkpoints); one that exists must be resumed
[ $had_checkpoint = 0 ] || grep -q "resuming from" "$T/k2.out" || fail "rerun did not resume the killed job's checkpoint"
cmp -s "$T/full.probes" "$T/k.probes" || fail "rerun after the kill differs"
[ ! -e "$T/k.probes.partial" ] || fail "checkpoint left behind"
[ ! -e "$T/k.probes.ckpt" ] || fail "batch checkpoints left behind"
# per-rank batch checkpoints: rank 1 killed after its second batch (no prefix
# checkpoint in so short a bake): its two batch files are on disk, and a
# rerun on 3 ranks takes them and the others' and ends with the same bytes
VX_BAKE_MPI_FAIL=1:2 run 2 "$BIN/svo_bake" "$T/demo.svo" "$T/b.probes" $O >"$T/b.out" 2>&1
[ $? -ne 0 ] || fail "a killed rank must fail the job (batch checkpoints)"
[ ! -e "$T/b.probes" ] || fail "killed job left an output file (batch checkpoints)"
[ "$(ls "$T/b.probes.ckpt" 2>/dev/null | grep -c '^b[0-9]*-[0-9]*\.r1\.probes$')" -ge 2 ] ||
  { ls -l "$T/b.probes.ckpt"; cat "$T/b.out"; fail "rank 1's batch checkpoints are missing"; }
run 3 "$BIN/svo_bake" "$T/demo.svo" "$T/b.probes" $O >"$T/b2.out" 2>&1 || { cat "$T/b2.out"; fail "rerun from batch checkpoints"; }
grep -q "resuming from .*b.probes.ckpt: [1-9][0-9]* probes from [1-9][0-9]* batch checkpoints" "$T/b2.out" ||
  { cat "$T/b2.out"; fail "rerun did not take the batch checkpoints"; }
cmp -s "$T/full.probes" "$T/b.probes" || fail "rerun from batch checkpoints differs from the single bake"
[ ! -e "$T/b.probes.ckpt" ] || fail "batch checkpoints left behind after the rerun"
# a batch file counts by its range, whoever wrote it: shard 1 (probes 18..35
# of the 4x3x3 grid) resumes 18 probes; a batch of another job (another
# seed) is ignored with a message and left alone
mkdir "$T/s.probes.ckpt"
cp "$T/p1.probes" "$T/s.probes.ckpt/b18-36.r7.probes"
"$BIN/svo_bake" "$T/demo.svo" "$T/other.probes" --grid 4,3,3 --res 16 --spp 2 --seed 6 -q --cpu --shard 0/2 >/dev/null ||
  fail "bake of another job"
cp "$T/other.probes" "$T/s.probes.ckpt/b0-18.r3.probes"
run 2 "$BIN/svo_bake" "$T/demo.svo" "$T/s.probes" $O >"$T/s.out" 2>&1 || { cat "$T/s.out"; fail "bake over planted batches"; }
grep -q ": 18 probes from 1 batch checkpoints" "$T/s.out" || { cat "$T/s.out"; fail "the shard as a batch was not taken"; }
grep -q "b0-18.r3.probes: not a batch of this job" "$T/s.out" || { cat "$T/s.out"; fail "another job's batch not refused"; }
cmp -s "$T/full.probes" "$T/s.probes" || fail "bake over planted batches differs"
[ -e "$T/s.probes.ckpt/b0-18.r3.probes" ] || fail "another job's file was removed"
[ ! -e "$T/s.probes.ckpt/b18-36.r7.probes" ] || fail "a taken batch file was left behind"
# a rank failing with an error: a message naming it, nonzero, no output
VX_BAKE_MPI_FAIL=1:1:error run 3 "$BIN/svo_bake" "$T/demo.svo" "$T/e.probes" $O >"$T/e.out" 2>&1
[ $? -ne 0 ] || fail "a failing rank must fail the job"
grep -q "rank 1 (.*): failing after 1 batches" "$T/e.out" || { cat "$T/e.out"; fail "no message naming the rank"; }
[ ! -e "$T/e.probes" ] || fail "failed job left an output file"
# a single-process checkpoint (shard 0's probes) is continued under MPI
cp "$T/p0.probes" "$T/r.probes.partial"
run 2 "$BIN/svo_bake" "$T/demo.svo" "$T/r.probes" $O >"$T/r.out" 2>&1 || fail "resume under MPI"
grep -q "resuming from" "$T/r.out" || fail "no resume under MPI"
cmp -s "$T/full.probes" "$T/r.probes" || fail "resumed MPI bake differs"
# GPU (lavapipe here): rank r on its host's GPU r mod GPUs
G="--grid 4,3,3 --res 16 --spp 2 --seed 5 -q"
if "$BIN/svo_bake" "$T/demo.svo" "$T/g.probes" $G >/dev/null 2>&1; then
  for n in ${VX_MPI_RANKS:-2 3}; do
    run $n "$BIN/svo_bake" "$T/demo.svo" "$T/g$n.probes" $G >"$T/g$n.out" 2>&1 || { cat "$T/g$n.out"; fail "GPU mpirun -n $n"; }
    cmp -s "$T/g.probes" "$T/g$n.probes" || fail "GPU: mpirun -n $n differs from the single bake"
  done
  # --load models: each rank builds the compact layout from the model reader and places the probes from it
  run 2 "$BIN/svo_bake" "$T/demo.svo" "$T/gm.probes" $G --load models -v >"$T/gm.out" 2>&1 || { cat "$T/gm.out"; fail "GPU mpirun -n 2 --load models"; }
  grep -q "load models: the layout, the placement and the device" "$T/gm.out" || { cat "$T/gm.out"; fail "--load models under mpirun: not over the reader"; }
  cmp -s "$T/g.probes" "$T/gm.probes" || fail "GPU: mpirun -n 2 --load models differs from the single bake"
else
  echo "no Vulkan device: GPU checks skipped"
fi
echo "svo_bake under MPI: all checks passed"
