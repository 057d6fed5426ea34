"""The Python module against the tools (ctest python_build, python_installed).

Usage: python3 test_voxkit.py BIN_DIR CORPUS_DIR WORK_DIR [PREFIX]

BIN_DIR holds vox2svo and svo_info, the independent path: vox2svo converts,
`svo_info --dump` prints every voxel; the module must give the same cells and
colours. Without the corpus only the generated demo scene is checked (with a
message). With PREFIX, the module and libvoxkit must be loaded from there.
"""
import os
import re
import subprocess
import sys
import warnings

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from vxtest import Checks, tools  # noqa: E402
import voxkit

BIN, CORPUS, WORK = sys.argv[1:4]
PREFIX = sys.argv[4] if len(sys.argv) > 4 else None
os.makedirs(WORK, exist_ok=True)
check = Checks()
tool = tools(BIN)


def rows_sorted(a):
    return a[np.lexsort(a.T[::-1])] if len(a) else a


def dump(svo, all_=False):
    text = tool("svo_info", svo, "--dump", *(["--all"] if all_ else []))
    return rows_sorted(np.fromstring(text, dtype=np.int64, sep=" ").reshape(-1, 7))


def module_cells(scene, all_=False):
    xyz, rgba = scene.scene_voxels(all=all_)
    if not (xyz.dtype == np.int64 and xyz.shape[1:] == (3,) and rgba.dtype == np.uint8 and rgba.shape == (len(xyz), 4)):
        check(False, "scene_voxels: (N,3) int64 and (N,4) uint8")
    return rows_sorted(np.hstack([xyz, rgba.astype(np.int64)]))


def same_as_dump(name, src, svo, **options):
    """src converted by vox2svo (options as its flags) and by the module."""
    flags = []
    for k, v in options.items():
        flags += ["--" + k.replace("_", "-")] + ([] if v is True else [str(v)])
    tool("vox2svo", src, svo, *flags)
    ref = dump(svo)
    s = voxkit.open(svo)
    check(np.array_equal(module_cells(s), ref), f"{name}: scene_voxels equals svo_info --dump ({len(ref)} voxels)")
    # the module's own conversion gives the same scene
    check(np.array_equal(module_cells(voxkit.open(src, **options)), ref), f"{name}: voxkit.open({os.path.basename(src)}) "
          "converts to the same voxels")
    # models and instances: each model's cells placed by its instance's xform
    placed = []
    for i, inst in enumerate(s.instances):
        if not inst["visible"]:
            continue
        m = s.models[inst["model"]]
        xyz, rgba = s.voxels(inst["model"])
        ok = len(xyz) == m["voxel_count"] and xyz.dtype == np.int32 and (xyz >= 0).all() and (xyz < m["size"]).all()
        if not ok:
            check(False, f"{name}: model {inst['model']} cells within its size, voxel_count of them")
            return s
        x = inst["xform"]
        g = np.floor((xyz + 0.5) @ x[:, :3].T + x[:, 3]).astype(np.int64)
        placed.append(np.hstack([g, rgba.astype(np.int64)]))
    placed = rows_sorted(np.vstack(placed)) if placed else np.zeros((0, 7), np.int64)
    check(np.array_equal(placed, ref), f"{name}: voxels(model) placed by instances[i]['xform'] equal the dump")
    return s


# ---- where the module comes from -----------------------------------------------
print("voxkit", voxkit.__version__, "from", voxkit.__file__)
if PREFIX:
    prefix = os.path.realpath(PREFIX)
    check(os.path.realpath(voxkit.__file__).startswith(prefix + "/"), "the module is loaded from the prefix")
    with open("/proc/self/maps") as f:
        libs = {line.split()[-1] for line in f if "libvoxkit.so" in line}
    check(len(libs) == 1 and all(os.path.realpath(p).startswith(prefix + "/") for p in libs),
          f"libvoxkit is loaded from the prefix ({', '.join(libs)})")
check(issubclass(voxkit.Error, Exception), "voxkit.Error is an Exception")

# ---- a generated scene: the demo island (hidden layer, rotations, mirrors) -----
demo_vox, demo = os.path.join(WORK, "demo.vox"), os.path.join(WORK, "demo.svo")
tool("vox2svo", "--write-demo", demo_vox)
s = same_as_dump("demo", demo_vox, demo, keep_hidden=True)  # with its hidden layer
check(np.array_equal(module_cells(s, True), dump(demo, True)) and len(module_cells(s, True)) > len(module_cells(s)),
      "demo: scene_voxels(all=True) equals --dump --all (more voxels)")
