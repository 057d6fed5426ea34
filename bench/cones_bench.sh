#!/bin/sh
# bench/cones_bench.sh - voxel cone tracing (issue 12) on the GPU machine in
# one call: gi_bench's cone rows (cones, cones-iso, cones-16, cones-256) on
# the scenes of bench/gi_table (references of 2 x REF spp), and cones-512 on
# eph_monu1 (the volume build at 512^3: voxelize, inject, filter times).
#
#   bench/cones_bench.sh BIN SCENES OUT [REF]
#
# BIN holds gi_bench; SCENES cornell.svo, tworooms512.svo, eph_monu1.vox
# (as bench/gi_table makes them); OUT gets one .txt per scene and cones.csv.
set -e
BIN=$1 S=$2 OUT=$3 REF=${4:-1024}
if [ ! -x "$BIN/gi_bench" ] || [ -z "$OUT" ]; then
    echo "usage: bench/cones_bench.sh BIN SCENES OUT [REF]" >&2
    exit 2
fi
mkdir -p "$OUT"
M=cones,cones-iso,cones-16,cones-256
run() {
    name=$1
    shift
    "$BIN/gi_bench" --name "$name" --ref-spp "$REF" --runs 5 --warm 100 --csv "$OUT/cones.csv" "$@" > "$OUT/$name.txt" 2>&1 ||
        echo "cones_bench: $name failed" >&2
    echo "cones_bench: $name done" >&2
}
run cornell --methods $M "$S/cornell.svo" 1920x1080
run two-rooms --methods $M --camera 220,-260,120,0,0,10 --up 0,0,1 --light 0.35,-0.45,0.82 "$S/tworooms512.svo" 1920x1080
run monu1 --methods $M "$S/eph_monu1.vox" 1920x1080
run thin-wall --methods $M --camera 32,20,12,32,46,6 --up 0,0,1 thin-wall 1920x1080
run monu1-512 --methods cones-512 --ref-spp 16 "$S/eph_monu1.vox" 1920x1080
