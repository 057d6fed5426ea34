#!/bin/bash
# issue 18, branch load, batch 2: why the frames of a scene loaded model by model (svo_render
# --load models) timed 2.1-2.7 ms against 0.6 ms for main's (same image, same layout bytes) in
# batch 1. Sphere shell 8192 in regions of 256 (3,944 models); variants by environment (temporary):
# VXEXP_VIA_WHOLE (the reader's models gathered into a whole scene, then main's create),
# VXEXP_NODROP (no madvise on the map), VXEXP_THREADS=4, VXEXP_EARLY (the GPU scene's buffers made
# before the build, instance boxes the models' whole cubes), and both binaries pinned (taskset -c 0-7).
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
echo "== machine"
nproc; cat /sys/devices/system/node/online 2>/dev/null; ls /sys/devices/system/node/ 2>/dev/null | tr '\n' ' '; echo
grep -m1 "model name" /proc/cpuinfo
cat /sys/kernel/mm/transparent_hugepage/enabled 2>/dev/null; cat /proc/sys/kernel/numa_balancing 2>/dev/null
nvidia-smi --query-gpu=name,memory.total,driver_version,clocks.sm,clocks.max.sm --format=csv,noheader 2>/dev/null

ms() { date +%s%N; }
run() {
  local lab=$1; shift
  local t0=$(ms)
  "$@" --size $SIZE --mode albedo --layout compact --frames 21 -v > $T/$lab.log 2>&1
  local rc=$?
  local t1=$(ms)
  local rss=$(grep "Maximum resident" $T/$lab.log | awk '{printf "%.1f MiB", $6/1024}')
  echo "-- $lab rc=$rc process $(( (t1 - t0) / 1000000 )) ms, max RSS ${rss:-?}"
  grep -E "^read|^gpu scene|^compact|^frames|error|Error" $T/$lab.log | sed 's/^/   /'
}

echo "== warm-up: sphere 1024 in regions of 64"
$G $T/s1024.svo --res 1024 --region 64 > /dev/null || exit 1
run w_main $TIMEV $B $T/s1024.svo $T/w_main.ppm
run w_models $TIMEV $L $T/s1024.svo $T/w_models.ppm
cmp $T/w_main.ppm $T/w_models.ppm && echo "cmp w: same"

echo "== sphere $RES in regions of $REGION"
t0=$(ms)
$G $T/s.svo --res $RES --region $REGION || exit 1
echo "made in $(( ($(ms) - t0) / 1000000 )) ms; $(stat -c %s $T/s.svo) bytes"
run main_1 $TIMEV $B $T/s.svo $T/main_1.ppm
run models_1 $TIMEV $L $T/s.svo $T/models_1.ppm
run models_viawhole env VXEXP_VIA_WHOLE=1 $TIMEV $L $T/s.svo $T/models_viawhole.ppm
run models_nodrop env VXEXP_NODROP=1 $TIMEV $L $T/s.svo $T/models_nodrop.ppm
run models_t4 env VXEXP_THREADS=4 $TIMEV $L $T/s.svo $T/models_t4.ppm
run models_early env VXEXP_EARLY=1 $TIMEV $L $T/s.svo $T/models_early.ppm
run main_pin taskset -c 0-7 $TIMEV $B $T/s.svo $T/main_pin.ppm
run models_pin taskset -c 0-7 $TIMEV $L $T/s.svo $T/models_pin.ppm
run main_2 $TIMEV $B $T/s.svo $T/main_2.ppm
run models_2 $TIMEV $L $T/s.svo $T/models_2.ppm
for v in models_1 models_viawhole models_nodrop models_t4 models_early main_pin models_pin main_2 models_2; do
  cmp $T/main_1.ppm $T/$v.ppm > /dev/null && echo "cmp main_1 $v: same" || echo "cmp main_1 $v: DIFFERENT"
done
