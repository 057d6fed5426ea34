#!/bin/bash
# gdeep (issue 18): the passes' kernels with trace_common.glsl's DEEP constant set from the scene (pipeline.c), not 0.
# A = main's passes_bench (library and kernels), B = gdeep's, C = gdeep's with TRACE_LEAN_DEEP2 in gbuffer.comp and
# frame.comp (the lean walk at DEEP 2 as trace.comp's; not committed: those kernels are branch gbvh's). passes_bench --gbuffer: "gbuffer" (frame.comp merged
# with resolve), "=gbuffer" (gbuffer.comp alone), "gbuffer,direct" (frame.comp with the sun's shadow rays).
# 1: --check on eph_monu1 (DEEP 0: must be the same images, value for value): A writes, B and C compare.
# 2: one process per binary, A B C A B C (a third round if time is left; a process starts where the last one's time is left): the generated terrain 4096 (depth 12, DEEP 2: the
# kernels change) and eph_monu1 (DEEP 0), two views each, median of RUNS frames. Lavapipe: SIZE=160x90 RUNS=3 WU=0 TS=20.
s0=$(date +%s); LIM=${LIM:-86}; left() { echo $(( LIM * ${TS:-1} - ($(date +%s) - s0) )); }
T=/tmp/gdeep; rm -rf $T; mkdir -p $T/chk
for x in A B C; do gunzip -c ${x}_passes_bench.gz > $T/${x}_passes_bench; chmod +x $T/${x}_passes_bench; done
SIZE=${SIZE:-1920x1080}; RUNS=${RUNS:-21}; WU=${WU:-0.25}
smi() { nvidia-smi --query-gpu=clocks.sm,clocks.max.sm,power.draw,temperature.gpu,pstate --format=csv,noheader 2>/dev/null | head -1; }
echo "== gdeep on $(nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader 2>/dev/null | head -1) $(nproc) CPUs $(date -u +%T); A = main $(cat A_COMMIT), B = gdeep $(cat B_COMMIT), C = B + TRACE_LEAN_DEEP2 in the passes; $SIZE, $RUNS frames, warm-up $WU s"
echo "-- 1: eph_monu1 --check, A writes, B and C compare $(date -u +%T)"
for x in A B C; do
  t=$(date +%s); timeout $(left) $T/${x}_passes_bench --gbuffer --runs 1 --size $SIZE --check $T/chk eph_monu1.vox > $T/chk_$x.txt 2>&1 || echo "   $x rc $?"
  echo "   $x: $(( $(date +%s) - t )) s"
done
echo "   A wrote $(grep -c 'written to' $T/chk_A.txt) images"
for x in B C; do
  echo "   $x: $(grep -c ' 0 of .* pixels differ' $T/chk_$x.txt) of $(grep -c '^check' $T/chk_$x.txt) with 0 pixels different; the others:"
  grep '^check' $T/chk_$x.txt | grep -v ' 0 of ' | sed "s|$T/chk/||; s/^/   /"
done
echo "-- 2: passes_bench --gbuffer terrain:4096 eph_monu1.vox, A B C A B C $(date -u +%T)"
D=20 # the last process's seconds: a process starts only where that much and 3 s more are left
run() { # binary round
  local x=$1 r=$2 l=$(left) t=$(date +%s); [ $l -gt $((D + 3)) ] || { echo "   $x$r: no time left ($l s)"; return; }
  echo "   $x$r: clock $(smi)"
  timeout $l $T/${x}_passes_bench --gbuffer --runs $RUNS --warmup $WU --size $SIZE terrain:4096 eph_monu1.vox 2>&1 | grep -E '^#|^\| [a-z]|passes_bench' | grep -v '^| passes' | sed "s/^/$x$r /"
  D=$(( $(date +%s) - t )); echo "   $x$r: $D s"
}
run A 1; run B 1; run C 1; run A 2; run B 2; run C 2; run A 3; run B 3; run C 3
echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
