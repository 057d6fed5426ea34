#!/bin/sh
# vox2svo under MPI (issue 22): mpirun -n 2 and -n 3 conversions of a mesh
# equal the single-process file byte for byte: the corpus Duck and
# DamagedHelmet (colour textures) when the corpus is there, and always a mesh
# exported from the demo scene (svo_info --to-glb). --res 640 makes 8 regions
# (models), so every rank converts some; -v prints one line per rank. A
# non-mesh input is one usage error; a failing rank 0 (an output folder that
# does not exist) ends the job nonzero with no output. With a GPU voxelizer
# (lavapipe will do), mpirun -n 2 vox2svo --gpu gives the same file.
# Usage: test_vox2svo_mpi.sh BIN_DIR [MPIEXEC]; exits 77 (skipped) without mpirun.
set -u
BIN=$1
MPIRUN=${2:-mpirun}
. "$(dirname "$0")/../common/mpi.sh"
CORPUS=${VX_CORPUS_DIR:-$(dirname "$0")/../../../shared/corpus}/gltf
"$BIN/vox2svo" --write-demo "$T/demo.vox" >/dev/null || fail "write demo"
"$BIN/vox2svo" "$T/demo.vox" "$T/demo.svo" >/dev/null || fail "vox2svo demo"
meshes=""
if "$BIN/svo_info" "$T/demo.svo" --to-glb "$T/demo.glb" >/dev/null 2>&1; then meshes="$T/demo.glb"; fi
for f in julian_Duck.glb khronos_DamagedHelmet.glb; do
  if [ -f "$CORPUS/$f" ]; then meshes="$meshes $CORPUS/$f"; else echo "corpus $f absent: not tested"; fi
done
[ -n "$meshes" ] || { echo "SKIP: no mesh to convert (no corpus, no --to-glb)"; exit 77; }
O="--res 640"
k=0
for m in $meshes; do
  k=$((k + 1))
  "$BIN/vox2svo" "$m" "$T/one$k.svo" $O >"$T/one$k.out" || fail "vox2svo $m"
  models=$(sed -n 's/^  models *\([0-9]*\),.*/\1/p' "$T/one$k.out")
  [ "${models:-0}" -ge 4 ] || { cat "$T/one$k.out"; fail "$m at $O: $models models, expected several regions"; }
  for n in ${VX_MPI_RANKS:-2 3}; do
    run $n "$BIN/vox2svo" "$m" "$T/m$k-$n.svo" $O -v >"$T/m$k-$n.out" 2>&1 || { cat "$T/m$k-$n.out"; fail "mpirun -n $n $m"; }
    cmp -s "$T/one$k.svo" "$T/m$k-$n.svo" || fail "mpirun -n $n: $m differs from one process"
    [ "$(grep -c "^rank [0-9]*: .* regions, .* peak " "$T/m$k-$n.out")" = $n ] || { cat "$T/m$k-$n.out"; fail "-v: not one line per rank"; }
    # every rank converted a share
    grep -q "^rank [0-9]*: 0 regions" "$T/m$k-$n.out" && { cat "$T/m$k-$n.out"; fail "a rank got no region"; }
    grep -q "converted on $n ranks" "$T/m$k-$n.out" || { cat "$T/m$k-$n.out"; fail "no summary line"; }
  done
  echo "ok: $(basename "$m") ($models models) on 2 and 3 ranks"
done
# --gpu under mpirun: each rank voxelizes on the device (here whatever vx_gpu_create
# finds, lavapipe) and builds its share; the file is the one-process CPU file
# (skipped without a device with float64 shaders)
set -- $meshes
if "$BIN/vox2svo" "$1" "$T/probe.svo" --res 16 --gpu -q 2>"$T/probe.err"; then
  run 2 "$BIN/vox2svo" "$1" "$T/g2.svo" $O --gpu -v >"$T/g2.out" 2>&1 || { cat "$T/g2.out"; fail "mpirun -n 2 --gpu $1"; }
  cmp -s "$T/one1.svo" "$T/g2.svo" || fail "mpirun -n 2 --gpu: $1 differs from one process"
  grep -q "^rank [0-9]*: 0 regions" "$T/g2.out" && { cat "$T/g2.out"; fail "--gpu: a rank got no region"; }
  echo "ok: $(basename "$1") on 2 ranks with --gpu"
else
  echo "no GPU voxelizer here ($(head -c 200 "$T/probe.err")): --gpu under mpirun not tested"
fi
# a .vox is not split: one usage error, exit 2, no output
run 2 "$BIN/vox2svo" "$T/demo.vox" "$T/x.svo" >"$T/u.out" 2>&1; st=$?
[ $st -ne 0 ] || fail "a .vox under mpirun must fail"
[ "$(grep -c "under mpirun only glTF meshes" "$T/u.out")" = 1 ] || { cat "$T/u.out"; fail "usage error not printed once"; }
[ ! -e "$T/x.svo" ] || fail "usage error left an output"
# rank 0 cannot write: the job ends nonzero, naming the rank, nothing left behind
set -- $meshes
run 2 "$BIN/vox2svo" "$1" "$T/no/such/dir/bad.svo" $O >"$T/bad.out" 2>&1
[ $? -ne 0 ] || fail "a failed write must fail the job"
grep -q "rank 0 (.*): .*ending the job" "$T/bad.out" || { cat "$T/bad.out"; fail "no message naming the rank"; }
[ ! -e "$T/no" ] || fail "failed job left a folder"
echo "OK: mpirun vox2svo equals one process"
