#version 450
// bench/shaders/tree64.comp - the 64-tree prototype of bench/render_bench
// (issue 21): primary rays through a sparse 64-tree (bench/tree64.c).
//
// A node is a uvec4: a 64-bit mask of its 4x4x4 children (bit x + 4 y + 16 z),
// the index of its children's block (children stored in mask order, so a
// child is the block plus the popcount of the mask below its bit) and a free
// word. Nodes of the last level hold the cells' mask only.
//
// The loop keeps the octree loop's frame (bench/shaders/esvo.comp, Laine and
// Karras 2010): the cube mapped to [1,2]^3 and mirrored so that every
// direction component is negative, positions as float bit patterns whose
// mantissa holds the path, a pop finding its level from the highest changed
// bit. Each step looks at one cell of a 4^3 node, its mirrored 2-bit
// coordinates kept in idx: a set bit descends (the child cell holding the ray
// from two plane tests per axis: the half, then the quarter), an empty cell is
// left through its exit planes (with SKIP 0 an empty aligned 2^3 group of
// cells as one cell of twice the size), and the node is left (a pop) only
// when a stepping axis was in the node's first cell. A node covers two
// octree levels, so a descent takes half the steps and crossings inside a
// node need no pop. Measured in docs/PERFORMANCE.md section 2 ("A 64-tree").
layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(std140, binding = 0) uniform Frame {
    vec4 fwd;   // w: t_start
    vec4 rx;    // w: ortho
    vec4 uy;
    vec4 box;   // xyz: cube corner relative to the frame reference, w: the 64-tree's side 4^levels
    uvec4 dims; // width, height, levels | clip depth << 8 (rays clipped to 2^clip cells), root node
} F;
layout(std430, binding = 1) readonly buffer Nodes { uvec4 nodes[]; };
layout(std430, binding = 2) writeonly buffer Out { uvec2 outp[]; }; // depth bits, steps | entered << 31

// 0: empty cells are left one at a time or as an empty aligned 2^3 group;
// 1: one at a time only (a shorter loop, more steps)
layout(constant_id = 0) const uint SKIP = 0u;

