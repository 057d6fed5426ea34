#!/bin/sh
# tests/render/test_passes_tool.sh BIN_DIR - svo_render's and svo_view's pass
# options on lavapipe: usage errors name the pass, -v prints a row per pass,
# --timings writes one row per frame and pass, --show writes intermediates
# (float ones only as EXR), the default list equals --mode color byte for
# byte, and svo_view's 'passes' script command gives svo_render's image.
set -u
BIN=$1
. "$(dirname "$0")/../common/expect.sh"
R="$BIN/svo_render"
"$BIN/vox2svo" --write-demo "$T/demo.vox" >/dev/null && "$BIN/vox2svo" "$T/demo.vox" "$T/demo.svo" >/dev/null ||
    { echo "cannot make the demo scene"; exit 1; }
if ! "$R" "$T/demo.svo" "$T/probe.png" --size 8x8 >/dev/null 2>&1; then
    echo "skipped: no Vulkan device"
    exit 0
fi
S="--size 96x64"
expect_status 2 "unknown pass" "$R" "$T/demo.svo" "$T/x.png" --passes gbuffer,bloom
grep -q "'bloom'" "$T/err" && ok "the error names the pass" || bad "the error names the pass"
expect_status 2 "misplaced pass" "$R" "$T/demo.svo" "$T/x.png" --passes direct,gbuffer
grep -q "'direct'" "$T/err" && ok "misplaced: the error names the pass" || bad "misplaced: the error names the pass"
expect_status 2 "gi without a method" "$R" "$T/demo.svo" "$T/x.png" --passes gbuffer,gi
expect_status 2 "gi=probes without probes" "$R" "$T/demo.svo" "$T/x.png" --passes gbuffer,gi=probes
expect_status 2 "float intermediate to PNG" "$R" "$T/demo.svo" "$T/x.png" --show depth
expect_status 2 "--passes with --cpu" "$R" "$T/demo.svo" "$T/x.png" --cpu --passes gbuffer
[ ! -e "$T/x.png" ] && ok "usage errors write nothing" || bad "usage errors write nothing"
expect_status 0 "default list" "$R" "$T/demo.svo" "$T/a.png" $S
expect_status 0 "mode color, separate passes" "$R" "$T/demo.svo" "$T/b.png" $S --separate-passes
cmp -s "$T/a.png" "$T/b.png" && ok "merged and separate passes: same bytes" || bad "merged and separate passes: same bytes"
expect_status 0 "every pass, -v, timings" "$R" "$T/demo.svo" "$T/c.png" $S --spp 2 -v --frames 2 \
    --passes gbuffer,dof,direct,ao,aa,tonemap --separate-passes --timings "$T/t.csv"
for p in gbuffer direct ao resolve aa tonemap; do
    grep -q "^$p " "$T/out" && ok "-v row $p" || bad "-v row $p"
    n=$(grep -c ",$p," "$T/t.csv")
    [ "$n" = 2 ] && ok "timings: 2 frames of $p" || bad "timings: $n rows of $p, wanted 2"
done
[ "$(grep -c ',frame,' "$T/t.csv")" = 2 ] && ok "timings: a frame row per frame" || bad "timings: frame rows"
for s in albedo ao direct instance; do
    expect_status 0 "--show $s" "$R" "$T/demo.svo" "$T/s-$s.png" $S --passes gbuffer,direct,ao --show $s
done
for s in depth normal material; do
    expect_status 0 "--show $s (EXR)" "$R" "$T/demo.svo" "$T/s-$s.exr" $S --show $s
done
expect_status 0 "point and spot lights" "$R" "$T/demo.svo" "$T/l.png" $S --light point:0,0,40:900,800,700 \
    --light spot:10,10,40:0,0,-1:0,0,3000:10,25 --sky 0.05,0.05,0.08 --passes gbuffer,direct,ao,tonemap
for m in brute tiled clustered; do
    expect_status 0 "--light-culling $m" "$R" "$T/demo.svo" "$T/lc-$m.png" $S --light point:0,0,40:900,800,700 \
        --light spot:10,10,40:0,0,-1:0,0,3000:10,25 --sky 0.05,0.05,0.08 --light-culling $m --shadow-lights 0 -v
    grep -q -- "--light-culling $m --shadow-lights 0" "$T/out" && ok "-v prints --light-culling $m" ||
        bad "-v prints --light-culling $m"
done
cmp -s "$T/lc-brute.png" "$T/lc-clustered.png" && ok "clustered culling: brute force's bytes" ||
    bad "clustered culling: brute force's bytes"
