#version 450
// render/shaders/inst_rows.comp - the instance rows of a recorded frame on the
// GPU (render/render_scene.c): from each instance's rows relative to the
// world (model from world, in double, and its world box), written when the
// instances change, the rows relative to the frame's reference point R the
// trace reads (render_internal.h vx__gpu_inst) and the box the BVH refit
// starts from (refit.comp), as the host's frame_tables and instance_boxes
// compute them, bit for bit: the same double operations in the same order
// (precise: no fused multiply-add), rounded to float once, the boxes
// rounded outward. So a camera move writes no row: only R changes.
layout(local_size_x = 64) in;

struct Src {           // render_scene.c inst_src, 160 bytes
    double inv[12];    // model from world, rows of 4
    double lo[3], hi[3]; // world box
    uint model, id;
    float cell;
    uint pad;
};
struct Inst { vec4 r[3]; uint model; float cell; uint id; float pad; vec4 lo; }; // vx__gpu_inst
layout(std430, binding = 0) readonly buffer Srcs { Src src[]; };
layout(std430, binding = 1) writeonly buffer Insts { Inst inst[]; };
layout(std430, binding = 2) writeonly buffer Boxes { vec4 boxes[]; }; // per instance: lo, hi
layout(push_constant) uniform Push {
    uint count;
    uint pad;
    uvec2 ref[3]; // R, doubles as their two words
} pc;

// The float next to f towards -inf (+inf): nextafterf.
float below(float f) {
    uint b = floatBitsToUint(f);
    if ((b & 0x7FFFFFFFu) == 0u) return uintBitsToFloat(0x80000001u);
    return uintBitsToFloat(f > 0.0 ? b - 1u : b + 1u);
}
float above(float f) {
    uint b = floatBitsToUint(f);
    if ((b & 0x7FFFFFFFu) == 0u) return uintBitsToFloat(1u);
    return uintBitsToFloat(f > 0.0 ? b + 1u : b - 1u);
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    double R[3] = double[3](packDouble2x32(pc.ref[0]), packDouble2x32(pc.ref[1]), packDouble2x32(pc.ref[2]));
    Inst o;
    for (int r = 0; r < 3; r++) {
        precise double p0 = src[i].inv[4 * r] * R[0];
        precise double p1 = src[i].inv[4 * r + 1] * R[1];
        precise double p2 = src[i].inv[4 * r + 2] * R[2];
        precise double w = ((p0 + p1) + p2) + src[i].inv[4 * r + 3];
        float fw = float(w);
        o.r[r] = vec4(float(src[i].inv[4 * r]), float(src[i].inv[4 * r + 1]), float(src[i].inv[4 * r + 2]), fw);
        precise double d = w - double(fw);
        o.lo[r] = float(d);
    }
    o.lo.w = 0.0;
    o.model = src[i].model;
    o.cell = src[i].cell;
    o.id = src[i].id;
    o.pad = 0.0;
    inst[i] = o;
    vec4 lo = vec4(0.0), hi = vec4(0.0);
    for (int k = 0; k < 3; k++) {
        precise double a = src[i].lo[k] - R[k];
        precise double b = src[i].hi[k] - R[k];
        float fa = float(a), fb = float(b);
        if (double(fa) > a) fa = below(fa);
        if (double(fb) < b) fb = above(fb);
        lo[k] = fa, hi[k] = fb;
    }
    boxes[2u * i] = lo;
    boxes[2u * i + 1u] = hi;
}
