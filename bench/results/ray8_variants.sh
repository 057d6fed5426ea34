#!/bin/sh
# ray8 (issue 21, twenty-third sitting): the trace.comp variants of the H200 batches (render_bench --kernels K.spv@c1).
#   sh ray8_variants.sh MAIN_TREE BRANCH_TREE OUTDIR
# MAIN_TREE: main 0acd33a (t_main). BRANCH_TREE: ray8's tree with the BVH kernels' lean walk (t_bvh); the same tree with
# ray8_variants.patch applied to a copy gives t_bvhsh (-DBVH_SHARED: the BVH walk's state, o, d and 1/d in shared
# memory while each instance's octree walk runs) and t_bvhshv (-DBVH_SHARED -DBVH_SHARED_VEC: o, d and 1/d only).
set -e
M=$1; B=$2; O=$3; mkdir -p $O
gv() { glslangValidator -V --target-env vulkan1.1 "$@" > /dev/null; }
gv -o $O/t_main.spv $M/render/shaders/trace.comp
gv -o $O/t_bvh.spv $B/render/shaders/trace.comp
P=$(cd "$(dirname "$0")" && pwd)/ray8_variants.patch
V=$(mktemp -d); mkdir -p $V/render; cp -r $B/render/shaders $V/render/; patch -s -d $V -p1 < $P
gv -DBVH_SHARED -o $O/t_bvhsh.spv $V/render/shaders/trace.comp
gv -DBVH_SHARED -DBVH_SHARED_VEC -o $O/t_bvhshv.spv $V/render/shaders/trace.comp
rm -rf $V
