#!/bin/sh
# vox2svo --gpu (issue 12): a mesh voxelized on the GPU gives the CPU path's
# file byte for byte (the corpus Duck and DamagedHelmet when the corpus is
# there, always a mesh exported from the demo scene), with and without
# --normals, and with --solid (the GPU's surface filled by the CPU); -v
# prints the GPU stages; --gpu with a non-mesh input and --device without
# --gpu are usage errors (exit 2).
# Usage: test_vox2svo_gpu.sh BIN_DIR; exits 77 (skipped) without a Vulkan
# device with float64 shaders.
set -u
BIN=$1
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
CORPUS=${VX_CORPUS_DIR:-$(dirname "$0")/../../../shared/corpus}/gltf
"$BIN/vox2svo" --write-demo "$T/demo.vox" >/dev/null || fail "write demo"
"$BIN/vox2svo" "$T/demo.vox" "$T/demo.svo" >/dev/null || fail "vox2svo demo"
meshes=""
if "$BIN/svo_info" "$T/demo.svo" --to-glb "$T/demo.glb" >/dev/null 2>&1; then meshes="$T/demo.glb"; fi
for f in julian_Duck.glb khronos_DamagedHelmet.glb; do
  if [ -f "$CORPUS/$f" ]; then meshes="$meshes $CORPUS/$f"; else echo "corpus $f absent: not tested"; fi
done
[ -n "$meshes" ] || { echo "SKIP: no mesh to convert (no corpus, no --to-glb)"; exit 77; }
first=$(echo $meshes | cut -d' ' -f1)
if ! "$BIN/vox2svo" "$first" "$T/probe.svo" --res 16 --gpu -q 2>"$T/probe.err"; then
  if grep -q -e "no Vulkan" -e "shaderFloat64" -e "no suitable" "$T/probe.err"; then
    echo "SKIP: $(cat "$T/probe.err")"; exit 77
  fi
  cat "$T/probe.err"; fail "vox2svo --gpu on $first"
fi
k=0
for m in $meshes; do
  k=$((k + 1))
  for opt in "--res 96" "--res 160 --normals" "--res 80 --solid"; do
    "$BIN/vox2svo" "$m" "$T/cpu$k.svo" $opt -q || fail "vox2svo $m $opt"
    "$BIN/vox2svo" "$m" "$T/gpu$k.svo" $opt --gpu -v >"$T/gpu$k.out" 2>&1 || { cat "$T/gpu$k.out"; fail "vox2svo --gpu $m $opt"; }
    cmp -s "$T/cpu$k.svo" "$T/gpu$k.svo" || fail "--gpu $opt: $m differs from the CPU path's file"
    grep -q "GPU voxelizer: bin .* sort .* cells" "$T/gpu$k.out" || { cat "$T/gpu$k.out"; fail "-v: no GPU stage line"; }
  done
  echo "ok: $(basename "$m"): --gpu gives the CPU file"
done
usage() {
  "$BIN/vox2svo" "$@" >"$T/u.out" 2>&1
  rc=$?
  [ $rc = 2 ] || { cat "$T/u.out"; fail "vox2svo $*: exit $rc, expected 2"; }
}
usage "$T/demo.vox" "$T/x.svo" --gpu
grep -q "meshes only" "$T/u.out" || fail "--gpu with .vox: no reason given"
usage "$first" "$T/x.svo" --device 0
[ ! -e "$T/x.svo" ] || fail "a usage error wrote the output"
echo "ok: usage errors"
