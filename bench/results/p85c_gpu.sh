#!/bin/bash
# Stop 85 (issue 21): the final form (C, payload/render_bench_b.gz: the cells' cube only where smaller, GRID_CUBE)
# against main (A, payload/render_bench_il.gz, cca6620's code), one process each, A C A C, on the views p85b found
# slowest (eph_menger, eph_monu1; GRID_CUBE off there: the kernel should be main's) and two scenes with it on
# (chr_man, cubictest). Carry [".gl", "payload"].
[ -n "$OUT" ] && exec > >(tee $OUT/p85c.log) 2>&1
LIM=${LIM:-150}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_|^[a-z]*_|^grid:"
payload_setup p85c
gunzip -c payload/render_bench_il.gz > $T/A; gunzip -c payload/render_bench_b.gz > $T/C; chmod +x $T/A $T/C
V="payload/eph_menger.vox payload/eph_monu1.vox payload/more/eph_character_chr_man.vox payload/more/vengi_data_tests_cubictest.vox"
echo "== A il / C stop 85 on $(gpu_name), $(date -u +%T)"
clock_start
for r in 1 2; do
  run A$r 30 $T/A --no-esvo --views oblique,closeup --sizes $SIZE --runs $RUNS --warmup $WU $V
  run C$r 30 $T/C --no-esvo --views oblique,closeup --sizes $SIZE --runs $RUNS --warmup $WU $V
done
payload_end p85c
