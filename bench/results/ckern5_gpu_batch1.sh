#!/bin/bash
# ckern5 batch 1 (issue 18, twelfth step): the compact kernel against
# trace.comp in the same process; processes alternate (ABAB, 2 rounds):
# main (bench/out/base/bin, b16046b) and the branch's exploration binary
# with VX_CK5 picking a kernel variant (trace_compact.comp CK5 bits):
# 1 one sample (no samples' loop), 2 the instance and the model's walk
# fields from the frame block (one instance), 4 restrict on the read-only
# buffers, 8 no depth-1 model (the load's choice 2-way), 16 the BVH leaf's
# items flat (trace.comp's TRACE_FLAT_ITEMS), 31 all five, 32 the colour's
# descent with levels 4 and 3 out of its loop, 64 trace.comp's own kernel
# (trace_common.glsl's COMPACT form, as the passes') over the compact
# layout. All with VX_CK5_UNI=0 (main's start tables), but u = the kernel
# as main's with the start tables' uniform cubes (VX_CK5_UNI=1: an entry
# whose level-K cube's cells all hold one value gives that value, no
# descent or decode) and u31 = 31 with them. Round 2 runs what fits before
# TMAX seconds.
G=bench/out/ckern5; B=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; TER=${TER:-1024}; ROUNDS=${ROUNDS:-2}; REPS=${REPS:-30}; TOB=${TOB:-14}; TMAX=${TMAX:-136}
VARS=${VARS:-"u u31 64 31 2 1 32 4 16 8"}
export LD_LIBRARY_PATH=$G:$B
mkdir -p /tmp/ck5; gzip -dc $G/compact_bench.gz > /tmp/ck5/compact_bench && chmod +x /tmp/ck5/compact_bench
X=/tmp/ck5/compact_bench
echo "== ckern5 batch 1, $(cat $G/COMMIT 2>/dev/null), $(date -u)"; nproc; cat /proc/loadavg
nvidia-smi --query-gpu=name,clocks.sm,clocks.mem,temperature.gpu --format=csv,noheader 2>/dev/null
T0=$(date +%s); t() { echo $(( $(date +%s) - T0 )); }
SC="$G/eph_monu1.vox $G/eph_menger.vox $G/helmet512.svo --terrain $TER"
echo "=== warm-up t=$(t)"; timeout 4 $B/compact_bench --gpu $SIZE --reps 60 $G/eph_menger.vox > /dev/null 2>&1
run() { # who round bin env...
  who=$1 round=$2 bin=$3; shift 3
  if [ $(t) -gt $TMAX ]; then echo "=== skip $who $round t=$(t)"; return; fi
  st=""; [ $round = 1 ] && st="--shader-stats"
  echo "=== K$round $who t=$(t) $*"
  env "$@" timeout $TOB $bin $st --gpu $SIZE --reps $REPS $SC > /tmp/ck5/k_${who}_$round.txt 2>&1
  echo "rc=$? t=$(t)"
  grep -v "^|\|^stats\|^device\|^$" /tmp/ck5/k_${who}_$round.txt | sort | uniq -c | head -5
  grep "^| .* | \(overview\|close-up\)" /tmp/ck5/k_${who}_$round.txt | cut -c1-300
  grep "^stats: trace\( compact\| (compact)\) \[spec [13]," /tmp/ck5/k_${who}_$round.txt | sort -u | cut -c1-220 | head -8
  [ $who = main ] && [ $round = 1 ] && grep "^stats: trace \[spec [13]," /tmp/ck5/k_${who}_$round.txt | sort -u | cut -c1-220 | head -8
}
for round in $(seq $ROUNDS); do
  run main $round $B/compact_bench VX_CK5=0
  for v in $VARS; do
    case $v in
      u) run u $round $X VX_CK5=0 VX_CK5_UNI=1 ;;
      u31) run u31 $round $X VX_CK5=31 VX_CK5_UNI=1 ;;
      *) run v$v $round $X VX_CK5=$v VX_CK5_UNI=0 ;;
    esac
  done
done
echo "=== summary: compact / trace.comp rays/s, albedo (depth mode), per round"
for who in main $(for v in $VARS; do case $v in u*) echo $v ;; *) echo v$v ;; esac; done); do
  cat /tmp/ck5/k_${who}_*.txt 2>/dev/null | awk -F'|' -v who=$who '$3 ~ /overview|close-up/ { k=$2"|"$3; gsub(/\*/,"",$6); r[k]=r[k]" "$6"("$7")"; if (!(k in o)) { o[k]=++n; key[n]=k } }
    END { for (i=1;i<=n;i++) print who " |" key[i] "|" r[key[i]] }'
done
echo "=== end t=$(t)"
