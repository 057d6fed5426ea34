#!/bin/bash
# deep3 (issue 21, twenty-fourth sitting), batch 2: A = main, B = the colour kernel without the lean walk at DEEP 2,
# C = B + the exact and rebased walks' slots stored before the path start (registers), process by process
# A B C A B C A B C on the generated terrains, every view (ESVO in A1's process only: its 4096 octree takes ~17 s);
# then one A process with --kernels (t_B, t_C: B's and C's trace.comp, px against main's built-in kernel; t_d1, t_norb,
# t_nohl: the diagnostic one-frame walks on B's tree, bench/results/deep3_variants.sh) and --shader-stats.
# Payload: A/B/C_render_bench.gz, k.tgz, A_COMMIT, B_COMMIT, C_COMMIT.
# SIZE, RUNS, WU, TS (time scale) may be set (lavapipe: SIZE=96x54 RUNS=1 WU=0 TS=20).
BATCH=2; LIM=${LIM:-160}; . "${DEEP3_LIB:-$(dirname "$0")/deep3_gpu_lib.sh}" # (the payloads had these lines inline)
run A1 40 $T/A --generate --sizes $SIZE --runs $RUNS --warmup $WU
for r in 1 2 3; do for x in A B C; do [ $r$x = 1A ] && continue; run $x$r 16 $T/$x --generate --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU; done; done
run Ka 40 $T/A --generate --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU --views oblique,closeup --shader-stats --kernels $(kl t_B,t_C,t_nohl,t_norb,t_d1)
finish
