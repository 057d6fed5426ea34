#!/bin/sh
# Command (2) of the README: build (if needed) and run the whole test suite
# with ctest. Usage: scripts/test.sh [BUILD_DIR] [extra cmake options...]
# VX_SANITIZE=1 builds with ASan + UBSan (Debug).
set -eu
cd "$(dirname "$0")/.."
BUILD=${1:-build}
[ $# -gt 0 ] && shift
TYPE=Release
EXTRA=""
if [ "${VX_SANITIZE:-0}" = 1 ]; then
    # The benchmarks are left out (-DVX_BENCH=OFF): no test runs them under the sanitizers, and the release
    # build of command (2) compiles them; about a tenth of the build (docs/TESTING.md).
    TYPE=Debug; EXTRA="-DVX_SANITIZE=ON -DVX_BENCH=OFF"
    # The Vulkan validation layer checks the API calls, which are the same in
    # both builds: the release run (command (2)) checks them; under ASan the
    # layer's own allocations made the GPU tests 1.5 times slower. VX_VALIDATE=1 keeps it.
    if [ "${VX_VALIDATE:-0}" != 1 ]; then export VK_LOADER_LAYERS_DISABLE=VK_LAYER_KHRONOS_validation; fi
fi
if [ "${CI:-}" = true ]; then EXTRA="$EXTRA -DVX_WERROR=ON"; fi
cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=$TYPE $EXTRA "$@"
cmake --build "$BUILD" -j"$(nproc)"
ctest --test-dir "$BUILD" --output-on-failure -j"$(nproc)"
