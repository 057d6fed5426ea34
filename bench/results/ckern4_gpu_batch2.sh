#!/bin/bash
# ckern4 batch 2 (issue 18, eleventh step): each compact kernel against
# trace.comp in the same process; processes alternate (ABAB, 2 rounds):
# main (bench/out/base/bin, b74da51); x = the branch before the unroll
# (9902dd3: exploration switches, all off); u = the branch with the
# descent's level-3 step unrolled (61cedec: its brick loads and the brick's
# slot issued together); ut4 = u + start-table entries of 4 words (the
# node's slot inlined: VX_CK_TAB4=1); ub2 = u + attr_bits' second word
# loaded without a branch (VX_CK_BITS2=1). Then one process of x with the
# colour left to a second dispatch that is not run (VX_CK_SPLIT=2
# VX_CK_NORESOLVE=1): the walk's dispatch alone of batch 1's split, timed.
G=bench/out/ckern4; B=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; TER=${TER:-1024}; ROUNDS=${ROUNDS:-2}; REPS=${REPS:-30}; TOB=${TOB:-14}
export LD_LIBRARY_PATH=$G:$B
echo "== ckern4 batch 2, $(cat $G/COMMIT 2>/dev/null), $(date -u)"; nproc; cat /proc/loadavg
nvidia-smi --query-gpu=name,clocks.sm,clocks.mem,temperature.gpu --format=csv,noheader 2>/dev/null
T0=$(date +%s); t() { echo $(( $(date +%s) - T0 )); }
SC="$G/eph_monu1.vox $G/eph_menger.vox $G/helmet512.svo --terrain $TER"
echo "=== warm-up t=$(t)"; timeout 4 $B/compact_bench --gpu $SIZE --reps 60 $G/eph_menger.vox > /dev/null 2>&1
run() { # who round bin env...
  who=$1 round=$2 bin=$3; shift 3
  st=""; [ $round = 1 ] && st="--shader-stats"
  echo "=== K$round $who t=$(t) $*"
  env "$@" timeout $TOB $bin $st --gpu $SIZE --reps $REPS $SC > /tmp/ckern4_k_${who}_$round.txt 2>&1
  echo "rc=$? t=$(t)"
  grep -v "^|\|^stats\|^device\|^$" /tmp/ckern4_k_${who}_$round.txt | sort | uniq -c | head -5
  grep "^| .* | \(overview\|close-up\)" /tmp/ckern4_k_${who}_$round.txt | cut -c1-300
  grep "^stats: \(trace compact\|resolve compact\) \[spec 1," /tmp/ckern4_k_${who}_$round.txt | cut -c1-200 | head -8
}
for round in $(seq $ROUNDS); do
  run main $round $B/compact_bench VX_CK=0
  run x $round $G/compact_bench_x VX_CK=0
  run u $round $G/compact_bench_u VX_CK=0
  run ut4 $round $G/compact_bench_u VX_CK_TAB4=1
  run ub2 $round $G/compact_bench_u VX_CK_BITS2=1
done
run s2n 1 $G/compact_bench_x VX_CK_SPLIT=2 VX_CK_NORESOLVE=1
echo "=== summary: compact / trace.comp rays/s, albedo (depth mode), per round"
for who in main x u ut4 ub2 s2n; do
  cat /tmp/ckern4_k_${who}_*.txt | awk -F'|' -v who=$who '$3 ~ /overview|close-up/ { k=$2"|"$3; gsub(/\*/,"",$6); r[k]=r[k]" "$6"("$7")"; if (!(k in o)) { o[k]=++n; key[n]=k } }
    END { for (i=1;i<=n;i++) print who " |" key[i] "|" r[key[i]] }'
done
echo "=== end t=$(t)"
