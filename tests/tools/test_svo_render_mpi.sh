#!/bin/sh
# svo_render under MPI (issue 22): mpirun -n 2 and -n 3 path-traced images
# equal the single-process image byte for byte (EXR and PNG; the GPU device,
# lavapipe here, and the CPU renderer); a usage error is printed once; a rank
# that cannot render ends the job nonzero and leaves no output file.
# Usage: test_svo_render_mpi.sh BIN_DIR [MPIEXEC]; exits 77 (skipped) without mpirun.
set -u
BIN=$1
MPIRUN=${2:-mpirun}
. "$(dirname "$0")/../common/mpi.sh"
"$BIN/vox2svo" --write-demo "$T/demo.vox" >/dev/null || fail "write demo"
"$BIN/vox2svo" "$T/demo.vox" "$T/demo.svo" >/dev/null || fail "vox2svo"
# 27 rows: 2 ranks get 14 and 13 rows, every other one; 3 ranks 9 each
O="--mode pathtrace --size 40x27 --spp 3 --seed 9"
gpu=1
"$BIN/svo_render" "$T/demo.svo" "$T/one.exr" $O >"$T/one.out" 2>&1 || { cat "$T/one.out"; echo "no Vulkan device: GPU cases skipped"; gpu=0; }
"$BIN/svo_render" "$T/demo.svo" "$T/cpu.exr" $O --cpu --threads 1 >/dev/null || fail "single CPU render"
"$BIN/svo_render" "$T/demo.svo" "$T/cpu.png" $O --cpu --threads 1 >/dev/null || fail "single CPU render (PNG)"
for n in ${VX_MPI_RANKS:-2 3}; do
  if [ $gpu = 1 ]; then
    t0=$(date +%s.%N)
    run $n "$BIN/svo_render" "$T/demo.svo" "$T/g$n.exr" $O -v >"$T/g$n.out" 2>&1 || { cat "$T/g$n.out"; fail "mpirun -n $n"; }
    t1=$(date +%s.%N)
    check_timeline "$T/g$n.out" $n "$t0" "$t1" || { cat "$T/g$n.out"; fail "mpirun -n $n: the ranks' timelines"; }
    cmp -s "$T/one.exr" "$T/g$n.exr" || fail "mpirun -n $n (GPU) differs from one process"
    grep -q "on $n ranks" "$T/g$n.out" || { cat "$T/g$n.out"; fail "mpirun -n $n: no summary line"; }
    [ "$(grep -c "^rank [0-9]*: .* rows, set-up" "$T/g$n.out")" = $n ] || { cat "$T/g$n.out"; fail "-v: not one line per rank"; }
  fi
  run $n "$BIN/svo_render" "$T/demo.svo" "$T/c$n.exr" $O --cpu --threads 1 >"$T/c$n.out" 2>&1 || { cat "$T/c$n.out"; fail "mpirun -n $n --cpu"; }
  cmp -s "$T/cpu.exr" "$T/c$n.exr" || fail "mpirun -n $n (CPU) differs from one process"
  run $n "$BIN/svo_render" "$T/demo.svo" "$T/c$n.png" $O --cpu --threads 1 >/dev/null 2>&1 || fail "mpirun -n $n --cpu (PNG)"
  cmp -s "$T/cpu.png" "$T/c$n.png" || fail "mpirun -n $n (CPU, PNG) differs from one process"
done
# the GPU's sample blocks (probe_gpu.c: 64 samples, at most 16 a round): 1,100
# spp is 18 blocks in 2 rounds, the last block partial; each rank traces only
# its own rows (compacted), so the ranks' rounds differ from one process's
if [ $gpu = 1 ]; then
  B="--mode pathtrace --size 24x20 --spp 1100 --seed 4"
  "$BIN/svo_render" "$T/demo.svo" "$T/b1.pfm" $B >/dev/null 2>&1 || fail "single render, 1,100 spp"
  for n in ${VX_MPI_RANKS:-2 3}; do
    run $n "$BIN/svo_render" "$T/demo.svo" "$T/b$n.pfm" $B >"$T/b$n.out" 2>&1 || { cat "$T/b$n.out"; fail "mpirun -n $n, 1,100 spp"; }
    cmp -s "$T/b1.pfm" "$T/b$n.pfm" || fail "mpirun -n $n, 1,100 spp (GPU) differs from one process"
  done
fi
# not every pixel is black or equal: the comparison compares something
[ "$(od -An -v -tu1 "$T/cpu.png" | tr -s ' ' '\n' | sort -u | wc -l)" -gt 20 ] || fail "the reference image is flat"
# the colour mode is not spread: one usage error, exit 2
run 2 "$BIN/svo_render" "$T/demo.svo" "$T/x.png" >"$T/u.out" 2>&1; st=$?
[ $st -ne 0 ] || fail "the colour mode under mpirun must fail"
[ "$(grep -c "under mpirun" "$T/u.out")" = 1 ] || { cat "$T/u.out"; fail "usage error not printed once"; }
[ ! -e "$T/x.png" ] || fail "usage error left an output"
# a rank that cannot open its device ends the job: nonzero, no output file
run 2 "$BIN/svo_render" "$T/demo.svo" "$T/bad.exr" $O --device 99 >"$T/bad.out" 2>&1
[ $? -ne 0 ] || fail "a rank without a device must fail the job"
grep -q "rank [01] (.*): .*ending the job" "$T/bad.out" || { cat "$T/bad.out"; fail "no message naming the rank"; }
[ ! -e "$T/bad.exr" ] || fail "failed job left an output file"
ls "$T" | grep -q "^bad.exr" && fail "failed job left a temporary file"
echo "OK: mpirun svo_render equals one process (GPU: $gpu)"
