#!/bin/sh
# Runs every libFuzzer target for SECONDS seconds each (default 60), seeded
# with the corpus. Builds them with clang in build-fuzz. Any crash fails.
set -eu
cd "$(dirname "$0")/.."
SECONDS_EACH=${1:-60}
CORPUS=${VX_CORPUS_DIR:-../shared/corpus}
# Libraries get coverage instrumentation (fuzzer-no-link) so libFuzzer sees
# inside them; only the fuzz targets link the libFuzzer main.
F="-fsanitize=fuzzer-no-link,address,undefined"
CC=clang CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DVX_FUZZ=ON \
    -DCMAKE_C_FLAGS="$F" -DCMAKE_CXX_FLAGS="$F" \
    -DVX_WITH_VULKAN=OFF -DVX_WITH_OPENVDB=OFF -DVX_WITH_OIIO=OFF >/dev/null
targets=""
for t in vox_fuzz svo_fuzz gltf_fuzz; do
    if cmake --build build-fuzz --target "$t" -j"$(nproc)" >/dev/null 2>&1; then targets="$targets $t"; fi
done
for t in $targets; do
    mkdir -p "build-fuzz/work-$t"
    seeds=""
    case $t in
        vox_fuzz) seeds="$CORPUS/vox" ;;
        svo_fuzz) seeds="tests/fuzz/svo_seeds" ;;
        gltf_fuzz) seeds="$CORPUS/gltf" ;;
    esac
    dict=""
    [ -f "tests/fuzz/${t%_fuzz}.dict" ] && dict="-dict=tests/fuzz/${t%_fuzz}.dict"
    echo "fuzz: $t for ${SECONDS_EACH}s"
    [ -d "$seeds" ] || seeds=""
    # shellcheck disable=SC2086
    if ! "build-fuzz/bin/$t" -max_total_time="$SECONDS_EACH" -rss_limit_mb=4096 -max_len=1048576 $dict \
        "build-fuzz/work-$t" $seeds >"build-fuzz/$t.log" 2>&1; then
        tail -n 40 "build-fuzz/$t.log"
        echo "fuzz: $t found a failure (input saved in the current folder as crash-*)"
        exit 1
    fi
    tail -n 2 "build-fuzz/$t.log"
done
