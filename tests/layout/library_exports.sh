#!/bin/sh
# docs/LIBRARY.md states how many symbols libvoxkit exports; this check
# counts them in the built library (nm -D) and fails when the document and
# the library differ, so the count cannot drift again (stop 49 found 225
# written against 495 built). It also fails on any export outside the map's
# two families: vx_* and the two OpenVDB chunk readers LIBRARY.md names.
#   library_exports.sh LIB DOC FULL
# FULL: 1 when the build has every module of cmake/library.cmake (the count
# LIBRARY.md states is that build's); else the counts are printed and the
# check is skipped (exit 77): a build without OpenVDB or glTF exports fewer.
# To update LIBRARY.md after an API change, run it and copy the line it prints.
lib=$1 doc=$2 full=${3:-1}
if [ ! -f "$lib" ] || [ ! -f "$doc" ]; then
    echo "library exports: usage: library_exports.sh LIB DOC FULL (missing '$lib' or '$doc')"
    exit 2
fi
syms=$(nm -D --defined-only "$lib" | awk 'NF == 3 { print $2, $3 }') || exit 2
vx=$(printf '%s\n' "$syms" | awk '$2 ~ /^vx_/' | wc -l)
fn=$(printf '%s\n' "$syms" | awk '$2 ~ /^vx_/ && $1 == "T"' | wc -l)
tab=$((vx - fn))
inner=$(printf '%s\n' "$syms" | awk '$2 ~ /^vx__/' | wc -l)
other=$(printf '%s\n' "$syms" | awk '$2 !~ /^vx_/ { print $2 }' |
        grep -v -E '^_ZN7openvdb.*2io1[5](blosc|unzip)FromStreamERSiPcm$')
line="\`vx_*\` ($vx symbols: $fn functions and $tab tables; $inner of them are"
echo "library exports: $lib: $line \`vx__*\`"
if [ -n "$other" ]; then
    echo "library exports: exported outside cmake/voxkit.map's families:"
    printf '%s\n' "$other"
    exit 1
fi
if [ "$full" != 1 ]; then
    echo "library exports: not every module is built here; LIBRARY.md's count is the full build's (skipped)"
    exit 77
fi
if ! tr '\n' ' ' < "$doc" | tr -s ' ' | grep -q -F "$line"; then
    echo "library exports: $doc does not say: $line \`vx__*\`"
    echo "  it says: $(tr '\n' ' ' < "$doc" | tr -s ' ' | grep -o -E '`vx_\*` \([^)]{0,80}' | head -1)"
    exit 1
fi
echo "library exports: $doc states the built library's count"
