#!/bin/bash
# (batch 1 as run: svo_bake = build-gpu of the branch at 8d7e51a's beam (before --frame); cornell.svo =
# /work/coord/cornell.svo; monu1.svo = vox2svo of the corpus eph_monu1.vox with its defaults)
# rdr4 batch 1 (issue 18, branch rdr4): the compact layout's beam pass in the bake (probes/shaders/probe_beam.comp
# beam_model_compact). svo_bake of the branch: --load whole (W), --load models with the beam (M), --load models
# without it (N: VX_BAKE_BEAM=off, main's compact bake), each process warm, rounds W M N in turn; bytes compared.
# RDR4_ARGS/RDR4_ROUNDS: a smaller bake for the dev VM's lavapipe only (unset on the device).
START=$SECONDS; T=/tmp/$NAME; rm -rf $T; mkdir -p $T
gzip -dc svo_bake.gz > $T/svo_bake; chmod +x $T/svo_bake
echo "== $(date -u +%T) host: $(nproc) CPUs, $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1), load $(cut -d' ' -f1-3 /proc/loadavg)"
ARGS=${RDR4_ARGS:-"--grid 8,8,8 --res 128 --spp 64 -q -v"}; ROUNDS=${RDR4_ROUNDS:-9}
echo "== args: $ARGS"
run() { # tag scene variant -> wall ms, bake s, GPU trace s
  local tag=$1 sc=$2 v=$3 extra="" env=X=0
  [ $v != W ] && extra="--load models"; [ $v = N ] && env=VX_BAKE_BEAM=off
  local s=${EPOCHREALTIME/./}; env $env timeout 60 $T/svo_bake $sc $T/$tag.probes $ARGS $extra > $T/$tag.log 2>&1; local rc=$?
  local e=${EPOCHREALTIME/./}
  echo "  $tag rc=$rc wall $(( (e - s + 500) / 1000 )) ms; $(grep -oE 'bake [0-9.]+ s' $T/$tag.log | head -1); $(grep -oE 'GPU trace [0-9.]+ s' $T/$tag.log | head -1)"
}
cmpb() { echo "  cmp $1 $2: $(cmp -l $T/$1.probes $T/$2.probes 2>/dev/null | wc -l) bytes differ ($(stat -c %s $T/$1.probes 2>/dev/null) bytes)"; }
for sc in cornell monu1; do
  echo "== $sc: warm-up (each variant's kernels into the driver's cache), elapsed $((SECONDS-START)) s"
  for v in W M N; do run warm_${sc}_$v $sc.svo $v; done
  grep -E '^(load|grid|gpu|bake|times):' $T/warm_${sc}_M.log | cut -c1-260 | sed 's/^/    M: /'
  n=$ROUNDS; [ $sc = monu1 ] && n=$(( (ROUNDS + 2) / 3 ))
  for r in $(seq 1 $n); do
    [ $((SECONDS-START)) -lt 80 ] || { echo "  (time: stopped before round $r)"; break; }
    for v in W M N; do run ${sc}_${v}$r $sc.svo $v; done
    cmpb ${sc}_W$r ${sc}_M$r; cmpb ${sc}_M$r ${sc}_N$r
  done
done
echo "== done in $((SECONDS-START)) s"
