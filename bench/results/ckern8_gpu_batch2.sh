#!/bin/bash
# ckern8 batch 2 (issue 18): the branch's exploration binary (B:
# --variants, trace_compact.comp's CK8 constant: 2 a pop to level 2 keeps
# the brick (its descriptor from the slot in registers, no load), 4 the
# brick's load in the push from level 3 (the loop top loads only slots of
# level 3 and above),
# 1 the GPU form turned at the load, 0x100 starts below the root from one
# push), each timing trace.comp (GPU form, main's) against the compact
# kernels in one process; two processes split the scenes (monu1 and the
# helmet, menger and the terrain); then main's compact_bench (46eb6d3).
G=bench/out/ckern8; B=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; TER=${TER:-1024}; REPS=${REPS:-30}; END=${END:-97}
export LD_LIBRARY_PATH=$PWD/$G:$PWD/$B
T=/tmp/ck8; rm -rf $T; mkdir -p $T
gzip -dc $G/compact_bench.gz > $T/compact_bench && chmod +x $T/compact_bench
O=${OUTDIR:-$T}; mkdir -p $O
echo "== ckern8 batch 2, $(date -u)"; nproc; cat /proc/loadavg
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.mem,temperature.gpu --format=csv,noheader 2>/dev/null
T0=$(date +%s); t() { echo $(( $(date +%s) - T0 )); }
echo "=== warm-up t=$(t)"; timeout 3 $B/compact_bench --gpu $SIZE --reps 60 $G/eph_menger.vox > /dev/null 2>&1
run() { # who round need_s bin [args]
  who=$1 round=$2 need=$3 bin=$4; shift 4
  tob=$(( END - $(t) )); [ $tob -gt $(( need + 8 )) ] && tob=$(( need + 8 ))
  if [ $tob -lt $need ]; then echo "=== skip $who $round t=$(t)"; return; fi
  st=""; [ $round = 1 ] && st="--shader-stats"
  echo "=== K$round $who t=$(t)"
  timeout $tob $bin $st --gpu $SIZE --reps $REPS "$@" > $O/k_${who}_$round.txt 2>&1
  echo "rc=$? t=$(t)"
  grep -v "^|\|^stats\|^device\|^$" $O/k_${who}_$round.txt | sort | uniq -c | head -5
  grep "^| .* | \(overview\|close-up\)" $O/k_${who}_$round.txt | cut -d'|' -f2-8,10,14 | sed "s/^/$who$round |/"
  [ $round = 1 ] && grep "^stats: trace compact \[spec [13]," $O/k_${who}_$round.txt | sort -u | sed 's/ CS (subgroup 32)//; s/Stack Size=0; Local Memory Size=[0-9]*; //; s/Register Count/R/; s/Binary Size/bin/; s/Shared Memory Size/shm/' | cut -c1-150
}
V=4,6,7,0x106
run Ba 1 32 $T/compact_bench --variants $V $G/eph_monu1.vox $G/helmet512.svo
run Bb 1 32 $T/compact_bench --variants $V $G/eph_menger.vox --terrain $TER
run main 2 10 $B/compact_bench $G/eph_monu1.vox $G/eph_menger.vox $G/helmet512.svo --terrain $TER
echo "=== end t=$(t)"
