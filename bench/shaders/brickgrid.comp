#version 450
// bench/shaders/brickgrid.comp - the two-level grid prototype of
// bench/render_bench (bench/brickgrid.h): primary rays by a hierarchical
// DDA. Coarse cells are 8^3-cell bricks; in an empty coarse cell the ray
// leaves the empty cube of the cell's distance in one step (SKIP 1; SKIP 0
// one coarse cell a step, the plain two-level DDA); in an occupied one it
// walks the brick's cells by a DDA over the brick's 512 bits until a set bit
// (the hit) or the brick's face, then goes on in the neighbour coarse cell
// across that face. Directions are mirrored to be positive (a mirrored
// axis's stored index is the walked one xor (2^depth - 1)), so a cell is left
// through its upper planes only. Rays are generated exactly as
// render/shaders/trace.comp and bench/shaders/esvo.comp generate them.
layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
layout(constant_id = 0) const uint SKIP = 1u;

layout(std140, binding = 0) uniform Frame {
    vec4 fwd;   // w: t_start
    vec4 rx;    // w: ortho
    vec4 uy;
    vec4 box;   // xyz: the cube's corner relative to the frame reference, w: side (2^depth)
    uvec4 dims; // width, height, depth
} F;
layout(std430, binding = 1) readonly buffer Words { uint words[]; };
layout(std430, binding = 2) writeonly buffer Out { uvec2 outp[]; }; // depth bits, steps | entered << 31

const uint MAX_STEPS = 100000u; // the same guard as voxkit's tracer

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
    uint D = F.dims.z, N = 1u << D, C = N >> 3;
    // mirrored to positive directions, in cells from the cube's corner
    vec3 om = o - F.box.xyz;
    uvec3 flip = uvec3(0u);
    if (d.x < 0.0) { om.x = side - om.x; flip.x = N - 1u; }
    if (d.y < 0.0) { om.y = side - om.y; flip.y = N - 1u; }
    if (d.z < 0.0) { om.z = side - om.z; flip.z = N - 1u; }
    vec3 ad = max(abs(d), vec3(exp2(-23.0))); // tiny components would overflow the coefficients
    vec3 invd = 1.0 / ad;
    vec3 bias = -om * invd;
    uvec3 cflip = flip >> 3u;                                       // coarse index flip
    uint bflip = (flip.x & 7u) | ((flip.y & 7u) << 3) | ((flip.z & 7u) << 6); // bit index flip in a brick
    uint C2 = C * C, C3 = C2 * C;

    float t = te;
    uvec3 f = min(uvec3(max(fma(vec3(t), ad, om), vec3(0.0))), uvec3(N - 1u)); // cell
    uvec3 P = f >> 3u;                                                         // coarse cell
    bool fine = false;
    uint brick = 0u;
    uint steps = 0u;
    bool hit = false;
    while (steps < MAX_STEPS) {
        steps++;
        if (!fine) {
            uvec3 q = P ^ cflip;
            uint w = words[q.z * C2 + q.y * C + q.x];
            if (w < 0x80000000u) {
                // an occupied coarse cell: its brick from the cell the ray is in
                fine = true;
                brick = C3 + 16u * w;
                uvec3 lo8 = P << 3u;
                f = clamp(uvec3(max(fma(vec3(t), ad, om), vec3(0.0))), lo8, lo8 + 7u);
                continue;
            }
            uint dist = SKIP != 0u ? (w & 0xFFFFu) : 1u;
            vec3 tc = fma(vec3((P + dist) << 3u), invd, bias);
            float tmin = min(min(tc.x, tc.y), tc.z);
            t = max(t, tmin);
            uvec3 Pn = P + dist;
            if (dist > 1u) {
                // the other axes where the ray leaves the empty cube (within it: clamped)
                uvec3 at = uvec3(max(fma(vec3(tmin), ad, om), vec3(0.0))) >> 3u;
                at = clamp(at, P, P + (dist - 1u));
                Pn = mix(at, Pn, lessThanEqual(tc, vec3(tmin)));
            } else {
                Pn = mix(P, Pn, lessThanEqual(tc, vec3(tmin)));
            }
            P = Pn;
            if (max(max(P.x, P.y), P.z) >= C) break;
        } else {
            uint i = (((f.z & 7u) << 6) | ((f.y & 7u) << 3) | (f.x & 7u)) ^ bflip;
            if (((words[brick + (i >> 5)] >> (i & 31u)) & 1u) != 0u) { hit = true; break; }
            vec3 tc = fma(vec3(f + 1u), invd, bias);
            float tmin = min(min(tc.x, tc.y), tc.z);
            t = max(t, tmin);
            f += uvec3(lessThanEqual(tc, vec3(tmin)));
            uvec3 Pn = f >> 3u;
            if (Pn != P) {
                // left the brick across a face (or an edge or corner): the coarse cell there
                P = Pn;
                fine = false;
                if (max(max(P.x, P.y), P.z) >= C) break;
            }
        }
    }
    float td = hit ? t_off + t : uintBitsToFloat(0x7F800000u);
    outp[out_i] = uvec2(floatBitsToUint(td), steps | 0x80000000u);
}
