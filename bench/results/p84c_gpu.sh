#!/bin/bash
# Stop 84 (issue 21), the two short runs after p84b_gpu.sh on the same H100 (logs p84c_h100.txt, p84d_h100.txt): main's
# depth map alone (payload/render_bench_il.gz, 5731c2e's code) against 442a119 (payload/render_bench.gz), one process
# each, terrain4096's overview timed again among them; then main's shader statistics (p84d). No 2 s warm-up (the
# runs fit the device time left; render_bench's own --warmup per kernel and view). Carry [".gl", "payload"].
LIM=${LIM:-110}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_|^shadow map"
payload_setup p84c
gunzip -c payload/render_bench_il.gz > $T/il; chmod +x $T/il
V="payload/eph_menger.vox payload/eph_monu1.vox payload/eph_dragon.vox payload/ogt_test_multiple_model_scene.vox"
{
echo "== A $(cat payload/REV) / IL main on $(gpu_name)"
clock_start
run tA 30 $T/render_bench --no-esvo --generate --views overview --sizes $SIZE --runs $RUNS --warmup $WU
run tIL 30 $T/il --no-esvo --generate --views overview --sizes $SIZE --runs $RUNS --warmup $WU
run A 16 $T/render_bench --no-esvo --views overview,closeup --sizes $SIZE --runs $RUNS --warmup $WU $V
run IL 16 $T/il --no-esvo --views overview,closeup --sizes $SIZE --runs $RUNS --warmup $WU $V
payload_end p84c
} 2>&1 | tee ${OUT:-/tmp}/p84c.txt
timeout 40 $T/il --shader-stats --no-esvo --views closeup --sizes 1920x1080 --runs 3 --warmup 0 payload/eph_monu1.vox \
  payload/ogt_test_multiple_model_scene.vox 2>&1 | grep -E "^stats|^device|^eph|^ogt" | cut -c1-400 | tee ${OUT:-/tmp}/p84d.txt
