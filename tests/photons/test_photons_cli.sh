#!/bin/sh
# tests/photons/test_photons_cli.sh BIN_DIR - issue 13's command line,
# `svo_render --passes ...,gi=photons --photons N --radius R --passes-count K`,
# on a small generated scene (photons_bench's Cornell box with spheres,
# written as .vox by the toolkit's writer): the same bytes as the old
# spelling (--photon-radius, --spp), and each of the new names changes the
# image (a radius or pass count that was ignored would give the same bytes).
# Float .pfm output: no OpenImageIO needed (lavapipe).
set -u
BIN=$1
. "$(dirname "$0")/../common/expect.sh"
# the Vulkan driver's own allocations at exit (see tests/tools/test_tools.sh)
run() { env ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0" "$@"; }

expect_status 0 "svo_render --help" run "$BIN/svo_render" --help
grep -q -- "--radius R .*gi=photons" "$T/out" && grep -q -- "--passes-count K" "$T/out" &&
    grep -q -- "also --photon-radius" "$T/out" && ok "help lists --radius and --passes-count" ||
    bad "help lists --radius and --passes-count"
# the scene: a tiny bench run that writes cornell.vox on the way
expect_status 0 "photons_bench --write" run "$BIN/photons_bench" --write "$T" --size 8x8 --photons 1000 --runs 1 \
    --max-passes 1 --max-spp 1 --ref-spp 1 cornell
expect_status 0 "vox2svo cornell" run "$BIN/vox2svo" "$T/cornell.vox" "$T/c.svo"
R="$BIN/svo_render $T/c.svo"
P="--passes gbuffer,direct,gi=photons --show gi --size 32x24"
# shellcheck disable=SC2086
expect_status 0 "issue's spelling" run $R "$T/new.pfm" $P --photons 5000 --radius 3 --passes-count 3
# shellcheck disable=SC2086
expect_status 0 "old spelling" run $R "$T/old.pfm" $P --photons 5000 --photon-radius 3 --spp 3
cmp -s "$T/new.pfm" "$T/old.pfm" && ok "--radius/--passes-count: the same bytes as --photon-radius/--spp" ||
    bad "--radius/--passes-count: the same bytes as --photon-radius/--spp"
# shellcheck disable=SC2086
expect_status 0 "--radius 6" run $R "$T/r6.pfm" $P --photons 5000 --radius 6 --passes-count 3
# shellcheck disable=SC2086
expect_status 0 "--passes-count 1" run $R "$T/k1.pfm" $P --photons 5000 --radius 3 --passes-count 1
! cmp -s "$T/r6.pfm" "$T/new.pfm" && ok "--radius changes the image" || bad "--radius changes the image"
! cmp -s "$T/k1.pfm" "$T/new.pfm" && ok "--passes-count changes the image" || bad "--passes-count changes the image"
# shellcheck disable=SC2086
expect_status 2 "--radius -1" run $R "$T/x.pfm" $P --radius -1
grep -q -- "--radius" "$T/err" && ok "the error names --radius" || bad "the error names --radius"
# shellcheck disable=SC2086
expect_status 2 "--passes-count 0" run $R "$T/x.pfm" $P --passes-count 0
grep -q -- "--passes-count" "$T/err" && ok "the error names --passes-count" || bad "the error names --passes-count"
[ ! -e "$T/x.pfm" ] && ok "usage errors write nothing" || bad "usage errors write nothing"
echo "$pass passed, $fail failed"
[ "$fail" = 0 ]
