#!/bin/bash
# rbstart (issue 21, twenty-fifth sitting), batch 2: A = main 54224d6, B = rbstart (the primary ray's start in the
# rebased frame), C = B with the host's listed top 4x as long (VX__TOP_NODES 16384: terrain4096's close-up X one level
# deeper, 6 instead of 5). First B's test_render_gpu (the path starts and the deep tests, on the H200's compiler),
# then A B C process by process, three rounds (--no-esvo), then one C process with --kernels: main's trace.comp from
# the root (t_main@c1p0) and C's own from the root (@c1p0), pixels against C's built-in kernel (the start on).
# Payload: A/B/C_render_bench.gz, T_test_render_gpu.gz, k.tgz (t_main.spv), A_COMMIT, B_COMMIT, C_COMMIT.
# SIZE, RUNS, WU, TS (time scale) may be set (lavapipe: SIZE=96x54 RUNS=1 WU=0 TS=20).
LIM=${LIM:-280}
T=/tmp/rbstart; rm -rf $T; mkdir -p $T; for x in A B C; do gunzip -c ${x}_render_bench.gz > $T/$x; chmod +x $T/$x; done
gunzip -c T_test_render_gpu.gz > $T/T; chmod +x $T/T
tar xzf k.tgz -C $T
. "$(dirname "$0")/gpu_payload_lib.sh" # (the payload carried these lines inline)
echo "== rbstart batch 2 on $(gpu_name) $(nproc) CPUs $(date -u +%T); A = main $(cat A_COMMIT), B = rbstart $(cat B_COMMIT), C = $(cat C_COMMIT)"
clock_start
echo "-- T $(date -u +%T): B's test_render_gpu"
VX_TEST_ONLY=test_path_start,test_path_start_deep,test_deep_float,test_stack_levels,test_deep_octrees timeout $(( 110 * ${TS:-1} )) $T/T 2>&1 | grep --line-buffered -E '^\[|passed|FAIL|path start:|deep float|deep octrees|differ' | sed -u 's/^/T /' | stamp
for r in 1 2 3; do for x in A B C; do run $x$r 20 $T/$x --generate --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU; done; done
run KC 30 $T/C --generate --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU --views oblique,closeup --kernels $T/t_main.spv@c1p0,@c1p0
payload_end rbstart
