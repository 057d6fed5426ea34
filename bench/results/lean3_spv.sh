#!/bin/bash
# lean3: trace_compact.comp specialised (spirv-opt set, freeze, fold, -O) and validated (spirv-val); main's and the
# branch's disassembly compared per configuration: the kernels without the lean walk must be main's.
#   bash lean3_spv.sh MAIN_SRC BRANCH_SRC [X_SRC]
T=/tmp/lean3spv; rm -rf $T; mkdir -p $T
for v in main:$1 branch:$2 ${3:+x:$3}; do
  glslangValidator -V --target-env vulkan1.1 -o $T/${v%%:*}.spv ${v#*:}/render/shaders/trace_compact.comp > /dev/null || echo "COMPILE FAILED ${v%%:*}"
done
spec() { # name constants -> $T/name.dis
  spirv-opt --set-spec-const-default-value "$2" $T/$1.spv -o $T/$1.a.spv &&
  spirv-opt --freeze-spec-const $T/$1.a.spv -o $T/$1.b.spv &&
  spirv-opt --fold-spec-const-op-composite $T/$1.b.spv -o $T/$1.c.spv &&
  spirv-val --target-env vulkan1.1 $T/$1.c.spv || echo "INVALID $1: $2"
  spirv-opt -O $T/$1.c.spv -o $T/$1.o.spv
  rm -rf $T/r_$1; mkdir -p $T/r_$1; spirv-remap --map all --strip all -i $T/$1.o.spv -o $T/r_$1 > /dev/null
  spirv-dis --no-header $T/r_$1/$1.o.spv > $T/$1.dis
}
# ids: 0 MODE 1 HAS_COLOR 2 USE_BVH 3 RECORDS 4 WRITE_HITS 6 ONE_SAMPLE 7 UNIFORM 8 DEEP 9 PAGES 12 PATH_START 100 NODES_FILE
same=0; differ=0
for cfg in "0:1 2:false 4:false 9:0 100:false" "0:0 2:false 4:false 9:0 100:false" "0:3 2:false 4:false 9:0 100:false" \
           "0:1 2:false 4:true 9:0 100:false" "0:1 2:true 4:false 9:0 100:false" "0:1 2:false 4:false 9:64 100:false" \
           "0:1 2:false 4:false 9:0 100:true" "0:0 2:false 4:false 9:0 100:true" "0:5 2:false 4:false 9:0 100:false"; do
  for deep in 0 1 2; do
    c="1:true 3:true 6:true 7:true 12:true $cfg 8:$deep"
    spec main "$c"; spec branch "$c"
    lean=no; case "$cfg" in "0:"[0-4]" 2:false 4:false 9:0 100:false") [ $deep -le 1 ] && lean=yes;; esac
    if cmp -s $T/main.dis $T/branch.dis; then same=$((same + 1)); r=same; else differ=$((differ + 1)); r="DIFFER $(diff $T/main.dis $T/branch.dis | grep -c '^[<>]') lines"; fi
    echo "$c (lean $lean): $r"
    if [ -n "$3" ]; then for lv in 0 7 8 32 64; do spec x "$c 13:$lv"; done; fi
  done
done
echo "$same the same as main's, $differ differ"
