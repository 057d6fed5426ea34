#!/bin/bash
# ray4 (issue 21, fifteenth sitting): lavapipe, main's render_bench (A: /work/main/bench/out/base/bin, 8ab2eb2)
# and the branch's (B: build/bin) alternated process by process, rays per CPU second, with ESVO;
# LP_NUM_THREADS=1 (one worker, as the fourteenth sitting).
A=/work/main/bench/out/base/bin/render_bench; B=build/bin/render_bench
export LD_LIBRARY_PATH=/work/main/bench/out/base/bin LP_NUM_THREADS=1
V=bench/out/ray4
SC="$V/eph_monu1.vox $V/ogt_doom.vox $V/eph_dragon.vox"
OPT="--mrays --cpu-time --sizes 480x270 --runs 5 --warmup 0.3 --views overview,oblique,closeup"
echo "== lavapipe A B A B $(date -u +%T) B=$(git rev-parse --short HEAD)"
for round in 1 2; do
  for who in A B; do
    bin=$A; [ $who = B ] && bin=$B
    echo "-- round $round $who $(date -u +%T)"
    nice $bin $OPT $SC 2>&1 | grep -E '^(eph|ogt)'
  done
done
echo "== done $(date -u +%T)"
