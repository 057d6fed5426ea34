#!/bin/bash
# issue 21 (branch bake): the goal bake, main's svo_bake against the branch's, alternated process by process;
# final check of the branch's binary. Prints every -v line; medians at the end.
export LD_LIBRARY_PATH=$PWD/bench/out/bake:$PWD/bench/out/base/bin
D=bench/out/bake; B=bench/out/base/bin; T=/tmp/bakeq; rm -rf $T; mkdir -p $T
ARGS=${BAKE_ARGS:---grid 8,8,8 --res 128 --spp 64 -q -v}
ROUNDS=${BAKE_ROUNDS:-8}
echo "== $(date -u) host: $(nproc) CPUs, $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1); /tmp: $(stat -f -c %T /tmp)"
echo "== args: $ARGS; rounds $ROUNDS"
# variants: name, binary, environment
run() { # name bin env...
  local name=$1 bin=$2; shift 2
  local s=${EPOCHREALTIME/./}
  env "$@" $bin $D/cornell.svo $T/$name.probes $ARGS > $T/$name.log 2>&1
  local rc=$? e=${EPOCHREALTIME/./}
  local ms=$(( (e - s + 500) / 1000 ))
  echo $ms >> $T/$name.wall
  echo "  $name rc=$rc wall $ms ms"
  grep -E "^(times|bake|sun map|close):" $T/$name.log | sed 's/^/    /'
  if [ $name != M ]; then cmp -s $T/M.probes $T/$name.probes && echo "    $name: same bytes as main's" || echo "    $name: PROBES DIFFER from main's"; fi
}
M() { run M $B/svo_bake X=0; }
F() { run F $D/svo_bake X=0; }
echo "== THP: $(cat /sys/kernel/mm/transparent_hugepage/enabled 2>&1) defrag: $(cat /sys/kernel/mm/transparent_hugepage/defrag 2>&1); /tmp: $(grep -E ' /tmp | / ' /proc/mounts | tr '\n' ';')"
echo "== warm-up"
M; F; M; F
for f in $T/*.wall; do : > $f; done
for r in $(seq 1 $ROUNDS); do
  echo "= round $r"
  M; F; M; F
done
echo "== walls (ms), medians"
for n in M F; do
  [ -s $T/$n.wall ] || continue
  w=$(tr '\n' ' ' < $T/$n.wall); v=($(sort -n $T/$n.wall)); k=${#v[@]}
  if (( k % 2 )); then med=${v[$((k/2))]}; else med=$(( (v[k/2-1] + v[k/2]) / 2 )); fi
  echo "$n: $w median $med"
done
echo "== done $(date -u)"
