"""ctest test_blender: a real client reads voxkit's exports. Blender (Debian's
`blender`, headless) imports `svo_info --to-glb` and `--to-vdb` files through
its own importers (blender_dump.py runs inside Blender); what it made of them
is compared with the files as read here without Blender (tests/common/glbduck.py)
and with `svo_info --dump`:
  - .glb: one Blender object per mesh node; every vertex of the file, no more,
    no fewer, at its place once glTF's +Y up is turned into Blender's +Z up
    (x, y, z) -> (x, -z, y), with its colour (to the sRGB byte Blender stores);
    the corpus Duck stands upright in Blender (head above body along +Z); the
    demo's materials (metal, glass, emission) with the file's values.
  - .vdb: a volume with the grids "density" (float) and "color" (vec3), the
    .svo's world_from_grid (svo_info's "world" line) with voxel centres at cell
    centres, and a bounding box around exactly the dumped cells (to OpenVDB's
    8^3 leaves, which Blender reports).
Skipped (exit 77) when Blender is not installed.

Usage: python3 test_blender.py BIN_DIR CORPUS_DIR WORK_DIR BLENDER
"""
import os
import shutil
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "common"))
from vxtest import Checks, tools  # noqa: E402
from glbduck import head_lift, read_glb, to_srgb  # noqa: E402

BIN, CORPUS, WORK = sys.argv[1:4]
BLENDER = sys.argv[4] if len(sys.argv) > 4 and sys.argv[4] else shutil.which("blender")
if not BLENDER or not os.path.exists(BLENDER):
    print("skip: Blender not installed (scripts/install-deps.sh installs Debian's blender)")
    sys.exit(77)
shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)
check = Checks()
tool = tools(BIN)


def blender(kind, src):
    out = os.path.join(WORK, os.path.basename(src) + ".npz")
    r = subprocess.run([BLENDER, "-b", "--factory-startup", "--python-exit-code", "1", "--python",
                        os.path.join(HERE, "blender_dump.py"), "--", kind, src, out], capture_output=True, text=True)
    if r.returncode != 0 or not os.path.exists(out):
        print(r.stdout[-3000:], r.stderr[-3000:])
        check(False, f"Blender imports {os.path.basename(src)}")
        return None
    return np.load(out)


def keys(pos, rgb):
    """rows sorted by position (to 1e-4) and sRGB byte colour"""
    k = np.hstack([np.round(pos * 1e4), np.round(to_srgb(np.clip(rgb, 0, 1)) * 255)]).astype(np.int64)
    return k[np.lexsort(k.T[::-1])]


def check_glb(name, glb, duck=False):
    pos, rgb, nodes, _ = read_glb(glb)
    b = blender("glb", glb)
    if b is None:
        return
    check(int(b["objects"]) == nodes, f"{name}.glb: {int(b['objects'])} Blender mesh objects for {nodes} mesh nodes")
    bpos, brgb = b["pos"], b["col"][:, :3]
    check(len(bpos) == len(pos), f"{name}.glb: {len(bpos)} vertices in Blender, {len(pos)} in the file")
    if len(bpos) != len(pos):
        return
    zup = np.stack([pos[:, 0], -pos[:, 2], pos[:, 1]], 1)  # glTF +Y up -> Blender +Z up
    a, c = keys(zup, rgb), keys(bpos, brgb)
    dpos = np.abs(a[:, :3] - c[:, :3]).max() if len(a) else 0
    dcol = np.abs(a[:, 3:] - c[:, 3:]).max() if len(a) else 0
    check(dpos <= 1, f"{name}.glb: every vertex where the file puts it, +Z up (largest difference {dpos} e-4)")
    check(dcol <= 1, f"{name}.glb: every vertex with the file's colour (largest difference {dcol} of 255)")
    # control: without the turn to +Z up the same vertices do not match
    if len(a) and np.ptp(pos[:, 1]) > 0:
        check(not np.array_equal(keys(pos, rgb)[:, :3], c[:, :3]), f"{name}.glb: control: glTF's +Y-up positions differ from Blender's")
    if duck:
        nh, nb, lift = head_lift(bpos, to_srgb(np.clip(brgb, 0, 1)), 2)
        check(nh > 10 and nb > 10 and lift > 0.25,
              f"{name}.glb: stands upright in Blender (head {nh}, body {nb} vertices, head {lift:+.2f} of the height above the body along +Z)")


