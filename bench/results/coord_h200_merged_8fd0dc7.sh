#!/bin/bash
# Coordinator's check of merged main (stop 50: occ, bakex, io9, pager, debt) against eb010c8
# (bench/out/base/bin; passes_bench_main built from eb010c8), process by process.
C=bench/out/coord; B=bench/out/base/bin; T=/tmp/coord; rm -rf $T; mkdir -p $T
export LD_LIBRARY_PATH=$PWD/$C:$PWD/$B
for f in $C/*.gz; do gzip -dc $f > $T/$(basename $f .gz) && chmod +x $T/$(basename $f .gz); done
M=$T; s0=$(date +%s); left() { echo $(( $1 - ($(date +%s) - s0) )); }
echo "== merged main $(cat $C/REV) on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader | head -1) $(date +%T)"
ARGS="--grid 8,8,8 --res 128 --spp 64 -q -v"
bake() { # who cachedir|default verbose [extra]
  local bin=$B/svo_bake; [ $1 != main ] && bin=$M/svo_bake
  local cenv=X=0; [ $2 != default ] && mkdir -p $T/$2 && cenv=__GL_SHADER_DISK_CACHE_PATH=$T/$2
  local s=${EPOCHREALTIME/./}; env $cenv timeout 20 $bin $C/cornell.svo $T/$1.probes $ARGS $4 > $T/bake_$1.log 2>&1; local rc=$?
  local e=${EPOCHREALTIME/./}; echo "  bake $1 ($2 $4) rc=$rc wall $(( (e - s + 500) / 1000 )) ms"
  [ $3 = 1 ] && grep -E '^(times):' $T/bake_$1.log | cut -c1-200 | sed 's/^/    /'
}
echo "== svo_bake: first process (merged, empty cache), base, warm AB, merged --load models twice"
bake coord cold1 1; bake main cold2 0
cmp -s $T/main.probes $T/coord.probes && echo "  cold: same bytes" || echo "  cold: PROBES DIFFER"
bake main default 0; bake coord default 1; cmp -s $T/main.probes $T/coord.probes && echo "  warm: same bytes" || echo "  warm: PROBES DIFFER"
bake models default 1 "--load models"; cmp -s $T/main.probes $T/models.probes && echo "  models: same bytes" || { echo "  models: PROBES DIFFER"; tail -3 $T/bake_models.log; }
bake coord default 0; bake models default 1 "--load models"
echo "== 1: compact_bench A B A B $(date +%T)"
for who in base coord base coord; do
  l=$(left 100); [ $l -gt 5 ] || break
  bin=$B/compact_bench; [ $who = coord ] && bin=$M/compact_bench
  echo "-- $who"; timeout $l $bin --gpu 1920x1080 --reps 30 $C/eph_monu1.vox $C/eph_menger.vox $C/helmet512.svo --terrain 1024 2>&1 | grep '^| ' | grep 'G rays' | cut -c1-150
done
echo "== 2: passes_bench --layout compact A B A B $(date +%T)"
for who in base coord base coord; do
  l=$(left 150); [ $l -gt 5 ] || break
  bin=$M/passes_bench_main; [ $who = coord ] && bin=$M/passes_bench
  echo "-- $who"; timeout $l $bin --layout compact --runs 7 --size 1920x1080 $C/eph_monu1.vox $C/eph_menger.vox 2>&1 | grep "^##\|^| gbuffer |\|^| gbuffer,direct |\|^| gbuffer,direct,ao,aa,tonemap |"
done
echo "== 3: render_bench A B (with ESVO) $(date +%T)"
for who in base coord; do
  l=$(left 200); [ $l -gt 5 ] || break
  bin=$M/render_bench; [ $who = base ] && bin=$B/render_bench
  echo "-- $who"; timeout $l $bin --sizes 1920x1080 --runs 10 --warmup 0.1 --views overview,oblique,closeup $C/eph_monu1.vox $C/eph_menger.vox 2>&1 | grep -E '^(eph|ogt)' | cut -c1-170
done
export VX_CORPUS_DIR=$PWD/$C/corpus
runt() { # test form
  local l=$(left 420); [ $l -gt 4 ] || { echo "== $1 ($2): no time left"; return; }
  local fe=X=0; [ $2 = file ] && fe=VX_GPU_NODE_FORM=file
  local s=$(date +%s); (cd $T && env $fe timeout $l ./$1 > $T/$1.$2.log 2>&1); local rc=$?
  echo "== $1 ($2 form) rc=$rc $(( $(date +%s) - s )) s: $(grep -E 'passed|failed' $T/$1.$2.log | tail -1)"
  [ $rc != 0 ] && { grep -n -i -B3 -A2 'fail' $T/$1.$2.log | head -30; tail -5 $T/$1.$2.log; }
}
echo "== 4: GPU tests $(date +%T)"
for t in test_compact_gpu test_compact_load_gpu test_probes_gpu test_render_gpu test_render_edit test_render_hits test_render_smap test_render_beam test_compact_page_file test_compact_passes; do runt $t gpu; done
echo "== end $(date +%T), $(( $(date +%s) - s0 )) s"
