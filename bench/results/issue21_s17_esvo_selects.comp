#version 450
// bench/results/issue21_s17_esvo_selects.comp - bench/shaders/esvo.comp with its
// stack as a ladder of selects at constant indices (issue 21's seventeenth sitting:
// the same change as trace.comp's TRACE_STACK_SELECTS on CPU devices), for
// render_bench --esvo-kernel on lavapipe. Exact for octrees of depth <= 12 only
// (the ladder holds scales S_MAX - 12 .. S_MAX - 1; render_bench's depth
// agreement shows a deeper one). Otherwise bench/shaders/esvo.comp:
//
// bench/shaders/esvo.comp - the ESVO baseline of bench/render_bench: primary
// rays through a plain full-depth octree with the traversal loop of Laine and
// Karras, "Efficient Sparse Voxel Octrees" (2010), written for the benchmark.
//
// Octree (bench/esvo.c): groups of eight 32-bit child slots, one group per
// inner node, the root's group first. A slot: bit 31 valid, bit 30 leaf; a
// valid inner slot holds in bits 0-29 the slot index of its children's group,
// a leaf slot its RGB colour. Leaves are the scene's cells (no collapsing).
//
// The loop is the paper's: the cube is mapped to [1,2]^3 and mirrored so that
// every direction component is negative; cube corners are float bit patterns
// whose mantissa is the octree path, so a pop finds its level from the highest
// differing bit of the position. Without contours and with rays running to the
// cube's exit, the stack holds parents only and the ray's span is the root's
// (as in AdamYuan/SparseVoxelOctree's port of the paper's code). Rays are
// generated exactly as render/shaders/trace.comp generates them.
layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(std140, binding = 0) uniform Frame {
    vec4 fwd;   // w: t_start
    vec4 rx;    // w: ortho
    vec4 uy;
    vec4 box;   // xyz: octree cube corner relative to the frame reference, w: side
    uvec4 dims; // width, height
} F;
layout(std430, binding = 1) readonly buffer Slots { uint slots[]; };
layout(std430, binding = 2) writeonly buffer Out { uvec2 outp[]; }; // depth bits, steps | entered << 31

const int S_MAX = 23;
const uint MAX_STEPS = 100000u; // the same guard as voxkit's tracer

