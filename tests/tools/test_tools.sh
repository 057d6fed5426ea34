#!/bin/sh
# tests/tools/test_tools.sh BIN_DIR CORPUS_DIR - the command-line contract of
# vox2svo and svo_info: help and usage errors, exit codes, the demo scene,
# dump/export round trips, and bad input leaving no output behind.
set -u
BIN=$1
CORPUS=$2
. "$(dirname "$0")/../common/expect.sh"
# svo_render: the Vulkan driver (lavapipe) leaves its own allocations at
# exit, which LeakSanitizer cannot attribute: no leak check for the renderer
# here (ours is test_passes'); vox2svo and svo_info keep theirs
svo_render() { env ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0" "$BIN/svo_render" "$@"; }

expect_status 0 "vox2svo --help" "$BIN/vox2svo" --help
grep -q "^Usage:" "$T/out" && grep -q "^Options:" "$T/out" && grep -q "^Examples:" "$T/out" && ok "help sections" || bad "help sections"
grep -q "default: 256" "$T/out" && ok "help shows defaults" || bad "help shows defaults"
grep -q -- "--keep-unused" "$T/out" && ok "help lists --keep-unused" || bad "help lists --keep-unused"
expect_status 2 "vox2svo without arguments" "$BIN/vox2svo"
expect_status 2 "vox2svo unknown option" "$BIN/vox2svo" a.vox b.svo --bogus
grep -q "not a valid option" "$T/err" && ok "unknown option message" || bad "unknown option message"
expect_status 2 "vox2svo missing argument" "$BIN/vox2svo" a.vox b.svo --frame
expect_status 0 "svo_info --help" "$BIN/svo_info" --help
expect_status 2 "svo_info without arguments" "$BIN/svo_info"
expect_status 1 "vox2svo missing input" "$BIN/vox2svo" "$T/none.vox" "$T/none.svo"
grep -q "none.vox" "$T/err" && ok "error names the file" || bad "error names the file"
[ ! -e "$T/none.svo" ] && ok "no output on failure" || bad "no output on failure"

# the demo scene: write, convert, verify, dump, export and convert again
expect_status 0 "write demo" "$BIN/vox2svo" --write-demo "$T/demo.vox"
expect_status 0 "convert demo" "$BIN/vox2svo" "$T/demo.vox" "$T/demo.svo"
grep -q "descriptors  plain" "$T/out" && grep -q "bytes/voxel" "$T/out" && ok "statistics printed" || bad "statistics printed"
cp "$T/out" "$T/out.demo"
expect_status 0 "svo_info demo" "$BIN/svo_info" "$T/demo.svo"
grep -q "^model 0" "$T/out" && grep -q "^sections" "$T/out" && ok "svo_info lists sections and models" || bad "svo_info lists sections and models"
grep -q "3 materials" "$T/out" && ok "demo has lamp, glass and metal materials" || bad "demo has lamp, glass and metal materials"
# the materials as read (the demo's MATL: _glass with _trans 0.9, _rough 0.05, _ior 0.5 = index 1.5)
grep -q "^material 14   glass, roughness 0.05, ior 1.5, transmission 0.9$" "$T/out" &&
    grep -q "^material 15   metal, roughness 0.2, metalness 1, specular 0.5$" "$T/out" &&
    grep -q "^material 12   emit, emission 3.2 of the voxels' colour$" "$T/out" &&
    ok "svo_info lists the materials" || bad "svo_info lists the materials"
nl=$(sed -n 's/^lights       0 stored, \([0-9]*\) from the voxels of 1 emissive materials.*/\1/p' "$T/out")
[ "${nl:-0}" -ge 5 ] && ok "demo lamps: $nl lights from emissive voxels" || bad "demo lamps: ${nl:-no} lights from emissive voxels"
expect_status 0 "verify demo" "$BIN/svo_info" "$T/demo.svo" --verify
# --max-memory: too small a budget is an error naming the cap, with no output;
# a large one changes nothing
expect_status 1 "vox2svo --max-memory 64K" "$BIN/vox2svo" "$T/demo.vox" "$T/small.svo" --max-memory 64K
grep -q -- "needs more than --max-memory 64.0 KiB" "$T/err" && ok "vox2svo names the cap" || bad "vox2svo names the cap"
[ ! -e "$T/small.svo" ] && ok "no output over the cap" || bad "no output over the cap"
expect_status 0 "vox2svo --max-memory 1G" "$BIN/vox2svo" "$T/demo.vox" "$T/big.svo" --max-memory 1G
cmp -s "$T/demo.svo" "$T/big.svo" && ok "a budget does not change the file" || bad "a budget does not change the file"
# --chunked and --chunked-fast are accepted; the demo's models lie far below the
# chunked form's 2^20 words, so both keep the compact form's bytes (the chunks
# themselves, deflated and fast: test_svo_io's test_chunked_large)
expect_status 0 "vox2svo --chunked" "$BIN/vox2svo" "$T/demo.vox" "$T/ch.svo" --chunked -q
expect_status 0 "vox2svo --chunked-fast" "$BIN/vox2svo" "$T/demo.vox" "$T/chf.svo" --chunked-fast -q
cmp -s "$T/demo.svo" "$T/ch.svo" && cmp -s "$T/demo.svo" "$T/chf.svo" && ok "small models stay in the compact form" ||
  bad "small models stay in the compact form"
expect_status 1 "svo_info --max-memory 4K" "$BIN/svo_info" "$T/demo.svo" --max-memory 4K
grep -q -- "needs more than --max-memory 4.0 KiB" "$T/err" && grep -q "demo.svo" "$T/err" && ok "svo_info names the cap and file" || bad "svo_info names the cap and file"
expect_status 0 "svo_info --max-memory 1G" "$BIN/svo_info" "$T/demo.svo" --max-memory 1G --verify
expect_status 2 "bad --max-memory" "$BIN/vox2svo" "$T/demo.vox" "$T/x.svo" --max-memory 12X
expect_status 2 "zero --max-memory" "$BIN/svo_info" "$T/demo.svo" --max-memory 0
"$BIN/svo_info" "$T/demo.svo" --dump | sort >"$T/d1" || bad "dump"
n=$(wc -l <"$T/d1")
[ "$n" -gt 1000 ] && ok "dump has $n cells" || bad "dump has $n cells"
expect_status 0 "export to vox" "$BIN/svo_info" "$T/demo.svo" --to-vox "$T/demo2.vox"
expect_status 0 "convert export" "$BIN/vox2svo" "$T/demo2.vox" "$T/demo2.svo"
"$BIN/svo_info" "$T/demo2.svo" --dump | sort >"$T/d2"
cmp -s "$T/d1" "$T/d2" && ok "dump(svo) == dump(svo -> vox -> svo)" || bad "dump(svo) == dump(svo -> vox -> svo)"
"$BIN/vox2svo" "$T/demo.vox" "$T/plain.svo" --no-collapse --no-dag -q
"$BIN/svo_info" "$T/plain.svo" --dump | sort >"$T/d3"
cmp -s "$T/d1" "$T/d3" && ok "minimization does not change the voxels" || bad "minimization does not change the voxels"
s1=$(wc -c <"$T/demo.svo"); s3=$(wc -c <"$T/plain.svo")
[ "$s1" -lt "$s3" ] && ok "minimized file smaller ($s1 < $s3 bytes)" || bad "minimized file smaller ($s1 vs $s3)"
# the crate model is placed only on the hidden layer: left out by default,
# kept with --keep-unused (same voxels, a larger file), placed with --keep-hidden
grep -q "models       6, instances 22, unused models left out 1" "$T/out.demo" && ok "statistics count the unused model" ||
    bad "statistics count the unused model: $(grep models "$T/out.demo")"
expect_status 0 "convert --keep-unused" "$BIN/vox2svo" "$T/demo.vox" "$T/keep.svo" --keep-unused
grep -q "models       7, instances 22, unused models kept 1" "$T/out" && ok "--keep-unused keeps it" ||
    bad "--keep-unused keeps it: $(grep models "$T/out")"
"$BIN/svo_info" "$T/keep.svo" --dump | sort >"$T/d5"
cmp -s "$T/d1" "$T/d5" && ok "--keep-unused does not change the voxels" || bad "--keep-unused does not change the voxels"
s5=$(wc -c <"$T/keep.svo")
[ "$s1" -lt "$s5" ] && ok "unused model left out: $s1 < $s5 bytes" || bad "unused model left out: $s1 vs $s5 bytes"
"$BIN/vox2svo" "$T/demo.vox" "$T/hid.svo" --keep-hidden -q
"$BIN/svo_info" "$T/hid.svo" --dump --all | sort >"$T/d4"
[ "$(wc -l <"$T/d4")" -gt "$n" ] && ok "--keep-hidden keeps the hidden layer" || bad "--keep-hidden keeps the hidden layer"

# an animation (the demo over 24 frames): every frame by default, each frame
# of the all-frames file dumps like the same frame converted alone (--frame)
expect_status 0 "write animated demo" "$BIN/vox2svo" --write-demo "$T/anim.vox" --demo-frames 24
expect_status 0 "convert animation" "$BIN/vox2svo" "$T/anim.vox" "$T/anim.svo"
grep -q "instances [0-9]*, frames 24" "$T/out" && ok "vox2svo counts the frames" || bad "vox2svo counts the frames: $(grep models "$T/out")"
expect_status 0 "svo_info animation" "$BIN/svo_info" "$T/anim.svo"
grep -q "^frames       24" "$T/out" && grep -q "^frame 15 .*1 instances changed" "$T/out" && grep -q "8 more frames" "$T/out" &&
    ok "svo_info lists the frames" || bad "svo_info lists the frames"
grep -q "format version 2" "$T/out" && ok "an animation is format version 2" || bad "an animation is format version 2"
grep -q "^frames" "$T/out" && "$BIN/svo_info" "$T/demo.svo" | grep -q "format version 1" &&
    ok "a still scene stays version 1" || bad "a still scene stays version 1"
for f in 0 7 23; do
    "$BIN/vox2svo" "$T/anim.vox" "$T/one.svo" --frame $f -q
    "$BIN/svo_info" "$T/one.svo" --dump | sort >"$T/f1"
    "$BIN/svo_info" "$T/anim.svo" --dump --frame $f | sort >"$T/f2"
    [ -s "$T/f1" ] && cmp -s "$T/f1" "$T/f2" && ok "frame $f == --frame $f" || bad "frame $f == --frame $f"
done
"$BIN/svo_info" "$T/anim.svo" --dump --frame 12 | sort >"$T/f3"
cmp -s "$T/f2" "$T/f3" && bad "frames 23 and 12 differ" || ok "frames 23 and 12 differ"
expect_status 1 "svo_info --frame past the end" "$BIN/svo_info" "$T/anim.svo" --dump --frame 24
grep -q "no frame 24 (the scene has 24)" "$T/err" && ok "names the frame count" || bad "names the frame count"
# --to-vox writes every frame as keyframes; converted again, every frame is the same
expect_status 0 "animation to vox" "$BIN/svo_info" "$T/anim.svo" --to-vox "$T/anim2.vox"
expect_status 0 "convert the exported animation" "$BIN/vox2svo" "$T/anim2.vox" "$T/anim2.svo"
grep -q "frames 24" "$T/out" && ok "the export keeps 24 frames" || bad "the export keeps 24 frames"
same=0
for f in 0 1 6 13 23; do
    "$BIN/svo_info" "$T/anim.svo" --dump --frame $f | sort >"$T/g1"
    "$BIN/svo_info" "$T/anim2.svo" --dump --frame $f | sort >"$T/g2"
    cmp -s "$T/g1" "$T/g2" && same=$((same + 1))
done
[ $same -eq 5 ] && ok "svo -> vox -> svo keeps every frame" || bad "svo -> vox -> svo keeps every frame ($same of 5)"
if [ -x "$BIN/svo_render" ]; then
    # a sequence: one scene upload, frames traced in turn; each image equals
    # the frame rendered alone, and frames differ
    expect_status 0 "svo_render --frames 0..3" svo_render "$T/anim.svo" "$T/seq_##.png" --frames 0..3 --size 48x32 --mode albedo
    [ -s "$T/seq_00.png" ] && [ -s "$T/seq_03.png" ] && [ ! -e "$T/seq_04.png" ] && ok "four images written" || bad "four images written"
    expect_status 0 "svo_render --frame 3" svo_render "$T/anim.svo" "$T/one3.png" --frame 3 --size 48x32 --mode albedo
    cmp -s "$T/seq_03.png" "$T/one3.png" && ok "sequence frame 3 == --frame 3" || bad "sequence frame 3 == --frame 3"
    cmp -s "$T/seq_00.png" "$T/seq_03.png" && bad "frames 0 and 3 differ" || ok "frames 0 and 3 differ"
    # --load models (the default: the compact layout built model by model before the device is made, AUTO's
    # plain layout read whole) against --load whole: the same images, a sequence and a later frame alone
    for lay in compact auto; do
        same=0
        svo_render "$T/anim.svo" "$T/lm_##.png" --frames 0..3 --size 48x32 --mode albedo --layout $lay -v >"$T/out" 2>&1
        svo_render "$T/anim.svo" "$T/lw_##.png" --frames 0..3 --size 48x32 --mode albedo --layout $lay --load whole >/dev/null 2>&1
        for f in 00 01 02 03; do [ -s "$T/lm_$f.png" ] && cmp -s "$T/lm_$f.png" "$T/lw_$f.png" && same=$((same + 1)); done
        svo_render "$T/anim.svo" "$T/lm1.png" --frame 2 --size 48x32 --mode albedo --layout $lay >/dev/null 2>&1
        [ -s "$T/lm1.png" ] && cmp -s "$T/lm1.png" "$T/lm_02.png" && same=$((same + 1))
        [ $same -eq 5 ] && ok "--load models == --load whole ($lay)" || bad "--load models == --load whole ($lay: $same of 5)"
    done
    grep -q "layout is plain: the scene was read whole" "$T/out" && ok "auto's plain layout read whole" ||
        bad "auto's plain layout read whole"
    expect_status 2 "--frames without #" svo_render "$T/anim.svo" "$T/seq.png" --frames 0..3
    expect_status 1 "--frames past the end" svo_render "$T/anim.svo" "$T/s_#.png" --frames 20..24 --size 8x8
    grep -q "no frame 24 (the scene has 24)" "$T/err" && ok "svo_render names the frame count" || bad "svo_render names the frame count"
    # a damaged file and a missing one: svo_render (either load) and svo_bake name the file once, write nothing
    cp "$T/demo.svo" "$T/dmg.svo" && printf '\377\377\377\377' | dd of="$T/dmg.svo" bs=1 seek=200 conv=notrunc 2>/dev/null
    for f in dmg none; do
        for load in models whole; do
            expect_status 1 "svo_render $f.svo --load $load" svo_render "$T/$f.svo" "$T/dmg.png" --size 8x8 --load $load
            [ "$(grep -o "$T/$f.svo" "$T/err" | wc -l)" -eq 1 ] && [ ! -e "$T/dmg.png" ] && ok "svo_render names $f.svo once" ||
                bad "svo_render names $f.svo once: $(cat "$T/err")"
        done
        expect_status 1 "svo_bake $f.svo" "$BIN/svo_bake" "$T/$f.svo" "$T/dmg.probes" --grid 2,2,2 --res 16 --spp 1 -q
        [ "$(grep -o "$T/$f.svo" "$T/err" | wc -l)" -eq 1 ] && [ ! -e "$T/dmg.probes" ] && ok "svo_bake names $f.svo once" ||
            bad "svo_bake names $f.svo once: $(cat "$T/err")"
    done
    # the scene's GPU layout (issue 18): -v states it; auto under a budget
    # below the plain layout's bytes takes the compact one, which gives the
    # plain layout's image; passes need the plain one
    expect_status 0 "svo_render --layout plain" svo_render "$T/demo.svo" "$T/lay_p.pfm" --layout plain --grid off --mode albedo --size 48x32 -v
    grep -q "^layout: plain, .* asked for" "$T/out" && ok "-v states the plain layout" || bad "-v states the plain layout"
    expect_status 0 "svo_render --gpu-budget 1K" svo_render "$T/demo.svo" "$T/lay_c.pfm" --gpu-budget 1K --mode albedo --size 48x32 -v
    # (with its brick dictionary where that is smaller: render.h compact_bricks)
    grep -Eq "^layout: compact( \(brick dictionary\))?, .* auto: budget" "$T/out" &&
        ok "auto takes the compact layout under a small budget" ||
        bad "auto takes the compact layout under a small budget"
    cmp -s "$T/lay_p.pfm" "$T/lay_c.pfm" && ok "compact and plain layouts give the same image" ||
        bad "compact and plain layouts give the same image"
    # the grid walk (issue 21, render/grid.h; on by default on every device, lavapipe too): -v states it and
    # the image is the octree walk's (lay_p: --grid off)
    expect_status 0 "svo_render default (grids)" svo_render "$T/demo.svo" "$T/lay_gr.pfm" --layout plain --mode albedo --size 48x32 -v
    grep -Eq "^grid walk: [1-9][0-9]* models with a grid" "$T/out" && ok "-v states the grids (the default on a CPU device)" ||
        bad "-v states the grids (the default on a CPU device): $(cat "$T/out")"
    cmp -s "$T/lay_p.pfm" "$T/lay_gr.pfm" && ok "grid and octree walks give the same image" ||
        bad "grid and octree walks give the same image"
    expect_status 0 "svo_render --grid 16M" svo_render "$T/demo.svo" "$T/lay_g16.pfm" --layout plain --grid 16M --mode albedo --size 48x32 -v
    cmp -s "$T/lay_gr.pfm" "$T/lay_g16.pfm" && ok "--grid 16M: the default's image" || bad "--grid 16M: the default's image"
    expect_status 2 "svo_render --grid 12" svo_render "$T/demo.svo" "$T/lay_x.pfm" --grid 12
    expect_status 0 "svo_render default layout" svo_render "$T/demo.svo" "$T/lay_a.pfm" --mode albedo --size 48x32 -v
    grep -q "^layout: plain, .* auto: budget" "$T/out" && ok "auto keeps the plain layout where it fits" ||
        bad "auto keeps the plain layout where it fits"
    # the passes read the whole compact layout (issue 18): the plain layout's image
    expect_status 0 "svo_render --layout compact --passes" svo_render "$T/demo.svo" "$T/lay_xc.pfm" --layout compact --passes gbuffer,direct,ao --size 48x32
    expect_status 0 "svo_render --layout plain --passes" svo_render "$T/demo.svo" "$T/lay_xp.pfm" --layout plain --passes gbuffer,direct,ao --size 48x32
    cmp -s "$T/lay_xc.pfm" "$T/lay_xp.pfm" && ok "passes: compact and plain layouts give the same image" ||
        bad "passes: compact and plain layouts give the same image"
    expect_status 1 "svo_render paged --passes" svo_render "$T/demo.svo" "$T/lay_x.png" --layout compact --gpu-budget 20K --page-level 3 --passes gbuffer,direct --size 8x8
    grep -q "paged compact layout" "$T/err" && ok "passes on a paged scene: the reason" || bad "passes on a paged scene: the reason"
    expect_status 2 "svo_render bad --layout" svo_render "$T/demo.svo" "$T/lay_x.png" --layout dense
    expect_status 2 "svo_render bad --warm-up" svo_render "$T/demo.svo" "$T/lay_x.png" --warm-up -1
    # the compact layout over the budget too: paged, the pages that do not fit drawn coarse, and said
    expect_status 0 "svo_render paged" svo_render "$T/demo.svo" "$T/lay_g.pfm" --layout compact --gpu-budget 20K --page-level 3 --mode albedo --size 48x32 -v
    grep -q "^paging: level 3, [0-9]* pages; after [0-9]* frames [0-9]* resident .* [1-9][0-9]* drawn coarse ([0-9]* refused, .* over the budget)" "$T/out" &&
        ok "-v states the paging and the coarse pages" || bad "-v states the paging and the coarse pages"
    expect_status 0 "svo_render paged, not verbose" svo_render "$T/demo.svo" "$T/lay_g.pfm" --layout compact --gpu-budget 20K --page-level 3 --mode albedo --size 48x32
    # paged from the layout built model by model (the default --load models) and from the scene read whole
    svo_render "$T/demo.svo" "$T/lay_gw.pfm" --layout compact --gpu-budget 20K --page-level 3 --mode albedo --size 48x32 --load whole >/dev/null 2>&1
    [ -s "$T/lay_g.pfm" ] && cmp -s "$T/lay_g.pfm" "$T/lay_gw.pfm" && ok "paged: --load models == --load whole" ||
        bad "paged: --load models == --load whole"
    grep -q "^note: [1-9][0-9]* pages drawn coarse" "$T/out" && ok "coarse pages noted" || bad "coarse pages noted"
    # paging from the file (--host-budget: a host cache of 2 KB, pages cut again from their models): the
    # in-memory pager's image under the same budget, the cache's counts, a fly-through after the image
    expect_status 0 "svo_render --host-budget" svo_render "$T/demo.svo" "$T/lay_gf.pfm" --layout compact --gpu-budget 20K \
        --page-level 3 --host-budget 2K --mode albedo --size 48x32 -v --fly 3
    [ -s "$T/lay_gf.pfm" ] && cmp -s "$T/lay_g.pfm" "$T/lay_gf.pfm" && ok "paged from the file == paged in memory" ||
        bad "paged from the file == paged in memory"
    grep -q "^paging from the file: host cache .* of 0.002 MB .*; [1-9][0-9]* pages cut from the file ([1-9][0-9]* model reads)" "$T/out" &&
        ok "-v states the host cache" || bad "-v states the host cache"
    grep -q "^fly-through: 3 frames, median .* ms a frame" "$T/out" && ok "--fly times its frames" || bad "--fly times its frames"
    expect_status 2 "svo_render --host-budget with --load whole" svo_render "$T/demo.svo" "$T/lay_x.png" --load whole --host-budget 1M
    expect_status 2 "svo_render bad --host-budget" svo_render "$T/demo.svo" "$T/lay_x.png" --host-budget 0
    expect_status 2 "svo_render --fly with passes" svo_render "$T/demo.svo" "$T/lay_x.png" --passes gbuffer,direct --fly 2
    # a misspelt gi method is named as unknown (listing the methods), not asked for a probe file
    expect_status 2 "svo_render unknown gi method" svo_render "$T/demo.svo" "$T/lay_x.png" --passes gbuffer,direct,gi=cone
    grep -q "unknown gi method 'cone' (probes, lightfield, pathtrace, photons, cones)" "$T/err" && ok "unknown gi method named" || bad "unknown gi method named"
    expect_status 2 "svo_render gi=lightfield without probes" svo_render "$T/demo.svo" "$T/lay_x.png" --passes gbuffer,direct,gi=lightfield
    grep -q "gi=lightfield needs --probes FILE (bake them: svo_bake $T/demo.svo OUT.probes)" "$T/err" &&
        ok "probe method asks for probes, with the bake's command" || bad "probe method asks for probes, with the bake's command"
    expect_status 2 "svo_render bad --page-level" svo_render "$T/demo.svo" "$T/lay_x.png" --page-level 2
    # a storage buffer range below the plain words (the helmet at 32768^3 on a 4 GB range, issue 18):
    # auto takes the compact layout, its attributes (about 20 KB) in two buffers, the plain image
    expect_status 0 "svo_render --buffer-range 16K" svo_render "$T/demo.svo" "$T/lay_r.pfm" --buffer-range 16K --mode albedo --size 48x32 -v
    grep -q "^layout: compact, .* auto: budget" "$T/out" && grep -q "^note: the compact attributes are in 2 storage buffers" "$T/out" &&
        ok "-v states the attributes' buffers" || bad "-v states the attributes' buffers"
    cmp -s "$T/lay_p.pfm" "$T/lay_r.pfm" && ok "attributes in two buffers: the plain layout's image" ||
        bad "attributes in two buffers: the plain layout's image"
    expect_status 1 "svo_render --buffer-range --passes" svo_render "$T/demo.svo" "$T/lay_x.png" --buffer-range 16K --passes gbuffer,direct --size 8x8
    grep -q "in 2 storage buffers" "$T/err" && ok "passes on attributes in parts: the reason" || bad "passes on attributes in parts: the reason"
    expect_status 1 "svo_render --buffer-range below the geometry" svo_render "$T/demo.svo" "$T/lay_x.png" --buffer-range 1K --size 8x8
    grep -q "geometry bytes exceed" "$T/err" && ok "geometry past the range: the reason" || bad "geometry past the range: the reason"
    expect_status 2 "svo_render bad --buffer-range" svo_render "$T/demo.svo" "$T/lay_x.png" --buffer-range 8
fi

# a VDB sequence named by a pattern or a list (the corpus sphere as 3 frames):
# one animation, each frame as converted alone, the repeats stored once
SPH="$CORPUS/vdb/mjurczyk_sphere.vdb"
SMK="$CORPUS/vdb/mjurczyk_smoke.vdb"
if [ -f "$SPH" ] && [ -f "$SMK" ] && "$BIN/vox2svo" "$SPH" "$T/sph.svo" -q 2>/dev/null; then
    SPH="$(cd "$(dirname "$SPH")" && pwd)/mjurczyk_sphere.vdb" # links from another folder
    SMK="$(cd "$(dirname "$SMK")" && pwd)/mjurczyk_smoke.vdb"
    mkdir -p "$T/seq"
    ln -s "$SPH" "$T/seq/s_0000.vdb"
    ln -s "$SPH" "$T/seq/s_0001.vdb"
    ln -s "$SPH" "$T/seq/s_0002.vdb"
    ln -s "$SMK" "$T/seq/s_01.vdb" # not 4 digits: not part of s_####.vdb
    for pat in 's_####.vdb' 's_%04d.vdb' 'list.txt'; do
        printf 's_0000.vdb\n\ns_0001.vdb\n# a comment\ns_0002.vdb\n' >"$T/seq/list.txt"
        expect_status 0 "vox2svo $pat" "$BIN/vox2svo" "$T/seq/$pat" "$T/seq.svo"
        grep -q "frames 3" "$T/out" && ok "$pat: 3 frames" || bad "$pat: 3 frames: $(grep models "$T/out")"
        n=0
        for f in 0 1 2; do
            "$BIN/svo_info" "$T/sph.svo" --dump | sort >"$T/v1"
            "$BIN/svo_info" "$T/seq.svo" --dump --frame $f | sort >"$T/v2"
            [ -s "$T/v1" ] && cmp -s "$T/v1" "$T/v2" && n=$((n + 1))
        done
        [ $n -eq 3 ] && ok "$pat: every frame as converted alone" || bad "$pat: every frame as converted alone ($n of 3)"
    done
    m3=$(sed -n 's/^  models *\([0-9]*\),.*/\1/p' "$T/out")
    printf 's_0000.vdb\n' >"$T/seq/one.txt"
    "$BIN/vox2svo" "$T/seq/one.txt" "$T/seq1.svo" >"$T/out1"
    m1=$(sed -n 's/^  models *\([0-9]*\),.*/\1/p' "$T/out1")
    [ -n "$m3" ] && [ "$m3" = "$m1" ] && ok "repeated frames add no model ($m3)" || bad "repeated frames add no model ($m3 vs $m1)"
    printf 's_0000.vdb\ns_01.vdb\n' >"$T/seq/mixed.txt"
    expect_status 1 "frames with other transforms" "$BIN/vox2svo" "$T/seq/mixed.txt" "$T/x.svo"
    grep -q "frame 1 (.*s_01.vdb): its grid transform differs from frame 0's" "$T/err" && ok "names the frame and file" ||
        bad "names the frame and file"
    expect_status 1 "no file matches" "$BIN/vox2svo" "$T/seq/none_###.vdb" "$T/x.svo"
    grep -q "none_###.vdb: no file matches" "$T/err" && ok "names the pattern" || bad "names the pattern"
fi

# bad input: truncated .vox, corrupted .svo; clear error, exit 1, no output
head -c 2000 "$T/demo.vox" >"$T/trunc.vox"
expect_status 1 "truncated .vox" "$BIN/vox2svo" "$T/trunc.vox" "$T/trunc.svo"
[ ! -e "$T/trunc.svo" ] && ! ls "$T"/trunc.svo.tmp* >/dev/null 2>&1 && ok "no output or temp file left" || bad "no output or temp file left"
grep -q "trunc.vox" "$T/err" && ok "error names the input" || bad "error names the input"
cp "$T/demo.svo" "$T/corrupt.svo"
size=$(wc -c <"$T/corrupt.svo")
printf '\377\377\377\377' | dd of="$T/corrupt.svo" bs=1 seek=$((size / 2)) conv=notrunc 2>/dev/null
expect_status 1 "corrupted .svo fails --verify" "$BIN/svo_info" "$T/corrupt.svo" --verify
head -c $((size - 3)) "$T/demo.svo" >"$T/short.svo"
expect_status 1 "truncated .svo fails" "$BIN/svo_info" "$T/short.svo"
printf 'not a voxel file at all' >"$T/junk.vox"
expect_status 1 "junk .vox" "$BIN/vox2svo" "$T/junk.vox" "$T/junk.svo"
expect_status 1 "unknown extension" "$BIN/vox2svo" "$T/demo.svo" "$T/x.svo"

# lights and sky (LGHT): svo_info lists them; svo_render uses them by default
LIT="$(dirname "$0")/../fuzz/svo_seeds/seed4.svo"
expect_status 0 "svo_info lights" "$BIN/svo_info" "$LIT"
grep -q "^lights       5 stored" "$T/out" && grep -q "^light 2 .*spot at (-0 5 6)" "$T/out" &&
    grep -q "^sky          gradient zenith 0.2 0.4 1" "$T/out" && ok "svo_info prints lights and sky" || bad "svo_info prints lights and sky"
grep -q "LGHT" "$T/out" && grep -q "format version 2" "$T/out" && ok "a file with lights is version 2" || bad "a file with lights is version 2"
if [ -x "$BIN/svo_render" ]; then
    expect_status 0 "svo_render --help" svo_render --help
    grep -q -- "--no-scene-lights" "$T/out" && grep -q "sphere:X,Y,Z:R,G,B:RADIUS" "$T/out" && grep -q "rect:X,Y,Z:NX,NY,NZ" "$T/out" &&
        ok "svo_render --help documents the lights" || bad "svo_render --help documents the lights"
    expect_status 2 "svo_render bad --light" svo_render "$LIT" "$T/l.png" --light sphere:1,2,3:1,1,1
    grep -q "sphere:X,Y,Z:R,G,B:RADIUS" "$T/err" && ok "bad --light names the syntax" || bad "bad --light names the syntax"
    expect_status 2 "svo_render negative --light" svo_render "$LIT" "$T/l.png" --light point:1,2,3:1,1,1:-1
    grep -q "light 0" "$T/err" && ok "a bad light is named" || bad "a bad light is named"
    svo_render "$LIT" "$T/l.png" -v --size 32x32 >"$T/out" 2>"$T/err"
    grep -q "lights: 5 from the file, 0 from emissive voxels, 0 from --light" "$T/out" && ok "svo_render uses the file's lights" ||
        bad "svo_render uses the file's lights"
    svo_render "$LIT" "$T/l.png" -v --size 32x32 --no-scene-lights --light point:1,2,3:1,1,1 >"$T/out" 2>"$T/err"
    grep -q "lights: 0 from the file, 0 from emissive voxels, 1 from --light" "$T/out" && ok "--no-scene-lights drops them" ||
        bad "--no-scene-lights drops them"
fi

# glTF KHR_lights_punctual through vox2svo: stored, counted, listed by svo_info
cat >"$T/lamp.gltf" <<'EOF'
{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0,1]}],
 "nodes":[{"mesh":0},{"translation":[0.5,0.5,2],"extensions":{"KHR_lights_punctual":{"light":0}}}],
 "extensions":{"KHR_lights_punctual":{"lights":[{"type":"point","name":"bulb","intensity":40,"color":[1,0.8,0.6]}]}},
 "meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],
 "buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}],
 "bufferViews":[{"buffer":0,"byteLength":36}],
 "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}]}
