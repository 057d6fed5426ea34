#!/bin/bash
# (batch 2 as run: bake_diff = main eb010c8 + c4042b4; bake_diff_cell, svo_bake, render_bench = edf1d59; bake_diff_cellp,
# svo_bake_p = edf1d59 with `#define WALK_PRECISE` beside `#define CELL_HITS` in probes/shaders/probe.comp, not kept;
# monu1/menger/teapot.svo: vox2svo of the corpus eph_monu1/eph_menger/eph_teapot.vox with its defaults)
# issue 18 (branch bakex), batch 2: the bake's cell walk (CELL_HITS in probe.comp's bake kernels,
# render/shaders/trace_common.glsl: a leaf above the cell level walked as a full node down to the cell, no push
# tests the child's exit) against main, on the H200. bench/bake_diff bakes one set four ways in one process
# (P: plain layout, beam; Pn: plain, no beam; C: compact layout from the whole scene; M: compact layout from the
# model reader, as svo_bake --load models) and counts the differing bytes. bake_diff: main eb010c8;
# bake_diff_cell: the branch; bake_diff_cellp: the branch with the bake's walk also precise (WALK_PRECISE).
# Then svo_bake warm, main (A) / branch (B) / branch precise (P), --load whole (W) / models (M), rounds of
# AW BW PW AM BM PM, bytes compared; render_bench main / branch (trace.comp's SPIR-V is main's byte for byte).
START=$SECONDS
D=bench/out/bakex; B=bench/out/base/bin; T=/tmp/bakexq; rm -rf $T; mkdir -p $T
export LD_LIBRARY_PATH=$PWD/$B
OUT=${OUTDIR:-$T/out}; mkdir -p $OUT
left() { echo $(( $1 - (SECONDS - START) )); }
echo "== $(date -u) host: $(nproc) CPUs, $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1)"
for f in bake_diff bake_diff_cell bake_diff_cellp svo_bake svo_bake_p render_bench; do gzip -dc $D/$f.gz > $T/$f; chmod +x $T/$f; done
ms() { echo $(( (${2/./} - ${1/./} + 500) / 1000 )); }
diffrun() { # tag binary scene args...
  local tag=$1 bin=$2 sc=$3; shift 3
  [ $(left 45) -gt 0 ] || { echo "== $tag: skipped (time)"; return; }
  echo "== $tag: $bin $sc $*"
  timeout 20 $T/$bin $sc "$@" > $OUT/$tag.txt 2>&1; echo "  rc=$?"
  grep -E "^(P|Pn|C) vs (C|M)" $OUT/$tag.txt | sed 's/^/  /'
}
diffrun cell_cornell16 bake_diff_cell $D/cornell.svo --grid 4,4,4 --res 16 --spp 4 --max 20 --kernel inline
diffrun cell_cornell128 bake_diff_cell $D/cornell.svo --grid 8,8,8 --res 128 --spp 1 --max 20
diffrun cellp_cornell128 bake_diff_cellp $D/cornell.svo --grid 8,8,8 --res 128 --spp 1 --max 20
for sc in monu1 menger teapot; do
  diffrun main_$sc bake_diff $D/$sc.svo --grid 5,5,5 --res 64 --spp 1 --max 10
  diffrun cell_$sc bake_diff_cell $D/$sc.svo --grid 5,5,5 --res 64 --spp 1 --max 20
  diffrun cellp_$sc bake_diff_cellp $D/$sc.svo --grid 5,5,5 --res 64 --spp 1 --max 20
done
echo "== elapsed $((SECONDS-START)) s"
echo "== svo_bake warm, main (A) / branch (B) / branch precise (P), --load whole (W) / models (M), R=128 64 spp"
ARGS="--grid 8,8,8 --res 128 --spp 64 -q -v"
bin_of() { case $1 in A) echo $B/svo_bake;; B) echo $T/svo_bake;; P) echo $T/svo_bake_p;; esac; }
for w in A B P; do for v in W M; do # warm-up: each binary's kernels into the driver's cache
  extra=""; [ $v = M ] && extra="--load models"
  timeout 20 $(bin_of $w) $D/cornell.svo $T/warm.probes $ARGS $extra > /dev/null 2>&1; done; done
for r in 1 2 3; do
  for wv in AW BW PW AM BM PM; do
    [ $(left 82) -gt 0 ] || break 2
    w=${wv:0:1}; v=${wv:1:1}; extra=""; [ $v = M ] && extra="--load models"
    s=$EPOCHREALTIME; timeout 20 $(bin_of $w) $D/cornell.svo $T/$wv.probes $ARGS $extra > $T/run.log 2>&1; rc=$?
    echo "  $wv round $r rc=$rc wall $(ms $s $EPOCHREALTIME) ms: $(grep -oE 'bake [0-9.]+ s' $T/run.log | head -1); $(grep -oE 'GPU trace [0-9.]+ s' $T/run.log | head -1)"
  done
  [ $r = 1 ] && grep -E "^(gpu|times|stats|bake)" $T/run.log | cut -c1-240 | sed 's/^/    last: /'
  for p in "AW AM" "BW BM" "PW PM" "AW BW" "AW PW" "BW PW"; do set -- $p; echo "  cmp $1 $2: $(cmp -l $T/$1.probes $T/$2.probes 2>/dev/null | wc -l) bytes differ"; done
done
echo "== render_bench main (A) / branch (B), monu1 and menger, ABAB, elapsed $((SECONDS-START)) s"
for who in A B A B; do
  l=$(left 97); [ $l -gt 6 ] || break
  bin=$T/render_bench; [ $who = A ] && bin=$B/render_bench
  echo "-- $who"; timeout $l $bin --no-esvo --runs 5 --warmup 0.2 --views overview,closeup $D/monu1.svo $D/menger.svo 2>&1 | grep -E '^(scene|monu|menger)' | cut -c1-150 | head -6
done
echo "== done in $((SECONDS-START)) s"
