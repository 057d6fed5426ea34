#!/bin/bash
# issue 18, branch page2, H200 batch 3 (small): scene B of batch 2 (the sphere 4096 in regions of 128, 15,560
# pages; the view needs more than the 40M pool) in memory, main's binary (527d0fd) and the branch's in the same
# run, a fly-through of 8 frames each (batch 2 cut main's runs at 9 s, before their fly-throughs).
# Usage (device): bash run.sh  (cwd bench/out/gpuq/page2; LIMIT seconds for the whole script, default 80)
set -u
T=/tmp/${NAME:-page2}
rm -rf $T && mkdir -p $T
for b in svo_render svo_render_main svo_regions; do gunzip -c $b.gz > $T/$b && chmod +x $T/$b; done
LIB=$(cd ../lib 2>/dev/null && pwd)
[ -n "$LIB" ] && export LD_LIBRARY_PATH=$LIB${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
RES=${RES:-2048} RES2=${RES2:-4096} REG=${REG:-128} LP=${LP:-6} GB=${GB:-16M} GB2=${GB2:-40M} FLY=${FLY:-8}
SIZE=${SIZE:-1920x1080} LIMIT=${LIMIT:-30} CAP=${CAP:-20}
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
echo "   sphere $RES2 in regions of $REG"
timeout 30 $T/svo_regions $T/b.svo --res $RES2 --region $REG > /dev/null || { echo "svo_regions failed"; exit 1; }
echo "   made in $(( ($(ms) - T0) / 1000000 )) ms, $(stat -c %s $T/b.svo) bytes"
ARGS="$ARGS0 --gpu-budget $GB2" S=b
run page2_bigmem_1 svo_render
run main_bigmem_1 svo_render_main
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
