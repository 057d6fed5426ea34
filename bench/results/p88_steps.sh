#!/bin/bash
# Stop 88 (issue 21): where the grid walk's steps go, per ray: the fine steps (a brick's cells, GRID_FINE), the brick
# entries (GRID_ENTER) and the rest (empty entries left, GRID_SKIP), from two variants of trace.comp that count only
# the first or only the second in the steps image (a copy of render/shaders with grid_walk.glsl patched by the
# python below; the walk itself unchanged, so 0 px differ). Steps do not depend on the device: lavapipe, 640x360.
# Usage: bench/results/p88_steps.sh BUILD [FILE.vox...] > LOG
B=${1:-build}/bin; shift; C=${VX_CORPUS_DIR:-../shared/corpus}
[ $# -gt 0 ] || set -- $C/vox/eph_monu1.vox $C/vox/eph_menger.vox $C/vox/eph_dragon.vox
W=$(mktemp -d); cp -r render/shaders $W/
for v in fine enter; do
  python3 - $v $W/shaders/grid_walk.glsl <<'PY'
import sys
v, p = sys.argv[1], sys.argv[2]
s = open(p).read()
mac = '#define GRID_FINE \\\n' if v == 'fine' else '#define GRID_ENTER \\\n'
assert mac in s and '    uint steps = 0u;\n' in s
s = s.replace(mac, mac + '            xsteps++; \\\n', 1)
s = s.replace('    uint steps = 0u;\n', '    uint steps = 0u, xsteps = 0u;\n', 1)
s = s.replace('g_iter += steps;', 'g_iter += xsteps;')
open(p, 'w').write(s)
PY
  glslangValidator -V --target-env vulkan1.1 -o $W/$v.spv $W/shaders/trace.comp > /dev/null || exit 1
  cp render/shaders/grid_walk.glsl $W/shaders/grid_walk.glsl
done
echo "# columns as render_bench's; stVX of the rows: all steps (built-in), fine steps ([kernel ...fine.spv]), brick entries ([kernel ...enter.spv])"
$B/render_bench --kernels $W/fine.spv@c0,$W/enter.spv@c0 --sizes 640x360 --runs 1 --warmup 0 --no-esvo "$@" 2>&1 | grep -v "^shadow map"
rm -rf $W
