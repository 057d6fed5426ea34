#!/bin/bash
# issue 21 (branch bake4), batch 1: the goal bake's first process on a fresh machine. First the driver's own
# floor (bench/results/bake4_floor.c: instance, device, two trivial pipelines) as the machine's first Vulkan
# process, then main's svo_bake (M) and the branch's (B) each cold in the default shader cache, then rounds
# alternated process by process: each binary with an empty shader cache of its own (__GL_SHADER_DISK_CACHE_PATH
# a fresh directory: every pipeline compiled, as on a fresh machine but with the driver's files in the page
# cache), the branch also with its pipelines made in turn (S: VX_BAKE_SERIAL_PIPES=1, its bake-only SPIR-V),
# the branch's kernel with the sun's shadow ray traced at one place of path() (O: VX_BAKE_SUN_ONCE=1, an
# exploration variant), then warm rounds (the default cache). Every output cmp'd against main's of the same kind.
START=$SECONDS
LIMIT=${BAKE_LIMIT:-88}
D=bench/out/bake4; B=bench/out/base/bin; T=/tmp/bake4q; rm -rf $T; mkdir -p $T
export LD_LIBRARY_PATH=$PWD/$B
ARGS=${BAKE_ARGS:---grid 8,8,8 --res 128 --spp 64 -q -v}
echo "== $(date -u) host: $(nproc) CPUs, $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1)"
echo "== uptime: $(uptime)"
nvidia-smi -q 2>/dev/null | grep -i persistence
echo "== shader caches before: $(ls -d ~/.nv/GLCache ~/.cache/nvidia/GLCache 2>/dev/null | tr '\n' ' ') $(du -sk ~/.nv ~/.cache/nvidia 2>/dev/null | tr '\n' ' ')"
echo "== user $(id -un), HOME $HOME, XDG_CACHE_HOME ${XDG_CACHE_HOME:-unset}, __GL vars: $(env | grep -c __GL)"
ms() { echo $(( (${2/./} - ${1/./} + 500) / 1000 )); }
floor() { # tag env...
  local tag=$1; shift
  local s=$EPOCHREALTIME
  env "$@" timeout 20 $D/floor > $T/floor.log 2>&1; local rc=$?
  echo "  floor $tag rc=$rc wall $(ms $s $EPOCHREALTIME) ms: $(cat $T/floor.log)"
}
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
  if [ $name != M ] && [ -e $T/M.$mode.probes ]; then
    if cmp -s $T/M.$mode.probes $out; then echo "    $name: same bytes as main's"; else echo "    $name: PROBES DIFFER from main's"; fi
  fi
  [ $rc = 0 ] && [ $measure = 1 ] && echo "$w $vk $setup $sm $pipes $gt" >> $T/$name.$mode.row
}
measure=0
echo "== the machine's first Vulkan process: the floor, then again"
floor first
floor second
echo "== first bakes (default shader cache; each binary's first: its pipelines compiled)"
run M default
run B default
echo "== shader caches now: $(du -sk ~/.nv ~/.cache/nvidia 2>/dev/null | tr '\n' ' ')"
echo "== the floor with an empty cache and with the cache off"
mkdir -p $T/fc1 $T/fc2
floor fresh-cache __GL_SHADER_DISK_CACHE_PATH=$T/fc1
floor cache-off __GL_SHADER_DISK_CACHE=0
measure=1
echo "== rounds, each process with an empty shader cache (M, B, S alternated, order reversed every other round)"
for r in $(seq 1 ${FRESH_ROUNDS:-8}); do
  if (( SECONDS - START > LIMIT - 25 )); then echo "== time: stopped before fresh round $r"; break; fi
  echo "= fresh round $r ($((SECONDS - START)) s)"
  if (( r % 2 )); then run M fresh; run B fresh; run S fresh VX_BAKE_SERIAL_PIPES=1; run O fresh VX_BAKE_SUN_ONCE=1
  else run O fresh VX_BAKE_SUN_ONCE=1; run S fresh VX_BAKE_SERIAL_PIPES=1; run B fresh; run M fresh; fi
done
echo "== one with the cache off (__GL_SHADER_DISK_CACHE=0) for each"
run M off __GL_SHADER_DISK_CACHE=0
run B off __GL_SHADER_DISK_CACHE=0
echo "== shader statistics of the bake's kernel, B and O (VX_GPU_SHADER_STATS=1: another compile)"
for v in B O; do
  e=X=0; [ $v = O ] && e=VX_BAKE_SUN_ONCE=1
  VX_GPU_SHADER_STATS=1 env $e timeout 30 $D/svo_bake $D/cornell.svo $T/st.probes $ARGS 2>&1 | grep -E "^stats: probe |GPU trace" | sed "s/^/  $v: /" | cut -c1-400
done
echo "== O's first in the default cache (not counted)"
measure=0; run O default VX_BAKE_SUN_ONCE=1; measure=1
echo "== warm rounds (the default cache)"
for r in $(seq 1 ${WARM_ROUNDS:-10}); do
  if (( SECONDS - START > LIMIT )); then echo "== time: stopped before warm round $r"; break; fi
  echo "= warm round $r ($((SECONDS - START)) s)"
  if (( r % 2 )); then run M default; run B default; run O default VX_BAKE_SUN_ONCE=1
  else run O default VX_BAKE_SUN_ONCE=1; run B default; run M default; fi
done
echo "== medians: wall_ms (min-max) vulkan setup sun_map pipelines gpu_trace; n"
for f in $T/*.row; do
  nm=$(basename $f .row); line="$nm: n=$(wc -l < $f)"
  for c in 1 2 3 4 5 6; do
    v=($(awk -v c=$c '{print $c}' $f | sort -g)); k=${#v[@]}
    (( k )) || continue
    if (( k % 2 )); then m=${v[$((k/2))]}; else m=$(awk -v a=${v[k/2-1]} -v b=${v[k/2]} 'BEGIN{printf "%.4g", (a+b)/2}'); fi
    line="$line $m"; [ $c = 1 ] && line="$line (${v[0]}-${v[k-1]})"
  done
  echo "$line"; echo "   walls: $(awk '{printf "%s ", $1}' $f)"
done
echo "== done $(date -u) ($((SECONDS - START)) s)"