const int S_MAX = 23;
const uint MAX_STEPS = 100000u;

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
    int levels = int(F.dims.z & 0xFFu);
    float clip = exp2(float(F.dims.z >> 8));
    float side = F.box.w;
    vec3 inv;
    for (int k = 0; k < 3; k++) inv[k] = abs(d[k]) < 1e-30 ? (d[k] < 0.0 ? -1e30 : 1e30) : 1.0 / d[k];
    vec3 a = (F.box.xyz - o) * inv, b = (F.box.xyz + clip - o) * inv;
    vec3 tn = min(a, b), tf = max(a, b);
    float te = max(max(max(tn.x, tn.y), tn.z), 0.0);
    float tx = min(min(tf.x, tf.y), tf.z);
    if (!(te < tx) || F.dims.w == 0xFFFFFFFFu) {
        outp[out_i] = uvec2(0x7F800000u, te < tx ? 0x80000000u : 0u);
        return;
    }
    vec3 p = clamp(1.0 + (o + d * te - F.box.xyz) / side, vec3(1.0), vec3(2.0));

    const float eps = exp2(-float(S_MAX));
    if (abs(d.x) < eps) d.x = d.x < 0.0 ? -eps : eps;
    if (abs(d.y) < eps) d.y = d.y < 0.0 ? -eps : eps;
    if (abs(d.z) < eps) d.z = d.z < 0.0 ? -eps : eps;
    vec3 coef = 1.0 / -abs(d);
    vec3 bias = coef * p;
    uint flip = 0u; // real child bit = mirrored bit ^ flip (a mirrored axis's 2-bit coordinate is complemented)
    if (d.x > 0.0) { flip |= 3u; bias.x = 3.0 * coef.x - bias.x; }
    if (d.y > 0.0) { flip |= 12u; bias.y = 3.0 * coef.y - bias.y; }
    if (d.z > 0.0) { flip |= 48u; bias.z = 3.0 * coef.z - bias.z; }
    uvec3 flipv = uvec3(flip & 3u, (flip >> 2) & 3u, (flip >> 4) & 3u);

    float t_min = max(max(2.0 * coef.x - bias.x, 2.0 * coef.y - bias.y), 2.0 * coef.z - bias.z);
    t_min = max(t_min, 0.0);
    float t_max = (tx - te) / side; // the clip cube's exit, in [1,2] units

    uint stack[12];
    int scale = S_MAX - 2;      // the root's cells are 1/4 wide
    int leaf_scale = S_MAX - 2 * levels;
    float h = 0.25;             // cell size, 2^(scale - S_MAX)
    uint node = F.dims.w;
    uvec4 nd = nodes[node];
    // pos: the cell's lower corner (mirrored); idx: its mirrored 2-bit
    // coordinates in the node, x + 4 y + 16 z (the mask bit is idx ^ flip)
    vec3 pos = vec3(1.0);
    uint idx = 0u;
    {
        vec3 tc = -bias + coef; // t at pos = 1
        vec3 q = h * coef;
        bvec3 hi2 = greaterThan(tc + 2.0 * q, vec3(t_min));
        bvec3 q1 = greaterThan(tc + (2.0 * vec3(hi2) + 1.0) * q, vec3(t_min));
        uvec3 k = 2u * uvec3(hi2) + uvec3(q1);
        idx = k.x + 4u * k.y + 16u * k.z;
        pos += h * vec3(k);
    }
    uint steps = 0u;
    bool hit = false;
    while (steps < MAX_STEPS) {
        steps++;
        uint bit = idx ^ flip;
        uint word = bit < 32u ? nd.x : nd.y;
        uint b5 = bit & 31u;
        vec3 tc = pos * coef - bias;
        if ((word & (1u << b5)) != 0u) {
            if (scale == leaf_scale) { hit = true; break; }
            uint below = bitCount(word & ((1u << b5) - 1u)) + (bit < 32u ? 0 : bitCount(nd.x));
            stack[scale >> 1] = node;
            node = nd.z + uint(below);
            nd = nodes[node];
            scale -= 2;
            h *= 0.25;
            // the child cell holding the ray at t_min: the half by the middle
            // plane, then the quarter by the plane inside that half
            vec3 q = h * coef;
            bvec3 hi2 = greaterThan(tc + 2.0 * q, vec3(t_min));
            bvec3 q1 = greaterThan(tc + (2.0 * vec3(hi2) + 1.0) * q, vec3(t_min));
            uvec3 k = 2u * uvec3(hi2) + uvec3(q1);
            idx = k.x + 4u * k.y + 16u * k.z;
            pos += h * vec3(k);
            continue;
        }
        // advance: an empty aligned 2^3 group of cells is left at once
        uint gword = (bit & 32u) != 0u ? nd.y : nd.x;
        bool group = SKIP == 0u && (gword & (0x330033u << (bit & 10u))) == 0u;
        float sz = h;
        vec3 pc = pos;
        if (group) {
            uint m = ~((2u << uint(scale)) - 1u);
            pc = uintBitsToFloat(floatBitsToUint(pos) & m);
            sz = 2.0 * h;
            tc = pc * coef - bias;
        }
        float tc_max = min(min(tc.x, tc.y), tc.z);
        if (tc_max >= t_max) break; // the ray leaves the clip cube
        // the ray leaves the node when a stepping axis is in the node's
        // first cell (mirrored coordinate 0; of a group: below 2)
        bvec3 stp = lessThanEqual(tc, vec3(tc_max));
        uint ci = group ? idx & 0x2Au : idx;
        bool leave = (stp.x && (ci & 3u) == 0u) || (stp.y && (ci & 12u) == 0u) || (stp.z && (ci & 48u) == 0u);
        if (stp.x) pc.x -= sz;
        if (stp.y) pc.y -= sz;
        if (stp.z) pc.z -= sz;
        t_min = tc_max;
        if (leave) {
            uint diff = 0u;
            if (stp.x) diff |= floatBitsToUint(pc.x) ^ floatBitsToUint(pc.x + sz);
            if (stp.y) diff |= floatBitsToUint(pc.y) ^ floatBitsToUint(pc.y + sz);
            if (stp.z) diff |= floatBitsToUint(pc.z) ^ floatBitsToUint(pc.z + sz);
            int msb = findMSB(diff);
            // pop to the node whose cell field holds the highest changed bit
            scale += (msb - scale) & ~1;
            if (scale >= S_MAX) break;
            h = uintBitsToFloat(uint(scale - S_MAX + 127) << 23);
            node = stack[scale >> 1];
            nd = nodes[node];
            uvec3 pb = floatBitsToUint(pc) >> uint(scale);
            pos = uintBitsToFloat(pb << uint(scale));
            uvec3 c = pb & 3u;
            idx = c.x | (c.y << 2) | (c.z << 4);
        } else {
            pos = pc;
            uint dec = (stp.x ? 1u : 0u) + (stp.y ? 4u : 0u) + (stp.z ? 16u : 0u);
            if (group) {
                // the ray may be in either half of the group on each axis
                bvec3 up = greaterThan((pc + h) * coef - bias, vec3(t_min));
                pos += h * vec3(up);
                idx = ci - 2u * dec + (up.x ? 1u : 0u) + (up.y ? 4u : 0u) + (up.z ? 16u : 0u);
            } else {
                idx -= dec;
            }
        }
    }
    float t = hit ? t_off + te + t_min * side : uintBitsToFloat(0x7F800000u);
    outp[out_i] = uvec2(floatBitsToUint(t), steps | 0x80000000u);
}
