#!/bin/sh
# Modules talk through documented headers, never through another module's
# private one. A private header is one named *_internal.h or one whose
# opening comment says "(not public)" or "private to"; one in folder M may be
# included only by M's own sources and by M's own white-box tests in tests/M/
# (tests/svo/ may look inside svo/, tests/render/ inside render/). bench/,
# tools/, python/, the other modules and other modules' tests use the
# documented headers (render/testing.h holds what benchmarks and tests switch
# in the tracer). Fails listing each include that crosses a module boundary.
root=${1:-$(dirname "$0")/../..}
cd "$root" || exit 2
if ! git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
    echo "module headers: skipped, $root is not a git checkout (the check lists files through git)"
    exit 0
fi
bad=0
private=$( (git ls-files '*_internal.h'
            for h in $(git ls-files '*.h'); do
                head -n 3 "$h" | grep -q -e '(not public)' -e 'private to' && echo "$h"
            done) | sort -u)
for h in $private; do
    mod=${h%%/*}
    [ "$mod" = "$h" ] && continue # a header at the root belongs to no module
    for f in $(git grep -l "#include \"$h\"" -- '*.c' '*.h' '*.cpp' '*.comp' '*.glsl'); do
        case "$f" in
            "$mod"/* | tests/"$mod"/*) ;;
            *) echo "$f includes $h, private to $mod/"; bad=1 ;;
        esac
    done
done
[ $bad -eq 0 ] && echo "module headers: no private header crosses a module boundary ($(echo $private | wc -w) private headers)"
exit $bad
