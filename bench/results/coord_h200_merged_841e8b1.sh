#!/bin/bash
# Coordinator (stop 56): merged main (m/) on the H200 against the stop's start 54224d6 (b/): issue 21's table (merged
# render_bench, ESVO in the same processes), compact_bench A B A B (issue 18's ratio), then the GPU tests.
# SIZE, RUNS, WU, TS (time scale) may be set for lavapipe.
T=/tmp/final; rm -rf $T; mkdir -p $T/m $T/b $T/t
gunzip -c render_bench.gz > $T/m/rb; gunzip -c compact_bench.gz > $T/m/cb
gunzip -c base_render_bench.gz > $T/b/rb; gunzip -c base_compact_bench.gz > $T/b/cb
for f in tests/*.gz; do gunzip -c $f > $T/t/$(basename $f .gz); done; chmod +x $T/m/* $T/b/* $T/t/*
s0=$(date +%s); left() { echo $(( $1 * ${TS:-1} - ($(date +%s) - s0) )); }
SIZE=${SIZE:-1920x1080}; RUNS=${RUNS:-15}; WU=${WU:-0.5}
smi() { nvidia-smi --query-gpu=clocks.sm,power.draw,temperature.gpu --format=csv,noheader 2>/dev/null | head -1; }
echo "== merged $(cat REV) against base $(cat BASE) on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1) $(date -u +%T)"
timeout $((10 * ${TS:-1})) $T/m/rb --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup eph_monu1.vox > /dev/null 2>&1
echo "-- 1: table, corpus scenes, clock $(smi)"
timeout $((70 * ${TS:-1})) $T/m/rb --sizes $SIZE --runs $RUNS --warmup $WU eph_monu1.vox eph_menger.vox eph_dragon.vox ogt_doom.vox ogt_test_multiple_model_scene.vox 2>&1 | grep -E '^scene|^eph|^ogt|^device' | sed -E 's/  *\[warps[^]]*\]//' | cut -c1-200
echo "-- 1: table, generated terrains, clock $(smi)"
timeout $((70 * ${TS:-1})) $T/m/rb --generate --sizes $SIZE --runs $RUNS --warmup $WU 2>&1 | grep -E '^scene|^terrain|^device' | sed -E 's/  *\[warps[^]]*\]//' | cut -c1-200
echo "-- 2: compact_bench A B A B A B $(date -u +%T)"
for r in 1 2 3; do for who in b m; do
  l=$(left 330); [ $l -gt 8 ] || break 2; [ $l -gt $((15 * ${TS:-1})) ] && l=$((15 * ${TS:-1}))
  timeout $l $T/$who/cb --gpu $SIZE --reps ${REPS:-30} eph_monu1.vox helmet512.svo --terrain ${TER:-1024} 2>&1 | grep '^| .* | \(overview\|close-up\)' | grep 'G rays' | cut -d'|' -f2-8 | sed "s/^/$who$r |/"
done; done
export VX_CORPUS_DIR=$PWD/corpus
runt() { # test
  local l=$(left 560); [ $l -gt 4 ] || { echo "== $1: no time left"; return; }
  local s=$(date +%s); (cd $T && timeout $l $T/t/$1 > $T/$1.log 2>&1); local rc=$?
  echo "== $1 rc=$rc $(( $(date +%s) - s )) s: $(grep -E 'passed|failed' $T/$1.log | tail -1)"
  [ $rc != 0 ] && { grep -n -i -B3 -A2 'fail' $T/$1.log | head -30; tail -5 $T/$1.log; }
}
echo "== 3: GPU tests $(date -u +%T)"
for t in $(cat tests/LIST); do runt $t; done
echo "== end $(date -u +%T), $(( $(date +%s) - s0 )) s"
