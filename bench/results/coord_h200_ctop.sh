#!/bin/bash
# Coordinator (stop 56): the compact layout's listed top 4x as long for a scene of one model (VX__TOP_NODES_ONE,
# compact_gpu.c path_lists), B, against merged main 841e8b1 (M), processes M B M B M B.
T=/tmp/ctop; rm -rf $T; mkdir -p $T; for x in M B; do gunzip -c cb_$x.gz > $T/$x; chmod +x $T/$x; done
echo "== ctop on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1) $(date -u +%T)"
s0=$(date +%s)
for r in 1 2 3; do for x in M B; do
  [ $(( $(date +%s) - s0 )) -lt ${LIM:-150} ] || break 2
  timeout ${PL:-20} $T/$x --gpu ${SIZE:-1920x1080} --reps ${REPS:-30} eph_monu1.vox helmet512.svo --terrain ${TER:-1024} 2>&1 | grep '^| .* | \(overview\|close-up\)' | grep 'G rays' | cut -d'|' -f2-10 | sed "s/^/$x$r |/"
done; done
echo "== end $(date -u +%T), $(( $(date +%s) - s0 )) s"
