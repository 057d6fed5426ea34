#!/bin/bash
# issue 18 (branch bakex), batch 1: which rays of the probe bake differ between the plain and the compact layout
# on the H200. bench/bake_diff (a diagnostic) bakes one small set four ways in one process (P: plain layout with
# the beam pass, Pn: plain without it, C: compact layout from the whole scene, M: compact layout from the model
# reader, as svo_bake --load models), counts the differing bytes per array and lists the differing texels with
# both bakes' distance, normal and radiance and the CPU caster's double-precision hit of the centre ray (the
# entry planes' gap: an edge tie). Then main's svo_bake --load whole against --load models, warm, ABAB.
# (bake_diff built from main eb010c8 + bench/bake_diff.c, c4042b4's; bench/out/bakex/cornell.svo: the Cornell box
# of the coordinator's bench/results/coord_h200_bake_models_diff.sh)
START=$SECONDS
D=bench/out/bakex; B=bench/out/base/bin; T=/tmp/bakexq; rm -rf $T; mkdir -p $T
export LD_LIBRARY_PATH=$PWD/$B
OUT=${OUTDIR:-$T/out}; mkdir -p $OUT
echo "== $(date -u) host: $(nproc) CPUs, $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1)"
gzip -dc $D/bake_diff.gz > $T/bake_diff; chmod +x $T/bake_diff
ms() { echo $(( (${2/./} - ${1/./} + 500) / 1000 )); }
echo "== bake_diff R=16, 64 probes, 1 spp"
timeout 40 $T/bake_diff $D/cornell.svo --grid 4,4,4 --res 16 --spp 1 --max 80 > $OUT/diff_r16.txt 2>&1; echo "rc=$?"
grep -E "^(device|P|Pn|C) " $OUT/diff_r16.txt; head -c 6000 $OUT/diff_r16.txt | grep -E "^  probe|cpu:|^      " | head -60
echo "== bake_diff R=16, 64 probes, 4 spp (--kernel inline)"
timeout 40 $T/bake_diff $D/cornell.svo --grid 4,4,4 --res 16 --spp 4 --max 20 --kernel inline > $OUT/diff_r16s4.txt 2>&1; echo "rc=$?"
grep -E "^(device|P|Pn|C) " $OUT/diff_r16s4.txt
echo "== bake_diff R=128, 512 probes, 1 spp"
timeout 60 $T/bake_diff $D/cornell.svo --grid 8,8,8 --res 128 --spp 1 --max 200 > $OUT/diff_r128.txt 2>&1; echo "rc=$?"
grep -E "^(device|P|Pn|C) " $OUT/diff_r128.txt
echo "== elapsed $((SECONDS-START)) s"
echo "== main's svo_bake warm, --load whole (W) against --load models (M), R=128 64 spp, ABAB"
ARGS="--grid 8,8,8 --res 128 --spp 64 -q -v"
timeout 30 $B/svo_bake $D/cornell.svo $T/warm.probes $ARGS > /dev/null 2>&1 # warm-up (shader cache)
timeout 30 $B/svo_bake $D/cornell.svo $T/warm.probes $ARGS --load models > /dev/null 2>&1
for r in 1 2 3; do
  for v in W M; do
    [ $((SECONDS-START)) -gt 80 ] && break 2
    extra=""; [ $v = M ] && extra="--load models"
    s=$EPOCHREALTIME; timeout 30 $B/svo_bake $D/cornell.svo $T/$v.probes $ARGS $extra > $T/run.log 2>&1; rc=$?
    echo "  $v round $r rc=$rc wall $(ms $s $EPOCHREALTIME) ms"; grep -E "^(baked|times|gpu)" $T/run.log | sed 's/^/    /'
  done
  echo "  cmp W M: $(cmp -l $T/W.probes $T/M.probes 2>/dev/null | wc -l) bytes differ"
done
echo "== done in $((SECONDS-START)) s"
