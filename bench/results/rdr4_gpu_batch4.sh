#!/bin/bash
# rdr4 batch 4 (issue 18, branch rdr4): (a) batch 3 found the animated demo's --load models 2,710 bytes from --load
# whole --no-shadow-map at 512 probes R=128 at 64 and at 1 spp and without the sun (eph_monu1's 88 bytes and the
# demo's other 10 are the sun's depth map: whole against whole --no-shadow-map): bench/bake_diff lists the texels
# (P plain, Pn plain without the beam, C compact from the whole scene, M compact from the reader); (b) the camera
# and centre rays alone (1 spp, no bounce, no sun): whole (W), whole without the beam (B), models (M), models
# without the beam (N) on the Cornell box, 3 rounds in turn: what each beam saves.
# RDR4_ARGS/RDR4_DIFF: smaller runs for the dev VM's lavapipe only (unset on the device).
START=$SECONDS; T=/tmp/$NAME; rm -rf $T; mkdir -p $T
gzip -dc svo_bake.gz > $T/svo_bake; gzip -dc bake_diff.gz > $T/bake_diff; chmod +x $T/svo_bake $T/bake_diff
echo "== $(date -u +%T) host: $(nproc) CPUs, $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1), load $(cut -d' ' -f1-3 /proc/loadavg)"
DIFFA=${RDR4_DIFF:-"--grid 8,8,8 --res 128"}
echo "== (a) bake_diff anim.svo $DIFFA --spp 1 --max 16"
timeout 25 $T/bake_diff anim.svo $DIFFA --spp 1 --max 16 2>&1 | cut -c1-330 | head -70
ARGS=${RDR4_ARGS:-"--grid 8,8,8 --res 128 --spp 1 --bounces 0 --sun 0,0,0 -q -v"}
echo "== (b) args: $ARGS, elapsed $((SECONDS-START)) s"
run() { # tag variant
  local tag=$1 v=$2 extra="" env=X=0
  case $v in M|N) extra="--load models";; esac; case $v in B|N) env=VX_BAKE_BEAM=off;; esac
  local s=${EPOCHREALTIME/./}; env $env timeout 30 $T/svo_bake cornell.svo $T/$tag.probes $ARGS $extra > $T/$tag.log 2>&1; local rc=$?
  local e=${EPOCHREALTIME/./}
  echo "  $tag rc=$rc wall $(( (e - s + 500) / 1000 )) ms; $(grep -oE 'GPU trace [0-9.]+ s' $T/$tag.log | head -1)"
}
for v in W B M N; do run warm_$v $v; done
for r in 1 2 3; do
  [ $((SECONDS-START)) -lt 38 ] || break
  for v in W B M N; do run c_$v$r $v; done
  echo "  cmp W M: $(cmp -l $T/c_W$r.probes $T/c_M$r.probes 2>/dev/null | wc -l), W B: $(cmp -l $T/c_W$r.probes $T/c_B$r.probes 2>/dev/null | wc -l), M N: $(cmp -l $T/c_M$r.probes $T/c_N$r.probes 2>/dev/null | wc -l) bytes differ"
done
echo "== done in $((SECONDS-START)) s"
