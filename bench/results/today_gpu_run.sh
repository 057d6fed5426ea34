#!/bin/bash
# today (issue 18's speed goal as written; coordinator, stop 57): "primary-ray speed with the new layout within 10% of
# today's on the full-frame views", today = the day the issue was filed. O = today_bench built in the tree of that day
# (00625c1, the commit before issue 18's first, 521150f): trace.comp's albedo primary rays on compact_bench's two views;
# N = the same program built in main (1dff501): today's trace.comp; C = main's compact_bench (trace.comp and the
# compact kernel, trace_compact.comp, on the same views, every pixel compared). Processes O N C in turn, rounds while
# time is left; the first C with --shader-stats. Scenes: eph_monu1.vox, helmet512.svo (DamagedHelmet at 512^3, made
# by O's tree's vox2svo, read by every binary), the generated terrain at 1024. SIZE, REPS, TER: smaller on lavapipe.
T=/tmp/today; rm -rf $T; mkdir -p $T; for x in O N C; do gunzip -c $x.gz > $T/$x; chmod +x $T/$x; done
cp eph_monu1.vox helmet512.svo $T/; cd $T; START=$(date +%s); LIM=${LIMIT:-300}
left() { echo $(( LIM - ($(date +%s) - START) )); }
echo "== today on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1), $(nproc) CPUs, $(date -u +%T) UTC"
md5sum O N C helmet512.svo eph_monu1.vox
A="--gpu ${SIZE:-1920x1080} --reps ${REPS:-30} eph_monu1.vox helmet512.svo --terrain ${TER:-1024}"
run() { # label max bin args
  local x=$1 mx=$2; shift 2; local l=$(left); [ $l -gt 10 ] || { echo "-- $x: no time left"; return 1; }; [ $l -gt $mx ] && l=$mx
  echo "-- $x $(date -u +%T) SM $(nvidia-smi --query-gpu=clocks.sm --format=csv,noheader 2>/dev/null | head -1)"
  timeout $l "$@" 2>&1 | grep -E "^\| (eph|helmet|terrain)|^stats: trace|rror" | grep -v "^stats: .*misses" | sed "s/^/$x /"
}
run C1 60 ./C --shader-stats $A
for r in 1 2 3 4 5; do run O$r 40 ./O $A || break; run N$r 40 ./N $A || break; [ $r = 1 ] || run C$r 60 ./C $A || break; done
echo "== done in $(( $(date +%s) - START )) s"
