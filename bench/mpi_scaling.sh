#!/bin/sh
# MPI scaling of the probe bake and of the path-traced reference render
# (issues 22 and 23): one process, then mpirun -n N for each N in RANKS
# (REPS runs each), the same seed; every output must equal the
# single-process file byte for byte (the -n 1 file where ONE=0); prints each
# run's wall time, the median per N, parallel efficiency T1 / (N x TN) with T1
# the median -n 1 run, and where each run's time went (the tools' -v lines
# and their per-rank timelines set against this script's launch of mpirun).
# On a host with G GPUs rank r uses GPU r mod G (issue 23: one rank per GPU);
# on the lent one-GPU machines the ranks share it (issue 22).
#
# Usage: bench/mpi_scaling.sh BIN_DIR SCENE.svo [RANKS] [BAKE OPTIONS...]
#   defaults: RANKS "1 2 4", options "--grid 16,16,16 --res 128 --spp 64" (4,096 probes)
# Environment:
#   RENDER       reference render options (default "--mode pathtrace --size
#                1920x1080 --spp 16384 --seed 0"); "none" skips the render
#   BAKE=none    skips the bake
#   REPS         runs per rank count (default 1)
#   ONE=0        skips the single process (no mpirun; the outputs are then
#                compared with the -n 1 run's)
#   BASE=DIR     a baseline's binaries (main's): each run of BIN_DIR's tool is
#                followed by the same run of BASE's, so both see the same host
#                state; BASE runs with OpenMPI's defaults (no ONE_HOST
#                settings) unless BASE_ONE_HOST=1, as main's script ran them
#   ONE_HOST=0   OpenMPI's defaults instead of the one-host settings below
#   MPIRUN_ARGS  more mpirun options
#   TIMELINE=0   no per-rank timeline lines
#   OUT          folder for the outputs (default a temporary one)
#   VX_MPI_DEBS  folder of Debian OpenMPI .debs to extract into / first, for
#                a GPU machine without OpenMPI: see docs/PERFORMANCE.md section 9
#
# One host's settings (ONE_HOST=1, the default), each measured on the
# 4-H200 host (docs/PERFORMANCE.md section 10, bench/startup/mpit.c):
#   HWLOC_COMPONENTS=-opencl,-gl
#                          mpirun discovers the host's topology before it
#                          starts a rank; hwloc's OpenCL plugin opens every
#                          OpenCL platform installed (that host has pocl's),
#                          which took 1.1 s of every mpirun's launch (from
#                          mpirun's start to a rank's exec: 1.14-1.20 s, with
#                          it left out 0.09 s); a GPU's place in the topology
#                          comes from its PCI device, which hwloc's pci
#                          component still reports
#   --mca pml ob1 --mca btl self,vader
#                          the ranks of one host talk through shared memory;
#                          OpenMPI's default selection first probes UCX (its
#                          CUDA, InfiniBand and TCP transports), openib and
#                          ofi in every MPI_Init (0.28-0.33 s, with these
#                          0.08-0.14 s)
#   --mca osc ^ucx         no UCX one-sided component (the tools use none)
#   --bind-to none         the tools start threads (the device's, the bake's
#                          writer); mpirun's default binding would put them on
#                          one core per rank
# and inside the tools (not a setting): each rank's Vulkan driver sees only
# the rank's GPU (tools/common/gpu_only.c; VX_MPI_ALL_GPUS=1 in the
# environment, passed with mpirun -x, turns that off).
#
# The GPU machines have no Vulkan loader: extract the loader debs first as in
# ../shared/guide/GPU.md (for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig;
# export VK_DRIVER_FILES=...), and carry svo_bake and svo_render built with
# -DVX_WITH_OIIO=OFF (they need only libvulkan, libz and OpenMPI; the render
# is written as .pfm, which needs no OpenImageIO). OpenMPI: the host's own
# (4.1.6 on the H100/H200 hosts so far); the script prints which.
set -u
BIN=$1
SCENE=$2
RANKS=${3:-"1 2 4"}
[ $# -ge 3 ] && shift 3 || shift $#
OPTS=${*:-"--grid 16,16,16 --res 128 --spp 64"}
REPS=${REPS:-1}
BASE=${BASE:-}
D=${OUT:-$(mktemp -d)}
mkdir -p "$D"
if [ -n "${VX_MPI_DEBS:-}" ]; then
  for f in "$VX_MPI_DEBS"/*.deb; do dpkg -x "$f" /; done
  ldconfig
fi
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
MPIRUN=${MPIRUN:-mpirun}
[ -x /usr/bin/mpirun ] && MPIRUN=/usr/bin/mpirun
ONEHOST_ARGS="--mca pml ob1 --mca btl self,vader --mca osc ^ucx"
ONEHOST_HWLOC="-opencl,-gl"
echo "host: $(hostname), $(nproc) CPUs; $(nvidia-smi -L 2>/dev/null | wc -l) NVIDIA GPUs"
nvidia-smi -L 2>/dev/null | head -8
echo "mpirun: $(command -v "$MPIRUN") ($("$MPIRUN" --version 2>&1 | head -1))"
echo "scene: $SCENE; bake options: $OPTS; $REPS run(s) per rank count"
if [ "${ONE_HOST:-1}" = 1 ]; then echo "one-host settings: $ONEHOST_ARGS, HWLOC_COMPONENTS=$ONEHOST_HWLOC"; else echo "OpenMPI's defaults"; fi
[ -n "$BASE" ] && echo "baseline: $BASE ($([ "${BASE_ONE_HOST:-0}" = 1 ] && echo "one-host settings" || echo "OpenMPI's defaults"))"
now() { date +%s.%N; }
median() { sort -n | awk '{ v[NR] = $1 } END { if (NR % 2) print v[(NR + 1) / 2]; else print (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
# timeline FILE LAUNCH RETURN: the ranks' timeline lines against the launch
# of mpirun (+s) and its return
timeline() {
  awk -v L="$2" -v R="$3" '
    /^timeline rank/ {
      r = $3; sub(":", "", r); n++
      for (i = 4; i < NF; i += 2) t[r, $i] = $(i + 1) - L
      ranks[r] = 1
    }
    function at(r, k) { return ((r, k) in t) ? sprintf("%.3f", t[r, k]) : "-" }
    function span(r, a, b) { return ((r, a) in t && (r, b) in t) ? sprintf("%.3f-%.3f", t[r, a], t[r, b]) : "-" }
    END {
      if (!n) exit
      last = 0
      for (r in ranks) if (t[r, "end"] > last) last = t[r, "end"]
      for (r = 0; (r in ranks); r++)
        printf("  rank %d: exec %s, main %s, MPI_Init %s, Vulkan %s (device %s), work %s, reduced %s, output %s, end %s\n",
               r, at(r, "exec"), at(r, "main"), span(r, "mpi_init", "mpi_ready"), span(r, "vk_start", "vk_ready"),
               at(r, "vk_device"), span(r, "work", "done"), at(r, "reduced"), at(r, "output"), at(r, "end"))
      printf("  mpirun returned at %.3f: %.3f s after the last rank ended\n", R - L, R - L - last)
    }' "$1"
}
# run ONEHOST DIR TOOL N OUTFILE ARGS...: one mpirun; prints its lines; sets TN
run() {
  oh=$1 dir=$2 tl=$3 n=$4 of=$5
  shift 5
  if [ "$oh" = 1 ]; then
    a=$ONEHOST_ARGS h=$ONEHOST_HWLOC
  else
    a="" h=${HWLOC_COMPONENTS:-}
  fi
  t=$(now)
  # shellcheck disable=SC2086
  HWLOC_COMPONENTS=$h "$MPIRUN" --oversubscribe --bind-to none $a ${MPIRUN_ARGS:-} -n "$n" "$dir/$tl" "$SCENE" "$of" "$@" -v >"$D/run.out" 2>&1 ||
    { tail -20 "$D/run.out"; echo "mpirun -n $n $dir/$tl failed"; exit 1; }
  e=$(now)
  TN=$(awk -v a="$e" -v b="$t" "BEGIN{printf \"%.2f\", a-b}")
  grep -E "^rank|^baked|^output|^rendered|render:" "$D/run.out" | head -24
  [ "${TIMELINE:-1}" = 1 ] && timeline "$D/run.out" "$t" "$e"
}
# scale TOOL OUTEXT ARGS...: one process, then mpirun -n N for every N
scale() {
  tool=$1 ext=$2
  shift 2
  printf "| binary | run | wall s (each run) | median s | efficiency T1/(N TN) | output |\n| --- | --- | --- | ---: | ---: | --- |\n" > "$D/table.md"
  REF=""
  if [ "${ONE:-1}" = 1 ]; then
    t=$(now)
    "$BIN/$tool" "$SCENE" "$D/one.$ext" "$@" >"$D/one.out" 2>&1 || { cat "$D/one.out"; echo "single $tool failed"; exit 1; }
    T0=$(awk -v a="$(now)" -v b="$t" "BEGIN{print a-b}")
    grep -E "device|baked|render:" "$D/one.out"
    printf "| %s | one process | %.2f | | | |\n" "$BIN" "$T0" >> "$D/table.md"
    REF=$D/one.$ext
  fi
  T1=""
  B1=""
  for n in $RANKS; do
    runs="" same="identical" r=0 bruns="" bsame="identical"
    : >"$D/times"
    : >"$D/btimes"
    while [ $r -lt "$REPS" ]; do
      run "${ONE_HOST:-1}" "$BIN" "$tool" "$n" "$D/n$n.$ext" "$@"
      echo "$TN" >>"$D/times"
      runs="$runs${runs:+, }$TN"
      [ -z "$REF" ] && { cp "$D/n$n.$ext" "$D/ref.$ext"; REF=$D/ref.$ext; }
      cmp -s "$REF" "$D/n$n.$ext" || same="differs"
      echo "== $BIN/$tool mpirun -n $n, run $((r + 1)): $TN s"
      rm -f "$D/n$n.$ext"
      if [ -n "$BASE" ]; then
        run "${BASE_ONE_HOST:-0}" "$BASE" "$tool" "$n" "$D/b$n.$ext" "$@"
        echo "$TN" >>"$D/btimes"
        bruns="$bruns${bruns:+, }$TN"
        cmp -s "$REF" "$D/b$n.$ext" || bsame="differs"
        echo "== $BASE/$tool mpirun -n $n, run $((r + 1)): $TN s"
        rm -f "$D/b$n.$ext"
      fi
      r=$((r + 1))
    done
    TM=$(median <"$D/times")
    [ -z "$T1" ] && T1=$TM
    E=$(awk -v a="$T1" -v n="$n" -v b="$TM" "BEGIN{printf \"%.3f\", a/(n*b)}")
    printf "| %s | mpirun -n %s | %s | %.2f | %s | %s |\n" "$BIN" "$n" "$runs" "$TM" "$E" "$same" >> "$D/table.md"
    if [ -n "$BASE" ]; then
      BM=$(median <"$D/btimes")
      [ -z "$B1" ] && B1=$BM
      E=$(awk -v a="$B1" -v n="$n" -v b="$BM" "BEGIN{printf \"%.3f\", a/(n*b)}")
      printf "| %s | mpirun -n %s | %s | %.2f | %s | %s |\n" "$BASE" "$n" "$bruns" "$BM" "$E" "$bsame" >> "$D/table.md"
    fi
  done
  echo "$tool $*"
  cat "$D/table.md"
  rm -f "$D/one.$ext" "$D/ref.$ext"
}
if [ "${RENDER:-}" != none ]; then
  # shellcheck disable=SC2086
  scale svo_render pfm ${RENDER:---mode pathtrace --size 1920x1080 --spp 16384 --seed 0}
fi
[ "${BAKE:-}" = none ] && exit 0
# shellcheck disable=SC2086
scale svo_bake probes $OPTS
