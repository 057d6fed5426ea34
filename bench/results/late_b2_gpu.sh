#!/bin/bash
# late (issue 21, twenty-sixth sitting), batch 2: A = main 1dff501, B = late e4eaee0 (F: a return out of the rebased node
# N into an inner sibling goes straight to the next switch; batch 1's B), C = B + G2 (the node after a switch into a
# frame and after a return's pop loaded before the walk's loop re-enters, the word its first step loads). First C's
# test_render_gpu (the deep tests), one C process with --shader-stats, then A B C A B C A B C A B C process by process
# (--no-esvo), then two B processes with --kernels (the second in reverse order): main's trace.comp (t_main), F
# (t_F: B's own source), G1 (F + the load after a switch only), G2 (C's source). Payload: A/B/C_render_bench.gz,
# T_test_render_gpu.gz (C's), k.tgz (t_*.spv), A_COMMIT, B_COMMIT, C_COMMIT.
# SIZE, RUNS, WU, TS (time scale) may be set (lavapipe: SIZE=96x54 RUNS=1 WU=0 TS=20).
LIM=${LIM:-400}
# (the binaries' libz, libzstd, libdeflate travel in lib/, for a host without them)
export LD_LIBRARY_PATH=$(cd "$(dirname "$0")" && pwd)/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
T=/tmp/late2; rm -rf $T; mkdir -p $T; for x in A B C; do gunzip -c ${x}_render_bench.gz > $T/$x; chmod +x $T/$x; done
gunzip -c T_test_render_gpu.gz > $T/T; chmod +x $T/T
tar xzf k.tgz -C $T
. "$(dirname "$0")/gpu_payload_lib.sh"
echo "== late batch 2 on $(gpu_name) $(nproc) CPUs $(date -u +%T); A = main $(cat A_COMMIT), B = late $(cat B_COMMIT), C = late $(cat C_COMMIT)"
clock_start
echo "-- T $(date -u +%T): C's test_render_gpu"
VX_TEST_ONLY=test_path_start,test_path_start_deep,test_deep_float,test_stack_levels,test_deep_octrees timeout $(( 110 * ${TS:-1} )) $T/T 2>&1 | grep --line-buffered -E '^\[|passed|FAIL|path start:|deep float|deep octrees|differ' | sed -u 's/^/T /' | stamp
run C0 20 $T/C --generate --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU --shader-stats
for r in 1 2 3 4; do for x in A B C; do run $x$r 20 $T/$x --generate --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU; done; done
K=$T/t_main.spv@c1,$T/t_F.spv@c1,$T/t_G1.spv@c1,$T/t_G2.spv@c1
KR=$T/t_G2.spv@c1,$T/t_G1.spv@c1,$T/t_F.spv@c1,$T/t_main.spv@c1
run KB 70 $T/B --generate --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU --kernels $K
run KR 70 $T/B --generate --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU --kernels $KR
payload_end late2
