#!/bin/bash
# ckern2 batch 2 (issue 18, ninth step): the branch's forms against main,
# processes alternating (ABAB): f2 = cell_index without the Morton code +
# a one-cell hit's cell is its corner; f3 = f2 + the depth kernel's desc-0
# sentinel; main = bench/out/base/bin. Then once the EXPLORE binary's
# variants in one process (x, VARIANT constant): 16 one-cell hit, 32 no
# Morton code, 8 sentinel (both modes), 4|128 pop onto level 2 keeps the
# brick's descriptor, 256 node-load decode behind dont_flatten branches,
# 512 the push's level test likewise.
G=bench/out/ckern2; B=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; TER=${TER:-1024}; ROUNDS=${ROUNDS:-2}; REPS=${REPS:-30}; TO=${TO:-45}; TOB=${TOB:-20}
VARS=${VARS:-0,48,56,304,312,560,816,180}
export LD_LIBRARY_PATH=$G:$B
echo "== ckern2 batch 2, $(cat $G/COMMIT 2>/dev/null), $(date -u)"; grep -m1 "model name" /proc/cpuinfo; nproc; cat /proc/loadavg
nvidia-smi --query-gpu=name,clocks.sm,clocks.mem,temperature.gpu --format=csv,noheader 2>/dev/null
T0=$(date +%s); t() { echo $(( $(date +%s) - T0 )); }
SC="$G/eph_monu1.vox $G/eph_menger.vox $G/helmet512.svo --terrain $TER"
echo "=== warm-up t=$(t)"; timeout 4 $B/compact_bench --gpu $SIZE --reps 60 $G/eph_menger.vox > /dev/null 2>&1
run() { # who round
  local who=$1 round=$2 bin opt="" to=$TOB st=""
  case $who in main) bin=$B/compact_bench;; x) bin=$G/compact_bench_x; opt="--variants $VARS"; to=$TO;; *) bin=$G/compact_bench_$who;; esac
  [ $round = 1 ] && [ $who != main ] && st="--shader-stats"
  echo "=== K$round $who t=$(t)"
  timeout $to $bin $st $opt --gpu $SIZE --reps $REPS $SC > /tmp/ckern2_k_${who}_$round.txt 2>&1
  echo "rc=$? t=$(t)"
  grep -v "^|\|^stats\|^device\|^$" /tmp/ckern2_k_${who}_$round.txt | sort | uniq -c | head -5
  grep "^| .* | \(overview\|close-up\)\|stats: trace compact \[spec [13],1,0,0,0,0,0\|stats: trace \[spec [13],1,0,0,0" /tmp/ckern2_k_${who}_$round.txt | cut -c1-300
}
for round in $(seq $ROUNDS); do
  for who in main f2 f3; do run $who $round; done
done
run x 1
echo "=== summary: compact / trace.comp rays/s, albedo (depth mode), per round"
for who in main f2 f3 x; do
  cat /tmp/ckern2_k_${who}_*.txt | awk -F'|' -v who=$who '$3 ~ /overview|close-up/ { k=$2"|"$3; gsub(/\*/,"",$6); r[k]=r[k]" "$6"("$7")"; if (!(k in o)) { o[k]=++n; key[n]=k } }
    END { for (i=1;i<=n;i++) print who " |" key[i] "|" r[key[i]] }'
done
echo "=== end t=$(t)"
