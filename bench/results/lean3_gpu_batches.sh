#!/bin/bash
# lean3's device scripts (issue 18), one file: BATCH=1, 2 or 3 runs what that batch ran as its run.sh (the payload
# folder held the binaries it names, gzipped, and helmet512.svo, eph_monu1.vox, eph_menger.vox; cwd the folder).
# M = main's compact_bench (527d0fd); L = the branch's whole lean walk (40cbc23); X = the branch at 4fbae79 with
# lean3_explore.patch (trace_compact.comp's LV from VX_LEAN3: 1 scale_exp2 carried, 2 the ray-end test kept, 4 no
# early pixel index; diagnostics, wrong colours on purpose: 8 the colour a hash of the cell, 16 of the index); K = the
# kept form (e9a4795). Every compact kernel timed against trace.comp in its process.
# Batch 1: M, L, M, L, X8, X16, then the branch's test_compact_gpu and test_compact_passes' frames (no time left).
# Batch 2: X1, X2, X3, M, then passes_bench --layout compact --quick, main's and the branch's (40cbc23).
# Batch 3: K, then test_compact_passes' room frames (e9a4795). SIZE, REPS, END, SC: smaller runs on lavapipe.
B=${BATCH:-3}
D=$PWD; T=/tmp/${NAME:-lean3}; rm -rf $T; mkdir -p $T
for f in $D/*.gz; do gzip -dc $f > $T/$(basename $f .gz); done; chmod +x $T/*
cp $D/helmet512.svo $D/eph_monu1.vox $D/eph_menger.vox $T/
cd $T
END=${END:-$(case $B in 1) echo 190;; 2) echo 98;; *) echo 35;; esac)}
RES=$(case $B in 1) echo 75;; 2) echo 24;; *) echo 15;; esac) # seconds kept for what follows the compact_bench runs
CUT=$(case $B in 1) echo 2-11;; *) echo 2-11,14;; esac) # batch 2 on: the albedo pixels differing without hits
echo "== lean3 batch $B, $(date -u)"; nproc; cat /proc/loadavg
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.mem,temperature.gpu --format=csv,noheader 2>/dev/null
T0=$(date +%s); t() { echo $(( $(date +%s) - T0 )); }
[ $B != 3 ] && { echo "=== warm-up t=$(t)"; timeout 4 $T/compact_bench_main --gpu ${SIZE:-1920x1080} --reps 60 eph_menger.vox > /dev/null 2>&1; }
SC=${SC:-"eph_monu1.vox eph_menger.vox helmet512.svo --terrain 1024"}
run() { # who need_s max_s bin args...
  who=$1 need=$2 max=$3 bin=$4; shift 4
  tob=$(( END - RES - $(t) )); [ $tob -gt $max ] && tob=$max
  if [ $tob -lt $need ]; then echo "=== skip $who t=$(t)"; return; fi
  echo "=== $who t=$(t) ${VX_LEAN3:+VX_LEAN3=$VX_LEAN3}"
  timeout $tob $bin "$@" > $T/k_${who}.txt 2>&1
  echo "rc=$? t=$(t)"
  grep -v "^|\|^stats\|^device\|^$" $T/k_${who}.txt | sort | uniq -c | head -5
  grep "^| .* | \(overview\|close-up\)" $T/k_${who}.txt | cut -d'|' -f$CUT | sed "s/^/$who |/"
  grep "^stats: trace" $T/k_${who}.txt | grep -v misses | sort -u | sed 's/ CS (subgroup 32)//; s/Register Count/R/; s/Binary Size/bin/; s/Shared Memory Size/shm/; s/Local Memory Size=6871947/lmem=/; s/Stack Size/stk/' | cut -c1-150
}
M=$T/compact_bench_main; L=$T/compact_bench; X=$T/compact_bench_x
G="--gpu ${SIZE:-1920x1080} --reps ${REPS:-30}"
runt() { # test only
  local l=$(( END - $(t) )); [ $l -gt 4 ] || { echo "== $1: no time left"; return; }
  local s=$(date +%s); VX_TEST_ONLY=$2 timeout $l $T/$1 > $T/$1.log 2>&1; local rc=$?
  echo "== $1 ($2) rc=$rc $(( $(date +%s) - s )) s: $(grep -E 'passed|failed' $T/$1.log | tail -1)"
  [ $rc != 0 ] && { grep -n -i -B3 -A2 'fail' $T/$1.log | head -30; tail -5 $T/$1.log; }
}
if [ $B = 1 ]; then
  run M1 9 20 $M --shader-stats $G $SC
  run L1 9 20 $L --shader-stats $G $SC
  run M2 9 16 $M $G $SC
  run L2 9 16 $L $G $SC
  VX_LEAN3=8 run X8 9 16 $X $G $SC
  VX_LEAN3=16 run X16 9 16 $X $G $SC
  export VX_CORPUS_DIR=$T
  runt test_compact_gpu test_generated,test_seams,test_deep,test_start_table,test_uniform_cubes,test_attr_parts,test_path_start,test_path_records,test_corpus
  runt test_compact_passes _frames
elif [ $B = 2 ]; then
  VX_LEAN3=1 run X1 9 18 $X --shader-stats $G $SC
  VX_LEAN3=2 run X2 9 18 $X --shader-stats $G $SC
  VX_LEAN3=3 run X3 9 12 $X $G $SC
  run M 9 12 $M $G $SC
  for who in main branch; do
    l=$(( END - $(t) )); [ $l -gt 11 ] && l=11; [ $l -gt 3 ] || { echo "=== skip passes $who"; continue; }
    bin=$T/passes_bench; [ $who = main ] && bin=$T/passes_bench_main
    echo "=== passes $who t=$(t)"; timeout $l $bin --layout compact --quick --warmup 0.2 --runs 10 --size ${SIZE:-1920x1080} eph_monu1.vox eph_menger.vox > $T/p_$who.txt 2>&1
    echo "rc=$? t=$(t)"; grep "^##\|^| " $T/p_$who.txt | head -24
  done
else
  run K 9 20 $L --shader-stats $G $SC
  l=$(( END - $(t) ))
  if [ $l -gt 4 ]; then
    s=$(date +%s); VX_TEST_ONLY=test_room_frames timeout $l $T/test_compact_passes > $T/tp.log 2>&1; rc=$?
    echo "== test_compact_passes (test_room_frames) rc=$rc $(( $(date +%s) - s )) s: $(grep -E 'passed|failed' $T/tp.log | tail -1)"
    grep -c "0 floats differ" $T/tp.log; grep "CHECK failed" $T/tp.log | head -5; grep "floats differ" $T/tp.log | head -30 | cut -c1-160
  fi
fi
echo "=== end t=$(t)"
