#!/bin/bash
# (run on the GPU machine from the repository root with the loader packages in .gl/ and the binaries in payload/bin68)
# stop 68: host specialisation on the NVIDIA driver: same bits (test_pipeline_cache's shared device forces it),
# the pass and photon tests with it forced, and the default frame's start-up with each, the driver's cache off.
for f in .gl/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
export LD_LIBRARY_PATH=$PWD/payload/lib
B=payload/bin68
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
$B/test_pipeline_cache 2>&1 | tail -28
echo "== test_passes, VX_GPU_SPECIALISE=1"; VX_GPU_SPECIALISE=1 $B/test_passes 2>&1 | tail -3
echo "== test_photons, VX_GPU_SPECIALISE=1"; VX_GPU_SPECIALISE=1 $B/test_photons 2>&1 | tail -3
$B/vox2svo payload/eph_monu1.vox /tmp/m.svo >/dev/null
$B/vox2svo payload/ogt_test_multiple_model_scene.vox /tmp/mm.svo >/dev/null
for scene in /tmp/m.svo /tmp/mm.svo; do
for args in "" "--passes gbuffer,direct,gi=pathtrace --spp 2" "--passes gbuffer,direct,gi=photons --spp 2"; do
  for s in 0 1 0 1 0 1; do
    rm -rf /tmp/nvc; mkdir -p /tmp/nvc
    __GL_SHADER_DISK_CACHE_PATH=/tmp/nvc VX_GPU_SPECIALISE=$s /usr/bin/time -f "%e" -o /tmp/t $B/svo_render $scene /tmp/o_$s.png $args >/dev/null 2>&1
    echo "$(basename $scene) [$args] specialise=$s $(cat /tmp/t) s"
  done
  cmp /tmp/o_0.png /tmp/o_1.png && echo "  same bytes"
done
done
