#!/bin/sh
# Mesh voxelization: surface error and conversion time against --res for
# DamagedHelmet, the Duck and the shuttle (see bench/mesh_bench.c), then the
# plot docs/mesh_error.svg (bench/mesh_plot.py).
# Usage: bench/mesh_bench.sh [BUILD_DIR] [RES ...]    (default: build 64 .. 4096)
# Env: CORPUS (default ../shared/corpus/gltf), BIN (default BUILD_DIR/bin/mesh_bench),
#      OUT (default bench/out/mesh.txt), MAXRES_ERROR (skip the error pass above, default 4096)
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
build=${1:-$root/build}
[ $# -gt 0 ] && shift
res=${*:-64 128 256 512 1024 2048 4096}
corpus=${CORPUS:-$root/../shared/corpus/gltf}
bin=${BIN:-$build/bin/mesh_bench}
out=${OUT:-$root/bench/out/mesh.txt}
maxerr=${MAXRES_ERROR:-4096}
mkdir -p "$(dirname "$out")"
echo "# $(date -u +%Y-%m-%dT%H:%M:%SZ) $(nproc) cores" > "$out"
for f in khronos_DamagedHelmet.glb julian_Duck.glb mjurczyk_shuttle.glb; do
  for r in $res; do
    if [ "$r" -gt "$maxerr" ]; then "$bin" "$corpus/$f" "$r" --no-error | grep -v '^#' >> "$out"
    else "$bin" "$corpus/$f" "$r" | grep -v '^#' >> "$out"; fi
    tail -1 "$out"
  done
done
python3 "$here/mesh_plot.py" "$out" "$root/docs/mesh_error.svg"
