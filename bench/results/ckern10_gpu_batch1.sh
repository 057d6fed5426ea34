#!/bin/bash
# ckern10 batch 1 (issue 18). Xa: the helmet close-up's colour, exploration binary (--variants: CK10 bits
# 1 a start-table entry in one 64-bit load, 2 a delta block's minimum and widths in one 64-bit load
# (delta payloads at even words), 4 the block index subgroup-uniform where the lanes share it, 8 the
# delta widths from a side array per block (the chain one load shorter: a latency test), 0x40 the
# level-3 slot and, where odd, the previous one in one 128-bit load, 0x80 level 3's bricks and the
# cell's brick in 128-bit loads of slot pairs; 0x10 / 0x20 diagnostic cuts (wrong colours): a hash
# of the header / of the minimum and widths), each timed against trace.comp in the process.
# Then whole processes: main's compact_bench (bench/out/base/bin, ca70d1a) and the exploration binary
# with VX_CK10=0xc3 (1 + 2 + 0x40 + 0x80 for every kernel of the process) alternating (main, K, main, K),
# each kernel against trace.comp in its process; then the passes' compact kernels (trace_common.glsl: DEEP 0 without the exit test before a push),
# passes_bench --layout compact, main's (built from ca70d1a) and the branch's alternating, eph_monu1 and
# eph_menger (DEEP 0 scenes).
G=bench/out/ckern10; B=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; TER=${TER:-1024}; REPS=${REPS:-30}; END=${END:-95}
export LD_LIBRARY_PATH=$PWD/$G:$PWD/$B
T=/tmp/ck10; rm -rf $T; mkdir -p $T
for f in compact_bench passes_bench passes_bench_main; do gzip -dc $G/$f.gz > $T/$f && chmod +x $T/$f; done
O=${OUTDIR:-$T}; mkdir -p $O
echo "== ckern10 batch 1, $(date -u)"; nproc; cat /proc/loadavg
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.mem,temperature.gpu --format=csv,noheader 2>/dev/null
T0=$(date +%s); t() { echo $(( $(date +%s) - T0 )); }
echo "=== warm-up t=$(t)"; timeout 3 $B/compact_bench --gpu $SIZE --reps 60 $G/eph_menger.vox > /dev/null 2>&1
SC="$G/eph_monu1.vox $G/eph_menger.vox $G/helmet512.svo --terrain $TER"
run() { # who need_s max_s stats bin [args]
  who=$1 need=$2 max=$3 st=$4 bin=$5; shift 5
  tob=$(( END - $(t) )); [ $tob -gt $max ] && tob=$max
  if [ $tob -lt $need ]; then echo "=== skip $who t=$(t)"; return; fi
  echo "=== $who t=$(t)"
  timeout $tob $bin $st --gpu $SIZE --reps $REPS "$@" > $O/k_${who}.txt 2>&1
  echo "rc=$? t=$(t)"
  grep -v "^|\|^stats\|^device\|^$" $O/k_${who}.txt | sort | uniq -c | head -5
  grep "^| .* | \(overview\|close-up\)" $O/k_${who}.txt | cut -d'|' -f2-8,10,11 | sed "s/^/$who |/"
  grep "^stats: trace compact \[spec 1,1,0,[0-9]*,0," $O/k_${who}.txt | sort -u | sed 's/ CS (subgroup 32)//; s/Register Count/R/; s/Binary Size/bin/; s/Shared Memory Size/shm/; s/Local Memory Size=6871947/lmem=/; s/Stack Size/stk/' | cut -c1-170
}
prun() { # who max_s bin
  who=$1 max=$2 bin=$3
  tob=$(( END - $(t) )); [ $tob -gt $max ] && tob=$max
  if [ $tob -lt 4 ]; then echo "=== skip $who t=$(t)"; return; fi
  echo "=== $who t=$(t)"
  timeout $tob $bin --layout compact --runs 7 --size $SIZE $G/eph_monu1.vox $G/eph_menger.vox > $O/p_${who}.txt 2>&1
  echo "rc=$? t=$(t)"
  grep "^##\|^| single\|^| gbuffer |\|^| gbuffer,direct |\|^| gbuffer,direct,ao,aa,tonemap |" $O/p_${who}.txt | sed "s/^/$who /"
}
run Xa 10 15 --shader-stats $T/compact_bench --closeups --variants 1,2,3,0x40,0x80,0xc3,8,4,0x10,0x20 $G/helmet512.svo
run main1 11 16 "" $B/compact_bench $SC
VX_CK10=0xc3 run K1 11 16 --shader-stats $T/compact_bench $SC
run main2 11 16 "" $B/compact_bench $SC
VX_CK10=0xc3 run K2 11 16 "" $T/compact_bench $SC
prun Pm1 9 $T/passes_bench_main
prun Pk1 9 $T/passes_bench
prun Pm2 8 $T/passes_bench_main
prun Pk2 8 $T/passes_bench
echo "=== end t=$(t)"
