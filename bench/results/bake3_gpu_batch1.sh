#!/bin/bash
# issue 21 (branch bake3, eleventh sitting), batch 1: the goal bake, main's svo_bake (M) against the branch's
# (A: its defaults, the same as main's kernel) and its exploration switches: VX_BAKE_KV (probe.comp PCONST bits
# 24-28: 1 centre ray's results stored early, 2 the random key made per draw, 4 the stratum shift per sample,
# 8 the probe's position read per sample, 16 the running sum kept in the output buffer; F: all five), VX_BAKE_WG (the bake kernel's workgroup: 1024 caps registers at 64),
# VX_GPU_QUEUES=2 (the second slot's batches on a second queue). Alternated process by process, the order
# reversed every other round; every output cmp'd against main's.
START=$SECONDS
LIMIT=${BAKE_LIMIT:-128}
export LD_LIBRARY_PATH=$PWD/bench/out/bake3:$PWD/bench/out/base/bin
D=bench/out/bake3; B=bench/out/base/bin; T=/tmp/bake3q; rm -rf $T; mkdir -p $T
ARGS=${BAKE_ARGS:---grid 8,8,8 --res 128 --spp 64 -q -v}
ROUNDS=${BAKE_ROUNDS:-20}
VARS=${BAKE_VARS:-M A F W WF Q QF}
STATS=${BAKE_STATS:-A G K S O C F W WF}
echo "== $(date -u) host: $(nproc) CPUs, $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1)"
echo "== args: $ARGS; rounds $ROUNDS; variants $VARS; stats $STATS"
run() { # name bin env...
  local name=$1 bin=$2; shift 2
  local s=${EPOCHREALTIME/./}
  env "$@" $bin $D/cornell.svo $T/$name.probes $ARGS > $T/$name.log 2>&1
  local rc=$? e=${EPOCHREALTIME/./}
  local ms=$(( (e - s + 500) / 1000 ))
  local L=$T/$name.log
  echo "  $name rc=$rc wall $ms ms"
  if [ $measure = 0 ]; then grep -E "^(times|bake|sun map|close|batch|stats):" $L | sed 's/^/    /'
  else grep -E "^(times|bake|close: the GPU):" $L | sed 's/^/    /'; fi
  [ $rc = 0 ] || tail -5 $L | sed 's/^/    ! /'
  local dev=$(sed -n 's/.*device \([0-9.]*\) s on its thread (Vulkan \([0-9.]*\) s.*/\2/p' $L | head -1)
  local setup=$(sed -n 's/.*setup \([0-9.]*\) s.*/\1/p' $L | head -1)
  local loop=$(sed -n 's/.*loop \([0-9.]*\) s.*/\1/p' $L | head -1)
  local gpu=$(sed -n 's/.*GPU trace \([0-9.]*\) s.*/\1/p' $L | head -1)
  local td=$(sed -n 's/.*output.s end in \([0-9.]*\) s (baker \([0-9.]*\),.*waited for \([0-9.]*\) s.*/\1 \2 \3/p' $L | head -1)
  local same=0
  if [ $name != M ]; then
    if cmp -s $T/M.probes $T/$name.probes; then same=1; echo "    $name: same bytes as main's"; else echo "    $name: PROBES DIFFER from main's"; fi
  fi
  [ $measure = 1 ] && [ $rc = 0 ] && echo "$ms $dev $setup $loop $gpu $td" >> $T/$name.row
  [ $measure = 1 ] && [ $name != M ] && echo $same >> $T/$name.same
}
V() { case $1 in
  M) run M $B/svo_bake X=0;;
  A) run A $D/svo_bake X=0;;
  G) run G $D/svo_bake VX_BAKE_KV=1;;
  K) run K $D/svo_bake VX_BAKE_KV=2;;
  S) run S $D/svo_bake VX_BAKE_KV=4;;
  O) run O $D/svo_bake VX_BAKE_KV=8;;
  C) run C $D/svo_bake VX_BAKE_KV=16;;
  F) run F $D/svo_bake VX_BAKE_KV=31;;
  W) run W $D/svo_bake VX_BAKE_WG=1024;;
  WF) run WF $D/svo_bake VX_BAKE_WG=1024 VX_BAKE_KV=31;;
  Q) run Q $D/svo_bake VX_GPU_QUEUES=2;;
  QF) run QF $D/svo_bake VX_GPU_QUEUES=2 VX_BAKE_KV=31;;
  *) echo "unknown variant $1";;
esac; }
measure=0
echo "== warm-up"
V M
for v in $VARS; do [ $v = M ] || V $v; done
echo "== shader statistics (VX_GPU_SHADER_STATS=1, not timed; the bake's kernel is 'probe')"
for v in $STATS; do
  echo " variant $v"
  VX_GPU_SHADER_STATS=1 V $v 2>&1 | grep -E "rc=|stats: probe \[|GPU trace|same bytes|DIFFER" | sed 's/bake: .*\(GPU trace [0-9.]* s\).*/\1/'
done
measure=1
for r in $(seq 1 $ROUNDS); do
  if (( SECONDS - START > LIMIT )); then echo "== time limit: stopped before round $r"; break; fi
  echo "= round $r ($((SECONDS - START)) s)"
  if (( r % 2 )); then for v in $VARS; do V $v; done; else for v in $(echo $VARS | tr ' ' '\n' | tac); do V $v; done; fi
done
echo "== medians: wall_ms (min-max) vulkan setup loop gpu_trace teardown baker waited; runs under 600 ms; same bytes"
for n in $VARS; do
  [ -s $T/$n.row ] || continue
  cols=$(awk '{print NF}' $T/$n.row | sort -n | head -1); line="$n: n=$(wc -l < $T/$n.row)"
  for c in $(seq 1 $cols); do
    v=($(awk -v c=$c '{print $c}' $T/$n.row | sort -g)); k=${#v[@]}
    if (( k % 2 )); then m=${v[$((k/2))]}; else m=$(awk -v a=${v[k/2-1]} -v b=${v[k/2]} 'BEGIN{printf "%.4g", (a+b)/2}'); fi
    line="$line $m"; [ $c = 1 ] && line="$line (${v[0]}-${v[k-1]})"
  done
  under=$(awk '$1 < 600' $T/$n.row | wc -l)
  sm=""; [ -s $T/$n.same ] && sm="; same bytes $(grep -c 1 $T/$n.same) of $(wc -l < $T/$n.same)"
  echo "$line; under 600 ms: $under$sm"
  echo "   walls: $(awk '{printf "%s ", $1}' $T/$n.row)"
done
echo "== done $(date -u) ($((SECONDS - START)) s)"
