#!/bin/bash
# issue 18 (branch giant), batch 1: DamagedHelmet at RES^3 (mpirun vox2svo --chunked on this host's CPUs,
# ranks = CPUs / 4), then the close-up at 1920x1080 rendered by main's svo_render and the branch's in turn
# (ABAB, -v: read, GPU scene, peaks, frame median), images compared; compact_bench --threads: the geometry
# DAG on 1 and N threads (same bytes, merge time). Env (local tests): G_RES, G_LIMIT, G_SIZE, G_NP, G_THREADS
export LD_LIBRARY_PATH=bench/out/giant:bench/out/base/bin
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
D=bench/out/giant; B=bench/out/base/bin; T=/tmp/giantrun; rm -rf $T; mkdir -p $T
RES=${G_RES:-16384}; LIMIT=${G_LIMIT:-290}; SIZE=${G_SIZE:-1920x1080}
NP=${G_NP:-$(( $(nproc) / 4 ))}; [ "$NP" -lt 1 ] && NP=1
TH=${G_THREADS:-1,8,$(nproc)}
start=$(date +%s)
left() { echo $(( LIMIT - ($(date +%s) - start) )); }
stamp() { echo "-- $(date -u +%H:%M:%S) t=$(( $(date +%s) - start )) s: $*"; }
HAVE_SMI=0; command -v nvidia-smi >/dev/null 2>&1 && HAVE_SMI=1
echo "== host: $(nproc) CPUs, $(awk '/MemTotal/{printf "%.1f GiB", $2/1048576}' /proc/meminfo), /tmp free $(df -h /tmp | awk 'NR==2{print $4}')"
[ $HAVE_SMI = 1 ] && nvidia-smi --query-gpu=index,name,driver_version,memory.total,memory.used --format=csv,noheader
echo "== ranks $NP, res $RES, size $SIZE, limit $LIMIT s, main $(cat bench/out/base/COMMIT 2>/dev/null)"

# run LABEL BIN ARGS...: one process (wall, max RSS by /usr/bin/time if present), GPU 0 memory sampled every 0.2 s
run() {
  local label=$1; shift
  local t=$(left); [ $t -lt 5 ] && { echo "$label: no time left"; return 1; }
  if [ $HAVE_SMI = 1 ]; then
    nvidia-smi --query-gpu=memory.used --format=csv,noheader,nounits -i 0 -lms 200 > $T/smi.$label 2>/dev/null &
    local smi=$!
  fi
  local s=$(date +%s%N)
  timeout $t "$@" > $T/$label.log 2>&1; local rc=$?
  local e=$(date +%s%N)
  [ $HAVE_SMI = 1 ] && { kill $smi 2>/dev/null; wait $smi 2>/dev/null; }
  local gmax=""
  [ $HAVE_SMI = 1 ] && gmax="; GPU 0 memory used: max $(sort -n $T/smi.$label | tail -1) MiB (before $(head -1 $T/smi.$label) MiB)"
  stamp "$label: rc=$rc wall $(( (e - s) / 1000000 )) ms$gmax"
  grep -v '^svo_render ' $T/$label.log | sed "s/^/  $label| /"
  return $rc
}

convert() {
  local r=$1 t=$(left)
  stamp "convert $r ($NP ranks, --chunked)"
  local s=$(date +%s%N)
  timeout $t mpirun --bind-to none -n $NP $D/vox2svo $D/helmet.glb $T/h$r.svo --res $r --chunked -v > $T/conv$r.log 2>&1; local rc=$?
  local e=$(date +%s%N)
  stamp "convert $r: rc=$rc wall $(( (e - s) / 1000000 )) ms, file $(stat -c %s $T/h$r.svo 2>/dev/null) B"
  grep -E 'voxels|models|output|time |peak|converted|rank 0:' $T/conv$r.log | grep -v '^rank [1-9]' | head -12 | sed 's/^/  conv| /'
  [ $rc = 0 ] || tail -5 $T/conv$r.log
  return $rc
}

CLOSE="--camera 0.396,-0.698,0.576,-0.002,0.187,-0.144"
# warm-up and check: a small helmet by both binaries, images compared
convert 512 || exit 1
run warm_main $B/svo_render $T/h512.svo $T/w_main.ppm --mode albedo --size $SIZE --layout compact
run warm_giant $D/svo_render $T/h512.svo $T/w_giant.ppm --mode albedo --size $SIZE --layout compact -v --frames 5
cmp $T/w_main.ppm $T/w_giant.ppm && echo "warm-up: images identical (main, branch)"

convert $RES || exit 1
free -g | sed 's/^/  mem| /'
round() {
  run main_$1 $B/svo_render $T/h$RES.svo $T/m$RES.ppm --size $SIZE --mode albedo --layout compact --frames 21 -v $CLOSE
  run giant_$1 $D/svo_render $T/h$RES.svo $T/g$RES.ppm --size $SIZE --mode albedo --layout compact --frames 21 -v $CLOSE
  cmp $T/m$RES.ppm $T/g$RES.ppm && echo "$RES round $1: images identical (main, branch)"
}
round 1
# the geometry DAG on 1 and more threads in one process (same bytes checked), then a second round if time is left
[ $(left) -gt 60 ] && run threads $D/compact_bench --threads $TH --reps 1 $T/h$RES.svo
[ $(left) -gt 80 ] && round 2
stamp "end"
