#!/bin/bash
# ray5 (issue 21, sixteenth sitting; branch ray4): the descriptors' form per device (gpu.h's nodes_file: CPU
# devices the file's form and main's loop, GPUs the GPU form). Limit 120 s. A = main (bench/out/base/bin),
# B = the branch (bench/out/ray5, gz'd), alternated process by process.
# 1: --generate --no-esvo --shader-stats (terrain1024, terrain4096: the rebased walk's FILE_FORM kernels),
#    A B A B (shader statistics in round 1). 2: eph_monu1, eph_menger, 1920x1080, 3 views, A B A B (ESVO
#    included). 3: B's test_render_gpu and test_render_edit (the GPU form, this device's default); 4: with the
#    time left, the same in the file's form (VX_GPU_NODE_FORM=file).
R=bench/out/ray5; A=bench/out/base/bin; T=/tmp/ray5; rm -rf $T; mkdir -p $T
export LD_LIBRARY_PATH=$PWD/$A
for f in $R/*.gz; do [ -e "$f" ] && gzip -dc $f > $T/$(basename $f .gz) && chmod +x $T/$(basename $f .gz); done
SIZE=${SIZE:-1920x1080}; WU=${WU:-0.1}; RUNS=${RUNS:-10}
s0=$(date +%s)
left() { echo $(( ${1} - ($(date +%s) - s0) )); }
echo "== ray5 B $(cat $R/REV) on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1 || echo 'no nvidia-smi') size $SIZE $(date -u +%T)"
echo "== 1: terrains (--generate --no-esvo), A B A B $(date -u +%T)"
for round in 1 2; do
  for who in A B; do
    l=$(left ${T1:-45}); [ $l -gt 3 ] || break 2
    bin=$A/render_bench; [ $who = B ] && bin=$T/render_bench
    echo "-- round $round $who $(date -u +%T)"
    timeout $l $bin --generate --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU --views overview,oblique,closeup \
      $( [ $round = 1 ] && echo --shader-stats ) 2>&1 | grep -E '^terr|far pointer|^stats: trace|^\| terr'
  done
done
echo "== 2: eph_monu1, eph_menger, A B A B (with ESVO) $(date -u +%T)"
for round in 1 2; do
  for who in A B; do
    l=$(left ${T2:-90}); [ $l -gt 3 ] || break 2
    bin=$A/render_bench; [ $who = B ] && bin=$T/render_bench
    echo "-- round $round $who $(date -u +%T)"
    timeout $l $bin --sizes $SIZE --runs $RUNS --warmup $WU --views overview,oblique,closeup $R/eph_monu1.vox $R/eph_menger.vox \
      2>&1 | grep -v '^shadow map' | cut -c1-220
  done
done
echo "== 3: B's tests (VX_GPU_NODE_FORM unset: this device's default form) $(date -u +%T)"
export VX_CORPUS_DIR=$PWD/$R/corpus
for t in test_render_gpu test_render_edit; do
  l=$(left ${TOTAL:-117}); [ $l -gt 2 ] || break
  [ -x $T/$t ] || { echo "== $t missing"; continue; }
  s=$(date +%s); (cd $T && timeout $l ./$t > $T/$t.log 2>&1); rc=$?
  echo "== $t rc=$rc $(( $(date +%s) - s )) s: $(grep -E 'passed|failed' $T/$t.log | tail -1)"
  [ $rc != 0 ] && { grep -n -i -B3 -A2 'fail' $T/$t.log | head -30; tail -5 $T/$t.log; }
done
echo "== 4: with the time left, B's tests in the file's form on this GPU (VX_GPU_NODE_FORM=file) $(date -u +%T)"
for t in test_render_edit test_render_gpu; do
  l=$(left ${TOTAL:-117}); [ $l -gt 8 ] || break
  s=$(date +%s); (cd $T && VX_GPU_NODE_FORM=file timeout $l ./$t > $T/$t.file.log 2>&1); rc=$?
  echo "== $t (file form) rc=$rc $(( $(date +%s) - s )) s: $(grep -E 'passed|failed' $T/$t.file.log | tail -1)"
  [ $rc != 0 ] && { grep -n -i -B3 -A2 'fail' $T/$t.file.log | head -20; tail -3 $T/$t.file.log; }
done
echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
