#!/bin/bash
# issue 18, branch load2, batch 2. Batch 1 found: the models path's slow frames (2.8 ms against 0.6) come
# from the device left idle for the seconds of the build after it was made: the compact layout built
# before the device (VX_LATE_DEVICE) gave 0.595 ms, and --load whole with the device idle 3 s
# (VX_IDLE_AFTER_DEVICE=3) gave the slow 2.84 ms. Memory types, the frame's buffers: the same.
# Here: (1) the SM clock meanwhile (nvidia-smi, every 50 ms, the samples of each process in order);
# (2) the idle time it takes (1, 2, 3 s) and whether the kernel back to back for a while before the
# timed frames (VX_WARMUP_S) brings the speed back, on the sphere 2048 (its build is short: no idle);
# (3) the fix: --load models now builds before making the device (the default order; VX_EARLY_DEVICE=1
# the old one), main's binary and the branch's process by process on the sphere 8192 in 3,944 regions,
# --layout compact and the default AUTO (which asks a first device for its memory, then closes it).
set -u
export LD_LIBRARY_PATH=bench/out/base/bin
B=bench/out/base/bin/svo_render
L=bench/out/load2/svo_render
G=bench/out/base/bin/svo_regions
T=/tmp/load2
rm -rf $T && mkdir -p $T
SIZE=${SIZE:-1920x1080}
S2RES=${S2RES:-2048}
BIGRES=${BIGRES:-8192}
BIGREG=${BIGREG:-256}
nvidia-smi --query-gpu=clocks.sm,clocks.max.sm,pstate --format=csv,noheader 2>&1 | head -2
nvidia-smi --query-gpu=timestamp,clocks.sm,pstate,utilization.gpu --format=csv,noheader -lms 50 > $T/smi.csv 2>&1 &
SMI=$!
stamp() { date "+%Y/%m/%d %H:%M:%S.%N" | cut -c1-23; }
run() {
  local lab=$1 n=$2; shift 2
  local s0=$(stamp)
  echo "-- $lab"
  timeout 30 "$@" --size $SIZE --mode albedo --frames $n -v > $T/$lab.log 2> $T/$lab.err
  local rc=$?
  local s1=$(stamp)
  grep -E "^gpu scene|^layout|^note|^warm|^frame|error|Error" $T/$lab.log | cut -c1-160 | sed 's/^/   /'
  grep -iE "error|fail" $T/$lab.err | head -3 | sed 's/^/   ERR /'
  # the SM clock's samples during the process, runs of equal values as value*count
  awk -F', ' -v a="$s0" -v b="$s1" '$1 >= a && $1 <= b { v = $2 " " $3; if (v == last) n++; else { if (n) printf "%s*%d ", last, n; last = v; n = 1 } }
    END { if (n) printf "%s*%d", last, n; printf "\n" }' $T/smi.csv | sed "s/ MHz//g; s/^/   rc=$rc sm clock, pstate: /" | cut -c1-400
}
echo "== sphere $S2RES in regions of 64: idle after the device, warm-up"
$G $T/s2.svo --res $S2RES --region 64 > /dev/null || exit 1
run s2_whole 21 $L $T/s2.svo $T/s2_whole.ppm --layout compact --load whole
run s2_idle1 21 env VX_IDLE_AFTER_DEVICE=1 $L $T/s2.svo $T/s2_idle1.ppm --layout compact --load whole
run s2_idle2 21 env VX_IDLE_AFTER_DEVICE=2 $L $T/s2.svo $T/s2_idle2.ppm --layout compact --load whole
run s2_idle3 21 env VX_IDLE_AFTER_DEVICE=3 $L $T/s2.svo $T/s2_idle3.ppm --layout compact --load whole
run s2_idle3_warm02 21 env VX_IDLE_AFTER_DEVICE=3 VX_WARMUP_S=0.2 $L $T/s2.svo $T/s2_idle3_warm02.ppm --layout compact --load whole
run s2_idle3_warm1 21 env VX_IDLE_AFTER_DEVICE=3 VX_WARMUP_S=1 $L $T/s2.svo $T/s2_idle3_warm1.ppm --layout compact --load whole
echo "== sphere $BIGRES in regions of $BIGREG: main's binary (read whole) and the branch's --load models"
$G $T/s.svo --res $BIGRES --region $BIGREG > /dev/null || exit 1
run main_1 21 $B $T/s.svo $T/main_1.ppm --layout compact
run models_1 21 $L $T/s.svo $T/models_1.ppm --layout compact --load models
run main_2 21 $B $T/s.svo $T/main_2.ppm --layout compact
run models_2 21 $L $T/s.svo $T/models_2.ppm --layout compact --load models
run main_auto 21 $B $T/s.svo $T/main_auto.ppm
run models_auto 21 $L $T/s.svo $T/models_auto.ppm --load models
run models_early 21 env VX_EARLY_DEVICE=1 $L $T/s.svo $T/models_early.ppm --layout compact --load models
kill $SMI 2>/dev/null
for v in s2_idle1 s2_idle2 s2_idle3 s2_idle3_warm02 s2_idle3_warm1; do
  cmp $T/s2_whole.ppm $T/$v.ppm > /dev/null 2>&1 && echo "cmp s2_whole $v: same" || echo "cmp s2_whole $v: DIFFERENT"
done
for v in models_1 main_2 models_2 main_auto models_auto models_early; do
  cmp $T/main_1.ppm $T/$v.ppm > /dev/null 2>&1 && echo "cmp main_1 $v: same" || echo "cmp main_1 $v: DIFFERENT"
done
echo "== smi samples: $(wc -l < $T/smi.csv); first: $(head -1 $T/smi.csv)"
