#!/bin/bash
# Stop 83 (issue 21), second run, the generated terrains (render_bench --generate: terrain1024 and terrain4096, every
# view, ESVO in each process): A (442a119) and PI (p83a_gpu.sh's candidate), A PI A PI where time allows.
# Carry [".gl", "payload"].
LIM=${LIM:-540}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_|^grid:|^shadow map"
payload_setup p83b
R=${OUT:-/tmp}/p83b.txt
{
echo "== $(cat payload/REV | tr '\n' ' ') on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
gunzip -c payload/render_bench_pi.gz > $T/render_bench_pi; chmod +x $T/render_bench_pi
timeout 10 $T/render_bench --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
for k in 1 2; do
  run A$k 120 $T/render_bench --generate --sizes $SIZE --runs $RUNS --warmup $WU
  run PI$k 120 $T/render_bench_pi --generate --sizes $SIZE --runs $RUNS --warmup $WU
done
payload_end p83b
} 2>&1 | tee $R
