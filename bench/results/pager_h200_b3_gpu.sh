#!/bin/bash
# issue 18, branch pager, batch 3 (H200, <= 60 s): fly-throughs of the two sources. Batches 1 and 2 lost theirs
# (15,560 pages: the frames that swap thousands of pages took seconds in the service of both sources). Here
# the sphere 2048 in regions of 128 (fewer pages, made here), svo_render --layout compact --gpu-budget 16M
# --page-level 6 --fly 16 (after the image; -v a line a frame): the branch in memory, from the file with a
# host cache of 6M and of 32M; max RSS each.
set -u
export LD_LIBRARY_PATH=bench/out/base/bin
B=bench/out/pager/svo_render
G=bench/out/base/bin/svo_regions
T=/tmp/pager
rm -rf $T && mkdir -p $T
RES=${RES:-2048} REG=${REG:-128} LP=${LP:-6} GB=${GB:-16M} FLY=${FLY:-16} SIZE=${SIZE:-1920x1080} LIMIT=${LIMIT:-56}
TIMEV=""
[ -x /usr/bin/time ] && TIMEV="/usr/bin/time -v"
ms() { date +%s%N; }
T0=$(ms)
ARGS="--size $SIZE --mode albedo --layout compact --gpu-budget $GB --page-level $LP -v --fly $FLY"
run() { # label command...
  local lab=$1; shift
  local t0=$(ms)
  local left=$(( LIMIT - (t0 - T0) / 1000000000 ))
  [ $left -gt 17 ] && left=17
  if [ $left -lt 4 ]; then echo "-- $lab: skipped (the batch's time)"; return; fi
  echo "-- $lab: ${*:2}" | sed "s|$T/||g"
  timeout $left $TIMEV "$@" > $T/$lab.log 2>&1
  local rc=$?
  local rss=$(grep "Maximum resident" $T/$lab.log | awk '{printf "%.1f MiB", $6/1024}')
  echo "   rc=$rc process $(( ($(ms) - t0) / 1000000 )) ms, max RSS ${rss:-?}"
  grep -E "^gpu scene|^compact|^view|^paging|^fly|^render|rror" $T/$lab.log | cut -c1-230 | sed 's/^/   /'
}
echo "== $(date -u) $(uname -n) $(nproc) CPUs; sphere $RES in regions of $REG"
timeout 20 $G $T/s.svo --res $RES --region $REG > /dev/null || { echo "svo_regions failed"; exit 1; }
echo "   made in $(( ($(ms) - T0) / 1000000 )) ms, $(stat -c %s $T/s.svo) bytes"
run memory_fly $B $T/s.svo $T/memory_fly.ppm $ARGS
run file6_fly $B $T/s.svo $T/file6_fly.ppm $ARGS --host-budget 6M
run file32_fly $B $T/s.svo $T/file32_fly.ppm $ARGS --host-budget 32M
for v in file6_fly file32_fly; do
  [ -e $T/$v.ppm ] && [ -e $T/memory_fly.ppm ] && { cmp -s $T/memory_fly.ppm $T/$v.ppm && echo "$v == memory_fly (cmp)" || echo "$v DIFFERS"; }
done
echo "== done in $(( ($(ms) - T0) / 1000000 )) ms"
