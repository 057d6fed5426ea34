"""Shared by the Python tests that check exports of the corpus Duck
(test_up_axis, test_blender): a .glb read with the standard library and numpy
only (independent of tinygltf and of voxkit's writer), and the Duck's head and
body told apart by colour."""
import json
import struct

import numpy as np


def read_glb(path):
    """(positions (N,3) with the node matrices applied, linear RGB (N,3), mesh
    node count, the parsed JSON) of every mesh node of a .glb"""
    data = open(path, "rb").read()
    jlen = struct.unpack_from("<I", data, 12)[0]
    g = json.loads(data[20:20 + jlen])
    binary = data[20 + jlen + 8:]

    def accessor(i):
        a = g["accessors"][i]
        bv = g["bufferViews"][a["bufferView"]]
        dtype = {5126: np.float32, 5123: np.uint16}[a["componentType"]]
        ncomp = {"VEC3": 3, "VEC4": 4}[a["type"]]
        start = bv.get("byteOffset", 0) + a.get("byteOffset", 0)
        x = np.frombuffer(binary, dtype, a["count"] * ncomp, start).reshape(-1, ncomp)
        return x / 65535.0 if a.get("normalized") else x.astype(float)

    pos, rgb, nodes = [], [], 0
    for node in g["nodes"]:
        if "mesh" not in node:
            continue
        nodes += 1
        M = np.array(node.get("matrix", np.eye(4).reshape(-1))).reshape(4, 4).T  # column-major
        # a mesh's primitives (one per material) may share their vertex
        # accessors, each drawing its own index range: the vertices once
        seen = set()
        for prim in g["meshes"][node["mesh"]]["primitives"]:
            key = (prim["attributes"]["POSITION"], prim["attributes"].get("COLOR_0"))
            if key in seen:
                continue
            seen.add(key)
            p = accessor(prim["attributes"]["POSITION"])
            pos.append(p @ M[:3, :3].T + M[:3, 3])
            if "COLOR_0" in prim["attributes"]:
                rgb.append(accessor(prim["attributes"]["COLOR_0"])[:, :3])
            else:
                rgb.append(np.ones((len(p), 3)))
    return np.vstack(pos), np.vstack(rgb), nodes, g


def to_srgb(c):
    return np.where(c <= 0.0031308, 12.92 * c, 1.055 * np.power(np.maximum(c, 0), 1 / 2.4) - 0.055)


def classify(rgb):
    """head (orange beak, dark eyes) and body (yellow) masks of (N,3) sRGB colours in [0,1]"""
    r, g, b = rgb[:, 0], rgb[:, 1], rgb[:, 2]
    head = ((r > 0.3) & (r > 1.4 * g)) | (r + g + b < 0.45)
    body = (r > 0.3) & (g > 0.6 * r) & (b < 0.7 * g)
    return head, body


def head_lift(pos, rgb, up):
    """(head count, body count, the head's mean height above the body's as a
    part of the whole height) along axis up"""
    head, body = classify(rgb)
    h = pos[:, up]
    span = h.max() - h.min()
    lift = (h[head].mean() - h[body].mean()) / span if head.any() and body.any() else float("nan")
    return int(head.sum()), int(body.sum()), lift
