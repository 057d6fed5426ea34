#!/bin/bash
# Stop 64: the issue-21 bake goal (512 probes, R=128, 64 spp, whole process < 0.6 s on the Cornell box) measured
# again after probes63 moved an explicit grid's probes a quarter cell past the bounds. base = 19520e6 (cell-centre
# placement), main = this stop's binary; processes alternated, wall from $EPOCHREALTIME, 2 first (cache) runs each.
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
export LD_LIBRARY_PATH=$PWD/payload/lib
nvidia-smi --query-gpu=name,driver_version,clocks.sm --format=csv,noheader
P=payload; O=/tmp/bake
for b in base main; do for i in 1 2; do $P/svo_bake_$b $P/cornell.svo $O-$b.probes --grid 8,8,8 --res 128 --spp 64 -q >/dev/null 2>&1; done; done
for r in $(seq 1 11); do
  for b in base main; do
    s=$EPOCHREALTIME; $P/svo_bake_$b $P/cornell.svo $O-$b.probes --grid 8,8,8 --res 128 --spp 64 -q -v > /tmp/v-$b.txt 2>&1; e=$EPOCHREALTIME
    echo "$b round $r wall $(awk -v a=$s -v b=$e 'BEGIN{printf "%.3f", b-a}')"; cp /tmp/v-$b.txt ${OUT:-/tmp}/v-$b-$r.txt
  done
done
ls -l $O-*.probes
