#!/bin/bash
# issue 18, branch rdr2, batch 2 (H200): AUTO's brick dictionary from the model reader. The sphere 8192
# in 3,944 regions of 256 (bench/svo_regions), svo_render --layout compact --gpu-budget B between the
# dictionary's layout and the layout in blocks: main's binary (f807bf3) with --load models builds the
# layout in blocks only (over the budget: paged), with --load whole reads the scene and builds both;
# the branch's --load models builds both from two passes over the file, now both before the device is
# made (batch 1: the second pass ran after it, and the idle device's clock fell to 345 MHz for the frames
# of one of two processes: 3.35 ms against 0.68). Process by process (ABAB), two rounds; max RSS, the load,
# the layout, the frames (GPU median), the SM clock during the process, the images compared. Then one
# round under a budget that pages both.
set -u
export LD_LIBRARY_PATH=bench/out/base/bin
B=bench/out/base/bin/svo_render
L=/tmp/rdr2/svo_render
G=bench/out/base/bin/svo_regions
T=/tmp/rdr2
rm -rf $T && mkdir -p $T
gunzip -c bench/out/rdr2/svo_render.gz > $L && chmod +x $L || exit 1
SIZE=${SIZE:-1920x1080}
BUDGET=${BUDGET:-300000000}
SMALL=${SMALL:-150000000}
TIMEV=""
[ -x /usr/bin/time ] && TIMEV="/usr/bin/time -v"
nvidia-smi --query-gpu=timestamp,clocks.sm,pstate,utilization.gpu --format=csv,noheader -lms 50 > $T/smi.csv 2>&1 &
SMI=$!
stamp() { date "+%Y/%m/%d %H:%M:%S.%N" | cut -c1-23; }
ms() { date +%s%N; }
T0=$(ms)
run() {
  local lab=$1 n=$2; shift 2
  local s0=$(stamp) t0=$(ms)
  local left=$(( 92 - (t0 - T0) / 1000000000 ))
  [ $left -gt 25 ] && left=25
  if [ $left -lt 5 ]; then echo "-- $lab: skipped (the batch's time)"; return; fi
  echo "-- $lab"
  timeout $left $TIMEV "$@" --size $SIZE --mode albedo --frames $n -v > $T/$lab.log 2>&1
  local rc=$?
  local s1=$(stamp)
  local rss=$(grep "Maximum resident" $T/$lab.log | awk '{printf "%.1f MiB", $6/1024}')
  echo "   rc=$rc process $(( ($(ms) - t0) / 1000000 )) ms, max RSS ${rss:-?}"
  grep -E "^read|^gpu scene|^layout|^compact|^paging|^note|^warm|^frames|^render|error|Error" $T/$lab.log | cut -c1-230 | sed 's/^/   /'
  awk -F', ' -v a="$s0" -v b="$s1" '$1 >= a && $1 <= b { v = $2 " " $3; if (v == last) n++; else { if (n) printf "%s*%d ", last, n; last = v; n = 1 } }
    END { if (n) printf "%s*%d", last, n; printf "\n" }' $T/smi.csv | sed "s/ MHz//g; s/^/   sm clock, pstate: /" | cut -c1-300
}
echo "== sphere ${RES:-8192} in regions of ${REG:-256}, --gpu-budget $BUDGET"
timeout 40 $G $T/s.svo --res ${RES:-8192} --region ${REG:-256} > /dev/null || exit 1
echo "   made in $(( ($(ms) - T0) / 1000000 )) ms"
for r in 1 2; do
  run main_models_$r 11 $B $T/s.svo $T/main_models_$r.ppm --layout compact --gpu-budget $BUDGET --load models
  run branch_models_$r 11 $L $T/s.svo $T/branch_models_$r.ppm --layout compact --gpu-budget $BUDGET --load models
  run main_whole_$r 11 $B $T/s.svo $T/main_whole_$r.ppm --layout compact --gpu-budget $BUDGET --load whole
done
if [ $(( ($(ms) - T0) / 1000000000 )) -lt 62 ]; then
  echo "== --gpu-budget $SMALL (paged)"
  run main_models_paged 11 $B $T/s.svo $T/main_models_paged.ppm --layout compact --gpu-budget $SMALL --load models
  run branch_models_paged 11 $L $T/s.svo $T/branch_models_paged.ppm --layout compact --gpu-budget $SMALL --load models
fi
kill $SMI 2>/dev/null
for v in main_models_1 branch_models_1 branch_models_2 main_whole_2 main_models_paged branch_models_paged; do
  [ -e $T/$v.ppm ] || continue
  cmp $T/main_whole_1.ppm $T/$v.ppm > /dev/null 2>&1 && echo "cmp main_whole_1 $v: same" || echo "cmp main_whole_1 $v: DIFFERENT"
done
echo "total $(( ($(ms) - T0) / 1000000000 )) s"
