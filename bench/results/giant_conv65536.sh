#!/bin/bash
# issue 18 (branch giant): the DamagedHelmet at 65536^3 made on this host's CPUs (mpirun vox2svo --chunked,
# ranks = CPUs / 4, each on 4 threads) into /tmp/giant/h65536.svo, kept for render65536.sh (a second command).
# Skipped when the file is there with its size marker (a finished conversion). Prints progress every 30 s.
# Env: LIMIT (s, default 570), RES (default 65536), NP (ranks), OUTDIR (default /tmp/giant)
export LD_LIBRARY_PATH=bench/out/giant:bench/out/base/bin
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
D=${GDIR:-bench/out/giant}; O=${OUTDIR:-/tmp/giant}; mkdir -p $O
RES=${RES:-65536}; LIMIT=${LIMIT:-570}
NP=${NP:-$(( $(nproc) / 4 ))}; [ "$NP" -lt 1 ] && NP=1
F=$O/h$RES.svo
start=$(date +%s)
stamp() { echo "-- $(date -u +%H:%M:%S) t=$(( $(date +%s) - start )) s: $*"; }
echo "== host: $(nproc) CPUs, $(awk '/MemTotal/{printf "%.1f GiB", $2/1048576}' /proc/meminfo), $O free $(df -h $O | awk 'NR==2{print $4}')"
if [ -f $F ] && [ -f $F.size ] && [ "$(stat -c %s $F)" = "$(cat $F.size)" ]; then
  stamp "$F is there ($(cat $F.size) B, its marker agrees): not converted again"; exit 0
fi
rm -f $F $F.size $O/h$RES.svo.tmp*
stamp "convert $RES: $NP ranks, limit $LIMIT s"
timeout $LIMIT mpirun --bind-to none -n $NP $D/vox2svo $D/helmet.glb $F --res $RES --chunked -v > $O/conv$RES.log 2>&1 &
pid=$!; t0=$(date +%s%N)
n=0
while kill -0 $pid 2>/dev/null; do
  sleep 1; n=$((n + 1))
  kill -0 $pid 2>/dev/null || break
  [ $((n % 30)) = 0 ] || continue
  stamp "converting: host memory used $(free -g | awk '/Mem:/{print $3}') GiB, $(ls -la $O | grep -c tmp) partial files ($(du -sb $O | cut -f1) B in $O), load $(cut -d' ' -f1 /proc/loadavg)"
done
wait $pid; rc=$?; t1=$(date +%s%N); echo "wall $(( (t1 - t0) / 1000000 )) ms"
stamp "convert $RES: rc=$rc, file $(stat -c %s $F 2>/dev/null) B"
grep -E 'voxels|models|output|time |peak|converted|^rank' $O/conv$RES.log | head -80 | sed 's/^/  conv| /'
[ $rc = 0 ] && [ -f $F ] && stat -c %s $F > $F.size || { tail -20 $O/conv$RES.log; exit 1; }
df -h $O | sed 's/^/  disk| /'
