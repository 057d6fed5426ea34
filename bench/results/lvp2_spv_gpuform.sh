#!/bin/bash
# lvp2 (issue 21, eighteenth sitting): trace.comp's kernels as GPUs run them (NODES_FILE false) are main's:
# both sources compiled, specialised with a GPU's constants (spirv-opt: set, freeze, fold the spec-constant
# ops, -O, in separate runs as issue21_s15_ops.sh) for the depth, colour, hits, BVH, beam kernels with
# DEEP 0, 1 and 2 (FAR on and off), ids canonicalised (spirv-remap --map all), disassembled, compared;
# then the file's form (NODES_FILE true, CPU devices) for the depth and colour kernels: only DEEP 2 may differ.
#   bash bench/results/lvp2_spv_gpuform.sh MAIN_SRC BRANCH_SRC
set -e
T=/tmp/lvp2spv; mkdir -p $T
for v in main:$1 branch:$2; do
  glslangValidator -V --target-env vulkan1.1 -o $T/${v%%:*}.spv ${v#*:}/render/shaders/trace.comp > /dev/null
done
same=0; differ=0
# ids: 0 MODE 1 HAS_COLOR 2 USE_BVH 3 LOD 4 WRITE_HITS 5 BEAM 6 ONE_SAMPLE 7 PATH_START 8 DEEP 9 FAR 10 COMPACT_FORM
# 11 smap 12 MISS_PASS, 100 NODES_FILE (false: the GPU form)
for cfg in "0:3 1:true 2:false 4:false 5:0 7:true" "0:0 1:true 2:true 4:false 5:0 7:false" "0:3 1:true 2:false 4:true 5:0 7:true" \
           "0:3 1:false 2:false 4:false 5:8 7:false" "0:1 1:true 2:false 4:false 5:0 7:true 11:true"; do
  for deep in 0 1 2; do for far in false true; do
    for n in main branch; do
      spirv-opt --set-spec-const-default-value "$cfg 8:$deep 9:$far 100:false" $T/$n.spv -o $T/$n.a.spv
      spirv-opt --freeze-spec-const $T/$n.a.spv -o $T/$n.b.spv
      spirv-opt --fold-spec-const-op-composite $T/$n.b.spv -o $T/$n.c.spv
      spirv-opt -O $T/$n.c.spv -o $T/$n.o.spv
      mkdir -p $T/r_$n; spirv-remap --map all --strip all -i $T/$n.o.spv -o $T/r_$n > /dev/null
      spirv-dis --no-header $T/r_$n/$n.o.spv > $T/$n.dis
    done
    if cmp -s $T/main.dis $T/branch.dis; then same=$((same + 1)); else differ=$((differ + 1)); echo "DIFFER: $cfg DEEP $deep FAR $far: $(diff $T/main.dis $T/branch.dis | grep -c '^[<>]') lines"; fi
  done; done
done
echo "GPU form (NODES_FILE false): $same kernels the same as main's, $differ differ"
spec() { # name constants -> $T/name.dis
  spirv-opt --set-spec-const-default-value "$2" $T/$1.spv -o $T/$1.a.spv
  spirv-opt --freeze-spec-const $T/$1.a.spv -o $T/$1.b.spv
  spirv-opt --fold-spec-const-op-composite $T/$1.b.spv -o $T/$1.c.spv
  spirv-opt -O $T/$1.c.spv -o $T/$1.o.spv
  mkdir -p $T/r_$1; spirv-remap --map all --strip all -i $T/$1.o.spv -o $T/r_$1 > /dev/null
  spirv-dis --no-header $T/r_$1/$1.o.spv > $T/$1.dis
}
for cfg in "0:3 1:true 2:false 4:false 5:0 7:false" "0:0 1:true 2:false 4:false 5:0 7:false" "0:3 1:true 2:true 4:false 5:0 7:false 9:true"; do
  for deep in 0 1 2; do
    spec main "$cfg 8:$deep 100:true"; spec branch "$cfg 8:$deep 100:true"
    cmp -s $T/main.dis $T/branch.dis && r=same || r="differ ($(diff $T/main.dis $T/branch.dis | grep -c '^[<>]') lines)"
    echo "file form (NODES_FILE true) $cfg DEEP $deep: $r"
  done
done
