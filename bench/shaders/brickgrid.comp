#version 450
// bench/shaders/brickgrid.comp - the grid hierarchy prototype of
// bench/render_bench (bench/brickgrid.h, layout in bench/brickgrid.c):
// primary rays by a hierarchical DDA. At each level the ray walks the
// level's cells; an occupied entry is entered (the cell the ray is in, one
// level down), an empty one is left in one step through its empty cube
// (SKIP 1: the entry's distance, within its node; SKIP 0: the cell alone),
// a step out of a node goes up to the cell beside it one level up; a set
// bit of a brick is the hit. Directions are mirrored to be positive (a
// mirrored axis's stored index is the walked one xor (2^depth - 1)), so a
// cell is left through its upper planes only. Rays are generated exactly as
// render/shaders/trace.comp and bench/shaders/esvo.comp generate them; they
// start where they enter the occupied cells' box.
layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
layout(constant_id = 0) const uint SKIP = 1u;
layout(constant_id = 1) const uint TOP = 1u; // the root's level (1-3; the header's word 0), a constant for the compiler
// FCOORD 1: a brick's DDA keeps its cells' upper planes as floats beside the integer cell (two adds a step for
// three integer-to-float conversions; the same values, so the same t)
layout(constant_id = 2) const uint FCOORD = 0u;

layout(std140, binding = 0) uniform Frame {
    vec4 fwd;   // w: t_start
    vec4 rx;    // w: ortho
    vec4 uy;
    vec4 box;   // xyz: the cube's corner relative to the frame reference, w: side (2^depth)
    uvec4 dims; // width, height, depth
    uvec4 hdr0; // the buffer's header (bench/brickgrid.c): top, R, the occupied cells' box lo
    uvec4 hdr1; //   (x, y) and hi (.. w)
    uvec4 rect; // the pixels [x, z) x [y, w) whose rays can meet that box (bench/brickgrid.c screen_rect)
} F;
layout(std430, binding = 1) readonly buffer Words { uint words[]; };
layout(std430, binding = 2) writeonly buffer Out { uvec2 outp[]; }; // depth bits, steps | entered << 31

const uint MAX_STEPS = 100000u; // the same guard as voxkit's tracer
const uint HEADER = 8u;

