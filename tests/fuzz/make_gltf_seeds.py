#!/usr/bin/env python3
"""Writes tests/fuzz/gltf_seeds/: tiny .glb files whose base colour texture is a
PNG or a JPEG stored in the binary chunk, so gltf_fuzz reaches the image code
(header sniffing, size limits, decoding) from its first input; one also uses
the PNG as metallic-roughness and emissive texture (the materials' plan). Run from the
repository root: python3 tests/fuzz/make_gltf_seeds.py"""
import json
import os
import struct
import zlib


def png(w, h):
    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data))
    raw = b"".join(b"\0" + b"".join(bytes((x * 60 % 256, y * 60 % 256, 200, 255)) for x in range(w))
                   for y in range(h))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def jpeg():
    """8x8 grey baseline JPEG: one block, DC difference 0 and end of block,
    each coded by a one-symbol Huffman table."""
    def seg(marker, body):
        return b"\xff" + bytes((marker,)) + struct.pack(">H", len(body) + 2) + body
    dqt = seg(0xDB, b"\x00" + b"\x01" * 64)
    sof = seg(0xC0, struct.pack(">BHHB", 8, 8, 8, 1) + b"\x01\x11\x00")
    counts = b"\x01" + b"\x00" * 15
    dht = seg(0xC4, b"\x00" + counts + b"\x00") + seg(0xC4, b"\x10" + counts + b"\x00")
    sos = seg(0xDA, b"\x01\x01\x00\x00\x3f\x00")
    return b"\xff\xd8" + dqt + sof + dht + sos + b"\x3f" + b"\xff\xd9"


def glb(image, mime, indexed, materials=False):
    pos = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0.5)
    uv = struct.pack("<6f", 0, 0, 1, 0, 0, 1)
    idx = struct.pack("<3H", 0, 1, 2) + b"\0\0"
    views, blob = [], b""

    def add(data, target=None):
        nonlocal blob
        v = {"buffer": 0, "byteOffset": len(blob), "byteLength": len(data)}
        if target:
            v["target"] = target
        views.append(v)
        blob += data + b"\0" * (-len(data) % 4)
        return len(views) - 1
    accessors = [
        {"bufferView": add(pos, 34962), "componentType": 5126, "count": 3, "type": "VEC3",
         "min": [0, 0, 0], "max": [1, 1, 0.5]},
        {"bufferView": add(uv, 34962), "componentType": 5126, "count": 3, "type": "VEC2"},
    ]
    prim = {"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "material": 0}
    material = {"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "baseColorFactor": [1, 1, 1, 1]}}
    if materials:
        # the same image as metallic-roughness and emissive texture, so that every channel varies per cell
        # (the materials' per-cell levels and per-channel emission ids, convert/mesh_material.c)
        material["pbrMetallicRoughness"].update(metallicFactor=0.8, roughnessFactor=0.5,
                                                metallicRoughnessTexture={"index": 0})
        material.update(emissiveFactor=[1, 0.5, 0.25], emissiveTexture={"index": 0},
                        extensions={"KHR_materials_emissive_strength": {"emissiveStrength": 3}})
    if indexed:
        accessors.append({"bufferView": add(idx, 34963), "componentType": 5123, "count": 3, "type": "SCALAR"})
        prim["indices"] = 2
    img = add(image)
    doc = {
        "asset": {"version": "2.0"},
        "scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "scale": [1, 2, 1]}],
        "meshes": [{"primitives": [prim]}],
        "materials": [material],
        "textures": [{"source": 0, "sampler": 0}],
        "samplers": [{"magFilter": 9728, "minFilter": 9728, "wrapS": 10497, "wrapT": 10497}],
        "images": [{"bufferView": img, "mimeType": mime}],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(blob)}],
    }
    js = json.dumps(doc, separators=(",", ":")).encode()
    js += b" " * (-len(js) % 4)
    body = struct.pack("<I4s", len(js), b"JSON") + js + struct.pack("<I4s", len(blob), b"BIN\0") + blob
    return struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body


out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "gltf_seeds")
os.makedirs(out, exist_ok=True)
for name, data in (("png_tri.glb", glb(png(4, 4), "image/png", False)),
                   ("jpeg_tri.glb", glb(jpeg(), "image/jpeg", True)),
                   ("png_materials.glb", glb(png(4, 4), "image/png", True, True))):
    with open(os.path.join(out, name), "wb") as f:
        f.write(data)
