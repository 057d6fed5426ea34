# The lines the H200 payloads of issue 21 share (deep3_gpu_lib.sh, rbstart_b1_gpu.sh, rbstart_b2_gpu.sh; the payloads
# that ran carried them inline), sourced once LIM (the whole run's seconds) is set, T (a fresh temporary folder) by the
# caller or payload_setup:
# the time left, the clock, a time stamp per line, the rows' filter, one labelled process (run), the clock's log
# (clock_start) and the end (payload_end NAME: $OUT/NAME.tar.gz holds the clock's log).
# SIZE, RUNS, WU, TS (time scale) may be set (lavapipe: SIZE=96x54 RUNS=1 WU=0 TS=20).
# payload_setup NAME [TEST...]: the NVIDIA driver's Vulkan loader where there is a GPU (docs: ../shared/guide/GPU.md),
# payload/lib on the library path, T=/tmp/NAME afresh with render_bench and payload/T_TEST.gz unpacked into it.
payload_setup() {
  if command -v nvidia-smi >/dev/null; then for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
    export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json; fi
  export LD_LIBRARY_PATH=$PWD/payload/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
  T=/tmp/$1; shift; rm -rf $T; mkdir -p $T
  gunzip -c payload/render_bench.gz > $T/render_bench; chmod +x $T/render_bench
  local t; for t in "$@"; do gunzip -c payload/T_$t.gz > $T/$t; chmod +x $T/$t; done
}
s0=$(date +%s); left() { echo $(( $1 * ${TS:-1} - ($(date +%s) - s0) )); }
SIZE=${SIZE:-1920x1080}; RUNS=${RUNS:-15}; WU=${WU:-0.5}
smi() { nvidia-smi --query-gpu=clocks.sm,clocks.mem,power.draw,temperature.gpu,pstate --format=csv,noheader 2>/dev/null | head -1; }
stamp() { while IFS= read -r l; do printf '%s %s\n' "$(date -u +%T.%1N)" "$l"; done; }
flt() { sed -u -E "s|$T/||g; s/  *\[warps[^]]*\]//; s/  *\[traced[^]]*\]//; s/^(.{300}).*/\1/"; }
F='^scene|^terrain|^  \(|px differ|^device|^render_bench|^stats: '
gpu_name() { nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1; }
clock_start() { nvidia-smi --query-gpu=timestamp,clocks.sm --format=csv,noheader -lms 250 > $T/smi.log 2>/dev/null & smipid=$!; }
# gpu_warmup FILE: 2 s of FILE's close-up without ESVO, output dropped, so that the first timed
# process starts at the SM's clocks (the line the payloads before stop 89 carried inline)
gpu_warmup() { timeout 10 $T/render_bench --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup "$1" > /dev/null 2>&1; }
run() { # label max-seconds args...: one process if 8 s of the whole are left
  local x=$1 mx=$2; shift 2; local l=$(left $LIM); [ $l -gt $((8 * ${TS:-1})) ] || { echo "   $x: no time left"; return; }
  [ $l -gt $(($mx * ${TS:-1})) ] && l=$(($mx * ${TS:-1}))
  echo "-- $x $(date -u +%T): clock $(smi)"
  timeout $l "$@" 2>&1 | grep --line-buffered -E "$F" | flt | sed -u "s/^/$x /" | stamp
}
payload_end() {
  kill $smipid 2>/dev/null; wait $smipid 2>/dev/null
  echo "-- clock samples: $(wc -l < $T/smi.log), SM MHz min/median/max $(cut -d, -f2 $T/smi.log | tr -dc '0-9\n' | sort -n | awk '{a[NR]=$1} END {if (NR) print a[1], a[int((NR+1)/2)], a[NR]}')"
  [ -n "$OUT" ] && tar czf $OUT/$1.tar.gz -C $T smi.log
  echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
}
# The GPU tests after a payload's timings: gpu_tests PATTERN NAME...: each test binary $T/NAME (unpacked by the
# payload) within TLIM seconds (default 150), its exit status and time, and its log's lines that match the
# failures, the counts and PATTERN (extra lines a payload wants, "" for none).
gpu_tests() {
  local pat=$1 t s rc; shift
  for t in "$@"; do
    s=$(date +%s); timeout ${TLIM:-150} $T/$t > $T/$t.log 2>&1; rc=$?
    echo "-- $t: exit $rc in $(( $(date +%s) - s )) s"
    grep -E "CHECK failed|FAIL|passed,|SKIP${pat:+|$pat}" $T/$t.log | head -60
  done
}
