#!/bin/bash
# occ (issue 21, twentieth sitting), batch 3 (limit 100 s): is the lean kernel's gain its occupancy? and ESVO at fewer
# warps. A: main's render_bench (eb010c8); B: the branch's (TRACE_LEAN, as batch 2). k.tgz (occ_s20_variants.patch):
# l_regN: lean5 (batch 1) with N words held across the loop (ray7's RAY7_REG probe): 33+ registers = 50 warps per
# SM again with the lean loop; e_regN: ESVO with N distinct words held (16, 24: 41-48 / 49-56 registers = 42 / 36
# warps; batch 1's reg12 held only 8 distinct words and stayed at 40). V: B with k_main, b_lean, l_reg1/2/4 and
# e_reg2/16/24 on the obliques and close-ups; then A B A B (as time allows) over the four scenes, three views.
export LD_LIBRARY_PATH=bench/out/base/bin
L=bench/out/occ; A=bench/out/base/bin/render_bench
T=$(mktemp -d); tar xzf $L/k.tgz -C $T; gunzip -c $L/render_bench.gz > $T/render_bench; chmod +x $T/render_bench; B=$T/render_bench
SIZE=${SIZE:-1920x1080}; WU=${WU:-0.1}; RUNS=${RUNS:-10}; V=${V:-overview,oblique,closeup}
S="$L/eph_monu1.vox $L/eph_menger.vox $L/ogt_doom.vox $L/eph_dragon.vox"
s0=$(date +%s); left() { echo $(( $1 - ($(date +%s) - s0) )); }
F='^eph|^ogt|^esvo-variant|^stats: (trace \[spec (3|0),1,0,0,0,0,1,1|esvo)'
flt() { sed "s|$T/||g; s/\[shadow rays[^]]*\]  //; s/\[traced[^]]*\]  //" | cut -c1-330; }
echo "== occ batch 3, A $(cat bench/out/base/bin/COMMIT 2>/dev/null | head -c 12), on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1) $(date -u +%T)"
timeout 4 $A --no-esvo --sizes $SIZE --runs 200 --warmup 2 --views overview $L/eph_monu1.vox > /dev/null 2>&1
K=""; for k in k_main b_lean l_reg1 l_reg2 l_reg4; do K="$K,$T/$k.spv@c1"; done
E=""; for k in e_reg2 e_reg16 e_reg24; do E="$E,$T/$k.spv"; done
l=$(left 40); echo "-- V: variants in B $(date -u +%T)"
timeout $l $B --sizes $SIZE --runs $RUNS --warmup $WU --views oblique,closeup --shader-stats --kernels ${K#,} --esvo-kernels ${E#,} $S 2>&1 | grep -E "$F" | flt
for r in 1 2; do
  for x in A B; do
    case $r$x in 1A) d=55;; 1B) d=70;; 2A) d=84;; 2B) d=98;; esac
    l=$(left $d); [ $l -gt 3 ] || continue
    echo "-- $x$r $(date -u +%T)"
    timeout $l ${!x} --sizes $SIZE --runs $RUNS --warmup $WU --views $V --shader-stats $S 2>&1 | grep -E "$F" | flt
  done
done
echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
