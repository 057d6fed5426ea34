// render/shaders/model_cell_leaf.glsl - one descent of a model to the leaf that holds a cell (its
// attribute record): the glass walks' (cell_leaf.glsl) and the grid walk's hit record (grid_walk.glsl).
// Include after trace_common.glsl's declarations (float variant); included once however often.
#ifndef VX_MODEL_CELL_LEAF_GLSL
#define VX_MODEL_CELL_LEAF_GLSL
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
#endif
