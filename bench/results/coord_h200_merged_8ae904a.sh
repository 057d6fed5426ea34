#!/bin/bash
# Coordinator's merged check (stop 54): merged main (bins/) against the session's start 396b0f0 (base/), process by process.
T=/tmp/coordm; rm -rf $T; mkdir -p $T/b $T/m $T/t
for f in base/*.gz; do gzip -dc $f > $T/b/$(basename $f .gz); done
for f in bins/*.gz; do gzip -dc $f > $T/m/$(basename $f .gz); done
for f in tests/*.gz; do gzip -dc $f > $T/t/$(basename $f .gz); done
chmod +x $T/b/* $T/m/* $T/t/*
B=$T/b; M=$T/m; s0=$(date +%s); left() { echo $(( $1 - ($(date +%s) - s0) )); }
echo "== merged $(cat bins/REV) against base $(cat base/REV) on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader | head -1) $(date +%T)"
ARGS="--grid 8,8,8 --res 128 --spp 64 -q -v"
bake() { # who cachedir|default verbose [extra]
  local bin=$B/svo_bake; [ $1 != base ] && bin=$M/svo_bake
  local cenv=X=0; [ $2 != default ] && mkdir -p $T/$2 && cenv=__GL_SHADER_DISK_CACHE_PATH=$T/$2
  local s=${EPOCHREALTIME/./}; env $cenv timeout 20 $bin cornell.svo $T/$1.probes $ARGS $4 > $T/bake_$1.log 2>&1; local rc=$?
  local e=${EPOCHREALTIME/./}; echo "  bake $1 ($2 $4) rc=$rc wall $(( (e - s + 500) / 1000 )) ms"
  [ $3 = 1 ] && grep -E '^(times):' $T/bake_$1.log | cut -c1-200 | sed 's/^/    /'
}
echo "== svo_bake: base and merged (warm) bytes, merged --load models against merged whole"
bake base cold1 0; bake merged cold2 0
cmp -s $T/base.probes $T/merged.probes && echo "  base = merged bytes" || echo "  base and merged PROBES DIFFER"
bake base default 0; bake merged default 1
bake models default 0 "--load models"; cmp -s $T/merged.probes $T/models.probes && echo "  merged models = merged whole bytes" || echo "  models: PROBES DIFFER from merged whole"
echo "== 1: compact_bench A B $(date +%T)"
for who in base merged; do
  l=$(left 80); [ $l -gt 5 ] || break
  bin=$B/compact_bench; [ $who = merged ] && bin=$M/compact_bench
  echo "-- $who"; timeout $l $bin --gpu 1920x1080 --reps 30 eph_monu1.vox helmet512.svo 2>&1 | grep '^| ' | grep 'G rays' | cut -c1-150
done
echo "== 2: render_bench A B (with ESVO) $(date +%T)"
for who in base merged; do
  l=$(left 130); [ $l -gt 5 ] || break
  bin=$M/render_bench; [ $who = base ] && bin=$B/render_bench
  echo "-- $who"; timeout $l $bin --sizes 1920x1080 --runs 10 --warmup 0.5 --views oblique,closeup ogt_test_multiple_model_scene.vox eph_monu1.vox 2>&1 | grep -E '^(eph|ogt)' | cut -c1-170
done
export VX_CORPUS_DIR=$PWD/corpus
runt() { # test
  local l=$(left 505); [ $l -gt 4 ] || { echo "== $1: no time left"; return; }
  local s=$(date +%s); (cd $T && timeout $l $T/t/$1 > $T/$1.log 2>&1); local rc=$?
  echo "== $1 rc=$rc $(( $(date +%s) - s )) s: $(grep -E 'passed|failed' $T/$1.log | tail -1)"
  [ $rc != 0 ] && { grep -n -i -B3 -A2 'fail' $T/$1.log | head -30; tail -5 $T/$1.log; }
}
echo "== 3: GPU tests $(date +%T)"
for t in $(cat tests/LIST); do runt $t; done
echo "== end $(date +%T), $(( $(date +%s) - s0 )) s"
