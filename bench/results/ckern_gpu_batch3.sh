#!/bin/bash
# ckern batch 3 (issue 18, eighth step): the branch's final forms against
# main, processes alternating: f1 = the start table (the colour's descent
# from the node of the cell's level-K cube); f2 = f1 + at level 3 the
# bricks before counted from the nearer end of the block (the node's cells
# from its rank and its previous slot's); main = bench/out/base/bin. Then
# the passes on the compact layout: f2 against the batch-2 binary with its
# tables off (VX_CK_NOTABLE=1: main's descent), and the plain layout.
G=bench/out/ckern; B=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; TER=${TER:-1024}; ROUNDS=${ROUNDS:-2}; REPS=${REPS:-30}; TO=${TO:-25}; PTO=${PTO:-15}
export LD_LIBRARY_PATH=$G:$B
echo "== ckern batch 3, $(cat $G/COMMIT 2>/dev/null), $(date -u)"; grep -m1 "model name" /proc/cpuinfo; nproc; cat /proc/loadavg
nvidia-smi --query-gpu=name,clocks.sm,clocks.mem,temperature.gpu --format=csv,noheader 2>/dev/null
T0=$(date +%s); t() { echo $(( $(date +%s) - T0 )); }
SC="$G/eph_monu1.vox $G/eph_menger.vox $G/helmet512.svo --terrain $TER"
echo "=== warm-up t=$(t)"; timeout 4 $B/compact_bench --gpu $SIZE --reps 60 $G/eph_menger.vox > /dev/null 2>&1
for round in $(seq $ROUNDS); do
  for who in main f1 f2; do
    bin=$G/compact_bench_$who; [ $who = main ] && bin=$B/compact_bench
    st=""; [ $round = 1 ] && [ $who != main ] && st="--shader-stats"
    echo "=== K$round $who t=$(t)"
    timeout $TO $bin $st --gpu $SIZE --reps $REPS $SC > /tmp/ckern_k_${who}_$round.txt 2>&1
    echo "rc=$? t=$(t)"
    grep "^| .* | \(overview\|close-up\)\|stats: trace compact \[spec [13],1,0,0,0" /tmp/ckern_k_${who}_$round.txt | cut -c1-300
  done
done
echo "=== summary: compact / trace.comp rays/s, albedo (depth mode), per round"
for who in main f1 f2; do
  cat /tmp/ckern_k_${who}_*.txt | awk -F'|' -v who=$who '$3 ~ /overview|close-up/ { k=$2"|"$3; gsub(/\*/,"",$6); r[k]=r[k]" "$6"("$7")"; if (!(k in o)) { o[k]=++n; key[n]=k } }
    END { for (i=1;i<=n;i++) print who " |" key[i] "|" r[key[i]] }'
done
PS="$G/eph_monu1.vox $G/helmet512.svo"
for run in notable_1 f2_1 notable_2 f2_2 plain_1; do
  bin=$G/passes_bench_f2; opt="--layout compact"; env=""
  case $run in notable_*) bin=$G/passes_bench_x; env="VX_CK_NOTABLE=1";; plain_*) opt="";; esac
  echo "=== P $run t=$(t)"
  env $env timeout $PTO $bin $opt --runs 10 --size $SIZE $PS > /tmp/ckern_p_$run.txt 2>&1
  echo "rc=$? t=$(t)"
  grep "^## \|^| single\|^| gbuffer |\|^| gbuffer,direct,ao,aa,tonemap |" /tmp/ckern_p_$run.txt
done
echo "=== end t=$(t)"
