#!/bin/sh
# Distributed voxelization (issue 22): mpirun -n N vox2svo MESH OUT.svo --res R
# for each R in RESES, with vox2svo's per-rank lines (-v: regions, voxels,
# read / convert / send seconds, wall, peak memory) and the file's size; first
# one check that the MPI file equals the single-process file at CHECK_RES.
# Each conversion runs under `timeout` with what is left of LIMIT_S seconds,
# so one device command holds the whole bench; a resolution cut short says so.
#
# Usage: bench/vox2svo_mpi.sh BIN_DIR MESH.glb [N] [RESES] [LIMIT_S]
#   defaults: N 8, RESES "8192 16384 32768", LIMIT_S 570
# Environment: OUT (folder for the outputs, default a temporary one; the
#   largest files are removed after measuring), CHECK_RES (default 2048; 0 skips
#   the check), MPIRUN, MPIRUN_ARGS (more mpirun options).
set -u
BIN=$1
MESH=$2
N=${3:-8}
RESES=${4:-"8192 16384 32768"}
LIMIT=${5:-570}
CHECK=${CHECK_RES:-2048}
D=${OUT:-$(mktemp -d)}
mkdir -p "$D"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
MPIRUN=${MPIRUN:-mpirun}
now() { date +%s.%N; }
T0=$(now)
left() { echo "$T0 $LIMIT $(now)" | awk '{ l = $1 + $2 - $3; print (l > 0 ? int(l) : 0) }'; }
echo "host: $(hostname), $(nproc) CPUs, $(awk '/MemTotal/ { printf "%.0f GiB", $2 / 1048576 }' /proc/meminfo); $("$MPIRUN" --version 2>&1 | head -1)"
echo "mesh: $MESH; $N ranks; resolutions: $RESES"
if [ "$CHECK" != 0 ]; then
  t=$(now)
  "$BIN/vox2svo" "$MESH" "$D/one.svo" --res "$CHECK" -q || exit 1
  t1=$(now)
  $MPIRUN ${MPIRUN_ARGS:-} -n "$N" "$BIN/vox2svo" "$MESH" "$D/mpi.svo" --res "$CHECK" -q || exit 1
  t2=$(now)
  if cmp -s "$D/one.svo" "$D/mpi.svo"; then same=identical; else same=DIFFERENT; fi
  echo "check --res $CHECK: one process $(echo "$t $t1" | awk '{ printf "%.1f", $2 - $1 }') s, -n $N $(echo "$t1 $t2" | awk '{ printf "%.1f", $2 - $1 }') s; files $same ($(stat -c %s "$D/one.svo") bytes)"
  rm -f "$D/one.svo" "$D/mpi.svo"
fi
for r in $RESES; do
  l=$(left)
  [ "$l" -gt 10 ] || { echo "--res $r: not run (time limit)"; continue; }
  echo "--res $r (at most $l s):"
  t=$(now)
  timeout "$l" $MPIRUN ${MPIRUN_ARGS:-} -n "$N" "$BIN/vox2svo" "$MESH" "$D/r$r.svo" --res "$r" -v >"$D/r$r.out" 2>&1
  st=$?
  t1=$(now)
  tr '\r' '\n' <"$D/r$r.out" | grep -v '%\|^ *$\|input \|lights ' | tail -n 40 # no progress lines
  echo "--res $r: exit $st, wall $(echo "$t $t1" | awk '{ printf "%.1f", $2 - $1 }') s, file $(stat -c %s "$D/r$r.svo" 2>/dev/null || echo none) bytes"
  rm -f "$D/r$r.svo"
  [ $st = 0 ] || break
done
