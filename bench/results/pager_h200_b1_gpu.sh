#!/bin/bash
# issue 18, branch pager, batch 1 (H200): paging from files. svo_render --layout compact under a GPU budget
# that pages the layout: main's binary (eb010c8; the in-memory pager: the layout built from the reader, its
# pages cut in memory), the branch's without --host-budget (the same path) and with --host-budget (the file
# source: the top and a host cache of page images, pages cut again from their models read from the file),
# process by process (ABC), two rounds: max RSS, the load, the frames until the view is resident, the timed
# frames (GPU median), the images compared; then the branch's two sources with --fly 48 (a fly-through).
# The scene: the sphere 2048 in 3,944 regions of 64 (bench/svo_regions, 16.0 M cells), made here.
set -u
export LD_LIBRARY_PATH=bench/out/base/bin
M=bench/out/base/bin/svo_render
B=bench/out/pager/svo_render
G=bench/out/base/bin/svo_regions
T=/tmp/pager
rm -rf $T && mkdir -p $T
RES=${RES:-2048} REG=${REG:-64} LP=${LP:-5}
GB=${GB:-12M} HB=${HB:-8M} SIZE=${SIZE:-1920x1080} LIMIT=${LIMIT:-76}
TIMEV=""
[ -x /usr/bin/time ] && TIMEV="/usr/bin/time -v"
nvidia-smi --query-gpu=timestamp,clocks.sm,pstate,utilization.gpu,memory.used --format=csv,noheader -lms 100 > $T/smi.csv 2>&1 &
SMI=$!
ms() { date +%s%N; }
T0=$(ms)
ARGS="--size $SIZE --mode albedo --layout compact --gpu-budget $GB --page-level $LP -v"
run() { # label command...
  local lab=$1; shift
  local t0=$(ms)
  local left=$(( LIMIT - (t0 - T0) / 1000000000 ))
  [ $left -gt 20 ] && left=20
  if [ $left -lt 4 ]; then echo "-- $lab: skipped (the batch's time)"; return; fi
  echo "-- $lab: ${*:2}" | sed "s|$T/||g"
  timeout $left $TIMEV "$@" > $T/$lab.log 2>&1
  local rc=$?
  local rss=$(grep "Maximum resident" $T/$lab.log | awk '{printf "%.1f MiB", $6/1024}')
  echo "   rc=$rc process $(( ($(ms) - t0) / 1000000 )) ms, max RSS ${rss:-?}"
  grep -E "^read|^device|^gpu scene|^layout|^compact|^view|^paging|^note|^warm|^frames|^fly-through|^render|rror" $T/$lab.log | cut -c1-260 | sed 's/^/   /'
}
echo "== $(date -u) $(uname -n) $(nproc) CPUs; sphere $RES in regions of $REG"
timeout 30 $G $T/s.svo --res $RES --region $REG > /dev/null || { echo "svo_regions failed"; exit 1; }
echo "   made in $(( ($(ms) - T0) / 1000000 )) ms, $(stat -c %s $T/s.svo) bytes"
for r in 1 2; do
  run main_$r $M $T/s.svo $T/main_$r.ppm $ARGS --frames 11
  run memory_$r $B $T/s.svo $T/memory_$r.ppm $ARGS --frames 11
  run file_$r $B $T/s.svo $T/file_$r.ppm $ARGS --frames 11 --host-budget $HB
done
for r in 1 2; do
  [ -e $T/main_$r.ppm ] || continue
  for v in memory file; do
    [ -e $T/${v}_$r.ppm ] && { cmp -s $T/main_$r.ppm $T/${v}_$r.ppm && echo "round $r: $v == main (cmp)" || echo "round $r: $v DIFFERS from main"; }
  done
done
run memory_fly $B $T/s.svo $T/memory_fly.ppm $ARGS --fly 48
run file_fly $B $T/s.svo $T/file_fly.ppm $ARGS --fly 48 --host-budget $HB
for v in memory_fly file_fly; do
  [ -e $T/$v.log ] && { echo "   $v per frame:"; grep "^fly [0-9]" $T/$v.log | cut -c1-200 | sed 's/^/     /'; }
done
kill $SMI 2>/dev/null
awk -F', ' '{print $2}' $T/smi.csv | sort | uniq -c | sort -rn | head -4 | sed 's/^/   sm clock samples: /'
awk -F', ' '{print $5}' $T/smi.csv | sort -t' ' -k1 -n | tail -1 | sed 's/^/   GPU memory used, max sample: /'
if [ -n "${OUTDIR:-}" ]; then cp $T/*.log "$OUTDIR"/ 2>/dev/null; fi
echo "== done in $(( ($(ms) - T0) / 1000000 )) ms"
