// render/shaders/smap_lookup.glsl - the directional light's conservative depth
// map (render/shadow_map.c, smap.comp) read by a shadow ray towards that light:
// the one lookup that trace.comp's colour mode and probes/shaders/probe.comp's
// sun rays share (render/gpu.h, vx__render_scene_sun_map, gives a pass the
// buffers and the values below).
//
// Define SMAP_BINDING (the first of three bindings) before including it. The
// map: a header of 16 words (rows giving texel u and v from a point relative
// to the map's origin, then the light), then per texel 4 words: m1, the
// largest s = dot(x - origin, light) of the geometry over it as an ordered
// uint (0: none), m2, the largest of the others, top, the one node
// (smap.comp's work item + 1; 0 or bit 31: none or several) that gave m1,
// and occl, below which a ray of the texel surely meets a solid cube (0:
// none). A texel's four words are one 16-byte load (smap_texels, the same
// binding: the header is 4 of its entries), not four loads a texel's side^2
// words apart.
layout(constant_id = 11) const bool SMAP = false;
layout(std430, binding = SMAP_BINDING) readonly buffer SMap { uint smap[]; };
layout(std430, binding = SMAP_BINDING) readonly buffer SMapTexels { uvec4 smap_texels[]; };
struct SNode { uint x, y, z, level; };
struct SInst { vec4 pu, pv, ps; vec4 q0, q1, q2, qd; uvec4 range; };
layout(std430, binding = SMAP_BINDING + 1) readonly buffer SNodes { SNode snodes[]; };
layout(std430, binding = SMAP_BINDING + 2) readonly buffer SInsts { SInst sinsts[]; };

// A shadow ray from ps along light L (the direction the map was built for;
// ps relative to the pass's reference) meets geometry only where s <= the
// texel's bound: its end (t), or -1 where it meets none, -2 where it surely
// meets one; 3e38 (the whole ray) where ps lies outside the map. org.xyz:
// the map's origin relative to the reference, org.w: the margin; side: texels
// a side, ninst: entries in sinsts. The bound is m1, or m2 where m1 came from
// one solid cube alone that holds the primary hit (instance slot inst, cell)
// entered from outside (entered): the ray, which leaves that cube's face
// plane, cannot meet it.
float smap_tmax(vec3 ps, vec3 L, vec4 org, uint side, uint ninst, uint inst, uvec3 cell, bool entered) {
    vec3 q = ps - org.xyz;
    vec4 ru = uintBitsToFloat(uvec4(smap[0], smap[1], smap[2], smap[3]));
    vec4 rv = uintBitsToFloat(uvec4(smap[4], smap[5], smap[6], smap[7]));
    float u = dot(q, ru.xyz) + ru.w, v = dot(q, rv.xyz) + rv.w;
    float fside = float(side);
    if (!(u >= 0.0 && v >= 0.0 && u < fside && v < fside)) return 3.0e38;
    uvec4 tx = smap_texels[4u + uint(v) * side + uint(u)]; // m1, m2, top, occl
    uint w = tx.x;
    if (w == 0u) return -1.0;
    float sp = dot(q, L);
    uint oc = tx.w;
    if (oc != 0u) {
        float so = (oc & 0x80000000u) != 0u ? uintBitsToFloat(oc & 0x7FFFFFFFu) : uintBitsToFloat(~oc);
        if (sp < so - org.w) return -2.0;
    }
    uint top = tx.z;
    if (entered && top != 0u && (top & 0x80000000u) == 0u) {
        uint id = top - 1u, lo = 0u, hi = ninst;
        while (hi - lo > 1u) {
            uint mid = (lo + hi) / 2u;
            if (sinsts[mid].range.z <= id) lo = mid; else hi = mid;
        }
        uvec4 rg = sinsts[lo].range;
        SNode n = snodes[rg.x + (id - rg.z)];
        uvec3 d = cell - uvec3(n.x, n.y, n.z); // wraps below the cube's corner
        uint sz = 1u << (n.level & 255u);
        if (rg.w == inst && (n.level & 0x100u) != 0u && all(lessThan(d, uvec3(sz)))) {
            w = tx.y;
            if (w == 0u) return -1.0;
        }
    }
    float smax = (w & 0x80000000u) != 0u ? uintBitsToFloat(w & 0x7FFFFFFFu) : uintBitsToFloat(~w);
    float tc = smax - sp + org.w;
    return tc >= 0.0 ? tc : -1.0;
}
