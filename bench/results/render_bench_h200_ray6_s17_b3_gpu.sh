#!/bin/bash
# ray6 (issue 21, seventeenth sitting), batch 3 (limit 80 s): the final form against main, process by process.
# A: main's render_bench (bench/out/base/bin, 46eb6d3; GPUs take the GPU form, the rebased walk's kernels turn
# each loaded descriptor back); B: the branch's (the rebased walk's depth kernel reads the GPU form as it is, the
# colour kernel keeps the turn); F: main's with VX_GPU_NODE_FORM=file (the file form's rate: the goal of (a)).
# 1: terrains (--generate --no-esvo), rounds A B F, twice; --shader-stats in round 1; B's round-1 process also
#    runs main's trace.comp (k_main.spv, @c1) on the same scene: its "px differ" is the exactness check on the H200.
# 2: eph_menger and eph_monu1 with ESVO, B A, as time allows (their kernels' SPIR-V is main's after
#    specialisation).
export LD_LIBRARY_PATH=bench/out/base/bin
L=bench/out/ray6; A=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; WU=${WU:-0.1}; RUNS=${RUNS:-10}
s0=$(date +%s); left() { echo $(( $1 - ($(date +%s) - s0) )); }
echo "== ray6 batch 3, B $(head -1 $L/REV), on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1) $(date -u +%T)"
timeout 4 $A/render_bench --no-esvo --sizes $SIZE --runs 200 --warmup 2 --views overview $L/eph_monu1.vox > /dev/null 2>&1
for round in 1 2; do
  for who in A B F; do
    l=$(left 62); [ $l -gt 5 ] || break 2
    echo "-- 1: terrains round $round $who $(date -u +%T)"
    bin=$A/render_bench; fe=X=0; extra=""
    [ $who = B ] && bin=$L/render_bench
    [ $who = F ] && fe=VX_GPU_NODE_FORM=file
    [ $round = 1 ] && extra="--shader-stats"
    [ $round = 1 ] && [ $who = B ] && extra="--shader-stats --kernels $L/k_main.spv@c1"
    env $fe timeout $l $bin --generate --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU --views overview,oblique,closeup $extra 2>&1 \
      | grep -E '^terr|^stats: trace \[spec [03],1,0,0,[01],0,1,1,2' | cut -c1-400
  done
done
for who in B A; do
  l=$(left 78); [ $l -gt 6 ] || break
  echo "-- 2: eph_menger, eph_monu1 with ESVO, $who $(date -u +%T)"
  bin=$A/render_bench; [ $who = B ] && bin=$L/render_bench
  timeout $l $bin --sizes $SIZE --runs $RUNS --warmup $WU --views overview,oblique,closeup $L/eph_menger.vox $L/eph_monu1.vox 2>&1 \
    | grep -E '^eph' | cut -c1-250
done
echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
