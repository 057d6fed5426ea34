#!/bin/sh
# bench/probes_error.sh - error of the indirect diffuse light against time for
# probe GI, the light field and path tracing, on the three scenes of issue 5,
# in one run (the tables of docs/PERFORMANCE.md section 5 and the plot).
#
#   sh bench/probes_error.sh BIN DATA [SIZE REF_SPP] > results.txt
#
# BIN holds probes_bench; DATA holds cornell.svo (`vox2svo rtxgi_cornell.glb
# cornell.svo --res 256`), tworooms512.svo (`vox2svo rtxgi_two-rooms.glb
# tworooms512.svo --res 512`) and eph_monu1.vox. Default: 640x480 against a
# 4096-spp path-traced reference, on the first Vulkan device (GPU).
# Plot: python3 bench/probes_plot.py results.txt docs/probes_error.svg
set -e
BIN=$1 DATA=$2 SIZE=${3:-640x480} REF=${4:-4096}
[ -x "$BIN/probes_bench" ] || { echo "usage: probes_error.sh BIN DATA [WxH REF_SPP]" >&2; exit 2; }
PB="$BIN/probes_bench ${PB_FLAGS:-}"
echo "# probes_error.sh $SIZE, reference $REF spp; $(date -u +%Y-%m-%dT%H:%MZ)"
echo "## cornell"
# bake spp 1..256, resolution 32..128 and spacing 0.5..0.125 (bounds ~2.02 units)
$PB --pt-spp 256 --lf-spp 256 error "$DATA/cornell.svo" "$SIZE" "$REF" \
    0.25:64:1 0.25:64:4 0.25:64:16 0.25:64:64 0.25:64:256 0.25:32:64 0.25:128:64 0.5:64:64 0.125:64:64
echo "## two-rooms (outside, sun from above)"
# converted +Z up (convert/mesh.h): the former +Y-up view turned by (x, y, z) -> (x, -z, y)
$PB --pt-spp 256 --lf-spp 256 --camera 220,-260,120,0,0,10 --up 0,0,1 --light 0.35,-0.45,0.82 \
    --bounds -150,-150,-5,150,150,60 error "$DATA/tworooms512.svo" "$SIZE" "$REF" \
    25:64:16 25:64:64 25:128:64 12.5:64:64
echo "## monu1"
$PB --pt-spp 256 --lf-spp 256 error "$DATA/eph_monu1.vox" "$SIZE" "$REF" \
    32:64:64 16:64:16 16:64:64 16:128:64 8:64:64 8:32:16 4:32:16
