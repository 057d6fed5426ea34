#!/bin/sh
# tests/photons/test_photons_tool.sh BIN_DIR CORPUS_DIR - svo_render's
# gi=photons: --help lists it with its defaults, bad --photons,
# --photon-radius and --final-gather are usage errors, and the Cornell box
# renders with it, also with a final gather
# (lavapipe: a few thousand photons) with the gi pass timed; what the
# images hold is test_photons' matter.
set -u
BIN=$1
CORPUS=$2
. "$(dirname "$0")/../common/expect.sh"
# the Vulkan driver's own allocations at exit (see tests/tools/test_tools.sh)
svo_render() { env ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0" "$BIN/svo_render" "$@"; }

expect_status 0 "svo_render --help" svo_render --help
grep -q "gi=photons" "$T/out" && grep -q -- "--photons N .*default: 1048576" "$T/out" && ok "help lists gi=photons" ||
    bad "help lists gi=photons"
if [ -f "$CORPUS/gltf/rtxgi_cornell.glb" ]; then
    expect_status 0 "vox2svo cornell" "$BIN/vox2svo" "$CORPUS/gltf/rtxgi_cornell.glb" "$T/c.svo" --res 64
    expect_status 2 "--photons 0" svo_render "$T/c.svo" "$T/x.png" --passes gbuffer,direct,gi=photons --photons 0
    expect_status 2 "--photon-radius -1" svo_render "$T/c.svo" "$T/x.png" --passes gbuffer,direct,gi=photons \
        --photon-radius -1
    expect_status 2 "--final-gather 2000" svo_render "$T/c.svo" "$T/x.png" --passes gbuffer,direct,gi=photons \
        --final-gather 2000
    [ ! -e "$T/x.png" ] && ok "usage errors write nothing" || bad "usage errors write nothing"
    expect_status 0 "gi=photons" svo_render "$T/c.svo" "$T/gi.exr" --passes gbuffer,direct,gi=photons --show gi \
        --photons 20000 --spp 2 --size 64x48
    expect_status 0 "gi=photons --final-gather 2" svo_render "$T/c.svo" "$T/fg.png" --passes gbuffer,direct,gi=photons \
        --photons 20000 --final-gather 2 --size 32x24
    expect_status 0 "gi=photons -v" svo_render "$T/c.svo" "$T/c.png" --passes gbuffer,direct,gi=photons,tonemap \
        --photons 20000 --size 64x48 -v
    grep -q "^gi " "$T/out" && ok "gi pass timed" || bad "gi pass timed"
else
    echo "[ skip ] corpus scene: $CORPUS not found"
fi
echo "$pass passed, $fail failed"
[ "$fail" = 0 ]
