#!/bin/bash
# ray6 (issue 21, seventeenth sitting), batch 2 (limit 100 s). Main's render_bench (bench/out/base/bin, 46eb6d3)
# with trace kernel variants built from the branch's source (--kernels). Batch 1: the deep kernel in the GPU form
# without the turn had 96 registers (k_gf), 56-64 with the stack array kept in local memory (k_gfz, k_gfp2);
# its timings on terrain4096 fell in a slow phase of that process.
# 1: shader statistics only (320x180, closeup, one process, terrains): 7 more variants of the deep kernel in the
#    GPU form: gfp2 (stack array padded to 128), gfzp2 (+ rebase slots through an opaque 0), gfx (the loaded
#    word XORed with an opaque 0), gfxp2, gf1p2 (one call site + pad), gfp3 (pad to 96), gfx1.
# 2: the two with the fewest registers on terrain4096's colour kernel, timed: F (VX_GPU_NODE_FORM=file, the file
#    form's rate, the goal) and G (GPU form: built-in kernel = main's turn, + the two), F G F G, terrains,
#    oblique and closeup, no --shader-stats.
# 3: k_wt (the walk's loop without its scale test) on eph_menger and eph_monu1 with ESVO, one process.
# (the k_*.spv: bench/results/issue21_s17_variants.sh)
export LD_LIBRARY_PATH=bench/out/base/bin
L=bench/out/ray6; A=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; WU=${WU:-0.1}; RUNS=${RUNS:-10}; SSIZE=${SSIZE:-320x180}
s0=$(date +%s); left() { echo $(( $1 - ($(date +%s) - s0) )); }
echo "== ray6 batch 2 on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1) $(date -u +%T)"
timeout 4 $A/render_bench --no-esvo --sizes $SIZE --runs 200 --warmup 2 --views overview $L/eph_monu1.vox > /dev/null 2>&1
VARS="gfp2 gfzp2 gfx gfxp2 gf1p2 gfp3 gfx1"
K=""; for v in $VARS; do K="$K${K:+,}$L/k_$v.spv@c1"; done
echo "-- 1: statistics sweep $(date -u +%T)"
timeout $(left 22) $A/render_bench --generate --no-esvo --sizes $SSIZE --runs 1 --warmup 0 --views closeup --kernels $K --shader-stats \
  > /tmp/ray6_sweep.txt 2>&1
# per variant: the colour kernel (SMAP, no hits) of terrain4096 printed before its row
awk '/^stats: trace \[spec 0,1,0,0,0,0,1,1,2,1,0,1,0\]/ { match($0, /Register Count=[0-9]+/); r = substr($0, RSTART + 15, RLENGTH - 15);
       match($0, /Binary Size=[0-9]+/); b = substr($0, RSTART + 12, RLENGTH - 12); match($0, /Local Memory Size=[0-9]+/); lm = substr($0, RSTART + 18, RLENGTH - 18) - 68719476736 }
     /^terrain4096/ { k = "built-in"; if (match($0, /k_[a-z0-9]+\.spv/)) k = substr($0, RSTART, RLENGTH - 4); print k, r, b, lm }' /tmp/ray6_sweep.txt > /tmp/ray6_regs.txt
echo "variant registers binary local (terrain4096 colour kernel)"; cat /tmp/ray6_regs.txt
grep -E '^stats: trace \[spec [03],1,0,0,[01],0,1,1,2' /tmp/ray6_sweep.txt | cut -c1-200
grep -E 'px differ' /tmp/ray6_sweep.txt | grep -v '0 px differ from the first row, 0 in colour' | cut -c1-300
BEST=$(grep '^k_' /tmp/ray6_regs.txt | sort -k2,2n -k3,3n | head -2 | awk '{print $1}')
K2=""; for v in $BEST; do K2="$K2${K2:+,}$L/$v.spv@c1"; done
echo "-- 2: timed: $BEST $(date -u +%T)"
for round in 1 2; do
  for who in F G; do
    l=$(left 82); [ $l -gt 6 ] || break 2
    echo "-- round $round $who $(date -u +%T)"
    if [ $who = F ]; then
      VX_GPU_NODE_FORM=file timeout $l $A/render_bench --generate --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU --views oblique,closeup 2>&1 | grep -E '^terr' | cut -c1-420
    else
      timeout $l $A/render_bench --generate --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU --views oblique,closeup $( [ -n "$K2" ] && echo --kernels $K2 ) 2>&1 | grep -E '^terr' | cut -c1-420
    fi
  done
done
echo "-- 3: eph_menger, eph_monu1 with ESVO, k_wt $(date -u +%T)"
l=$(left 98); [ $l -gt 6 ] && timeout $l $A/render_bench --sizes $SIZE --runs $RUNS --warmup $WU --views overview,oblique,closeup \
  --kernels $L/k_wt.spv@c1 $L/eph_menger.vox $L/eph_monu1.vox 2>&1 | grep -E '^eph' | cut -c1-420
echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
