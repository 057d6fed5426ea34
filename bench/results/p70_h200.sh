#!/bin/bash
# Issue 21 (stop 70): on one fresh H200, main 8bec8ee (the stop 69 head; no trace-loop change since stop 66):
# (1) test_render_hits (the 4096 terrain's hits frame under 1 s), (2) the bench table with ESVO in the same
# processes, (3) the trace kernels from modules specialised on the host (VX_GPU_SPECIALISE=1) against the driver's
# own specialisation (0), alternately, two rounds, without ESVO (stop 68's open question, p68_h200_trace_spec.sh),
# (4) the beam pass (--beam 8, 16) against none with today's kernels.
# Run with carry [".gl", "payload"]: payload/ holds render_bench.gz and test_render_hits.gz (build/, Release), REV,
# lib/ (libz, libzstd, libdeflate) and the five corpus .vox files. Lavapipe dry run: SIZE=96x54 RUNS=1 WU=0 TS=20.
if command -v nvidia-smi >/dev/null; then for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json; fi
export LD_LIBRARY_PATH=$PWD/payload/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
T=/tmp/p70; rm -rf $T; mkdir -p $T
for b in render_bench test_render_hits; do gunzip -c payload/$b.gz > $T/$b; chmod +x $T/$b; done
LIM=${LIM:-560}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_|^stats"
V="payload/eph_monu1.vox payload/eph_menger.vox payload/eph_dragon.vox payload/ogt_doom.vox payload/ogt_test_multiple_model_scene.vox"
echo "== main $(cat payload/REV) on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
echo "-- test_render_hits $(date -u +%T)"
( time timeout $((90 * ${TS:-1})) $T/test_render_hits ) 2>&1 | grep -v "^$" | stamp
timeout 10 $T/render_bench --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
run corpus 130 $T/render_bench --sizes $SIZE --runs $RUNS --warmup $WU $V
run terrain 120 $T/render_bench --generate --sizes $SIZE --runs $RUNS --warmup $WU
for r in 1 2; do for s in 0 1; do
  export VX_GPU_SPECIALISE=$s; X=; [ $r = 1 ] && X=--shader-stats
  run "c${r}s$s" 60 $T/render_bench --no-esvo $X --sizes $SIZE --runs $RUNS --warmup $WU $V
  run "t${r}s$s" 60 $T/render_bench --no-esvo $X --generate --sizes $SIZE --runs $RUNS --warmup $WU
done; done
unset VX_GPU_SPECIALISE
# (4) the beam pass (off by default since the H100's table, before the later sittings' kernels) against none, today's kernels
run beam 90 $T/render_bench --no-esvo --beam 0,8,16 --sizes $SIZE --runs $RUNS --warmup $WU $V
run tbeam 90 $T/render_bench --no-esvo --beam 0,8 --generate --sizes $SIZE --runs $RUNS --warmup $WU
payload_end p70
