#!/bin/bash
# ckern7 (issue 18): the compact kernel's primary rays start below the root
# (trace_compact.comp PATH_START). Processes alternate main (bench/out/base/bin,
# 8ab2eb2) and the branch (B: compact_bench with --start-ab, which also times
# the compact kernel with its starts off in the same rounds), each timing
# trace.comp against the compact kernel in the same process. Then the
# branch's test_path_start (test_compact_gpu) on the H200.
G=bench/out/ckern7; B=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; TER=${TER:-1024}; REPS=${REPS:-30}; TOB=${TOB:-20}; END=${END:-90}
export LD_LIBRARY_PATH=$PWD/$G:$PWD/$B
T=/tmp/ck7; rm -rf $T; mkdir -p $T
for v in compact_bench test_compact_gpu; do gzip -dc $G/$v.gz > $T/$v && chmod +x $T/$v; done
O=${OUTDIR:-$T}; mkdir -p $O
echo "== ckern7 batch, $(date -u)"; nproc; cat /proc/loadavg
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.mem,temperature.gpu --format=csv,noheader 2>/dev/null
T0=$(date +%s); t() { echo $(( $(date +%s) - T0 )); }
SC="$G/eph_monu1.vox $G/eph_menger.vox $G/helmet512.svo --terrain $TER"
echo "=== warm-up t=$(t)"; timeout 3 $B/compact_bench --gpu $SIZE --reps 60 $G/eph_menger.vox > /dev/null 2>&1
run() { # who round bin [args]
  who=$1 round=$2 bin=$3; shift 3
  tob=$(( END - $(t) )); [ $tob -gt $TOB ] && tob=$TOB
  if [ $tob -lt 12 ]; then echo "=== skip $who $round t=$(t)"; return; fi
  st=""; [ $round = 1 ] && st="--shader-stats"
  echo "=== K$round $who t=$(t)"
  timeout $tob $bin $st "$@" --gpu $SIZE --reps $REPS $SC > $O/k_${who}_$round.txt 2>&1
  echo "rc=$? t=$(t)"
  grep -v "^|\|^stats\|^device\|^$" $O/k_${who}_$round.txt | sort | uniq -c | head -5
  grep "^| .* | \(overview\|close-up\)" $O/k_${who}_$round.txt | cut -d'|' -f2-8,10,14 | sed "s/^/$who$round |/"
  [ $round = 1 ] && grep "^stats: trace compact \[spec [13]," $O/k_${who}_$round.txt | sort -u | sed 's/ CS (subgroup 32)//; s/Stack Size=0; Local Memory Size=[0-9]*; //' | cut -c1-150
}
run main 1 $B/compact_bench
run B 1 $T/compact_bench --start-ab
run main 2 $B/compact_bench
run B 2 $T/compact_bench --start-ab
echo "=== test_compact_gpu test_path_start t=$(t)"
VX_TEST_ONLY=test_path_start timeout 20 $T/test_compact_gpu > $O/test_path_start.txt 2>&1; echo "rc=$? t=$(t)"
head -24 $O/test_path_start.txt; echo ...; tail -4 $O/test_path_start.txt
run main 3 $B/compact_bench
run B 3 $T/compact_bench --start-ab
echo "=== end t=$(t)"
