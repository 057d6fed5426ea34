#!/bin/bash
# ray7 (issue 21, nineteenth sitting), batch 2 (limit 100 s): occupancy without the L1 carveout, and the issue probe's
# slope. B: the branch's render_bench (main ca70d1a's kernels built in, --esvo-kernels, warps' lane use); k.tgz:
# variants (issue21_s19_variants.patch, macros RAY7_*): regN: N words loaded before the walk's loop and used after it
# (registers held across the loop: ESVO from 32 to more, i.e. 64 -> 50 warps per SM; voxkit from 39 to more, 50 -> 42
# warps; no shared memory, so L1 keeps its size); ialu4 / ialu: 4 / 8 rounds of two dependent integer operations per
# loop iteration off the loop's chain. One command, two processes (B1, B2); ogt_doom first as a burn-in (batch 1's
# first scene had slow rows in both processes). nog: the depth kernel without the iteration count and guard (the colour
# kernel's form: the advance tests !(tc > tc_max), so NaN times still leave the root).
export LD_LIBRARY_PATH=bench/out/base/bin
L=bench/out/ray7; A=bench/out/base/bin/render_bench; B=$L/render_bench
T=$(mktemp -d); tar xzf $L/k.tgz -C $T
SIZE=${SIZE:-1920x1080}; WU=${WU:-0.1}; RUNS=${RUNS:-10}; V=overview,oblique,closeup
S="$L/ogt_doom.vox $L/eph_monu1.vox $L/eph_menger.vox $L/eph_dragon.vox $L/ogt_doom.vox"
s0=$(date +%s); left() { echo $(( $1 - ($(date +%s) - s0) )); }
F='^eph|^ogt|^esvo-variant|^stats: (trace \[spec 3,1,0,0,0,0,1,1|esvo)'
echo "== ray7 batch 2, B $(head -1 $L/REV), on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1) $(date -u +%T)"
timeout 4 $A --no-esvo --sizes $SIZE --runs 200 --warmup 2 --views overview $L/eph_monu1.vox > /dev/null 2>&1
K=""; for k in main ialu4 ialu reg4 reg8 nog; do K="$K,$T/k_$k.spv@c1"; done
E=""; for k in ialu4 ialu reg2 reg8; do E="$E,$T/e_$k.spv"; done
for p in 1 2; do
  l=$(left $((p == 1 ? 50 : 97))); [ $l -gt 5 ] || break
  echo "-- B$p $(date -u +%T)"
  timeout $l $B --sizes $SIZE --runs $RUNS --warmup $WU --views $V --shader-stats --kernels ${K#,} --esvo-kernels ${E#,} $S 2>&1 \
    | grep -E "$F" | sed "s|$T/||g; s/\[shadow rays[^]]*\]  //; s/\[traced[^]]*\]  //" | cut -c1-330
done
echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
