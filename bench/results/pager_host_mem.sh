#!/bin/bash
# issue 18, branch pager: paging from files (svo_render --host-budget) against the in-memory pager, host memory
# and frame times on the dev VM (lavapipe, 2 cores shared with other jobs). The helmet at 1024 in regions of 64
# (vox2svo khronos_DamagedHelmet.glb --res 1024 --region 64: 1,244 models, 11.4 MB), --layout compact
# --gpu-budget 6M --page-level 5 (pages of 32^3 cells; the compact layout is about 12 MB): main's binary (the
# in-memory pager: the layout built from the reader, its pages cut in memory), the branch's without
# --host-budget (the same path) and with --host-budget 4M (the file source), process by process (ABC), two
# rounds, under /usr/bin/time -v; then each of the branch's sources with --fly 24 (a fly-through after the
# image: its frame times; the file source also with --host-budget 16M, more than the pages it touches). Both binaries built as for the GPU machine (build-gpu: no OIIO, OpenVDB, glTF).
# Usage: bench/results/pager_host_mem.sh MAIN_SVO_RENDER BRANCH_SVO_RENDER HELMET.svo > pager_host_mem.txt
set -u
M=$1 B=$2 H=$3
O=${TMPDIR:-/tmp}/pager_hm
rm -rf $O && mkdir -p $O
ARGS="--size 320x240 --mode albedo --layout compact --gpu-budget 6M --page-level 5 -v"
run() { # label command...
  local lab=$1; shift
  echo "-- $lab: $*"
  /usr/bin/time -v "$@" > $O/$lab.log 2>&1
  echo "   rc=$? max RSS $(grep 'Maximum resident' $O/$lab.log | awk '{printf "%.1f MiB", $6/1024}'), wall $(grep 'Elapsed (wall' $O/$lab.log | awk '{print $8}')"
  grep -E "^read|^gpu scene|^layout|^compact|^view|^paging|^note|^fly-through|^render|error" $O/$lab.log | cut -c1-260 | sed 's/^/   /'
}
echo "== $(date -u) $(uname -n), $(nproc) CPUs, load $(cut -d' ' -f1-3 /proc/loadavg)"
for r in 1 2; do
  run main_$r $M $H $O/main_$r.ppm $ARGS
  run memory_$r $B $H $O/memory_$r.ppm $ARGS
  run file_$r $B $H $O/file_$r.ppm $ARGS --host-budget 4M
done
for r in 1 2; do
  cmp -s $O/main_$r.ppm $O/memory_$r.ppm && cmp -s $O/main_$r.ppm $O/file_$r.ppm && echo "round $r: the three images equal (cmp)" ||
    echo "round $r: IMAGES DIFFER"
done
# a first fly-through of each, not counted: lavapipe compiles a kernel variant the first time it meets it
# (Mesa's shader cache on disk serves it afterwards), which a measured run must not pay alone
$B $H $O/warm.ppm $ARGS --fly 2 > /dev/null 2>&1
$B $H $O/warm.ppm $ARGS --fly 2 --host-budget 4M > /dev/null 2>&1
run memory_fly $B $H $O/memory_fly.ppm $ARGS --fly 24
run file_fly $B $H $O/file_fly.ppm $ARGS --fly 24 --host-budget 4M
run file16_fly $B $H $O/file16_fly.ppm $ARGS --fly 24 --host-budget 16M
echo "   per frame: frame, wall ms in memory, from the file with 4M, with 16M; the 4M run's pages loaded and cut from the file so far"
paste <(grep "^fly [0-9]" $O/memory_fly.log | awk '{print $2, $3}') <(grep "^fly [0-9]" $O/file_fly.log | awk '{print $3}') \
  <(grep "^fly [0-9]" $O/file16_fly.log | awk '{print $3}') \
  <(grep "^fly [0-9]" $O/file_fly.log | sed 's/.* \([0-9]*\) loaded.*, \([0-9]*\) cut from the file so far/\1 \2/') | sed 's/^/   /'
echo "== $(date -u), load $(cut -d' ' -f1-3 /proc/loadavg)"
