#!/bin/sh
# bench/cones2_gpu.sh - the device script of docs/PERFORMANCE.md "Cone tracing, second part" (run 2): run from the repo root
# with gi_bench (this branch), gi_bench_base (main 7908f9a) and scenes/ in bench/out/cones; its log into $OUT/cones.log.
# (the volume as a 3D-texture atlas, half-res cones, cone shadows, sparse relighting)
B=bench/out/cones
S=$B/scenes
LOG="$OUT/cones.log"
exec > "$LOG" 2>&1
set -x
nvidia-smi -L
chmod +x $B/gi_bench $B/gi_bench_base
t0=$(date +%s)
run() { # LIMIT BIN ARGS...
    lim=$1; shift
    left=$(( 112 - ($(date +%s) - t0) ))
    [ $left -lt 5 ] && { echo "SKIPPED (time): $*"; return; }
    [ $lim -gt $left ] && lim=$left
    timeout $lim stdbuf -oL "$@"
    echo "rc $? elapsed $(( $(date +%s) - t0 )) s"
}
M=cones,cones-half,cones-iso,cones-iso-half,cones-half-4,cones-shadows
R2="--camera 220,-260,120,0,0,10 --up 0,0,1 --light 0.35,-0.45,0.82"
run 12 $B/gi_bench_base --name cornell --ref-spp 512 --runs 5 --warm 100 --methods cones $S/cornell.svo 1920x1080
run 25 $B/gi_bench --name cornell --ref-spp 512 --runs 5 --warm 100 --methods $M $S/cornell.svo 1920x1080
run 12 $B/gi_bench_base --name two-rooms --ref-spp 512 --runs 5 --warm 100 --methods cones $R2 $S/tworooms512.svo 1920x1080
run 20 $B/gi_bench --name two-rooms --ref-spp 512 --runs 5 --warm 100 --methods $M $R2 $S/tworooms512.svo 1920x1080
run 10 $B/gi_bench_base --name monu1 --ref-spp 512 --runs 5 --warm 100 --methods cones $S/eph_monu1.vox 1920x1080
run 20 $B/gi_bench --name monu1 --ref-spp 512 --runs 5 --warm 100 --methods $M,cones-256 $S/eph_monu1.vox 1920x1080
run 12 $B/gi_bench --name monu1-512 --ref-spp 16 --runs 3 --warm 0 --methods cones-512 $S/eph_monu1.vox 1920x1080
run 12 $B/gi_bench_base --name monu1-512 --ref-spp 16 --runs 3 --warm 0 --methods cones-512 $S/eph_monu1.vox 1920x1080
