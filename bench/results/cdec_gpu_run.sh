#!/bin/bash
# cdec (issue 18): the cheaper exact decode (compact_attr.glsl decode_value) against main's compact_bench (REV: 54224d6).
# Binaries cb_X.gz: M = main's compact_bench, B = cdec 82de5e0 (the cheaper decode); batch 1 also C = 0d5cdfa (B + the width
# table), batch 2 D = 9c864ab (B + width headers) and E = 33d211c (D + palette headers). Processes in
# turn M B ... M B ... while time is left; the first of each with --shader-stats. SIZE, REPS, END, TER, SLOW
# (the limits times SLOW): smaller runs on lavapipe.
D=$PWD; T=/tmp/${NAME:-cdec}; rm -rf $T; mkdir -p $T
for f in $D/cb_*.gz; do gzip -dc $f > $T/$(basename $f .gz); done; chmod +x $T/cb_*
cp $D/helmet512.svo $D/eph_monu1.vox $T/; cd $T
END=${END:-270}
V=$(ls cb_* | sed 's/^cb_//' | grep -v '^M$' | sort | tr '\n' ' ')
echo "== cdec, $(date -u), main $(cat $D/REV 2>/dev/null), variants M $V"; nproc; cat /proc/loadavg
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.mem,temperature.gpu --format=csv,noheader 2>/dev/null
md5sum cb_*
T0=$(date +%s); t() { echo $(( $(date +%s) - T0 )); }
G="--gpu ${SIZE:-1920x1080} --reps ${REPS:-30}"; ALL="eph_monu1.vox helmet512.svo --terrain ${TER:-1024}"
run() { # who need_s max_s bin args...
  who=$1 need=$2 max=$(( $3 * ${SLOW:-1} )) bin=$4; shift 4
  tob=$(( END - $(t) )); [ $tob -gt $max ] && tob=$max
  if [ $tob -lt $need ]; then echo "=== skip $who t=$(t)"; return 1; fi
  echo "=== $who t=$(t)"
  timeout $tob $bin "$@" > $T/k_$who.txt 2>&1
  echo "rc=$? t=$(t)"
  grep -v "^|\|^stats\|^device\|^$" $T/k_$who.txt | sort | uniq -c | head -5
  grep "^| .* | \(overview\|close-up\)" $T/k_$who.txt | cut -d"|" -f2-10,14 | sed "s/^/$who |/"
  grep "^stats: trace compact" $T/k_$who.txt | grep -v misses | sort -u | sed 's/ CS (subgroup 32)//; s/Register Count/R/; s/Binary Size/bin/; s/Shared Memory Size/shm/; s/Local Memory Size=6871947/lmem=/; s/Stack Size/stk/' | cut -c1-150
  return 0
}
run M1 8 20 $T/cb_M --shader-stats $G $ALL
for v in $V; do run ${v}1 8 20 $T/cb_$v --shader-stats $G $ALL; done
for round in 2 3 4 5 6 7 8 9 10; do
  run M$round 8 14 $T/cb_M $G $ALL || break
  for v in $V; do run $v$round 8 14 $T/cb_$v $G $ALL || break 2; done
done
echo "=== end t=$(t)"
