#!/bin/bash
# lean3 batch 3 (issue 18): the kept form (the compact kernels' DEEP 0 primary push without the ray-end test; DEEP 1
# as main's) in one whole run, every view's compact / trace.comp ratio and bits (the last column: albedo pixels that
# differ from trace.comp's without hits); then test_compact_passes' room frames (the compact G-buffer's lean walk,
# trace_common.glsl, against the plain one's) while time is left. SIZE, REPS, END, SC: smaller runs on lavapipe.
D=$PWD; T=/tmp/${NAME:-lean3}; rm -rf $T; mkdir -p $T
for f in $D/*.gz; do gzip -dc $f > $T/$(basename $f .gz); done; chmod +x $T/*
cp $D/helmet512.svo $D/eph_monu1.vox $D/eph_menger.vox $T/
cd $T
END=${END:-35}
echo "== lean3 batch 3, $(date -u)"; nproc; cat /proc/loadavg
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.mem,temperature.gpu --format=csv,noheader 2>/dev/null
T0=$(date +%s); t() { echo $(( $(date +%s) - T0 )); }
SC=${SC:-"eph_monu1.vox eph_menger.vox helmet512.svo --terrain 1024"}
echo "=== K t=$(t)"
timeout 20 $T/compact_bench --shader-stats --gpu ${SIZE:-1920x1080} --reps ${REPS:-30} $SC > $T/k_K.txt 2>&1
echo "rc=$? t=$(t)"
grep -v "^|\|^stats\|^device\|^$" $T/k_K.txt | sort | uniq -c | head -5
grep "^| .* | \(overview\|close-up\)" $T/k_K.txt | cut -d'|' -f2-11,14 | sed "s/^/K |/"
grep "^stats: trace" $T/k_K.txt | grep -v misses | sort -u | sed 's/ CS (subgroup 32)//; s/Register Count/R/; s/Binary Size/bin/; s/Shared Memory Size/shm/; s/Local Memory Size=6871947/lmem=/; s/Stack Size/stk/' | cut -c1-150
l=$(( END - $(t) ))
if [ $l -gt 4 ]; then
  s=$(date +%s); VX_TEST_ONLY=test_room_frames timeout $l $T/test_compact_passes > $T/tp.log 2>&1; rc=$?
  echo "== test_compact_passes (test_room_frames) rc=$rc $(( $(date +%s) - s )) s: $(grep -E 'passed|failed' $T/tp.log | tail -1)"
  grep -c "0 floats differ" $T/tp.log; grep "CHECK failed" $T/tp.log | head -5; grep "floats differ" $T/tp.log | head -30 | cut -c1-160
fi
echo "=== end t=$(t)"
