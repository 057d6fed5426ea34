#!/bin/bash
# ckern5 batch 3 (issue 18, twelfth step): whole binaries, each compact
# kernel against trace.comp in the same process; processes alternate
# (ABAB, 2 rounds, a third where time is left): main (bench/out/base/bin,
# b16046b), B = the branch (b77e106: start-table entries of one value,
# the ONE_SAMPLE constant), C = B + a uniform entry holding the colour
# itself (a palette model's: no palette load), D = C + the colour's
# descent with its levels 4 and 3 out of its loop (cell_index_peel).
G=bench/out/ckern5; B=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; TER=${TER:-1024}; ROUNDS=${ROUNDS:-3}; REPS=${REPS:-30}; TOB=${TOB:-14}; TMAX=${TMAX:-84}
export LD_LIBRARY_PATH=$G:$B
mkdir -p /tmp/ck5
for v in B C D; do gzip -dc $G/compact_bench_$v.gz > /tmp/ck5/compact_bench_$v && chmod +x /tmp/ck5/compact_bench_$v; done
echo "== ckern5 batch 3, $(cat $G/COMMIT 2>/dev/null), $(date -u)"; nproc; cat /proc/loadavg
nvidia-smi --query-gpu=name,clocks.sm,clocks.mem,temperature.gpu --format=csv,noheader 2>/dev/null
T0=$(date +%s); t() { echo $(( $(date +%s) - T0 )); }
SC="$G/eph_monu1.vox $G/eph_menger.vox $G/helmet512.svo --terrain $TER"
echo "=== warm-up t=$(t)"; timeout 4 $B/compact_bench --gpu $SIZE --reps 60 $G/eph_menger.vox > /dev/null 2>&1
run() { # who round bin
  who=$1 round=$2 bin=$3
  if [ $(t) -gt $TMAX ]; then echo "=== skip $who $round t=$(t)"; return; fi
  st=""; [ $round = 1 ] && st="--shader-stats"
  echo "=== K$round $who t=$(t)"
  timeout $TOB $bin $st --gpu $SIZE --reps $REPS $SC > /tmp/ck5/k_${who}_$round.txt 2>&1
  echo "rc=$? t=$(t)"
  grep -v "^|\|^stats\|^device\|^$" /tmp/ck5/k_${who}_$round.txt | sort | uniq -c | head -5
  grep "^| .* | \(overview\|close-up\)" /tmp/ck5/k_${who}_$round.txt | cut -c1-300
  grep "^stats: trace compact \[spec [13]," /tmp/ck5/k_${who}_$round.txt | sort -u | cut -c1-220 | head -8
}
for round in $(seq $ROUNDS); do
  run main $round $B/compact_bench
  run C $round /tmp/ck5/compact_bench_C
  run D $round /tmp/ck5/compact_bench_D
  run B $round /tmp/ck5/compact_bench_B
done
echo "=== summary: compact / trace.comp rays/s, albedo (depth mode), per round"
for who in main B C D; do
  cat /tmp/ck5/k_${who}_*.txt 2>/dev/null | awk -F'|' -v who=$who '$3 ~ /overview|close-up/ { k=$2"|"$3; gsub(/\*/,"",$6); r[k]=r[k]" "$6"("$7")"; if (!(k in o)) { o[k]=++n; key[n]=k } }
    END { for (i=1;i<=n;i++) print who " |" key[i] "|" r[key[i]] }'
done
echo "=== end t=$(t)"
