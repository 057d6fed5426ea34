#!/bin/bash
# ckern3 batch 2 (issue 18, tenth step): whole binaries, each compact kernel
# against trace.comp in the same process, process by process ABAB:
# main (bench/out/base/bin, e034838); f1 = main + every push writes its stack
# entry (no hh) + the level tests on the scale (batch 1's variant 5);
# f2 = f1 + parent/nd/lvl_off declared before the root-leaf test (batch 1's
# exploration binary had it: +2% on the deep scenes' albedo?). Then one
# process of the exploration binary: variants 0, 5, 13 = 5 + a brick's
# level-2 descriptor from a byte per slot made at upload (every load), 21 =
# 5 + the same at level-2 loads only.
G=bench/out/ckern3; B=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; TER=${TER:-1024}; ROUNDS=${ROUNDS:-2}; REPS=${REPS:-30}; TO=${TO:-30}; TOB=${TOB:-16}
VARS=${VARS:-0,5,13,21}
export LD_LIBRARY_PATH=$G:$B
echo "== ckern3 batch 2, $(cat $G/COMMIT 2>/dev/null), $(date -u)"; nproc; cat /proc/loadavg
nvidia-smi --query-gpu=name,clocks.sm,clocks.mem,temperature.gpu --format=csv,noheader 2>/dev/null
T0=$(date +%s); t() { echo $(( $(date +%s) - T0 )); }
SC="$G/eph_monu1.vox $G/eph_menger.vox $G/helmet512.svo --terrain $TER"
echo "=== warm-up t=$(t)"; timeout 4 $B/compact_bench --gpu $SIZE --reps 60 $G/eph_menger.vox > /dev/null 2>&1
run() { # who round bin opt to
  st=""; [ $2 = 1 ] && st="--shader-stats"
  echo "=== K$2 $1 t=$(t)"
  timeout $5 $3 $st $4 --gpu $SIZE --reps $REPS $SC > /tmp/ckern3_k_$1_$2.txt 2>&1
  echo "rc=$? t=$(t)"
  grep -v "^|\|^stats\|^device\|^$" /tmp/ckern3_k_$1_$2.txt | sort | uniq -c | head -5
  grep "^| .* | \(overview\|close-up\)\|stats: trace compact \[spec [13],1,\|stats: trace \[spec [13],1," /tmp/ckern3_k_$1_$2.txt | cut -c1-300
}
for round in $(seq $ROUNDS); do
  run main $round $B/compact_bench "" $TOB
  run f1 $round $G/compact_bench_f1 "" $TOB
  run f2 $round $G/compact_bench_f2 "" $TOB
done
run x 1 $G/compact_bench_x "--variants $VARS" $TO
echo "=== summary: compact / trace.comp rays/s, albedo (depth mode), per round"
for who in main f1 f2 x; do
  cat /tmp/ckern3_k_${who}_*.txt | awk -F'|' -v who=$who '$3 ~ /overview|close-up/ { k=$2"|"$3; gsub(/\*/,"",$6); r[k]=r[k]" "$6"("$7")"; if (!(k in o)) { o[k]=++n; key[n]=k } }
    END { for (i=1;i<=n;i++) print who " |" key[i] "|" r[key[i]] }'
done
echo "=== end t=$(t)"
