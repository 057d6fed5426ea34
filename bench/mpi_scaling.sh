#!/bin/sh
# MPI scaling of the probe bake and of the path-traced reference render
# (issues 22 and 23): one process, then mpirun -n N for each N in RANKS
# (REPS runs each), the same seed; every output must equal the
# single-process file byte for byte; prints each run's wall time, the median
# per N, parallel efficiency T1 / (N x TN) with T1 the median -n 1 run, and
# the tools' per-rank lines (-v: set-up, render or bake, waiting, messages,
# writes).
# On a host with G GPUs rank r uses GPU r mod G (issue 23: one rank per GPU);
# on the lent one-GPU machines the ranks share it (issue 22).
#
# Usage: bench/mpi_scaling.sh BIN_DIR SCENE.svo [RANKS] [BAKE OPTIONS...]
#   defaults: RANKS "1 2 4", options "--grid 16,16,16 --res 128 --spp 64" (4,096 probes)
# Environment: RENDER (reference render options; default "--mode pathtrace
#   --size 1920x1080 --spp 16384 --seed 0"; "none" skips it), BAKE=none skips
#   the bake, REPS (runs per rank count, default 1), OUT (folder for the
#   outputs, default a temporary one), MPIRUN_ARGS (more mpirun options, e.g.
#   --mca btl self,vader), VX_MPI_DEBS (folder of Debian OpenMPI .debs to
#   extract into / first, for a GPU machine without OpenMPI: see
#   docs/PERFORMANCE.md section 9).
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
D=${OUT:-$(mktemp -d)}
mkdir -p "$D"
if [ -n "${VX_MPI_DEBS:-}" ]; then
  for f in "$VX_MPI_DEBS"/*.deb; do dpkg -x "$f" /; done
  ldconfig
fi
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
MPIRUN=${MPIRUN:-mpirun}
[ -x /usr/bin/mpirun ] && MPIRUN=/usr/bin/mpirun
echo "host: $(hostname), $(nproc) CPUs; $(nvidia-smi -L 2>/dev/null | wc -l) NVIDIA GPUs"
nvidia-smi -L 2>/dev/null | head -8
echo "mpirun: $(command -v "$MPIRUN") ($("$MPIRUN" --version 2>&1 | head -1))"
echo "scene: $SCENE; bake options: $OPTS; $REPS run(s) per rank count"
now() { date +%s.%N; }
median() { sort -n | awk '{ v[NR] = $1 } END { if (NR % 2) print v[(NR + 1) / 2]; else print (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
# scale TOOL OUTEXT ARGS...: one process, then mpirun -n N for every N
scale() {
  tool=$1 ext=$2
  shift 2
  t=$(now)
  "$BIN/$tool" "$SCENE" "$D/one.$ext" "$@" >"$D/one.out" 2>&1 || { cat "$D/one.out"; echo "single $tool failed"; exit 1; }
  T0=$(awk -v a="$(now)" -v b="$t" "BEGIN{print a-b}")
  grep -E "device|baked|render:" "$D/one.out"
  printf "| run | wall s (each run) | median s | efficiency T1/(N TN) | output |\n| --- | --- | ---: | ---: | --- |\n" > "$D/table.md"
  printf "| one process | %.2f | | | |\n" "$T0" >> "$D/table.md"
  T1=""
  for n in $RANKS; do
    runs="" same="identical" r=0
    : >"$D/times"
    while [ $r -lt "$REPS" ]; do
      t=$(now)
      "$MPIRUN" --oversubscribe --bind-to none ${MPIRUN_ARGS:-} -n "$n" "$BIN/$tool" "$SCENE" "$D/n$n.$ext" "$@" -v >"$D/n$n.out" 2>&1 ||
        { tail -20 "$D/n$n.out"; echo "mpirun -n $n $tool failed"; exit 1; }
      TN=$(awk -v a="$(now)" -v b="$t" "BEGIN{printf \"%.2f\", a-b}")
      echo "$TN" >>"$D/times"
      runs="$runs${runs:+, }$TN"
      cmp -s "$D/one.$ext" "$D/n$n.$ext" || same="differs"
      echo "== $tool mpirun -n $n, run $((r + 1)): $TN s"
      grep -E "^rank|^baked|^output|^rendered|render:" "$D/n$n.out" | head -20
      rm -f "$D/n$n.$ext"
      r=$((r + 1))
    done
    TM=$(median <"$D/times")
    [ -z "$T1" ] && T1=$TM
    E=$(awk -v a="$T1" -v n="$n" -v b="$TM" "BEGIN{printf \"%.3f\", a/(n*b)}")
    printf "| mpirun -n %s | %s | %.2f | %s | %s |\n" "$n" "$runs" "$TM" "$E" "$same" >> "$D/table.md"
  done
  echo "$tool $*"
  cat "$D/table.md"
  rm -f "$D/one.$ext"
}
if [ "${RENDER:-}" != none ]; then
  # shellcheck disable=SC2086
  scale svo_render pfm ${RENDER:---mode pathtrace --size 1920x1080 --spp 16384 --seed 0}
fi
[ "${BAKE:-}" = none ] && exit 0
# shellcheck disable=SC2086
scale svo_bake probes $OPTS
