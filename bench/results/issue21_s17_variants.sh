#!/bin/sh
# issue 21, seventeenth sitting (branch ray6): the trace kernel variants of batches 1 and 2, built from main's
# source at 46eb6d3 with issue21_s17_variants.patch applied (macros RAY6_*), run with main's render_bench as
# `--kernels k_NAME.spv@c1` (render_bench_h200_ray6_s17_b{1,2}_gpu.sh; raw logs beside them).
#   sh bench/results/issue21_s17_variants.sh REPO_WITH_PATCH OUTDIR
set -e
S=$1/render/shaders; O=$2; mkdir -p $O
while read name defs; do
  glslangValidator -V --target-env vulkan1.1 $defs -o $O/k_$name.spv $S/trace.comp > /dev/null
done <<'LIST'
gf -DRAY6_GF
gfz -DRAY6_GF -DRAY6_Z
gfp -DRAY6_GF -DRAY6_PAD=13
gfzp -DRAY6_GF -DRAY6_Z -DRAY6_PAD=13
gfp2 -DRAY6_GF -DRAY6_PAD=77
gfzp2 -DRAY6_GF -DRAY6_Z -DRAY6_PAD=77
gfp3 -DRAY6_GF -DRAY6_PAD=45
gfx -DRAY6_GF -DRAY6_X
gfxp2 -DRAY6_GF -DRAY6_X -DRAY6_PAD=77
gf1 -DRAY6_GF -DRAY6_ONE
gf1p2 -DRAY6_GF -DRAY6_ONE -DRAY6_PAD=77
gfx1 -DRAY6_GF -DRAY6_X -DRAY6_ONE
merge -DRAY6_MERGE
wt -DRAY6_WT
LIST
