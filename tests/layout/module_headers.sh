#!/bin/sh
# Modules talk through documented headers, never through another module's
# private one: a header named *_internal.h in folder M may be included only
# by M's own sources (and by tests/ and bench/, which look inside on purpose).
# Fails listing each include that crosses a module boundary.
root=${1:-$(dirname "$0")/../..}
cd "$root" || exit 2
if ! git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
    echo "module headers: skipped, $root is not a git checkout (the check lists files through git)"
    exit 0
fi
bad=0
for h in $(git ls-files '*_internal.h'); do
    mod=${h%%/*}
    for f in $(git grep -l "#include \"$h\"" -- '*.c' '*.h' '*.cpp' '*.comp' '*.glsl'); do
        case "$f" in
            "$mod"/* | tests/* | bench/*) ;;
            *) echo "$f includes $h, private to $mod/"; bad=1 ;;
        esac
    done
done
[ $bad -eq 0 ] && echo "module headers: no private header crosses a module boundary"
exit $bad
