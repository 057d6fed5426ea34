"""The up axis (ctest test_up_axis): the corpus Duck, converted from glTF
(+Y up), must stand upright in voxkit's +Z-up world and in every export, each
in its own up axis: the cells of its head (the orange beak, the black eyes)
lie above those of its yellow body in
  - the .svo (grid z; svo_info --dump),
  - svo_render's default view (the tracer's own framing, through the voxkit
    module: the head is nearer the top of the image),
  - the .vox export (MagicaVoxel's z, read here from the file's chunks),
  - the .glb export (glTF's y, read here from the GLB's JSON and buffer, node
    matrices applied).
A control converts with --y-up (glTF's axes kept): then the head must not be
above the body along z, so the check can fail.

Usage: python3 test_up_axis.py BIN_DIR CORPUS_DIR WORK_DIR  (PYTHONPATH: the voxkit module)
"""
import os
import struct
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from vxtest import Checks, tools  # noqa: E402
from glbduck import head_lift, read_glb, to_srgb  # noqa: E402

BIN, CORPUS, WORK = sys.argv[1:4]
DUCK = os.path.join(CORPUS, "gltf", "julian_Duck.glb")
if not os.path.exists(DUCK):
    print(f"skip: {DUCK} not found")
    sys.exit(0)
os.makedirs(WORK, exist_ok=True)
check = Checks()
tool = tools(BIN)


def head_above(name, pos, rgb, up, want=True, by=0.25):
    """the head's mean height above the body's by a part of the height (a quarter)"""
    nh, nb, lift = head_lift(pos, rgb, up)
    ok = nh > 10 and nb > 10 and (lift > by) == want
    check(ok, f"{name}: head {'above' if want else 'not above'} the body along axis {'xyz'[up]} "
              f"(head {nh}, body {nb}, lift {lift:+.2f} of the height)")


def dump_cells(svo):
    a = np.fromstring(tool("svo_info", svo, "--dump"), dtype=np.int64, sep=" ").reshape(-1, 7)
    return a[:, :3].astype(float), a[:, 3:6] / 255.0


svo = os.path.join(WORK, "duck.svo")
tool("vox2svo", DUCK, svo, "--res", "64")
pos, rgb = dump_cells(svo)
head_above(".svo (grid z)", pos, rgb, 2)

control = os.path.join(WORK, "duck-yup.svo")
tool("vox2svo", DUCK, control, "--res", "64", "--y-up")
cpos, crgb = dump_cells(control)
head_above("control: --y-up (glTF's axes kept)", cpos, crgb, 2, want=False)
head_above("control: --y-up (glTF's axes kept)", cpos, crgb, 1)

# ---- the default view ----------------------------------------------------------
try:
    import voxkit
except ImportError as e:
    print(f"skip: the default view (no voxkit module: {e})")
    voxkit = None
if voxkit is not None:
    for name, path, want in (("default view (image rows)", svo, True), ("control: default view of --y-up", control, False)):
        img = voxkit.open(path).render(96, 96, mode="albedo", cpu=True)
        rows = np.repeat(np.arange(96), 96).astype(float)
        px = img[:, :, :3].reshape(-1, 3)
        hit = img[:, :, 3].reshape(-1) > 0
        # image rows grow downwards: height = -row; seen from above, so a smaller lift
        head_above(name, np.stack([rows * 0, rows * 0, -rows], 1)[hit], px[hit], 2, want, by=0.12)

# ---- .vox export (MagicaVoxel, +Z up) -------------------------------------------
vox = os.path.join(WORK, "duck.vox")
tool("svo_info", svo, "--to-vox", vox)
data = open(vox, "rb").read()
check(data[:4] == b"VOX ", ".vox export starts with 'VOX '")
xyzi, palette, rotations = [], None, []
off = 8 + 12  # header, MAIN chunk header
while off + 12 <= len(data):
    cid, n, m = data[off:off + 4], *struct.unpack_from("<ii", data, off + 4)
    body = data[off + 12:off + 12 + n]
    if cid == b"XYZI":
        count = struct.unpack_from("<i", body)[0]
        xyzi.append(np.frombuffer(body, np.uint8, 4 * count, 4).reshape(-1, 4))
    elif cid == b"RGBA":
        palette = np.frombuffer(body, np.uint8).reshape(256, 4)
    elif cid == b"nTRN":  # node id, attributes DICT, child, reserved, layer, frames, frame DICTs
        p = 4

        def rstr(p):
            k = struct.unpack_from("<i", body, p)[0]
            return body[p + 4:p + 4 + k].decode(), p + 4 + k

        def rdict(p):
            d, k = {}, struct.unpack_from("<i", body, p)[0]
            p += 4
            for _ in range(k):
                key, p = rstr(p)
                val, p = rstr(p)
                d[key] = val
            return d, p

        _, p = rdict(p)
        p += 12
        frames = struct.unpack_from("<i", body, p)[0]
        p += 4
        for _ in range(frames):
            f, p = rdict(p)
            rotations.append(f.get("_r", "4"))
    off += 12 + n + m
check(len(xyzi) == 1 and palette is not None, f".vox export: {len(xyzi)} model, a palette")
check(all(r == "4" for r in rotations), f".vox export: no rotation in the scene graph ({rotations})")
if xyzi and palette is not None:
    v = np.vstack(xyzi)
    head_above(".vox export (MagicaVoxel z)", v[:, :3].astype(float), palette[v[:, 3].astype(int) - 1][:, :3] / 255.0, 2)

# ---- .glb export (glTF, +Y up) --------------------------------------------------
glb = os.path.join(WORK, "duck.glb")
tool("svo_info", svo, "--to-glb", glb)
pos, rgb, _, _ = read_glb(glb)
head_above(".glb export (glTF y, node matrices applied)", pos, to_srgb(rgb), 1)

check.exit()
