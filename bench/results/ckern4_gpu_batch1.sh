#!/bin/bash
# ckern4 batch 1 (issue 18, eleventh step): the compact kernel's albedo colour
# in a second dispatch. Each compact kernel against trace.comp in the same
# process; processes alternate: main (bench/out/base/bin, b74da51), the
# branch with VX_CK_SPLIT=2 (s2: 8 bytes a pixel in a buffer of their own),
# =1 (s1: model and cell in the pixel, the resolve reads it back), h: the
# colour in the trace kernel with VX_CK_HDR=1 (a header word per block, no
# group word), s2h: both. Ratios compact / trace.comp per process; both
# dispatches timed together.
G=bench/out/ckern4; B=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; TER=${TER:-1024}; ROUNDS=${ROUNDS:-2}; REPS=${REPS:-30}; TOB=${TOB:-16}
export LD_LIBRARY_PATH=$G:$B
echo "== ckern4 batch 1, $(cat $G/COMMIT 2>/dev/null), $(date -u)"; nproc; cat /proc/loadavg
nvidia-smi --query-gpu=name,clocks.sm,clocks.mem,temperature.gpu --format=csv,noheader 2>/dev/null
T0=$(date +%s); t() { echo $(( $(date +%s) - T0 )); }
SC="$G/eph_monu1.vox $G/eph_menger.vox $G/helmet512.svo --terrain $TER"
echo "=== warm-up t=$(t)"; timeout 4 $B/compact_bench --gpu $SIZE --reps 60 $G/eph_menger.vox > /dev/null 2>&1
run() { # who round bin split hdr
  st=""; [ $2 = 1 ] && st="--shader-stats"
  echo "=== K$2 $1 t=$(t)"
  VX_CK_SPLIT=$4 VX_CK_HDR=$5 timeout $TOB $3 $st --gpu $SIZE --reps $REPS $SC > /tmp/ckern4_k_$1_$2.txt 2>&1
  echo "rc=$? t=$(t)"
  grep -v "^|\|^stats\|^device\|^$" /tmp/ckern4_k_$1_$2.txt | sort | uniq -c | head -5
  grep "^| .* | \(overview\|close-up\)" /tmp/ckern4_k_$1_$2.txt | cut -c1-300
  grep "^stats: \(trace compact\|resolve compact\|trace\) \[spec 1," /tmp/ckern4_k_$1_$2.txt | cut -c1-260 | head -12
}
for round in $(seq $ROUNDS); do
  run main $round $B/compact_bench 0 0
  run s2 $round $G/compact_bench_s 2 0
  run s1 $round $G/compact_bench_s 1 0
  run h $round $G/compact_bench_s 0 1
  run s2h $round $G/compact_bench_s 2 1
done
echo "=== summary: compact / trace.comp rays/s, albedo (depth mode), per round"
for who in main s2 s1 h s2h; do
  cat /tmp/ckern4_k_${who}_*.txt | awk -F'|' -v who=$who '$3 ~ /overview|close-up/ { k=$2"|"$3; gsub(/\*/,"",$6); r[k]=r[k]" "$6"("$7")"; if (!(k in o)) { o[k]=++n; key[n]=k } }
    END { for (i=1;i<=n;i++) print who " |" key[i] "|" r[key[i]] }'
done
echo "=== end t=$(t)"
