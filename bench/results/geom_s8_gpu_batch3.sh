#!/bin/bash
# geom batch 3 (issue 18, seventh step): trace_compact.comp against
# trace.comp in one process (compact_bench --gpu), alternating process by
# process: main's binary; the branch with the DICT specialization constant
# (bricks in their blocks: the index word's path compiled out); the batch-2
# binary (the same layout, the path behind a runtime test); the branch with
# the brick dictionary.
G=bench/out/geom; B=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; TER=${TER:-1024}; ROUNDS=${ROUNDS:-2}
export LD_LIBRARY_PATH=$G:$B
ldconfig -p 2>/dev/null | grep -q 'libstdc++.so.6 ' || export LD_LIBRARY_PATH=$LD_LIBRARY_PATH:$G/cxx
echo "== geom batch 3, $(cat $G/COMMIT 2>/dev/null), $(date -u)"; grep -m1 "model name" /proc/cpuinfo; nproc; cat /proc/loadavg
nvidia-smi --query-gpu=name,clocks.sm,clocks.mem,temperature.gpu --format=csv,noheader 2>/dev/null
T0=$(date +%s); t() { echo $(( $(date +%s) - T0 )); }
SC="$G/eph_monu1.vox $G/eph_menger.vox $G/helmet512.svo --terrain $TER"
echo "=== warm-up t=$(t)"; timeout 15 $B/compact_bench --gpu $SIZE --reps 60 $G/eph_menger.vox > /dev/null 2>&1
for round in $(seq $ROUNDS); do
  for who in main spec runtime dict; do
    bin=$G/compact_bench; opt=""
    [ $who = main ] && bin=$B/compact_bench
    [ $who = runtime ] && bin=$G/compact_bench_b2
    [ $who = dict ] && opt="--bricks dict"
    echo "=== K$round $who t=$(t)"
    timeout 30 $bin $opt --shader-stats --gpu $SIZE --reps 30 $SC 2>&1 | tee /tmp/geom_k_${who}_$round.txt | grep "^| .* | \(overview\|close-up\) |\|^stats: .*compact" | sort -u
  done
done
echo "=== summary: compact / trace.comp rays/s, albedo (depth mode), per round"
for who in main spec runtime dict; do
  cat /tmp/geom_k_${who}_*.txt | awk -F'|' -v who=$who '$3 ~ /overview|close-up/ { k=$2"|"$3; gsub(/\*/,"",$6); r[k]=r[k]" "$6"("$7")"; if (!(k in o)) { o[k]=++n; key[n]=k } }
    END { for (i=1;i<=n;i++) print who " |" key[i] "|" r[key[i]] }'
done
echo "=== end t=$(t)"
