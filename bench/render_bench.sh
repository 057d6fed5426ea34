#!/bin/sh
# bench/render_bench.sh - the whole tracer table in one run:
#   bench/render_bench.sh [BUILD_DIR] [extra render_bench options]
# Corpus .vox scenes (read directly) plus the generated 1024^3 and 4096^3
# terrains, each from an overview, an oblique and a full-frame close-up view
# at 1920x1080: voxkit's primary rays against the ESVO octree baseline (and
# the dense DDA where the grid fits), primary+shadow, steps, memory.
# VX_EXTRA_SCENES: more scene files (space-separated) traced after the corpus's,
# e.g. scenes that are not in the corpus (eph_monu3.vox: ephtracy/voxel-model
# @8044f9e vox/monument/monu3.vox, issue 21's lavapipe goal).
set -e
here=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$here/build-release}
[ $# -gt 0 ] && shift
corpus=${VX_CORPUS_DIR:-$here/../shared/corpus}
bin=${RENDER_BENCH:-$build/bin/render_bench}
[ -x "$bin" ] || { echo "render_bench: build the render_bench target in $build first" >&2; exit 1; }
files=""
for f in eph_monu1 eph_menger eph_dragon ogt_doom ogt_test_multiple_model_scene; do
  [ -f "$corpus/vox/$f.vox" ] && files="$files $corpus/vox/$f.vox"
done
for f in ${VX_EXTRA_SCENES:-}; do
  [ -f "$f" ] || { echo "render_bench.sh: VX_EXTRA_SCENES: $f: no such file" >&2; exit 1; }
  files="$files $f"
done
exec "$bin" --generate "$@" $files
