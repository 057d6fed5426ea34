#!/bin/sh
# deep3 (issue 21, twenty-fourth sitting): the trace.comp variants of the H200 batches (render_bench --kernels K.spv@c1).
#   sh deep3_variants.sh TREE OUTDIR
# TREE: a source tree (main 396b0f0 for batch 1, the branch's head for batch 2); deep3_variants.patch applied to a copy of its render/shaders gives:
#   t_ref  the tree's trace.comp (the built-in kernel's source: 0 px must differ)
#   t_cin, t_cout, t_clow  counters in the hits kernel's iteration count (+1000 per rebase into a depth-k node, per
#          return to the model frame, per step in the rebased frame): steps/ray minus t_ref's over 1000
#   t_d1   REBASE off: DEEP 2's models walked by the DEEP 1 code (one frame; float error, pixels differ)
#   t_norb the DEEP 2 code with no rebase (rb_scale -100: one frame; pixels differ)
#   t_nohl t_norb without the origin's hi/lo pair (trace_instance's two-sum, trace_model's exact box entry)
#   t_rbup the rebase one level shallower (depth k - 1; frames of FRAME_LEVELS + 1 levels)
#   t_swin the frame switch inside the walk's loop (one loop; the rebase and the return as a branch of its body)
#   t_lnc  the lean walk at DEEP 2 in the kernels other than the colour kernel (MODE_COLOR keeps the full walk)
set -e
S=$1; O=$2; mkdir -p $O
P=$(cd "$(dirname "$0")" && pwd)/deep3_variants.patch
V=$(mktemp -d); mkdir -p $V/b/render; cp -r $S/render/shaders $V/b/render/; (cd $V && patch -s -p0 < $P)
gv() { glslangValidator -V --target-env vulkan1.1 "$@" $V/b/render/shaders/trace.comp > /dev/null; }
gv -o $O/t_ref.spv
gv -DCNT_IN -o $O/t_cin.spv
gv -DCNT_OUT -o $O/t_cout.spv
gv -DCNT_LOW -o $O/t_clow.spv
gv -DD1LIKE -o $O/t_d1.spv
gv -DNO_RB -o $O/t_norb.spv
gv -DNO_HL -o $O/t_nohl.spv
gv -DRB_UP=1 -o $O/t_rbup.spv
gv -DSW_IN -o $O/t_swin.spv
gv -DLEAN_NOCOLOR2 -o $O/t_lnc.spv
for f in $O/*.spv; do spirv-val --target-env vulkan1.1 $f; done
rm -rf $V
