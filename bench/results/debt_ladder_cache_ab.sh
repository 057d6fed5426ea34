#!/bin/bash
# test_compact_gpu on lavapipe: main's compact kernel (A: its own copy of the stack ladder) against the same
# kernel with trace_common.glsl's ladder text (X: the shared form), each with its own Mesa shader cache,
# first cold (an empty cache) then warm; vk_time_shim.so splits the time into vkCreateComputePipelines
# (SPIR-V to NIR) and the waits for the device (on lavapipe the first dispatch of a kernel compiles it
# with LLVM unless the cache holds it, then the dispatches run).
S=$(dirname $0)
ONLY=${1:-}
for k in cold warm; do for v in A X; do
  [ $k = cold ] && rm -rf /tmp/debt_mesa_$v
  /usr/bin/time -f "$v $k: %e s wall, %U s user, %S s sys" env LD_PRELOAD=$S/vk_time_shim.so \
    MESA_SHADER_CACHE_DIR=/tmp/debt_mesa_$v ${ONLY:+VX_TEST_ONLY=$ONLY} $S/test_compact_gpu.$v 2>&1 | tail -3
done; done
