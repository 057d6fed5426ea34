#!/bin/bash
# Stop 83 (issue 21), first run, the corpus scenes and the generated terrains: three builds alternating in processes, every view, ESVO in each
# process: A, 442a119's render_bench; PI, the candidate: a brick's two words of a z pair side by side, read in one
# 8-byte load by the grid walk's cell step, the bricks at multiples of 16 words (bench/results/p83_pair_layout.patch),
# and the depth map's four texel words in one 16-byte load (bench/results/p82e_smap_texels.patch, prepared at stop
# 82, never measured); order A1 PI1 A2 PI2, then the terrains (render_bench
# --generate: terrain1024 and terrain4096) A PI (cut to fit the session's last device time: no IL build alone, no
# second terrain pair, no test_render_smap on the GPU).
# Then PI's map off and on (--shadow-map off,0: the map must change no pixel), and the GPU tests of PI's tree:
# test_render_gpu (every walk's depth and albedo against the CPU reference).
# Carry [".gl", "payload"].
LIM=${LIM:-200}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_|^grid:|^shadow map"
payload_setup p83a test_render_gpu
A="payload/eph_monu1.vox payload/eph_menger.vox payload/eph_dragon.vox payload/ogt_doom.vox payload/ogt_test_multiple_model_scene.vox"
R=${OUT:-/tmp}/p83a.txt
{
echo "== $(cat payload/REV | tr '\n' ' ') on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
for b in pi; do gunzip -c payload/render_bench_$b.gz > $T/render_bench_$b; chmod +x $T/render_bench_$b; done
timeout 10 $T/render_bench --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
run A1 60 $T/render_bench --sizes $SIZE --runs $RUNS --warmup $WU $A
run PI1 60 $T/render_bench_pi --sizes $SIZE --runs $RUNS --warmup $WU $A
run A2 60 $T/render_bench --sizes $SIZE --runs $RUNS --warmup $WU $A
run PI2 60 $T/render_bench_pi --sizes $SIZE --runs $RUNS --warmup $WU $A
for k in 1; do
  run tA$k 60 $T/render_bench --generate --sizes $SIZE --runs $RUNS --warmup $WU
  run tPI$k 60 $T/render_bench_pi --generate --sizes $SIZE --runs $RUNS --warmup $WU
done
run mapsPI 20 $T/render_bench_pi --no-esvo --views overview --shadow-map off,0 --sizes $SIZE --runs $RUNS --warmup $WU payload/eph_menger.vox
payload_end p83a
# (test_render_gpu left out: the device time left did not hold it; its lavapipe run passed)
} 2>&1 | tee $R
