#!/bin/bash
# Coordinator (stop 53): issue 21's table with merged main d6c73c6 (ray8's BVH and DEEP 2 lean walks in), ESVO beside,
# one process for the corpus scenes and one for the generated terrains; a 2 s warm-up first (ray8: the clock dips while
# a process compiles). SIZE, RUNS, WU may be set for lavapipe.
T=/tmp/table; rm -rf $T; mkdir -p $T; gunzip -c render_bench.gz > $T/rb; chmod +x $T/rb
SIZE=${SIZE:-1920x1080}; RUNS=${RUNS:-15}; WU=${WU:-0.5}
smi() { nvidia-smi --query-gpu=clocks.sm,power.draw,temperature.gpu --format=csv,noheader 2>/dev/null | head -1; }
echo "== table: render_bench $(cat REV) on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1) $(date -u +%T)"
timeout 10 $T/rb --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup eph_monu1.vox > /dev/null 2>&1
echo "-- corpus scenes, clock $(smi)"
timeout 70 $T/rb --sizes $SIZE --runs $RUNS --warmup $WU eph_monu1.vox eph_menger.vox eph_dragon.vox ogt_doom.vox ogt_test_multiple_model_scene.vox 2>&1 | grep -E '^scene|^eph|^ogt|^device' | sed -E 's/  *\[warps[^]]*\]//' | cut -c1-200
echo "-- generated terrains, clock $(smi)"
timeout 70 $T/rb --generate --sizes $SIZE --runs $RUNS --warmup $WU 2>&1 | grep -E '^scene|^terrain|^device' | sed -E 's/  *\[warps[^]]*\]//' | cut -c1-200
echo "== done $(date -u +%T) clock $(smi)"
