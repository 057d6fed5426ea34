#!/bin/bash
# ckern batch 1 (issue 18, eighth step): trace_compact.comp variants against
# trace.comp in one process (compact_bench --variants: the kernel's VARIANT
# constant, exploration only), main's compact_bench (base) alternating
# process by process. VARIANT bits: 1 subgroup-shared descent to level 3,
# 2 no descent (diagnostic, colours wrong), 4 no decode (diagnostic), 8 the
# start table, 16 (with 8) the table a level lower, 32 one-extraction decode.
G=bench/out/ckern; B=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; TER=${TER:-1024}; ROUNDS=${ROUNDS:-2}; REPS=${REPS:-30}; TO=${TO:-32}
VARS=${VARS:-0,1,2,4,8,24,40,56}
export LD_LIBRARY_PATH=$G:$B
echo "== ckern batch 1, $(cat $G/COMMIT 2>/dev/null), $(date -u)"; grep -m1 "model name" /proc/cpuinfo; nproc; cat /proc/loadavg
nvidia-smi --query-gpu=name,clocks.sm,clocks.mem,temperature.gpu --format=csv,noheader 2>/dev/null
T0=$(date +%s); t() { echo $(( $(date +%s) - T0 )); }
SC="$G/eph_monu1.vox $G/eph_menger.vox $G/helmet512.svo --terrain $TER"
echo "=== warm-up t=$(t)"; timeout 15 $B/compact_bench --gpu $SIZE --reps 60 $G/eph_menger.vox > /dev/null 2>&1
for round in $(seq $ROUNDS); do
  for who in branch main; do
    bin=$G/compact_bench; opt="--variants $VARS"
    [ $who = main ] && bin=$B/compact_bench && opt=""
    st=""; [ $round = 1 ] && st="--shader-stats"
    echo "=== K$round $who t=$(t)"
    timeout $TO $bin $opt $st --gpu $SIZE --reps $REPS $SC > /tmp/ckern_k_${who}_$round.txt 2>&1
    echo "rc=$? t=$(t)"
    grep "^| .* | \(overview\|close-up\)\|stats\|compact\]" /tmp/ckern_k_${who}_$round.txt | grep -v "^| scene" | cut -c1-400
  done
done
echo "=== summary: compact / trace.comp rays/s, albedo (depth mode), per round"
for who in main branch; do
  cat /tmp/ckern_k_${who}_*.txt | awk -F'|' -v who=$who '$3 ~ /overview|close-up/ { k=$2"|"$3; gsub(/\*/,"",$6); r[k]=r[k]" "$6"("$7")"; if (!(k in o)) { o[k]=++n; key[n]=k } }
    END { for (i=1;i<=n;i++) print who " |" key[i] "|" r[key[i]] }'
done
echo "=== end t=$(t)"
