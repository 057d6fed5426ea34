#!/bin/bash
# lean4 (issue 18): three DEEP 1 variants of trace_compact.comp against main's kernel, one H200 payload.
# M = main's compact_bench (408d3f2); X = lean4's exploration build (bench/results/lean4_explore.patch):
# VX_LEAN4 (spec constant LV, DEEP 1 kernels only) 1 PUSH_BRICK, 2 SENT (desc 0 = not loaded), 4 the brick
# descriptor computed in the branch. Processes in turn M X1 X2 X4 M X1 X2 X4 ... while time is left.
# SIZE, REPS, END, TER: smaller runs on lavapipe.
D=$PWD; T=/tmp/${NAME:-lean4}; rm -rf $T; mkdir -p $T
for f in $D/*.gz; do gzip -dc $f > $T/$(basename $f .gz); done; chmod +x $T/*
cp $D/helmet512.svo $T/; cd $T
END=${END:-55}
echo "== lean4, $(date -u)"; nproc; cat /proc/loadavg
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.mem,temperature.gpu --format=csv,noheader 2>/dev/null
T0=$(date +%s); t() { echo $(( $(date +%s) - T0 )); }
G="--gpu ${SIZE:-1920x1080} --reps ${REPS:-30}"; SC="helmet512.svo --terrain ${TER:-1024}"
run() { # who need_s max_s bin
  who=$1 need=$2 max=$3 bin=$4
  tob=$(( END - $(t) )); [ $tob -gt $max ] && tob=$max
  if [ $tob -lt $need ]; then echo "=== skip $who t=$(t)"; return 1; fi
  echo "=== $who t=$(t) ${VX_LEAN4:+VX_LEAN4=$VX_LEAN4}"
  timeout $tob $bin $G $SC > $T/k_$who.txt 2>&1
  echo "rc=$? t=$(t)"
  grep -v "^|\|^stats\|^device\|^$" $T/k_$who.txt | sort | uniq -c | head -5
  grep "^| .* | \(overview\|close-up\)" $T/k_$who.txt | cut -d"|" -f2-10,14 | sed "s/^/$who |/"
}
M=$T/compact_bench_main; X=$T/compact_bench
for round in 1 2 3; do
  run M$round 6 12 $M || break
  for v in 1 2 4; do VX_LEAN4=$v run X$v.$round 6 12 $X || break 2; done
done
echo "=== end t=$(t)"
