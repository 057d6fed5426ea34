#!/bin/sh
# Command (1) of the README: install the Debian packages, build voxkit and run
# the main job on the built-in demo scene (generate it, convert it with
# vox2svo, print the statistics, verify the file and render a picture).
set -eu
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
BUILD=${BUILD:-build}
cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=Release
cmake --build "$BUILD" -j"$(nproc)"
mkdir -p "$BUILD/demo"
"$BUILD/bin/vox2svo" --write-demo "$BUILD/demo/island.vox"
"$BUILD/bin/vox2svo" "$BUILD/demo/island.vox" "$BUILD/demo/island.svo"
"$BUILD/bin/svo_info" "$BUILD/demo/island.svo" --verify
if [ -x "$BUILD/bin/svo_render" ]; then
    # the GPU path where Vulkan works (lavapipe counts), the CPU reference otherwise
    "$BUILD/bin/svo_render" "$BUILD/demo/island.svo" "$BUILD/demo/island.png" --size 640x360 ||
        "$BUILD/bin/svo_render" "$BUILD/demo/island.svo" "$BUILD/demo/island.png" --size 640x360 --cpu
    echo "demo: rendered $BUILD/demo/island.png"
    # the pass pipeline: ambient occlusion and anti-aliasing, with each pass's GPU time
    if "$BUILD/bin/svo_render" "$BUILD/demo/island.svo" "$BUILD/demo/island-passes.png" --size 640x360 \
        --passes gbuffer,direct,ao,aa --ao-rays 8 -v; then
        echo "demo: rendered $BUILD/demo/island-passes.png (passes gbuffer,direct,ao,aa)"
    fi
    # the path tracer, the reference: the lamps' emissive voxels light the
    # island at dusk, the greenhouse is glass, the statue metal
    if "$BUILD/bin/svo_render" "$BUILD/demo/island.svo" "$BUILD/demo/island-pathtrace.png" --size 640x360 \
        --mode pathtrace --spp 32; then
        echo "demo: rendered $BUILD/demo/island-pathtrace.png (path tracer: lamps, glass, metal)"
    fi
fi
