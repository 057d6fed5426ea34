#!/bin/bash
# bakeq (issue 18, branch bakeq): the bake's kernels (probe, probe_one) precise (PT_PREC + WALK_PRECISE, as the
# render kernel probe_pt) against main (base, 408d3f2). (1) bytes: each scene baked whole with the sun's depth map
# (D), without (S, --no-shadow-map) and through the model reader (M, --load models, compact layout), per binary (main: the
# animated demo and eph_monu1; its Cornell box agreed already, rdr4);
# cmp -l counts the differing bytes. (2) time: cornell and eph_monu1 D, base and new in turn, 3 rounds (medians);
# bake_diff (1 spp) lists texels if the new bakes' layouts still differ on the demo.
# BAKEQ_ARGS: smaller runs for the dev VM's lavapipe only (unset on the device).
START=$SECONDS; T=/tmp/$NAME; rm -rf $T; mkdir -p $T
gzip -dc base_svo_bake.gz > $T/base; gzip -dc svo_bake.gz > $T/new; gzip -dc bake_diff.gz > $T/bake_diff; chmod +x $T/base $T/new $T/bake_diff
echo "== $(date -u +%T) host: $(nproc) CPUs, $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1), load $(cut -d' ' -f1-3 /proc/loadavg); base $(cat BASE_REV), new $(cat NEW_REV)"
ARGS=${BAKEQ_ARGS:-"--grid 8,8,8 --res 128 --spp 64 -q -v"}
echo "== args: $ARGS"
bake() { # who scene variant tag
  local extra=""
  case $3 in S) extra="--no-shadow-map";; M) extra="--load models";; esac
  local l=$((57 - (SECONDS - START))); [ $l -gt 15 ] && l=15
  [ $l -ge 3 ] || { echo "  $4 skipped (time)"; return; }
  local s=${EPOCHREALTIME/./}; timeout $l $T/$1 $2.svo $T/$4.probes $ARGS $extra > $T/$4.log 2>&1; local rc=$?
  local e=${EPOCHREALTIME/./}
  echo "  $4 rc=$rc wall $(( (e - s + 500) / 1000 )) ms; $(grep -oE 'GPU trace [0-9.]+ s' $T/$4.log | head -1)"
  [ $rc = 0 ] || tail -3 $T/$4.log
}
nd() { [ -s $T/$1.probes ] && [ -s $T/$2.probes ] && cmp -l $T/$1.probes $T/$2.probes | wc -l || echo n/a; }
bytes() { # who scenes...
  local who=$1; shift
  echo "== (1) $who: bytes, elapsed $((SECONDS-START)) s"
  for sc in "$@"; do
    [ $((SECONDS-START)) -lt 46 ] || { echo "  (time: $sc skipped)"; continue; }
    for v in D S M; do bake $who $sc $v ${who}_${sc}_$v; done
    echo "  $who $sc: D vs S $(nd ${who}_${sc}_D ${who}_${sc}_S), D vs M $(nd ${who}_${sc}_D ${who}_${sc}_M), S vs M $(nd ${who}_${sc}_S ${who}_${sc}_M) bytes differ (of $(stat -c %s $T/${who}_${sc}_D.probes 2>/dev/null))"
  done
}
timing() { # round
  echo "== (2) time round $1: D, base and new in turn, elapsed $((SECONDS-START)) s"
  for sc in cornell eph_monu1; do
    [ $((SECONDS-START)) -lt 52 ] || return
    bake base $sc D t_base_${sc}_$1; bake new $sc D t_new_${sc}_$1
  done
}
bytes new anim eph_monu1 cornell
timing 1; timing 2
bytes base anim eph_monu1 # main's Cornell box bytes agree already (rdr4)
for sc in anim eph_monu1 cornell; do echo "  $sc new vs base (D): $(nd new_${sc}_D base_${sc}_D) bytes differ"; done
timing 3
# where the new layouts still differ: the texels (bench/bake_diff, the new libraries, 1 spp)
l=$((57 - (SECONDS - START)))
if [ "$(nd new_anim_D new_anim_M)" != 0 ] && [ $l -gt 6 ]; then
  echo "== bake_diff anim.svo (${l} s left)"; timeout $l $T/bake_diff anim.svo --grid 8,8,8 --res 128 --spp 1 --max 6 2>&1 | cut -c1-300 | head -40
fi
echo "== done in $((SECONDS-START)) s"
