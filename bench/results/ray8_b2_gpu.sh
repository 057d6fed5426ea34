#!/bin/bash
# ray8 (issue 21, twenty-third sitting), batch 2: the worst full-frame view of batch 1 is terrain4096's close-up
# (voxkit / ESVO 0.74; its oblique 0.76): the rebased walk (DEEP 2), which the lean walk left out. C = B with the
# lean walk at DEEP 2 too (TRACE_LEAN_DEEP2). First one B process with --kernels t_B,t_C (trace.comp of B and of C;
# colour frames compared with the built-in kernel) and --shader-stats on the generated terrains; then A (main) and C
# process by process, A C A C, on the generated terrains (--no-esvo: its 4096 octree takes 15 s to build; ESVO's
# rates are batch 1's; B, ray8's BVH lean walk kept after batch 1, has A's kernels where one instance is traced);
# then A B on ogt_test_multiple_model_scene once more (B's committed build); a third A C round if time is left. Clocks: nvidia-smi every 200 ms (log in
# $OUT/ray8.tar.gz) and before each process; output lines stamped with the time.
# Payload: A/B/C_render_bench.gz, k.tgz (t_B.spv, t_C.spv), ogt_test_multiple_model_scene.vox, A_COMMIT, B_COMMIT.
# SIZE, RUNS, WU, WU1 (section 1's), TS (time scale) may be set (lavapipe: SIZE=96x54 RUNS=1 WU=0 WU1=0 TS=20).
BINS="A B C"; . "${RAY8_LIB:-$(dirname "$0")/ray8_gpu_lib.sh}" # (the payload had these lines inline)
SIZE=${SIZE:-1920x1080}; RUNS=${RUNS:-15}; WU=${WU:-0.2}; WU1=${WU1:-0.2}
echo "== ray8 batch 2 on $(nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader 2>/dev/null | head -1) $(nproc) CPUs $(date -u +%T); A = main $(cat A_COMMIT), B = ray8 $(cat B_COMMIT), C = B with the lean walk at DEEP 2"
nvidia-smi --query-gpu=timestamp,clocks.sm,clocks.mem,power.draw,temperature.gpu,pstate,clocks_throttle_reasons.active --format=csv,noheader -lms 200 > $T/smi.log 2>/dev/null &
smipid=$!
echo "-- warm-up (A, ogt_test_multiple_model_scene close-up, 2 s) $(date -u +%T): clock before $(smi)"
timeout $(left 8) $T/A --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup ogt_test_multiple_model_scene.vox > /dev/null 2>&1
echo "   clock after $(smi)"
echo "-- 1: B with --kernels t_B,t_C, --shader-stats, terrains (--generate --no-esvo --views oblique,closeup --warmup $WU1) $(date -u +%T): clock $(smi)"
l=$(left 22)
[ $l -gt 3 ] && timeout $l $T/B --generate --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU1 --views oblique,closeup --shader-stats --kernels $T/t_B.spv@c1,$T/t_C.spv@c1 2>&1 | grep --line-buffered -E "$F|^stats: trace \[" | flt | stamp
echo "-- 2: A C A C on the terrains (--generate --no-esvo --runs $RUNS --warmup $WU; B's kernels of one instance are A's) $(date -u +%T)"
run() { # binary round scene-args...: one process, if 12 s of the 85 are left
  local x=$1 r=$2; shift 2; local l=$(left 85); [ $l -gt $((12 * ${TS:-1})) ] || { echo "   $x$r: no time left"; return; }
  [ $l -gt $((22 * ${TS:-1})) ] && l=$((22 * ${TS:-1}))
  echo "   $x$r: clock $(smi)"
  timeout $l $T/$x --sizes $SIZE --runs $RUNS --warmup $WU "$@" 2>&1 | grep --line-buffered -E "$F" | flt | sed -u "s/^/$x$r /" | stamp
}
run A 1 --generate --no-esvo; run C 1 --generate --no-esvo; run A 2 --generate --no-esvo; run C 2 --generate --no-esvo
echo "-- 3: A B on ogt_test_multiple_model_scene (ESVO beside) $(date -u +%T)"
run A 4 ogt_test_multiple_model_scene.vox; run B 4 ogt_test_multiple_model_scene.vox
echo "-- 4: A C once more if time is left $(date -u +%T)"
run A 3 --generate --no-esvo; run C 3 --generate --no-esvo
kill $smipid 2>/dev/null; wait $smipid 2>/dev/null
echo "-- clock samples: $(wc -l < $T/smi.log), SM MHz min/median/max $(cut -d, -f2 $T/smi.log | tr -dc '0-9\n' | sort -n | awk '{a[NR]=$1} END {if (NR) print a[1], a[int((NR+1)/2)], a[NR]}')"
[ -n "$OUT" ] && tar czf $OUT/ray8.tar.gz -C $T smi.log
echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
