#!/bin/bash
# lvp1 (issue 21, seventeenth sitting): the branch's final render_bench (fbb131c: the stack's ladder in the
# rebased walk too) on the terrains (--generate), with the bench's ESVO and with the ESVO given the same stack
# form (--esvo-kernel issue21_s17_esvo_selects.comp), host and avx2 (issue21_s17_lvp.sh), process by process.
B=${B:-/tmp/lvp1_bin/render_bench_fbb131c}; K=${K:-/tmp/lvp1_bin/esvo_sel.spv}
export LP_NUM_THREADS=${THREADS:-1}
OPT="--mrays --cpu-time --sizes 480x270 --runs 5 --warmup 0.3 --views overview,oblique,closeup --generate"
echo "== lavapipe final gen $(date -u +%F' '%T) B=$B LP_NUM_THREADS=$LP_NUM_THREADS"
for cfg in host avx2; do
  for es in plain sel; do
    ov=; [ $cfg = avx2 ] && ov=avx
    ek=; [ $es = sel ] && ek="--esvo-kernel $K"
    echo "-- round 1 $cfg $es gen $(date -u +%T) load $(cut -d' ' -f1-3 /proc/loadavg)"
    GALLIUM_OVERRIDE_CPU_CAPS=$ov timeout 1500 $B $OPT $ek 2>&1 | grep -v '^shadow map'
  done
done
echo "== done $(date -u +%T)"
