#!/bin/bash
# ray8 (issue 21, twenty-third sitting), batch 1: the whole issue-21 table on the H200 with main's binary (A), one
# process per scene (the generated terrains in one), ESVO beside, --runs 15; the GPU's clocks sampled every 200 ms
# in the background (nvidia-smi -lms, log in $OUT/ray8.tar.gz) and printed before each process; every output line
# stamped with the time (so each row can be matched with the clock it ran at). Then lean2's BVH lean walk rebuilt on
# main (B: trace_common.glsl's LEAN without "!USE_BVH &&", but the ray-end test at a push kept with several
# instances: without it a tie between two instances' faces went the other way, 1 pixel of test_many_instances) against A, process by process A B A B ..., on
# ogt_test_multiple_model_scene (104 instances, the BVH kernels); and one A process with both trace.comp builds as
# --kernels (t_main, t_bvh, t_bvhsh: B with the BVH walk's state held in shared memory across each instance's octree
# walk, an idea for the multi-instance views' registers; t_bvhshv: only o, d and 1/d so) for the colour frame's pixels compared in one process.
# Payload: A_render_bench.gz, B_render_bench.gz, k.tgz (t_main.spv, t_bvh.spv, t_bvhsh.spv, t_bvhshv.spv), the five corpus .vox, A_COMMIT.
# SIZE, RUNS, WU, TS (time scale) may be set (lavapipe: SIZE=96x54 RUNS=1 WU=0 TS=20).
BINS="A B"; . "${RAY8_LIB:-$(dirname "$0")/ray8_gpu_lib.sh}" # (the payload had these lines inline)
SIZE=${SIZE:-1920x1080}; RUNS=${RUNS:-15}; WU=${WU:-0.2}
echo "== ray8 batch 1 on $(nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader 2>/dev/null | head -1) $(nproc) CPUs $(date -u +%T); A = main $(cat A_COMMIT), B = A with the BVH kernels' lean walk (the push's ray-end test kept)"
nvidia-smi --query-gpu=timestamp,clocks.sm,clocks.mem,power.draw,temperature.gpu,pstate,clocks_throttle_reasons.active --format=csv,noheader -lms 200 > $T/smi.log 2>/dev/null &
smipid=$!
V=.
echo "-- warm-up (A, eph_monu1 overview, 300 frames after 2 s) $(date -u +%T): clock before $(smi)"
timeout $(left 12) $T/A --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup $V/eph_monu1.vox > /dev/null 2>&1
echo "   clock after $(smi)"
echo "-- 1: the table, main's binary (A), --runs $RUNS --warmup $WU, ESVO beside $(date -u +%T)"
dl=20
for sc in eph_monu1 eph_menger eph_dragon ogt_doom ogt_test_multiple_model_scene; do
  l=$(left $dl); dl=$((dl + 7)); [ $l -gt 2 ] || { echo "   $sc: no time left"; continue; }
  echo "   $sc: clock $(smi)"
  timeout $l $T/A --sizes $SIZE --runs $RUNS --warmup $WU $V/$sc.vox 2>&1 | grep --line-buffered -E "$F" | flt | stamp
done
l=$(left 100); echo "   terrains (--generate): clock $(smi)"
[ $l -gt 2 ] && timeout $l $T/A --generate --sizes $SIZE --runs $RUNS --warmup $WU 2>&1 | grep --line-buffered -E "$F" | flt | stamp
echo "   clock after $(smi)"
echo "-- 2: A with --kernels t_main,t_bvh,t_bvhsh,t_bvhshv (trace.comp of main, of B, of B with the BVH walk's state in shared memory across the instance walk, of B with only its vectors o, d, 1/d there; colour frames compared), --shader-stats $(date -u +%T)"
l=$(left 112)
[ $l -gt 3 ] && timeout $l $T/A --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU --shader-stats --kernels $T/t_main.spv@c1,$T/t_bvh.spv@c1,$T/t_bvhsh.spv@c1,$T/t_bvhshv.spv@c1 $V/ogt_test_multiple_model_scene.vox 2>&1 | grep --line-buffered -E "$F|^stats: trace" | flt | stamp
echo "-- 3: BVH lean walk, A B A B on ogt_test_multiple_model_scene (--runs $RUNS --warmup $WU, ESVO beside) $(date -u +%T)"
dl=118
for r in 1 2 3; do
  for x in A B; do
    l=$(left $dl); dl=$((dl + 5)); [ $l -gt 3 ] || { echo "   $x$r: no time left"; continue; }
    echo "   $x$r: clock $(smi)"
    timeout $l $T/$x --sizes $SIZE --runs $RUNS --warmup $WU $V/ogt_test_multiple_model_scene.vox 2>&1 | grep --line-buffered -E "$F" | flt | sed -u "s/^/$x$r /" | stamp
  done
done
kill $smipid 2>/dev/null; wait $smipid 2>/dev/null
echo "-- clock samples: $(wc -l < $T/smi.log), SM MHz min/median/max $(cut -d, -f2 $T/smi.log | tr -dc '0-9\n' | sort -n | awk '{a[NR]=$1} END {if (NR) print a[1], a[int((NR+1)/2)], a[NR]}')"
[ -n "$OUT" ] && tar czf $OUT/ray8.tar.gz -C $T smi.log
echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
