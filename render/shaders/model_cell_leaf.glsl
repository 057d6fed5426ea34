// render/shaders/model_cell_leaf.glsl - one descent of a model to the leaf that holds a cell (its
// attribute record): the glass walks' (cell_leaf.glsl) and the grid walk's hit record (grid_walk.glsl).
// Include after trace_common.glsl's declarations (float variant); included once however often.
#ifndef VX_MODEL_CELL_LEAF_GLSL
#define VX_MODEL_CELL_LEAF_GLSL
// model_cell_leaf's descent from node `parent` (absolute) of model m, whose children are cubes of 2^l0 cells a side
uint model_cell_descend(Model m, uint parent, int l0, uvec3 c, out uint level) {
    level = 0u;
    uint nbase = m.node_off;
    for (int l = l0; l >= 0; l--) {
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
    return model_cell_descend(m, m.node_off + m.root, int(m.depth) - 1, c, level);
}

// A grid walk's hit (grid_walk.glsl): model_cell_leaf's attribute from the record word rw of the brick that holds
// cell c (render/grid.h vx__grid_brick_record: the node whose cube is the brick, relative to the model's first
// node, from which the descent takes the last min(depth, 3) levels instead of all; or bit 31 and the record of a
// uniform leaf that holds the whole brick).
uint model_cell_leaf_brick(uint mi, uvec3 c, uint rw) {
    uint level;
    if (COMPACT) return model_cell_leaf(mi, c, level);
    Model m = models[mi];
    if ((rw & 0x80000000u) != 0u) return m.color_off + (rw & 0x7FFFFFFFu);
    return model_cell_descend(m, m.node_off + rw, int(min(m.depth, 3u)) - 1, c, level);
}
#endif
