#!/bin/bash
# issue 18 (branch big), second run: DamagedHelmet at RES^3 (mpirun vox2svo on this host's CPUs), the
# close-up at 1920x1080 rendered by main's svo_render and the branch's in turn (compact layout, same
# file): process wall (read + layout build and upload + frames), the branch's breakdown (read, build,
# attributes, tables and upload), frame times, host and GPU memory. Env (local tests): BIG_RES,
# BIG_LIMIT (s), BIG_SIZE, BIG_NP (ranks), BIG_MPIARGS
export LD_LIBRARY_PATH=bench/out/big:bench/out/base/bin
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
D=bench/out/big; B=bench/out/base/bin; T=/tmp/bigrun; rm -rf $T; mkdir -p $T
RES=${BIG_RES:-16384}; LIMIT=${BIG_LIMIT:-192}; SIZE=${BIG_SIZE:-1920x1080}
NP=${BIG_NP:-$(( $(nproc) / 4 ))}; [ "$NP" -lt 1 ] && NP=1
MPIARGS=${BIG_MPIARGS:---bind-to none}
CLOSE="--camera 0.396,-0.698,0.576,-0.002,0.187,-0.144"
start=$(date +%s)
left() { echo $(( LIMIT - ($(date +%s) - start) )); }
stamp() { echo "-- t=$(( $(date +%s) - start )) s: $*"; }
HAVE_SMI=0; command -v nvidia-smi >/dev/null 2>&1 && HAVE_SMI=1
echo "== host: $(nproc) CPUs, $(awk '/MemTotal/{printf "%.1f GiB", $2/1048576}' /proc/meminfo)"
[ $HAVE_SMI = 1 ] && nvidia-smi --query-gpu=index,name,memory.used --format=csv,noheader
echo "== ranks $NP ($MPIARGS), res $RES, size $SIZE, limit $LIMIT s"
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
  [ $HAVE_SMI = 1 ] && gmax="; GPU 0 memory used: max $(sort -n $T/smi.$label | tail -1) MiB"
  echo "$label: rc=$rc wall $(( (e - s) / 1000000 )) ms$gmax"
  grep -v '^svo_render ' $T/$label.log | sed "s/^/  $label| /"
  return $rc
}
convert() {
  local r=$1 t=$(left)
  stamp "convert $r ($NP ranks)"
  local s=$(date +%s%N)
  timeout $t mpirun $MPIARGS -n $NP $D/vox2svo $D/helmet.glb $T/h$r.svo --res $r -v > $T/conv$r.log 2>&1; local rc=$?
  local e=$(date +%s%N)
  echo "convert $r: rc=$rc wall $(( (e - s) / 1000000 )) ms, file $(stat -c %s $T/h$r.svo 2>/dev/null) B"
  grep -E '^  (voxels|models|output|time )|converted' $T/conv$r.log | sed 's/^/  conv| /'
  [ $rc = 0 ] || tail -5 $T/conv$r.log
  return $rc
}
convert 512 || exit 1
run warm $D/svo_render $T/h512.svo $T/w.ppm --mode albedo --size $SIZE --layout compact > /dev/null
convert $RES || exit 1
A="--size $SIZE --mode albedo --layout compact $CLOSE"
run big_1 $D/svo_render $T/h$RES.svo $T/b.ppm $A --frames 21 -v
[ $(left) -gt 50 ] && run main_1 $B/svo_render $T/h$RES.svo $T/m.ppm $A -v
cmp $T/m.ppm $T/b.ppm && echo "$RES: images identical (main, branch)"
[ $(left) -gt 40 ] && run big_2 $D/svo_render $T/h$RES.svo $T/b.ppm $A --frames 21 -v
[ $(left) -gt 50 ] && run main_2 $B/svo_render $T/h$RES.svo $T/m.ppm $A -v
stamp "end"
