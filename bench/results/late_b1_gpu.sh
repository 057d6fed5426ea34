#!/bin/bash
# late (issue 21, twenty-sixth sitting), batch 1: A = main 1dff501, B = late (a return out of the rebased node N into
# an inner sibling goes straight to the next switch, F: the loop's push step taken outside the loop). First B's
# test_render_gpu (the deep tests), one B process with ESVO and --shader-stats, one A process with --shader-stats, then
# A B A B A B A B A B process by process (--no-esvo), then two B processes with --kernels (the second in reverse
# order): main's trace.comp (t_main: its pixels must be B's), the late switch at 1, 2, 3 levels below the rebase depth
# (t_L1, t_L2, t_L3: the model frame walks those levels; other pixels than main's on lavapipe from 2), F with the
# model frame's bias and ray end stored once before the loop, not at each switch (t_FB); then A B A B on the .vox
# scenes eph_menger and eph_monu1. Payload: A/B_render_bench.gz, T_test_render_gpu.gz, k.tgz (t_*.spv), *.vox,
# A_COMMIT, B_COMMIT. SIZE, RUNS, WU, TS (time scale) may be set (lavapipe: SIZE=96x54 RUNS=1 WU=0 TS=20).
LIM=${LIM:-400}
# (the binaries' libz, libzstd, libdeflate travel in lib/, for a host without them)
export LD_LIBRARY_PATH=$(cd "$(dirname "$0")" && pwd)/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
T=/tmp/late; rm -rf $T; mkdir -p $T; for x in A B; do gunzip -c ${x}_render_bench.gz > $T/$x; chmod +x $T/$x; done
gunzip -c T_test_render_gpu.gz > $T/T; chmod +x $T/T
tar xzf k.tgz -C $T
. "$(dirname "$0")/gpu_payload_lib.sh"
F="$F|^eph_"
echo "== late batch 1 on $(gpu_name) $(nproc) CPUs $(date -u +%T); A = main $(cat A_COMMIT), B = late $(cat B_COMMIT)"
clock_start
echo "-- T $(date -u +%T): B's test_render_gpu"
VX_TEST_ONLY=test_path_start,test_path_start_deep,test_deep_float,test_stack_levels,test_deep_octrees timeout $(( 110 * ${TS:-1} )) $T/T 2>&1 | grep --line-buffered -E '^\[|passed|FAIL|path start:|deep float|deep octrees|differ' | sed -u 's/^/T /' | stamp
run E 45 $T/B --generate --sizes $SIZE --runs $RUNS --warmup $WU --shader-stats
run A0 20 $T/A --generate --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU --shader-stats
for r in 1 2 3 4 5; do for x in A B; do run $x$r 20 $T/$x --generate --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU; done; done
K=$T/t_main.spv@c1,$T/t_L1.spv@c1,$T/t_L2.spv@c1,$T/t_L3.spv@c1,$T/t_FB.spv@c1
KR=$T/t_FB.spv@c1,$T/t_L3.spv@c1,$T/t_L2.spv@c1,$T/t_L1.spv@c1,$T/t_main.spv@c1
run KB 80 $T/B --generate --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU --kernels $K
run KR 80 $T/B --generate --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU --kernels $KR
for r in 6 7; do for x in A B; do run $x$r 20 $T/$x --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU eph_menger.vox eph_monu1.vox; done; done
payload_end late
