#!/bin/bash
# issue 18, branch load2, batch 3: the branch's svo_render as committed (--load models the default:
# the compact layout built from the reader before the device is made; --warm-up 0.25 s before timed
# frames) against main's binary (the scene read whole), process by process, on the sphere 8192 in
# 3,944 regions of 256 (--layout compact, three rounds; the default AUTO layout, plain here, one round)
# and the sphere 2048 in regions of 64; the SM clock meanwhile (nvidia-smi every 50 ms), max RSS.
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
TIMEV=""
[ -x /usr/bin/time ] && TIMEV="/usr/bin/time -v"
nvidia-smi --query-gpu=timestamp,clocks.sm,pstate,utilization.gpu --format=csv,noheader -lms 50 > $T/smi.csv 2>&1 &
SMI=$!
stamp() { date "+%Y/%m/%d %H:%M:%S.%N" | cut -c1-23; }
ms() { date +%s%N; }
run() {
  local lab=$1 n=$2; shift 2
  local s0=$(stamp) t0=$(ms)
  echo "-- $lab"
  timeout 30 $TIMEV "$@" --size $SIZE --mode albedo --frames $n -v > $T/$lab.log 2>&1
  local rc=$?
  local s1=$(stamp)
  local rss=$(grep "Maximum resident" $T/$lab.log | awk '{printf "%.1f MiB", $6/1024}')
  echo "   rc=$rc process $(( ($(ms) - t0) / 1000000 )) ms, max RSS ${rss:-?}"
  grep -E "^read|^gpu scene|^layout|^note|^warm|^frames|error|Error" $T/$lab.log | cut -c1-170 | sed 's/^/   /'
  awk -F', ' -v a="$s0" -v b="$s1" '$1 >= a && $1 <= b { v = $2 " " $3; if (v == last) n++; else { if (n) printf "%s*%d ", last, n; last = v; n = 1 } }
    END { if (n) printf "%s*%d", last, n; printf "\n" }' $T/smi.csv | sed "s/ MHz//g; s/^/   sm clock, pstate: /" | cut -c1-300
}
echo "== sphere $S2RES in regions of 64"
$G $T/s2.svo --res $S2RES --region 64 > /dev/null || exit 1
run s2_main_1 21 $B $T/s2.svo $T/s2_main_1.ppm --layout compact
run s2_branch_1 21 $L $T/s2.svo $T/s2_branch_1.ppm --layout compact
run s2_main_2 21 $B $T/s2.svo $T/s2_main_2.ppm --layout compact
run s2_branch_2 21 $L $T/s2.svo $T/s2_branch_2.ppm --layout compact
echo "== sphere $BIGRES in regions of $BIGREG"
$G $T/s.svo --res $BIGRES --region $BIGREG > /dev/null || exit 1
for r in 1 2 3; do
  run main_$r 21 $B $T/s.svo $T/main_$r.ppm --layout compact
  run branch_$r 21 $L $T/s.svo $T/branch_$r.ppm --layout compact
done
run main_auto 21 $B $T/s.svo $T/main_auto.ppm
run branch_auto 21 $L $T/s.svo $T/branch_auto.ppm
kill $SMI 2>/dev/null
for v in s2_branch_1 s2_main_2 s2_branch_2; do
  cmp $T/s2_main_1.ppm $T/$v.ppm > /dev/null 2>&1 && echo "cmp s2_main_1 $v: same" || echo "cmp s2_main_1 $v: DIFFERENT"
done
for v in branch_1 main_2 branch_2 main_3 branch_3 main_auto branch_auto; do
  cmp $T/main_1.ppm $T/$v.ppm > /dev/null 2>&1 && echo "cmp main_1 $v: same" || echo "cmp main_1 $v: DIFFERENT"
done
