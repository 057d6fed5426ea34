#version 450
// bench/shaders/mipgrid.comp - the occupancy pyramid prototype of
// bench/render_bench (bench/mipgrid.h): primary rays through a pointerless
// octree. A cell's bit is found from its coordinates and level, so the walk
// keeps no stack: a push halves the cell (the child from the three mid-plane
// crossings against the entry time, as ESVO chooses it), an advance moves to
// the neighbour and rises to the highest level whose coordinate bit changed
// (ESVO's pop, without reading a parent back). Directions are mirrored to be
// positive; a mirrored axis's cell index is the stored one xor (2^level - 1).
// PROBE (spec constant 0): 0 the walk alone; 1 on entering an occupied node
// first test the finest cell at the entry point (the first cell the ray meets
// in the node: a hit there ends the ray, else the walk descends as before);
// 2 as 1 from nodes at most 8 cells wide only. Rays are generated exactly as
// render/shaders/trace.comp and bench/shaders/esvo.comp generate them.
layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
layout(constant_id = 0) const uint PROBE = 0u;

layout(std140, binding = 0) uniform Frame {
    vec4 fwd;   // w: t_start
    vec4 rx;    // w: ortho
    vec4 uy;
    vec4 box;   // xyz: the cube's corner relative to the frame reference, w: side (2^depth)
    uvec4 dims; // width, height, depth
} F;
layout(std430, binding = 1) readonly buffer Bits { uint bits[]; };
layout(std430, binding = 2) writeonly buffer Out { uvec2 outp[]; }; // depth bits, steps | entered << 31

const uint MAX_STEPS = 100000u; // the same guard as voxkit's tracer

// bench/mipgrid.c level_base: the first word of level l, coarse levels first
uint level_base(uint D, uint l) {
    int k = int(D) - int(l) - 2;
    return k <= 0 ? uint(36 + 2 * k) : 36u + ((2u << uint(3 * k)) - 2u) / 7u;
}

bool occupied(uint D, uint l, uvec3 P, uvec3 flip) {
    uvec3 q = (P ^ flip) >> l;
    uint bl = uint(max(int(D) - int(l) - 2, 0));
    uint b = ((((q.z >> 2) << bl) | (q.y >> 2)) << bl) | (q.x >> 2);
    uint i = (q.x & 3u) | ((q.y & 3u) << 2) | ((q.z & 3u) << 4);
    uint w = bits[level_base(D, l) + 2u * b + (i >> 5)];
    return ((w >> (i & 31u)) & 1u) != 0u;
}

void main() {
    uvec2 px = gl_GlobalInvocationID.xy;
    uint W = F.dims.x, H = F.dims.y;
    if (px.x >= W || px.y >= H) return;
    float u = ((float(px.x) + 0.5) / float(W)) * 2.0 - 1.0;
    float v = 1.0 - ((float(px.y) + 0.5) / float(H)) * 2.0;
    vec3 o, d;
    float t_off;
    float t_start = F.fwd.w;
    if (F.rx.w != 0.0) {
        o = u * F.rx.xyz + v * F.uy.xyz;
        d = F.fwd.xyz;
        t_off = t_start;
    } else {
        vec3 du = F.fwd.xyz + u * F.rx.xyz + v * F.uy.xyz;
        float len = length(du);
        d = du / len;
        o = t_start * (u * F.rx.xyz + v * F.uy.xyz);
        t_off = t_start * len;
    }
    uint out_i = px.y * W + px.x;
    float side = F.box.w;
    vec3 inv;
    for (int k = 0; k < 3; k++) inv[k] = abs(d[k]) < 1e-30 ? (d[k] < 0.0 ? -1e30 : 1e30) : 1.0 / d[k];
    vec3 a = (F.box.xyz - o) * inv, b = (F.box.xyz + side - o) * inv;
    vec3 tn = min(a, b), tf = max(a, b);
    float te = max(max(max(tn.x, tn.y), tn.z), 0.0);
    float tx = min(min(tf.x, tf.y), tf.z);
    if (!(te < tx)) {
        outp[out_i] = uvec2(0x7F800000u, 0u);
        return;
    }
    uint D = F.dims.z, N = 1u << D;
    // mirrored to positive directions, in cells from the cube's corner
    vec3 om = o - F.box.xyz;
    uvec3 flip = uvec3(0u);
    if (d.x < 0.0) { om.x = side - om.x; flip.x = N - 1u; }
    if (d.y < 0.0) { om.y = side - om.y; flip.y = N - 1u; }
    if (d.z < 0.0) { om.z = side - om.z; flip.z = N - 1u; }
    vec3 ad = max(abs(d), vec3(exp2(-23.0))); // tiny components would overflow the coefficients
    vec3 invd = 1.0 / ad;
    vec3 bias = -om * invd;

    float t = te;
    uint L = D;
    uvec3 P = uvec3(0u);
    uint steps = 0u;
    bool hit = false;
    while (steps < MAX_STEPS) {
        steps++;
        if (occupied(D, L, P, flip)) {
            if (L == 0u) { hit = true; break; }
            if (PROBE != 0u && L > 1u && (PROBE == 1u || L <= 3u)) {
                vec3 p = clamp(fma(vec3(t), ad, om), vec3(P), vec3(P + ((1u << L) - 1u)));
                if (occupied(D, 0u, uvec3(p), flip)) { hit = true; break; }
            }
            // push: the child holding the entry point
            L--;
            uint half_ = 1u << L;
            vec3 tm = fma(vec3(P + half_), invd, bias);
            if (tm.x <= t) P.x += half_;
            if (tm.y <= t) P.y += half_;
            if (tm.z <= t) P.z += half_;
            continue;
        }
        // advance to the neighbour, then rise to the highest level whose bit changed
        uint size = 1u << L;
        vec3 tc = fma(vec3(P + size), invd, bias);
        float tmin = min(min(tc.x, tc.y), tc.z);
        uvec3 Pn = P;
        if (tc.x <= tmin) Pn.x += size;
        if (tc.y <= tmin) Pn.y += size;
        if (tc.z <= tmin) Pn.z += size;
        t = max(t, tmin);
        if (max(max(Pn.x, Pn.y), Pn.z) >= N) break;
        uvec3 diff = P ^ Pn;
        L = uint(findMSB(diff.x | diff.y | diff.z));
        P = Pn & uvec3(~((1u << L) - 1u));
    }
    float td = hit ? t_off + t : uintBitsToFloat(0x7F800000u);
    outp[out_i] = uvec2(floatBitsToUint(td), steps | 0x80000000u);
}
