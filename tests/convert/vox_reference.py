"""An independent .vox reader against vox2svo (ctest vox_reference).

The reader below is written from MagicaVoxel's own format notes
(ephtracy/voxel-model: MagicaVoxel-file-format-vox.txt and
MagicaVoxel-file-format-vox-extension.txt), not from formats/vox.c, and only
with the standard library. It walks the scene graph from node 0 and yields the
world cell and colour of every visible voxel; the test converts the same file
with vox2svo and compares with `svo_info OUT.svo --dump` (sorted lists, so a
voxel lost, added, moved or recoloured shows).

Conventions, as MagicaVoxel's notes and its editor have them:
  - XYZI colour index i (1..255) is RGBA entry i-1 of the file ("color [0-254]
    are mapped to palette index [1-255]"); without RGBA the default palette's
    entry i (whose [0] is 0). Index 0, and voxels outside SIZE, are no voxel.
  - _r: row-major signed permutation; bits 0-1 the column of row 0's non-zero
    entry, bits 2-3 row 1's, row 2 takes the column left; bits 4, 5, 6 the
    signs of rows 0, 1, 2. _t: three integers.
  - A shape's voxel v (model size s) covers the unit cube [v, v+1] of its model
    whose pivot is floor(s/2) (ogt_vox's "EXPLANATION OF MODEL PIVOTS"); the
    transforms from the shape up to node 0 act on that cube, and the world cell
    is the one its centre lands in: floor(R (v + 1/2 - floor(s/2)) + t).
  - _hidden "1" on a transform node hides its subtree, on a group node (which
    MagicaVoxel writes beside its transform's) likewise; a transform whose layer
    id is a LAYR with _hidden "1" likewise, at any depth. nSHP attributes are
    "reserved" in the notes: a _hidden there hides nothing. Frame f of an animation: the nTRN
    frame and the nSHP model whose _f is the largest <= f (the first if none).
  - Without nTRN/nGRP/nSHP: model 0 (model f of a PACK sequence) at the
    identity, same pivot.
  - Teardown's .vox: a model's voxels in a TDCZ chunk after its SIZE instead
    of XYZI: the three sizes again (refused unless they are SIZE's), then a
    zlib stream of one colour index per cell, x fastest (x + y sx + z sx sy),
    0 empty. Teardown stops the stream after the last cell (no final block, no
    Adler-32), so it counts as whole once it has given every cell, whatever
    follows; one that gives fewer is refused. Its RGBA chunk has 255 entries
    (1020 bytes); any whole number of entries up to 256 is read, the indices
    it lacks keeping the default palette's colours (as ogt_vox does).

The files checked: every .vox of CORPUS/vox (skipped with a message where
absent; files over VX_REF_MAX_BYTES, default 1 MiB, are left out, said so),
every .vox under $VX_EXTRA_VOX when set (no size cap; a file the reader
refuses, such as another program's .vox, must be refused by vox2svo too), and
scenes this script writes itself: all 48 rotation bytes (24 turns, 24
mirrored) on models of odd, even and unequal sides, turned and mirrored nested
groups, group instances (several transforms on one group), models of side
256, hidden nodes, groups and layers (also with --keep-hidden against
--dump --all), a default-palette model without a scene graph, keyframes
(_f) on a transform and a shape, one scene written with XYZI and with TDCZ
(unterminated, terminated with bytes after it), RGBA chunks of 255 and 16
entries, and files both must refuse (a TDCZ stream short of its cells, TDCZ
sizes that are not SIZE's, an RGBA chunk ending inside an entry: vox2svo
exits 1 naming the file and the chunk, and writes no file). An animated file
is also checked at frames 1, 2 and its last, a file with hidden parts also
with --keep-hidden.
Each generated scene is checked twice: the cells against the reader, and the
reader's cells against ones computed here from the scene's own description
(so a reader mistake cannot hide a converter one of the same kind).

Usage: python3 vox_reference.py BIN_DIR CORPUS_DIR WORK_DIR
       python3 vox_reference.py --cells FILE.vox [--frame N] [--all]
"""
import os
import struct
import subprocess
import sys
import time
import zlib