check(len(s.instances) > len(s.models) >= 3, f"demo: {len(s.models)} models, {len(s.instances)} instances")
check(any(not i["visible"] for i in s.instances), "demo: the hidden layer's instance is listed as not visible")
np.testing.assert_array_equal(s.world_from_grid, np.eye(3, 4))
again = os.path.join(WORK, "demo-again.svo")
s.save(again)
check(np.array_equal(dump(again), dump(demo)), "save(): svo_info reads the same voxels back")
vox_again = os.path.join(WORK, "demo-again.vox")
s.to_vox(vox_again)
check(np.array_equal(module_cells(voxkit.open(vox_again, keep_hidden=True)), dump(demo)), "to_vox(): the .vox converts back to the same voxels")
conv = os.path.join(WORK, "demo-convert.svo")
voxkit.convert(demo_vox, conv, no_dag=True, keep_hidden=True)
check(np.array_equal(dump(conv), dump(demo)), "convert(src, dst, no_dag=True) writes the same voxels")

# ---- exports: to_glb and to_vdb (convert/export.h, svo_info's --to-glb, --to-vdb) ----
def read(path):
    with open(path, "rb") as f:
        return f.read()


glb_py, glb_tool = os.path.join(WORK, "demo-py.glb"), os.path.join(WORK, "demo-tool.glb")
s.to_glb(glb_py)
tool("svo_info", demo, "--to-glb", glb_tool)
check(read(glb_py) == read(glb_tool) and read(glb_py)[:4] == b"glTF",
      f"to_glb(): the bytes svo_info --to-glb writes ({os.path.getsize(glb_py)} bytes)")
glb_all, glb_all_tool = os.path.join(WORK, "demo-py-all.glb"), os.path.join(WORK, "demo-tool-all.glb")
s.to_glb(glb_all, all=True)
tool("svo_info", demo, "--all", "--to-glb", glb_all_tool)
check(read(glb_all) == read(glb_all_tool) and read(glb_all) != read(glb_py),
      "to_glb(all=True): the bytes svo_info --all --to-glb writes (the hidden layer's instance too: not the default's)")
# the independent path for .vdb: the module's own OpenVDB import reads the grids back
vdb_py = os.path.join(WORK, "demo-py.vdb")
s.to_vdb(vdb_py)
back = module_cells(voxkit.open(vdb_py, color_grid="color"))
ref = module_cells(s)
ref_cells = np.unique(ref[:, :3], axis=0)
ref_rows = {tuple(r) for r in ref}
check(np.array_equal(back[:, :3], ref_cells) and all(tuple(r) in ref_rows for r in back),
      f"to_vdb(): read back, the scene's {len(ref_cells)} cells with their colours (overlaps: one instance's)")
s.to_vdb(vdb_py, models=True)
tool("svo_info", demo, "--vdb-models", "--to-vdb", os.path.join(WORK, "demo-tool-models.vdb"))
check(abs(os.path.getsize(vdb_py) - os.path.getsize(os.path.join(WORK, "demo-tool-models.vdb"))) <= 64,
      "to_vdb(models=True): the size svo_info --vdb-models writes (OpenVDB's files differ only in their UUIDs)")
for call, what in ((lambda: s.to_glb(os.path.join(WORK, "no-such-folder", "x.glb")), "to_glb into a missing folder"),
                   (lambda: s.to_vdb(os.path.join(WORK, "no-such-folder", "x.vdb")), "to_vdb into a missing folder")):
    try:
        call()
        check(False, f"{what} raises voxkit.Error")
    except voxkit.Error as e:
        check("no-such-folder" in str(e), f"{what} raises voxkit.Error naming the file: {e}")

# ---- an animation: the demo with a moving tower (issue 24) ---------------------
anim_vox, anim = os.path.join(WORK, "anim.vox"), os.path.join(WORK, "anim.svo")
tool("vox2svo", "--write-demo", anim_vox, "--demo-frames", "6")
tool("vox2svo", anim_vox, anim)
a = voxkit.open(anim)
info = tool("svo_info", anim).decode()
check(a.frame_count == 6 and "frames       6 " in info and s.frame_count == 1,
      f"frame_count: 6 as svo_info lists them ({a.frame_count}; the static demo: {s.frame_count})")
