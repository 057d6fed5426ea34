#!/bin/sh
# tests/cones/test_cones_tool.sh BIN_DIR - svo_render's gi=cones (issue 12):
# the options and their defaults in --help, usage errors, a frame of the
# demo island with cones (and with a point light injected), the cone AO.
set -u
BIN=$1
. "$(dirname "$0")/../common/expect.sh"
# lavapipe leaves its own allocations at exit (see tests/tools/test_tools.sh)
svo_render() { env ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0" "$BIN/svo_render" "$@"; }

expect_status 0 "svo_render --help" svo_render --help
grep -q -- "--cone-res R .*(default: 128)" "$T/out" && grep -q -- "--cones N .*(default: 6; at most 32)" "$T/out" &&
    ok "help lists the cone options with their defaults" || bad "help lists the cone options with their defaults"
expect_status 0 "write demo" "$BIN/vox2svo" --write-demo "$T/demo.vox"
expect_status 0 "convert demo" "$BIN/vox2svo" "$T/demo.vox" "$T/demo.svo"
for bad_opt in "--cone-res 1" "--cone-res 513" "--cones 0" "--cones 33" "--cone-aperture 90" "--cone-bounces 9" \
    "--cone-sun-angle 30" "--cone-sun-angle x"; do
    # shellcheck disable=SC2086 # the option and its value split on purpose
    expect_status 2 "usage error: $bad_opt" svo_render "$T/demo.svo" "$T/x.png" --passes gbuffer,direct,gi=cones $bad_opt
done
[ ! -e "$T/x.png" ] && ok "no output after usage errors" || bad "no output after usage errors"
expect_status 0 "gi=cones (no probes needed)" svo_render "$T/demo.svo" "$T/cones.png" --size 48x32 \
    --passes gbuffer,direct,gi=cones,tonemap --cone-res 24 -v
grep -q "^cones: .* voxels with geometry" "$T/out" && grep -q "^gi " "$T/out" && [ -s "$T/cones.png" ] &&
    ok "cone volume and gi pass reported, image written" || bad "cone volume and gi pass reported, image written"
expect_status 0 "gi=cones with a point light, isotropic, 2 bounces" svo_render "$T/demo.svo" "$T/light.png" \
    --size 32x24 --passes gbuffer,direct,gi=cones --cone-res 16 --cone-isotropic --cone-bounces 2 \
    --light point:40,40,20:1,0.8,0.6:0:1
expect_status 0 "cone AO as the gi image" svo_render "$T/demo.svo" "$T/ao.png" --size 32x24 \
    --passes gbuffer,direct,gi=cones --show gi --cone-ao --cone-res 16 --cones 3 --cone-aperture 40
[ -s "$T/ao.png" ] && ok "AO image written" || bad "AO image written"
expect_status 0 "gi=cones at half resolution with cone shadows (direct dropped from the list)" svo_render "$T/demo.svo" \
    "$T/soft.png" --size 32x24 --passes gbuffer,direct,gi=cones --cone-res 16 --cone-half --cone-shadows \
    --cone-sun-angle 5 --timings "$T/soft.csv"
grep -q "gi" "$T/soft.csv" && ! grep -q "direct" "$T/soft.csv" && [ -s "$T/soft.png" ] &&
    ok "no direct pass timed, image written" || bad "no direct pass timed, image written"
echo "$pass passed, $fail failed"
[ "$fail" = 0 ]
