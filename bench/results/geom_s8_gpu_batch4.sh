#!/bin/bash
# geom batch 4 (issue 18, seventh step): the passes (trace_common.glsl with
# COMPACT_FORM) on the default compact form against main's, and the plain
# layout against main's; passes_bench, processes alternating, 3 rounds.
G=bench/out/geom; B=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; ROUNDS=${ROUNDS:-3}; RUNS=${RUNS:-10}
export LD_LIBRARY_PATH=$G:$B
ldconfig -p 2>/dev/null | grep -q 'libstdc++.so.6 ' || export LD_LIBRARY_PATH=$LD_LIBRARY_PATH:$G/cxx
echo "== geom batch 4, $(cat $G/COMMIT 2>/dev/null | tr '\n' ' '), $(date -u)"; nproc; cat /proc/loadavg
nvidia-smi --query-gpu=name,clocks.sm,clocks.mem,temperature.gpu --format=csv,noheader 2>/dev/null
T0=$(date +%s); t() { echo $(( $(date +%s) - T0 )); }
SC="$G/eph_monu1.vox $G/helmet512.svo"
echo "=== warm-up t=$(t)"; timeout 15 $G/passes_bench_main --runs 5 --size $SIZE $G/eph_monu1.vox > /dev/null 2>&1
for round in $(seq $ROUNDS); do
  for who in main_plain branch_plain main_compact branch_compact; do
    bin=$G/passes_bench; opt=""
    case $who in main_*) bin=$G/passes_bench_main;; esac
    case $who in *_compact) opt="--layout compact";; esac
    echo "=== P$round $who t=$(t)"
    timeout ${TO:-20} $bin $opt --runs $RUNS --size $SIZE $SC > /tmp/geom_p_${who}_$round.txt 2>&1
    grep "^## \|^| single\|^| gbuffer |\|^| gbuffer,direct |\|^| gbuffer,direct,ao,aa,tonemap |" /tmp/geom_p_${who}_$round.txt
  done
done
echo "=== summary: frame ms per round (gbuffer; gbuffer,direct,ao,aa,tonemap)"
for who in main_plain branch_plain main_compact branch_compact; do
  for f in /tmp/geom_p_${who}_*.txt; do
    awk -F'|' -v who=$who '/^## / { view=$0; sub(/^## [^ ]*\//,"",view) } $2 ~ /^ gbuffer $/ { g=$3 } $2 ~ /gbuffer,direct,ao,aa,tonemap/ { printf "%s | %s | %s | %s\n", who, view, g, $3 }' $f
  done
done | sort -t'|' -k2,2 -k1,1 -s
echo "=== end t=$(t)"
