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
# check_timeline FILE N LAUNCH RETURN: the tools' -v timeline lines (issue
# 23, tools/common/mpi.h): one per rank 0..N-1; on each the stamps in the
# order the rank takes them, exec to end, and every stamp between this
# script's clock before mpirun (LAUNCH) and after it (RETURN), both
# `date +%s.%N`; rank 0 also has the reduction and the output after its work.
# exec comes from /proc in 10 ms steps: 0.02 s of slack for it.
check_timeline() {
  awk -v N="$2" -v L="$3" -v R="$4" '
    function bad(m) { print "timeline: " m; err = 1 }
    /^timeline rank [0-9]+:/ {
      r = $3; sub(":", "", r)
      if (r in seen) bad("rank " r " twice"); seen[r] = 1
      delete t
      for (i = 4; i < NF; i += 2) t[$i] = $(i + 1) + 0
      split("exec main mpi_init mpi_ready work done end", k, " ")
      for (i = 1; i <= 7; i++) if (!(k[i] in t)) bad("rank " r ": no " k[i])
      if (t["exec"] > t["main"] + 0.02) bad("rank " r ": exec after main")
      for (i = 3; i <= 7; i++) if (t[k[i]] < t[k[i - 1]]) bad("rank " r ": " k[i] " before " k[i - 1])
      if ("vk_start" in t) {
        if (!(t["main"] <= t["vk_start"] && t["vk_start"] <= t["vk_device"] && t["vk_device"] <= t["vk_ready"] && t["vk_ready"] <= t["work"]))
          bad("rank " r ": the device thread out of order")
      }
      if (r == 0 && !(t["done"] <= t["reduced"] && t["reduced"] <= t["output"] && t["output"] <= t["end"]))
        bad("rank 0: reduction and output out of order")
      for (s in t) if (t[s] < L - 0.02 || t[s] > R + 0.02) bad(sprintf("rank %s: %s %.4f outside %.4f..%.4f", r, s, t[s], L, R))
    }
    END { for (r = 0; r < N; r++) if (!(r in seen)) bad("no line for rank " r); exit err }' "$1"
}
