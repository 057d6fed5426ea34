# gbvh (issue 21, twenty-fourth sitting): the lines both H200 payloads (gbvh_b1_gpu.sh, gbvh_b2_gpu.sh) share, sourced
# by them here (the payloads carried them inline): the time left of a limit, the binaries unpacked (BINS: the
# A_/B_ programs of the payload), the clock before each process and every 200 ms, a time stamp per line, the
# multi-instance scenes with render_bench's three views (bench/results/gbvh_views.c). BATCH: the batch's number.
s0=$(date +%s); left() { echo $(( $1 * ${TS:-1} - ($(date +%s) - s0) )); }
T=/tmp/gbvh; rm -rf $T; mkdir -p $T/chk
for x in A B; do for b in $BINS; do gunzip -c ${x}_$b.gz > $T/${x}_$b; chmod +x $T/${x}_$b; done; done
smi() { nvidia-smi --query-gpu=clocks.sm,clocks.max.sm,clocks.mem,power.draw,temperature.gpu,pstate,clocks_throttle_reasons.active --format=csv,noheader 2>/dev/null | head -1; }
stamp() { while IFS= read -r l; do printf '%s %s\n' "$(date -u +%T.%2N)" "$l"; done; }
echo "== gbvh batch $BATCH on $(nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader 2>/dev/null | head -1) $(nproc) CPUs $(date -u +%T); A = main $(cat A_COMMIT), B = gbvh $(cat B_COMMIT)"
nvidia-smi --query-gpu=timestamp,clocks.sm,clocks.mem,power.draw,temperature.gpu,pstate,clocks_throttle_reasons.active --format=csv,noheader -lms 200 > $T/smi.log 2>/dev/null &
smipid=$!
M="ogt_test_multiple_model_scene.vox@default;5.24973348,-21.6430856,44.3215428,76,39,14;80.6680227,43.0011623,11.9994188,84.999992,46.7142788,10.1428606"
G="ogt_test_groups.vox@default;-3.68564184,-42.087693,45.2938465,46,0.5,24;54.4395007,-1.33239196,16.270592,58.9868398,1.85604196,13.9999983"
# the end: the clock samples' range, the log in $OUT/gbvh.tar.gz
finish() {
  kill $smipid 2>/dev/null; wait $smipid 2>/dev/null
  echo "-- clock samples: $(wc -l < $T/smi.log), SM MHz min/median/max $(cut -d, -f2 $T/smi.log | tr -dc '0-9\n' | sort -n | awk '{a[NR]=$1} END {if (NR) print a[1], a[int((NR+1)/2)], a[NR]}')"
  [ -n "$OUT" ] && tar czf $OUT/gbvh.tar.gz -C $T smi.log
  echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
}
