#!/bin/bash
# rdr4 batch 3 (issue 18, branch rdr4): batch 2 found --load whole and --load models apart on the H200 at 512
# probes R=128 64 spp: eph_monu1 84-88 bytes (bake_diff: radiance and irradiance only, every listed texel darker in
# the compact bake; 0 at 1 spp), the animated demo 2,716 (frame 0) and 2,773 (frame 5); the Cornell box 0. The
# compact layout has no sun depth map: is it the map or the walk? whole (W), whole without the map (S:
# --no-shadow-map), models (M), bytes compared, on each scene; and the demo at 1 spp.
# RDR4_ARGS: a smaller bake for the dev VM's lavapipe only (unset on the device).
START=$SECONDS; T=/tmp/$NAME; rm -rf $T; mkdir -p $T
gzip -dc svo_bake.gz > $T/svo_bake; chmod +x $T/svo_bake
echo "== $(date -u +%T) host: $(nproc) CPUs, $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1), load $(cut -d' ' -f1-3 /proc/loadavg)"
ARGS=${RDR4_ARGS:-"--grid 8,8,8 --res 128 --spp 64 -q -v"}
echo "== args: $ARGS"
run() { # tag scene variant [extra]
  local tag=$1 sc=$2 v=$3 extra=$4
  case $v in M) extra="$extra --load models";; S) extra="$extra --no-shadow-map";; esac
  local s=${EPOCHREALTIME/./}; timeout 60 $T/svo_bake $sc $T/$tag.probes $ARGS $extra > $T/$tag.log 2>&1; local rc=$?
  local e=${EPOCHREALTIME/./}
  echo "  $tag rc=$rc wall $(( (e - s + 500) / 1000 )) ms; $(grep -oE 'bake [0-9.]+ s' $T/$tag.log | head -1); $(grep -oE 'GPU trace [0-9.]+ s' $T/$tag.log | head -1)"
}
cmpb() { echo "  cmp $1 $2: $(cmp -l $T/$1.probes $T/$2.probes 2>/dev/null | wc -l) bytes differ ($(stat -c %s $T/$1.probes 2>/dev/null) bytes)"; }
for sc in monu1 anim cornell; do
  echo "== $sc, elapsed $((SECONDS-START)) s"
  for v in W S M; do run ${sc}_$v $sc.svo $v; done
  cmpb ${sc}_W ${sc}_S; cmpb ${sc}_S ${sc}_M; cmpb ${sc}_W ${sc}_M
done
echo "== anim at 1 spp (the centre and camera rays, one bounce path), elapsed $((SECONDS-START)) s"
for v in W S M; do run anim1_$v anim.svo $v "--spp 1"; done
cmpb anim1_W anim1_S; cmpb anim1_S anim1_M; cmpb anim1_W anim1_M
echo "== anim, the sun off (--sun 0,0,0: no sun rays, no map), elapsed $((SECONDS-START)) s"
for v in W M; do run animns_$v anim.svo $v "--sun 0,0,0"; done
cmpb animns_W animns_M
echo "== done in $((SECONDS-START)) s"
