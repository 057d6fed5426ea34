#!/bin/bash
# gbvh (issue 21, twenty-fourth sitting), batch 1: the lean walk in the G-buffer's BVH kernels (gbuffer.comp,
# frame.comp: TRACE_LEAN_BVH). A = main's library and kernels, B = the branch's; both with the branch's
# passes_bench.c (its --gbuffer, --check and SCENE@CAMERA;... are new). render_bench's three views
# (bench/results/gbvh_views.c) of ogt_test_multiple_model_scene (several instances: the kernels that changed),
# ogt_test_groups (several instances; checked only), eph_monu1 and terrain4096 (one instance: the same kernels,
# controls). 1: --check: A writes the G-buffer's images (show albedo, normal, depth, instance, material:
# gbuffer.comp) and the frame's (gbuffer,direct merged: frame.comp, and separate), B compares them value for value.
# 2: render_bench --shader-stats (registers of gbuffer.comp and frame.comp), A and B. 3: passes_bench --gbuffer
# process by process A B A B A B: rows "gbuffer" (frame.comp with resolve), "gbuffer (separate passes)" (gbuffer.comp)
# and "gbuffer,direct" (frame.comp, svo_render's default), ms per frame, medians of RUNS frames after WU s of each
# row's frame. Clocks: nvidia-smi every 200 ms (log in $OUT/gbvh.tar.gz) and before each process.
# SIZE, RUNS, WU, TS (time scale) may be set (lavapipe: SIZE=160x90 RUNS=1 WU=0 TS=20).
BATCH=1; BINS="passes_bench render_bench"; . "${GBVH_LIB:-$(dirname "$0")/gbvh_gpu_lib.sh}" # (the payload had these lines inline)
SIZE=${SIZE:-1920x1080}; RUNS=${RUNS:-21}; WU=${WU:-0.25}; LIM=${LIM:-115}
E="eph_monu1.vox@default;-100.297822,-85.9695617,42.9847808,0,0,0;-17.3319618,-14.8559673,7.42798364,-12.9999926,-11.1428508,5.5714254"
R="terrain:4096@default;-1281.41587,-805.785031,3474.89252,2048,2048,2048;2829.24215,2606.20062,1736.78004,2850.00668,2623.43589,1728.00016"
# timed: the multi-instance scene's three views, the controls' oblique and close-up (terrain last: its generation
# idles the GPU for about 1.5 s)
E2="eph_monu1.vox@-100.297822,-85.9695617,42.9847808,0,0,0;-17.3319618,-14.8559673,7.42798364,-12.9999926,-11.1428508,5.5714254"
R2="terrain:4096@-1281.41587,-805.785031,3474.89252,2048,2048,2048;2829.24215,2606.20062,1736.78004,2850.00668,2623.43589,1728.00016"
echo "-- 1: check, A writes, B compares ($SIZE) $(date -u +%T): clock $(smi)"
for x in A B; do
  l=$(left $LIM); [ $l -gt 5 ] || { echo "   no time left"; break; }
  timeout $l $T/${x}_passes_bench --gbuffer --runs 1 --size $SIZE --check $T/chk "$M" "$G" "$E" "$R" 2>&1 | tee $T/check_$x.txt | grep --line-buffered -E '^check|^##|passes_bench' | grep --line-buffered -v 'written to' | sed -u "s|$T/chk/||; s/^/$x /" | stamp
done
echo "   A wrote $(grep -c 'written to' $T/check_A.txt) images"
echo "   B's checks: $(grep -c ' 0 of .* pixels differ' $T/check_B.txt) of $(grep -c '^check' $T/check_B.txt) with 0 pixels different; others: $(grep '^check' $T/check_B.txt | grep -vc ' 0 of ')"
echo "-- 2: shader stats (render_bench --shader-stats, multi-instance close-up, one small frame; gbuffer and frame are the passes') $(date -u +%T)"
for x in A B; do
  l=$(left $LIM); [ $l -gt 8 ] && [ $l -gt $((30 * ${TS:-1})) ] || { echo "   no time left"; break; }
  timeout 15 $T/${x}_render_bench --no-esvo --sizes 192x108 --runs 1 --warmup 0 --views closeup --shader-stats ogt_test_multiple_model_scene.vox 2>&1 | grep --line-buffered -E '^stats: ' | cut -c1-330 | sed -u "s/^/$x /" | stamp
done
echo "-- 3: passes_bench --gbuffer A B A B A B (--runs $RUNS --warmup $WU --size $SIZE) $(date -u +%T)"
run() { # binary round: one process, if 15 s (scaled) of the limit are left
  local x=$1 r=$2; local l=$(left $LIM); [ $l -gt $((15 * ${TS:-1})) ] || { echo "   $x$r: no time left"; return; }
  echo "   $x$r: clock $(smi)"
  timeout $l $T/${x}_passes_bench --gbuffer --runs $RUNS --warmup $WU --size $SIZE "$M" "$E2" "$R2" 2>&1 | grep --line-buffered -E '^#|^\| [a-z]|passes_bench' | sed -u "s/^/$x$r /" | stamp
}
run A 1; run B 1; run A 2; run B 2; run A 3; run B 3
finish
