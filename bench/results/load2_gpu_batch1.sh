#!/bin/bash
# issue 18, branch load2, batch 1: why `svo_render --load models` frames take 2.1-2.9 ms on the H200
# against 0.6 ms for `--load whole` (same layout bytes, same image; branch load's batches 1-3).
# Diagnostics in the branch's svo_render (environment variables):
#   VX_GPU_MEMORY_LOG=1  every allocation's memory type, flags, heap (and the CPU/NUMA node allocating)
#   VX_FRAME_TIMES=1     each frame's GPU ms in order;  VX_NUMA_MAPS=1  the driver's mappings' NUMA pages
#   VX_LATE_DEVICE=1     the compact layout built from the reader BEFORE the Vulkan device is created
#   VX_GPU_MAPPED=device the mapped per-frame tables (instances, BVH nodes, frame block) in device-local
#                        host-visible memory (ReBAR) instead of host memory
#   VX_IDLE_AFTER_DEVICE=S  --load whole, but the device idle S seconds before the scene is built
# nvidia-smi samples the SM clock, pstate, utilisation and power every 100 ms meanwhile (smi.csv).
# (The diagnostics were removed after batch 2, except VX_GPU_MEMORY_LOG; VX_LATE_DEVICE's order is
# --load models' own since.)
set -u
export LD_LIBRARY_PATH=bench/out/base/bin
B=bench/out/base/bin/svo_render
L=bench/out/load2/svo_render
G=bench/out/base/bin/svo_regions
O=${OUTDIR:-/tmp/load2_out}
mkdir -p $O
T=/tmp/load2
rm -rf $T && mkdir -p $T
SIZE=${SIZE:-1920x1080}
S2RES=${S2RES:-2048}
BIGRES=${BIGRES:-8192}
BIGREG=${BIGREG:-256}
echo "== machine"
nproc; ls /sys/devices/system/node/ 2>/dev/null | grep node | tr '\n' ' '; echo
nvidia-smi --query-gpu=name,driver_version,pstate,clocks.sm,clocks.max.sm,clocks.applications.graphics,persistence_mode,compute_mode --format=csv 2>&1 | head -3
nvidia-smi --query-gpu=timestamp,clocks.sm,clocks.mem,pstate,utilization.gpu,power.draw,clocks_event_reasons.active \
  --format=csv,noheader -lms 100 > $O/smi.csv 2>&1 &
SMI=$!
ms() { date +%s%N; }
run() {
  local lab=$1 n=$2; shift 2
  local t0=$(ms)
  echo "-- $lab start $(date +%T.%N | cut -c1-12)"
  timeout 30 "$@" --size $SIZE --mode albedo --layout compact --frames $n -v > $T/$lab.log 2> $T/$lab.err
  local rc=$?
  echo "   rc=$rc process $(( ($(ms) - t0) / 1000000 )) ms, end $(date +%T.%N | cut -c1-12)"
  grep -E "^gpu scene|^compact|^frame|^view|error|Error" $T/$lab.log | sed 's/^/   /'
  grep -iE "error|fail" $T/$lab.err | head -3 | sed 's/^/   ERR /'
  cp $T/$lab.log $T/$lab.err $O/ 2>/dev/null
}
D="env VX_GPU_MEMORY_LOG=1 VX_FRAME_TIMES=1 VX_NUMA_MAPS=1"
echo "== sphere $S2RES in regions of 64"
$G $T/s2.svo --res $S2RES --region 64 > /dev/null || exit 1
run s2_main_1 21 $B $T/s2.svo $T/s2_main_1.ppm
run s2_models_1 21 $D $L $T/s2.svo $T/s2_models_1.ppm --load models
run s2_main_2 21 $B $T/s2.svo $T/s2_main_2.ppm
run s2_models_2 21 $D $L $T/s2.svo $T/s2_models_2.ppm --load models
echo "== sphere $BIGRES in regions of $BIGREG"
t0=$(ms)
$G $T/s.svo --res $BIGRES --region $BIGREG > /dev/null || exit 1
echo "made in $(( ($(ms) - t0) / 1000000 )) ms"
run main_1 41 $B $T/s.svo $T/main_1.ppm
run models_1 41 $D $L $T/s.svo $T/models_1.ppm --load models
run main_2 21 $B $T/s.svo $T/main_2.ppm
run late_1 21 $D VX_LATE_DEVICE=1 $L $T/s.svo $T/late_1.ppm --load models
run whole_1 21 $D $L $T/s.svo $T/whole_1.ppm --load whole
run mapped_models 21 $D VX_GPU_MAPPED=device $L $T/s.svo $T/mapped_models.ppm --load models
run main_3 21 $B $T/s.svo $T/main_3.ppm
run idle3_whole 21 $D VX_IDLE_AFTER_DEVICE=3 $L $T/s.svo $T/idle3_whole.ppm --load whole
run late_2 21 $D VX_LATE_DEVICE=1 $L $T/s.svo $T/late_2.ppm --load models
run models_2 21 $L $T/s.svo $T/models_2.ppm --load models
kill $SMI 2>/dev/null
for v in s2_models_1 s2_main_2 s2_models_2; do
  cmp $T/s2_main_1.ppm $T/$v.ppm > /dev/null 2>&1 && echo "cmp s2_main_1 $v: same" || echo "cmp s2_main_1 $v: DIFFERENT"
done
for v in models_1 main_2 late_1 whole_1 mapped_models main_3 idle3_whole late_2 models_2; do
  cmp $T/main_1.ppm $T/$v.ppm > /dev/null 2>&1 && echo "cmp main_1 $v: same" || echo "cmp main_1 $v: DIFFERENT"
done
echo "== memory types and the scene's allocations (models_1, whole_1; first of each label)"
for v in models_1 whole_1 mapped_models; do
  echo "-- $v"; grep "gpu.memory" $T/$v.err | awk '!seen[$0]++' | grep -v "'staging'" | cut -c1-220 | head -40
  grep -c "'staging'" $T/$v.err | sed 's/^/   staging allocations: /'
  grep "numa_maps" $T/$v.log | head -5 | cut -c1-200
done
echo "== smi samples: $(wc -l < $O/smi.csv)"
