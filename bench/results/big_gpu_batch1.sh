#!/bin/bash
# issue 18 (branch big): DamagedHelmet at RES^3 (mpirun vox2svo on this host's CPUs) rendered at
# 1920x1080 on one H200 by the branch's svo_render (compact attributes in several storage buffers past
# the 4 GB range), frame times and resident memory; then, with the time left, RES2 rendered by main's
# svo_render and the branch's in turn (same-run baseline).
# Env (local tests): BIG_RES, BIG_RES2, BIG_LIMIT (s), BIG_SIZE, BIG_NP (ranks), BIG_MPIARGS, BIG_RANGE
export LD_LIBRARY_PATH=bench/out/big:bench/out/base/bin
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
D=bench/out/big; B=bench/out/base/bin; T=/tmp/bigrun; rm -rf $T; mkdir -p $T
RES=${BIG_RES:-32768}; RES2=${BIG_RES2:-16384}; LIMIT=${BIG_LIMIT:-540}; SIZE=${BIG_SIZE:-1920x1080}
NP=${BIG_NP:-$(( $(nproc) / 4 ))}; [ "$NP" -lt 1 ] && NP=1
MPIARGS=${BIG_MPIARGS:---bind-to none}
RANGE=${BIG_RANGE:+--buffer-range $BIG_RANGE}
start=$(date +%s)
left() { echo $(( LIMIT - ($(date +%s) - start) )); }
stamp() { echo "-- t=$(( $(date +%s) - start )) s: $*"; }
HAVE_SMI=0; command -v nvidia-smi >/dev/null 2>&1 && HAVE_SMI=1
echo "== host: $(nproc) CPUs, $(awk '/MemTotal/{printf "%.1f GiB", $2/1048576}' /proc/meminfo), /tmp free $(df -h /tmp | awk 'NR==2{print $4}')"
[ $HAVE_SMI = 1 ] && nvidia-smi --query-gpu=index,name,driver_version,memory.total,memory.used --format=csv,noheader
echo "== ranks $NP ($MPIARGS), res $RES then $RES2, size $SIZE, limit $LIMIT s"

# run LABEL BIN ARGS...: one render process, its GPU memory sampled every 0.2 s (GPU 0)
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
  echo "$label: rc=$rc wall $(( (e - s) / 1000000 )) ms$gmax"
  grep -v '^svo_render ' $T/$label.log | sed "s/^/  $label| /"
  return $rc
}

# convert RES: the helmet to $T/hRES.svo on the CPUs (mpirun vox2svo)
convert() {
  local r=$1 t=$(left)
  stamp "convert $r ($NP ranks)"
  local s=$(date +%s%N)
  timeout $t mpirun $MPIARGS -n $NP $D/vox2svo $D/helmet.glb $T/h$r.svo --res $r -v > $T/conv$r.log 2>&1; local rc=$?
  local e=$(date +%s%N)
  echo "convert $r: rc=$rc wall $(( (e - s) / 1000000 )) ms, file $(stat -c %s $T/h$r.svo 2>/dev/null) B"
  grep -E 'voxels|models|output|time |peak|converted|rank 0:' $T/conv$r.log | grep -v '^rank [1-9]' | head -12 | sed 's/^/  conv| /'
  [ $rc = 0 ] || tail -5 $T/conv$r.log
  return $rc
}

# warm-up and check: a small helmet by both binaries, the images compared
convert 512 || exit 1
run warm_main $B/svo_render $T/h512.svo $T/w_main.ppm --mode albedo --size $SIZE --layout compact
run warm_big $D/svo_render $T/h512.svo $T/w_big.ppm --mode albedo --size $SIZE --layout compact -v --frames 5
cmp $T/w_main.ppm $T/w_big.ppm && echo "warm-up: images identical (main, branch)"
run warm_split $D/svo_render $T/h512.svo $T/w_split.ppm --mode albedo --size $SIZE --layout compact --buffer-range 1M -v
cmp $T/w_main.ppm $T/w_split.ppm && echo "warm-up: attributes in parts: image identical"

# the goal step: RES on one GPU, the default view (the whole helmet) then a close-up (bench/bench_view.h's,
# about 99% of pixels hit; world units are the mesh's, the same at every --res)
CLOSE="--camera 0.396,-0.698,0.576,-0.002,0.187,-0.144"
if convert $RES; then
  rm -f $T/h512.svo
  free -g | sed 's/^/  mem| /'
  run big${RES}_overview $D/svo_render $T/h$RES.svo $T/r$RES.ppm --size $SIZE --mode albedo --frames 21 -v $RANGE
  [ -f $T/r$RES.ppm ] && echo "image $RES: $(md5sum < $T/r$RES.ppm)"
  [ $(left) -gt 230 ] && run big${RES}_closeup $D/svo_render $T/h$RES.svo $T/c$RES.ppm --size $SIZE --mode albedo --frames 21 -v $RANGE $CLOSE
  rm -f $T/h$RES.svo
fi

# the baseline with what is left: RES2 (close-up) by main's and the branch's renderer, ABAB
if [ $(left) -gt 140 ] && convert $RES2; then
  for round in 1 2; do
    [ $(left) -gt 45 ] || break
    run main${RES2}_$round $B/svo_render $T/h$RES2.svo $T/m$RES2.ppm --size $SIZE --mode albedo --layout compact -v $CLOSE
    [ $(left) -gt 45 ] || break
    run big${RES2}_$round $D/svo_render $T/h$RES2.svo $T/b$RES2.ppm --size $SIZE --mode albedo --layout compact --frames 21 -v $CLOSE
  done
  cmp $T/m$RES2.ppm $T/b$RES2.ppm && echo "$RES2: images identical (main, branch)"
fi
stamp "end"
