#!/bin/bash
# ckern8 batch 1 (issue 18): the compact kernel against trace.comp, which
# takes the descriptors' GPU form by default since 46eb6d3. Processes
# alternate main's compact_bench (bench/out/base/bin, 46eb6d3: the ratios'
# new denominator; once with VX_GPU_NODE_FORM=file, the old one) and the
# branch's exploration binary (B: --variants, trace_compact.comp's CK8
# constant: 1 the walk's descriptors in the GPU form, 2 a pop to level 2
# keeps the brick, 4 the brick's load in the push from level 3), each timing
# trace.comp against the compact kernels in the same process.
G=bench/out/ckern8; B=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; TER=${TER:-1024}; REPS=${REPS:-30}; END=${END:-96}
export LD_LIBRARY_PATH=$PWD/$G:$PWD/$B
T=/tmp/ck8; rm -rf $T; mkdir -p $T
gzip -dc $G/compact_bench.gz > $T/compact_bench && chmod +x $T/compact_bench
O=${OUTDIR:-$T}; mkdir -p $O
echo "== ckern8 batch 1, $(date -u)"; nproc; cat /proc/loadavg
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.mem,temperature.gpu --format=csv,noheader 2>/dev/null
T0=$(date +%s); t() { echo $(( $(date +%s) - T0 )); }
SC="$G/eph_monu1.vox $G/eph_menger.vox $G/helmet512.svo --terrain $TER"
echo "=== warm-up t=$(t)"; timeout 3 $B/compact_bench --gpu $SIZE --reps 60 $G/eph_menger.vox > /dev/null 2>&1
run() { # who round need_s bin [args]
  who=$1 round=$2 need=$3 bin=$4; shift 4
  tob=$(( END - $(t) )); [ $tob -gt $(( need + 8 )) ] && tob=$(( need + 8 ))
  if [ $tob -lt $need ]; then echo "=== skip $who $round t=$(t)"; return; fi
  st=""; [ $round = 1 ] && st="--shader-stats"
  echo "=== K$round $who t=$(t)"
  timeout $tob $bin $st "$@" --gpu $SIZE --reps $REPS $SC > $O/k_${who}_$round.txt 2>&1
  echo "rc=$? t=$(t)"
  grep -v "^|\|^stats\|^device\|^$" $O/k_${who}_$round.txt | sort | uniq -c | head -5
  grep "^| .* | \(overview\|close-up\)" $O/k_${who}_$round.txt | cut -d'|' -f2-8,10,14 | sed "s/^/$who$round |/"
  [ $round = 1 ] && grep "^stats: trace compact \[spec [13]," $O/k_${who}_$round.txt | sort -u | sed 's/ CS (subgroup 32)//; s/Stack Size=0; Local Memory Size=[0-9]*; //' | cut -c1-150
}
run main 1 9 $B/compact_bench
run B 1 22 $T/compact_bench --variants 1,2,3,7
VX_GPU_NODE_FORM=file run mainF 1 9 $B/compact_bench
run main 2 9 $B/compact_bench
run B 2 22 $T/compact_bench --variants 1,2,3,7
echo "=== end t=$(t)"
