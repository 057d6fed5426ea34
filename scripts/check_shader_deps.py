#!/usr/bin/env python3
"""scripts/check_shader_deps.py - the whole tree's check of the shader build rules' dependencies (docs/TESTING.md,
"Shader dependencies"; ctest's test_shader_deps checks the same on a small tree). Touches each shader source of the
tree (every .comp and .glsl of the shader folders, and probes' beam_body.cmake) in turn, runs the build command,
and records which embedded SPIR-V headers (*.comp.h) it rewrote; compares them with the files each header's source
includes, found by reading the sources with the rule's -D defines (an independent path: no compiler, no depfile;
#ifdef, #ifndef, #if of defined() terms, #elif, #else, #endif and #define NAME are followed). Prints one line per
touched file and exits 1 when some rebuild differs. About 1 minute with Ninja, 3 with Makefiles (the libraries
that embed the headers recompile: ccache).

  scripts/check_shader_deps.py SRC BUILD -- BUILD COMMAND...
  e.g. scripts/check_shader_deps.py . build -- cmake --build build -j2 --target vx_render vx_probes vx_cones \
           vx_photons vx_conv_mesh_gpu render_bench test_pipeline_cache test_spirv_valid
  (Ninja can build the headers alone: ninja -C build $(ninja -C build -t targets all | grep -o '^[^:]*comp\.h'))"""
import os, re, subprocess, sys, time, glob
src, build = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
cmd = sys.argv[sys.argv.index('--') + 1:]
# headers and their sources, from the glslangValidator command lines of the generated build files
pairs = {}
for f in glob.glob(build + '/**/build.ninja', recursive=True) + glob.glob(build + '/**/build.make', recursive=True):
    if 'shader_deps' in f: continue  # test_shader_deps' own small tree
    for line in open(f, errors='replace'):
        m = re.search(r'glslangValidator (.*) -o (\S+\.comp\.h) (\S+\.comp)', line)
        if m: pairs[os.path.normpath(os.path.join(build, m.group(2)))] = (m.group(3), set(re.findall(r'-D(\w+)', m.group(1))))
shaders = [p for d in ('render', 'probes', 'cones', 'photons', 'convert', 'bench', 'tests/render')
           for p in sorted(glob.glob(f'{src}/{d}/shaders/*')) if p.endswith(('.glsl', '.comp', '.cmake'))]
byname = {os.path.basename(p): p for p in shaders}
gen = {'beam_body.glsl': [byname['beam_body.cmake'], byname['beam.comp']]}  # probes' include generated from beam.comp
def cond(expr, defs):
    e = re.sub(r'defined\s*\(\s*(\w+)\s*\)', lambda m: str(m.group(1) in defs), expr)
    e = e.replace('&&', ' and ').replace('||', ' or ').replace('!', ' not ')
    try: return bool(eval(e, {}))
    except Exception: return True  # not understood: assume taken (over-approximates)
def closure(path, defs, seen):
    seen.add(path)
    if not path.endswith(('.glsl', '.comp')): return seen
    stack = []  # (this branch taken, some branch taken) per open #if
    for line in open(path):
        m = re.match(r'\s*#\s*(\w+)\s*(.*)', line)
        if not m: continue
        d, arg = m.group(1), m.group(2).split('//')[0].strip()
        live = all(t for t, _ in stack)
        if d in ('ifdef', 'ifndef', 'if'):
            t = (arg in defs) if d == 'ifdef' else (arg not in defs) if d == 'ifndef' else cond(arg, defs)
            stack.append((t, t))
        elif d == 'elif':
            t = not stack[-1][1] and cond(arg, defs); stack[-1] = (t, stack[-1][1] or t)
        elif d == 'else': stack[-1] = (not stack[-1][1], True)
        elif d == 'endif': stack.pop()
        elif not live: continue
        elif d == 'define': defs.add(arg.split()[0])
        elif d == 'undef': defs.discard(arg)
        elif d == 'include':
            inc = arg.strip('"')
            for f in gen.get(inc, [byname.get(inc)]):
                closure(f, defs, seen)
    return seen
expect = {h: closure(s, set(defs), set()) for h, (s, defs) in pairs.items()}
def mtimes(): return {h: os.stat(h).st_mtime_ns for h in pairs}
subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
bad = 0
for f in shaders:
    before = mtimes()
    time.sleep(0.02)
    os.utime(f)
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    after = mtimes()
    got = sorted(os.path.basename(h) for h in pairs if after[h] != before[h])
    want = sorted(os.path.basename(h) for h in pairs if f in expect[h])
    tag = 'ok' if got == want else 'DIFF'
    bad += got != want
    print(f'{tag:4} {os.path.relpath(f, src)}: {len(got)} rebuilt' + ('' if got == want else
          f'\n     rebuilt, not in the closure: {sorted(set(got) - set(want))}\n     in the closure, not rebuilt: {sorted(set(want) - set(got))}'))
    sys.stdout.flush()
print(f'{len(shaders)} files touched, {len(pairs)} headers, {bad} differ from the closure')
sys.exit(1 if bad or not pairs else 0)
