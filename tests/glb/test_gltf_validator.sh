#!/bin/sh
# ctest test_gltf_validator: svo_info --to-glb output checked by the Khronos
# glTF validator (the npm package gltf-validator, run by gltf_validate.js):
# no errors, warnings or infos (an unused mesh was one); an export with
# lights among them. Skipped (exit 77) when node or the package is
# absent; the package is found through NODE_PATH, VX_NODE_PATH (CMake) or
# npm's global root:  npm install --prefix DIR gltf-validator, then
# NODE_PATH=DIR/node_modules ctest -R gltf_validator  (nothing is vendored).
# Usage: test_gltf_validator.sh BIN_DIR CORPUS_DIR WORK_DIR [NODE_PATH]
set -eu
BIN=$1 CORPUS=${VX_CORPUS_DIR:-$2} WORK=$3 EXTRA=${4:-}
command -v node >/dev/null 2>&1 || { echo "skip: node is not installed"; exit 77; }
HERE=$(cd "$(dirname "$0")" && pwd)
GLOBAL=$(npm root -g 2>/dev/null || true)
NODE_PATH=${NODE_PATH:+$NODE_PATH:}${EXTRA:+$EXTRA:}$GLOBAL
export NODE_PATH
node -e 'require("gltf-validator")' 2>/dev/null || {
  echo "skip: the npm package gltf-validator is not installed (npm install --prefix DIR gltf-validator; NODE_PATH=DIR/node_modules)"
  exit 77
}
rm -rf "$WORK"
mkdir -p "$WORK"
cd "$WORK"
"$BIN/vox2svo" -q --write-demo demo.vox
"$BIN/vox2svo" -q demo.vox demo.svo --keep-hidden
"$BIN/svo_info" -q demo.svo --to-glb demo.glb
"$BIN/svo_info" -q demo.svo --to-glb demo-all.glb --all
# lights: tests/glb/lights.gltf's five (KHR_lights_punctual, voxkit's records in extras)
"$BIN/vox2svo" -q "$HERE/lights.gltf" lights.svo --res 8
"$BIN/svo_info" -q lights.svo --to-glb lights.glb
set -- demo.glb demo-all.glb lights.glb
for spec in vox/ogt_test_multiple_model_scene.vox: gltf/julian_Duck.glb:--res=64 vdb/mjurczyk_sphere.vdb:; do
  rel=${spec%%:*} opt=$(echo "${spec#*:}" | tr = ' ')
  if [ ! -f "$CORPUS/$rel" ]; then echo "skip: $CORPUS/$rel not found"; continue; fi
  name=$(basename "$rel" | tr . _)
  # shellcheck disable=SC2086
  "$BIN/vox2svo" -q "$CORPUS/$rel" "$name.svo" $opt
  "$BIN/svo_info" -q "$name.svo" --to-glb "$name.glb"
  set -- "$@" "$name.glb"
done
node "$HERE/gltf_validate.js" "$@"