EOF
expect_status 0 "vox2svo glTF with a light" "$BIN/vox2svo" "$T/lamp.gltf" "$T/lamp.svo" --res 8
grep -q "lights       1 stored, 0 from emissive voxels" "$T/out" && ok "vox2svo counts the lights" || bad "vox2svo counts the lights"
expect_status 0 "svo_info glTF light" "$BIN/svo_info" "$T/lamp.svo"
# (0.5, 0.5, 2) in glTF's +Y-up frame is (0.5, -2, 0.5) in voxkit's +Z-up one
grep -q "^light 0      point at (0.5 -2 0.5), colour 1 0.8 0.6 x 40" "$T/out" && ok "the light keeps its node's place" ||
    bad "the light keeps its node's place"
sed 's/"intensity":40/"intensity":-40/' "$T/lamp.gltf" >"$T/bad.gltf"
expect_status 1 "vox2svo negative light" "$BIN/vox2svo" "$T/bad.gltf" "$T/bad.svo"
grep -q "light 0 ('bulb') on node 1: negative" "$T/err" && [ ! -e "$T/bad.svo" ] && ok "a bad light is an error naming it" ||
    bad "a bad light is an error naming it"

# a model over 256 cells a side (the triangle at --res 300: one 300x1x300 model) was refused by
# --to-vox ("model 0 is 300x1x300: .vox models are at most 256 cells per side"); it is now split
# into 256^3 tiles, the three holding cells one .vox model each (the fourth, empty, left out),
# under one group; converted back, the same cells
expect_status 0 "vox2svo glTF at --res 300" "$BIN/vox2svo" "$T/lamp.gltf" "$T/big.svo" --res 300 -q
"$BIN/svo_info" "$T/big.svo" | grep -q "^model 0      300x1x300" && ok "one model of 300x1x300" || bad "one model of 300x1x300"
expect_status 0 "--to-vox of a model over 256" "$BIN/svo_info" "$T/big.svo" --to-vox "$T/big.vox"
expect_status 0 "convert the split export" "$BIN/vox2svo" "$T/big.vox" "$T/big2.svo"
grep -q "models       3, instances 3" "$T/out" && ok "three pieces" || bad "three pieces: $(grep models "$T/out")"
"$BIN/svo_info" "$T/big.svo" --dump | sort >"$T/b1"
"$BIN/svo_info" "$T/big2.svo" --dump | sort >"$T/b2"
[ "$(wc -l <"$T/b1")" -gt 40000 ] && cmp -s "$T/b1" "$T/b2" && ok "dump(svo) == dump(split vox -> svo)" ||
    bad "dump(svo) == dump(split vox -> svo)"

