#!/bin/bash
# deep3 (issue 21, twenty-fourth sitting), batch 2: A = main, B = the colour kernel without the lean walk at DEEP 2,
# C = B + the exact and rebased walks' slots stored before the path start (registers), process by process
# A B C A B C A B C on the generated terrains, every view (ESVO in A1's process only: its 4096 octree takes ~17 s);
# then one A process with --kernels (t_B, t_C: B's and C's trace.comp, px against main's built-in kernel; t_d1, t_norb,
# t_nohl: the diagnostic one-frame walks on B's tree, bench/results/deep3_variants.sh) and --shader-stats.
# Payload: A/B/C_render_bench.gz, k.tgz, A_COMMIT, B_COMMIT, C_COMMIT.
# SIZE, RUNS, WU, TS (time scale) may be set (lavapipe: SIZE=96x54 RUNS=1 WU=0 TS=20).
s0=$(date +%s); left() { echo $(( $1 * ${TS:-1} - ($(date +%s) - s0) )); }
T=/tmp/deep3; rm -rf $T; mkdir -p $T; for x in A B C; do gunzip -c ${x}_render_bench.gz > $T/$x; chmod +x $T/$x; done
tar xzf k.tgz -C $T
SIZE=${SIZE:-1920x1080}; RUNS=${RUNS:-15}; WU=${WU:-0.5}
smi() { nvidia-smi --query-gpu=clocks.sm,clocks.mem,power.draw,temperature.gpu,pstate --format=csv,noheader 2>/dev/null | head -1; }
stamp() { while IFS= read -r l; do printf '%s %s\n' "$(date -u +%T.%1N)" "$l"; done; }
flt() { sed -u -E "s|$T/||g; s/  *\[warps[^]]*\]//; s/  *\[traced[^]]*\]//; s/^(.{300}).*/\1/"; }
F='^scene|^terrain|^  \(|px differ|^device|^render_bench|^stats: trace \['
echo "== deep3 batch 2 on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1) $(nproc) CPUs $(date -u +%T); A = main $(cat A_COMMIT), B = $(cat B_COMMIT), C = $(cat C_COMMIT)"
nvidia-smi --query-gpu=timestamp,clocks.sm --format=csv,noheader -lms 250 > $T/smi.log 2>/dev/null &
smipid=$!
kl() { local r=; for k in ${1//,/ }; do r="$r${r:+,}$T/$k.spv@c1"; done; echo $r; }
run() { # label max-seconds args...: one process if 8 s of the whole are left
  local x=$1 mx=$2; shift 2; local l=$(left ${LIM:-160}); [ $l -gt $((8 * ${TS:-1})) ] || { echo "   $x: no time left"; return; }
  [ $l -gt $(($mx * ${TS:-1})) ] && l=$(($mx * ${TS:-1}))
  echo "-- $x $(date -u +%T): clock $(smi)"
  timeout $l "$@" 2>&1 | grep --line-buffered -E "$F" | flt | sed -u "s/^/$x /" | stamp
}
run A1 40 $T/A --generate --sizes $SIZE --runs $RUNS --warmup $WU
for r in 1 2 3; do for x in A B C; do [ $r$x = 1A ] && continue; run $x$r 16 $T/$x --generate --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU; done; done
run Ka 40 $T/A --generate --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU --views oblique,closeup --shader-stats --kernels $(kl t_B,t_C,t_nohl,t_norb,t_d1)
kill $smipid 2>/dev/null; wait $smipid 2>/dev/null
echo "-- clock samples: $(wc -l < $T/smi.log), SM MHz min/median/max $(cut -d, -f2 $T/smi.log | tr -dc '0-9\n' | sort -n | awk '{a[NR]=$1} END {if (NR) print a[1], a[int((NR+1)/2)], a[NR]}')"
[ -n "$OUT" ] && tar czf $OUT/deep3.tar.gz -C $T smi.log
echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
