#!/bin/bash
# lean2 (issue 21): the lean walk in the colour / G-buffer kernels. Batch 2: registers (--shader-stats) and rates of
# trace.comp variants in one process (--kernels; colour frames compared with the built-in): t_main (main's), t_lean
# (the branch's: the colour kernels of one instance lean, DEEP 0), t_d1 (also DEEP 1), t_bvh (also the BVH kernels),
# t_bvhd1 (both). Then A (main 1695247) against B (branch: trace.comp's colour kernels lean; the G-buffer kernels
# (frame.comp, gbuffer.comp) lean) and C (B with the G-buffer's camera ray formed again after the walk) process by
# process; svo_render images of A and B compared (cmp). passes_bench of A is main's library with the branch's
# bench driver (--quick, --warmup). SIZE, RUNS, WU, CHK (svo_render size), TS (time scale) may be set (lavapipe).
# (Batch 1, lean2_b1.txt, was this script with the variants t_main t_lean t_re t_re3 t_bvh t_bvhre t_bvhre3 on the
# close-ups only, B = t_re with the G-buffer's ray formed again, C = B without it, passes_bench without --warmup.)
# Payload: bins.tgz (A, B, C: render_bench, passes_bench, svo_render, gzipped), k.tgz (k/*.spv, lean2_variants.sh),
# eph_monu1.vox, eph_menger.vox, island.vox (vox2svo --write-demo), terrain1024.svo (lean2_mkterrain.c) and their
# .svo (vox2svo) for svo_render.
s0=$(date +%s); left() { echo $(( $1 * ${TS:-1} - ($(date +%s) - s0) )); }
T=/tmp/lean2; rm -rf $T; mkdir -p $T; tar xzf bins.tgz -C $T; for f in $T/*/*.gz; do gunzip -f $f; done; chmod +x $T/*/*
tar xzf k.tgz -C $T
SIZE=${SIZE:-1920x1080}; RUNS=${RUNS:-10}; WU=${WU:-0.1}; CHK=${CHK:-1920x1080}; PWU=${PWU:-0.2}
S="eph_monu1.vox eph_menger.vox terrain1024.svo island.vox"
echo "== lean2 batch 2 on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1) $(nproc) CPUs $(date -u +%T); A $(cat A_COMMIT), B/C $(cat B_COMMIT)"
flt() { sed "s|$T/||g; s/\[shadow rays[^]]*\]  //; s/\[traced[^]]*\]  //; s/  *\[warps[^]]*\]//" | cut -c1-300; }
F='^scene|^eph|^terrain|^island|^stats: |^device'
l=$(left 4); timeout $l $T/A/render_bench --no-esvo --sizes $SIZE --runs 200 --warmup 1 --views overview eph_monu1.vox > /dev/null 2>&1
K=""; for k in t_main t_lean t_d1 t_bvh t_bvhd1; do K="$K,$T/k/$k.spv@c1"; done
echo "-- V: B with the variants $(date -u +%T)"
l=$(left 22); timeout $l $T/B/render_bench --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU --views closeup,oblique --shader-stats --kernels ${K#,} island.vox 2>&1 | grep -E "$F" | flt
l=$(left 40); timeout $l $T/B/render_bench --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU --views closeup --shader-stats --kernels ${K#,} terrain1024.svo eph_monu1.vox 2>&1 | grep -E "$F" | flt
echo "-- stats of the pass kernels: A, then C $(date -u +%T)"
for x in A C; do l=$(left 45); timeout $l $T/$x/render_bench --no-esvo --sizes 64x64 --runs 1 --warmup 0 --views overview --shader-stats eph_monu1.vox terrain1024.svo island.vox 2>&1 | grep -E "^stats: (frame|gbuffer)" | sed "s/^/$x /" | flt; done
echo "-- svo_render A against B (cmp) $(date -u +%T)"
n=0; bad=0
for cfg in "p:--passes gbuffer,direct" "s:--passes gbuffer,direct --separate-passes" "a:--mode albedo" "n:--mode normal"; do
  for sc in island eph_monu1 terrain1024 eph_menger; do
    [ $(left 65) -gt 2 ] || break
    for x in A B; do timeout 20 $T/$x/svo_render $sc.svo $T/$x.$sc.${cfg%%:*}.pfm --size $CHK ${cfg#*:} > /dev/null 2>&1 || echo "   $x $sc ${cfg%%:*}: rc $?"; done
    n=$((n + 1)); if cmp -s $T/A.$sc.${cfg%%:*}.pfm $T/B.$sc.${cfg%%:*}.pfm; then :; else bad=$((bad + 1)); echo "   DIFFER: $sc ${cfg#*:} ($(cmp -l $T/A.$sc.${cfg%%:*}.pfm $T/B.$sc.${cfg%%:*}.pfm 2>&1 | wc -l) bytes)"; fi
  done
done
echo "   $n images compared, $bad differ"
dl=80
for r in 1 2; do
  for x in A B; do
    l=$(left $dl); dl=$((dl + 15)); [ $l -gt 3 ] || continue
    echo "-- render_bench $x$r $(date -u +%T)"
    timeout $l $T/$x/render_bench --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU island.vox eph_monu1.vox eph_menger.vox terrain1024.svo 2>&1 | grep -E "$F" | flt
  done
done
dl=132
for r in 1 2; do
  for x in A B C; do
    [ $r = 2 ] && [ $x = C ] && continue
    l=$(left $dl); dl=$((dl + 7)); [ $l -gt 3 ] || continue
    echo "-- passes_bench $x$r $(date -u +%T)"
    timeout $l $T/$x/passes_bench --quick --warmup $PWU --runs $RUNS --size $SIZE $S 2>&1 | grep -E "^## |^\| (single|gbuffer)|check"
  done
done
echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
