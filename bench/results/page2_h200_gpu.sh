#!/bin/bash
# issue 18, branch page2, the H200's batches (BATCH=1, 2 or 3; the three payloads' run.sh merged into one file:
# the same runs, arguments and caps; batch 1's cmp loop compared each page2 image with main's of the same label).
# Fly-throughs of a paged scene, main's svo_render (527d0fd) and the branch's in turn in one run, 1920x1080 albedo,
# svo_render --layout compact --page-level 6 -v --fly N after the still image (which repeats its frame until the
# view's pages are resident). Scene A, pager batch 3's: the sphere 2048 in regions of 128, --gpu-budget 16M.
# Scene B, pager batch 2's: the sphere 4096 in regions of 128 (15,560 pages; the view needs more than the pool),
# --gpu-budget 40M. Usage (device): BATCH=N [LIMIT=S] bash page2_h200_gpu.sh; batch 1 ran with LIMIT=80, batch 3
# with LIMIT=30 FLY=8. Batch 1 (the branch at d12bc99): scene A from the file (32M twice, 6M) and in memory, A B then
# B A. Batch 2 (1ea14cc): scene A (32M, 6M, memory) and scene B (16M, memory). Batch 3: scene B in memory, 8 frames.
# (cwd bench/out/gpuq/page2 on the device, the binaries gzipped beside it; LIMIT: seconds for the whole script)
set -u
T=/tmp/${NAME:-page2}
rm -rf $T && mkdir -p $T
for b in svo_render svo_render_main svo_regions; do gunzip -c $b.gz > $T/$b && chmod +x $T/$b; done
LIB=$(cd ../lib 2>/dev/null && pwd)
[ -n "$LIB" ] && export LD_LIBRARY_PATH=$LIB${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
RES=${RES:-2048} RES2=${RES2:-4096} REG=${REG:-128} LP=${LP:-6} GB=${GB:-16M} GB2=${GB2:-40M} FLY=${FLY:-16}
SIZE=${SIZE:-1920x1080} LIMIT=${LIMIT:-66} CAP=${CAP:-14} BATCH=${BATCH:-2}
TIMEV=""
[ -x /usr/bin/time ] && TIMEV="/usr/bin/time -v"
ms() { date +%s%N; }
T0=$(ms)
ARGS0="--size $SIZE --mode albedo --layout compact --page-level $LP -v --fly $FLY"
ARGS="$ARGS0 --gpu-budget $GB" S=s
run() { # label binary extra-args...
  local lab=$1 bin=$2; shift 2
  local t0=$(ms)
  local left=$(( LIMIT - (t0 - T0) / 1000000000 - 2 ))
  [ $left -gt $CAP ] && left=$CAP
  if [ $left -lt 3 ]; then echo "-- $lab: skipped (the batch's time)"; return; fi
  echo "-- $lab: $bin $S.svo $ARGS $*"
  timeout $left $TIMEV $T/$bin $T/$S.svo $T/$lab.ppm $ARGS "$@" > $T/$lab.log 2>&1
  local rc=$?
  local rss=$(grep "Maximum resident" $T/$lab.log | awk '{printf "%.1f MiB", $6/1024}')
  echo "   rc=$rc process $(( ($(ms) - t0) / 1000000 )) ms, max RSS ${rss:-?}, limit $left s"
  grep -E "^gpu scene|^compact|^view|^paging|^fly-through|^render|rror" $T/$lab.log | cut -c1-260 | sed 's/^/   /'
  grep -E "^fly [0-9]" $T/$lab.log | sed 's/; host cache.*//; s/^/   /'
}
echo "== $(date -u) $(uname -n) $(nproc) CPUs, load $(cut -d' ' -f1-3 /proc/loadavg); $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1)"
[ $BATCH != 3 ] && { timeout 30 $T/svo_regions $T/s.svo --res $RES --region $REG > /dev/null || { echo "svo_regions failed"; exit 1; }; }
[ $BATCH != 1 ] && { timeout 30 $T/svo_regions $T/b.svo --res $RES2 --region $REG > /dev/null || { echo "svo_regions failed"; exit 1; }; }
echo "   spheres made in $(( ($(ms) - T0) / 1000000 )) ms (batch $BATCH)"
case $BATCH in
1)
  run main_file32_1 svo_render_main --host-budget 32M
  run page2_file32_1 svo_render --host-budget 32M
  run page2_memory_1 svo_render
  run main_memory_1 svo_render_main
  run page2_file6_1 svo_render --host-budget 6M
  run page2_file32_2 svo_render --host-budget 32M
  run main_file32_2 svo_render_main --host-budget 32M
  run main_memory_2 svo_render_main
  run page2_memory_2 svo_render
  run main_file6_1 svo_render_main --host-budget 6M ;;
2)
  run page2_file32_1 svo_render --host-budget 32M
  run main_file32_1 svo_render_main --host-budget 32M
  run page2_file6_1 svo_render --host-budget 6M
  run page2_memory_1 svo_render
  ARGS="$ARGS0 --gpu-budget $GB2" S=b
  CAP=12
  run page2_big16_1 svo_render --host-budget 16M
  run page2_bigmem_1 svo_render
  CAP=9
  run main_big16_1 svo_render_main --host-budget 16M
  run main_bigmem_1 svo_render_main ;;
3)
  ARGS="$ARGS0 --gpu-budget $GB2" S=b CAP=20
  run page2_bigmem_1 svo_render
  run main_bigmem_1 svo_render_main ;;
esac
echo "== still images against main's (cmp)"
for pair in page2_file32_1:main_file32_1 page2_file6_1:main_file32_1 page2_memory_1:main_file32_1 \
            page2_big16_1:main_big16_1 page2_bigmem_1:main_bigmem_1 page2_big16_1:page2_bigmem_1; do
  a=$T/${pair%%:*}.ppm b=$T/${pair##*:}.ppm
  if [ -e $a ] && [ -e $b ]; then cmp -s $a $b && echo "   ${pair%%:*} == ${pair##*:}" || echo "   ${pair%%:*} DIFFERS from ${pair##*:}"
  else echo "   ${pair%%:*} / ${pair##*:}: not both written"; fi
done
echo "== summary: label, still-view convergence, fly-through median"
for l in $T/*.log; do
  printf "   %-16s %s | %s\n" $(basename $l .log) "$(grep -o 'after [0-9]* frames [0-9]* resident' $l | head -1)" \
    "$(grep -o 'median [0-9.]* ms a frame (min [0-9.]*, max [0-9.]*; GPU median [0-9.]* ms)' $l | head -1)"
done
echo "== done in $(( ($(ms) - T0) / 1000000 )) ms"
