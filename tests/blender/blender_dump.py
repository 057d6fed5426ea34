"""Run inside Blender (blender -b --python blender_dump.py -- KIND IN OUT.npz):
imports IN with Blender's own importer and writes what Blender made of it to
OUT.npz, for test_blender.py to compare with the file's contents.

  glb: bpy.ops.import_scene.gltf; per mesh object its vertices in world space
       (Blender's +Z-up world) and each vertex's colour from the imported colour
       attribute (linear RGBA), plus the object count; each material's
       Principled BSDF inputs (metallic, roughness, transmission, emission);
       each light's type, world position and direction, colour, energy, spot
       size and blend, and the voxkit_light record's type kept from extras.
  vdb: bpy.ops.object.volume_import; the grids' names, types and channel
       counts, the first grid's index-to-object matrix and the evaluated
       object's bounding box.
"""
import sys

import bpy
import numpy as np

# Debian 12's Blender 3.4 glTF importer uses np.bool, which Debian 12's numpy
# (1.24) no longer has; the alias is what the importer meant.
if not hasattr(np, "bool"):
    np.bool = bool

kind, src, out = sys.argv[sys.argv.index("--") + 1:][:3]
bpy.ops.wm.read_factory_settings(use_empty=True)
if kind == "glb":
    bpy.ops.import_scene.gltf(filepath=src)
    meshes = [o for o in bpy.context.scene.objects if o.type == "MESH"]
    pos, col = [], []
    for o in meshes:
        me = o.data
        v = np.empty(len(me.vertices) * 3)
        me.vertices.foreach_get("co", v)
        v = v.reshape(-1, 3)
        m = np.array(o.matrix_world)
        pos.append(v @ m[:3, :3].T + m[:3, 3])
        c = np.zeros((len(me.vertices), 4))
        if me.color_attributes:
            a = me.color_attributes[0]
            vals = np.empty(len(a.data) * 4)
            a.data.foreach_get("color", vals)
            vals = vals.reshape(-1, 4)
            if a.domain == "CORNER":
                vi = np.empty(len(me.loops), dtype=np.int64)
                me.loops.foreach_get("vertex_index", vi)
                c[vi] = vals
            else:
                c[:] = vals
        col.append(c)
    # the materials as Blender's Principled BSDF holds them (name, metallic,
    # roughness, transmission, emission colour x strength)
    mats = []
    for m in bpy.data.materials:
        bsdf = m.node_tree.nodes.get("Principled BSDF") if m.use_nodes and m.node_tree else None
        if bsdf is None:
            continue
        inp = bsdf.inputs
        e = inp["Emission"].default_value
        k = inp["Emission Strength"].default_value
        mats.append((m.name, inp["Metallic"].default_value, inp["Roughness"].default_value,
                     inp["Transmission"].default_value, e[0] * k, e[1] * k, e[2] * k))
    # the lights: object name, type, world position, where it shines (the
    # object's -Z, as glTF's), colour, energy (watts), spot size and blend,
    # and the type of the voxkit_light record Blender keeps from the extras
    # as a custom property ("" without)
    lights = [o for o in bpy.context.scene.objects if o.type == "LIGHT"]
    lpos, ldir, lval, ltype, lname, lrec = [], [], [], [], [], []
    for o in lights:
        m = np.array(o.matrix_world)
        d = -m[:3, 2]
        lpos.append(m[:3, 3])
        ldir.append(d / np.linalg.norm(d))
        li = o.data
        spot = (li.spot_size, li.spot_blend) if li.type == "SPOT" else (0.0, 0.0)
        lval.append([li.color[0], li.color[1], li.color[2], li.energy, spot[0], spot[1]])
        ltype.append(li.type)
        lname.append(o.name)
        rec = li.get("voxkit_light")
        lrec.append(str(rec.get("type", "")) if rec is not None and hasattr(rec, "get") else "")
    np.savez(out, objects=len(meshes), pos=np.concatenate(pos) if pos else np.zeros((0, 3)),
             col=np.concatenate(col) if col else np.zeros((0, 4)),
             mat_names=np.array([m[0] for m in mats]), mat_values=np.array([m[1:] for m in mats]).reshape(-1, 6),
             light_names=np.array(lname), light_types=np.array(ltype), light_records=np.array(lrec),
             light_pos=np.array(lpos).reshape(-1, 3), light_dir=np.array(ldir).reshape(-1, 3),
             light_values=np.array(lval).reshape(-1, 6))
elif kind == "vdb":
    bpy.ops.object.volume_import(filepath=src)
    o = bpy.context.scene.objects[0]
    grids = o.data.grids
    grids.load()
    names = [g.name for g in grids]
    types = [g.data_type for g in grids]
    channels = [g.channels for g in grids]
    mat = np.array(grids[0].matrix_object) if len(grids) else np.zeros((4, 4))
    oe = o.evaluated_get(bpy.context.evaluated_depsgraph_get())
    bb = np.array([tuple(c) for c in oe.bound_box])
    np.savez(out, names=np.array(names), types=np.array(types), channels=np.array(channels), matrix=mat,
             bbox=np.stack([bb.min(axis=0), bb.max(axis=0)]))
else:
    raise SystemExit(f"unknown kind {kind}")
