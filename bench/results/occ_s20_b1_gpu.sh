#!/bin/bash
# occ (issue 21, twentieth sitting), batch 1 (limit 100 s): the occupancy probe without shared memory (ray7's batch 2,
# paths adapted). A: main's render_bench (eb010c8, --esvo-kernels, the warps' lane use). k.tgz: trace.comp / esvo.comp
# variants of bench/results/issue21_s19_variants.patch + occ's r7k[RAY7_REG] (macros RAY7_*):
#   regN: N words loaded before the walk's loop and used after it (registers held across the loop, no shared memory,
#   the L1 unchanged): ESVO 32 -> 33..40 registers = 64 -> 50 warps/SM, 41..48 = 42 warps; voxkit 39 -> 41..48 = 42.
#   nog: the depth kernel without the iteration guard. c_*: occ's variants (c.list; macros OCC_*, bench/results/occ_s20_variants.patch):
#   nopath / notail (diagnostic: no start below the root / no t after the loop), se (scale_exp2 from scale at the loop top),
#   tmax (no ray-end test at the push), hh (every push stores its parent), px1 (the pixel index before the walk), lean5 (se+nog+tmax+hh+px1)
# Two processes (P1, P2), ogt_doom first as a burn-in; --shader-stats for every kernel's registers.
export LD_LIBRARY_PATH=bench/out/base/bin
L=bench/out/occ; A=bench/out/base/bin/render_bench
T=$(mktemp -d); tar xzf $L/k.tgz -C $T
SIZE=${SIZE:-1920x1080}; WU=${WU:-0.1}; RUNS=${RUNS:-10}; V=${V:-overview,oblique,closeup}
S1="$L/ogt_doom.vox $L/eph_monu1.vox $L/eph_menger.vox $L/eph_dragon.vox"
S2="$L/eph_dragon.vox $L/eph_menger.vox $L/eph_monu1.vox $L/ogt_doom.vox"
s0=$(date +%s); left() { echo $(( $1 - ($(date +%s) - s0) )); }
F='^eph|^ogt|^esvo-variant|^stats: (trace \[spec 3,1,0,0,0,0,1,1|esvo)'
echo "== occ batch 1, A $(cat bench/out/base/bin/COMMIT 2>/dev/null | head -c 12), on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1) $(date -u +%T)"
timeout 4 $A --no-esvo --sizes $SIZE --runs 200 --warmup 2 --views overview $L/eph_monu1.vox > /dev/null 2>&1
K=""; for k in main reg4 reg8 nog; do K="$K,$T/k_$k.spv@c1"; done
E=""; for k in reg1 reg2 reg8 reg12; do E="$E,$T/e_$k.spv"; done
C=""; [ -f $T/c.list ] && for k in $(cat $T/c.list); do C="$C,$T/$k@c1"; done
run() { # $1 limit, $2 kernels, $3 esvo kernels, $4.. scenes
  local l=$1 k=$2 e=$3; shift 3
  timeout $l $A --sizes $SIZE --runs $RUNS --warmup $WU --views $V --shader-stats --kernels ${k#,} ${e:+--esvo-kernels ${e#,}} "$@" 2>&1 \
    | grep -E "$F" | sed "s|$T/||g; s/\[shadow rays[^]]*\]  //; s/\[traced[^]]*\]  //" | cut -c1-330
}
l=$(left 52); echo "-- P1 probe $(date -u +%T)"; run $l "$K" "$E" $S1
l=$(left 97); [ $l -gt 5 ] && { echo "-- P2 $( [ -n "$C" ] && echo candidates || echo probe) $(date -u +%T)";
  if [ -n "$C" ]; then run $l "$T/k_main.spv@c1$C" "" $S2; else run $l "$K" "$E" $S2; fi; }
echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