check(a.frame_rate == 0.0 and "frame rate not known" in info, "frame_rate: 0.0 where the .vox has none")
moved = 0
for f in range(a.frame_count):
    ref = rows_sorted(np.fromstring(tool("svo_info", anim, "--dump", "--frame", str(f)), dtype=np.int64,
                                    sep=" ").reshape(-1, 7))
    xyz, rgba = a.scene_voxels(frame=f)
    got = rows_sorted(np.hstack([xyz, rgba.astype(np.int64)]))
    # independent of scene_voxels: frame f's instances place their models' cells
    placed = []
    insts = a.frame_instances(f)
    for inst in insts:
        if inst["visible"]:
            mx, mc = a.voxels(inst["model"])
            x = inst["xform"]
            placed.append(np.hstack([np.floor((mx + 0.5) @ x[:, :3].T + x[:, 3]).astype(np.int64), mc.astype(np.int64)]))
    placed = rows_sorted(np.vstack(placed))
    moved += f > 0 and any(not np.array_equal(i["xform"], j["xform"]) for i, j in zip(insts, a.instances))
    check(np.array_equal(got, ref) and np.array_equal(placed, ref),
          f"frame {f}: scene_voxels(frame={f}) and frame_instances({f}) placed equal --dump --frame {f} ({len(ref)} voxels)")
check(moved == a.frame_count - 1, f"frame_instances: an instance moves in each of frames 1..5 ({moved})")
a.to_glb(os.path.join(WORK, "anim-3.glb"), frame=3)
tool("svo_info", anim, "--frame", "3", "--to-glb", os.path.join(WORK, "anim-3-tool.glb"))
a.to_glb(os.path.join(WORK, "anim-0.glb"))
check(read(os.path.join(WORK, "anim-3.glb")) == read(os.path.join(WORK, "anim-3-tool.glb")) and
      read(os.path.join(WORK, "anim-3.glb")) != read(os.path.join(WORK, "anim-0.glb")),
      "to_glb(frame=3): the bytes svo_info --frame 3 --to-glb writes (not frame 0's)")
check(len(a.frame_instances(0)) == len(a.instances) and
      all(np.array_equal(i["xform"], j["xform"]) for i, j in zip(a.frame_instances(0), a.instances)),
      "frame_instances(0) is instances")
for call, what in ((lambda: a.frame_instances(6), "frame_instances(6)"), (lambda: a.scene_voxels(frame=6), "scene_voxels(frame=6)"),
                   (lambda: s.frame_instances(1), "frame 1 of a static scene")):
    try:
        call()
        check(False, f"{what} raises IndexError")
    except IndexError as e:
        check(True, f"{what} raises IndexError: {e}")

# ---- more than 255 colours: to_vox refuses; quantize=True maps them to 255 ------
# a triangle whose corners are red, green and blue (test_tools' rgb.gltf): its cells interpolate them
rgb_gltf, rgb, rgb_vox = (os.path.join(WORK, n) for n in ("rgb.gltf", "rgb.svo", "rgb.vox"))
with open(rgb_gltf, "w") as f:
    f.write('{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],'
            '"meshes":[{"primitives":[{"attributes":{"POSITION":0,"COLOR_0":1}}]}],'
            '"buffers":[{"byteLength":72,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAA'
            'AAAAgD8AAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAAAAAAAAAAAAIA/"}],'
            '"bufferViews":[{"buffer":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":36}],'
            '"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},'
            '{"bufferView":1,"componentType":5126,"count":3,"type":"VEC3"}]}')
try:
    tool("vox2svo", rgb_gltf, rgb, "--res", "64", "-q")
except subprocess.CalledProcessError as e:
    print(f"skip: more than 255 colours: vox2svo {rgb_gltf}: {e.stderr.decode().strip()}")
    rgb = None
