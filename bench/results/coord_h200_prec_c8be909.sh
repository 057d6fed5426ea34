#!/bin/bash
# Coordinator, stop 51: passes_bench's gbuffer rows, base 1695247 / merged c8be909 / nop (merged without WALK_PRECISE
# in gbuffer.comp and frame.comp), in turn, one process each, both layouts.
T=/tmp/prec; mkdir -p $T; for f in pb_*.gz; do gzip -dc $f > $T/${f%.gz}; chmod +x $T/${f%.gz}; done
s0=$(date +%s)
for round in 1 2; do for lay in compact plain; do for who in base merged nop; do
  [ $(( $(date +%s) - s0 )) -lt 135 ] || break 3
  echo "-- round $round $lay $who $(date +%T)"
  timeout 20 $T/pb_$who --layout $lay --runs 9 --size 1920x1080 eph_monu1.vox eph_menger.vox 2>&1 | grep "^##\|^| gbuffer |\|^| gbuffer,direct |"
done; done; done
echo "== end $(( $(date +%s) - s0 )) s"
