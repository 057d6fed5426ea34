#!/bin/bash
# Coordinator's check of merged main (stop 48: rdr2, lvp2, io7, ckern9 merged) against main at the session start
# (bench/out/base/bin, f807bf3), the two binaries alternating process by process; GPU tests in the GPUs' default
# (the descriptors' GPU form) and test_render_gpu in the file's form (lvp2's DEEP 2 ladder runs there on a GPU).
C=bench/out/coord; B=bench/out/base/bin; T=/tmp/coord; rm -rf $T; mkdir -p $T
export LD_LIBRARY_PATH=$PWD/$C:$PWD/$B
for f in $C/*.gz; do gzip -dc $f > $T/$(basename $f .gz) && chmod +x $T/$(basename $f .gz); done
M=$T; s0=$(date +%s); left() { echo $(( $1 - ($(date +%s) - s0) )); }
echo "== merged main $(cat $C/REV) on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader | head -1) $(date +%T), uptime: $(uptime)"
ARGS="--grid 8,8,8 --res 128 --spp 64 -q -v"
bake() { # who cachedir|default verbose
  local bin=$B/svo_bake; [ $1 = coord ] && bin=$M/svo_bake
  local cenv=X=0; [ $2 != default ] && mkdir -p $T/$2 && cenv=__GL_SHADER_DISK_CACHE_PATH=$T/$2
  local s=${EPOCHREALTIME/./}; env $cenv timeout 20 $bin $C/cornell.svo $T/$1.probes $ARGS > $T/bake_$1.log 2>&1; local rc=$?
  local e=${EPOCHREALTIME/./}; echo "  bake $1 ($2) rc=$rc wall $(( (e - s + 500) / 1000 )) ms"
  [ $3 = 1 ] && grep -E '^(times):' $T/bake_$1.log | cut -c1-200 | sed 's/^/    /'
}
echo "== svo_bake: the machine's first Vulkan process (merged, empty shader cache), base (empty cache), warm AB"
bake coord cold1 1; bake main cold2 0
cmp -s $T/main.probes $T/coord.probes && echo "  cold: same bytes" || echo "  cold: PROBES DIFFER"
bake main default 0; bake coord default 0; cmp -s $T/main.probes $T/coord.probes && echo "  warm: same bytes" || echo "  warm: PROBES DIFFER"
echo "== 1: terrains (--generate --no-esvo), base / merged, A B A B $(date +%T)"
for r in 1 2; do for who in base coord; do
  l=$(left 70); [ $l -gt 5 ] || break 2
  bin=$M/render_bench; [ $who = base ] && bin=$B/render_bench
  echo "-- $who round $r"
  timeout $l $bin --generate --no-esvo --sizes 1920x1080 --runs 10 --warmup 0.1 --views overview,closeup 2>&1 | grep -E '^terr' | cut -c1-150
done; done
echo "== 2: eph_monu1, eph_menger, ogt multiple (with ESVO), A B A B $(date +%T)"
for r in 1 2; do for who in base coord; do
  l=$(left 150); [ $l -gt 5 ] || break 2
  bin=$M/render_bench; [ $who = base ] && bin=$B/render_bench
  echo "-- $who round $r"
  timeout $l $bin --sizes 1920x1080 --runs 10 --warmup 0.1 --views overview,oblique,closeup $C/eph_monu1.vox $C/eph_menger.vox 2>&1 | grep -E '^(eph|ogt)' | cut -c1-170
done; done
echo "== 3: compact_bench, A B A B $(date +%T)"
for who in base coord base coord; do
  l=$(left 200); [ $l -gt 5 ] || break
  bin=$B/compact_bench; [ $who = coord ] && bin=$M/compact_bench
  echo "-- $who"; timeout $l $bin --gpu 1920x1080 --reps 30 $C/eph_monu1.vox $C/eph_menger.vox $C/helmet512.svo --terrain 1024 2>&1 | grep '^| ' | cut -c1-200
done
export VX_CORPUS_DIR=$PWD/$C/corpus
runt() { # test form
  local l=$(left 440); [ $l -gt 4 ] || { echo "== $1 ($2): no time left"; return; }
  local fe=X=0; [ $2 = file ] && fe=VX_GPU_NODE_FORM=file
  local s=$(date +%s); (cd $T && env $fe timeout $l ./$1 > $T/$1.$2.log 2>&1); local rc=$?
  echo "== $1 ($2 form) rc=$rc $(( $(date +%s) - s )) s: $(grep -E 'passed|failed' $T/$1.$2.log | tail -1)"
  grep -E 'deep float, depth 16|compact start:' $T/$1.$2.log | head -2 | cut -c1-200
  [ $rc != 0 ] && cp $T/$1.$2.log $OUTDIR/ 2>/dev/null
  [ $rc != 0 ] && { grep -n -i -B3 -A2 'fail' $T/$1.$2.log | head -30; tail -5 $T/$1.$2.log; }
}
echo "== 4: GPU tests $(date +%T)"
for t in test_render_gpu test_render_edit test_render_hits test_render_smap test_render_beam test_compact_load_gpu test_probes_gpu; do runt $t gpu; done
runt test_render_gpu file
runt test_compact_gpu gpu
echo "== end $(date +%T), $(( $(date +%s) - s0 )) s"
