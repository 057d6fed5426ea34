#!/bin/bash
# deep3 (issue 21, twenty-fourth sitting), batch 1: where DEEP 2's per-step cost is (terrain4096, the rebased walk).
# Ka: main's binary A with --kernels (trace.comp variants, bench/results/deep3_variants.sh) and --shader-stats on the
#    generated terrains (oblique, close-up); Kb: the same kernels in the reverse order (position in the process);
# then A, B (main + the frame switch inside the walk's loop) and C (B + the colour kernel without the lean walk at
# DEEP 2) process by process, A B C A B C, every view.
# Payload: A_render_bench.gz (main), B_, C_render_bench.gz, k.tgz, A_COMMIT, B_COMMIT, C_COMMIT.
# SIZE, RUNS, WU, TS (time scale) may be set (lavapipe: SIZE=96x54 RUNS=1 WU=0 TS=20).
s0=$(date +%s); left() { echo $(( $1 * ${TS:-1} - ($(date +%s) - s0) )); }
T=/tmp/deep3; rm -rf $T; mkdir -p $T; for x in A B C; do gunzip -c ${x}_render_bench.gz > $T/$x; chmod +x $T/$x; done
tar xzf k.tgz -C $T
SIZE=${SIZE:-1920x1080}; RUNS=${RUNS:-15}; WU=${WU:-0.5}
smi() { nvidia-smi --query-gpu=clocks.sm,clocks.mem,power.draw,temperature.gpu,pstate --format=csv,noheader 2>/dev/null | head -1; }
stamp() { while IFS= read -r l; do printf '%s %s\n' "$(date -u +%T.%1N)" "$l"; done; }
flt() { sed -u -E "s|$T/||g; s/  *\[warps[^]]*\]//; s/  *\[traced[^]]*\]//; s/^(.{300}).*/\1/"; }
F='^scene|^terrain|^  \(|px differ|^device|^render_bench|^stats: trace \['
echo "== deep3 batch 1 on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1) $(nproc) CPUs $(date -u +%T); A = main $(cat A_COMMIT), B = $(cat B_COMMIT), C = $(cat C_COMMIT)"
nvidia-smi --query-gpu=timestamp,clocks.sm --format=csv,noheader -lms 250 > $T/smi.log 2>/dev/null &
smipid=$!
K1=t_ref,t_d1,t_norb,t_swin,t_rbup,t_lnc
K2=t_lnc,t_rbup,t_swin,t_norb,t_d1,t_ref
kl() { local r=; for k in ${1//,/ }; do r="$r${r:+,}$T/$k.spv@c1"; done; echo $r; }
run() { # label max-seconds args...: one process if 8 s of the whole are left
  local x=$1 mx=$2; shift 2; local l=$(left ${LIM:-150}); [ $l -gt $((8 * ${TS:-1})) ] || { echo "   $x: no time left"; return; }
  [ $l -gt $(($mx * ${TS:-1})) ] && l=$(($mx * ${TS:-1}))
  echo "-- $x $(date -u +%T): clock $(smi)"
  timeout $l "$@" 2>&1 | grep --line-buffered -E "$F" | flt | sed -u "s/^/$x /" | stamp
}
run Ka 45 $T/A --generate --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU --views oblique,closeup --shader-stats --kernels $(kl $K1)
run Kb 40 $T/A --generate --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU --views oblique,closeup --kernels $(kl $K2)
for r in 1 2; do for x in A B C; do run $x$r 16 $T/$x --generate --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU; done; done
kill $smipid 2>/dev/null; wait $smipid 2>/dev/null
echo "-- clock samples: $(wc -l < $T/smi.log), SM MHz min/median/max $(cut -d, -f2 $T/smi.log | tr -dc '0-9\n' | sort -n | awk '{a[NR]=$1} END {if (NR) print a[1], a[int((NR+1)/2)], a[NR]}')"
[ -n "$OUT" ] && tar czf $OUT/deep3.tar.gz -C $T smi.log
echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
