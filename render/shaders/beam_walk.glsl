// render/shaders/beam_walk.glsl - the beam pass's model walk (beam.comp), written once for both node
// layouts: a template that its includer instantiates once per layout, defining before each #include
//   BW_NAME                 the function's name
//   BW_MODEL, BW_MODELS     the model record's type and its array (m: the model)
//   BW_NODE                 a node's handle (node; the stack holds it)
//   BW_ROOT                 statements that declare node and desc, the root's handle and its descriptor in
//                           the file's form or the GPU form (desc >> 8: the valid mask)
//   BW_IS_LEAF(desc, cbit)  the child cbit (1 << octant) of a node with descriptor desc is a leaf
//   BW_CHILD                statements that set node and desc to that child c (cbit) of node; lvl is then
//                           the child's depth below the model's root
// beam.comp instantiates it for the plain layout (beam_model; probes/shaders/probe_beam.comp takes that as
// beam_model_plain through beam_body.cmake) and probe_beam.comp for the compact one (beam_model_compact): the
// same tube, order, budget and stops over either layout, one text. No include guard, and the parameters are
// undefined at the end, so it can be included again.

// The first t >= t0 (below h.t) at which the tube, scaled into model mi's
// space (o + t d, radius at most `scale` times the world radius), meets a
// leaf or a non-empty node at most BEAM_STOP radii wide there: a
// depth-first walk over the valid children, nearer ones first, pruned by
// the best t so far. Any node's entry bounds its cells' from below, so the
// walk may stop at any node (budget) and stay conservative.
bool BW_NAME(uint mi, vec3 o, vec3 d, float scale, float t0, inout Hit h) {
    BW_MODEL m = BW_MODELS[mi];
    if (m.root == ROOT_EMPTY) return false;
    float side = exp2(float(m.depth));
    // padded against the rounding of the box tests (coordinates up to side)
    float pad = 1e-3 + 4e-6 * (side + max(max(abs(o.x), abs(o.y)), abs(o.z)));
    float ra = g_ra * scale * 1.0001 + pad, rb = g_rb * scale * 1.0001;
    Tube T = tube_setup(o, d, ra, rb);
    vec2 tr = tube_box(T, vec3(0.0), vec3(side));
    float tlo = max(tr.x, t0), best = h.t;
    if (!(tlo <= tr.y && tlo < best)) return false;
    if (m.root == ROOT_LEAF || side <= BEAM_STOP * (ra + rb * tlo)) {
        h.t = tlo;
        return true;
    }
    BW_ROOT
    // children in the order the centre ray's octant visits them first
    uint mirror = (d.x < 0.0 ? 1u : 0u) | (d.y < 0.0 ? 2u : 0u) | (d.z < 0.0 ? 4u : 0u);
    uint rem = mirror_mask((desc >> 8) & 0xFFu, mirror);
    BW_NODE stk_node[S_MAX];
    uint stk_desc[S_MAX], stk_rem[S_MAX];
    int lvl = 0;
    vec3 lo = vec3(0.0);
    float size = side;
    bool found = false;
    while (true) {
        if (--g_budget < 0) {
            // out of iterations: the model's entry is a bound
            best = tlo;
            found = true;
            break;
        }
        if (rem != 0u) {
            uint c = uint(findLSB(rem)) ^ mirror, cbit = 1u << c;
            rem &= rem - 1u;
            float hs = 0.5 * size;
            vec3 clo = lo + vec3(float(c & 1u), float((c >> 1) & 1u), float((c >> 2) & 1u)) * hs;
            vec2 tc = tube_box(T, clo, clo + hs);
            float te = max(tc.x, tlo);
            if (!(te <= tc.y && te < best)) continue;
            if (BW_IS_LEAF(desc, cbit) || hs <= BEAM_STOP * (ra + rb * te)) {
                best = te;
                found = true;
                continue;
            }
            stk_node[lvl] = node;
            stk_desc[lvl] = desc;
            stk_rem[lvl] = rem;
            lvl++;
            BW_CHILD
            rem = mirror_mask((desc >> 8) & 0xFFu, mirror);
            lo = clo;
            size = hs;
        } else {
            if (lvl == 0) break;
            lvl--;
            node = stk_node[lvl];
            desc = stk_desc[lvl];
            rem = stk_rem[lvl];
            size *= 2.0;
            lo = floor(lo / size) * size;
        }
    }
    if (!found) return false;
    h.t = best;
    return true;
}

#undef BW_NAME
#undef BW_MODEL
#undef BW_MODELS
#undef BW_NODE
#undef BW_ROOT
#undef BW_IS_LEAF
#undef BW_CHILD
