#!/bin/bash
# lean3 batch 2 (issue 18): which part of the lean walk costs the compact albedo kernel (batch 1: the whole lean walk
# 0.827-0.974 of trace.comp against main's 0.868-0.967, DEEP 1 albedo kernels 40 -> 32 registers with 16-32 bytes
# more local memory; the depth mode 0.89-0.93 against 0.86-0.93). M = main's compact_bench (527d0fd), X = the branch
# with trace_compact.comp's exploration constant LV from VX_LEAN3 (1 scale_exp2 carried as main's, 2 the ray-end test
# kept as main's, 4 no pix_i; 0 = the whole lean walk, 3 = pix_i alone). Every compact kernel timed against
# trace.comp in its process; the last column: albedo pixels that differ from trace.comp's without hits (lean kernels).
# Then the compact G-buffer (trace_common.glsl LEAN with COMPACT): passes_bench --quick --layout compact, main, branch.
# SIZE, REPS, END, SC: smaller runs for a check on lavapipe.
D=$PWD; T=/tmp/${NAME:-lean3}; rm -rf $T; mkdir -p $T
for f in $D/*.gz; do gzip -dc $f > $T/$(basename $f .gz); done; chmod +x $T/*
cp $D/helmet512.svo $D/eph_monu1.vox $D/eph_menger.vox $T/
cd $T
END=${END:-98}
echo "== lean3 batch 2, $(date -u)"; nproc; cat /proc/loadavg
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.mem,temperature.gpu --format=csv,noheader 2>/dev/null
T0=$(date +%s); t() { echo $(( $(date +%s) - T0 )); }
echo "=== warm-up t=$(t)"; timeout 4 $T/compact_bench_main --gpu ${SIZE:-1920x1080} --reps 60 eph_menger.vox > /dev/null 2>&1
SC=${SC:-"eph_monu1.vox eph_menger.vox helmet512.svo --terrain 1024"}
run() { # who need_s max_s bin args...
  who=$1 need=$2 max=$3 bin=$4; shift 4
  tob=$(( END - 24 - $(t) )); [ $tob -gt $max ] && tob=$max
  if [ $tob -lt $need ]; then echo "=== skip $who t=$(t)"; return; fi
  echo "=== $who t=$(t) ${VX_LEAN3:+VX_LEAN3=$VX_LEAN3}"
  timeout $tob $bin "$@" > $T/k_${who}.txt 2>&1
  echo "rc=$? t=$(t)"
  grep -v "^|\|^stats\|^device\|^$" $T/k_${who}.txt | sort | uniq -c | head -5
  grep "^| .* | \(overview\|close-up\)" $T/k_${who}.txt | cut -d'|' -f2-11,14 | sed "s/^/$who |/"
  grep "^stats: trace" $T/k_${who}.txt | grep -v misses | sort -u | sed 's/ CS (subgroup 32)//; s/Register Count/R/; s/Binary Size/bin/; s/Shared Memory Size/shm/; s/Local Memory Size=6871947/lmem=/; s/Stack Size/stk/' | cut -c1-150
}
M=$T/compact_bench_main; X=$T/compact_bench_x
G="--gpu ${SIZE:-1920x1080} --reps ${REPS:-30}"
VX_LEAN3=1 run X1 9 18 $X --shader-stats $G $SC
VX_LEAN3=2 run X2 9 18 $X --shader-stats $G $SC
VX_LEAN3=3 run X3 9 12 $X $G $SC
run M 9 12 $M $G $SC
for who in main branch; do
  l=$(( END - $(t) )); [ $l -gt 11 ] && l=11; [ $l -gt 3 ] || { echo "=== skip passes $who"; continue; }
  bin=$T/passes_bench; [ $who = main ] && bin=$T/passes_bench_main
  echo "=== passes $who t=$(t)"; timeout $l $bin --layout compact --quick --warmup 0.2 --runs 10 --size ${SIZE:-1920x1080} eph_monu1.vox eph_menger.vox > $T/p_$who.txt 2>&1
  echo "rc=$? t=$(t)"; grep "^##\|^| " $T/p_$who.txt | head -24
done
echo "=== end t=$(t)"
