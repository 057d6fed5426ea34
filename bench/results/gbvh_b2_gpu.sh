#!/bin/bash
# gbvh (issue 21, twenty-fourth sitting), batch 2: the lean walk in the G-buffer's BVH kernels (gbuffer.comp,
# frame.comp: TRACE_LEAN_BVH). A = main's library and kernels, B = the branch's; both with the branch's passes_bench.c
# (times now to 0.1 us with --gbuffer: batch 1's 1 us steps were 1-2% of the multi-instance rows).
# 1: --check (A writes, B compares, value for value): the tests' scenes of several instances (test_render_gpu's
# "60 instances (bvh)" and test_passes' generated scene, bench/results/gbvh_scenes.c), and the two corpus scenes of
# several instances in the compact layout (the compact G-buffer is lean with several instances too now).
# 2: passes_bench --gbuffer process by process A B A B A B on ogt_test_multiple_model_scene (render_bench's three
# views), ogt_test_groups (three views, several instances) and eph_monu1's close-up (one instance: the same kernels).
# 3: the same with --layout compact, ogt_test_multiple_model_scene, A B A B. Clocks: nvidia-smi every 200 ms (log in
# $OUT/gbvh.tar.gz) and before each process. SIZE, RUNS, WU, TS (time scale) may be set (lavapipe: SIZE=160x90 RUNS=1
# WU=0 TS=20).
BATCH=2; BINS="passes_bench"; . "${GBVH_LIB:-$(dirname "$0")/gbvh_gpu_lib.sh}" # (the payload had these lines inline)
SIZE=${SIZE:-1920x1080}; RUNS=${RUNS:-21}; WU=${WU:-0.25}; LIM=${LIM:-98}
E1="eph_monu1.vox@-17.3319618,-14.8559673,7.42798364,-12.9999926,-11.1428508,5.5714254"
S60="many60.svo@default;-14.6391118,-5.33352437,17.9167622,19,23.5,3.5;-9.24863637,-0.713116885,15.6065584,-4.91666713,2.9999996,13.7500002"
S3="passes3.svo@default;-22.2828229,-12.9567053,19.4783527,4.5,10,8;-2.98387849,3.58524701,11.2073765,2.16666437,7.99999803,9.00000099"
chk() { # label passes_bench-options...: A writes, B compares
  local lab=$1; shift
  for x in A B; do
    l=$(left $LIM); [ $l -gt 5 ] || { echo "   no time left"; break; }
    timeout $l $T/${x}_passes_bench --gbuffer --runs 1 --size $SIZE --check $T/chk/$lab "$@" > $T/check_${lab}_$x.txt 2>&1 || echo "   $x rc $?"
  done
  echo "   $lab: A wrote $(grep -c 'written to' $T/check_${lab}_A.txt) images; B: $(grep -c ' 0 of .* pixels differ' $T/check_${lab}_B.txt) of $(grep -c '^check' $T/check_${lab}_B.txt) with 0 pixels different; the others:"
  grep '^check' $T/check_${lab}_B.txt | grep -v ' 0 of ' | sed "s|$T/chk/||; s/^/   /"
  grep '^##' $T/check_${lab}_B.txt | sed 's/^/   /'
}
echo "-- 1: checks ($SIZE) $(date -u +%T): clock $(smi)"
mkdir -p $T/chk/plain $T/chk/compact
chk plain "$S60" "$S3"
chk compact --layout compact "$M" "$G"
echo "-- 2: passes_bench --gbuffer A B A B A B (--runs $RUNS --warmup $WU --size $SIZE) $(date -u +%T)"
run() { # binary round need options...: one process, if need s (scaled) of the limit are left
  local x=$1 r=$2 need=$3; shift 3; local l=$(left $LIM); [ $l -gt $((need * ${TS:-1})) ] || { echo "   $x$r: no time left"; return; }
  echo "   $x$r: clock $(smi)"
  timeout $l $T/${x}_passes_bench --gbuffer --runs $RUNS --warmup $WU --size $SIZE "$@" 2>&1 | grep --line-buffered -E '^#|^\| [a-z]|passes_bench' | sed -u "s/^/$x$r /" | stamp
}
run A 1 12 "$M" "$G" "$E1"; run B 1 12 "$M" "$G" "$E1"; run A 2 12 "$M" "$G" "$E1"; run B 2 12 "$M" "$G" "$E1"
echo "-- 3: compact layout, A B A B $(date -u +%T)"
run A 4 6 --layout compact "$M"; run B 4 6 --layout compact "$M"
echo "-- 2 again: the third round $(date -u +%T)"
run A 3 12 "$M" "$G" "$E1"; run B 3 12 "$M" "$G" "$E1"
run A 5 6 --layout compact "$M"; run B 5 6 --layout compact "$M"
finish
