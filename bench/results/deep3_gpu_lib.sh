# deep3 (issue 21, twenty-fourth sitting): the lines both H200 payloads (deep3_b1_gpu.sh, deep3_b2_gpu.sh) share,
# sourced by them here (the payloads carried them inline): unpack A, B, C and k.tgz, the time left of LIM, the clock,
# a time stamp per line, the rows' filter, a --kernels list, one labelled process (run), and the end (finish).
# BATCH: the batch's number; LIM: the whole run's seconds.
s0=$(date +%s); left() { echo $(( $1 * ${TS:-1} - ($(date +%s) - s0) )); }
T=/tmp/deep3; rm -rf $T; mkdir -p $T; for x in A B C; do gunzip -c ${x}_render_bench.gz > $T/$x; chmod +x $T/$x; done
tar xzf k.tgz -C $T
SIZE=${SIZE:-1920x1080}; RUNS=${RUNS:-15}; WU=${WU:-0.5}
smi() { nvidia-smi --query-gpu=clocks.sm,clocks.mem,power.draw,temperature.gpu,pstate --format=csv,noheader 2>/dev/null | head -1; }
stamp() { while IFS= read -r l; do printf '%s %s\n' "$(date -u +%T.%1N)" "$l"; done; }
flt() { sed -u -E "s|$T/||g; s/  *\[warps[^]]*\]//; s/  *\[traced[^]]*\]//; s/^(.{300}).*/\1/"; }
F='^scene|^terrain|^  \(|px differ|^device|^render_bench|^stats: trace \['
echo "== deep3 batch $BATCH on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1) $(nproc) CPUs $(date -u +%T); A = main $(cat A_COMMIT), B = $(cat B_COMMIT), C = $(cat C_COMMIT)"
nvidia-smi --query-gpu=timestamp,clocks.sm --format=csv,noheader -lms 250 > $T/smi.log 2>/dev/null &
smipid=$!
kl() { local r=; for k in ${1//,/ }; do r="$r${r:+,}$T/$k.spv@c1"; done; echo $r; }
run() { # label max-seconds args...: one process if 8 s of the whole are left
  local x=$1 mx=$2; shift 2; local l=$(left $LIM); [ $l -gt $((8 * ${TS:-1})) ] || { echo "   $x: no time left"; return; }
  [ $l -gt $(($mx * ${TS:-1})) ] && l=$(($mx * ${TS:-1}))
  echo "-- $x $(date -u +%T): clock $(smi)"
  timeout $l "$@" 2>&1 | grep --line-buffered -E "$F" | flt | sed -u "s/^/$x /" | stamp
}
finish() {
  kill $smipid 2>/dev/null; wait $smipid 2>/dev/null
  echo "-- clock samples: $(wc -l < $T/smi.log), SM MHz min/median/max $(cut -d, -f2 $T/smi.log | tr -dc '0-9\n' | sort -n | awk '{a[NR]=$1} END {if (NR) print a[1], a[int((NR+1)/2)], a[NR]}')"
  [ -n "$OUT" ] && tar czf $OUT/deep3.tar.gz -C $T smi.log
  echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
}
