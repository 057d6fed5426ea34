#!/bin/sh
# bench/results/ptmetal_pt_cost.sh OLD_BIN NEW_BIN SCENES: the path tracer's cost on the GI table's material
# scenes (docs/PERFORMANCE.md section 7, "The reference counts metal events as the probe modes do"), two
# builds alternating twice; SCENES holds island.vox (bench/gi_table's OUTDIR/scenes). Writes mr.* and is.*
# (gi_bench's output) in the current folder.
OLD=$1 NEW=$2 S=$3
for round in 1 2; do
    for v in old new; do
        B=$OLD; [ $v = new ] && B=$NEW
        "$B/gi_bench" --ref-spp 16 --runs 3 --threads 2 --methods pathtrace --max-spp pathtrace=64 --name metal-room \
            --camera 58,8,20,20,40,2 --up 0,0,1 metal-room 160x120 > mr.$v.$round.txt 2>&1
        "$B/gi_bench" --ref-spp 16 --runs 3 --threads 2 --methods pathtrace --max-spp pathtrace=64 --name island \
            --camera 34,-34,22,10,-6,8 --up 0,0,1 "$S/island.vox" 160x120 > is.$v.$round.txt 2>&1
    done
done
