#!/bin/bash
# occ (issue 21, twentieth sitting), batch 2 (limit 100 s): the lean depth kernel (32 registers in batch 1: lean5)
# built in, against main's binary process by process, and which of its five parts the 32 registers need.
# A: main's render_bench (eb010c8). B: the branch's (trace.comp with TRACE_LEAN: the primary depth kernel of one
# instance without the iteration guard, scale_exp2 from scale at the loop's top, no ray-end test at a push, every push
# storing its parent, the pixel index before the walk). k.tgz: k_main (main's trace.comp), b_lean (the branch's),
# c_lean5 (batch 1's), l_noX: lean5 without part X (se, px, hh, tmax, nog), from occ_s20_variants.patch.
# V: B with the variants on two close-ups (registers, rates); then A B A B over the four scenes, three views.
export LD_LIBRARY_PATH=bench/out/base/bin
L=bench/out/occ; A=bench/out/base/bin/render_bench
T=$(mktemp -d); tar xzf $L/k.tgz -C $T; gunzip -c $L/render_bench.gz > $T/render_bench; chmod +x $T/render_bench; B=$T/render_bench
SIZE=${SIZE:-1920x1080}; WU=${WU:-0.1}; RUNS=${RUNS:-10}; V=${V:-overview,oblique,closeup}
S="$L/eph_monu1.vox $L/eph_menger.vox $L/ogt_doom.vox $L/eph_dragon.vox"
s0=$(date +%s); left() { echo $(( $1 - ($(date +%s) - s0) )); }
F='^eph|^ogt|^esvo-variant|^stats: (trace \[spec (3|0),1,0,0,0,0,1,1|esvo)'
flt() { sed "s|$T/||g; s/\[shadow rays[^]]*\]  //; s/\[traced[^]]*\]  //" | cut -c1-330; }
echo "== occ batch 2, A $(cat bench/out/base/bin/COMMIT 2>/dev/null | head -c 12), on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1) $(date -u +%T)"
timeout 4 $A --no-esvo --sizes $SIZE --runs 200 --warmup 2 --views overview $L/eph_monu1.vox > /dev/null 2>&1
K=""; for k in k_main b_lean c_lean5 l_nose l_nopx l_nohh l_notmax l_nonog; do K="$K,$T/$k.spv@c1"; done
l=$(left 24); echo "-- V: variants in B $(date -u +%T)"
timeout $l $B --sizes $SIZE --runs $RUNS --warmup $WU --views closeup --shader-stats --kernels ${K#,} $L/eph_monu1.vox $L/eph_dragon.vox 2>&1 | grep -E "$F" | flt
for r in 1 2; do
  for x in A B; do
    case $r$x in 1A) d=43;; 1B) d=62;; 2A) d=80;; 2B) d=98;; esac
    l=$(left $d); [ $l -gt 3 ] || continue
    echo "-- $x$r $(date -u +%T)"
    timeout $l ${!x} --sizes $SIZE --runs $RUNS --warmup $WU --views $V --shader-stats $S 2>&1 | grep -E "$F" | flt
  done
done
echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
