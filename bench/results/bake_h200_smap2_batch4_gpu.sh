#!/bin/bash
# smap2 batch 4: (1) the GPU path tracer's differing values with the sun map (batch 3: 54 of 2073600 on the
# Cornell box's diffuse row, 3 on eph_monu1's): this pathtrace_bench build has two exploration switches
# (environment, this binary only): VX_SMAP_NOCLIP=1 the map's pipeline (SMAP on) with the map's side 0, so no
# ray is clipped (the same kernel, whole rays); VX_SMAP_NOM2=1 the map without the rule of the one cube that
# gave m1. Each line "(no sun map: N of M values differ from the row above)" compares the process's last image
# of that variant with its last image without the map. (2) the goal bake, 3 more rounds A (branch) / B (main).
export LD_LIBRARY_PATH=bench/out/smap2:bench/out/base/bin
D=bench/out/smap2; B=bench/out/base/bin; T=/tmp/smap2; mkdir -p $T
echo "== smap2 batch 4 on $(nvidia-smi --query-gpu=name,driver_version,clocks.current.sm --format=csv,noheader 2>/dev/null) $(date -u)"
PT="960x540 --spp 64 --runs 3"
for v in "X=1" "X=2" "VX_SMAP_NOCLIP=1" "VX_SMAP_NOM2=1"; do
  for sc in cornell.svo eph_monu1.vox; do
    echo "== pathtrace_bench $sc $PT with $v"
    env $v timeout 40 $D/pathtrace_bench $D/$sc $PT 2>&1 | grep -E "diffuse|materials"
  done
done
ARGS="--grid 8,8,8 --res 128 --spp 64 -q -v"
run() { # tag binary out
  local s=$(date +%s%N)
  $2 $D/cornell.svo $3 $ARGS > $T/$1.log 2>&1; local rc=$?
  local e=$(date +%s%N)
  echo "  $1 rc=$rc wall $(( (e - s) / 1000000 )) ms, $(grep -o 'GPU trace [0-9.]* s' $T/$1.log) | $(grep '^sun map' $T/$1.log)"
}
echo "== svo_bake $D/cornell.svo OUT $ARGS (warm-up, then 3 rounds A this branch, B main)"
run W $D/svo_bake $T/w.probes; run W $B/svo_bake $T/wb.probes
for r in 1 2 3; do
  run A $D/svo_bake $T/a.probes; run B $B/svo_bake $T/b.probes
  cmp -s $T/a.probes $T/b.probes && echo "  round $r: same bytes" || echo "  round $r: BYTES DIFFER"
done
rm -f $T/*.probes
