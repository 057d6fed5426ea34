#!/bin/bash
# ckern6 batch 2 (issue 18, thirteenth step): compact kernel variants against
# trace.comp in the same process; processes alternate (ABAB): main
# (bench/out/base/bin, 0b39e32) and the branch's exploration binary, which
# times every kernel of VX_CK6_LIST (trace_compact.comp built with -DCK6=n)
# against trace.comp in one process. CK6 bits: 1 the depth kernel of DEEP>=1
# without the one-sample constant; 2 the hit's instance 0 where there is no
# BVH; 4 no t where nothing reads it (albedo, one instance); 8 the instance
# record from the frame block (one instance, as trace.comp's); 16 the model's
# CModel from the frame block (one instance, whole layout); 32 a model whose
# cells all hold one value (CModel flag 4): its colour from the record, no
# cell, no t (albedo, one instance). Batch 1 had x2,
# x4, x7, x8, x14 and the diagnostics 256 (the colour a hash of the cell: no
# descent, no decode; then bit 16) and 512 (a constant colour; then bit 32).
G=bench/out/ckern6; B=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; TER=${TER:-1024}; ROUNDS=${ROUNDS:-2}; REPS=${REPS:-30}; TOB=${TOB:-46}; TMAX=${TMAX:-72}
VARS=${VARS:-"x0 x14 x15 x28 x30 x31 x63"}; END=${END:-86}
export LD_LIBRARY_PATH=$PWD/$G:$PWD/$B
T=/tmp/ck6; rm -rf $T; mkdir -p $T; gzip -dc $G/compact_bench.gz > $T/compact_bench && chmod +x $T/compact_bench
X=$T/compact_bench
LIST=""; for v in $VARS; do LIST="$LIST $PWD/$G/$v.spv"; done
O=${OUTDIR:-$T}; mkdir -p $O
echo "== ckern6 batch 2, $(date -u)"; nproc; cat /proc/loadavg
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.mem,temperature.gpu --format=csv,noheader 2>/dev/null
T0=$(date +%s); t() { echo $(( $(date +%s) - T0 )); }
SC="$G/eph_monu1.vox $G/eph_menger.vox $G/helmet512.svo --terrain $TER"
echo "=== warm-up t=$(t)"; timeout 5 $B/compact_bench --gpu $SIZE --reps 60 $G/eph_menger.vox > /dev/null 2>&1
run() { # who round bin env...
  who=$1 round=$2 bin=$3; shift 3
  if [ $(t) -gt $TMAX ]; then echo "=== skip $who $round t=$(t)"; return; fi
  st=""; [ $round = 1 ] && st="--shader-stats"
  echo "=== K$round $who t=$(t)"
  tob=$(( END - $(t) )); [ $tob -gt $TOB ] && tob=$TOB
  env "$@" timeout $tob $bin $st --gpu $SIZE --reps $REPS $SC > $O/k_${who}_$round.txt 2>&1
  echo "rc=$? t=$(t)"
  grep -v "^|\|^stats\|^device\|^$\|^ck6" $O/k_${who}_$round.txt | sort | uniq -c | head -5
}
# main, x, x, main: the x process compiles 7 kernels per scene (its first round the longest)
run main 1 $B/compact_bench
run x 1 $X VX_CK6_LIST="$LIST"
run x 2 $X VX_CK6_LIST="$LIST"
run main 2 $B/compact_bench
echo "=== stats (round 1)"
grep "^stats: trace \[spec [13]," $O/k_main_1.txt | sort -u | cut -c1-200
grep "^stats: trace compact \[spec [13]," $O/k_main_1.txt | sort -u | cut -c1-200
grep "^stats: x[0-9]*.spv \[spec [13]," $O/k_x_1.txt | sort -u | cut -c1-200
echo "=== rows: scene | view | variant | trace.comp ms | compact ms | albedo ratio | depth ratio | differ (cell / colour)"
for f in $O/k_*_*.txt; do
  who=$(basename $f .txt)
  awk -F'|' -v who=$who '
    /^\| .* \| (overview|close-up) \|/ { row=$0; split($0, a, "|"); gsub(/ /, "", a[3]); r_sc=a[2]; r_v=a[3]; r_ta=a[4]; r_tb=a[5]; r_al=a[6]; r_dp=a[7]; r_df=a[10];
      if (who !~ /^k_x/) print who " |" r_sc "| " r_v " | main |" r_ta "|" r_tb "|" r_al "|" r_dp "|" r_df; next }
    /^nohits: / { split($0, c, "|"); nh=c[3]; gsub(/ pixels differ without hits/, "", nh) }
    /^ck6: / { n=split($0, b, "/"); v=b[n]; print who " |" r_sc "| " r_v " | " v " |" r_ta "|" r_tb "|" r_al "|" r_dp "|" r_df "| nohits" nh }' $f
done
echo "=== end t=$(t)"
