#!/bin/bash
# Whole-process times of svo_render where the start-up dominates (issue 21's lavapipe rows are the tracer's; this
# is what a user waits for around it): --help (the dynamic loading before main), the default colour frame of a
# small scene (the frame's pipelines: lavapipe compiles each), and gi=photons (the photon steps' pipelines).
# Usage: bench/startup.sh NEW_SVO_RENDER [BASE_SVO_RENDER] [RUNS]   (BASE: a binary of another commit, run
# alternately with NEW, so both see the same machine; RUNS per command, default 5). Prints the median wall
# seconds and peak resident memory of each, and NEW / BASE. Scene: eph_teapot from the corpus (../shared/corpus or
# $VX_CORPUS_DIR), converted with NEW's vox2svo.
set -eu
NEW=$1 BASE=${2:-} RUNS=${3:-5}
CORPUS=${VX_CORPUS_DIR:-$(cd "$(dirname "$0")/.." && pwd)/../shared/corpus}
W=$(mktemp -d)
trap 'rm -rf "$W"' EXIT
"$(dirname "$NEW")/vox2svo" "$CORPUS/vox/eph_teapot.vox" "$W/t.svo" >/dev/null
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'); device: $("$NEW" --list-devices 2>/dev/null | head -n 1)"
# median of a list of numbers on stdin
median() { sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}'; }
run() { # BIN LABEL ARGS...: one run, "wall KB" appended to $W/LABEL
  local bin=$1 label=$2
  shift 2
  /usr/bin/time -f "%e %M" -o "$W/one" "$bin" "$@" >/dev/null 2>&1 || true
  cat "$W/one" >>"$W/$label"
}
for c in help frame photons; do
  case $c in
    help) args=(--help) ;;
    frame) args=("$W/t.svo" "$W/o.png") ;;
    photons) args=("$W/t.svo" "$W/o.png" --passes gbuffer,direct,gi=photons) ;;
  esac
  for i in $(seq "$RUNS"); do
    run "$NEW" "new_$c" "${args[@]}"
    [ -n "$BASE" ] && run "$BASE" "base_$c" "${args[@]}"
  done
  n=$(cut -d' ' -f1 "$W/new_$c" | median) nm=$(cut -d' ' -f2 "$W/new_$c" | median)
  if [ -n "$BASE" ]; then
    b=$(cut -d' ' -f1 "$W/base_$c" | median) bm=$(cut -d' ' -f2 "$W/base_$c" | median)
    awk -v c="$c" -v n="$n" -v b="$b" -v nm="$nm" -v bm="$bm" 'BEGIN {printf "%-8s new %7.3f s %7.1f MiB   base %7.3f s %7.1f MiB   new/base %.3f\n", c, n, nm / 1024, b, bm / 1024, (b > 0 ? n / b : 0)}'
  else
    awk -v c="$c" -v n="$n" -v nm="$nm" 'BEGIN {printf "%-8s %7.3f s %7.1f MiB\n", c, n, nm / 1024}'
  fi
done
