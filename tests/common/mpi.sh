# tests/common/mpi.sh - sourced by the tests that start tools under mpirun
# (test_svo_bake_mpi.sh, test_svo_render_mpi.sh) after setting BIN and
# MPIRUN: skips (77) without a launcher that can start processes here, makes
# $T (removed at exit), defines fail() and run N CMD... (mpirun -n N CMD...).
command -v "$MPIRUN" >/dev/null 2>&1 || { echo "SKIP: no $MPIRUN (install openmpi-bin)"; exit 77; }
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
# OpenMPI refuses root without these, and more ranks than cores without --oversubscribe
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
MPIFLAGS=""
"$MPIRUN" --version 2>/dev/null | grep -qi "open mpi\|openrte" && MPIFLAGS="--oversubscribe"
run() { n=$1; shift; "$MPIRUN" $MPIFLAGS -n "$n" "$@"; }
# a launcher that cannot start processes here (no usable network set-up in a
# container, say) is the environment's problem, not the tool's
run 2 true >"$T/launch.out" 2>&1 || { cat "$T/launch.out"; echo "SKIP: $MPIRUN cannot start 2 processes here"; exit 77; }