if rgb:
    ref = dump(rgb)
    nc = len(np.unique(ref[:, 3:], axis=0))
    check(nc > 255, f"the triangle has {nc} colours")
    q = voxkit.open(rgb)
    if os.path.exists(rgb_vox):
        os.remove(rgb_vox)
    try:
        q.to_vox(rgb_vox)
        check(False, "to_vox of more than 255 colours raises voxkit.Error")
    except voxkit.Error as e:
        check(f"{nc} distinct colours" in str(e) and "quantize=True" in str(e) and "svo_info" not in str(e) and
              e.path == rgb_vox and not os.path.exists(rgb_vox), f"to_vox of {nc} colours is refused, naming quantize=True: {e}")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        r = q.to_vox(rgb_vox, quantize=True)
    qw = [w for w in caught if issubclass(w.category, voxkit.QuantizeWarning)]
    m = re.search(r"max ([0-9.]+), mean ([0-9.]+)", str(qw[0].message)) if len(qw) == 1 else None
    check(r is None and issubclass(voxkit.QuantizeWarning, UserWarning) and m and
          str(qw[0].message).startswith(f"{rgb_vox}: {nc} distinct colours quantized to a 255-entry palette"),
          f"to_vox(quantize=True) warns once with voxkit.QuantizeWarning: {[str(w.message) for w in caught]}")
    # the independent path: vox2svo reads the .vox, svo_info dumps it; every cell where it was,
    # its colour the nearest entry in use, the error as the warning says
    back_svo = os.path.join(WORK, "rgb-back.svo")
    tool("vox2svo", rgb_vox, back_svo, "-q")
    back = dump(back_svo)
    if check(len(back) == len(ref) and np.array_equal(back[:, :3], ref[:, :3]), f"quantized: all {len(ref)} cells where they were"):
        err = np.sqrt(((ref[:, 3:] - back[:, 3:]).astype(np.float64) ** 2).sum(axis=1))
        entries = np.unique(back[:, 3:], axis=0)
        nearest = np.sqrt(((ref[:, None, 3:] - entries[None, :, :]).astype(np.float64) ** 2).sum(axis=2)).min(axis=1)
        check(np.array_equal(err, nearest), f"quantized: each cell's colour the nearest of the {len(entries)} entries in use")
        wmax, wmean = (float(m.group(1)), float(m.group(2))) if m else (-1.0, -1.0)
        check(abs(err.max() - wmax) <= 0.005 and abs(err.mean() - wmean) <= 0.005,
              f"quantized: error max {err.max():.2f}, mean {err.mean():.2f} as the warning says ({wmax}, {wmean})")
        # the colours fill a triangle of side 255 sqrt(2) (r + g + b = 255): 255 entries spread evenly
        # leave each colour within r of one, the hexagon of 1/255 of its area; the median cut's
        # axis-aligned boxes within twice that, plus the entries' rounding (half a unit a channel)
        r_even = np.sqrt(2 * (np.sqrt(3) / 2 * 255**2 / 255) / (3 * np.sqrt(3)))
        bound = 2 * r_even + 0.5 * np.sqrt(3)
        check(0 < err.max() <= bound and err.mean() <= r_even,
              f"quantized: error max {err.max():.2f} <= {bound:.2f}, mean {err.mean():.2f} <= {r_even:.2f}")
    # the caller's filters decide: "error" raises the warning
    with warnings.catch_warnings():
        warnings.simplefilter("error", voxkit.QuantizeWarning)
        try:
            q.to_vox(rgb_vox, quantize=True)
            check(False, "with the warning as an error, to_vox(quantize=True) raises voxkit.QuantizeWarning")
        except voxkit.QuantizeWarning as e:
            check(True, f"with the warning as an error, to_vox(quantize=True) raises voxkit.QuantizeWarning: {e}")

# ---- errors --------------------------------------------------------------------
bad = os.path.join(WORK, "bad.svo")
with open(bad, "wb") as f:
    f.write(b"this is not an octree" * 8)
