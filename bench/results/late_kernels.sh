#!/bin/sh
# late (issue 21, twenty-sixth sitting): the trace.comp kernels of the H200 batch (render_bench --kernels K.spv@c1..)
# and of the lavapipe counters.
#   sh late_kernels.sh REPO OUTDIR      (REPO: a clone holding main 1dff501 and branch late's commits)
#   t_main           main's trace.comp (1dff501)
#   t_L1, t_L2, t_L3 the late switch (32c7dbc, LATE_LEVELS 1, 2, 3): the model frame walks that many levels below
#                    the rebase depth k before the switch into N's frame
#   t_FB             F (e4eaee0: a return out of N into an inner sibling goes straight to the next switch) with the
#                    model frame's bias and ray end stored once before the loop instead of at each switch
#   c_in_L*, c_out_L*  counters: +1000 iterations in the hits kernel per switch taken from the loop (pending 1 there,
#                    the late switch's too) / per return out of N (pending 2), t_L* 0 to 3 (0: main's switches)
#   c_F              +1000 per return that F takes straight to the switch
#   t_F, t_G2, t_G1  batch 2: F (e4eaee0), G2 (b384188: the node after a switch and after a return's pop loaded before
#                    the loop), G1 (G2 without the pop's part)
set -e
R=$1; O=$2; mkdir -p $O
V=$(mktemp -d)
gv() { glslangValidator -V --target-env vulkan1.1 $3 -o "$2" "$1/trace.comp" > /dev/null; spirv-val --target-env vulkan1.1 "$2"; }
for c in 1dff501 32c7dbc e4eaee0 b384188; do mkdir -p $V/$c; git -C $R archive $c render/shaders | tar x -C $V/$c; done
gv $V/1dff501/render/shaders $O/t_main.spv
for L in 1 2 3; do gv $V/32c7dbc/render/shaders $O/t_L$L.spv -DLATE_LEVELS=$L; done
cp -r $V/e4eaee0 $V/fb; f=$V/fb/render/shaders/trace_common.glsl
python3 - $f <<'PY'
import sys
p = sys.argv[1]; s = open(p).read()
st = """                stk_node[RB_TMAX] = floatBitsToInt(tmax);
                stk_node[RB_BIAS] = floatBitsToInt(bias.x), stk_node[RB_BIAS + 1] = floatBitsToInt(bias.y);
                stk_node[RB_BIAS + 2] = floatBitsToInt(bias.z);
"""
t0 = """            stk_node[RB_T0] = floatBitsToInt(tmin);
"""
assert s.count(st) == 1 and s.count(t0) == 1
s = s.replace(st, "").replace(t0, t0 + st.replace("                ", "            "))
open(p, "w").write(s)
PY
gv $V/fb/render/shaders $O/t_FB.spv
for c in in out; do
  cp -r $V/32c7dbc $V/c$c; f=$V/c$c/render/shaders/trace_common.glsl
  if [ $c = in ]; then sed -i 's/^                        pending = 1, rb_cbit = cbit;/& g_iter += 1000u;/' $f
  else sed -i 's/^                    pending = 2, rb_step = step;/& g_iter += 1000u;/' $f; fi
  [ $(grep -c 'g_iter += 1000u' $f) = 1 ]
  for L in 0 1 2 3; do gv $V/c$c/render/shaders $O/c_${c}_L$L.spv -DLATE_LEVELS=$L; done
done
cp -r $V/e4eaee0 $V/cf; f=$V/cf/render/shaders/trace_common.glsl
sed -i 's/^                        if (GUARD) g_iter++;$/& g_iter += 1000u;/' $f; [ $(grep -c 'g_iter += 1000u' $f) = 1 ]
gv $V/cf/render/shaders $O/c_F.spv
gv $V/e4eaee0/render/shaders $O/t_F.spv
gv $V/b384188/render/shaders $O/t_G2.spv
cp -r $V/b384188 $V/g1; f=$V/g1/render/shaders/trace_common.glsl
python3 - $f <<'PY'
import sys
p = sys.argv[1]; s = open(p).read()
pop = """            hh = 0.0;
#ifdef TRACE_PATH
            if (!COMPACT) {
                desc = nodes[parent];
                if (TURN_LOAD) desc = desc_gpu_form(desc);
                loaded = true;
            } else
#endif
            { loaded = false; if (SENT) desc = 0u; }
        }
"""
assert s.count(pop) == 1
s = s.replace(pop, """            hh = 0.0;
            loaded = false; if (SENT) desc = 0u;
        }
""")
open(p, "w").write(s)
PY
gv $V/g1/render/shaders $O/t_G1.spv
rm -rf $V
