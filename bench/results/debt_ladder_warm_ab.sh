#!/bin/bash
# Warm caches only: test_compact_gpu's sub-test $1 with A (the compact kernel's own ladder copy) and X (the shared
# text), alternating process by process, $2 rounds; each with its own Mesa shader cache, warmed by one run first.
S=$(dirname $0); ONLY=$1; N=${2:-3}
for v in A X; do
  MESA_SHADER_CACHE_DIR=/tmp/debt_mesa_$v VX_TEST_ONLY=$ONLY $S/test_compact_gpu.$v > /dev/null 2>&1
done
for i in $(seq 1 $N); do for v in A X; do
  /usr/bin/time -f "$v warm round $i: %e s wall, %U s user, %S s sys" env LD_PRELOAD=$S/vk_time_shim.so \
    MESA_SHADER_CACHE_DIR=/tmp/debt_mesa_$v VX_TEST_ONLY=$ONLY $S/test_compact_gpu.$v 2>&1 | tail -2
done; done
