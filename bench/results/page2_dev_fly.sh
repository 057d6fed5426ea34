#!/bin/bash
# issue 18, branch page2: the fly-through of paging from files on the dev VM (lavapipe, 2 cores shared with other
# helpers' builds: wall times are rough), main's svo_render (527d0fd) and the branch's in turn, built as for the GPU
# machine (build-gpu). The scene and command of branch pager's section: the helmet at 1024 in regions of 64
# (vox2svo khronos_DamagedHelmet.glb --res 1024 --region 64), svo_render --size 320x240 --mode albedo --layout
# compact --gpu-budget 6M --page-level 5 -v --fly 24, from the file with host caches of 4M and 16M and in memory.
# Usage: bench/results/page2_dev_fly.sh MAIN_SVO_RENDER BRANCH_SVO_RENDER HELMET.svo [ROUNDS] > page2_dev_fly.txt
set -u
M=$1 B=$2 H=$3 ROUNDS=${4:-1}
O=${TMPDIR:-/tmp}/page2_fly
rm -rf $O && mkdir -p $O
ARGS="--size 320x240 --mode albedo --layout compact --gpu-budget 6M --page-level 5 -v --fly 24"
run() { # label binary extra...
  local lab=$1 bin=$2; shift 2
  echo "-- $lab: $(basename $bin) $ARGS $*  (load $(cut -d' ' -f1 /proc/loadavg))"
  /usr/bin/time -v $bin $H $O/$lab.ppm $ARGS "$@" > $O/$lab.log 2>&1
  echo "   rc=$? max RSS $(grep 'Maximum resident' $O/$lab.log | awk '{printf "%.1f MiB", $6/1024}'), wall $(grep 'Elapsed (wall' $O/$lab.log | awk '{print $8}')"
  grep -E "^view|^paging|^fly-through|error" $O/$lab.log | cut -c1-260 | sed 's/^/   /'
}
echo "== $(date -u) $(uname -n), $(nproc) CPUs, load $(cut -d' ' -f1-3 /proc/loadavg)"
# a first run of each binary not counted (lavapipe compiles each kernel variant once; Mesa's disk cache after)
$M $H $O/warm.ppm $ARGS --fly 2 --host-budget 4M > /dev/null 2>&1
$B $H $O/warm.ppm $ARGS --fly 2 --host-budget 4M > /dev/null 2>&1
for r in $(seq 1 $ROUNDS); do
  run main_file4_$r $M --host-budget 4M
  run page2_file4_$r $B --host-budget 4M
  run page2_file16_$r $B --host-budget 16M
  run main_file16_$r $M --host-budget 16M
  run main_memory_$r $M
  run page2_memory_$r $B
done
for f in $O/page2_*.ppm; do
  b=$(basename $f .ppm)
  cmp -s $O/main_${b#page2_}.ppm $f && echo "$b == main_${b#page2_} (cmp)" || echo "$b DIFFERS from main_${b#page2_}"
done
echo "   per frame (round 1): frame, wall ms of main 4M, page2 4M, main 16M, page2 16M, main memory, page2 memory; pages loaded (page2 4M)"
paste <(grep "^fly [0-9]" $O/main_file4_1.log | awk '{print $2, $3}') <(grep "^fly [0-9]" $O/page2_file4_1.log | awk '{print $3}') \
  <(grep "^fly [0-9]" $O/main_file16_1.log | awk '{print $3}') <(grep "^fly [0-9]" $O/page2_file16_1.log | awk '{print $3}') \
  <(grep "^fly [0-9]" $O/main_memory_1.log | awk '{print $3}') <(grep "^fly [0-9]" $O/page2_memory_1.log | awk '{print $3}') \
  <(grep "^fly [0-9]" $O/page2_file4_1.log | sed 's/.* \([0-9]*\) loaded.*/\1/') | sed 's/^/   /'
echo "== $(date -u), load $(cut -d' ' -f1-3 /proc/loadavg)"
