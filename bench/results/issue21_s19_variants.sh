#!/bin/sh
# issue 21, nineteenth sitting (ray7): the probe and candidate kernels of batches 1-2, built from main ca70d1a's
# tree with issue21_s19_variants.patch applied (macros RAY7_*): sh issue21_s19_variants.sh TREE OUTDIR
set -e
T=$1; O=$2; mkdir -p $O
while read name defs; do
  [ -z "$name" ] && continue
  glslangValidator -V --target-env vulkan1.1 $defs -o $O/k_$name.spv $T/render/shaders/trace.comp > /dev/null
done <<'LIST'
main
ialu -DRAY7_PROBE -DRAY7_IALU=8
ld2 -DRAY7_PROBE -DRAY7_LD2
alu2 -DRAY7_PROBE -DRAY7_ALU2
pad50 -DRAY7_PAD=2048
pad42 -DRAY7_PAD=2432
pad32 -DRAY7_PAD=3328
pre -DRAY7_PRE
stk2 -DRAY7_STK2
LIST
while read name defs; do
  [ -z "$name" ] && continue
  glslangValidator -V --target-env vulkan1.1 $defs -o $O/e_$name.spv $T/bench/shaders/esvo.comp > /dev/null
done <<'LIST'
ialu -DRAY7_IALU=8
ld2 -DRAY7_LD2
alu2 -DRAY7_ALU2
pad64 -DRAY7_PAD=1536
pad50 -DRAY7_PAD=2048
pad42 -DRAY7_PAD=2432
pad32 -DRAY7_PAD=3328
LIST
# batch 2: the occupancy probe without shared memory (RAY7_REG words held across the loop) and the issue probe at
# half the operations
while read name defs; do
  [ -z "$name" ] && continue
  glslangValidator -V --target-env vulkan1.1 $defs -o $O/k_$name.spv $T/render/shaders/trace.comp > /dev/null
done <<'LIST'
ialu4 -DRAY7_PROBE -DRAY7_IALU=4
reg8 -DRAY7_PROBE -DRAY7_REG=8
reg4 -DRAY7_PROBE -DRAY7_REG=4
nog -DRAY7_NOG
LIST
while read name defs; do
  [ -z "$name" ] && continue
  glslangValidator -V --target-env vulkan1.1 $defs -o $O/e_$name.spv $T/bench/shaders/esvo.comp > /dev/null
done <<'LIST'
ialu4 -DRAY7_IALU=4
reg8 -DRAY7_REG=8
reg2 -DRAY7_REG=2
LIST
