#!/bin/sh
# lean2 (issue 21, twenty-first sitting): the trace.comp variants of the H200 batches (render_bench --kernels K.spv@c1).
#   sh lean2_variants.sh MAIN_TREE BATCH1_TREE BRANCH_TREE OUTDIR
# MAIN_TREE: main 1695247 (t_main). BATCH1_TREE: main with lean2_variants.patch (batch 1's tree: L2_DEPTHONLY gives
# main's kernels; default the colour kernels lean with the camera ray formed again (L2_RE, t_re), L2_NORE without it
# (t_lean), L2_RE3 also the model-space ray formed again after the loop (t_re3), L2_BVH the lean walk in the BVH
# kernels too; gbuffer.comp / frame.comp: TRACE_LEAN and their ray formed again, L2_NORE without, L2_NOGB main's).
# BRANCH_TREE: the branch (t_d1 = its trace.comp: DEEP 0 and 1); t_bvhd1: the branch's trace_common.glsl with
# "!USE_BVH &&" taken out of LEAN's line (batch 2/3's file was built from the tree with the knob L2_BVH).
set -e
M=$1; V=$2; B=$3; O=$4; mkdir -p $O
gv() { glslangValidator -V --target-env vulkan1.1 "$@" > /dev/null; }
gv -o $O/t_main.spv $M/render/shaders/trace.comp
gv -DL2_NORE -o $O/t_lean.spv $V/render/shaders/trace.comp
gv -o $O/t_re.spv $V/render/shaders/trace.comp
gv -DL2_RE3 -o $O/t_re3.spv $V/render/shaders/trace.comp
gv -DL2_BVH -DL2_NORE -o $O/t_bvh.spv $V/render/shaders/trace.comp
gv -DL2_BVH -o $O/t_bvhre.spv $V/render/shaders/trace.comp
gv -DL2_BVH -DL2_RE3 -o $O/t_bvhre3.spv $V/render/shaders/trace.comp
gv -o $O/t_d1.spv $B/render/shaders/trace.comp
