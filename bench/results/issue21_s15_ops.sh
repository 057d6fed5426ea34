#!/bin/sh
# issue 21, fifteenth sitting: the traversal loop's operations per iteration in SPIR-V (main's trace.comp,
# the branch's, ESVO's), the depth kernel specialised as render_bench runs it on a scene of one instance
# (MODE 3, HAS_COLOR, no BVH, LOD, hits or beam, ONE_SAMPLE, PATH_START, DEEP 0, FAR off, plain layout).
# spirv-opt (SPIRV-Tools v2023.1) folds the spec constants only in separate runs (set, freeze, fold the
# spec-constant ops, then -O: with all four in one run the constants stayed here and the walk kept its
# compact and rebase paths; main's counts below equal the fourteenth sitting's table).
#   sh bench/results/issue21_s15_ops.sh MAIN_REPO BRANCH_REPO
set -e
for v in main:$1 branch:$2; do
  n=${v%%:*}; d=${v#*:}
  glslangValidator -V --target-env vulkan1.1 -o /tmp/$n.spv $d/render/shaders/trace.comp > /dev/null
  spirv-opt --set-spec-const-default-value "0:3 1:true 2:false 3:false 4:false 5:0 6:true 7:true 8:0 9:false 10:0 11:false 12:false" /tmp/$n.spv -o /tmp/$n.a.spv
  spirv-opt --freeze-spec-const /tmp/$n.a.spv -o /tmp/$n.b.spv
  spirv-opt --fold-spec-const-op-composite /tmp/$n.b.spv -o /tmp/$n.c.spv
  spirv-opt -O /tmp/$n.c.spv -o /tmp/$n.o.spv
  spirv-dis /tmp/$n.o.spv > /tmp/$n.dis
  PICK=OpBitCount python3 $2/bench/results/issue21_s15_loopops.py /tmp/$n.dis x
done
glslangValidator -V --target-env vulkan1.1 -o /tmp/esvo.spv $2/bench/shaders/esvo.comp > /dev/null
spirv-opt -O /tmp/esvo.spv -o /tmp/esvo.o.spv && spirv-dis /tmp/esvo.o.spv > /tmp/esvo.dis
python3 $2/bench/results/issue21_s15_loopops.py /tmp/esvo.dis x
