#!/bin/bash
# issue 21 (branch bake4), batch 3: the branch's last binary (A: the bake's kernel the first the driver has ready,
# bake() where its shader cache holds it, else the one-walk bake_one() while bake() is compiled for the next
# process) as the machine's first Vulkan process, then again (its second: bake() from the cache), the driver's
# floor, main's first bake (M, its pipelines compiled), then rounds alternated process by process, each process
# with an empty shader cache of its own (__GL_SHADER_DISK_CACHE_PATH a fresh directory: every pipeline compiled)
# M and A, then warm rounds (the default cache) M and A. Every output cmp'd against main's of the same kind.
START=$SECONDS
LIMIT=${BAKE_LIMIT:-88}
D=bench/out/bake4; B=bench/out/base/bin; T=/tmp/bake4q; rm -rf $T; mkdir -p $T
export LD_LIBRARY_PATH=$PWD/$B
ARGS=${BAKE_ARGS:---grid 8,8,8 --res 128 --spp 64 -q -v}
ms() { echo $(( (${2/./} - ${1/./} + 500) / 1000 )); }
n=0
run() { # name cachemode(default|fresh) env... ; binary from the name
  local name=$1 mode=$2; shift 2
  local bin=$D/svo_bake; [ $name = M ] && bin=$B/svo_bake
  local cenv=X=0
  if [ $mode = fresh ]; then n=$((n+1)); mkdir -p $T/cache$n; cenv=__GL_SHADER_DISK_CACHE_PATH=$T/cache$n; fi
  local out=$T/$name.$mode.probes
  local s=$EPOCHREALTIME
  env $cenv "$@" timeout 30 $bin $D/cornell.svo $out $ARGS > $T/run.log 2>&1
  local rc=$? e=$EPOCHREALTIME
  local w=$(ms $s $e)
  echo "  $name $mode rc=$rc wall $w ms"
  grep -E "^(gpu|times|bake|sun map|timeline|close: the GPU):" $T/run.log | sed 's/^/    /'
  [ $rc = 0 ] || tail -5 $T/run.log | sed 's/^/    ! /'
  local pipes=$(sed -n 's/.*pipelines \([0-9.]*\),.*/\1/p' $T/run.log | head -1)
  local setup=$(sed -n 's/.*, setup \([0-9.]*\) s.*/\1/p' $T/run.log | head -1)
  local vk=$(sed -n 's/.*(Vulkan \([0-9.]*\) s;.*/\1/p' $T/run.log | head -1)
  local sm=$(sed -n 's/.*sun map \([0-9.]*\), pipelines.*/\1/p' $T/run.log | head -1)
  local gt=$(sed -n 's/.*GPU trace \([0-9.]*\) s.*/\1/p' $T/run.log | head -1)
  local one=$(grep -c "kernel: one walk" $T/run.log)
  local jw=$(sed -n 's/.*waited for \([0-9.]*\) s after it.*/\1/p' $T/run.log | head -1)
  local ref=$T/M.$mode.probes; [ -e $ref ] || ref=$T/M.default.probes
  if [ $name != M ] && [ -e $ref ]; then
    if cmp -s $ref $out; then echo "    $name: same bytes as main's"; else echo "    $name: PROBES DIFFER from main's"; fi
  fi
  [ $rc = 0 ] && [ $measure = 1 ] && echo "$w $vk $setup $sm $pipes $gt ${jw:-0} $one" >> $T/$name.$mode.row
}
floor() { # tag env...
  local tag=$1; shift
  local s=$EPOCHREALTIME
  env "$@" timeout 20 $D/floor > $T/floor.log 2>&1; local rc=$?
  echo "  floor $tag rc=$rc wall $(ms $s $EPOCHREALTIME) ms: $(cat $T/floor.log)"
}
measure=0
echo "== the machine's first Vulkan process: the branch's bake A, in the default shader cache"
run A default
echo "== $(date -u) host: $(nproc) CPUs, $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1)"
echo "== uptime: $(uptime); branch binary at $(cat $D/REV 2>/dev/null)"
nvidia-smi -q 2>/dev/null | grep -i persistence
echo "== shader caches now: $(du -sk ~/.nv ~/.cache/nvidia 2>/dev/null | tr '\n' ' ')"
echo "== A's second process (bake() now in the driver's cache)"
run A default
echo "== the floor"
floor third
echo "== main's first bake (its pipelines compiled), then A again"
run M default
run A default
measure=1
echo "== rounds, each process with an empty shader cache (M, A; order reversed every other round)"
for r in $(seq 1 ${FRESH_ROUNDS:-11}); do
  if (( SECONDS - START > LIMIT - 28 )); then echo "== time: stopped before fresh round $r"; break; fi
  echo "= fresh round $r ($((SECONDS - START)) s)"
  if (( r % 2 )); then run M fresh; run A fresh; else run A fresh; run M fresh; fi
done
echo "== warm rounds (the default cache)"
for r in $(seq 1 ${WARM_ROUNDS:-20}); do
  if (( SECONDS - START > LIMIT )); then echo "== time: stopped before warm round $r"; break; fi
  echo "= warm round $r ($((SECONDS - START)) s)"
  if (( r % 2 )); then run M default; run A default; else run A default; run M default; fi
done
echo "== medians: wall_ms (min-max) vulkan setup sun_map pipelines gpu_trace teardown_waited; n; runs of the one-walk kernel"
for f in $T/*.row; do
  nm=$(basename $f .row); line="$nm: n=$(wc -l < $f)"
  for c in 1 2 3 4 5 6 7; do
    v=($(awk -v c=$c '{print $c}' $f | sort -g)); k=${#v[@]}
    (( k )) || continue
    if (( k % 2 )); then m=${v[$((k/2))]}; else m=$(awk -v a=${v[k/2-1]} -v b=${v[k/2]} 'BEGIN{printf "%.4g", (a+b)/2}'); fi
    line="$line $m"; [ $c = 1 ] && line="$line (${v[0]}-${v[k-1]})"
  done
  echo "$line; one walk: $(awk '{n += $8} END {print n + 0}' $f)"; echo "   walls: $(awk '{printf "%s ", $1}' $f)"
done
echo "== done $(date -u) ($((SECONDS - START)) s)"
