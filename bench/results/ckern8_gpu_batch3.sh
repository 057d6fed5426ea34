#!/bin/bash
# ckern8 batch 3 (issue 18): the branch's kept form (trace_compact.comp: in
# the kernels of DEEP 0 the push from level 3 loads the brick, the loop top
# loads only slots of level 3 and above) against main's compact_bench
# (bench/out/base/bin, 46eb6d3), alternating process by process (ABAB...),
# each timing trace.comp (main's, the GPU form) against the compact kernel
# in one process.
G=bench/out/ckern8; B=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; TER=${TER:-1024}; REPS=${REPS:-30}; END=${END:-77}
export LD_LIBRARY_PATH=$PWD/$G:$PWD/$B
T=/tmp/ck8; rm -rf $T; mkdir -p $T
gzip -dc $G/compact_bench.gz > $T/compact_bench && chmod +x $T/compact_bench
O=${OUTDIR:-$T}; mkdir -p $O
echo "== ckern8 batch 3, $(date -u)"; nproc; cat /proc/loadavg
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.mem,temperature.gpu --format=csv,noheader 2>/dev/null
T0=$(date +%s); t() { echo $(( $(date +%s) - T0 )); }
SC="$G/eph_monu1.vox $G/eph_menger.vox $G/helmet512.svo --terrain $TER"
echo "=== warm-up t=$(t)"; timeout 3 $B/compact_bench --gpu $SIZE --reps 60 $G/eph_menger.vox > /dev/null 2>&1
run() { # who round bin [args]
  who=$1 round=$2 bin=$3; shift 3
  tob=$(( END - $(t) )); [ $tob -gt 16 ] && tob=16
  if [ $tob -lt 11 ]; then echo "=== skip $who $round t=$(t)"; return; fi
  st=""; [ $round = 1 ] && st="--shader-stats"
  echo "=== K$round $who t=$(t)"
  timeout $tob $bin $st "$@" --gpu $SIZE --reps $REPS $SC > $O/k_${who}_$round.txt 2>&1
  echo "rc=$? t=$(t)"
  grep -v "^|\|^stats\|^device\|^$" $O/k_${who}_$round.txt | sort | uniq -c | head -5
  grep "^| .* | \(overview\|close-up\)" $O/k_${who}_$round.txt | cut -d'|' -f2-8,10,14 | sed "s/^/$who$round |/"
  [ $round = 1 ] && grep "^stats: trace compact \[spec [13]," $O/k_${who}_$round.txt | sort -u | sed 's/ CS (subgroup 32)//; s/Stack Size=0; Local Memory Size=[0-9]*; //; s/Register Count/R/; s/Binary Size/bin/; s/Shared Memory Size/shm/' | cut -c1-150
}
run main 1 $B/compact_bench
run K 1 $T/compact_bench
run main 2 $B/compact_bench
run K 2 $T/compact_bench
run main 3 $B/compact_bench
run K 3 $T/compact_bench
echo "=== end t=$(t)"
