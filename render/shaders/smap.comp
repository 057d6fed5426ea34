#version 450
// render/shaders/smap.comp - the directional light's conservative depth map
// (render/shadow_map.c): per texel of the light's orthographic view, the
// largest light-space coordinate s (distance along the unit light
// direction, towards the light) of any octree node whose projection touches
// the texel. A shadow ray from p meets geometry only where s <= that
// maximum, so trace.comp ends its walk there.
//
// Two modes (push constant; shadow_map.c clears the texels first): 1 adds
// the nodes to m1, the texel's largest s; 2 marks in top the node that gave
// m1 (its work item + 1, bit 31 where two or more did) and adds the other
// nodes to m2, the largest s below m1. A shadow ray from the surface of the one node that
// gave m1, a solid cube (a leaf), cannot meet that cube (it leaves the
// cube's face plane), so trace.comp takes m2 there. Mode 1 also makes occl,
// the largest, over the solid cubes whose projection holds the whole texel,
// of the least s of the cube's top over the texel: a shadow ray of the
// texel from below that meets that cube (trace.comp: shadowed without a
// walk). Each
// node is a cube of the model's cells [c, c + 2^level]^3; its instance's
// row maps model cells to (u, v) in texels and s in world units, so the
// box's projection is exactly the centre's image plus/minus |P| times the
// half side. The rectangle and s are widened by `margin` (world units, in
// the header), which covers the float rounding here and in the tracer's
// walk (shadow_map.c says why it suffices).
layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

// level: bits 0-7 the cube's level, bit 8 a leaf (the cube is solid)
struct Node { uint x, y, z, level; };
// pu, pv: texel coordinates from model cells; ps: s in world units;
// q0..q2: the inverse, model cell k from (u, v, s), with a usable flag in
// q.w's place (see face_bound); range: first node of the instance's model,
// its count, the instance's first work item (exclusive prefix of the
// counts), the instance's slot in the trace kernel's table
struct SInst { vec4 pu, pv, ps; vec4 q0, q1, q2, qd; uvec4 range; };

layout(std430, binding = 0) readonly buffer Nodes { Node nodes[]; };
layout(std430, binding = 1) readonly buffer Insts { SInst si[]; };
// header (16 words, shadow_map.c writes it) then side * side texels of 4
// words each: m1, m2, top and occl (all 0 first; smap_lookup.glsl reads a
// texel's four in one 16-byte load)
layout(std430, binding = 2) buffer Map { uint smap[]; };

layout(push_constant) uniform P {
    uint mode;   // 1: m1 and occl, 2: top and m2
    uint count;  // work items
    uint insts;  // entries in si
    uint side;
    float margin_tex; // the margin in texels
    float margin;     // in world units
} pc;

const uint HDR = 16u;

// s as a uint whose order is the float order (0 is below every s: empty)
uint ordered(float f) {
    uint b = floatBitsToUint(f);
    return (b & 0x80000000u) != 0u ? ~b : (b | 0x80000000u);
}

