#!/bin/bash
# Stop 79 (issue 21), first run: main with branch exact-t's cheaper exact entry t merged and the single
# instance's grid words packed in the frame block (gbox_lo, grid0, gbox_hi), the five corpus scenes and the
# generated terrains against ESVO as committed; then DamagedHelmet at 1024 cells twice, as vox2svo makes it
# (8 regions of 512 under the BVH) and as one model (--region 1024, the single-instance kernel), each against
# ESVO in one process: what the regions cost; then test_render_hits, test_passes and test_render_gpu on the GPU.
# Run with carry [".gl", "payload"]: payload/ holds render_bench.gz, vox2svo.gz and T_*.gz (Release), REV, lib/,
# the five corpus .vox files and khronos_DamagedHelmet.glb.
if command -v nvidia-smi >/dev/null; then for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json; fi
export LD_LIBRARY_PATH=$PWD/payload/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
T=/tmp/p79a; rm -rf $T; mkdir -p $T
for b in render_bench vox2svo; do gunzip -c payload/$b.gz > $T/$b; chmod +x $T/$b; done
for t in test_passes test_render_gpu test_render_hits; do gunzip -c payload/T_$t.gz > $T/$t; chmod +x $T/$t; done
LIM=${LIM:-300}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_|^helmet|^stats|^grid:|^\||^#|^##"
V="payload/eph_monu1.vox payload/eph_menger.vox payload/eph_dragon.vox payload/ogt_doom.vox payload/ogt_test_multiple_model_scene.vox"
R=${OUT:-/tmp}/p79a.txt
{
echo "== $(cat payload/REV | tr '\n' ' ') on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
$T/vox2svo payload/khronos_DamagedHelmet.glb $T/helmet1024.svo --res 1024 | grep -E "models|output"
$T/vox2svo payload/khronos_DamagedHelmet.glb $T/helmet1024r.svo --res 1024 --region 1024 | grep -E "models|output"
clock_start
timeout 10 $T/render_bench --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
run terrain 90 $T/render_bench --shader-stats --generate --sizes $SIZE --runs $RUNS --warmup $WU
run corpus 60 $T/render_bench --sizes $SIZE --runs $RUNS --warmup $WU $V
run helmet 60 $T/render_bench --shader-stats --grid-world --sizes $SIZE --runs $RUNS --warmup $WU $T/helmet1024.svo $T/helmet1024r.svo
payload_end p79a
for t in test_render_hits test_passes test_render_gpu; do
  s=$(date +%s); timeout ${TLIM:-120} $T/$t > $T/$t.log 2>&1; rc=$?
  echo "-- $t: exit $rc in $(( $(date +%s) - s )) s"
  grep -E "CHECK failed|FAIL|passed,|hits frame|deep float, depth|SKIP|mixed root|root level 2 only" $T/$t.log | head -40
done
} 2>&1 | tee $R
