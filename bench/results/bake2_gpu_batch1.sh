#!/bin/bash
# issue 21 (branch bake2, tenth sitting): the goal bake, main's svo_bake (M) against the branch's (F) and its
# exploration variants, alternated process by process; every output cmp'd against main's of the same round.
export LD_LIBRARY_PATH=$PWD/bench/out/bake2:$PWD/bench/out/base/bin
D=bench/out/bake2; B=bench/out/base/bin; T=/tmp/bake2q; rm -rf $T; mkdir -p $T
ARGS=${BAKE_ARGS:---grid 8,8,8 --res 128 --spp 64 -q -v}
ROUNDS=${BAKE_ROUNDS:-10}
VARS=${BAKE_VARS:-M F H B2 B8 K1 W32 W128}
echo "== $(date -u) host: $(nproc) CPUs, $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1)"
echo "== args: $ARGS; rounds $ROUNDS; variants $VARS"
num() { sed -n "s/.*$1 \([0-9.]*\) s.*/\1/p" $2 | head -1; }
run() { # name bin env...
  local name=$1 bin=$2; shift 2
  local s=${EPOCHREALTIME/./}
  env "$@" $bin $D/cornell.svo $T/$name.probes $ARGS > $T/$name.log 2>&1
  local rc=$? e=${EPOCHREALTIME/./}
  local ms=$(( (e - s + 500) / 1000 ))
  echo "  $name rc=$rc wall $ms ms"
  grep -E "^(times|bake|sun map|close|batch):" $T/$name.log | sed 's/^/    /'
  local L=$T/$name.log
  local dev=$(sed -n 's/.*device \([0-9.]*\) s on its thread.*/\1/p' $L | head -1)
  local setup=$(sed -n 's/.*setup \([0-9.]*\) s.*/\1/p' $L | head -1)
  local loop=$(sed -n 's/.*loop \([0-9.]*\) s.*/\1/p' $L | head -1)
  local gpu=$(sed -n 's/.*GPU trace \([0-9.]*\) s.*/\1/p' $L | head -1)
  local td=$(sed -n 's/.*output.s end in \([0-9.]*\) s (baker \([0-9.]*\),.*waited for \([0-9.]*\) s.*/\1 \2 \3/p' $L | head -1)
  [ $measure = 1 ] && echo "$ms $dev $setup $loop $gpu $td" >> $T/$name.row
  if [ $name != M ]; then cmp -s $T/M.probes $T/$name.probes && echo "    $name: same bytes as main's" || echo "    $name: PROBES DIFFER from main's"; fi
}
V() { case $1 in
  M) run M $B/svo_bake X=0;;
  F) run F $D/svo_bake X=0;;
  E) run E $D/svo_bake VX_BAKE_EARLY_FREE=0;;
  B2) run B2 $D/svo_bake VX_BAKE_BEAM=2;;
  B8) run B8 $D/svo_bake VX_BAKE_BEAM=8;;
  H) run H $D/svo_bake VX_BAKE_FIRST=32;;
  K1) run K1 $D/svo_bake VX_BAKE_KERNEL=b1;;
  W32) run W32 $D/svo_bake VX_BAKE_KERNEL=w32;;
  W128) run W128 $D/svo_bake VX_BAKE_KERNEL=w128;;
  *) echo "unknown variant $1";;
esac; }
measure=0
echo "== warm-up"
for v in $VARS; do V $v; done
V M
echo "== shader statistics (not timed)"
for k in default b1 w32 w128; do
  echo "  kernel $k"
  VX_BAKE_KERNEL=$k VX_GPU_SHADER_STATS=1 $D/svo_bake $D/cornell.svo $T/S.probes $ARGS 2>&1 | grep -E "^stats:|GPU trace" | sed 's/^/    /'
  cmp -s $T/M.probes $T/S.probes && echo "    S: same bytes as main's" || echo "    S: PROBES DIFFER from main's"
done
measure=1
for r in $(seq 1 $ROUNDS); do
  echo "= round $r"
  for v in $VARS; do V $v; done
done
echo "== medians: wall_ms device setup loop gpu_trace teardown baker waited (and min-max of wall)"
for n in $VARS; do
  [ -s $T/$n.row ] || continue
  cols=$(awk '{print NF}' $T/$n.row | sort -n | head -1); line="$n: n=$(wc -l < $T/$n.row)"
  for c in $(seq 1 $cols); do
    v=($(awk -v c=$c '{print $c}' $T/$n.row | sort -g)); k=${#v[@]}
    if (( k % 2 )); then m=${v[$((k/2))]}; else m=$(awk -v a=${v[k/2-1]} -v b=${v[k/2]} 'BEGIN{printf "%.4g", (a+b)/2}'); fi
    line="$line $m"; [ $c = 1 ] && line="$line (${v[0]}-${v[k-1]})"
  done
  echo "$line; walls $(awk '{printf "%s ", $1}' $T/$n.row)"
done
echo "== done $(date -u)"
