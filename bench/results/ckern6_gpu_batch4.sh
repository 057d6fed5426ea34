#!/bin/bash
# ckern6 batch 4 (issue 18, thirteenth step): whole binaries, each compact
# kernel against trace.comp in the same process; processes alternate
# (main, C, main, C): main (bench/out/base/bin, 0b39e32), C = the branch:
# batch 3's A (the single instance's instance and model records from the
# frame block, no t where nothing reads it, a model of one value) with the
# depth kernels of DEEP 0 walking with the model record from the buffer
# (batch 3's B there).
G=bench/out/ckern6; B=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; TER=${TER:-1024}; REPS=${REPS:-30}; TOB=${TOB:-15}; END=${END:-57}
export LD_LIBRARY_PATH=$PWD/$G:$PWD/$B
T=/tmp/ck6; rm -rf $T; mkdir -p $T
for v in C; do gzip -dc $G/$v/compact_bench.gz > $T/compact_bench_$v && chmod +x $T/compact_bench_$v; done
O=$T
echo "== ckern6 batch 4, $(date -u)"; nproc; cat /proc/loadavg
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.mem,temperature.gpu --format=csv,noheader 2>/dev/null
T0=$(date +%s); t() { echo $(( $(date +%s) - T0 )); }
SC="$G/eph_monu1.vox $G/eph_menger.vox $G/helmet512.svo --terrain $TER"
echo "=== warm-up t=$(t)"; timeout 3 $B/compact_bench --gpu $SIZE --reps 60 $G/eph_menger.vox > /dev/null 2>&1
run() { # who round bin
  who=$1 round=$2 bin=$3
  tob=$(( END - $(t) )); [ $tob -gt $TOB ] && tob=$TOB
  if [ $tob -lt 9 ]; then echo "=== skip $who $round t=$(t)"; return; fi
  st=""; [ $round = 1 ] && st="--shader-stats"
  echo "=== K$round $who t=$(t)"
  timeout $tob $bin $st --gpu $SIZE --reps $REPS $SC > $O/k_${who}_$round.txt 2>&1
  echo "rc=$? t=$(t)"
  grep -v "^|\|^stats\|^device\|^$" $O/k_${who}_$round.txt | sort | uniq -c | head -5
  grep "^| .* | \(overview\|close-up\)" $O/k_${who}_$round.txt | cut -d'|' -f2-8,10,14 | sed "s/^/$who$round |/"
  [ $round = 1 ] && grep "^stats: trace compact \[spec [13]," $O/k_${who}_$round.txt | sort -u | sed 's/ CS (subgroup 32)//; s/Stack Size=0; Local Memory Size=[0-9]*; //' | cut -c1-150
}
run main 1 $B/compact_bench
run C 1 $T/compact_bench_C
run main 2 $B/compact_bench
run C 2 $T/compact_bench_C
echo "=== end t=$(t)"
