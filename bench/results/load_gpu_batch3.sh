#!/bin/bash
# issue 18, branch load, batch 3: the frames of a scene loaded model by model (svo_render --load
# models) took 2.8 ms against 0.59 for main's (same image, same layout bytes; batches 1-2), also when
# the reader's models were gathered into a whole scene first (VXEXP_VIA_WHOLE), not from the map's
# madvise, the thread count or the buffers' order. Here the process's memory history:
# VXEXP_READFIRST (the file read whole and freed first), MALLOC_ARENA_MAX=1, VXEXP_NOHUGE (no
# MADV_HUGEPAGE on decoded arrays), VXEXP_DECODE1 (each model decoded on one thread).
set -u
export LD_LIBRARY_PATH=bench/out/load:bench/out/base/bin
B=bench/out/base/bin/svo_render
L=bench/out/load/svo_render
G=bench/out/load/svo_regions
RES=${RES:-8192}
REGION=${REGION:-256}
SIZE=${SIZE:-1920x1080}
T=/tmp/load_gpu
rm -rf $T && mkdir -p $T
TIMEV=""
[ -x /usr/bin/time ] && TIMEV="/usr/bin/time -v"
ms() { date +%s%N; }
run() {
  local lab=$1; shift
  local t0=$(ms)
  "$@" --size $SIZE --mode albedo --layout compact --frames 21 -v > $T/$lab.log 2>&1
  local rc=$?
  local t1=$(ms)
  local rss=$(grep "Maximum resident" $T/$lab.log | awk '{printf "%.1f MiB", $6/1024}')
  echo "-- $lab rc=$rc process $(( (t1 - t0) / 1000000 )) ms, max RSS ${rss:-?}"
  grep -E "^read|^gpu scene|^compact|^frames|^view|error|Error" $T/$lab.log | sed 's/^/   /'
}
echo "== warm-up: sphere 1024 in regions of 64"
$G $T/s1024.svo --res 1024 --region 64 > /dev/null || exit 1
run w_main $TIMEV $B $T/s1024.svo $T/w_main.ppm
echo "== sphere $RES in regions of $REGION"
t0=$(ms)
$G $T/s.svo --res $RES --region $REGION || exit 1
echo "made in $(( ($(ms) - t0) / 1000000 )) ms; $(stat -c %s $T/s.svo) bytes"
run main_1 $TIMEV $B $T/s.svo $T/main_1.ppm
run models_1 $TIMEV $L $T/s.svo $T/models_1.ppm --load models
run models_readfirst env VXEXP_READFIRST=1 $TIMEV $L $T/s.svo $T/models_readfirst.ppm --load models
run models_arena1 env MALLOC_ARENA_MAX=1 $TIMEV $L $T/s.svo $T/models_arena1.ppm --load models
run models_nohuge env VXEXP_NOHUGE=1 $TIMEV $L $T/s.svo $T/models_nohuge.ppm --load models
run models_decode1 env VXEXP_DECODE1=1 $TIMEV $L $T/s.svo $T/models_decode1.ppm --load models
run main_arena1 env MALLOC_ARENA_MAX=1 $TIMEV $B $T/s.svo $T/main_arena1.ppm
run whole_2 $TIMEV $L $T/s.svo $T/whole_2.ppm --load whole
for v in models_1 models_readfirst models_arena1 models_nohuge models_decode1 main_arena1 whole_2; do
  cmp $T/main_1.ppm $T/$v.ppm > /dev/null && echo "cmp main_1 $v: same" || echo "cmp main_1 $v: DIFFERENT"
done
