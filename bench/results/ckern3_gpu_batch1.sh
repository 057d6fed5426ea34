#!/bin/bash
# ckern3 batch 1 (issue 18, tenth step). One process of the branch's
# compact_bench times the compact kernel's EXPLORE variants (VARIANT
# constant of trace_compact.comp, bench/results/ckern3_explore_variants.patch
# at 5d090ed) against trace.comp in the same process; main's compact_bench
# (bench/out/base/bin, e034838) alternates with it process by process.
# Variants: 0 main's code, 1 the push always writes its stack entry (no hh),
# 2 the colour's attribute index at the hit from the walk's path (levels
# K..4 loaded together, the brick from the walk), 4 the walk's level tests
# on the scale (no add a step); sums: 3 = 1+2, 5 = 1+4, 6 = 2+4, 7 all.
# xT: the same binary with VX_CK_TABMUL=64 (start tables two levels deeper:
# what the descent below K still costs), variants 0 and 2.
G=bench/out/ckern3; B=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; TER=${TER:-1024}; ROUNDS=${ROUNDS:-2}; REPS=${REPS:-30}; TO=${TO:-60}; TOB=${TOB:-20}
VARS=${VARS:-0,1,2,3,4,5,6,7}
export LD_LIBRARY_PATH=$G:$B
echo "== ckern3 batch 1, $(cat $G/COMMIT 2>/dev/null), $(date -u)"; grep -m1 "model name" /proc/cpuinfo; nproc; cat /proc/loadavg
nvidia-smi --query-gpu=name,clocks.sm,clocks.mem,temperature.gpu --format=csv,noheader 2>/dev/null
T0=$(date +%s); t() { echo $(( $(date +%s) - T0 )); }
SC="$G/eph_monu1.vox $G/eph_menger.vox $G/helmet512.svo --terrain $TER"
echo "=== warm-up t=$(t)"; timeout 4 $B/compact_bench --gpu $SIZE --reps 60 $G/eph_menger.vox > /dev/null 2>&1
for round in $(seq $ROUNDS); do
  for who in main x xT; do
    env=""
    if [ $who = main ]; then bin=$B/compact_bench; opt=""; to=$TOB
    elif [ $who = x ]; then bin=$G/compact_bench_x; opt="--variants $VARS"; to=$TO
    else bin=$G/compact_bench_x; opt="--variants 0,2"; to=$TO; env="VX_CK_TABMUL=64"; fi
    st=""; [ $round = 1 ] && [ $who != xT ] && st="--shader-stats"
    echo "=== K$round $who t=$(t)"
    env $env timeout $to $bin $st $opt --gpu $SIZE --reps $REPS $SC > /tmp/ckern3_k_${who}_$round.txt 2>&1
    echo "rc=$? t=$(t)"
    grep -v "^|\|^stats\|^device\|^$" /tmp/ckern3_k_${who}_$round.txt | sort | uniq -c | head -5
    grep "^| .* | \(overview\|close-up\)\|stats: trace compact \[spec [13],1,\|stats: trace \[spec [13],1," /tmp/ckern3_k_${who}_$round.txt | cut -c1-300
  done
done
echo "=== summary: compact / trace.comp rays/s, albedo (depth mode), per round"
for who in main x xT; do
  cat /tmp/ckern3_k_${who}_*.txt | awk -F'|' -v who=$who '$3 ~ /overview|close-up/ { k=$2"|"$3; gsub(/\*/,"",$6); r[k]=r[k]" "$6"("$7")"; if (!(k in o)) { o[k]=++n; key[n]=k } }
    END { for (i=1;i<=n;i++) print who " |" key[i] "|" r[key[i]] }'
done
echo "=== end t=$(t)"
