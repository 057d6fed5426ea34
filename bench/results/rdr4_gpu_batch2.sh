#!/bin/bash
# rdr4 batch 2 (issue 18, branch rdr4): (a) svo_bake --load models --frame N (the frame's instances on the GPU
# scene, its bounds from the reader's model boxes) against --load whole --frame N on the animated demo
# (vox2svo --write-demo --demo-frames 8: the tower moves, four trees turn), frames 5 and 0, 512 probes R=128 64 spp;
# (b) eph_monu1 (vox2svo of the corpus .vox): batch 1 found --load whole and --load models 88 bytes apart at 512
# probes R=128 64 spp (models with and without the compact beam: the same bytes); bench/bake_diff (P plain, Pn plain
# without the beam, C compact from the whole scene, M compact from the reader) lists which arrays and texels;
# (c) where --load models' GPU time goes on the Cornell box: whole (W), whole without the sun's depth map (S:
# --no-shadow-map; the compact layout has none), models (M); warm, rounds in turn; bytes compared.
# RDR4_ARGS/RDR4_ROUNDS: a smaller bake for the dev VM's lavapipe only (unset on the device).
START=$SECONDS; T=/tmp/$NAME; rm -rf $T; mkdir -p $T
gzip -dc svo_bake.gz > $T/svo_bake; gzip -dc bake_diff.gz > $T/bake_diff; chmod +x $T/svo_bake $T/bake_diff
echo "== $(date -u +%T) host: $(nproc) CPUs, $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1), load $(cut -d' ' -f1-3 /proc/loadavg)"
ARGS=${RDR4_ARGS:-"--grid 8,8,8 --res 128 --spp 64 -q -v"}; ROUNDS=${RDR4_ROUNDS:-7}
echo "== args: $ARGS"
run() { # tag scene variant [extra] -> wall ms, bake s, GPU trace s
  local tag=$1 sc=$2 v=$3 extra=$4 env=X=0
  case $v in M|N) extra="$extra --load models";; S) extra="$extra --no-shadow-map";; esac
  case $v in N|B) env=VX_BAKE_BEAM=off;; esac
  local s=${EPOCHREALTIME/./}; env $env timeout 60 $T/svo_bake $sc $T/$tag.probes $ARGS $extra > $T/$tag.log 2>&1; local rc=$?
  local e=${EPOCHREALTIME/./}
  echo "  $tag rc=$rc wall $(( (e - s + 500) / 1000 )) ms; $(grep -oE 'bake [0-9.]+ s' $T/$tag.log | head -1); $(grep -oE 'GPU trace [0-9.]+ s' $T/$tag.log | head -1)"
}
cmpb() { echo "  cmp $1 $2: $(cmp -l $T/$1.probes $T/$2.probes 2>/dev/null | wc -l) bytes differ ($(stat -c %s $T/$1.probes 2>/dev/null) bytes)"; }
echo "== (a) the animated demo, frames 5 and 0, whole (W) and models (M), elapsed $((SECONDS-START)) s"
for f in 5 0; do run anim_W$f anim.svo W "--frame $f"; run anim_M$f anim.svo M "--frame $f"; cmpb anim_W$f anim_M$f; done
cmpb anim_W0 anim_W5
grep -E '^(load|grid):' $T/anim_M5.log | cut -c1-200 | sed 's/^/    M5: /'
echo "== (b) bake_diff monu1.svo, elapsed $((SECONDS-START)) s"
DIFFA=${RDR4_DIFF:-"--grid 8,8,8 --res 128"}
for spp in 1 64; do
  echo "-- bake_diff monu1.svo $DIFFA --spp $spp --max 12"
  timeout 40 $T/bake_diff monu1.svo $DIFFA --spp $spp --max 12 2>&1 | cut -c1-300 | head -60
done
echo "== (c) cornell: warm-up, elapsed $((SECONDS-START)) s"
for v in W S M; do run warm_$v cornell.svo $v; done
for r in $(seq 1 $ROUNDS); do
  [ $((SECONDS-START)) -lt 90 ] || { echo "  (time: stopped before round $r)"; break; }
  for v in W S M; do run c_${v}$r cornell.svo $v; done
  cmpb c_W$r c_S$r; cmpb c_W$r c_M$r
done
grep -E '^(bake):' $T/c_M1.log | cut -c1-260 | sed 's/^/    M1: /'
grep -E '^(bake):' $T/c_S1.log | cut -c1-260 | sed 's/^/    S1: /'
echo "== done in $((SECONDS-START)) s"
