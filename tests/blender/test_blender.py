"""ctest test_blender: a real client reads voxkit's exports. Blender (Debian's
`blender`, headless) imports `svo_info --to-glb` and `--to-vdb` files through
its own importers (blender_dump.py runs inside Blender); what it made of them
is compared with the files as read here without Blender (tests/common/glbduck.py)
and with `svo_info --dump`:
  - .glb: one Blender object per mesh node; every vertex of the file, no more,
    no fewer, at its place once glTF's +Y up is turned into Blender's +Z up
    (x, y, z) -> (x, -z, y), with its colour (to the sRGB byte Blender stores);
    the corpus Duck stands upright in Blender (head above body along +Z); the
    demo's materials (metal, glass, emission) with the file's values; the
    lights of tests/glb/lights.gltf (through vox2svo and --to-glb) with their
    types, places and aims (Blender's +Z-up world is voxkit's: the two turns
    cancel, so they are the .svo's own), colours, energies (Blender 3.4's
    conversion: W = lm / 683, 4 pi W/sr per candela) and spot cones.
  - .vdb: a volume with the grids "density" (float) and "color" (vec3), the
    .svo's world_from_grid (svo_info's "world" line) with voxel centres at cell
    centres, and a bounding box around exactly the dumped cells (to OpenVDB's
    8^3 leaves, which Blender reports).
Skipped (exit 77) when Blender is not installed.

Usage: python3 test_blender.py BIN_DIR CORPUS_DIR WORK_DIR BLENDER
"""
import math
import os
import re
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


# Blender 3.4's glTF importer (io_scene_gltf2/blender/imp/gltf2_blender_light.py,
# lighting mode "Standard", its default): a sun's strength is lux / 683 W/m^2,
# a point or spot light's power candela x 4 pi / 683 W
WATTS_TO_LUMENS = 683.0


def svo_lights(svo):
    """{index: (type, position, where it shines)} from svo_info's light lines (voxkit's +Z up)"""
    out = {}
    for line in tool("svo_info", svo, "--models").decode().splitlines():
        m = re.match(r"light (\d+) +(\w+) ", line)
        if not m:
            continue

        def vec(key):
            v = re.search(key + r" \(([^)]*)\)", line)
            return np.array([float(x) for x in v.group(1).split()]) if v else None
        kind = m.group(2)
        aim = {"sun": lambda: -vec("towards"), "spot": lambda: vec("towards"), "rect": lambda: vec("normal")}.get(kind)
        d = aim() if aim else None
        out[int(m.group(1))] = (kind, vec("at") if kind != "sun" else None, d / np.linalg.norm(d) if d is not None else None)
    return out


def check_lights(name, svo, glb):
    """Blender's lights against the file's KHR_lights_punctual lights (turned +Z up)
    and the .svo's own lights: type, place, aim, colour, energy, spot cones"""
    _, _, _, g = read_glb(glb)
    b = blender("glb", glb)
    if b is None:
        return
    lights = g["extensions"]["KHR_lights_punctual"]["lights"]
    nodes = [n for n in g["nodes"] if "KHR_lights_punctual" in n.get("extensions", {})]
    got = {n: k for k, n in enumerate(b["light_names"].tolist())}
    check(len(got) == len(nodes) > 0, f"{name}.glb: {len(got)} Blender lights for {len(nodes)} light nodes")
    mine = svo_lights(svo)
    blender_type = {"directional": "SUN", "point": "POINT", "spot": "SPOT"}
    voxkit_type = {"directional": "sun", "point": "point", "spot": "spot", "sphere": "sphere", "rect": "rect"}
    for node in nodes:
        L = lights[node["extensions"]["KHR_lights_punctual"]["light"]]
        k = got.get(node["name"])
        if k is None:
            check(False, f"{name}.glb: no Blender light '{node['name']}'")
            continue
        M = np.array(node.get("matrix", np.eye(4).reshape(-1))).reshape(4, 4).T  # column-major
        zup = lambda v: np.array([v[0], -v[2], v[1]])  # noqa: E731  glTF +Y up -> Blender +Z up
        want_pos, want_dir = zup(M[:3, 3]), zup(-M[:3, 2])
        want_dir /= np.linalg.norm(want_dir)
        pos, d = b["light_pos"][k], b["light_dir"][k]
        col, energy, size, blend = b["light_values"][k][:3], b["light_values"][k][3], b["light_values"][k][4], b["light_values"][k][5]
        t = L["type"]
        check(b["light_types"][k] == blender_type[t], f"{name}.glb: '{node['name']}' a {t} light, Blender's {b['light_types'][k]}")
        check(np.allclose(pos, want_pos, atol=1e-5), f"{name}.glb: '{node['name']}' at {np.round(pos, 5).tolist()} in Blender, "
                                                     f"the file's turned +Z up {np.round(want_pos, 5).tolist()}")
        if t != "point":
            check(np.allclose(d, want_dir, atol=1e-5), f"{name}.glb: '{node['name']}' shines along {np.round(d, 5).tolist()}, "
                                                       f"the file's {np.round(want_dir, 5).tolist()}")
        check(np.allclose(col, L.get("color", [1, 1, 1]), atol=1e-6), f"{name}.glb: '{node['name']}' colour {np.round(col, 6).tolist()}")
        I = L.get("intensity", 1.0)
        want_e = I / WATTS_TO_LUMENS * (1 if t == "directional" else 4 * math.pi)
        check(abs(energy - want_e) <= 1e-5 * max(1, want_e),
              f"{name}.glb: '{node['name']}' energy {energy:.6g} W, the file's {I:g} {'lux' if t == 'directional' else 'cd'} "
              f"as Blender converts it ({want_e:.6g})")
        if t == "spot":
            sp = L.get("spot", {})
            outer, inner = sp.get("outerConeAngle", math.pi / 4), sp.get("innerConeAngle", 0.0)
            check(abs(size - 2 * outer) < 1e-5 and abs(blend - (1 - inner / outer)) < 1e-5,
                  f"{name}.glb: '{node['name']}' spot size {size:.6g} blend {blend:.6g} for cones {inner:g}..{outer:g}")
        # the .svo's own light: Blender's +Z-up world is voxkit's
        idx = int(node["name"].split()[1])
        rec = L.get("extras", {}).get("voxkit_light", {}).get("type", "")
        kind, p, aim = mine.get(idx, (None, None, None))
        check(kind == voxkit_type[rec or t], f"{name}.glb: '{node['name']}' is the .svo's light {idx} ({kind})")
        if p is not None:
            check(np.allclose(pos, p, atol=1e-4 * (1 + np.abs(p).max())),
                  f"{name}.glb: '{node['name']}' where the .svo puts light {idx} ({p.tolist()})")
        if aim is not None:
            check(np.allclose(d, aim, atol=1e-4), f"{name}.glb: '{node['name']}' aimed as the .svo's light {idx} ({np.round(aim, 5).tolist()})")
        check(b["light_records"][k] == rec, f"{name}.glb: '{node['name']}' keeps voxkit's record '{rec}' as a custom property "
                                           f"('{b['light_records'][k]}')")


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

# lights: tests/glb/lights.gltf (directional, point, spot and voxkit's sphere and rect) through vox2svo and --to-glb
lsvo, lglb = os.path.join(WORK, "lights.svo"), os.path.join(WORK, "lights.glb")
tool("vox2svo", "-q", os.path.join(HERE, "..", "glb", "lights.gltf"), lsvo, "--res", "8")
tool("svo_info", lsvo, "--to-glb", lglb, "-q")
check_glb("lights", lglb)
check_lights("lights", lsvo, lglb)

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