void main() {
    uint id = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u;
    if (id >= pc.count) return;
    // the instance whose work items hold id (the last with range.z <= id)
    uint lo = 0u, hi = pc.insts;
    while (hi - lo > 1u) {
        uint mid = (lo + hi) / 2u;
        if (si[mid].range.z <= id) lo = mid; else hi = mid;
    }
    SInst I = si[lo];
    Node n = nodes[I.range.x + (id - I.range.z)];
    float sz = exp2(float(n.level & 255u)), h = 0.5 * sz;
    vec3 lo3 = vec3(n.x, n.y, n.z), c = lo3 + h;
    float u = dot(I.pu.xyz, c) + I.pu.w, v = dot(I.pv.xyz, c) + I.pv.w, s = dot(I.ps.xyz, c) + I.ps.w;
    float hu = dot(abs(I.pu.xyz), vec3(h)) + pc.margin_tex;
    float hv = dot(abs(I.pv.xyz), vec3(h)) + pc.margin_tex;
    float smax = s + dot(abs(I.ps.xyz), vec3(h));
    int side = int(pc.side);
    int u0 = int(clamp(floor(u - hu), 0.0, float(side - 1)));
    int u1 = int(clamp(floor(u + hu), 0.0, float(side - 1)));
    int v0 = int(clamp(floor(v - hv), 0.0, float(side - 1)));
    int v1 = int(clamp(floor(v + hv), 0.0, float(side - 1)));
    // The box projects to a hexagon, the sum of its three edges' images
    // e_k: a texel outside it along some edge's normal is not touched
    // (separating axes; the texel's own axes are the rectangle above).
    vec2 e[3] = vec2[3](vec2(I.pu.x, I.pv.x) * h, vec2(I.pu.y, I.pv.y) * h, vec2(I.pu.z, I.pv.z) * h);
    vec2 nk[3];
    float ck[3], rk[3], ik[3];
    for (int k = 0; k < 3; k++) {
        nk[k] = vec2(-e[k].y, e[k].x);
        ck[k] = dot(vec2(u, v), nk[k]);
        float ext = abs(dot(e[0], nk[k])) + abs(dot(e[1], nk[k])) + abs(dot(e[2], nk[k]));
        float tex = 0.5 * (abs(nk[k].x) + abs(nk[k].y)), mg = pc.margin_tex * length(nk[k]);
        rk[k] = ext + tex + mg; // touched: the texel's and the hexagon's extents overlap
        ik[k] = ext - tex - mg; // inside: the texel within the hexagon shrunk by the margin
    }
    // (the hexagon is the intersection of the three slabs |(x - c) . n_k| <= ext_k)
    bool occluder = (n.level & 0x100u) != 0u && floatBitsToUint(I.qd.w) == 7u;
    // Over a texel the box's top is below each face plane that bounds s from
    // above (the top of a convex body is the least of those planes): model
    // cell k = q_k . (u, v, s) + qd_k, so on the face m_k = bound, s is
    // linear in (u, v); qd.w's bit k: the face is steep enough to use.
    float fa[3], fb[3], fc[3];
    uint use = floatBitsToUint(I.qd.w);
    vec4 q[3] = vec4[3](I.q0, I.q1, I.q2);
    for (int k = 0; k < 3; k++) {
        float g = q[k].z;
        float mb = (g > 0.0 ? lo3[k] + sz : lo3[k]) - I.qd[k];
        fa[k] = mb / g, fb[k] = -q[k].x / g, fc[k] = -q[k].y / g;
    }
    for (int y = v0; y <= v1; y++)
        for (int x = u0; x <= u1; x++) {
            vec2 tc = vec2(float(x) + 0.5, float(y) + 0.5);
            bool touch = true;
            for (int k = 0; k < 3; k++)
                if (abs(dot(tc, nk[k]) - ck[k]) > rk[k]) touch = false;
            if (!touch) continue;
            // the same operations in both modes, so that mode 2 sees m1's bits
            precise float st = smax;
            for (int k = 0; k < 3; k++)
                if (((use >> k) & 1u) != 0u) {
                    precise float fk = fa[k] + fb[k] * tc.x + fc[k] * tc.y + 0.5 * (abs(fb[k]) + abs(fc[k]));
                    st = min(st, fk);
                }
            precise float sm = st + pc.margin;
            uint w = ordered(sm), t = uint(y * side + x);
            if (pc.mode == 1u) {
                atomicMax(smap[HDR + 4u * t], w);
                bool inside = occluder;
                for (int k = 0; k < 3; k++)
                    if (abs(dot(tc, nk[k]) - ck[k]) > ik[k]) inside = false;
                if (inside) {
                    // the least of the top over the texel: the top is the least
                    // of the three upper face planes, each least at a corner
                    float low = 3.0e38;
                    for (int k = 0; k < 3; k++)
                        low = min(low, fa[k] + fb[k] * tc.x + fc[k] * tc.y - 0.5 * (abs(fb[k]) + abs(fc[k])));
                    atomicMax(smap[HDR + 4u * t + 3u], ordered(low - pc.margin));
                }
            } else if (w == smap[HDR + 4u * t]) {
                if (atomicCompSwap(smap[HDR + 4u * t + 2u], 0u, id + 1u) != 0u) atomicOr(smap[HDR + 4u * t + 2u], 0x80000000u);
            } else {
                atomicMax(smap[HDR + 4u * t + 1u], w);
            }
        }
}
