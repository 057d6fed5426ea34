#!/bin/bash
# lvp1 (issue 21, seventeenth sitting): eph_monu1 at 1280x720 with lavapipe's default threads (two on the dev VM),
# wall rates (the dispatch timestamps, MrayVX) and per CPU second, main (A, 46eb6d3) and the final branch (F,
# fbb131c) alternated, host and avx2 (issue21_s17_lvp.sh); the goal's eph_monu3 is not in the corpus.
A=${A:-/tmp/lvp1_bin/render_bench_46eb6d3}; F=${F:-/tmp/lvp1_bin/render_bench_fbb131c}
unset LP_NUM_THREADS
OPT="--mrays --cpu-time --sizes 1280x720 --runs 5 --warmup 0.3 --views overview,oblique,closeup /work/shared/corpus/vox/eph_monu1.vox"
echo "== lavapipe default threads $(date -u +%F' '%T) load $(cut -d' ' -f1-3 /proc/loadavg)"
for cfg in host avx2; do
  for who in A F; do
    bin=$A; [ $who = F ] && bin=$F
    ov=; [ $cfg = avx2 ] && ov=avx
    echo "-- round 1 $cfg $who $(date -u +%T) load $(cut -d' ' -f1-3 /proc/loadavg)"
    GALLIUM_OVERRIDE_CPU_CAPS=$ov timeout 600 $bin $OPT 2>&1 | grep -v '^shadow map'
  done
done
echo "== done $(date -u +%T)"
