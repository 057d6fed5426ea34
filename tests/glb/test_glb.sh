#!/bin/sh
# tests/glb/test_glb.sh BIN_DIR GLB_CHECK CORPUS_DIR WORK_DIR - svo_info
# --to-glb read back by tinygltf (glb_check): the demo scene (hidden layer:
# default and --all), corpus .vox scenes and a voxelized glTF, each face of
# the voxel surface covered once and no interior faces; a glTF file's lights
# through vox2svo, --to-glb (glb_check checks the light nodes) and vox2svo
# again; vx_voxmesh's self-test on random sets.
set -u
BIN=$1 CHECK=$2 CORPUS=${VX_CORPUS_DIR:-$3} T=$4
HERE=$(cd "$(dirname "$0")" && pwd)
rm -rf "$T"
mkdir -p "$T"
fails=0
run() { # name command...
  name=$1
  shift
  if "$@" >"$T/out" 2>&1; then echo "ok   $name: $(tail -n 1 "$T/out")"; else echo "FAIL $name"; cat "$T/out"; fails=$((fails + 1)); fi
}
run "voxmesh self-test" "$CHECK" --self-test
run "write demo" "$BIN/vox2svo" -q --write-demo "$T/demo.vox"
run "convert demo" "$BIN/vox2svo" -q "$T/demo.vox" "$T/demo.svo"
run "demo to glb" "$BIN/svo_info" "$T/demo.svo" --to-glb "$T/demo.glb"
run "demo glb" "$CHECK" "$T/demo.svo" "$T/demo.glb"
# the hidden layer kept in the .svo: written with --all only
run "convert demo --keep-hidden" "$BIN/vox2svo" -q "$T/demo.vox" "$T/demo-h.svo" --keep-hidden
run "demo (hidden kept) to glb" "$BIN/svo_info" -q "$T/demo-h.svo" --to-glb "$T/demo-h.glb"
run "demo (hidden kept) glb" "$CHECK" "$T/demo-h.svo" "$T/demo-h.glb"
run "demo to glb --all" "$BIN/svo_info" -q "$T/demo-h.svo" --to-glb "$T/demo-all.glb" --all
run "demo glb --all" "$CHECK" "$T/demo-h.svo" "$T/demo-all.glb" --all
# lights (KHR_lights_punctual, voxkit's sphere and rect records in extras):
# tests/glb/lights.gltf -> vox2svo -> --to-glb (checked) -> vox2svo lists the same lights
run "lights to svo" "$BIN/vox2svo" -q "$HERE/lights.gltf" "$T/lights.svo" --res 8
run "lights to glb" "$BIN/svo_info" "$T/lights.svo" --to-glb "$T/lights.glb"
run "lights glb" "$CHECK" "$T/lights.svo" "$T/lights.glb"
"$BIN/svo_info" "$T/lights.svo" --to-glb "$T/lights.glb" >"$T/lights.out" 2>&1
if grep -q "^lights       5 written (KHR_lights_punctual), 3 approximated" "$T/lights.out" &&
  grep -q "^  light 0    sun without its angular diameter" "$T/lights.out" &&
  grep -q "^  light 3    sphere light as a point light" "$T/lights.out" &&
  grep -q "^  light 4    rect light as a spot" "$T/lights.out"; then
  echo "ok   --to-glb counts 5 lights, the sun, the sphere and the rect approximated"
else
  echo "FAIL --to-glb's light lines"; cat "$T/lights.out"; fails=$((fails + 1))
fi
run "lights glb to svo" "$BIN/vox2svo" -q "$T/lights.glb" "$T/lights2.svo" --res 8
"$BIN/svo_info" "$T/lights.svo" | grep '^light ' >"$T/lights1.txt"
"$BIN/svo_info" "$T/lights2.svo" | grep '^light ' >"$T/lights2.txt"
if [ "$(wc -l <"$T/lights1.txt")" = 5 ] && cmp -s "$T/lights1.txt" "$T/lights2.txt"; then
  echo "ok   glTF -> svo -> glb -> svo: the same 5 lights"
else
  echo "FAIL the lights did not come back"; diff "$T/lights1.txt" "$T/lights2.txt"; fails=$((fails + 1))
fi
# the checker fails a .glb that does not match (hidden instance missing)
if "$CHECK" "$T/demo-h.svo" "$T/demo-h.glb" --all >/dev/null 2>&1; then
  echo "FAIL glb_check accepts a .glb without the hidden instance"; fails=$((fails + 1))
else
  echo "ok   glb_check rejects a .glb without the hidden instance"
fi
# a failure leaves nothing behind
if "$BIN/svo_info" "$T/demo.svo" --to-glb "$T/no/such/dir/x.glb" >/dev/null 2>&1; then
  echo "FAIL unwritable --to-glb succeeded"; fails=$((fails + 1))
else
  echo "ok   unwritable --to-glb fails"
fi
for f in ogt_test_multiple_model_scene eph_menger eph_chr_knight ogt_doom ogt_test_groups; do
  if [ ! -f "$CORPUS/vox/$f.vox" ]; then echo "skip $f: not in the corpus"; continue; fi
  run "$f to svo" "$BIN/vox2svo" -q "$CORPUS/vox/$f.vox" "$T/$f.svo"
  run "$f to glb" "$BIN/svo_info" "$T/$f.svo" --to-glb "$T/$f.glb"
  run "$f glb" "$CHECK" "$T/$f.svo" "$T/$f.glb"
done
if [ -f "$CORPUS/gltf/julian_Duck.glb" ]; then
  run "Duck to svo" "$BIN/vox2svo" -q "$CORPUS/gltf/julian_Duck.glb" "$T/duck.svo" --res 64
  run "Duck to glb" "$BIN/svo_info" "$T/duck.svo" --to-glb "$T/duck.glb"
  run "Duck glb" "$CHECK" "$T/duck.svo" "$T/duck.glb"
else
  echo "skip Duck: not in the corpus"
fi
echo "$fails failed"
[ "$fails" = 0 ]
