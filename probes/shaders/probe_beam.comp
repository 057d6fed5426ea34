#version 450
// probes/shaders/probe_beam.comp - the beam pass of the bake's camera rays (render/shaders/beam.comp's
// walk for a probe's texel blocks): one invocation per block of BLK x BLK texels of a probe's
// octahedral map finds a distance S before which no ray from the probe through the block can meet a
// non-empty node; probe.comp's bake then starts the block's camera rays' octree walk there (g_tskip:
// the walk's coefficients unchanged, so the same hits as from the probe, bit for bit).
//
// The block's directions: oct_decode maps each of the four triangles of a quadrant of the map
// (|u| + |v| <= 1 and >= 1) affinely onto a face of the octahedron |x| + |y| + |z| = 1, so the block's
// part in each triangle is a convex polygon there, and a direction's angle to the block's centre
// direction dc is quasi-convex on it (its sublevel sets are convex cones): the largest angle is at a
// polygon vertex, a block corner or a point where a block edge crosses the fold |u| + |v| = 1 (blocks
// never cross u = 0 or v = 0: BLK divides res / 2). Every ray of the block then lies within chord
// r1 = max |d - dc| of dc, and its point at distance s within r1 s of the probe's o + s dc: the tube
// of beam.comp with radius 0 + r1 s.
#extension GL_GOOGLE_include_directive : require

#include "beam_body.glsl" // beam.comp: trace_common.glsl (BEAM_PASS), beam_model_plain, beam_s[] (binding 10)

// The compact layout's node (render/compact.h, compact_attr.glsl) of level lvl as a descriptor in the file's
// form (valid mask << 8 | leaf mask): level >= 3 its slot's word 0 (the bits above 16 are its rank or the
// dictionary's flag), level 2 a brick of 4^3 cells (its level-1 octants that hold cells, none a leaf), level 1
// octant o of the brick (its cells, all leaves).
uint beam_cdesc(int lvl, uvec2 cnd, uint o) {
    return lvl >= 3 ? cnd.x & 0xFFFFu : (lvl == 2 ? brick_desc(cnd) : brick_octant(cnd, o));
}

// beam_walk.glsl's walk (beam_model_plain's) over the compact layout (COMPACT: the bake of a scene read by
// the model reader, svo_bake --load models): the same tube, the same order and budget, the same stops (a leaf, here a solid
// cube of the geometry whatever its colours, or a node at most BEAM_STOP radii wide), so its distance bounds
// the cells' from below as the plain walk's does. The two layouts' distances may differ (the compact geometry
// merges solid cubes that colours split in the plain one, so the walks spend the budget differently), which
// the bake's walk does not see: it finds its hits in cells from any start before them (CELL_HITS; the bytes
// checked against the plain layout's bake, test_svo_bake.sh).
// A node is its slot's words (cnd; levels 2 and 1 the brick's) and its level, depth - lvl (lvl: the walk's
// depth below the root). The child (level lvl - 1) of the node at level lvl with words cnd and descriptor
// desc: level >= 3 the child's slot in the block (level 3 with the dictionary: through its index word),
// below that the same brick.
uvec2 beam_cchild(int lvl, uvec2 cnd, uint desc, uint cbit) {
    return lvl >= 3 ? cslots[ca_child(lvl, cnd.x, cnd.y, uint(bitCount((desc >> 8) & ~desc & (cbit - 1u))))] : cnd;
}
#define BW_NAME beam_model_compact
#define BW_MODEL CModel
#define BW_MODELS cmodels
#define BW_NODE uvec2
// (a depth-1 model's root: octant 0 of its slot)
#define BW_ROOT uvec2 node = cslots[m.root]; uint desc = beam_cdesc(int(m.depth), node, 0u);
#define BW_IS_LEAF(desc, cbit) ((desc & cbit) != 0u)
#define BW_CHILD node = beam_cchild(int(m.depth) - lvl + 1, node, desc, cbit); desc = beam_cdesc(int(m.depth) - lvl, node, c);
#include "beam_walk.glsl"

// trace_common.glsl's model walk of the tube (trace_instance): the scene's layout's
bool beam_model(uint mi, vec3 o, vec3 d, float scale, float t0, inout Hit h) {
    return COMPACT ? beam_model_compact(mi, o, d, scale, t0, h) : beam_model_plain(mi, o, d, scale, t0, h);
}

layout(push_constant) uniform Push {
    uint res, blk, first, count; // map side, block side in texels, the batch's first probe, its probes
} PB;
layout(std430, binding = 9) readonly buffer Probes { vec4 probes[]; }; // xyz: position - reference, w: state

float sgn_b(float v) { return v < 0.0 ? -1.0 : 1.0; }
vec3 oct_dir(vec2 uv) { // probes/shaders/path_common.glsl's oct_decode
    vec3 p = vec3(uv, 1.0 - abs(uv.x) - abs(uv.y));
    if (p.z < 0.0) p.xy = vec2((1.0 - abs(uv.y)) * sgn_b(uv.x), (1.0 - abs(uv.x)) * sgn_b(uv.y));
    return normalize(p);
}

void main() {
    uint nb = PB.res / PB.blk, blocks = nb * nb;
    uint b = gl_GlobalInvocationID.x, slot = gl_GlobalInvocationID.y;
    if (b >= blocks || slot >= PB.count) return;
    uint at = slot * blocks + b;
    vec4 pr = probes[PB.first + slot];
    if (pr.w == 2.0) { // disabled: its texels are not traced
        beam_s[at] = 0.0;
        return;
    }
    uint bx = b % nb, by = b / nb;
    // the block's edges in the map's [-1, 1] coordinates (texel edges: every jittered sample inside)
    vec2 lo = vec2(float(bx * PB.blk), float(by * PB.blk)) * 2.0 / float(PB.res) - 1.0;
    vec2 hi = vec2(float((bx + 1u) * PB.blk), float((by + 1u) * PB.blk)) * 2.0 / float(PB.res) - 1.0;
    vec3 dc = oct_dir(0.5 * (lo + hi));
    float r1 = 0.0;
    for (int k = 0; k < 4; k++) r1 = max(r1, length(oct_dir(vec2((k & 1) != 0 ? hi.x : lo.x, (k >> 1) != 0 ? hi.y : lo.y)) - dc));
    // where the edges cross the fold su u + sv v = 1 (the block lies in one quadrant)
    vec2 mid = 0.5 * (lo + hi), s = vec2(sgn_b(mid.x), sgn_b(mid.y));
    for (int k = 0; k < 2; k++) {
        float u = k == 0 ? lo.x : hi.x, v = s.y * (1.0 - s.x * u); // edge u = const
        if (v >= lo.y && v <= hi.y) r1 = max(r1, length(oct_dir(vec2(u, v)) - dc));
        v = k == 0 ? lo.y : hi.y;
        u = s.x * (1.0 - s.y * v); // edge v = const
        if (u >= lo.x && u <= hi.x) r1 = max(r1, length(oct_dir(vec2(u, v)) - dc));
    }
    g_dir = dc;
    g_ra = 0.0;
    g_rb = r1 * 1.001 + 1e-6; // the directions' rounding (normalize) besides beam_model's own padding
    Hit h;
    h.t = 3.0e38;
    h.inst = NO_HIT;
    trace_scene(pr.xyz, g_dir, 0.0, false, h);
    beam_s[at] = h.t;
}
