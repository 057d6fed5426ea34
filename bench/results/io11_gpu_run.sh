#!/bin/bash
# io11 (issue 18, the I/O goals at the host's full rate; coordinator, stop 57) on the H200 host's CPUs (no GPU used):
# main's svo_io_bench only (no A/B): the 4096^3 helmet made there by main's vox2svo (tinygltf compiled in, every core)
# and written again by svo_io_bench --write-as (the default form), then rounds of its read and write (--threads 2
# --pin 0,1), then the benchmark terrain (svo_build_bench -o) and its reads. Before every process the pair's ALU rate
# (io9's hostprobe alu: G adds/s a CPU, about 9.5-11 at full rate): the goal's "2 cores" are two cores at their
# rate, so the medians are given over all rounds and over the rounds whose pair ran at 8.5 G adds/s or more on both.
# LIMIT: the run's limit in s.
T=${T:-/tmp/io11}; rm -rf $T; mkdir -p $T/bin
for f in bin/*.gz; do gunzip -c $f > $T/bin/$(basename $f .gz); chmod +x $T/bin/$(basename $f .gz); done
cp bin/hostprobe $T/bin/; X=$T/bin; P=${PIN:-0,1}; START=$(date +%s)
left() { echo $(( ${LIMIT:-250} - ($(date +%s) - START) )); }
echo "== io11 $(cat REV) on $(hostname): $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2), $(nproc) cpus, load $(cut -d' ' -f1-3 /proc/loadavg); pin $P; $(date -u +%T) UTC"
run() { # name file only
  local alu=$(timeout 5 $X/hostprobe $P alu | grep alu | sed 's/.*: //; s/ G adds.*//')
  local out=$(timeout ${RT:-20} $X/svo_io_bench $2 --runs 1 --threads 2 --pin $P --only $3 --out $T 2>&1)
  local line=$(echo "$out" | grep -E '^2 +(read|write) file' | tail -1)
  local a0=$(echo "$alu" | awk '{print $3}') a1=$(echo "$alu" | awk '{print $6}')
  echo "$(echo "$line" | awk '{print $(NF-2), $(NF-1)}') $a0 $a1" >> $T/$1.txt
  echo "   $1: wall/cpu $(echo "$line" | awk '{print $(NF-2), $(NF-1)}'); alu before [$alu]; $(echo "$out" | grep rusage | sed 's/.*rusage: //') $(echo "$out" | grep -E 'rror|differ' | head -2 | tr '\n' ' ')"
}
med() { # all rounds, then rounds at full rate (both CPUs >= 8.5)
  [ -s $T/$1.txt ] || return
  sort -n -k1 $T/$1.txt | awk -v n=$1 '{w[NR]=$1; c[NR]=$2} END {m=int((NR+1)/2); printf "%-4s all rounds: n %d, median wall %s s (cpu %s); walls", n, NR, w[m], c[m]; for(i=1;i<=NR;i++) printf " %s", w[i]; print ""}'
  sort -n -k1 $T/$1.txt | awk -v n=$1 '$3 >= 8.5 && $4 >= 8.5 {k++; w[k]=$1; c[k]=$2} END {if (!k) {print n "  full rate: no round"; exit} m=int((k+1)/2); printf "%-4s full rate: n %d, median wall %s s (cpu %s); walls", n, k, w[m], c[m]; for(i=1;i<=k;i++) printf " %s", w[i]; print ""}'
}
s=$(date +%s); timeout 60 $X/vox2svo khronos_DamagedHelmet.glb $T/h0.svo --res ${RES:-4096} > $T/vox.log 2>&1; rc=$?
echo "== helmet made by main's vox2svo (every core) in $(( $(date +%s) - s )) s (rc $rc), $(stat -c %s $T/h0.svo 2>/dev/null) bytes"; tail -3 $T/vox.log
s=$(date +%s); timeout 30 $X/svo_io_bench $T/h0.svo --write-as $T/h.svo | tail -1; rm -f $T/h0.svo
echo "== --write-as copy in $(( $(date +%s) - s )) s: $(stat -c %s $T/h.svo 2>/dev/null) bytes, md5 $(md5sum $T/h.svo | cut -c1-32)"
for round in 1 2 3 4 5 6 7 8 9 10; do
  [ $(left) -gt 60 ] || break
  echo "-- helmet round $round ($(left) s left)"; run r $T/h.svo readfile; run w $T/h.svo writefile
done
rm -f $T/h.svo
s=$(date +%s); ( cd $T && timeout 40 $X/svo_build_bench -o $T/t.svo > $T/terrain.log 2>&1 )
echo "== terrain made by svo_build_bench in $(( $(date +%s) - s )) s (every core), $(stat -c %s $T/t.svo 2>/dev/null) bytes, md5 $(md5sum $T/t.svo | cut -c1-32)"
for round in 1 2 3 4 5 6; do [ $(left) -gt 8 ] || break; echo "-- terrain round $round"; run t $T/t.svo readfile; done
echo "== medians (goal: helmet write and read under 3 s each on 2 cores; terrain read under 2 s)"
for f in r w t; do med $f; done
echo "== done in $(( $(date +%s) - START )) s"
rm -rf $T
