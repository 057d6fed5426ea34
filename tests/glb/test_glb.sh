#!/bin/sh
# tests/glb/test_glb.sh BIN_DIR GLB_CHECK CORPUS_DIR WORK_DIR - svo_info
# --to-glb read back by tinygltf (glb_check): the demo scene (hidden layer:
# default and --all), corpus .vox scenes and a voxelized glTF, each face of
# the voxel surface covered once and no interior faces; a glTF file's lights
# through vox2svo, --to-glb (glb_check checks the light nodes) and vox2svo
# again; vx_voxmesh's self-test on random sets.
set -u
BIN=$1 CHECK=$2 CORPUS=${VX_CORPUS_DIR:-$3} T=$4
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
# glTF -> vox2svo -> --to-glb (checked) -> vox2svo lists the same lights
cat >"$T/lights.gltf" <<'GLTF'
{"asset":{"version":"2.0"},
 "buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAQAAAAAAAAAAAAAAAAAAAgEAAAAAA"}],
 "bufferViews":[{"buffer":0,"byteLength":36}],
 "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[4,4,0]}],
 "meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],
 "extensionsUsed":["KHR_lights_punctual"],
 "extensions":{"KHR_lights_punctual":{"lights":[
  {"type":"directional","color":[1,0.9,0.8],"intensity":3},
  {"type":"point","color":[0.2,0.4,1],"intensity":50,"range":20},
  {"type":"spot","intensity":100,"spot":{"innerConeAngle":0.2,"outerConeAngle":0.6}},
  {"type":"point","intensity":7.85,"extras":{"voxkit_light":{"type":"sphere","radiance":40,"radius":0.25}}},
  {"type":"spot","intensity":10,"spot":{"outerConeAngle":1.5707963267948966},
   "extras":{"voxkit_light":{"type":"rect","radiance":10,"size":[2,0.5]}}}]}},
 "nodes":[{"mesh":0},
  {"rotation":[-0.3826834,0,0,0.9238795],"extensions":{"KHR_lights_punctual":{"light":0}}},
  {"translation":[0.5,2,0.25],"extensions":{"KHR_lights_punctual":{"light":1}}},
  {"translation":[1,3,-2],"rotation":[0.2,0.1,0.3,0.927],"extensions":{"KHR_lights_punctual":{"light":2}}},
  {"translation":[2,4,-1],"extensions":{"KHR_lights_punctual":{"light":3}}},
  {"translation":[0,5,-3],"rotation":[-0.7071068,0,0,0.7071068],"extensions":{"KHR_lights_punctual":{"light":4}}}],
 "scenes":[{"nodes":[0,1,2,3,4,5]}],"scene":0}
GLTF
run "lights to svo" "$BIN/vox2svo" -q "$T/lights.gltf" "$T/lights.svo" --res 8
run "lights to glb" "$BIN/svo_info" "$T/lights.svo" --to-glb "$T/lights.glb"
run "lights glb" "$CHECK" "$T/lights.svo" "$T/lights.glb"
"$BIN/svo_info" "$T/lights.svo" --to-glb "$T/lights.glb" >"$T/lights.out" 2>&1
if grep -q "^lights       5 written (KHR_lights_punctual), 2 approximated" "$T/lights.out" &&
  grep -q "^  light 3    sphere light as a point light" "$T/lights.out" &&
  grep -q "^  light 4    rect light as a spot" "$T/lights.out"; then
  echo "ok   --to-glb counts 5 lights, the sphere and the rect approximated"
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
