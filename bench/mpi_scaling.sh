#!/bin/sh
# MPI scaling of the probe bake and of the path-traced reference render
# (issues 22 and 23): one process, then mpirun -n N for each N in RANKS, the
# same seed; every output must equal the single-process file byte for byte;
# prints wall time, parallel efficiency T1 / (N x TN) with T1 the -n 1 run,
# and svo_bake's per-rank summary (-v: bake, waiting, messages).
# On a host with G GPUs rank r uses GPU r mod G (issue 23: one rank per GPU);
# on the lent one-GPU machines the ranks share it (issue 22).
#
# Usage: bench/mpi_scaling.sh BIN_DIR SCENE.svo [RANKS] [BAKE OPTIONS...]
#   defaults: RANKS "1 2 4", options "--grid 16,16,16 --res 128 --spp 64" (4,096 probes)
# Environment: RENDER (reference render options; default "--mode pathtrace
#   --size 1920x1080 --spp 16384 --seed 0"; "none" skips it), BAKE=none skips
#   the bake, OUT (folder for the outputs, default a temporary one), MPIRUN_ARGS
#   (more mpirun options, e.g. --mca btl self,vader),
#   VX_MPI_DEBS (folder of Debian OpenMPI .debs to extract into / first, for a
#   GPU machine without OpenMPI: see docs/PERFORMANCE.md section 9).
#
# The GPU machines have no Vulkan loader: extract the loader debs first as in
# ../shared/guide/GPU.md (for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig;
# export VK_DRIVER_FILES=...), and carry svo_bake and svo_render built with
# -DVX_WITH_OIIO=OFF (they need only libvulkan, libz and OpenMPI; the render
# is written as .pfm, which needs no OpenImageIO).
set -u
BIN=$1
SCENE=$2
RANKS=${3:-"1 2 4"}
[ $# -ge 3 ] && shift 3 || shift $#
OPTS=${*:-"--grid 16,16,16 --res 128 --spp 64"}
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
"$MPIRUN" --version 2>&1 | head -1
echo "scene: $SCENE; options: $OPTS"
now() { date +%s.%N; }
# scale TOOL OUTEXT ARGS...: one process, then mpirun -n N for every N
scale() {
  tool=$1 ext=$2
  shift 2
  t=$(now)
  "$BIN/$tool" "$SCENE" "$D/one.$ext" "$@" >"$D/one.out" 2>&1 || { cat "$D/one.out"; echo "single $tool failed"; exit 1; }
  T0=$(awk -v a="$(now)" -v b="$t" "BEGIN{print a-b}")
  printf "| run | wall s | efficiency T1/(N TN) | output |\n| --- | ---: | ---: | --- |\n" > "$D/table.md"
  printf "| one process | %.2f | | |\n" "$T0" >> "$D/table.md"
  T1=""
  for n in $RANKS; do
    t=$(now)
    "$MPIRUN" --oversubscribe --bind-to none ${MPIRUN_ARGS:-} -n "$n" "$BIN/$tool" "$SCENE" "$D/n$n.$ext" "$@" -v >"$D/n$n.out" 2>&1 ||
      { tail -20 "$D/n$n.out"; echo "mpirun -n $n $tool failed"; exit 1; }
    TN=$(awk -v a="$(now)" -v b="$t" "BEGIN{print a-b}")
    [ -z "$T1" ] && T1=$TN
    same="differs"
    cmp -s "$D/one.$ext" "$D/n$n.$ext" && same="identical"
    E=$(awk -v a="$T1" -v n="$n" -v b="$TN" "BEGIN{print a/(n*b)}")
    printf "| mpirun -n %s | %.2f | %.2f | %s |\n" "$n" "$TN" "$E" "$same" >> "$D/table.md"
    grep -E "^rank|baked|device|render:" "$D/n$n.out" | head -12
    rm -f "$D/n$n.$ext"
  done
  echo "$tool $*"
  cat "$D/table.md"
}
if [ "${RENDER:-}" != none ]; then
  # shellcheck disable=SC2086
  scale svo_render pfm ${RENDER:---mode pathtrace --size 1920x1080 --spp 16384 --seed 0}
fi
[ "${BAKE:-}" = none ] && exit 0
t=$(now)
"$BIN/svo_bake" "$SCENE" "$D/one.probes" $OPTS -q >"$D/one.out" 2>&1 || { cat "$D/one.out"; echo "single bake failed"; exit 1; }
T1=$(awk -v a="$(now)" -v b="$t" "BEGIN{print a-b}")
grep -E "device|baked" "$D/one.out"
printf "| run | wall s | efficiency T1/(N TN) | output |\n| --- | ---: | ---: | --- |\n" > "$D/table.md"
printf "| one process | %.2f | | |\n" "$T1" >> "$D/table.md"
for n in $RANKS; do
  t=$(now)
  "$MPIRUN" --oversubscribe --bind-to none ${MPIRUN_ARGS:-} -n "$n" "$BIN/svo_bake" "$SCENE" "$D/n$n.probes" $OPTS -v >"$D/n$n.out" 2>&1 ||
    { tail -20 "$D/n$n.out"; echo "mpirun -n $n failed"; exit 1; }
  TN=$(awk -v a="$(now)" -v b="$t" "BEGIN{print a-b}")
  same="differs"
  cmp -s "$D/one.probes" "$D/n$n.probes" && same="identical"
  [ -z "${B1:-}" ] && B1=$TN
  E=$(awk -v a="$B1" -v n="$n" -v b="$TN" "BEGIN{print a/(n*b)}")
  printf "| mpirun -n %s | %.2f | %.2f | %s |\n" "$n" "$TN" "$E" "$same" >> "$D/table.md"
  grep -E "^rank|baked" "$D/n$n.out"
  rm -f "$D/n$n.probes"
done
cat "$D/table.md"
