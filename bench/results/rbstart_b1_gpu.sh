#!/bin/bash
# rbstart (issue 21, twenty-fifth sitting), batch 1: A = main 54224d6, B = rbstart (the primary ray's start in the
# rebased frame: X below the rebase level, the switch into N's frame before the loop). One B process with ESVO and
# --shader-stats, one A process with --shader-stats, then A B A B A B A B process by process (--no-esvo), then one A
# process with --kernels (counters: t_main_cin +1000 iterations per switch into N's frame taken from the walk's loop,
# t_main_cout +1000 per return out of N; main's kernels, the start on), one B process with --kernels: main's trace.comp
# from the root (t_main@c1p0) and B's own from the root (@c1p0), pixels against B's built-in kernel (the start on),
# and B's counters (t_rb_cin, t_rb_cout). Payload: A/B_render_bench.gz, k.tgz (t_*.spv), A_COMMIT, B_COMMIT.
# SIZE, RUNS, WU, TS (time scale) may be set (lavapipe: SIZE=96x54 RUNS=1 WU=0 TS=20).
LIM=${LIM:-280}
T=/tmp/rbstart; rm -rf $T; mkdir -p $T; for x in A B; do gunzip -c ${x}_render_bench.gz > $T/$x; chmod +x $T/$x; done
tar xzf k.tgz -C $T
. "$(dirname "$0")/gpu_payload_lib.sh" # (the payload carried these lines inline)
echo "== rbstart batch 1 on $(gpu_name) $(nproc) CPUs $(date -u +%T); A = main $(cat A_COMMIT), B = rbstart $(cat B_COMMIT)"
clock_start
run E 45 $T/B --generate --sizes $SIZE --runs $RUNS --warmup $WU --shader-stats
run A0 20 $T/A --generate --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU --shader-stats
for r in 1 2 3 4; do for x in A B; do run $x$r 20 $T/$x --generate --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU; done; done
run KA 40 $T/A --generate --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU --views oblique,closeup --kernels $T/t_main_cin.spv@c1,$T/t_main_cout.spv@c1
run KB 45 $T/B --generate --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU --views oblique,closeup --kernels $T/t_main.spv@c1p0,@c1p0,$T/t_rb_cin.spv@c1,$T/t_rb_cout.spv@c1
payload_end rbstart
