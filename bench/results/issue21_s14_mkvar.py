#!/usr/bin/env python3
# Makes trace.comp variants (issue 21, branch ray3): copies of render/shaders/trace.comp and
# trace_common.glsl with string edits, compiled with glslangValidator -V --target-env vulkan1.1.
# usage: mkvar.py SRC_DIR OUT_DIR NAME... (NAME in VARIANTS; "main" = no edit)
import os, subprocess, sys

def rep(s, a, b, count=1):
    if s.count(a) != count:
        raise SystemExit("edit not found %d times (found %d): %r" % (count, s.count(a), a[:80]))
    return s.replace(a, b)

def v_sh(c):
    # the paper's child masks: one shift puts the child's leaf bit at 7 and its valid bit at 15
    # (7 - cs == idx ^ oct), the inner children below it are bits 8-14 and 0-6 of the shifted word
    c = rep(c, "if ((desc & (cbit << 8)) != 0u && tmin <= tmax) {",
               "uint cm = desc << uint(idx ^ oct);\n            if ((cm & 0x8000u) != 0u && tmin <= tmax) {")
    c = rep(c, "bool is_leaf = (desc & cbit) != 0u;", "bool is_leaf = (cm & 0x80u) != 0u;")
    c = rep(c, "parent = child_node(parent, desc, cbit, nbase);",
               "uint blk = parent - (desc >> 17);\n                        if (FAR && (desc & 0x10000u) != 0u) blk = nbase + nodes[blk];\n"
               "                        parent = blk + uint(bitCount((cm >> 8) & ~cm & 0x7Fu));")
    return c

def v_rst(c):
    return rep(c, "layout(std430, binding = 1) readonly buffer Nodes", "layout(std430, binding = 1) restrict readonly buffer Nodes")

VARIANTS = {"main": [], "sh": [v_sh], "rst": [v_rst], "shrst": [v_sh, v_rst]}

def main():
    src, out = sys.argv[1], sys.argv[2]
    for name in sys.argv[3:]:
        d = os.path.join(out, "src_" + name)
        os.makedirs(d, exist_ok=True)
        comp = open(os.path.join(src, "trace.comp")).read()
        common = open(os.path.join(src, "trace_common.glsl")).read()
        for f in VARIANTS[name]:
            common = f(common)
        open(os.path.join(d, "trace.comp"), "w").write(comp)
        open(os.path.join(d, "trace_common.glsl"), "w").write(common)
        spv = os.path.join(out, "k_%s.spv" % name)
        subprocess.run(["glslangValidator", "-V", "--target-env", "vulkan1.1", "-I" + src, "-o", spv,
                        os.path.join(d, "trace.comp")], check=True, stdout=subprocess.DEVNULL)
        print("made", spv)

main()