# ---- the default palette (MagicaVoxel-file-format-vox.txt, section 8) -------
# 0xAABBGGRR values, index i is colour index i; [0] is 0.
DEFAULT_PALETTE = [
    0x00000000, 0xffffffff, 0xffccffff, 0xff99ffff, 0xff66ffff, 0xff33ffff, 0xff00ffff, 0xffffccff,
    0xffccccff, 0xff99ccff, 0xff66ccff, 0xff33ccff, 0xff00ccff, 0xffff99ff, 0xffcc99ff, 0xff9999ff,
    0xff6699ff, 0xff3399ff, 0xff0099ff, 0xffff66ff, 0xffcc66ff, 0xff9966ff, 0xff6666ff, 0xff3366ff,
    0xff0066ff, 0xffff33ff, 0xffcc33ff, 0xff9933ff, 0xff6633ff, 0xff3333ff, 0xff0033ff, 0xffff00ff,
    0xffcc00ff, 0xff9900ff, 0xff6600ff, 0xff3300ff, 0xff0000ff, 0xffffffcc, 0xffccffcc, 0xff99ffcc,
    0xff66ffcc, 0xff33ffcc, 0xff00ffcc, 0xffffcccc, 0xffcccccc, 0xff99cccc, 0xff66cccc, 0xff33cccc,
    0xff00cccc, 0xffff99cc, 0xffcc99cc, 0xff9999cc, 0xff6699cc, 0xff3399cc, 0xff0099cc, 0xffff66cc,
    0xffcc66cc, 0xff9966cc, 0xff6666cc, 0xff3366cc, 0xff0066cc, 0xffff33cc, 0xffcc33cc, 0xff9933cc,
    0xff6633cc, 0xff3333cc, 0xff0033cc, 0xffff00cc, 0xffcc00cc, 0xff9900cc, 0xff6600cc, 0xff3300cc,
    0xff0000cc, 0xffffff99, 0xffccff99, 0xff99ff99, 0xff66ff99, 0xff33ff99, 0xff00ff99, 0xffffcc99,
    0xffcccc99, 0xff99cc99, 0xff66cc99, 0xff33cc99, 0xff00cc99, 0xffff9999, 0xffcc9999, 0xff999999,
    0xff669999, 0xff339999, 0xff009999, 0xffff6699, 0xffcc6699, 0xff996699, 0xff666699, 0xff336699,
    0xff006699, 0xffff3399, 0xffcc3399, 0xff993399, 0xff663399, 0xff333399, 0xff003399, 0xffff0099,
    0xffcc0099, 0xff990099, 0xff660099, 0xff330099, 0xff000099, 0xffffff66, 0xffccff66, 0xff99ff66,
    0xff66ff66, 0xff33ff66, 0xff00ff66, 0xffffcc66, 0xffcccc66, 0xff99cc66, 0xff66cc66, 0xff33cc66,
    0xff00cc66, 0xffff9966, 0xffcc9966, 0xff999966, 0xff669966, 0xff339966, 0xff009966, 0xffff6666,
    0xffcc6666, 0xff996666, 0xff666666, 0xff336666, 0xff006666, 0xffff3366, 0xffcc3366, 0xff993366,
    0xff663366, 0xff333366, 0xff003366, 0xffff0066, 0xffcc0066, 0xff990066, 0xff660066, 0xff330066,
    0xff000066, 0xffffff33, 0xffccff33, 0xff99ff33, 0xff66ff33, 0xff33ff33, 0xff00ff33, 0xffffcc33,
    0xffcccc33, 0xff99cc33, 0xff66cc33, 0xff33cc33, 0xff00cc33, 0xffff9933, 0xffcc9933, 0xff999933,
    0xff669933, 0xff339933, 0xff009933, 0xffff6633, 0xffcc6633, 0xff996633, 0xff666633, 0xff336633,
    0xff006633, 0xffff3333, 0xffcc3333, 0xff993333, 0xff663333, 0xff333333, 0xff003333, 0xffff0033,
    0xffcc0033, 0xff990033, 0xff660033, 0xff330033, 0xff000033, 0xffffff00, 0xffccff00, 0xff99ff00,
    0xff66ff00, 0xff33ff00, 0xff00ff00, 0xffffcc00, 0xffcccc00, 0xff99cc00, 0xff66cc00, 0xff33cc00,
    0xff00cc00, 0xffff9900, 0xffcc9900, 0xff999900, 0xff669900, 0xff339900, 0xff009900, 0xffff6600,
    0xffcc6600, 0xff996600, 0xff666600, 0xff336600, 0xff006600, 0xffff3300, 0xffcc3300, 0xff993300,
    0xff663300, 0xff333300, 0xff003300, 0xffff0000, 0xffcc0000, 0xff990000, 0xff660000, 0xff330000,
    0xff0000ee, 0xff0000dd, 0xff0000bb, 0xff0000aa, 0xff000088, 0xff000077, 0xff000055, 0xff000044,
    0xff000022, 0xff000011, 0xff00ee00, 0xff00dd00, 0xff00bb00, 0xff00aa00, 0xff008800, 0xff007700,
    0xff005500, 0xff004400, 0xff002200, 0xff001100, 0xffee0000, 0xffdd0000, 0xffbb0000, 0xffaa0000,
    0xff880000, 0xff770000, 0xff550000, 0xff440000, 0xff220000, 0xff110000, 0xffeeeeee, 0xffdddddd,
    0xffbbbbbb, 0xffaaaaaa, 0xff888888, 0xff777777, 0xff555555, 0xff444444, 0xff222222, 0xff111111,
]
assert len(DEFAULT_PALETTE) == 256


class VoxError(Exception):
    pass


# ---- reading ---------------------------------------------------------------
class Cursor:
    def __init__(self, data, pos=0, end=None):
        self.d, self.p, self.end = data, pos, len(data) if end is None else end

    def take(self, n):
        if n < 0 or self.p + n > self.end:
            raise VoxError(f"truncated at byte {self.p}: {n} wanted, {self.end - self.p} left")
        b = self.d[self.p:self.p + n]
        self.p += n
        return b

    def i32(self):
        return struct.unpack("<i", self.take(4))[0]

    def string(self):
        return self.take(self.i32()).decode("latin-1")

    def dict(self):
        return {self.string(): self.string() for _ in range(self.i32())}


def rot_from_byte(b):
    """_r -> row-major 3x3 (ROTATION type, the extension's section (c))"""
    c0, c1 = b & 3, (b >> 2) & 3
    if c0 > 2 or c1 > 2 or c0 == c1:
        raise VoxError(f"invalid _r {b}")
    cols = (c0, c1, 3 - c0 - c1)
    m = [0] * 9
    for row in range(3):
        m[row * 3 + cols[row]] = -1 if (b >> (4 + row)) & 1 else 1
    return m


def mat_mul(a, b):
    return [sum(a[r * 3 + k] * b[k * 3 + c] for k in range(3)) for r in range(3) for c in range(3)]


def mat_vec(a, v):
    return [a[r * 3] * v[0] + a[r * 3 + 1] * v[1] + a[r * 3 + 2] * v[2] for r in range(3)]


