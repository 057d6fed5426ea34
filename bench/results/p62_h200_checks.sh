#!/bin/bash
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
export LD_LIBRARY_PATH=$PWD/payload/lib
N=$PWD/payload/nv; cd /tmp
echo "== $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader | head -1)"
VX_TEST_ONLY=test_float_range,test_transforms,test_empty_and_single timeout 200 $N/test_render_gpu 2>&1 | grep -E 'ok|FAIL|CHECK|passed|device|scaled' | head -20
VX_TEST_ONLY=test_lights_replace_sun timeout 100 $N/test_cones 2>&1 | grep -E 'ok|FAIL|CHECK|passed' | head
$N/svo_render $N/gen__huge_scale.svo /tmp/x.pfm --mode pathtrace; echo "huge pathtrace rc=$?"
$N/svo_bake $N/gen__huge_scale.svo /tmp/x.probes --grid 2,2,2 --res 16 --spp 1; echo "huge bake rc=$? $(ls /tmp/x.probes 2>&1)"
$N/svo_bake $N/vengi__data_tests_test-transform.svo /tmp/t.probes --grid 3,3,3 --res 16 --spp 2 | grep -E '^device'; echo "bake rc=$?"
