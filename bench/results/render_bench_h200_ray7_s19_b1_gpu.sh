#!/bin/bash
# ray7 (issue 21, nineteenth sitting), batch 1 (limit 100 s): where the per-step gap against ESVO is, by
# measurement. B: the branch's render_bench (main ca70d1a's kernels built in, plus --esvo-kernels and the warps'
# lane use); k.tgz: trace.comp and esvo.comp variants (issue21_s19_variants.patch, macros RAY7_*):
#   ialu  +8 rounds of two integer operations per loop iteration, off the loop's chain (issue probe)
#   ld2   each node load followed by a dependent second load of the same word (latency probe)
#   alu2  the same two operations on the chain without the second load (its control)
#   padN  shared memory that bounds the groups per SM to N warps (occupancy probe, L1 carveout at its maximum)
#   pre   voxkit: the inner child's descriptor loaded at the step's top (candidate)
#   stk2  voxkit: the descriptor kept on the stack beside its node, a pop loads nothing (candidate)
# 1: B with every probe, voxkit's (--kernels) and ESVO's (--esvo-kernels), in one process, --shader-stats.
# 2: B with the candidates and main's kernel compiled apart (k_main: the noise), in one process.
# 3: A (main's binary) as time allows: B's built-in kernel is main's.
export LD_LIBRARY_PATH=bench/out/base/bin
L=bench/out/ray7; A=bench/out/base/bin/render_bench; B=$L/render_bench
T=$(mktemp -d); tar xzf $L/k.tgz -C $T
SIZE=${SIZE:-1920x1080}; WU=${WU:-0.1}; RUNS=${RUNS:-10}; V=overview,oblique,closeup
S="$L/eph_monu1.vox $L/eph_menger.vox $L/ogt_doom.vox $L/eph_dragon.vox"
s0=$(date +%s); left() { echo $(( $1 - ($(date +%s) - s0) )); }
F='^eph|^ogt|^esvo-variant|^stats: (trace \[spec 3,1,0,0,0,0,1,1|esvo)'
echo "== ray7 batch 1, B $(head -1 $L/REV), on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1) $(date -u +%T)"
timeout 4 $A --no-esvo --sizes $SIZE --runs 200 --warmup 2 --views overview $L/eph_monu1.vox > /dev/null 2>&1
K1=""; for k in main ialu ld2 alu2 pad50 pad42 pad32; do K1="$K1,$T/k_$k.spv@c1"; done
E1=""; for k in ialu ld2 alu2 pad64 pad50 pad42 pad32; do E1="$E1,$T/e_$k.spv"; done
echo "-- 1: probes, B $(date -u +%T)"
timeout $(left 62) $B --sizes $SIZE --runs $RUNS --warmup $WU --views $V --shader-stats --kernels ${K1#,} \
  --esvo-kernels ${E1#,} $S 2>&1 | grep -E "$F" | sed "s|$T/||g" | cut -c1-420
echo "-- 2: candidates, B $(date -u +%T)"
l=$(left 92); [ $l -gt 5 ] && timeout $l $B --sizes $SIZE --runs $RUNS --warmup $WU --views $V --shader-stats \
  --kernels $T/k_pre.spv@c1,$T/k_stk2.spv@c1,$T/k_main.spv@c1 $S 2>&1 | grep -E "$F" | sed "s|$T/||g" | cut -c1-420
echo "-- 3: A $(date -u +%T)"
l=$(left 97); [ $l -gt 5 ] && timeout $l $A --sizes $SIZE --runs $RUNS --warmup $WU --views $V $S 2>&1 | grep -E '^eph|^ogt' | cut -c1-300
echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
