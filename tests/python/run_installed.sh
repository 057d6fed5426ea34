#!/bin/sh
# ctest python_installed: installs the build into a temporary prefix and runs
# test_voxkit.py with the documented PYTHONPATH, against the installed tools.
# Usage: run_installed.sh BUILD_DIR WORK_DIR CMAKE PYTHON CORPUS_DIR
set -eu
BUILD=$1 WORK=$2 CMAKE=$3 PYTHON=$4 CORPUS=${VX_CORPUS_DIR:-$5}
HERE=$(cd "$(dirname "$0")" && pwd)
rm -rf "$WORK"
PREFIX=$WORK/prefix
"$CMAKE" --install "$BUILD" --prefix "$PREFIX" >"$WORK.install.log"
SITE=$("$PYTHON" -c 'import sys; print("lib/python%d.%d/dist-packages" % sys.version_info[:2])')
[ -d "$PREFIX/$SITE" ] || { echo "no $PREFIX/$SITE"; exit 1; }
cd "$WORK"
PYTHONPATH=$PREFIX/$SITE "$PYTHON" "$HERE/test_voxkit.py" "$PREFIX/bin" "$CORPUS" "$WORK/run" "$PREFIX"
