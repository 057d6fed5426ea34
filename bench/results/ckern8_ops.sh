#!/bin/sh
# issue 18, ckern8: the traversal loop's SPIR-V operations per path (ckern8_loopops.py) of trace_compact.comp (main's
# and the branch's) and trace.comp, the albedo kernels as compact_bench runs them on a scene of one instance (MODE 1,
# HAS_COLOR, no BVH, no hits, no dictionary, ONE_SAMPLE, UNIFORM for DEEP 0, no pages, no start), DEEP 0 and 1;
# specialised and optimised as issue21_s15_ops.sh does (set, freeze, fold, -O in separate spirv-opt runs).
#   sh bench/results/ckern8_ops.sh MAIN_REPO BRANCH_REPO
set -e
ops() { # name shader specs
  glslangValidator -V --target-env vulkan1.1 -o /tmp/$1.spv $2 > /dev/null
  spirv-opt --set-spec-const-default-value "$3" /tmp/$1.spv -o /tmp/$1.a.spv
  spirv-opt --freeze-spec-const /tmp/$1.a.spv -o /tmp/$1.b.spv
  spirv-opt --fold-spec-const-op-composite /tmp/$1.b.spv -o /tmp/$1.c.spv
  spirv-opt -O /tmp/$1.c.spv -o /tmp/$1.o.spv && spirv-dis /tmp/$1.o.spv > /tmp/$1.dis
  echo "== $1"; PICK=OpBitCount python3 $BR/bench/results/ckern8_loopops.py /tmp/$1.dis x
}
MA=$1; BR=$2
for d in 0 1; do u=$([ $d = 0 ] && echo true || echo false)
  ops main_compact_d$d $MA/render/shaders/trace_compact.comp "0:1 1:true 2:false 4:false 5:false 6:true 7:$u 8:$d 9:0 10:0 11:false 12:false"
  ops branch_compact_d$d $BR/render/shaders/trace_compact.comp "0:1 1:true 2:false 4:false 5:false 6:true 7:$u 8:$d 9:0 10:0 11:false 12:false"
  ops trace_d$d $BR/render/shaders/trace.comp "0:1 1:true 2:false 3:false 4:false 5:0 6:true 7:true 8:$d 9:false 10:0 11:false 12:false"
done