# more than 255 colours (a triangle whose corners are red, green and blue: its cells interpolate
# them): --to-vox refuses, naming the count and --quantize; --quantize maps them to a 255-entry
# palette with a warning (count, largest and mean error), the same cells, the same bytes each run
cat >"$T/rgb.gltf" <<'EOF'
{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
 "meshes":[{"primitives":[{"attributes":{"POSITION":0,"COLOR_0":1}}]}],
 "buffers":[{"byteLength":72,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAAAAAAAAAAAAIA/"}],
 "bufferViews":[{"buffer":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":36}],
 "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},
              {"bufferView":1,"componentType":5126,"count":3,"type":"VEC3"}]}
EOF
expect_status 0 "vox2svo a vertex-coloured triangle" "$BIN/vox2svo" "$T/rgb.gltf" "$T/rgb.svo" --res 64 -q
nc=$("$BIN/svo_info" "$T/rgb.svo" --dump | awk '{print $4, $5, $6, $7}' | sort -u | wc -l)
[ "$nc" -gt 255 ] && ok "$nc colours" || bad "$nc colours, expected more than 255"
expect_status 1 "--to-vox of $nc colours" "$BIN/svo_info" "$T/rgb.svo" --to-vox "$T/rgb.vox" -q
grep -q "the scene has $nc distinct colours, a .vox palette holds 255; .*--quantize" "$T/err" && [ ! -e "$T/rgb.vox" ] &&
    ok "refused, naming the count and --quantize" || bad "refused, naming the count and --quantize: $(cat "$T/err")"
expect_status 2 "--quantize without --to-vox" "$BIN/svo_info" "$T/rgb.svo" --quantize
expect_status 0 "--to-vox --quantize" "$BIN/svo_info" "$T/rgb.svo" --to-vox "$T/rgb.vox" --quantize -q
grep -q "warning: .*rgb.vox: $nc distinct colours quantized to a 255-entry palette: .* max [0-9.]*, mean [0-9.]*" "$T/err" &&
    ok "a warning with the count and the errors" || bad "a warning with the count and the errors: $(cat "$T/err")"
expect_status 0 "--to-vox --quantize again" "$BIN/svo_info" "$T/rgb.svo" --to-vox "$T/rgb2.vox" --quantize -q
cmp -s "$T/rgb.vox" "$T/rgb2.vox" && ok "quantized: the same bytes each run" || bad "quantized: the same bytes each run"
"$BIN/vox2svo" "$T/rgb.vox" "$T/rgb2.svo" -q
"$BIN/svo_info" "$T/rgb.svo" --dump | cut -d' ' -f1-3 | sort >"$T/q1"
"$BIN/svo_info" "$T/rgb2.svo" --dump | cut -d' ' -f1-3 | sort >"$T/q2"
nq=$("$BIN/svo_info" "$T/rgb2.svo" --dump | awk '{print $4, $5, $6, $7}' | sort -u | wc -l)
[ -s "$T/q1" ] && cmp -s "$T/q1" "$T/q2" && [ "$nq" -le 255 ] && ok "the same cells in $nq colours" ||
    bad "the same cells in $nq colours"

# vox2svo --sky stores a sky; svo_info shows it; --to-glb keeps it in the scene's
# extras and vox2svo reads it back; a map's path given from the current folder
# is stored from the output's, and still names the same file after the round trip
# through another folder (stop 74); a bad spec is a usage error with no output
mkdir -p "$T/skya" "$T/skyb"
expect_status 0 "vox2svo --sky gradient" "$BIN/vox2svo" "$T/demo.vox" "$T/skya/g.svo" -q \
    --sky gradient:0.2,0.4,0.9:0.8,0.85,0.9:0.1,0.08,0.05
expect_status 0 "svo_info shows the sky" "$BIN/svo_info" "$T/skya/g.svo"
grep -q "^sky          gradient zenith 0.2 0.4 0.9, horizon 0.8 0.85 0.9, ground 0.1 0.08 0.05$" "$T/out" &&
    ok "the stored sky" || bad "the stored sky"
expect_status 0 "gradient sky to .glb" "$BIN/svo_info" "$T/skya/g.svo" --to-glb "$T/skyb/g.glb"
grep -q '"voxkit_sky"' "$T/skyb/g.glb" && ok ".glb holds voxkit_sky" || bad ".glb holds voxkit_sky"
expect_status 0 "the .glb back" "$BIN/vox2svo" "$T/skyb/g.glb" "$T/skyb/g2.svo" --res 32 -q
"$BIN/svo_info" "$T/skyb/g2.svo" | grep -q "^sky          gradient zenith 0.2 0.4 0.9, horizon 0.8 0.85 0.9, ground 0.1 0.08 0.05$" &&
    ok "the sky after the round trip" || bad "the sky after the round trip"
(cd "$T" && "$BIN/vox2svo" demo.vox skya/m.svo -q --sky map:env/sky.exr:2:90) && ok "vox2svo --sky map" ||
    bad "vox2svo --sky map"
"$BIN/svo_info" "$T/skya/m.svo" | grep -q '^sky          environment map "../env/sky.exr" x 2, turned 90 deg about +z$' &&
    ok "the map's path from the output's folder" || bad "the map's path from the output's folder"
expect_status 0 "map sky to .glb" "$BIN/svo_info" "$T/skya/m.svo" --to-glb "$T/skyb/m.glb"
expect_status 0 "map .glb back" "$BIN/vox2svo" "$T/skyb/m.glb" "$T/m2.svo" --res 32 -q
"$BIN/svo_info" "$T/m2.svo" | grep -q '^sky          environment map "env/sky.exr" x 2, turned 90 deg about +z$' &&
    ok "the map's path after the round trip" || bad "the map's path after the round trip"
# --sky default drops the input's sky (the .glb above holds one); svo_render still refuses it (the option left out says it)
expect_status 0 "vox2svo --sky default" "$BIN/vox2svo" "$T/skyb/g.glb" "$T/skyb/nosky.svo" --res 32 -q --sky default
"$BIN/svo_info" "$T/skyb/nosky.svo" | grep -q "^sky          default (the renderer's)$" && ok "--sky default drops the sky" ||
    bad "--sky default drops the sky"
expect_status 2 "svo_render --sky default" "$BIN/svo_render" "$T/skyb/nosky.svo" "$T/skyb/nosky.ppm" --sky default
expect_status 2 "vox2svo bad --sky" "$BIN/vox2svo" "$T/demo.vox" "$T/badsky.svo" --sky gradient:1,2
grep -q "bad --sky 'gradient:1,2'" "$T/err" && [ ! -e "$T/badsky.svo" ] && ok "bad --sky named, no output" ||
    bad "bad --sky named, no output"

# a corpus scene with instancing, when the corpus is there
if [ -f "$CORPUS/vox/ogt_test_multiple_model_scene.vox" ]; then
    expect_status 0 "convert corpus scene" "$BIN/vox2svo" "$CORPUS/vox/ogt_test_multiple_model_scene.vox" "$T/m.svo"
    expect_status 0 "verify corpus scene" "$BIN/svo_info" "$T/m.svo" --verify
else
    echo "[ skip ] corpus scene: $CORPUS not found"
fi
echo "$pass passed, $fail failed"
[ "$fail" = 0 ]
