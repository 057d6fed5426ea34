#!/bin/bash
# ckern batch 2 (issue 18, eighth step): trace_compact.comp variants against
# trace.comp in one process (compact_bench --variants: the kernel's VARIANT
# constant, exploration only), main's compact_bench alternating process by
# process; then the passes (passes_bench) on the compact layout with the
# start table and without (VX_CK_NOTABLE), and the plain layout.
# VARIANT bits: 8 the start table, 16 (with 8) the table a level lower,
# 64 the level-3 bricks before summed by the subgroup (4 blocks a warp at
# most, then the loop), 128 (with 64) every block, 256 the node load's brick
# decode behind a branch.
G=bench/out/ckern; B=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; TER=${TER:-1024}; ROUNDS=${ROUNDS:-2}; REPS=${REPS:-30}; TO=${TO:-40}; PTO=${PTO:-20}
VARS=${VARS:-0,8,24,88,216,280,344}
export LD_LIBRARY_PATH=$G:$B
echo "== ckern batch 2, $(cat $G/COMMIT 2>/dev/null), $(date -u)"; grep -m1 "model name" /proc/cpuinfo; nproc; cat /proc/loadavg
nvidia-smi --query-gpu=name,clocks.sm,clocks.mem,temperature.gpu --format=csv,noheader 2>/dev/null
T0=$(date +%s); t() { echo $(( $(date +%s) - T0 )); }
SC="$G/eph_monu1.vox $G/eph_menger.vox $G/helmet512.svo --terrain $TER"
echo "=== warm-up t=$(t)"; timeout 4 $B/compact_bench --gpu $SIZE --reps 60 $G/eph_menger.vox > /dev/null 2>&1
for round in $(seq $ROUNDS); do
  for who in branch main; do
    bin=$G/compact_bench; opt="--variants $VARS"
    [ $who = main ] && bin=$B/compact_bench && opt=""
    echo "=== K$round $who t=$(t)"
    timeout $TO $bin $opt --gpu $SIZE --reps $REPS $SC > /tmp/ckern_k_${who}_$round.txt 2>&1
    echo "rc=$? t=$(t)"
    grep "^| .* | \(overview\|close-up\)" /tmp/ckern_k_${who}_$round.txt | cut -c1-400
  done
done
echo "=== summary: compact / trace.comp rays/s, albedo (depth mode), per round"
for who in main branch; do
  cat /tmp/ckern_k_${who}_*.txt | awk -F'|' -v who=$who '$3 ~ /overview|close-up/ { k=$2"|"$3; gsub(/\*/,"",$6); r[k]=r[k]" "$6"("$7")"; if (!(k in o)) { o[k]=++n; key[n]=k } }
    END { for (i=1;i<=n;i++) print who " |" key[i] "|" r[key[i]] }'
done
PS="$G/eph_monu1.vox $G/helmet512.svo"
for who in compact_table compact_notable plain; do
  opt="--layout compact"; [ $who = plain ] && opt=""
  echo "=== P $who t=$(t)"
  if [ $who = compact_notable ]; then VX_CK_NOTABLE=1 timeout $PTO $G/passes_bench $opt --runs 10 --size $SIZE $PS > /tmp/ckern_p_$who.txt 2>&1
  else timeout $PTO $G/passes_bench $opt --runs 10 --size $SIZE $PS > /tmp/ckern_p_$who.txt 2>&1; fi
  echo "rc=$? t=$(t)"
  grep "^## \|^| single\|^| gbuffer |\|^| gbuffer,direct,ao,aa,tonemap |" /tmp/ckern_p_$who.txt
done
echo "=== end t=$(t)"
