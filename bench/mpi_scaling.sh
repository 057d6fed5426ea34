#!/bin/sh
# MPI scaling of the probe bake (issues 22 and 23): one process, then
# mpirun -n N for each N in RANKS, the same seed; every output must equal the
# single-process file byte for byte; prints wall time, parallel efficiency
# T1 / (N x TN) and svo_bake's per-rank summary (-v: bake, waiting, messages).
# On a host with G GPUs rank r uses GPU r mod G (issue 23: one rank per GPU);
# on the lent one-GPU machines the ranks share it (issue 22).
#
# Usage: bench/mpi_scaling.sh BIN_DIR SCENE.svo [RANKS] [BAKE OPTIONS...]
#   defaults: RANKS "1 2 4", options "--grid 16,16,16 --res 128 --spp 64" (4,096 probes)
# Environment: OUT (folder for the outputs, default a temporary one), MPIRUN_ARGS
#   (more mpirun options, e.g. --mca btl self,vader),
#   VX_MPI_DEBS (folder of Debian OpenMPI .debs to extract into / first, for a
#   GPU machine without OpenMPI: see docs/PERFORMANCE.md section 9).
#
# The GPU machines have no Vulkan loader: extract the loader debs first as in
# ../shared/guide/GPU.md (for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig;
# export VK_DRIVER_FILES=...), and carry a svo_bake built with
# -DVX_WITH_OIIO=OFF (it needs only libvulkan, libz and OpenMPI).
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
  E=$(awk -v a="$T1" -v n="$n" -v b="$TN" "BEGIN{print a/(n*b)}")
  printf "| mpirun -n %s | %.2f | %.2f | %s |\n" "$n" "$TN" "$E" "$same" >> "$D/table.md"
  grep -E "^rank|baked" "$D/n$n.out"
  rm -f "$D/n$n.probes"
done
cat "$D/table.md"
