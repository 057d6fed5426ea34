#!/bin/bash
# issue 18, branch load: the models one at a time into the compact layout (svo_render --load models,
# the branch's default) against main's svo_render (the scene read whole, then the layout built).
# A sphere shell in region models (bench/svo_regions), made here; host peak, load, GPU bytes, frame.
# RES (default 8192), REGION (default 256: a 32^3 grid, 65536^3's model grid), ROUNDS (default 3).
# (bc was missing on the GPU machine: the process times came out empty; svo_render -v gives the rest.)
set -u
export LD_LIBRARY_PATH=bench/out/load:bench/out/base/bin
B=bench/out/base/bin/svo_render
L=bench/out/load/svo_render
G=bench/out/load/svo_regions
RES=${RES:-8192}
REGION=${REGION:-256}
ROUNDS=${ROUNDS:-3}
SIZE=${SIZE:-1920x1080}
T=/tmp/load_gpu
rm -rf $T && mkdir -p $T
TIMEV=""
[ -x /usr/bin/time ] && TIMEV="/usr/bin/time -v"
echo "== machine"
nproc; free -g | head -2
nvidia-smi --query-gpu=name,memory.total,driver_version --format=csv,noheader 2>/dev/null
echo "time -v: ${TIMEV:-absent (peak host memory from svo_render -v: getrusage)}"
run() {
  local lab=$1 bin=$2 scn=$3 img=$4; shift 4
  local t0=$(date +%s.%N)
  $TIMEV $bin $scn $img --size $SIZE --mode albedo --layout compact --frames 11 -v "$@" > $T/$lab.log 2>&1
  local rc=$?
  local t1=$(date +%s.%N)
  local rss=$(grep "Maximum resident" $T/$lab.log | awk '{printf "%.1f MiB", $6/1024}')
  echo "-- $lab rc=$rc process $(echo "$t1 - $t0" | bc) s, max RSS ${rss:-?}"
  grep -E "^read|^gpu scene|^layout|^compact|^frames|^render|error|Error" $T/$lab.log | sed 's/^/   /'
}
echo "== warm-up and images: sphere 1024 in regions of 64"
$G $T/s1024.svo --res 1024 --region 64 || exit 1
run w_main $B $T/s1024.svo $T/w_main.ppm
run w_models $L $T/s1024.svo $T/w_models.ppm
run w_whole $L $T/s1024.svo $T/w_whole.ppm --load whole
cmp $T/w_main.ppm $T/w_models.ppm && echo "cmp main models: same"
cmp $T/w_main.ppm $T/w_whole.ppm && echo "cmp main whole: same"
echo "== sphere $RES in regions of $REGION"
t0=$(date +%s.%N)
$G $T/s.svo --res $RES --region $REGION || exit 1
echo "made in $(echo "$(date +%s.%N) - $t0" | bc) s; $(stat -c %s $T/s.svo) bytes"
nvidia-smi --query-gpu=memory.used --format=csv,noheader,nounits -lms 250 > $T/smi.txt 2>/dev/null &
SMI=$!
for r in $(seq 1 $ROUNDS); do
  run main_$r $B $T/s.svo $T/main_$r.ppm
  run models_$r $L $T/s.svo $T/models_$r.ppm
done
run whole_1 $L $T/s.svo $T/whole_1.ppm --load whole
kill $SMI 2>/dev/null
for r in $(seq 1 $ROUNDS); do cmp $T/main_$r.ppm $T/models_$r.ppm && echo "cmp main_$r models_$r: same"; done
cmp $T/main_1.ppm $T/whole_1.ppm && echo "cmp main_1 whole_1: same"
echo "GPU memory used (nvidia-smi, MiB): max $(sort -n $T/smi.txt | tail -1), samples $(wc -l < $T/smi.txt)"
