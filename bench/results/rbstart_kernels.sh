#!/bin/sh
# rbstart (issue 21, twenty-fifth sitting): the trace.comp kernels of the H200 batches (render_bench --kernels K.spv@c1..).
#   sh rbstart_kernels.sh MAIN_TREE BRANCH_TREE OUTDIR
#   t_main             main's trace.comp (54224d6): from the root (@c1p0) its pixels are main's walk's
#   t_main_cin, t_rb_cin    +1000 iterations in the hits kernel per switch into a depth-k node's frame taken from the
#                      walk's loop (pending 1 in the loop), main's and the branch's: steps/ray minus the built-in's, /1000
#   t_main_cout, t_rb_cout  +1000 per return out of N (pending 2)
# Counters run in their own tree's render_bench (main's kernel on the branch's starts is not exact: X below k).
set -e
M=$1; B=$2; O=$3; mkdir -p $O
V=$(mktemp -d)
gv() { glslangValidator -V --target-env vulkan1.1 -o "$2" "$1/shaders/trace.comp" > /dev/null; spirv-val --target-env vulkan1.1 "$2"; }
gv $M/render $O/t_main.spv
for t in main rb; do
  S=$M; [ $t = rb ] && S=$B
  for c in cin cout; do
    mkdir -p $V/$t$c; cp -r $S/render/shaders $V/$t$c/
    f=$V/$t$c/shaders/trace_common.glsl
    if [ $c = cin ]; then sed -i 's/                        pending = 1, rb_cbit = cbit;/& g_iter += 1000u;/' $f
    else sed -i 's/                    pending = 2, rb_step = step;/& g_iter += 1000u;/' $f; fi
    grep -q 'g_iter += 1000u' $f
    gv $V/$t$c $O/t_${t}_$c.spv
  done
done
rm -rf $V
