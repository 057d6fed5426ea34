#!/bin/sh
# bench/view_bench.sh BIN_DIR SCENE.{vox,svo} [WxH] [FRAMES]: svo_view's median
# frame time (trace + readback + 8-bit conversion + present, under xvfb-run
# when DISPLAY is unset) against svo_render's trace time for the same scene,
# size and device; then view_bench's edit + BVH update for 10k instances.
set -e
bin=$1; scene=$2; size=${3:-640x480}; frames=${4:-30}
tmp=${TMPDIR:-/tmp}/view_bench.$$
mkdir -p "$tmp"
case "$scene" in
  *.svo) svo=$scene ;;
  *) svo=$tmp/scene.svo; "$bin/vox2svo" -q "$scene" "$svo" ;;
esac
run() { if [ -z "$DISPLAY" ]; then xvfb-run -a "$@"; else "$@"; fi; }
run "$bin/svo_view" "$svo" --bench "$frames" --size "$size" --hidden
for i in 1 2 3 4 5; do "$bin/svo_render" "$svo" "$tmp/r.png" --size "$size" | grep '^render'; done
"$bin/view_bench" 10000 9
rm -rf "$tmp"