void main() {
    uvec2 px = gl_GlobalInvocationID.xy;
    uint W = F.dims.x, H = F.dims.y;
    if (px.x >= W || px.y >= H) return;
    uint out_i = px.y * W + px.x;
    if (px.x < F.rect.x || px.y < F.rect.y || px.x >= F.rect.z || px.y >= F.rect.w) {
        outp[out_i] = uvec2(0x7F800000u, 0u); // a ray that cannot meet the box, not made
        return;
    }
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
    uint R = F.hdr0.y;
    vec3 blo = vec3(F.hdr0.zw, F.hdr1.x), bhi = vec3(F.hdr1.yzw);
    vec3 inv;
    for (int k = 0; k < 3; k++) inv[k] = abs(d[k]) < 1e-30 ? (d[k] < 0.0 ? -1e30 : 1e30) : 1.0 / d[k];
    vec3 a = (F.box.xyz + blo - o) * inv, b = (F.box.xyz + bhi - o) * inv;
    vec3 tn = min(a, b), tf = max(a, b);
    float te = max(max(max(tn.x, tn.y), tn.z), 0.0);
    float tx = min(min(tf.x, tf.y), tf.z);
    if (!(te < tx)) {
        outp[out_i] = uvec2(0x7F800000u, 0u);
        return;
    }
    float side = F.box.w;
    uint D = F.dims.z, N = 1u << D;
    // mirrored to positive directions, in cells from the cube's corner
    vec3 om = o - F.box.xyz;
    uvec3 flip = uvec3(0u);
    if (d.x < 0.0) { om.x = side - om.x; flip.x = N - 1u; }
    if (d.y < 0.0) { om.y = side - om.y; flip.y = N - 1u; }
    if (d.z < 0.0) { om.z = side - om.z; flip.z = N - 1u; }
    vec3 ad = max(abs(d), vec3(exp2(-23.0))); // tiny components would overflow the coefficients
    // 1 / ad without three more divisions: 1 / |d| is |1 / d| exactly (both correctly rounded), and where
    // |d| < 2^-23 (inv 1e30 below 1e-30) both sides are 2^23
    vec3 invd = min(abs(inv), vec3(exp2(23.0)));
    vec3 bias = -om * invd;
    uint bflip = (flip.x & 7u) | ((flip.y & 7u) << 3) | ((flip.z & 7u) << 6); // a brick's bit index, mirrored

    float t = te;
    uint lv = TOP, sh = 3u * TOP; // the walk's level above the bricks (in a brick: 1)
    // LV and SH: the level and its shift, constants where the root is level 1 (the compiler then drops the
    // level's bookkeeping: this loop is then the two-level walk of 5674ddb)
#define LV (TOP == 1u ? 1u : lv)
#define SH (TOP == 1u ? 3u : sh)
    uvec3 f = min(uvec3(max(fma(vec3(t), ad, om), vec3(0.0))), uvec3(N - 1u)); // the cell (in a brick)
    uvec3 P = f >> SH;                                                         // the cell at level lv
    bool fine = false;
    vec3 fu = vec3(0.0); // FCOORD: vec3(f + 1u) in a brick
    uint base0 = 0u, base1 = 0u, base2 = 0u; // the brick and the nodes of levels 1 and 2 the walk is in
    // (three words, not an array: an array indexed by the level went to local memory)
    uint steps = 0u;
    bool hit = false;
    while (steps < MAX_STEPS) {
        steps++;
        uvec3 Pn;
        if (fine) {
            // a brick's cells by the plain DDA; leaving it, the level-1 cell beside it
            uint i = (((f.z & 7u) << 6) | ((f.y & 7u) << 3) | (f.x & 7u)) ^ bflip;
            if (((words[base0 + (i >> 5)] >> (i & 31u)) & 1u) != 0u) { hit = true; break; }
            vec3 tc = fma(FCOORD != 0u ? fu : vec3(f + 1u), invd, bias);
            float tmin = min(min(tc.x, tc.y), tc.z);
            t = max(t, tmin);
            bvec3 st = lessThanEqual(tc, vec3(tmin));
            f += uvec3(st);
            if (FCOORD != 0u) fu += vec3(st);
            Pn = f >> 3u;
            if (Pn == P) continue;
            fine = false;
        } else {
            uvec3 lf = flip >> SH; // a mirrored axis's index at this level: xor all ones
            uint w;
            if (LV == TOP) {
                uvec3 q = P ^ lf;
                w = words[HEADER + (q.z * R + q.y) * R + q.x];
            } else {
                uvec3 q = (P ^ lf) & 7u;
                w = words[(LV == 1u ? base1 : base2) + (q.x | (q.y << 3) | (q.z << 6))];
            }
            if (w < 0x80000000u) {
                // occupied: one level down, the cell the ray is in (at level 1: the brick's cell)
                uvec3 lo8 = P << 3u;
                uvec3 c = uvec3(max(fma(vec3(t), ad, om), vec3(0.0)));
                if (LV == 1u) {
                    fine = true;
                    base0 = w;
                    f = clamp(c, lo8, lo8 + 7u);
                    if (FCOORD != 0u) fu = vec3(f + 1u);
                } else {
                    lv--;
                    sh -= 3u;
                    if (LV == 1u) base1 = w;
                    else base2 = w;
                    P = clamp(c >> SH, lo8, lo8 + 7u);
                }
                continue;
            }
            // empty: leave the empty cube [P - dist + 1, P + dist) (within the node below the root)
            uint dist = SKIP != 0u ? (w & 0x7Fu) : 1u; // (render/grid.h: its octant extents above bit 6 not read)
            uvec3 up = P + dist;
            if (LV < TOP) up = min(up, (P | 7u) + 1u);
            vec3 tc = fma(vec3(up << SH), invd, bias);
            float tmin = min(min(tc.x, tc.y), tc.z);
            t = max(t, tmin);
            Pn = P;
            if (dist > 1u) Pn = clamp(uvec3(max(fma(vec3(tmin), ad, om), vec3(0.0))) >> SH, P, up - 1u);
            Pn = mix(Pn, up, lessThanEqual(tc, vec3(tmin)));
        }
        if (t >= tx) break; // out of the occupied cells' box
        // a step out of its node: the cell beside it one level up (and so on)
        while (LV < TOP && (Pn >> 3u) != (P >> 3u)) {
            P >>= 3u;
            Pn >>= 3u;
            lv++;
            sh += 3u;
        }
        P = Pn;
        if (LV == TOP && max(max(P.x, P.y), P.z) >= R) break;
    }
    float td = hit ? t_off + t : uintBitsToFloat(0x7F800000u);
    outp[out_i] = uvec2(floatBitsToUint(td), steps | 0x80000000u);
}
