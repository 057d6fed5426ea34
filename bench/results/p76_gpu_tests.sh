#!/bin/bash
# Stop 76 (issue 21): the render tests on the NVIDIA GPU with the grid walk on (a GPU builds the grids by default;
# test_render_gpu renders every scene with both walks against the CPU reference; test_render_hits: the hits frame
# of the 4096 terrain). Run with carry [".gl", "payload"] (payload/T_*.gz: the Release test binaries).
if command -v nvidia-smi >/dev/null; then for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json; fi
export LD_LIBRARY_PATH=$PWD/payload/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
T=/tmp/p76t; rm -rf $T; mkdir -p $T
for t in test_render_gpu test_render_hits; do gunzip -c payload/T_$t.gz > $T/$t; chmod +x $T/$t; done
R=${OUT:-/tmp}/p76_tests.txt
{
echo "== $(cat payload/REV | tr '\n' ' ') on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1)"
for t in test_render_hits test_render_gpu; do
  s=$(date +%s.%N); timeout ${TLIM:-200} $T/$t > $T/$t.log 2>&1; rc=$?
  echo "-- $t: exit $rc in $(echo "$(date +%s.%N) - $s" | bc) s"
  grep -E "CHECK failed|FAIL|passed,|hits frame|deep float, depth|SKIP" $T/$t.log | head -40
done
} 2>&1 | tee $R