#define STK_PUT(S, V) { int s_ = (S); uint v_ = (V); \
    stack[11] = s_ == 11 ? v_ : stack[11]; \
    stack[12] = s_ == 12 ? v_ : stack[12]; \
    stack[13] = s_ == 13 ? v_ : stack[13]; \
    stack[14] = s_ == 14 ? v_ : stack[14]; \
    stack[15] = s_ == 15 ? v_ : stack[15]; \
    stack[16] = s_ == 16 ? v_ : stack[16]; \
    stack[17] = s_ == 17 ? v_ : stack[17]; \
    stack[18] = s_ == 18 ? v_ : stack[18]; \
    stack[19] = s_ == 19 ? v_ : stack[19]; \
    stack[20] = s_ == 20 ? v_ : stack[20]; \
    stack[21] = s_ == 21 ? v_ : stack[21]; \
    stack[22] = s_ == 22 ? v_ : stack[22]; \
}
#define STK_GET(S, OUT) { int s_ = (S); uint g_ = stack[S_MAX - 1]; \
    g_ = s_ == 11 ? stack[11] : g_; \
    g_ = s_ == 12 ? stack[12] : g_; \
    g_ = s_ == 13 ? stack[13] : g_; \
    g_ = s_ == 14 ? stack[14] : g_; \
    g_ = s_ == 15 ? stack[15] : g_; \
    g_ = s_ == 16 ? stack[16] : g_; \
    g_ = s_ == 17 ? stack[17] : g_; \
    g_ = s_ == 18 ? stack[18] : g_; \
    g_ = s_ == 19 ? stack[19] : g_; \
    g_ = s_ == 20 ? stack[20] : g_; \
    g_ = s_ == 21 ? stack[21] : g_; \
    OUT = g_; }

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
    // clip to the cube first, so that [1,2] keeps the octree's precision
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
    vec3 p = clamp(1.0 + (o + d * te - F.box.xyz) / side, vec3(1.0), vec3(2.0));

    // tiny components would overflow the coefficients
    const float eps = exp2(-float(S_MAX));
    if (abs(d.x) < eps) d.x = d.x < 0.0 ? -eps : eps;
    if (abs(d.y) < eps) d.y = d.y < 0.0 ? -eps : eps;
    if (abs(d.z) < eps) d.z = d.z < 0.0 ? -eps : eps;
    vec3 coef = 1.0 / -abs(d);
    vec3 bias = coef * p;
    uint mirror = 0u;
    if (d.x > 0.0) { mirror ^= 1u; bias.x = 3.0 * coef.x - bias.x; }
    if (d.y > 0.0) { mirror ^= 2u; bias.y = 3.0 * coef.y - bias.y; }
    if (d.z > 0.0) { mirror ^= 4u; bias.z = 3.0 * coef.z - bias.z; }

    float t_min = max(max(2.0 * coef.x - bias.x, 2.0 * coef.y - bias.y), 2.0 * coef.z - bias.z);
    float t_max = min(min(coef.x - bias.x, coef.y - bias.y), coef.z - bias.z);
    t_min = max(t_min, 0.0);
    float h = t_max;

    uint stack[S_MAX];
    uint parent = 0u;
    uint slot = 0u; // 0: not loaded (an empty slot is 0 too, so an advance past one reloads)
    vec3 pos = vec3(1.0);
    uint idx = 0u;
    if (1.5 * coef.x - bias.x > t_min) { idx ^= 1u; pos.x = 1.5; }
    if (1.5 * coef.y - bias.y > t_min) { idx ^= 2u; pos.y = 1.5; }
    if (1.5 * coef.z - bias.z > t_min) { idx ^= 4u; pos.z = 1.5; }
    int scale = S_MAX - 1;
    float scale_exp2 = 0.5;
    uint steps = 0u;
    bool hit = false;
    while (scale < S_MAX && steps < MAX_STEPS) {
        steps++;
        if (slot == 0u) slot = slots[parent + (idx ^ mirror)];
        vec3 tc = pos * coef - bias;
        float tc_max = min(min(tc.x, tc.y), tc.z);
        if ((slot & 0x80000000u) != 0u && t_min <= t_max) {
            if ((slot & 0x40000000u) != 0u) { hit = true; break; }
            // push: the stack entry is needed only if the child ends before the parent
            float half_ = scale_exp2 * 0.5;
            vec3 tcen = half_ * coef + tc;
            if (tc_max < h) STK_PUT(scale, parent)
            h = tc_max;
            parent = slot & 0x3FFFFFFFu;
            idx = 0u;
            scale--;
            scale_exp2 = half_;
            if (tcen.x > t_min) { idx ^= 1u; pos.x += scale_exp2; }
            if (tcen.y > t_min) { idx ^= 2u; pos.y += scale_exp2; }
            if (tcen.z > t_min) { idx ^= 4u; pos.z += scale_exp2; }
            slot = 0u;
            continue;
        }
        // advance (only past an empty slot, or at the ray's end)
        uint step = 0u;
        if (tc.x <= tc_max) { step ^= 1u; pos.x -= scale_exp2; }
        if (tc.y <= tc_max) { step ^= 2u; pos.y -= scale_exp2; }
        if (tc.z <= tc_max) { step ^= 4u; pos.z -= scale_exp2; }
        t_min = tc_max;
        idx ^= step;
        if ((idx & step) != 0u) {
            // pop to the highest level whose position bit changed
            uint diff = 0u;
            if ((step & 1u) != 0u) diff |= floatBitsToUint(pos.x) ^ floatBitsToUint(pos.x + scale_exp2);
            if ((step & 2u) != 0u) diff |= floatBitsToUint(pos.y) ^ floatBitsToUint(pos.y + scale_exp2);
            if ((step & 4u) != 0u) diff |= floatBitsToUint(pos.z) ^ floatBitsToUint(pos.z + scale_exp2);
            scale = findMSB(diff);
            if (scale >= S_MAX) break;
            scale_exp2 = uintBitsToFloat(uint(scale - S_MAX + 127) << 23);
            STK_GET(scale, parent)
            uvec3 sh = floatBitsToUint(pos) >> uint(scale);
            pos = uintBitsToFloat(sh << uint(scale));
            idx = (sh.x & 1u) | ((sh.y & 1u) << 1) | ((sh.z & 1u) << 2);
            h = 0.0;
            slot = 0u;
        }
    }
    float t = hit ? t_off + te + t_min * side : uintBitsToFloat(0x7F800000u);
    outp[out_i] = uvec2(floatBitsToUint(t), steps | 0x80000000u);
}
