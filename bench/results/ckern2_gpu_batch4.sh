#!/bin/bash
# ckern2 batch 4 (issue 18, ninth step): whole binaries, processes
# alternating (ABAB), one compact kernel each: main = bench/out/base/bin;
# f5 = the branch (f4: the node load's brick decode before the level
# choice) + desc 0 marks an unloaded node in every mode; f6 = f4 + the
# sentinel in the depth kernel only (albedo keeps the flag).
G=bench/out/ckern2; B=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; TER=${TER:-1024}; ROUNDS=${ROUNDS:-2}; REPS=${REPS:-30}; TOB=${TOB:-15}; TMAX=${TMAX:-72}
export LD_LIBRARY_PATH=$G:$B
echo "== ckern2 batch 4, $(cat $G/COMMIT 2>/dev/null), $(date -u)"; grep -m1 "model name" /proc/cpuinfo; nproc; cat /proc/loadavg
nvidia-smi --query-gpu=name,clocks.sm,clocks.mem,temperature.gpu --format=csv,noheader 2>/dev/null
T0=$(date +%s); t() { echo $(( $(date +%s) - T0 )); }
SC="$G/eph_monu1.vox $G/eph_menger.vox $G/helmet512.svo --terrain $TER"
echo "=== warm-up t=$(t)"; timeout 4 $B/compact_bench --gpu $SIZE --reps 60 $G/eph_menger.vox > /dev/null 2>&1
run() { # who round
  local who=$1 round=$2 bin st=""
  [ $(t) -gt $TMAX ] && { echo "=== K$round $who skipped t=$(t)"; return; }
  case $who in main) bin=$B/compact_bench;; *) bin=$G/compact_bench_$who;; esac
  [ $round = 1 ] && [ $who != main ] && st="--shader-stats"
  echo "=== K$round $who t=$(t)"
  timeout $TOB $bin $st --gpu $SIZE --reps $REPS $SC > /tmp/ckern2_k_${who}_$round.txt 2>&1
  echo "rc=$? t=$(t)"
  grep -v "^|\|^stats\|^device\|^$" /tmp/ckern2_k_${who}_$round.txt | sort | uniq -c | head -5
  grep "^| .* | \(overview\|close-up\)\|stats: trace compact \[spec [13],1,0,0,0,0,0\|stats: trace \[spec [13],1,0,0,0" /tmp/ckern2_k_${who}_$round.txt | cut -c1-300
}
for round in $(seq $ROUNDS); do
  for who in main f5 f6; do run $who $round; done
done
echo "=== summary: compact / trace.comp rays/s, albedo (depth mode), per round"
for who in main f5 f6; do
  cat /tmp/ckern2_k_${who}_*.txt 2>/dev/null | awk -F'|' -v who=$who '$3 ~ /overview|close-up/ { k=$2"|"$3; gsub(/\*/,"",$6); r[k]=r[k]" "$6"("$7")"; if (!(k in o)) { o[k]=++n; key[n]=k } }
    END { for (i=1;i<=n;i++) print who " |" key[i] "|" r[key[i]] }'
done
echo "=== end t=$(t)"