IDENTITY = [1, 0, 0, 0, 1, 0, 0, 0, 1]


def inflate_cells(stream, cells):
    """the first `cells` bytes of a zlib stream, or what it gives before it
    ends or breaks (fewer): Teardown's streams stop after the last cell with
    no final block and no Adler-32, and what follows the cells is not read"""
    try:
        return zlib.decompressobj().decompress(stream, cells)
    except zlib.error:
        pass
    # broken somewhere: fed a byte at a time, so that a break after the last
    # cell (bytes after the stream that are no deflate data) does not count
    d, out = zlib.decompressobj(), b""
    for k in range(len(stream)):
        try:
            out += d.decompress(stream[k:k + 1], cells - len(out))
        except zlib.error:
            break
        if len(out) == cells:
            break
    return out


def tdcz_voxels(size, stream, where):
    sx, sy, sz = size
    if min(size) < 1:
        raise VoxError(f"{where}: size {size} has a side below 1")
    cells = sx * sy * sz
    out = inflate_cells(stream, cells)
    if len(out) < cells:
        raise VoxError(f"{where}: the compressed voxels end after {len(out)} of {cells} cells")
    sxy = sx * sy
    return [(k % sx, (k // sx) % sy, k // sxy, i) for k, i in enumerate(out) if i]


def parse(data):
    """the file's chunks: models [(size, [(x,y,z,i)...])], palette (256 RGBA
    tuples by colour index), nodes {id: (kind, ...)}, layers {id: dict}"""
    if data[:4] != b"VOX ":
        raise VoxError("not a .vox file (no 'VOX ' magic)")
    top = Cursor(data, 8)
    if top.take(4) != b"MAIN":
        raise VoxError("no MAIN chunk")
    n, m = top.i32(), top.i32()
    top.take(n)
    kids = Cursor(data, top.p, min(len(data), top.p + m))
    models, pending_size, rgba = [], None, None
    nodes, layers = {}, {}
    while kids.p + 12 <= kids.end:
        cid = kids.take(4)
        n, m = kids.i32(), kids.i32()
        c = Cursor(data, kids.p, kids.p + n)
        if kids.p + n > kids.end:
            raise VoxError(f"chunk {cid!r} at byte {kids.p - 12} overruns MAIN")
        kids.p += n + m
        if cid == b"SIZE":
            pending_size = (c.i32(), c.i32(), c.i32())
        elif cid == b"XYZI":
            if pending_size is None:
                raise VoxError("XYZI without SIZE")
            count = c.i32()
            raw = c.take(4 * count)
            models.append((pending_size, list(struct.iter_unpack("4B", raw))))
            pending_size = None
        elif cid == b"TDCZ":
            where = f"TDCZ chunk at byte {c.p - 12}"
            if pending_size is None:
                raise VoxError(f"{where}: no SIZE before it")
            sizes = (c.i32(), c.i32(), c.i32())
            if sizes != pending_size:
                raise VoxError(f"{where}: sizes {sizes} are not SIZE's {pending_size}")
            models.append((pending_size, tdcz_voxels(pending_size, c.take(c.end - c.p), where)))
            pending_size = None
        elif cid == b"RGBA":
            # entry k is colour index k + 1; a 256th entry is not used
            n = c.end - c.p
            if n < 1024 and n % 4:
                raise VoxError(f"RGBA chunk at byte {c.p - 12}: {n} bytes, not whole 4-byte entries")
            raw = c.take(min(n, 1020))
            rgba = [tuple((v >> s) & 255 for s in (0, 8, 16, 24)) for v in DEFAULT_PALETTE]
            rgba[0] = (0, 0, 0, 0)
            for k in range(len(raw) // 4):
                rgba[k + 1] = tuple(raw[4 * k:4 * k + 4])
        elif cid == b"nTRN":
            nid, attr = c.i32(), c.dict()
            child, _reserved, layer, nf = c.i32(), c.i32(), c.i32(), c.i32()
            frames = [c.dict() for _ in range(nf)]
            nodes[nid] = ("T", attr, child, layer, frames)
        elif cid == b"nGRP":
            nid, attr = c.i32(), c.dict()
            nodes[nid] = ("G", attr, [c.i32() for _ in range(c.i32())])
        elif cid == b"nSHP":
            nid, attr = c.i32(), c.dict()
            shapes = []
            for _ in range(c.i32()):
                shapes.append((c.i32(), c.dict()))
            nodes[nid] = ("S", attr, shapes)
        elif cid == b"LAYR":
            lid = c.i32()
            layers[lid] = c.dict()
    if rgba is None:
        rgba = [tuple((v >> s) & 255 for s in (0, 8, 16, 24)) for v in DEFAULT_PALETTE]
    return models, rgba, nodes, layers


def frame_pick(items, key, frame):
    """the item whose _f is the largest <= frame, else the first"""
    best, best_f = items[0], None
    for it in items:
        f = int(key(it).get("_f", "0"))
        if f <= frame and (best_f is None or f >= best_f):
            best, best_f = it, f
    return best


def frame_count(models, nodes):
    if not nodes:
        return len(models) if len(models) > 1 else 1
    top = 0
    for nd in nodes.values():
        dicts = nd[4] if nd[0] == "T" else [d for _, d in nd[2]] if nd[0] == "S" else []
        for d in dicts:
            if "_f" in d:
                top = max(top, int(d["_f"]))
    return top + 1


def instances(models, nodes, layers, frame=0, keep_hidden=False):
    """(model index, R, t) for every shape shown"""
    out = []
    if not nodes:
        if models:
            out.append((min(frame, len(models) - 1) if len(models) > 1 else 0, IDENTITY, [0, 0, 0]))
        return out
    hidden_layers = {lid for lid, d in layers.items() if d.get("_hidden", "0") == "1"}

    def walk(nid, R, t, depth):
        if depth > 1000 or nid not in nodes:
            raise VoxError(f"node {nid} missing or the graph too deep")
        nd = nodes[nid]
        if not keep_hidden and nd[0] != "S" and nd[1].get("_hidden", "0") == "1":
            return
        if nd[0] == "T":
            _, attr, child, layer, frames = nd
            if not keep_hidden and layer in hidden_layers:
                return
            fr = frame_pick(frames, lambda d: d, frame) if frames else {}
            r = rot_from_byte(int(fr["_r"])) if "_r" in fr else IDENTITY
            tt = [int(v) for v in fr["_t"].split()] if "_t" in fr else [0, 0, 0]
            # world(p) = R (r p + tt) + t
            walk(child, mat_mul(R, r), [a + b for a, b in zip(mat_vec(R, tt), t)], depth + 1)
        elif nd[0] == "G":
            for ch in nd[2]:
                walk(ch, R, t, depth + 1)
        else:
            mid, _ = frame_pick(nd[2], lambda s: s[1], frame)
            out.append((mid, R, t))

    walk(0, IDENTITY, [0, 0, 0], 0)
    return out


def model_cells(size, voxels):
    """{(x,y,z): colour index}: inside SIZE, index != 0, the last write wins"""
    cells = {}
    for x, y, z, i in voxels:
        if i and x < size[0] and y < size[1] and z < size[2]:
            cells[(x, y, z)] = i
    return cells


def place(R, t, size, v):
    """floor(R (v + 1/2 - floor(s/2)) + t), in halves so it stays exact"""
    h = [2 * v[k] + 1 - 2 * (size[k] // 2) for k in range(3)]
    hr = mat_vec(R, h)
    return tuple((hr[k] + 2 * t[k]) // 2 for k in range(3))


def scene_facts(path):
    """(frames, whether anything is hidden) of a file"""
    with open(path, "rb") as f:
        models, _, nodes, layers = parse(f.read())
    hidden = any(d.get("_hidden", "0") == "1" for d in layers.values()) or any(
        nd[0] != "S" and nd[1].get("_hidden", "0") == "1" for nd in nodes.values())
    return frame_count(models, nodes), hidden


def world_voxels(path, frame=0, keep_hidden=False):
    """sorted list of (x, y, z, r, g, b, a), one per voxel of each shape shown"""
    with open(path, "rb") as f:
        models, rgba, nodes, layers = parse(f.read())
    out = []
    cache = {}
    for mid, R, t in instances(models, nodes, layers, frame, keep_hidden):
        if mid < 0 or mid >= len(models):
            raise VoxError(f"shape refers to model {mid} of {len(models)}")
        size, vox = models[mid]
        if mid not in cache:
            cache[mid] = model_cells(size, vox)
        # R is a signed permutation: world axis r reads model axis col[r];
        # tables of place() along each axis (checked against place() below)
        col = [next(k for k in range(3) if R[r * 3 + k]) for r in range(3)]
        tab = []
        for r in range(3):
            e = [0, 0, 0]
            e[col[r]] = 1
            tab.append([place(R, t, size, [v * a for a in e])[r] for v in range(size[col[r]])])
        ax, ay, az = col
        tx, ty, tz = tab
        cells = cache[mid]
        for v, i in cells.items():
            out.append((tx[v[ax]], ty[v[ay]], tz[v[az]]) + rgba[i])
        for v in list(cells)[:8]:
            assert (tx[v[ax]], ty[v[ay]], tz[v[az]]) == place(R, t, size, v)
    out.sort()
    return out


# ---- writing (the generated scenes) -----------------------------------------
def _s(text):
    b = text.encode()
    return struct.pack("<i", len(b)) + b


def _d(d):
    return struct.pack("<i", len(d)) + b"".join(_s(k) + _s(v) for k, v in d.items())


def _chunk(cid, content, children=b""):
    return cid + struct.pack("<ii", len(content), len(children)) + content + children


def tdcz_content(size, voxels, finish=False, cells=None, sizes=None, tail=b""):
    """a TDCZ chunk's content: the sizes (`sizes`, else SIZE's), then the
    model's grid deflated (its first `cells` cells when given); finish False
    ends with a sync flush only, as Teardown's streams end (no final block, no
    Adler-32); tail follows the stream"""
    sx, sy, sz = size
    grid = bytearray(sx * sy * sz)
    for x, y, z, i in voxels:
        grid[x + y * sx + z * sx * sy] = i
    co = zlib.compressobj(9)
    data = co.compress(bytes(grid[:cells])) + co.flush(zlib.Z_FINISH if finish else zlib.Z_SYNC_FLUSH)
    return struct.pack("<iii", *(sizes or size)) + data + tail


def write_vox(path, models, nodes=(), layers=(), rgba=None, pack=False, tdcz=None):
    """models: [(size, voxels)]; nodes: [(kind, id, ...)] as in parse();
    layers: [(id, dict)]; rgba: RGBA tuples (file order, 256 as MagicaVoxel
    writes them, or fewer) or None; tdcz: None for XYZI chunks, else
    tdcz(model index, size, voxels) gives each model's TDCZ content"""
    body = b""
    if pack:
        body += _chunk(b"PACK", struct.pack("<i", len(models)))
    for mi, (size, vox) in enumerate(models):
        body += _chunk(b"SIZE", struct.pack("<iii", *size))
        if tdcz:
            body += _chunk(b"TDCZ", tdcz(mi, size, vox))
        else:
            body += _chunk(b"XYZI", struct.pack("<i", len(vox)) + bytes(c for v in vox for c in v))
    for nd in nodes:
        if nd[0] == "T":
            _, nid, attr, child, layer, frames = nd
            c = struct.pack("<i", nid) + _d(attr) + struct.pack("<iiii", child, -1, layer, len(frames))
            body += _chunk(b"nTRN", c + b"".join(_d(f) for f in frames))
        elif nd[0] == "G":
            _, nid, attr, kids = nd
            body += _chunk(b"nGRP", struct.pack("<i", nid) + _d(attr) + struct.pack("<i", len(kids))
                           + b"".join(struct.pack("<i", k) for k in kids))
        else:
            _, nid, attr, shapes = nd
            body += _chunk(b"nSHP", struct.pack("<i", nid) + _d(attr) + struct.pack("<i", len(shapes))
                           + b"".join(struct.pack("<i", m) + _d(d) for m, d in shapes))
    for lid, d in layers:
        body += _chunk(b"LAYR", struct.pack("<i", lid) + _d(d) + struct.pack("<i", -1))
    if rgba is not None:
        body += _chunk(b"RGBA", bytes(c for col in rgba for c in col))
    with open(path, "wb") as f:
        f.write(b"VOX " + struct.pack("<i", 150) + _chunk(b"MAIN", b"", body))


def _rgba_test():
    return [((37 * k) & 255, (91 * k + 7) & 255, (13 * k + 100) & 255, 255 - (k % 5)) for k in range(256)]


def _model(size, seed):
    """an asymmetric model: a corner marker, the three edges from voxel 0,
    and a scatter, colours varying with place (so a turn or mirror shows)"""
    sx, sy, sz = size
    vox = {}
    for x in range(sx):
        vox[(x, 0, 0)] = 1 + (x + seed) % 200
    for y in range(sy):
        vox[(0, y, 0)] = 30 + (y + seed) % 200
    for z in range(sz):
        vox[(0, 0, z)] = 60 + (z + seed) % 190
    vox[(sx - 1, sy - 1, sz - 1)] = 255
    k = seed * 7 + 3
    for _ in range(sx * sy * sz // 6):
        k = (k * 1103515245 + 12345) & 0x7FFFFFFF
        p = (k % sx, (k // sx) % sy, (k // (sx * sy)) % sz)
        vox[p] = 1 + (k >> 8) % 255
    return (sx, sy, sz), [(x, y, z, i) for (x, y, z), i in sorted(vox.items())]


def rot_byte(cols, signs):
    return cols[0] | (cols[1] << 2) | (signs[0] << 4) | (signs[1] << 5) | (signs[2] << 6)


ALL_ROTATIONS = sorted(rot_byte(c, (s0, s1, s2))
                       for c in [(0, 1, 2), (0, 2, 1), (1, 0, 2), (1, 2, 0), (2, 0, 1), (2, 1, 0)]
                       for s0 in (0, 1) for s1 in (0, 1) for s2 in (0, 1))


def _det(m):
    return (m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6])
            + m[2] * (m[3] * m[7] - m[4] * m[6]))


def generated_scenes(work):
    """(path, frame, expected voxels) for the scenes written here;
    expected comes from the scene's description, not from parse()"""
    rgba = _rgba_test()
    pal = [(0, 0, 0, 0)] + rgba[:255]
    out = []

    def expect(models, placed):
        cells = []
        for mid, R, t in placed:
            size, vox = models[mid]
            for x, y, z, i in vox:
                # the centre of cube [v, v+1] minus the pivot, turned, moved
                c = [(v + 0.5) - (s // 2) for v, s in zip((x, y, z), size)]
                w = [sum(R[r * 3 + k] * c[k] for k in range(3)) + t[r] for r in range(3)]
                cells.append(tuple(int(w[k] // 1) for k in range(3)) + pal[i])
        return sorted(cells)

    # 1. every rotation byte, on three models (odd, even, unequal sides)
    models = [_model((3, 3, 3), 1), _model((4, 2, 6), 2), _model((5, 4, 7), 3)]
    assert sorted({_det(rot_from_byte(b)) for b in ALL_ROTATIONS}) == [-1, 1] and len(ALL_ROTATIONS) == 48
    nodes = [("T", 0, {}, 1, -1, [{}]), None]
    kids, placed, nid = [], [], 2
    for k, b in enumerate(ALL_ROTATIONS):
        for mid in range(3):
            t = [k * 12 - 200, mid * 12 - 7, (k * 5 + mid * 3) % 11 - 5]
            nodes.append(("T", nid, {"_name": f"r{b}m{mid}"}, nid + 1, 0,
                          [{"_r": str(b), "_t": f"{t[0]} {t[1]} {t[2]}"}]))
            nodes.append(("S", nid + 1, {}, [(mid, {})]))
            kids.append(nid)
            placed.append((mid, rot_from_byte(b), t))
            nid += 2
    nodes[1] = ("G", 1, {}, kids)
    p = os.path.join(work, "gen_rotations.vox")
    write_vox(p, models, nodes, [(0, {})], rgba)
    out.append((p, 0, expect(models, placed)))

    # 2. nested groups, turned and mirrored at each level, with hidden parts:
    # node 0 T(_r a, _t) -> G1 -> [T2 (_r b) -> G3 -> [T4 -> S5 (m0), T6 (_r c) -> S7 (m1),
    #   T8 hidden -> S9], T10 (layer 1 hidden) -> S11, T12 (layer 2 shown) -> G13 hidden -> [T14 -> S15],
    #   T16 -> S17 (a _hidden in the nSHP's reserved attributes: shown), T18 -> G19 -> [T20 (_r d, layer 1: a nested layer id) -> S21 (m2)]]
    models = [_model((3, 5, 2), 4), _model((6, 1, 3), 5), _model((2, 2, 9), 6)]
    ra, rb, rc, rd = 0b0011001, 0b1100010, 0b0101001, 0b1001001
    ta, tb, tc, t4, td = [3, -4, 7], [10, 0, -3], [-2, 5, 1], [1, 1, 1], [0, 9, -6]
    nodes = [
        ("T", 0, {}, 1, -1, [{"_r": str(ra), "_t": " ".join(map(str, ta))}]),
        ("G", 1, {}, [2, 10, 12, 16, 18]),
        ("T", 2, {}, 3, 0, [{"_r": str(rb), "_t": " ".join(map(str, tb))}]),
        ("G", 3, {}, [4, 6, 8]),
        ("T", 4, {}, 5, -1, [{"_t": " ".join(map(str, t4))}]),
        ("S", 5, {}, [(0, {})]),
        ("T", 6, {}, 7, -1, [{"_r": str(rc), "_t": " ".join(map(str, tc))}]),
        ("S", 7, {}, [(1, {})]),
        ("T", 8, {"_hidden": "1"}, 9, -1, [{}]),
        ("S", 9, {}, [(2, {})]),
        ("T", 10, {}, 11, 1, [{"_t": "40 40 40"}]),
        ("S", 11, {}, [(0, {})]),
        ("T", 12, {}, 13, 2, [{"_t": "-40 0 0"}]),
        ("G", 13, {"_hidden": "1"}, [14]),
        ("T", 14, {}, 15, -1, [{}]),
        ("S", 15, {}, [(1, {})]),
        ("T", 16, {}, 17, 0, [{"_t": "0 -40 0"}]),
        ("S", 17, {"_hidden": "1"}, [(2, {})]),
        ("T", 18, {}, 19, 2, [{"_t": "20 20 0"}]),
        ("G", 19, {}, [20]),
        ("T", 20, {}, 21, 1, [{"_r": str(rd), "_t": " ".join(map(str, td))}]),
        ("S", 21, {}, [(2, {})]),
    ]
    layers = [(0, {"_name": "shown"}), (1, {"_hidden": "1"}), (2, {"_hidden": "0"})]

    def comp(*steps):
        R, t = IDENTITY, [0, 0, 0]
        for b, tt in steps:  # outermost first
            r = rot_from_byte(b) if b is not None else IDENTITY
            t = [a + c for a, c in zip(mat_vec(R, tt), t)]
            R = mat_mul(R, r)
        return R, t

    shown = [(0, *comp((ra, ta), (rb, tb), (None, t4))), (1, *comp((ra, ta), (rb, tb), (rc, tc))),
             (2, *comp((ra, ta), (None, [0, -40, 0])))]
    p = os.path.join(work, "gen_nested_hidden.vox")
    write_vox(p, models, nodes, layers, rgba)
    out.append((p, 0, expect(models, shown)))
    allp = shown + [(2, *comp((ra, ta), (rb, tb), (None, [0, 0, 0]))), (0, *comp((ra, ta), (None, [40, 40, 40]))),
                    (1, *comp((ra, ta), (None, [-40, 0, 0]))),
                    (2, *comp((ra, ta), (None, [20, 20, 0]), (rd, td)))]
    out.append((p, "all", expect(models, allp)))

    # 3. no scene graph, default palette, a voxel outside SIZE and an index 0
    size, vox = _model((7, 2, 5), 7)
    p = os.path.join(work, "gen_plain_default_palette.vox")
    write_vox(p, [(size, vox + [(7, 0, 0, 9), (0, 2, 0, 9), (1, 1, 1, 0)])])
    dpal = [tuple((v >> s) & 255 for s in (0, 8, 16, 24)) for v in DEFAULT_PALETTE]
    out.append((p, 0, sorted(place(IDENTITY, [0, 0, 0], size, v[:3]) + dpal[v[3]]
                          for v in model_cells(size, vox).items() for v in [v[0] + (v[1],)])))

    # 4. group instances (as MagicaVoxel writes them: several transforms on
    # one group): G3 under three transforms, G3 holding a turned shape and a
    # group G7 that two transforms inside G3 share again (six copies of m1)
    models = [_model((5, 3, 4), 10), _model((2, 3, 3), 11)]
    r1, r2, r3, r4 = 0b0100001, 0b0011000, 0b1000110, 0b0110010
    nodes = [("T", 0, {}, 1, -1, [{}]), ("G", 1, {}, [2, 10, 11]),
             ("T", 2, {}, 3, 0, [{"_t": "0 0 0"}]),
             ("T", 10, {}, 3, 0, [{"_r": str(r1), "_t": "30 1 -2"}]),
             ("T", 11, {}, 3, 0, [{"_r": str(r2), "_t": "-3 -30 5"}]),
             ("G", 3, {}, [4, 6, 12]),
             ("T", 4, {}, 5, -1, [{"_r": str(r3), "_t": "2 -1 3"}]), ("S", 5, {}, [(0, {})]),
             ("T", 6, {}, 7, -1, [{"_t": "7 7 0"}]), ("T", 12, {}, 7, -1, [{"_r": str(r4), "_t": "-6 4 1"}]),
             ("G", 7, {}, [8]), ("T", 8, {}, 9, -1, [{"_t": "0 0 9"}]), ("S", 9, {}, [(1, {})])]
    placed = []
    for top in [(None, [0, 0, 0]), (r1, [30, 1, -2]), (r2, [-3, -30, 5])]:
        placed.append((0, *comp(top, (r3, [2, -1, 3]))))
        placed.append((1, *comp(top, (None, [7, 7, 0]), (None, [0, 0, 9]))))
        placed.append((1, *comp(top, (r4, [-6, 4, 1]), (None, [0, 0, 9]))))
    p = os.path.join(work, "gen_group_instances.vox")
    write_vox(p, models, nodes, [(0, {})], rgba)
    out.append((p, 0, expect(models, placed)))

    # 5. the largest side, 256 (even: pivot 128), turned and mirrored
    models = [_model((256, 3, 2), 12), _model((1, 256, 1), 13)]
    rb1, rb2 = 0b1010001, 0b0001001
    nodes = [("T", 0, {}, 1, -1, [{}]), ("G", 1, {}, [2, 4, 6]),
             ("T", 2, {}, 3, 0, [{"_t": "0 0 0"}]), ("S", 3, {}, [(0, {})]),
             ("T", 4, {}, 5, 0, [{"_r": str(rb1), "_t": "5 -300 17"}]), ("S", 5, {}, [(0, {})]),
             ("T", 6, {}, 7, 0, [{"_r": str(rb2), "_t": "-129 1 -64"}]), ("S", 7, {}, [(1, {})])]
    p = os.path.join(work, "gen_side_256.vox")
    write_vox(p, models, nodes, [(0, {})], rgba)
    out.append((p, 0, expect(models, [(0, IDENTITY, [0, 0, 0]), (0, rot_from_byte(rb1), [5, -300, 17]),
                                      (1, rot_from_byte(rb2), [-129, 1, -64])])))

    # 6. keyframes: a transform and a shape's model both change at frame 2
    models = [_model((3, 4, 5), 8), _model((4, 4, 1), 9)]
    nodes = [("T", 0, {}, 1, -1, [{}]), ("G", 1, {}, [2]),
             ("T", 2, {}, 3, 0, [{"_f": "0", "_t": "1 2 3"}, {"_f": "2", "_r": str(0b0010110), "_t": "-5 0 4"}]),
             ("S", 3, {}, [(0, {"_f": "0"}), (1, {"_f": "2"})])]
    p = os.path.join(work, "gen_keyframes.vox")
    write_vox(p, models, nodes, [(0, {})], rgba)
    out.append((p, 0, expect(models, [(0, IDENTITY, [1, 2, 3])])))
    out.append((p, 1, expect(models, [(0, IDENTITY, [1, 2, 3])])))
    out.append((p, 2, expect(models, [(1, rot_from_byte(0b0010110), [-5, 0, 4])])))

    # 7. Teardown's TDCZ: one scene written with XYZI and with TDCZ, the
    # same voxels from both; its streams unterminated (a sync flush, as
    # Teardown's), terminated, and unterminated with bytes after it
    models = [_model((7, 5, 3), 14), _model((4, 4, 4), 15), _model((2, 9, 5), 16)]
    rt = 0b0100110
    nodes = [("T", 0, {}, 1, -1, [{}]), ("G", 1, {}, [2, 4, 6]),
             ("T", 2, {}, 3, 0, [{"_t": "0 0 0"}]), ("S", 3, {}, [(0, {})]),
             ("T", 4, {}, 5, 0, [{"_r": str(rt), "_t": "9 -3 2"}]), ("S", 5, {}, [(1, {})]),
             ("T", 6, {}, 7, 0, [{"_t": "-6 8 1"}]), ("S", 7, {}, [(2, {})])]
    placed = [(0, IDENTITY, [0, 0, 0]), (1, rot_from_byte(rt), [9, -3, 2]), (2, IDENTITY, [-6, 8, 1])]

    def teardown_streams(mi, size, vox):
        return tdcz_content(size, vox, finish=mi == 1, tail=b"\x03\x00 bytes after the cells" if mi == 2 else b"")
    for name, how in [("gen_tdcz_as_xyzi.vox", None), ("gen_tdcz.vox", teardown_streams)]:
        p = os.path.join(work, name)
        write_vox(p, models, nodes, [(0, {})], rgba, tdcz=how)
        out.append((p, 0, expect(models, placed)))

    # 8. RGBA chunks of 255 entries (Teardown's) and of 16: the indices
    # beyond them keep the default palette's colours; every index 1..255 used
    size = (16, 16, 1)
    vox = [(k % 16, k // 16, 0, k) for k in range(1, 256)]
    dpal = [tuple((v >> s) & 255 for s in (0, 8, 16, 24)) for v in DEFAULT_PALETTE]
    for entries, how in [(255, lambda mi, sz, v: tdcz_content(sz, v)), (16, None)]:
        p = os.path.join(work, f"gen_rgba_{entries}.vox")
        write_vox(p, [(size, vox)], rgba=rgba[:entries], tdcz=how)
        epal = [(0, 0, 0, 0)] + rgba[:entries] + dpal[entries + 1:]
        out.append((p, 0, sorted(place(IDENTITY, [0, 0, 0], size, v[:3]) + epal[v[3]] for v in vox)))

    # 9. files both readers refuse: vox2svo exits 1 naming the file and the
    # chunk, and writes no file
    size, vox = _model((6, 5, 4), 17)
    for name, content, chunk in [
            ("gen_refuse_tdcz_short.vox", tdcz_content(size, vox, cells=6 * 5 * 4 - 9), "TDCZ chunk at byte 44"),
            ("gen_refuse_tdcz_sizes.vox", tdcz_content(size, vox, sizes=(6, 4, 5)), "TDCZ chunk at byte 44"),
            ("gen_refuse_rgba_partial.vox", None, "RGBA chunk at byte")]:
        p = os.path.join(work, name)
        if content is None:
            write_vox(p, [(size, vox)], rgba=rgba[:100] + [(1, 2)])
        else:
            write_vox(p, [(size, vox)], tdcz=lambda mi, sz, v, content=content: content)
        out.append((p, 0, ("refuse", chunk)))
    return out


# ---- the test -----------------------------------------------------------------
def dump(bin_dir, svo, extra=()):
    r = subprocess.run([os.path.join(bin_dir, "svo_info"), svo, "--dump", *extra],
                       capture_output=True, text=True)
    if r.returncode != 0:
        raise VoxError(f"svo_info --dump {svo}: exit {r.returncode}: {r.stderr.strip()[:300]}")
    # compared as text (parsing every line into numbers costs more than the rest)
    return sorted(line for line in r.stdout.splitlines() if line)


def diff_text(want, got, limit=5):
    ws, gs = set(want), set(got)
    miss, more = sorted(ws - gs), sorted(gs - ws)
    s = f"{len(want)} voxels expected, {len(got)} dumped; {len(miss)} missing, {len(more)} extra"
    if miss:
        s += "; missing e.g. " + ", ".join(miss[:limit])
    if more:
        s += "; extra e.g. " + ", ".join(more[:limit])
    if not miss and not more:
        s += " (the same cells, counted differently)"
    return s


def main():
    if len(sys.argv) >= 3 and sys.argv[1] == "--cells":
        frame = int(sys.argv[sys.argv.index("--frame") + 1]) if "--frame" in sys.argv else 0
        for v in world_voxels(sys.argv[2], frame, "--all" in sys.argv):
            print(*v)
        return 0
    if len(sys.argv) != 4:
        print(__doc__.split("Usage:")[1].strip())
        return 2
    bin_dir, corpus, work = sys.argv[1:4]
    corpus = os.environ.get("VX_CORPUS_DIR") or corpus
    os.makedirs(work, exist_ok=True)
    cap = int(os.environ.get("VX_REF_MAX_BYTES", str(1 << 20)))
    files = []  # (label, path, frame: int or "all", expected or None)
    vdir = os.path.join(corpus, "vox")
    if os.path.isdir(vdir):
        for name in sorted(os.listdir(vdir)):
            p = os.path.join(vdir, name)
            if name.endswith(".vox"):
                if os.path.getsize(p) > cap:
                    print(f"left out: {p} ({os.path.getsize(p)} bytes > VX_REF_MAX_BYTES={cap})")
                else:
                    files.append((p, 0, None))
    else:
        print(f"skip: corpus {vdir} not found (the generated scenes still run)")
    extra = os.environ.get("VX_EXTRA_VOX")
    if extra:
        for root, _, names in sorted(os.walk(extra)):
            files += [(os.path.join(root, n), 0, None) for n in sorted(names) if n.endswith(".vox")]
    # real files: also frames 1, 2 and the last of an animation, and the
    # hidden parts where there are any
    real, files = files, []
    for path, _, _ in real:
        files.append((path, 0, None))
        try:
            frames, hidden = scene_facts(path)
        except VoxError:
            continue
        files += [(path, f, None) for f in sorted({1, 2, frames - 1}) if 0 < f < frames]
        if hidden:
            files.append((path, "all", None))
    files += generated_scenes(work)

    failed = 0
    t0 = time.time()
    for k, (path, frame, expected) in enumerate(files):
        label = os.path.basename(path) + ("" if frame == 0 else f" (frame {frame})" if frame != "all" else " (--all)")
        svo = os.path.join(work, f"ref{k}.svo")
        if os.path.exists(svo):
            os.remove(svo)
        conv = [os.path.join(bin_dir, "vox2svo"), path, svo]
        if frame == "all":
            conv += ["--keep-hidden", "--keep-unused"]
        r = subprocess.run(conv, capture_output=True, text=True)
        try:
            want = world_voxels(path, 0 if frame == "all" else frame, frame == "all")
        except VoxError as e:
            # not a file the notes describe (another program's .vox): vox2svo must refuse it too,
            # naming the file (and the chunk, for the generated ones) and writing nothing
            ok = r.returncode == 1 and "vox2svo: " + path in r.stderr and not os.path.exists(svo)
            if isinstance(expected, tuple):
                ok = ok and expected[1] in r.stderr
            print(f"{'ok  ' if ok else 'FAIL'} {label}: the reader refuses it ({e}); "
                  f"vox2svo: exit {r.returncode} {r.stderr.strip()[-200:]}")
            failed += not ok
            continue
        if isinstance(expected, tuple):
            print(f"FAIL {label}: the reader reads a file it must refuse; vox2svo: exit {r.returncode}")
            failed += 1
            continue
        if r.returncode != 0:
            print(f"FAIL {label}: vox2svo exit {r.returncode}: {(r.stderr or r.stdout).strip()[-300:]}")
            failed += 1
            continue
        args = ["--all"] if frame == "all" else [] if frame == 0 else ["--frame", str(frame)]
        try:
            got = dump(bin_dir, svo, args)
        except VoxError as e:
            print(f"FAIL {label}: {e}")
            failed += 1
            continue
        want = sorted("%d %d %d %d %d %d %d" % v for v in want)
        if expected is not None:
            expected = sorted("%d %d %d %d %d %d %d" % v for v in expected)
        ok = got == want
        msg = "" if ok else ": converter against the reader: " + diff_text(want, got)
        if expected is not None and expected != want:
            ok = False
            msg += "; reader against the scene's description: " + diff_text(expected, want)
        print(f"{'ok  ' if ok else 'FAIL'} {label}: {len(want)} voxels{msg}")
        failed += not ok
        os.remove(svo)
    print(f"{len(files) - failed}/{len(files)} equal in {time.time() - t0:.1f} s")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
