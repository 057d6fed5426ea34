#!/bin/sh
# bench/results/rdr2_host_mem.sh - issue 18, branch rdr2: svo_render's host peak memory when the
# compact layout is over --gpu-budget (AUTO's bricks: the brick dictionary; paging), main's binary
# (f807bf3: --load models builds the layout in blocks only; --load whole reads the scene, then
# builds both forms) against the branch's (--load models: a second pass over the file for the
# dictionary), process by process (ABAB), on the dev VM's lavapipe (2 cores shared with other jobs).
# Max RSS from /usr/bin/time; the tool's -v lines; the images compared with cmp. Both binaries are
# built without OIIO, OpenVDB and glTF (build-gpu: a full build maps about 115 MB more of libraries).
# Run from the repository root: sh bench/results/rdr2_host_mem.sh [ROUNDS [TERRAIN_ROUNDS]] > bench/results/rdr2_host_mem.txt
# (the terrain's processes take 20-60 s each on the dev VM: one round by default)
set -u
R=${1:-2}
TR=${2:-1}
D=bench/out/rdr2_data
MAIN=bench/out/base/bin/svo_render
[ -x "$MAIN" ] || MAIN=/work/main/bench/out/base/bin/svo_render
BR=build-gpu/bin/svo_render # configured as main's (the GPU machine's options: no OIIO, OpenVDB, glTF), so the libraries' pages weigh the same
mkdir -p $D/img
[ -e $D/helmet1024.svo ] || build/bin/vox2svo ../shared/corpus/gltf/khronos_DamagedHelmet.glb $D/helmet1024.svo --res 1024 -q
[ -e $D/helmet1024r.svo ] || build/bin/vox2svo ../shared/corpus/gltf/khronos_DamagedHelmet.glb $D/helmet1024r.svo --res 1024 --region 64 -q
[ -e $D/terrain.svo ] || build/bin/svo_build_bench -o $D/terrain.svo >/dev/null
echo "# $(date -u) $(uname -n) $(nproc) CPUs; main $MAIN ($(cat bench/out/base/bin/COMMIT 2>/dev/null || cat /work/main/bench/out/base/bin/COMMIT)), branch $(git rev-parse --short HEAD)"
run() { # tag binary file budget load
    tag=$1 bin=$2 f=$3 bud=$4 load=$5
    out=$D/img/$(basename $f .svo)_${bud}_$tag.ppm
    /usr/bin/time -f "maxrss_kb %M wall_s %e" $bin $f $out --size 320x240 --mode albedo --layout compact \
        --gpu-budget $bud --load $load -v >$D/log.txt 2>&1
    st=$?
    echo "== $tag $(basename $f) budget $bud load $load exit $st"
    grep -E "^(gpu scene|layout|compact|paging|note)|maxrss_kb" $D/log.txt
}
for spec in helmet1024r:4G helmet1024r:11800000 helmet1024r:8000000 helmet1024:11800000 helmet1024:8000000 \
    terrain:95000000 terrain:60000000; do
    f=$D/${spec%%:*}.svo bud=${spec#*:}
    n=$R
    case $f in *terrain*) n=$TR ;; esac
    i=0
    while [ $i -lt "$n" ]; do
        run main_models $MAIN $f $bud models
        run main_whole $MAIN $f $bud whole
        run branch_models $BR $f $bud models
        run branch_whole $BR $f $bud whole
        i=$((i + 1))
    done
    b=$(basename $f .svo)
    for t in main_models branch_models branch_whole; do
        cmp -s $D/img/${b}_${bud}_main_whole.ppm $D/img/${b}_${bud}_$t.ppm && echo "image $b $bud $t: main_whole's" ||
            echo "image $b $bud $t: DIFFERS from main_whole's"
    done
done
