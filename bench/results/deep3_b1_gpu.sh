#!/bin/bash
# deep3 (issue 21, twenty-fourth sitting), batch 1: where DEEP 2's per-step cost is (terrain4096, the rebased walk).
# Ka: main's binary A with --kernels (trace.comp variants, bench/results/deep3_variants.sh) and --shader-stats on the
#    generated terrains (oblique, close-up); Kb: the same kernels in the reverse order (position in the process);
# then A, B (main + the frame switch inside the walk's loop) and C (B + the colour kernel without the lean walk at
# DEEP 2) process by process, A B C A B C, every view.
# Payload: A_render_bench.gz (main), B_, C_render_bench.gz, k.tgz, A_COMMIT, B_COMMIT, C_COMMIT.
# SIZE, RUNS, WU, TS (time scale) may be set (lavapipe: SIZE=96x54 RUNS=1 WU=0 TS=20).
BATCH=1; LIM=${LIM:-150}; . "${DEEP3_LIB:-$(dirname "$0")/deep3_gpu_lib.sh}" # (the payloads had these lines inline)
K1=t_ref,t_d1,t_norb,t_swin,t_rbup,t_lnc
K2=t_lnc,t_rbup,t_swin,t_norb,t_d1,t_ref
run Ka 45 $T/A --generate --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU --views oblique,closeup --shader-stats --kernels $(kl $K1)
run Kb 40 $T/A --generate --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU --views oblique,closeup --kernels $(kl $K2)
for r in 1 2; do for x in A B C; do run $x$r 16 $T/$x --generate --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU; done; done
finish
