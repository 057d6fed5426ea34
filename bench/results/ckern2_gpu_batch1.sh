#!/bin/bash
# ckern2 batch 1 (issue 18, ninth step): where the compact walk loses per
# step. One process of the branch's compact_bench times the compact kernel's
# EXPLORE variants (VARIANT constant, trace_compact.comp) against trace.comp
# in the same process; main's compact_bench (bench/out/base/bin) alternates
# with it process by process (its compact kernel = the variant 0's code).
# Variants: 1 depth-1 root loaded before the loop, 2 level-2 octant byte
# test (no brick_desc), 4 pop onto level 2 keeps the brick, 8 desc-0
# sentinel, 16 a one-cell hit's cell is its corner, 32 the colour's descent
# without the Morton code, 64 a brick hit hands the colour its brick and
# level-3 node (from the walk's stack), 3 = 1+2, 6 = 2+4, 63, 127 all.
G=bench/out/ckern2; B=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; TER=${TER:-1024}; ROUNDS=${ROUNDS:-2}; REPS=${REPS:-30}; TO=${TO:-70}; TOB=${TOB:-20}
VARS=${VARS:-0,1,2,3,4,6,8,16,32,63,64,127}
export LD_LIBRARY_PATH=$G:$B
echo "== ckern2 batch 1, $(cat $G/COMMIT 2>/dev/null), $(date -u)"; grep -m1 "model name" /proc/cpuinfo; nproc; cat /proc/loadavg
nvidia-smi --query-gpu=name,clocks.sm,clocks.mem,temperature.gpu --format=csv,noheader 2>/dev/null
T0=$(date +%s); t() { echo $(( $(date +%s) - T0 )); }
SC="$G/eph_monu1.vox $G/eph_menger.vox $G/helmet512.svo --terrain $TER"
echo "=== warm-up t=$(t)"; timeout 4 $B/compact_bench --gpu $SIZE --reps 60 $G/eph_menger.vox > /dev/null 2>&1
for round in $(seq $ROUNDS); do
  for who in main x; do
    if [ $who = main ]; then bin=$B/compact_bench; opt=""; to=$TOB; else bin=$G/compact_bench_x; opt="--variants $VARS"; to=$TO; fi
    st=""; [ $round = 1 ] && st="--shader-stats"
    echo "=== K$round $who t=$(t)"
    timeout $to $bin $st $opt --gpu $SIZE --reps $REPS $SC > /tmp/ckern2_k_${who}_$round.txt 2>&1
    echo "rc=$? t=$(t)"
    grep -v "^|\|^stats\|^device\|^$" /tmp/ckern2_k_${who}_$round.txt | sort | uniq -c | head -5
    grep "^| .* | \(overview\|close-up\)\|stats: trace compact \[spec [13],1,0,0,0\|stats: trace \[spec [13],1,0,0,0" /tmp/ckern2_k_${who}_$round.txt | cut -c1-300
  done
done
echo "=== summary: compact / trace.comp rays/s, albedo (depth mode), per round"
for who in main x; do
  cat /tmp/ckern2_k_${who}_*.txt | awk -F'|' -v who=$who '$3 ~ /overview|close-up/ { k=$2"|"$3; gsub(/\*/,"",$6); r[k]=r[k]" "$6"("$7")"; if (!(k in o)) { o[k]=++n; key[n]=k } }
    END { for (i=1;i<=n;i++) print who " |" key[i] "|" r[key[i]] }'
done
echo "=== end t=$(t)"
