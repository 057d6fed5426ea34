#!/bin/sh
# The consumer test (ctest consumer_install): installs this build into a
# temporary prefix, then builds tests/consumer/consumer.c against that prefix
# twice, through find_package(voxkit) (app/CMakeLists.txt) and through
# pkg-config, and runs both builds on a corpus .vox (and .glb, .vdb), or on a
# .vox the consumer writes itself when the corpus is absent.
# Usage: run.sh BUILD_DIR WORK_DIR CC CMAKE GENERATOR CORPUS_DIR [SANITIZE_FLAGS]
set -eu
BUILD=$1 WORK=$2 CC=$3 CMAKE=$4 GEN=$5 CORPUS=${VX_CORPUS_DIR:-$6} SAN=${7:-}
HERE=$(cd "$(dirname "$0")" && pwd)
rm -rf "$WORK"
mkdir -p "$WORK/out"
PREFIX=$WORK/prefix

"$CMAKE" --install "$BUILD" --prefix "$PREFIX" >"$WORK/install.log"
LIB=$(ls -d "$PREFIX"/lib*/libvoxkit.so "$PREFIX"/lib/*/libvoxkit.so 2>/dev/null | head -n 1)
[ -n "$LIB" ] || { echo "no libvoxkit.so under $PREFIX"; exit 1; }
LIBDIR=$(dirname "$LIB")
SONAME=$(readelf -d "$LIB" | sed -n 's/.*SONAME.*\[\(.*\)\].*/\1/p')
echo "installed $LIB (soname $SONAME)"
[ -e "$LIBDIR/$SONAME" ] || { echo "no $LIBDIR/$SONAME"; exit 1; }

set -- -
VOX=$CORPUS/vox/ogt_test_multiple_model_scene.vox GLB=$CORPUS/gltf/tinygltf_box01.glb
VDB=$CORPUS/vdb/mjurczyk_sphere.vdb
if [ -f "$VOX" ]; then set -- "$VOX"; else echo "corpus $VOX not found: the consumer writes its own .vox"; fi
if [ -f "$GLB" ]; then set -- "$@" "$GLB"; else set -- "$@" -; fi
if [ -f "$VDB" ]; then set -- "$@" "$VDB"; fi

# Runs a consumer binary; it must load libvoxkit from the prefix.
check() {
  exe=$1
  shift
  loaded=$(ldd "$exe" | sed -n 's/.*libvoxkit[^ ]* => \([^ ]*\).*/\1/p')
  case $loaded in
    "$LIBDIR"/*) ;;
    *) echo "$exe loads libvoxkit from '$loaded', not from $LIBDIR"; exit 1 ;;
  esac
  "$exe" "$WORK/out" "$@"
}

echo "== find_package(voxkit)"
"$CMAKE" -S "$HERE/app" -B "$WORK/cmake-build" -G "$GEN" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_C_COMPILER="$CC" -DCMAKE_PREFIX_PATH="$PREFIX" ${SAN:+"-DCMAKE_C_FLAGS=$SAN" "-DCMAKE_EXE_LINKER_FLAGS=$SAN"} \
  >"$WORK/cmake-configure.log" || { cat "$WORK/cmake-configure.log"; exit 1; }
"$CMAKE" --build "$WORK/cmake-build" >"$WORK/cmake-build.log" || { cat "$WORK/cmake-build.log"; exit 1; }
check "$WORK/cmake-build/consumer" "$@"

echo "== pkg-config voxkit"
export PKG_CONFIG_PATH="$LIBDIR/pkgconfig"
pkg-config --exists --print-errors voxkit
echo "pkg-config: voxkit $(pkg-config --modversion voxkit): $(pkg-config --cflags --libs voxkit)"
# shellcheck disable=SC2046
"$CC" -std=c17 -Wall -Wextra -Werror $SAN -o "$WORK/consumer-pc" "$HERE/consumer.c" \
  $(pkg-config --cflags voxkit) $(pkg-config --libs voxkit) -Wl,-rpath,"$(pkg-config --variable=libdir voxkit)"
check "$WORK/consumer-pc" "$@"
echo "consumer: both builds passed"
