#!/bin/sh
# tests/tools/test_tools_cut.sh BIN_DIR CUT_PRELOAD SEEDS_DIR - a .svo cut short,
# at the tools: svo_info, svo_render (the scene read whole, and the model
# reader of --load models, and its pages read from the file again by
# --host-budget) and svo_bake given (a) a truncated copy of a real
# file (every NODE form: the reader fuzz seeds and vox2svo's demo; cut inside
# the header, the section table, the NODE section and before the last byte)
# and (b) a file that shrinks while the tool reads it (CUT_PRELOAD, an
# LD_PRELOAD module: tests/tools/cut_preload.c) and a FIFO. Each must exit 1,
# name the file and what is wrong, and leave no output (image, probes, their
# temporary, partial and checkpoint files) behind; under ASan/UBSan no report.
set -u
BIN=$1
CUT=$2
SEEDS=$3
. "$(dirname "$0")/../common/expect.sh"
# lavapipe leaves allocations LeakSanitizer cannot attribute (test_tools'
# note); the preload comes before the ASan runtime in the link order, which
# ASan accepts with verify_asan_link_order=0 (its interceptors stay in place)
export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0:verify_asan_link_order=0"

# no output of any kind left in $T/o
clean() { # description
    left=$(ls -A "$T/o")
    [ -z "$left" ] && ok "$1: no output left" || bad "$1: left $left"
    rm -rf "$T/o" && mkdir "$T/o"
}
# exit 1, the message names the file and matches PATTERN (grep -E)
fails() { # description pattern file command...
    what=$1 pat=$2 file=$3; shift 3
    expect_status 1 "$what" "$@"
    grep -q "$file" "$T/err" && grep -Eq "$pat" "$T/err" && ok "$what: names $file and '$pat'" ||
        bad "$what: message '$(cat "$T/err")' (wanted $file and '$pat')"
    grep -q "$file: $file" "$T/err" && bad "$what: the file named twice" || true
    grep -Eq "AddressSanitizer|runtime error|LeakSanitizer" "$T/err" && bad "$what: a sanitizer report" || true
    clean "$what"
}
mkdir "$T/o"
# the tools' outputs in $T/o; small and quick (lavapipe on two shared cores);
# $PRE runs them (env with the preload's variables, timeout)
PRE=
info() { $PRE "$BIN/svo_info" "$1" --to-vox "$T/o/x.vox"; }
render_whole() { $PRE "$BIN/svo_render" "$1" "$T/o/x.png" --size 32x24; }                                  # passes: read whole
render_models() { $PRE "$BIN/svo_render" "$1" "$T/o/x.png" --size 32x24 --mode albedo --layout compact; } # the model reader
# paging from the file: pages cut again from their models, read after the first pass (a host cache of 1 KB)
PAGED="--size 32x24 --mode albedo --layout compact --gpu-budget 1M --page-level 3 --host-budget 1K"
render_paged() { $PRE "$BIN/svo_render" "$1" "$T/o/x.png" $PAGED; }
render_paged_again() { $PRE env VX_CUT_AGAIN=1 "$BIN/svo_render" "$1" "$T/o/x.png" $PAGED; }
bake() { $PRE "$BIN/svo_bake" "$1" "$T/o/x.probes" --grid 2,2,2 --res 16 --spp 1; }
section() { # file tag -> "offset size"
    "$BIN/svo_info" "$1" | sed -n "s/^  $2  offset *\([0-9]*\)  size *\([0-9]*\) .*/\1 \2/p"
}

"$BIN/vox2svo" --write-demo "$T/demo.vox" >/dev/null && "$BIN/vox2svo" "$T/demo.vox" "$T/demo.svo" -q ||
    bad "the demo scene"
forms="$T/demo.svo"
for f in coded split split_mixed chunked_zstd chunked_deflate chunked_stored; do forms="$forms $SEEDS/$f.svo"; done

# the intact files pass (the renderer with the preload loaded and no cut asked
# for) and write their outputs: the cuts below are what fails
expect_status 0 "demo.svo: svo_info --to-vox" info "$T/demo.svo"
PRE="env LD_PRELOAD=$CUT"
expect_status 0 "split.svo: svo_render, models, the preload without a cut" render_models "$SEEDS/split.svo"
cp "$T/o/x.png" "$T/models.png"
expect_status 0 "split.svo: svo_render --host-budget, the preload without a cut" render_paged "$SEEDS/split.svo"
cmp -s "$T/o/x.png" "$T/models.png" && ok "split.svo: --host-budget's image is the whole layout's" ||
    bad "split.svo: --host-budget's image differs from the whole layout's"
