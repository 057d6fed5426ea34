#!/bin/bash
# ray5 (issue 21, sixteenth sitting): lavapipe, main's render_bench (A: /work/main/build/bin) and the branch's
# (B: build/bin; lavapipe keeps the file's form: gpu.h's nodes_file) alternated process by process, M rays per
# CPU second, no ESVO; LP_NUM_THREADS=1 (one worker, as the fourteenth and fifteenth sittings).
A=${A:-/work/main/build/bin/render_bench}; B=${B:-build/bin/render_bench}
export LP_NUM_THREADS=1
V=/work/shared/corpus/vox
SC="$V/eph_monu1.vox $V/ogt_doom.vox"
OPT="--mrays --cpu-time --sizes 480x270 --runs 5 --warmup 0.3 --no-esvo --views overview,oblique,closeup"
echo "== lavapipe A B A B $(date -u +%T) B=$(git rev-parse --short HEAD)+ VX_GPU_NODE_FORM=${VX_GPU_NODE_FORM:-unset}"
for round in 1 2; do
  for who in A B; do
    bin=$A; [ $who = B ] && bin=$B
    echo "-- round $round $who $(date -u +%T)"
    $bin $OPT $SC 2>&1 | grep -E '^(eph|ogt|\| (eph|ogt))'
  done
done
echo "== done $(date -u +%T)"