def check_materials(name, glb):
    """Blender's materials against the file's: every glTF material by name with
    its metallic, roughness, transmission and emission (factor x strength)"""
    _, _, _, g = read_glb(glb)
    b = blender("glb", glb)
    if b is None:
        return
    got = dict(zip(b["mat_names"].tolist(), b["mat_values"].tolist()))
    vals = list(got.values())
    check(any(v[0] > 0 for v in vals) and any(v[2] > 0 for v in vals) and any(max(v[3:]) > 0 for v in vals),
          f"{name}.glb: Blender has a metal, a transmissive and an emissive material ({len(vals)} materials)")
    for m in g.get("materials", []):
        pbr = m.get("pbrMetallicRoughness", {})
        ext = m.get("extensions", {})
        k = ext.get("KHR_materials_emissive_strength", {}).get("emissiveStrength", 1.0)
        want = [pbr.get("metallicFactor", 1.0), pbr.get("roughnessFactor", 1.0),
                ext.get("KHR_materials_transmission", {}).get("transmissionFactor", 0.0)] + \
            [c * k for c in m.get("emissiveFactor", [0, 0, 0])]
        have = got.get(m["name"])
        check(have is not None and np.allclose(have, want, atol=1e-4),
              f"{name}.glb: Blender's material '{m['name']}' {np.round(have, 4).tolist() if have else None} "
              f"(metallic, roughness, transmission, emission) is the file's {np.round(want, 4).tolist()}")


def check_vdb(name, svo):
    vdb = os.path.join(WORK, name + ".vdb")
    colours = b"colours" in tool("svo_info", svo, "--to-vdb", vdb)  # "wrote ... (N grids, ..., colours)"
    dump = np.fromstring(tool("svo_info", svo, "--dump"), dtype=np.int64, sep=" ").reshape(-1, 7)
    cells = dump[:, :3]
    b = blender("vdb", vdb)
    if b is None:
        return
    grids = list(zip(b["names"].tolist(), b["types"].tolist(), b["channels"].tolist()))
    want = [("density", "FLOAT", 1)] + ([("color", "VECTOR_FLOAT", 3)] if colours else [])
    check(grids == want, f"{name}.vdb: Blender volume grids {grids}")
    W = world_from_grid(svo)
    m, want_m = b["matrix"], W.copy()
    want_m[:3, 3] = W[:3, :3] @ np.full(3, 0.5) + W[:3, 3]  # index i's centre is cell i's centre
    check(np.allclose(m[:3, :4], want_m, atol=1e-5),
          f"{name}.vdb: the svo's world_from_grid with voxel centres at cell centres (index-to-object {m[:3, 3].tolist()})")

    def world_box(lo, hi):
        corners = np.array([[(lo, hi)[(k >> a) & 1][a] for a in range(3)] for k in range(8)])
        w = corners @ W[:3, :3].T + W[:3, 3]
        return w.min(0), w.max(0)

    inner = world_box(cells.min(0) + 0.5, cells.max(0) + 0.5)
    outer = world_box(np.floor(cells.min(0) / 8) * 8 + 0.5, np.floor(cells.max(0) / 8) * 8 + 7.5)
    bb, eps = b["bbox"], 1e-4 * max(1.0, np.abs(W[:3, :3]).max())
    ok = np.all(bb[0] <= inner[0] + eps) and np.all(bb[0] >= outer[0] - eps) and np.all(bb[1] >= inner[1] - eps) \
        and np.all(bb[1] <= outer[1] + eps)
    check(ok, f"{name}.vdb: Blender's bounds {np.round(bb, 4).tolist()} hold the cell centres "
              f"{np.round(inner[0], 4).tolist()}..{np.round(inner[1], 4).tolist()} within OpenVDB's 8^3 leaves")


def world_from_grid(svo):
    """svo_info's 'world' line as a 3x4 matrix (identity when grid cells are world units)"""
    for line in tool("svo_info", svo).decode().splitlines():
        if line.startswith("world"):
            if "grid cells are world units" in line:
                return np.hstack([np.eye(3), np.zeros((3, 1))])
            rows = [r.split("]")[0] for r in line.split("[")[1:4]]
            return np.array([[float(v) for v in r.replace("|", " ").split()] for r in rows])
    raise RuntimeError(f"svo_info {svo}: no 'world' line")


demo_vox, demo = os.path.join(WORK, "demo.vox"), os.path.join(WORK, "demo.svo")
tool("vox2svo", "-q", "--write-demo", demo_vox)
tool("vox2svo", "-q", demo_vox, demo)
tool("svo_info", demo, "--to-glb", os.path.join(WORK, "demo.glb"), "-q")
check_glb("demo", os.path.join(WORK, "demo.glb"))
# the demo's lamps (emission), greenhouse (glass) and statue (metal) as Blender reads them
check_materials("demo", os.path.join(WORK, "demo.glb"))
check_vdb("demo", demo)

duck = os.path.join(CORPUS, "gltf", "julian_Duck.glb")
if os.path.exists(duck):
    dsvo = os.path.join(WORK, "duck.svo")
    tool("vox2svo", "-q", duck, dsvo, "--res", "64")
    tool("svo_info", dsvo, "--to-glb", os.path.join(WORK, "duck.glb"), "-q")
    check_glb("duck", os.path.join(WORK, "duck.glb"), duck=True)
    check_vdb("duck", dsvo)
else:
    print(f"skip the Duck: {duck} not found")

check.exit()
