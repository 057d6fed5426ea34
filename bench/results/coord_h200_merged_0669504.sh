#!/bin/bash
# Coordinator's check of merged main (issues 18/21, stop 46: bake4, io5, ckern7 merged) against main at the
# session start (bench/out/base/bin, 8ab2eb2), the two binaries alternating process by process.
C=bench/out/coord; B=bench/out/base/bin; T=/tmp/coord; rm -rf $T; mkdir -p $T
export LD_LIBRARY_PATH=$PWD/$C:$PWD/$B
for f in $C/*.gz; do [ -e "$f" ] && gzip -dc $f > $T/$(basename $f .gz) && chmod +x $T/$(basename $f .gz); done
M=$T   # merged binaries
echo "== merged main $(cat $C/REV) on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader | head -1) $(date +%T), uptime: $(uptime)"
ARGS="--grid 8,8,8 --res 128 --spp 64 -q -v"
bake() { # who cachedir|default round
  local bin=$B/svo_bake; [ $1 = coord ] && bin=$M/svo_bake
  local cenv=X=0; [ $2 != default ] && mkdir -p $T/$2 && cenv=__GL_SHADER_DISK_CACHE_PATH=$T/$2
  local s=${EPOCHREALTIME/./}; env $cenv timeout 20 $bin $C/cornell.svo $T/$1.probes $ARGS > $T/bake_$1.log 2>&1; local rc=$?
  local e=${EPOCHREALTIME/./}; echo "  bake $1 ($2) rc=$rc wall $(( (e - s + 500) / 1000 )) ms"
  [ $3 = 1 ] && grep -E '^(bake|timeline|times):' $T/bake_$1.log | cut -c1-260 | sed 's/^/    /'
}
echo "== svo_bake: the machine's first Vulkan process (merged, empty shader cache), then main's (empty cache), then warm ABAB"
bake coord cold1 1; bake main cold2 1
cmp -s $T/main.probes $T/coord.probes && echo "  cold: same bytes" || echo "  cold: PROBES DIFFER"
bake coord cold3 0; bake main cold4 0
for r in 1 2 3; do bake main default 0; bake coord default 0; cmp -s $T/main.probes $T/coord.probes && echo "  round $r: same bytes" || echo "  round $r: PROBES DIFFER"; done
# GPU tests (ctest's working dirs are not here: the tests take the corpus from VX_CORPUS_DIR)
export VX_CORPUS_DIR=$PWD/$C/corpus
for t in test_render_gpu test_compact_gpu test_compact_load_gpu test_render_smap test_render_hits test_render_beam test_probes_gpu test_pipeline_cache; do
  [ -x $M/$t ] || continue
  s=$(date +%s); (cd $T && timeout 100 ./$t > $T/$t.log 2>&1); rc=$?
  echo "== $t rc=$rc $(( $(date +%s) - s )) s: $(grep -E 'passed|failed' $T/$t.log | tail -1)"
  grep -E 'deep float, depth 16|compact start:|path start' $T/$t.log | head -4 | cut -c1-240
  [ $rc != 0 ] && { grep -n -i -B3 -A2 'fail' $T/$t.log | head -40; tail -5 $T/$t.log; }
done
echo "== compact_bench: main, merged, main, merged $(date +%T)"
for who in main coord main coord; do
  bin=$B/compact_bench; [ $who = coord ] && bin=$M/compact_bench
  echo "-- $who"; timeout 50 $bin --gpu 1920x1080 --reps 30 $C/eph_monu1.vox $C/eph_menger.vox $C/helmet512.svo --terrain 1024 2>&1 | grep '^| ' | cut -c1-220
done
echo "== render_bench: main and merged, ABAB (with ESVO) $(date +%T)"
for r in 1 2; do for who in main coord; do
  bin=$B/render_bench; [ $who = coord ] && bin=$M/render_bench
  echo "-- $who round $r"
  timeout 60 $bin --sizes 1920x1080 --runs 10 --warmup 0.1 --views overview,oblique,closeup $C/eph_monu1.vox $C/eph_menger.vox $C/ogt_test_multiple_model_scene.vox 2>&1 | grep -v '^shadow map' | cut -c1-200
done; done
echo "== end $(date +%T)"