PRE=
expect_status 0 "split.svo: svo_bake" bake "$SEEDS/split.svo"
[ -s "$T/o/x.png" ] && [ -s "$T/o/x.probes" ] && [ -s "$T/o/x.vox" ] && ok "outputs written" || bad "outputs written"
rm -rf "$T/o" && mkdir "$T/o"

# (a) cut before the run: every form, four places
for f in $forms; do
    n=$(basename "$f" .svo)
    size=$(wc -c <"$f")
    set -- $(section "$f" NODE)
    node=$1 node_n=$2
    for cut in 6 20 $((node + node_n / 2)) $((size - 1)); do
        case $cut in
        6) pat="file is 6 bytes, the header needs" ;;
        20) pat="section table entry 0 at byte 12 is truncated" ;;
        $((size - 1))) pat="runs past the end of the $cut-byte file" ;;
        *) pat="section NODE \($node_n bytes at byte $node\) runs past the end of the $cut-byte file" ;;
        esac
        c="$T/$n.cut$cut.svo"
        head -c "$cut" "$f" >"$c"
        fails "$n cut at $cut: svo_info" "$pat" "$c" info "$c"
        # the renderer and the bake take the same table check: one form is enough for their exits and outputs
        case $n in demo)
            fails "$n cut at $cut: svo_render (whole)" "$pat" "$c" render_whole "$c"
            fails "$n cut at $cut: svo_render (models)" "$pat" "$c" render_models "$c"
            fails "$n cut at $cut: svo_bake" "$pat" "$c" bake "$c"
            ;;
        esac
    done
done

# (b) cut while the tool reads the file (the size taken at open): the whole
# reads at their first read (VX_CUT_FROM=0), the model reader when it takes
# its first model's stream (VX_CUT_FROM = NODE's offset), to half of NODE;
# and the whole reads to one byte less than the file
during() { # description pattern file from to command...
    what=$1 pat=$2 file=$3 from=$4 to=$5; shift 5
    PRE="env LD_PRELOAD=$CUT VX_CUT_PATH=$file VX_CUT_FROM=$from VX_CUT_TO=$to"
    fails "$what" "$pat" "$file" "$@"
    PRE=
    [ "$(wc -c <"$file")" = "$to" ] && ok "$what: the file was cut to $to bytes" || bad "$what: the file was not cut"
}
cut_msg="the file ends at byte [0-9]+, it had [0-9]+ bytes when opened \(cut short while it was read\)"
for f in $forms; do
    n=$(basename "$f" .svo)
    size=$(wc -c <"$f")
    set -- $(section "$f" NODE)
    node=$1 node_n=$2
    half=$((node + node_n / 2))
    c="$T/$n.live.svo"
    cp "$f" "$c"
    during "$n cut during the model reader's read: svo_render (models)" "model [0-9]+'s stream: .*$cut_msg" "$c" \
        "$node" "$half" render_models "$c"
    # mid-run: after the first pass, when a page's model is read again (VX_CUT_AGAIN: the first byte range read twice)
    cp "$f" "$c"
    during "$n cut mid-run, a page's model read again: svo_render --host-budget" "model [0-9]+'s stream: .*$cut_msg" \
        "$c" "$node" "$half" render_paged_again "$c"
    case $n in demo | split)
        for t in info render_whole bake; do
            cp "$f" "$c"
            during "$n cut during the whole read: $t" "$cut_msg" "$c" 0 "$half" $t "$c"
            cp "$f" "$c"
            during "$n cut by one byte during the whole read: $t" "ends at byte $((size - 1)), it had $size bytes" "$c" 0 \
                "$((size - 1))" $t "$c"
        done
        ;;
    esac
done

# a FIFO is not a file: refused at once, not read (a writer keeps the open from blocking)
mkfifo "$T/fifo.svo"
for t in info render_models bake; do
    (timeout 10 cat "$T/demo.svo" >"$T/fifo.svo") >/dev/null 2>&1 &
    PRE="timeout 20"
    fails "a FIFO: $t" "not a regular file" "$T/fifo.svo" $t "$T/fifo.svo"
    PRE=
    wait # the writer: ended by the tool's close (a broken pipe) or its timeout
done

echo "$pass passed, $fail failed"
[ "$fail" = 0 ]
