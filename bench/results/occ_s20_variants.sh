#!/bin/sh
# issue 21, twentieth sitting (occ): the probe and candidate kernels of the H200 batches, built from main eb010c8's
# tree with occ_s20_variants.patch applied (batch 2: l_noX, lean5 without part X; b_lean is the branch's trace.comp) (ray7's macros RAY7_* with r7k[RAY7_REG], and occ's OCC_*):
#   sh occ_s20_variants.sh TREE OUTDIR   (k_main is main's trace.comp, unpatched: build it from an unpatched tree).
# ESVO's RAY7_REG words are distinct up to 8 (& 7) and, past 8, up to 32 (& 31); batch 1's e_reg12 was built before
# that (& 7 for every N: 12 loads of 8 distinct words, which the compiler held in 8 registers: 40, as e_reg8)
set -e
T=$1; O=$2; mkdir -p $O
while read name defs; do
  [ -z "$name" ] && continue
  glslangValidator -V --target-env vulkan1.1 $defs -o $O/$name.spv $T/render/shaders/trace.comp > /dev/null
done <<'LIST'
k_reg4 -DRAY7_PROBE -DRAY7_REG=4
k_reg8 -DRAY7_PROBE -DRAY7_REG=8
k_nog -DRAY7_NOG
c_nopath -DOCC_NOPATH
c_notail -DOCC_NOTAIL
c_se -DOCC_SE
c_tmax -DOCC_TMAX
c_hh -DOCC_HH
c_px1 -DOCC_PX1
c_lean5 -DOCC_SE -DRAY7_NOG -DOCC_TMAX -DOCC_HH -DOCC_PX1
l_nose -DRAY7_NOG -DOCC_TMAX -DOCC_HH -DOCC_PX1
l_nopx -DOCC_SE -DRAY7_NOG -DOCC_TMAX -DOCC_HH
l_nohh -DOCC_SE -DRAY7_NOG -DOCC_TMAX -DOCC_PX1
l_notmax -DOCC_SE -DRAY7_NOG -DOCC_HH -DOCC_PX1
l_nonog -DOCC_SE -DOCC_TMAX -DOCC_HH -DOCC_PX1
l_reg1 -DOCC_SE -DRAY7_NOG -DOCC_TMAX -DOCC_HH -DOCC_PX1 -DRAY7_PROBE -DRAY7_REG=1
l_reg2 -DOCC_SE -DRAY7_NOG -DOCC_TMAX -DOCC_HH -DOCC_PX1 -DRAY7_PROBE -DRAY7_REG=2
l_reg4 -DOCC_SE -DRAY7_NOG -DOCC_TMAX -DOCC_HH -DOCC_PX1 -DRAY7_PROBE -DRAY7_REG=4
LIST
while read name defs; do
  [ -z "$name" ] && continue
  glslangValidator -V --target-env vulkan1.1 $defs -o $O/$name.spv $T/bench/shaders/esvo.comp > /dev/null
done <<'LIST'
e_reg1 -DRAY7_REG=1
e_reg2 -DRAY7_REG=2
e_reg8 -DRAY7_REG=8
e_reg12 -DRAY7_REG=12
e_reg16 -DRAY7_REG=16
e_reg24 -DRAY7_REG=24
LIST
