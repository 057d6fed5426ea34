#!/bin/bash
# ckern9 batch 3 (issue 18): the helmet's colour through color_table (the exploration binary
# of batch 2, --variants: 8 the group words loaded with the level-4 and level-3 slots, 0x88
# also the two candidate block headers loaded with the brick), each timed against trace.comp
# (main's) and the kernel without them (v0, main's DEEP 1 kernel) in one process; two
# processes; the helmet's and the terrain's close-ups (the scenes whose tables are of level 4
# or more). Batch 2's X process ran out of its limit before the helmet.
G=bench/out/ckern9; B=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; TER=${TER:-1024}; REPS=${REPS:-30}; END=${END:-57}
export LD_LIBRARY_PATH=$PWD/$G:$PWD/$B
T=/tmp/ck9; rm -rf $T; mkdir -p $T
gzip -dc $G/compact_bench.gz > $T/compact_bench && chmod +x $T/compact_bench
O=${OUTDIR:-$T}; mkdir -p $O
echo "== ckern9 batch 3, $(date -u)"; nproc; cat /proc/loadavg
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.mem,temperature.gpu --format=csv,noheader 2>/dev/null
T0=$(date +%s); t() { echo $(( $(date +%s) - T0 )); }
echo "=== warm-up t=$(t)"; timeout 3 $B/compact_bench --gpu $SIZE --reps 60 $G/eph_menger.vox > /dev/null 2>&1
run() { # who need_s max_s stats bin [args]
  who=$1 need=$2 max=$3 st=$4 bin=$5; shift 5
  tob=$(( END - $(t) )); [ $tob -gt $max ] && tob=$max
  if [ $tob -lt $need ]; then echo "=== skip $who t=$(t)"; return; fi
  echo "=== $who t=$(t)"
  timeout $tob $bin $st --gpu $SIZE --reps $REPS "$@" > $O/k_${who}.txt 2>&1
  echo "rc=$? t=$(t)"
  grep -v "^|\|^stats\|^device\|^$" $O/k_${who}.txt | sort | uniq -c | head -5
  grep "^| .* | \(overview\|close-up\)" $O/k_${who}.txt | cut -d'|' -f2-8,10,14 | sed "s/^/$who |/"
  grep "^stats: trace compact \[spec [13]," $O/k_${who}.txt | sort -u | sed 's/ CS (subgroup 32)//; s/Register Count/R/; s/Binary Size/bin/; s/Shared Memory Size/shm/; s/Local Memory Size=6871947/lmem=/; s/Stack Size/stk/' | cut -c1-170
}
run Xa 10 26 --shader-stats $T/compact_bench --closeups --variants 8,0x88 $G/helmet512.svo --terrain $TER
run Xb 10 26 "" $T/compact_bench --closeups --variants 0x88,8 $G/helmet512.svo --terrain $TER
echo "=== end t=$(t)"