expect_status 2 "bad light culling" "$R" "$T/demo.svo" "$T/x.png" --light-culling fast
expect_status 2 "too many shadow lights" "$R" "$T/demo.svo" "$T/x.png" --shadow-lights 17
expect_status 2 "malformed light" "$R" "$T/demo.svo" "$T/x.png" --light point:1,2
expect_status 2 "negative light" "$R" "$T/demo.svo" "$T/x.png" --light point:0,0,0:-1,1,1
grep -q "light 0" "$T/err" && ok "the error names the light" || bad "the error names the light"
expect_status 2 "--sky without lights" "$R" "$T/demo.svo" "$T/x.png" --sky 1,1,1
# --sky SPEC: malformed specs name the syntax; an even gradient is the constant sky (misses and the
# direct pass's sky term: the same bytes); an uneven one changes the image; a missing map is named
LP="--light point:0,0,40:900,800,700"
expect_status 2 "malformed --sky" "$R" "$T/demo.svo" "$T/x.png" $LP --sky gradient:1,1,1
grep -q "gradient:ZR" "$T/err" && ok "a bad --sky names the syntax" || bad "a bad --sky names the syntax"
expect_status 2 "negative --sky" "$R" "$T/demo.svo" "$T/x.png" $LP --sky -1,0,0
expect_status 0 "--sky constant" "$R" "$T/demo.svo" "$T/s1.png" $S $LP --sky 0.2,0.3,0.4
expect_status 0 "--sky even gradient" "$R" "$T/demo.svo" "$T/s2.png" $S $LP --sky gradient:0.2,0.3,0.4:0.2,0.3,0.4:0.2,0.3,0.4
cmp -s "$T/s1.png" "$T/s2.png" && ok "an even gradient is the constant sky" || bad "an even gradient is the constant sky"
expect_status 0 "--sky gradient" "$R" "$T/demo.svo" "$T/s3.png" $S $LP --sky gradient:0.9,0.3,0.1:0.2,0.3,0.4:0,0,0
cmp -s "$T/s1.png" "$T/s3.png" && bad "a gradient changes the image" || ok "a gradient changes the image"
expect_status 0 "--sky gradient, gi=cones" "$R" "$T/demo.svo" "$T/s4.png" --size 32x24 --passes gbuffer,direct,gi=cones \
    --sky gradient:0.9,0.3,0.1:0.2,0.3,0.4:0,0,0
expect_status 1 "--sky map missing" "$R" "$T/demo.svo" "$T/x.png" $S $LP --sky "map:$T/none.exr"
grep -q "none.exr" "$T/err" && ok "a missing sky map is named" || bad "a missing sky map is named"
expect_status 0 "lights with gi=pathtrace" "$R" "$T/demo.svo" "$T/lgi.exr" --size 32x24 \
    --light point:0,0,40:900,800,700 --light spot:10,10,40:0,0,-1:0,0,3000:10,25 --sky 0.05,0.05,0.08 \
    --passes gbuffer,direct,gi=pathtrace,tonemap
expect_status 0 "gi=pathtrace" "$R" "$T/demo.svo" "$T/gi.exr" --size 32x24 --passes gbuffer,direct,gi=pathtrace,tonemap
# --mode pathtrace renders --light lights (here the CPU's, the same option path as the GPU's): it was
# refused with "--passes, --show and --timings need the GPU colour mode", as if --passes were given
expect_status 0 "--mode pathtrace with --light" "$R" "$T/demo.svo" "$T/ptl.pfm" --size 16x12 --cpu --mode pathtrace $LP
expect_status 0 "--mode pathtrace without" "$R" "$T/demo.svo" "$T/pt0.pfm" --size 16x12 --cpu --mode pathtrace
cmp -s "$T/ptl.pfm" "$T/pt0.pfm" && bad "--light lights the path tracer's image" || ok "--light lights the path tracer's image"
# the probe methods take no lights: the error says so (it said the method lacked the frame's lights)
if [ -x "$BIN/svo_bake" ]; then
    expect_status 0 "a small bake" "$BIN/svo_bake" "$T/demo.svo" "$T/p.probes" --grid 2,2,2 --res 16 --spp 1
    expect_status 1 "gi=probes with lights" "$R" "$T/demo.svo" "$T/x.png" --probes "$T/p.probes" \
        --passes gbuffer,direct,gi=probes $LP
    grep -q "gi=probes takes no lights" "$T/err" && ok "gi=probes with lights: the error says why" ||
        bad "gi=probes with lights: the error says why"
fi
if [ -x "$BIN/svo_view" ] && command -v xvfb-run >/dev/null 2>&1; then
    printf 'passes gbuffer,direct,ao,aa,tonemap\nscreenshot %s\nquit\n' "$T/v.png" >"$T/script.txt"
    expect_status 0 "svo_view passes script" xvfb-run -a "$BIN/svo_view" "$T/demo.svo" --script "$T/script.txt" \
        --hidden --size 96x64
    expect_status 0 "svo_render same passes" "$R" "$T/demo.svo" "$T/r.png" $S --passes gbuffer,direct,ao,aa,tonemap
    cmp -s "$T/v.png" "$T/r.png" && ok "svo_view's frame equals svo_render's" || bad "svo_view's frame equals svo_render's"
else
    echo "svo_view or xvfb-run missing: viewer checks skipped"
fi
echo "$pass passed, $fail failed"
[ "$fail" = 0 ]
