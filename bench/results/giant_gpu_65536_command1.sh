#!/bin/bash
# issue 18 (branch giant), the first of the two 65536^3 commands (nvidia-h200-x4, limit 590 s): the warm-up check
# (main's and the branch's images of the helmet at 512, also with the attributes in several buffers), the 32768^3
# rehearsal (conv65536.sh and render65536.sh at 32768: convert on all CPUs, render the whole helmet and the
# close-up, then delete the file), then conv65536.sh at 65536 into /tmp/giant with the time left (kept there for
# the second command, render65536.sh). The rehearsal's render is skipped where the 65536 conversion (projected
# as 4.3 x the 32768 one's, measured here, + 30 s) would not fit after it; the whole rehearsal where the 65536
# file is already there (a rerun).
# Env (local tests): G_RES (65536), G_RES2 (32768), G_LIMIT (580), G_SIZE, G_NP
export LD_LIBRARY_PATH=bench/out/giant:bench/out/base/bin
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
D=bench/out/giant; B=bench/out/base/bin; T=/tmp/giantrun; rm -rf $T; mkdir -p $T /tmp/giant
RES=${G_RES:-65536}; RES2=${G_RES2:-32768}; LIMIT=${G_LIMIT:-580}; SIZE=${G_SIZE:-1920x1080}
NP=${G_NP:-$(( $(nproc) / 4 ))}; [ "$NP" -lt 1 ] && NP=1
start=$(date +%s)
left() { echo $(( LIMIT - ($(date +%s) - start) )); }
stamp() { echo "-- $(date -u +%H:%M:%S) t=$(( $(date +%s) - start )) s: $*"; }
echo "== host: $(nproc) CPUs, $(awk '/MemTotal/{printf "%.1f GiB", $2/1048576}' /proc/meminfo), /tmp free $(df -h /tmp | awk 'NR==2{print $4}')"
echo "== ranks $NP, res $RES2 then $RES, size $SIZE, limit $LIMIT s, main $(cat bench/out/base/COMMIT 2>/dev/null)"
command -v nvidia-smi >/dev/null 2>&1 && nvidia-smi --query-gpu=index,name,driver_version,memory.total,memory.used --format=csv,noheader
run() {
  local label=$1; shift
  local s=$(date +%s%N)
  timeout $(left) "$@" > $T/$label.log 2>&1; local rc=$?
  local e=$(date +%s%N)
  stamp "$label: rc=$rc wall $(( (e - s) / 1000000 )) ms"
  grep -v '^svo_render ' $T/$label.log | sed "s/^/  $label| /"
  return $rc
}
if [ -f /tmp/giant/h$RES.svo ] && [ -f /tmp/giant/h$RES.svo.size ]; then
  stamp "/tmp/giant/h$RES.svo is already there: no rehearsal"
else
  timeout 60 mpirun --bind-to none -n $NP $D/vox2svo $D/helmet.glb $T/h512.svo --res 512 --chunked > $T/conv512.log 2>&1 || tail $T/conv512.log
  run warm_main $B/svo_render $T/h512.svo $T/w_main.ppm --mode albedo --size $SIZE --layout compact
  run warm_giant $D/svo_render $T/h512.svo $T/w_giant.ppm --mode albedo --size $SIZE --layout compact -v --frames 5
  cmp $T/w_main.ppm $T/w_giant.ppm && echo "warm-up: images identical (main, branch)"
  run warm_split $D/svo_render $T/h512.svo $T/w_split.ppm --mode albedo --size $SIZE --layout compact --buffer-range 1M
  cmp $T/w_main.ppm $T/w_split.ppm && echo "warm-up: attributes in parts: image identical"
  # the rehearsal's conversion only where it leaves room for the real one (projected from 32 CPUs: 126 s at 32768)
  s2=$(date +%s)
  RES=$RES2 NP=$NP OUTDIR=/tmp/giant LIMIT=$(( $(left) / 4 )) bash $D/conv65536.sh
  c2=$(( $(date +%s) - s2 ))
  proj=$(( c2 * 43 / 10 + 30 ))
  stamp "the $RES2 conversion took $c2 s: the $RES one projected at $proj s, $(left) s left"
  if [ -f /tmp/giant/h$RES2.svo.size ] && [ $(( $(left) - proj - 20 )) -gt 60 ]; then
    RES=$RES2 OUTDIR=/tmp/giant SIZE=$SIZE LIMIT=$(( $(left) - proj - 20 )) bash $D/render65536.sh
  else
    stamp "the $RES2 render skipped: the $RES conversion needs the time"
  fi
  rm -f /tmp/giant/h$RES2.svo /tmp/giant/h$RES2.svo.size
fi
stamp "conv65536.sh at $RES with $(left) s left"
RES=$RES NP=$NP OUTDIR=/tmp/giant LIMIT=$(( $(left) - 3 )) bash $D/conv65536.sh
ls -la /tmp/giant | sed 's/^/  tmp| /'
stamp "end"
