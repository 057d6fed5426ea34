#!/usr/bin/env python3
# Makes trace.comp variants (issue 21, branch ray3): copies of render/shaders/trace.comp and
# trace_common.glsl with string edits, compiled with glslangValidator -V --target-env vulkan1.1.
# usage: mkvar.py SRC_DIR OUT_DIR NAME... ("main" = no edit). Variants marked "timing only" are
# not exact (measurements of a part's cost). main, sh, rst: main's sources (0b39e32); one, nopre, uni, noblk,
# notile, never, onlyp: the branch's at 38f1a6e (the per-tile starts, lavapipe's cost of their code).
import os, subprocess, sys

def rep(s, a, b, count=1):
    if s.count(a) != count:
        raise SystemExit("edit not found %d times (found %d): %r" % (count, s.count(a), a[:80]))
    return s.replace(a, b)

def v_sh(c, t):
    # the paper's child masks (one shift: the child's leaf bit at 7, its valid bit at 15; 7 - cs == idx ^ oct);
    # NOT exact: with a leaf mask (not the paper's non-leaf mask) the shifted word's low bits below 7 mix in
    # the leaf bits of the children after cs, so the inner children's count is wrong
    c = rep(c, "if ((desc & (cbit << 8)) != 0u && tmin <= tmax) {",
               "uint cm = desc << uint(idx ^ oct);\n            if ((cm & 0x8000u) != 0u && tmin <= tmax) {")
    c = rep(c, "bool is_leaf = (desc & cbit) != 0u;", "bool is_leaf = (cm & 0x80u) != 0u;")
    c = rep(c, "parent = child_node(parent, desc, cbit, nbase);",
               "uint blk = parent - (desc >> 17);\n                        if (FAR && (desc & 0x10000u) != 0u) blk = nbase + nodes[blk];\n"
               "                        parent = blk + uint(bitCount((cm >> 8) & ~cm & 0x7Fu));")
    return c, t

def v_rst(c, t):
    # the node buffer restrict (measured: no change)
    return rep(c, "layout(std430, binding = 1) readonly buffer Nodes", "layout(std430, binding = 1) restrict readonly buffer Nodes"), t

def v_one(c, t):
    # the start at most one level below X (K, X's child), not at K's child G
    return rep(c, "const bool PATH_KIDS = true;", "const bool PATH_KIDS = false;"), t

def v_nopre(c, t):
    # timing only: no stack prefill
    return rep(c, "for (int j = 0; j < dx; j++) stk_node[S_MAX - 1 - j] = int(nbase + F.paths[g_path].nodes[j >> 2][j & 3]);", ""), t

def no_assign(t):
    t = rep(t, "g_path = USE_BVH || tile >= uint(PATHS) ? 0xFFFFu : tile;", "")
    return rep(t, "        g_path = 0xFFFFu;\n", "")

def v_uni(c, t):
    # timing only: record 0 for every ray (a uniform index)
    return rep(c, "uint g_path = 0xFFFFu;", "const uint g_path = 0u;"), no_assign(t)

def v_noblk(c, t):
    # timing only: the start block removed (the tile lookup kept)
    a = c.index("        if (g_path != 0xFFFFu && !USE_BVH && !LOD")
    b = c.index("#endif", a)
    return c[:a] + c[b:], t

def v_notile(c, t):
    # timing only: the tile lookup for the BVH kernel only, as main's
    return c, rep(t, "        if (!MISS_PASS) {\n            uint ti", "        if (USE_BVH && !MISS_PASS) {\n            uint ti")

def v_never(c, t):
    # timing only: the start's condition never true (not provably)
    return rep(c, "            if (lv >= 0) {", "            if (lv >= 0 && ol.x < 0.5) {"), t

def v_onlyp(c, t):
    # timing only: the start sets the node and its level only
    c = rep(c, "                pos = lv == 0 ? px : lv == 1 ? pk : pg;\n", "")
    return c, t

VARIANTS = {"sh": [v_sh], "never": [v_never], "onlyp": [v_onlyp], "main": [], "rst": [v_rst], "one": [v_one], "nopre": [v_nopre], "uni": [v_uni], "noblk": [v_noblk],
            "notile": [v_notile]}

def main():
    src, out = sys.argv[1], sys.argv[2]
    for name in sys.argv[3:]:
        d = os.path.join(out, "src_" + name)
        os.makedirs(d, exist_ok=True)
        comp = open(os.path.join(src, "trace.comp")).read()
        common = open(os.path.join(src, "trace_common.glsl")).read()
        for f in VARIANTS[name]:
            common, comp = f(common, comp)
        open(os.path.join(d, "trace.comp"), "w").write(comp)
        open(os.path.join(d, "trace_common.glsl"), "w").write(common)
        spv = os.path.join(out, "k_%s.spv" % name)
        subprocess.run(["glslangValidator", "-V", "--target-env", "vulkan1.1", "-I" + src, "-o", spv,
                        os.path.join(d, "trace.comp")], check=True, stdout=subprocess.DEVNULL)
        print("made", spv)

main()