truncated = os.path.join(WORK, "truncated.svo")
with open(demo, "rb") as f, open(truncated, "wb") as g:
    g.write(f.read()[: os.path.getsize(demo) // 2])
missing = os.path.join(WORK, "missing.svo")
unknown = os.path.join(WORK, "scene.txt")
open(unknown, "w").close()
for path in (bad, truncated, missing, unknown):
    try:
        voxkit.open(path)
        check(False, f"{os.path.basename(path)} raises voxkit.Error")
    except voxkit.Error as e:
        check(path in str(e) and e.path == path and isinstance(e.code, str),
              f"{os.path.basename(path)} raises voxkit.Error naming it: {e}")
for call, exc, what in ((lambda: voxkit.open(demo_vox, resolution=3), TypeError, "an unknown option"),
                        (lambda: voxkit.open(demo_vox, res=0), ValueError, "res=0"),
                        (lambda: s.voxels(len(s.models)), IndexError, "a model out of range")):
    try:
        call()
        check(False, f"{what} raises {exc.__name__}")
    except exc as e:
        check(True, f"{what} raises {exc.__name__}: {e}")

# ---- rendering -----------------------------------------------------------------
if not voxkit.has_render:
    print("skip: this build has no Vulkan tracer (render)")
else:
    cpu = s.render(80, 60, cpu=True)
    check(cpu.shape == (60, 80, 4) and cpu.dtype == np.float32, "render(cpu=True): (60,80,4) float32")
    try:
        gpu = s.render(80, 60)
    except voxkit.Error as e:
        gpu = None
        print(f"skip: no Vulkan device ({e})")
    if gpu is not None:
        diff = np.abs(gpu - cpu).max(axis=2) > 2 / 255
        check(diff.mean() < 0.01, f"render(): GPU and CPU reference agree ({diff.sum()} of {diff.size} pixels differ)")
        import threading
        out = [None] * 4
        threads = [threading.Thread(target=lambda k=k: out.__setitem__(k, s.render(80, 60))) for k in range(4)]
        [t.start() for t in threads]
        [t.join() for t in threads]
        check(all(o is not None and np.array_equal(o, gpu) for o in out), "render() from 4 threads at once: the same images")
        depth = s.render(80, 60, mode="depth")[:, :, 0]
        hit = np.isfinite(depth)
        check(0.1 < hit.mean() < 1 and (depth[hit] > 0).all(), f"render(mode='depth'): {hit.mean():.0%} of pixels hit")
        lo, hi = np.array(s.bounds[0]), np.array(s.bounds[1])
        view = dict(mode="depth", eye=(lo + hi) / 2 + [0, 0, 100], target=(lo + hi) / 2, up=[0, 1, 0], ortho=True,
                    ortho_height=(hi - lo).max())
        top, top_cpu = s.render(32, 32, **view)[:, :, 0], s.render(32, 32, cpu=True, **view)[:, :, 0]
        same = (np.isinf(top) & np.isinf(top_cpu)) | (np.abs(top - top_cpu) < 1e-3)
        check(same.mean() > 0.99 and np.isfinite(top).mean() > 0.5,
              f"render(eye, target, up, ortho): a top-down depth view equals the CPU reference's ({same.mean():.1%})")

# ---- a map sky's relative path follows the file (stop 74) ----------------------
# vox2svo --sky stores a map given from the current folder relative to the output's folder; save() and convert()
# to other folders rebase it so that the saved file names the same image (before, the text was copied as it was)
sky_dir = os.path.join(WORK, "skya")
deep_dir = os.path.join(WORK, "skyb", "deep")
os.makedirs(sky_dir, exist_ok=True)
os.makedirs(deep_dir, exist_ok=True)
env = os.path.relpath(os.path.join(WORK, "env", "sky.exr"))
sky_svo = os.path.join(sky_dir, "m.svo")
tool("vox2svo", demo_vox, sky_svo, "-q", "--sky", "map:" + env + ":2")


def sky_line(svo):
    return [l for l in tool("svo_info", svo).decode().splitlines() if l.startswith("sky ")][0]


check('"../env/sky.exr" x 2' in sky_line(sky_svo), f"vox2svo --sky map: {sky_line(sky_svo)}")
deep_svo = os.path.join(deep_dir, "m.svo")
voxkit.open(sky_svo).save(deep_svo)
check('"../../env/sky.exr" x 2' in sky_line(deep_svo), f"save() to a deeper folder rebases the map: {sky_line(deep_svo)}")
conv_svo = os.path.join(WORK, "m-conv.svo")
voxkit.convert(deep_svo, conv_svo)
check('"env/sky.exr" x 2' in sky_line(conv_svo), f"convert() to the map's parent folder: {sky_line(conv_svo)}")

# ---- Scene.sky: the stored sky as svo_render --sky's text --------------------------
# set, read back, saved, reopened, shown by svo_info; a map's path given from the current folder is stored from the
# file's folder (as vox2svo --sky stores it); bad texts raise ValueError saying what is wrong (before, no setter)
s = voxkit.open(demo)
check(s.sky is None, f"Scene.sky: None for a scene without a sky ({s.sky!r})")
set_dir = os.path.join(WORK, "skyset")
os.makedirs(set_dir, exist_ok=True)
for spec, shown in (("gradient:0.2,0.3,0.6:0.7,0.7,0.8:0.1,0.1,0", "gradient zenith 0.2 0.3 0.6, horizon 0.7 0.7 0.8, "
                     "ground 0.1 0.1 0"), ("0.5,0.25,1000", "constant 0.5 0.25 1000")):
    s.sky = spec
    check(s.sky == spec, f"Scene.sky = {spec!r} reads back as {s.sky!r}")
    out = os.path.join(set_dir, "set.svo")
    s.save(out)
    check(voxkit.open(out).sky == spec, f"Scene.sky {spec!r} saved and reopened: {voxkit.open(out).sky!r}")
    check(shown in sky_line(out), f"svo_info shows the sky set: {sky_line(out)}")
s.sky = "gradient:1,1,1:1,1,1:1,1,1"
s.sky = None
check(s.sky is None, "Scene.sky = None resets it")
s.save(out)
check("default" in sky_line(out) and voxkit.open(out).sky is None, f"a reset sky is saved as the default: {sky_line(out)}")
s.sky = "1,1,1"
del s.sky
check(s.sky is None, "del Scene.sky resets it")
s.sky = "default"
check(s.sky is None, "Scene.sky = 'default' resets it")
# a map: given from here, stored from the scene's folder (skya/, so "../env/sky.exr"), given back from here
m = voxkit.open(sky_svo)
env_abs = os.path.realpath(os.path.join(WORK, "env", "sky.exr"))


def names_env(spec, tail):
    return spec.startswith("map:") and spec.endswith(tail) and os.path.realpath(spec[4:-len(tail)]) == env_abs


check(names_env(m.sky, ":2"), f"Scene.sky of vox2svo --sky map: gives the map from the current folder: {m.sky!r}")
m.sky = "map:" + env + ":0.5:90"
check(names_env(m.sky, ":0.5:90"), f"Scene.sky = map:{env}:0.5:90 reads back as {m.sky!r}")
m_out = os.path.join(sky_dir, "set-map.svo")
m.save(m_out)
check('"../env/sky.exr" x 0.5, turned 90 deg' in sky_line(m_out), f"the map set is stored from the file's folder: "
      f"{sky_line(m_out)}")
m.save(os.path.join(deep_dir, "set-map.svo"))
check('"../../env/sky.exr" x 0.5' in sky_line(os.path.join(deep_dir, "set-map.svo")), "the map set follows a save to "
      "another folder")
check(names_env(voxkit.open(os.path.join(deep_dir, "set-map.svo")).sky, ":0.5:90"), "and reads back from there")
before = open(m_out, "rb").read()
m.sky = m.sky
m.save(m_out)
check(open(m_out, "rb").read() == before, "Scene.sky = Scene.sky keeps the record, byte for byte")
for bad_spec, exc, why in (("gradient:1,1,1", ValueError, "gradient:ZR"), ("-1,0,0", ValueError, "negative"),
                           ("1,2", ValueError, "R,G,B"), ("map:", ValueError, "map:FILE"),
                           ("map:a.exr:x", ValueError, "map:FILE"), ("a:b:c:d:e:f", ValueError, "too many"),
                           ("1,1,1\0", ValueError, "NUL"), (5, TypeError, "str")):
    try:
        m.sky = bad_spec
        check(False, f"Scene.sky = {bad_spec!r} raises {exc.__name__}")
    except exc as e:
        check(why in str(e) and (exc is TypeError or "\0" in bad_spec or f"'{bad_spec}'" in str(e)),
              f"Scene.sky = {bad_spec!r}: {exc.__name__}: {e}")
check(names_env(m.sky, ":0.5:90"), f"a refused text leaves the sky as it was: {m.sky!r}")

# ---- corpus --------------------------------------------------------------------
if not os.path.isdir(CORPUS):
    print(f"skip: corpus {CORPUS} not found (only the generated scene was checked)")
else:
    cases = [("vox/ogt_test_multiple_model_scene.vox", {}), ("vox/ogt_test_groups.vox", {}),
             ("vox/eph_chr_knight.vox", {}), ("vox/ogt_doom.vox", {}), ("gltf/julian_Duck.glb", {"res": 64}),
             ("vdb/mjurczyk_sphere.vdb", {})]
    for rel, opts in cases:
        src = os.path.join(CORPUS, rel)
        if not os.path.exists(src):
            print(f"skip: {src} not found")
            continue
        out = os.path.join(WORK, os.path.basename(rel) + ".svo")
        try:
            same_as_dump(os.path.basename(rel), src, out, **opts)
        except subprocess.CalledProcessError as e:
            if b"without" in e.stderr or b"no glTF" in e.stderr or b"no OpenVDB" in e.stderr:
                print(f"skip: {rel}: {e.stderr.decode().strip()}")
            else:
                raise

check.exit()
