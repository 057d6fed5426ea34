#!/bin/bash
# lean3 batch 1 (issue 18): the lean walk in the compact kernels. M = main's compact_bench (527d0fd), L = the branch
# (lean, 40cbc23), X = L with trace_compact.comp's exploration constant LV from VX_LEAN3 (lean3_explore.patch;
# diagnostics, wrong colours on purpose: 8 the colour a hash of the cell, no index or decode; 16 a hash of the index,
# no decode). Every compact kernel timed against trace.comp in its process. Then the branch's test_compact_gpu
# (without the corpus: test_corpus found eph_monu1 and eph_menger in $T) and test_compact_passes' frames (no time left).
# The payload folder held these binaries gzipped (compact_bench_main, compact_bench, compact_bench_x, test_compact_gpu,
# test_compact_passes) and helmet512.svo, eph_monu1.vox, eph_menger.vox. SIZE, REPS, END, SC: smaller runs on lavapipe.
D=$PWD; T=/tmp/${NAME:-lean3}; rm -rf $T; mkdir -p $T
for f in $D/*.gz; do gzip -dc $f > $T/$(basename $f .gz); done; chmod +x $T/*
cp $D/helmet512.svo $D/eph_monu1.vox $D/eph_menger.vox $T/
cd $T
END=${END:-190}
echo "== lean3 batch 1, $(date -u)"; nproc; cat /proc/loadavg
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.mem,temperature.gpu --format=csv,noheader 2>/dev/null
T0=$(date +%s); t() { echo $(( $(date +%s) - T0 )); }
echo "=== warm-up t=$(t)"; timeout 4 $T/compact_bench_main --gpu ${SIZE:-1920x1080} --reps 60 eph_menger.vox > /dev/null 2>&1
SC=${SC:-"eph_monu1.vox eph_menger.vox helmet512.svo --terrain 1024"}
run() { # who need_s max_s bin args...
  who=$1 need=$2 max=$3 bin=$4; shift 4
  tob=$(( END - 75 - $(t) )); [ $tob -gt $max ] && tob=$max
  if [ $tob -lt $need ]; then echo "=== skip $who t=$(t)"; return; fi
  echo "=== $who t=$(t) ${VX_LEAN3:+VX_LEAN3=$VX_LEAN3}"
  timeout $tob $bin "$@" > $T/k_${who}.txt 2>&1
  echo "rc=$? t=$(t)"
  grep -v "^|\|^stats\|^device\|^$" $T/k_${who}.txt | sort | uniq -c | head -5
  grep "^| .* | \(overview\|close-up\)" $T/k_${who}.txt | cut -d'|' -f2-11 | sed "s/^/$who |/"
  grep "^stats: trace" $T/k_${who}.txt | grep -v misses | sort -u | sed 's/ CS (subgroup 32)//; s/Register Count/R/; s/Binary Size/bin/; s/Shared Memory Size/shm/; s/Local Memory Size=6871947/lmem=/; s/Stack Size/stk/' | cut -c1-150
}
M=$T/compact_bench_main; L=$T/compact_bench; X=$T/compact_bench_x
G="--gpu ${SIZE:-1920x1080} --reps ${REPS:-30}"
run M1 9 20 $M --shader-stats $G $SC
run L1 9 20 $L --shader-stats $G $SC
run M2 9 16 $M $G $SC
run L2 9 16 $L $G $SC
VX_LEAN3=8 run X8 9 16 $X $G $SC
VX_LEAN3=16 run X16 9 16 $X $G $SC
export VX_CORPUS_DIR=$T
runt() { # test only
  local l=$(( END - $(t) )); [ $l -gt 4 ] || { echo "== $1: no time left"; return; }
  local s=$(date +%s); VX_TEST_ONLY=$2 timeout $l $T/$1 > $T/$1.log 2>&1; local rc=$?
  echo "== $1 ($2) rc=$rc $(( $(date +%s) - s )) s: $(grep -E 'passed|failed' $T/$1.log | tail -1)"
  [ $rc != 0 ] && { grep -n -i -B3 -A2 'fail' $T/$1.log | head -30; tail -5 $T/$1.log; }
}
runt test_compact_gpu test_generated,test_seams,test_deep,test_start_table,test_uniform_cubes,test_attr_parts,test_path_start,test_path_records,test_corpus
runt test_compact_passes _frames
echo "=== end t=$(t)"
