#!/bin/bash
# Coordinator's check of main at the session start (stop 47, 213469c: ray4/ray5's descriptor form, never run on a
# GPU) against 8ab2eb2 (bench/out/base/bin), process by process; and the GPU form (VX_GPU_NODE_FORM=gpu) against
# the file's form (the default) on the same binary: the decision on the GPUs' default (issue 21).
C=bench/out/coord; B=bench/out/base/bin; T=/tmp/coord; rm -rf $T; mkdir -p $T
export LD_LIBRARY_PATH=$PWD/$C:$PWD/$B
for f in $C/*.gz; do gzip -dc $f > $T/$(basename $f .gz) && chmod +x $T/$(basename $f .gz); done
M=$T; s0=$(date +%s); left() { echo $(( $1 - ($(date +%s) - s0) )); }
echo "== main $(cat $C/REV) on $(nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv,noheader | head -1) $(date +%T), uptime: $(uptime)"
ARGS="--grid 8,8,8 --res 128 --spp 64 -q -v"
bake() { # who cachedir|default verbose
  local bin=$B/svo_bake; [ $1 = coord ] && bin=$M/svo_bake
  local cenv=X=0; [ $2 != default ] && mkdir -p $T/$2 && cenv=__GL_SHADER_DISK_CACHE_PATH=$T/$2
  local s=${EPOCHREALTIME/./}; env $cenv timeout 20 $bin $C/cornell.svo $T/$1.probes $ARGS > $T/bake_$1.log 2>&1; local rc=$?
  local e=${EPOCHREALTIME/./}; echo "  bake $1 ($2) rc=$rc wall $(( (e - s + 500) / 1000 )) ms"
  [ $3 = 1 ] && grep -E '^(bake|timeline|times):' $T/bake_$1.log | cut -c1-260 | sed 's/^/    /'
}
echo "== svo_bake: the machine's first Vulkan process (main now, empty shader cache), base (empty cache), warm ABAB"
bake coord cold1 1; bake main cold2 0
cmp -s $T/main.probes $T/coord.probes && echo "  cold: same bytes" || echo "  cold: PROBES DIFFER"
for r in 1 2; do bake main default 0; bake coord default 0; cmp -s $T/main.probes $T/coord.probes && echo "  round $r: same bytes" || echo "  round $r: PROBES DIFFER"; done
echo "== 1: terrains (--generate --no-esvo): base, now (file form), now (GPU form); 2 rounds, shader stats in round 1 $(date +%T)"
for r in 1 2; do for who in base file gpu; do
  l=$(left 110); [ $l -gt 5 ] || break 2
  bin=$M/render_bench; [ $who = base ] && bin=$B/render_bench; fe=X=0; [ $who = gpu ] && fe=VX_GPU_NODE_FORM=gpu
  echo "-- $who round $r $(date +%T)"
  env $fe timeout $l $bin --generate --no-esvo --sizes 1920x1080 --runs 10 --warmup 0.1 --views overview,oblique,closeup \
    $( [ $r = 1 ] && echo --shader-stats ) 2>&1 | grep -E '^terr|far pointer|^stats: trace|^\| terr' | cut -c1-220
done; done
echo "== 2: eph_monu1, eph_menger, ogt multiple: base, file, gpu, 2 rounds (with ESVO) $(date +%T)"
for r in 1 2; do for who in base file gpu; do
  l=$(left 215); [ $l -gt 5 ] || break 2
  bin=$M/render_bench; [ $who = base ] && bin=$B/render_bench; fe=X=0; [ $who = gpu ] && fe=VX_GPU_NODE_FORM=gpu
  echo "-- $who round $r $(date +%T)"
  env $fe timeout $l $bin --sizes 1920x1080 --runs 10 --warmup 0.1 --views overview,oblique,closeup $C/eph_monu1.vox $C/eph_menger.vox $C/ogt_test_multiple_model_scene.vox 2>&1 | grep -v '^shadow map' | cut -c1-200
done; done
export VX_CORPUS_DIR=$PWD/$C/corpus
runt() { # test form
  local l=$(left 430); [ $l -gt 4 ] || return
  local fe=X=0; [ $2 = gpu ] && fe=VX_GPU_NODE_FORM=gpu
  local s=$(date +%s); (cd $T && env $fe timeout $l ./$1 > $T/$1.$2.log 2>&1); local rc=$?
  echo "== $1 ($2 form) rc=$rc $(( $(date +%s) - s )) s: $(grep -E 'passed|failed' $T/$1.$2.log | tail -1)"
  grep -E 'deep float, depth 16|path start' $T/$1.$2.log | head -3 | cut -c1-200
  [ $rc != 0 ] && { grep -n -i -B3 -A2 'fail' $T/$1.$2.log | head -30; tail -5 $T/$1.$2.log; }
}
echo "== 3: GPU tests $(date +%T)"
for t in test_render_gpu test_render_edit test_render_hits test_render_smap test_render_beam test_compact_load_gpu test_probes_gpu; do runt $t file; done
for t in test_render_gpu test_render_edit test_render_beam test_render_hits test_probes_gpu; do runt $t gpu; done
runt test_pipeline_cache file
echo "== end $(date +%T), $(( $(date +%s) - s0 )) s"
