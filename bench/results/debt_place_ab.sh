#!/bin/bash
# The probe placement's time from svo_bake -v (--load models: vx_probe_place_compact), main's binary (A)
# and the branch's (B) alternating process by process; lavapipe does the one-probe bake.
# usage: place_ab.sh A B ROUNDS
A=$1; B=$2; N=${3:-5}
for sc in "monu1.svo --grid 48,48,48" "multi.svo --grid 64,48,16"; do
  for i in $(seq 1 $N); do
    for v in A B; do
      bin=$A; [ $v = B ] && bin=$B
      t=$($bin ${sc} /tmp/debt_place.probes --res 16 --spp 1 --shard 0/1000000 --fresh -q -v --load models 2>&1 |
          sed -n 's/.*the placement \([0-9.]*\) s (from the layout).*/\1/p')
      g=$($bin ${sc} /tmp/debt_place.probes --res 16 --spp 1 --shard 0/1000000 --fresh -q -v --load whole 2>&1 |
          sed -n 's/.*placement \([0-9.]*\) s, device.*/\1/p')
      echo "${sc%% *} $v round $i models_placement_s $t whole_placement_s $g"
    done
  done
done
