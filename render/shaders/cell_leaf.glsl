// render/shaders/cell_leaf.glsl - the octree leaf that holds a cell, for the glass walks (the passes'
// pass_bodies.glsl glass_pass_walk, the path tracer's and the photons' probes/shaders/path_common.glsl
// glass_walk). Include after trace_common.glsl.

// The walks' step limit (render/trace.h vx__glass_walk_steps: the one rule for the CPU path tracer and
// every kernel): 12 sides of the cube of the model where the walk starts, at least 512.
uint glass_walk_steps(uint mi) {
    uint side = 1u << min(model_at(mi).depth, 21u);
    return max(12u * side, 512u);
}

// The first voxel along a + s d, s in [0, len), of an instance other than inst (g: its hit, t from a): inside
// a glass box the walks (path_common.glsl glass_walk, pass_bodies.glsl glass_pass_walk) look this way for a
// model placed overlapping the glass, which the glass's own model says nothing of; a ray from inside the glass
// would meet the glass itself at once, so inst is passed over (trace_common.glsl g_skip_inst).
bool other_instance_hit(uint inst, vec3 a, vec3 d, float len, out Hit g) {
    g.t = len;
    g.inst = NO_HIT;
    g.color = 0xFFFFFFFFu;
    g.attr = NO_HIT;
    g_iter = 0u;
    g_skip_inst = inst;
    bool met = trace_scene(a, d, 0.0, false, g);
    g_skip_inst = NO_HIT;
    return met;
}

// The attribute (index into colors[]) of cell c of model mi, c inside its cube, and the level of the leaf
// that holds it (0: the cell alone; k: a uniform block of 2^k cells a side, one record, at c rounded down to
// a multiple of 2^k): NO_HIT (level 0) where the cell is empty or the model has no attributes. A walk down
// the octree, as trace_model descends (trace_common.glsl: a leaf child at any depth fills its cube). The
// compact layout keeps no collapsed blocks of one record (its geometry DAG ignores the attributes): level 0
// there, which the walks' arithmetic makes give the same exits (pass_bodies.glsl glass_pass_walk).
uint model_cell_leaf(uint mi, uvec3 c, out uint level) {
    level = 0u;
    if (COMPACT) {
        // the material id or palette index (trace_common.glsl's Hit.attr of a compact scene)
        CModel cm = cmodels[mi];
        if (!HAS_COLOR || (cm.flags & 1u) == 0u || !cell_set(cm, c)) return NO_HIT;
        uint ab;
        uint i = cell_index(cm, c, ab);
        return ca_table_index(cm, i, cm.kind == 1u ? decode_value(cm, ab, i) : 0u);
    }
    Model m = models[mi];
    if (m.root == ROOT_EMPTY || !HAS_COLOR || (m.flags & 1u) == 0u) return NO_HIT;
    if (m.root == ROOT_LEAF) {
        level = m.depth;
        return m.color_off + m.root_attr;
    }
    uint nbase = m.node_off, parent = nbase + m.root;
    for (int l = int(m.depth) - 1; l >= 0; l--) {
        uint desc = nodes[parent];
        uint cs = ((c.x >> uint(l)) & 1u) | (((c.y >> uint(l)) & 1u) << 1) | (((c.z >> uint(l)) & 1u) << 2);
        uint cbit = 1u << cs;
        if (!desc_valid(desc, cbit)) return NO_HIT;
        if (!desc_inner(desc, cbit)) {
            // a leaf (descriptors in the GPU form, trace_common.glsl)
            uint valid = (desc >> 8) & 0xFFu;
            uint blk = parent - (desc >> 17);
            if ((desc & 0x10000u) != 0u) blk = nbase + nodes[blk];
            level = uint(l);
            return m.color_off + nodes[blk + desc_inner_count(desc)] + uint(bitCount(valid & (cbit - 1u)));
        }
        parent = child_node(parent, desc, cbit, nbase);
    }
    return NO_HIT;
}
