#!/bin/bash
# Stop 88 (issue 21; stop 87's script, run again): lavapipe against ESVO with this stop's defaults (grids on every device, the turned
# instances' union on CPU devices): render_bench without --grid or --octree, the five corpus scenes then the
# generated terrains, two rounds, on a quiet dev machine. Table: python3 bench/results/p86_lavapipe_table.py LOG
# (its "grid" column is the default walk). Usage: bench/results/p87_lavapipe.sh BUILD > LOG
B=${1:-build}/bin; C=${VX_CORPUS_DIR:-../shared/corpus}
files=""; for f in eph_monu1 eph_menger eph_dragon ogt_doom ogt_test_multiple_model_scene; do files="$files $C/vox/$f.vox"; done
for round in 1 2; do
  uptime
  $B/render_bench --mrays --cpu-time --sizes 640x360 --runs 5 --warmup 0.3 $files
  $B/render_bench --mrays --cpu-time --sizes 640x360 --runs 5 --warmup 0.3 --generate
done
