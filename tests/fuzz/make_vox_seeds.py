#!/usr/bin/env python3
"""Writes tests/fuzz/vox_seeds/: small .vox files in Teardown's variant, so
vox_fuzz starts inside the TDCZ and short-RGBA code (the shared corpus holds
MagicaVoxel's own files only). Written from the layout, not copied from a
Teardown file: a scene graph of two shapes, each model's voxels in a TDCZ
chunk (its sizes, then a zlib stream of one colour index per cell, x fastest)
whose stream stops after a sync flush as Teardown's do (no final block, no
Adler-32), one terminated stream with bytes after it, a 255-entry RGBA chunk
as Teardown writes, and a MATL. Run from the repository root:
python3 tests/fuzz/make_vox_seeds.py"""
import os
import struct
import zlib


def chunk(cid, content):
    return cid + struct.pack("<ii", len(content), 0) + content


def string(s):
    return struct.pack("<i", len(s)) + s.encode()


def dictionary(d):
    return struct.pack("<i", len(d)) + b"".join(string(k) + string(v) for k, v in d.items())


def tdcz(size, finish=False, tail=b""):
    sx, sy, sz = size
    grid = bytes((1 + (x * 5 + y * 3 + z * 11) % 255) if (x + y + z) % 3 else 0
                 for z in range(sz) for y in range(sy) for x in range(sx))
    co = zlib.compressobj(9)
    data = co.compress(grid) + co.flush(zlib.Z_FINISH if finish else zlib.Z_SYNC_FLUSH)
    return chunk(b"SIZE", struct.pack("<iii", *size)) + chunk(b"TDCZ", struct.pack("<iii", *size) + data + tail)


def trn(nid, child, t):
    return chunk(b"nTRN", struct.pack("<i", nid) + dictionary({}) + struct.pack("<iiii", child, -1, 0, 1)
                 + dictionary({"_t": t}))


def main():
    body = tdcz((6, 4, 5)) + tdcz((3, 7, 2), finish=True, tail=b"\x03\x00tail")
    body += trn(0, 1, "0 0 0")
    body += chunk(b"nGRP", struct.pack("<i", 1) + dictionary({}) + struct.pack("<iii", 2, 2, 4))
    body += trn(2, 3, "0 0 0") + chunk(b"nSHP", struct.pack("<i", 3) + dictionary({}) + struct.pack("<ii", 1, 0)
                                       + dictionary({}))
    body += trn(4, 5, "8 -2 1") + chunk(b"nSHP", struct.pack("<i", 5) + dictionary({}) + struct.pack("<ii", 1, 1)
                                        + dictionary({}))
    body += chunk(b"RGBA", b"".join(struct.pack("<4B", k, 255 - k, (k * 7) & 255, 255) for k in range(255)))
    body += chunk(b"MATL", struct.pack("<i", 3) + dictionary({"_type": "_metal", "_rough": "0.2"}))
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "vox_seeds")
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "teardown_tdcz.vox"), "wb") as f:
        f.write(b"VOX " + struct.pack("<i", 150) + chunk(b"MAIN", b"")[:8] + struct.pack("<i", len(body)) + body)


if __name__ == "__main__":
    main()
