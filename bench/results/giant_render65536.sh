#!/bin/bash
# issue 18 (branch giant): /tmp/giant/h65536.svo (conv65536.sh, the command before) rendered at 1920x1080 on
# one H200 (GPU 0) by the branch's svo_render -v: the whole helmet, then the close-up (bench_view.h's camera)
# in the same process (--view2), 21 frames each: read time, GPU scene time, host peaks, the layout's bytes,
# frame medians; every GPU's memory sampled by nvidia-smi every 0.2 s (the render uses one: the maximum of each
# is printed), host memory every 30 s.
# Env: LIMIT (s, default 570), RES (default 65536), OUTDIR (default /tmp/giant), SIZE (default 1920x1080)
export LD_LIBRARY_PATH=bench/out/giant:bench/out/base/bin
D=${GDIR:-bench/out/giant}; O=${OUTDIR:-/tmp/giant}
RES=${RES:-65536}; LIMIT=${LIMIT:-570}; SIZE=${SIZE:-1920x1080}
F=$O/h$RES.svo
CLOSE=0.396,-0.698,0.576,-0.002,0.187,-0.144
start=$(date +%s)
stamp() { echo "-- $(date -u +%H:%M:%S) t=$(( $(date +%s) - start )) s: $*"; }
echo "== host: $(nproc) CPUs, $(awk '/MemTotal/{printf "%.1f GiB", $2/1048576}' /proc/meminfo)"
HAVE_SMI=0; command -v nvidia-smi >/dev/null 2>&1 && HAVE_SMI=1
[ $HAVE_SMI = 1 ] && nvidia-smi --query-gpu=index,name,driver_version,memory.total,memory.used --format=csv,noheader
if ! [ -f $F ] || ! [ -f $F.size ] || [ "$(stat -c %s $F)" != "$(cat $F.size)" ]; then
  stamp "$F is missing or unfinished (no size marker): run conv65536.sh first"; ls -la $O 2>&1 | head; exit 1
fi
stamp "render $F ($(stat -c %s $F) B), $SIZE, limit $LIMIT s"
if [ $HAVE_SMI = 1 ]; then
  nvidia-smi --query-gpu=index,memory.used --format=csv,noheader,nounits -lms 200 > $O/smi.txt 2>/dev/null &
  smi=$!
fi
timeout $LIMIT $D/svo_render $F $O/r$RES.ppm --size $SIZE --mode albedo --frames 21 -v \
  --view2 $CLOSE $O/c$RES.ppm > $O/render$RES.log 2>&1 &
pid=$!; t0=$(date +%s%N)
n=0
while kill -0 $pid 2>/dev/null; do
  sleep 1; n=$((n + 1))
  kill -0 $pid 2>/dev/null || break
  [ $((n % 30)) = 0 ] || continue
  g=""; [ $HAVE_SMI = 1 ] && g=", GPU memory (index, MiB) $(tail -4 $O/smi.txt | sort -n | tr '\n' ' ')"
  stamp "rendering: host memory used $(free -g | awk '/Mem:/{print $3}') GiB$g; $(grep -E '^(read|gpu scene)' $O/render$RES.log | tr '\n' ' ')"
done
wait $pid; rc=$?; t1=$(date +%s%N); echo "wall $(( (t1 - t0) / 1000000 )) ms"
[ $HAVE_SMI = 1 ] && { kill $smi 2>/dev/null; wait $smi 2>/dev/null; }
gmax=""; [ $HAVE_SMI = 1 ] && gmax="; GPU memory used, max per GPU (index, MiB): $(awk -F', ' '{if ($2 > m[$1]) m[$1] = $2} END {for (i in m) printf "%s: %s  ", i, m[i]}' $O/smi.txt)"
stamp "render $RES: rc=$rc$gmax"
sed 's/^/  render| /' $O/render$RES.log
for f in $O/r$RES.ppm $O/c$RES.ppm; do [ -f $f ] && echo "image $f: $(md5sum < $f)"; done
