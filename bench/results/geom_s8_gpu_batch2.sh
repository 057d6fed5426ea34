#!/bin/bash
# geom batch 2 (issue 18, seventh step). Kernel: trace_compact.comp against
# trace.comp in one process (compact_bench --gpu), main's binary, the
# branch's (bricks in their blocks, the default) and the branch's with the
# brick dictionary, alternating process by process (ABC ABC); then the
# 16384^3 geometry in both brick forms (the mesh voxelized in the process).
G=bench/out/geom; B=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; TER=${TER:-1024}; RES=${RES:-16384}; ROUNDS=${ROUNDS:-2}
export LD_LIBRARY_PATH=$G:$B
ldconfig -p 2>/dev/null | grep -q 'libstdc++.so.6 ' || export LD_LIBRARY_PATH=$LD_LIBRARY_PATH:$G/cxx
echo "== geom batch 2, $(cat $G/COMMIT 2>/dev/null), $(date -u)"; grep -m1 "model name" /proc/cpuinfo; nproc; cat /proc/loadavg
nvidia-smi --query-gpu=name,clocks.sm,clocks.mem,temperature.gpu --format=csv,noheader 2>/dev/null
T0=$(date +%s); t() { echo $(( $(date +%s) - T0 )); }
SC="$G/eph_monu1.vox $G/eph_menger.vox $G/helmet512.svo --terrain $TER"
echo "=== warm-up t=$(t)"; timeout 15 $B/compact_bench --gpu $SIZE --reps 60 $G/eph_menger.vox > /dev/null 2>&1
for round in $(seq $ROUNDS); do
  for who in main inline dict; do
    bin=$G/compact_bench; opt=""
    [ $who = main ] && bin=$B/compact_bench
    [ $who = dict ] && opt="--bricks dict"
    echo "=== K$round $who t=$(t)"
    timeout 30 $bin $opt --gpu $SIZE --reps 30 $SC 2>&1 | tee /tmp/geom_k_${who}_$round.txt | grep "^| .* | \(overview\|close-up\) |"
  done
done
echo "=== summary: compact / trace.comp rays/s, albedo (depth mode), per round"
for who in main inline dict; do
  cat /tmp/geom_k_${who}_*.txt | awk -F'|' -v who=$who '$3 ~ /overview|close-up/ { k=$2"|"$3; gsub(/\*/,"",$6); r[k]=r[k]" "$6"("$7")"; if (!(k in o)) { o[k]=++n; key[n]=k } }
    END { for (i=1;i<=n;i++) print who " |" key[i] "|" r[key[i]] }'
done
for r in $RES; do
  echo "=== geometry $r, both brick forms t=$(t)"
  /usr/bin/time -f "wall %e s, peak %M KB" timeout $(( 145 - $(t) )) $G/compact_bench --bricks both --levels --geometry --res $r $G/khronos_DamagedHelmet.glb 2>&1
done
echo "=== end t=$(t)"
