#!/bin/bash
# (not run in stop 68: no device was lent at the end of the session; needs payload/bin68 with render_bench from build-gpu)
# stop 68: the trace kernels' speed on the H200 from modules specialised on the host (VX_GPU_SPECIALISE=1) against the
# driver's specialisation (0), alternately, the corpus scenes' 15 views at 1920x1080
for f in .gl/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
export LD_LIBRARY_PATH=$PWD/payload/lib
B=payload/bin68
nvidia-smi --query-gpu=name,driver_version,clocks.sm --format=csv,noheader
timeout 10 $B/render_bench --no-esvo --sizes 1920x1080 --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
for r in 1 2; do for s in 0 1; do
  echo "== round $r VX_GPU_SPECIALISE=$s"
  VX_GPU_SPECIALISE=$s $B/render_bench --sizes 1920x1080 --runs 15 --warmup 0.5 payload/eph_monu1.vox payload/eph_menger.vox payload/eph_dragon.vox payload/ogt_doom.vox payload/ogt_test_multiple_model_scene.vox 2>&1 | grep -E "overview|oblique|closeup" | grep -v texels
done; done
