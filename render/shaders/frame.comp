#version 450
// render/shaders/frame.comp - the gbuffer, direct, ao and resolve passes
// merged into one dispatch per sample (render/pipeline.c merges them when
// nothing between them needs their images: no gi, no intermediate shown, ao
// only with few rays on a CPU device (which splits many over dispatches), and the caller did not ask for
// separate passes). The same functions as the pass shaders
// (pass_bodies.glsl), with the values in registers.
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

// built with WALK_PRECISE (the walk not contracted; the rule and why: cmake/shaders.cmake)
// the lean walk where it applies (trace_common.glsl LEAN: no ids, GPU form),
// in the BVH kernels (several instances) too, as trace.comp's (issue 21, gbvh);
// (H200: with several instances and the direct pass 1.8-3.2% less time)
// and at DEEP 2 (deep models, which the passes walk as trace.comp since gdeep), the colour
// mode's lean walk too (TRACE_LEAN_DEEP2_COLOR; trace.comp's colour kernel keeps the full one):
// terrain4096's G-buffer 4-7% less time, gbuffer+direct merged 4%, than with the full DEEP 2
// walk on the H200 (gdeep's C, bench/results/gdeep_h200.txt)
#define TRACE_LEAN
#define TRACE_LEAN_BVH
#define TRACE_LEAN_DEEP2
#define TRACE_LEAN_DEEP2_COLOR
#include "pass_grid.glsl"
#include "trace_common.glsl"
#include "passes_common.glsl"

layout(constant_id = 5) const uint FLAGS = 0u; // as resolve.comp (no gi)
layout(constant_id = 6) const bool DOF = false;
const uint SHOW = 0u;
const bool PHYS = (FLAGS & 16u) != 0u;
#define SMAP_BINDING 20 // the sun's depth map (direct_pixel; render/pipeline.c)
#define MAT_BINDING 23  // the records' materials where some is metal or glass (pass_bodies.glsl METAL, GLASS)
#include "smap_lookup.glsl"
#include "pass_bodies.glsl"
#include "display_out.glsl"

void main() {
    uvec2 px;
    uint i;
    if (!pass_pixel(px, i)) return;
    uvec4 g0, g1, ids0, ids1;
    gbuffer_pixel(px, PC.u0.x, g0, g1, ids0, ids1);
    if (WRITE_HITS && PC.u0.x == 0u) {
        gb2[2u * i] = ids0;
        gb2[2u * i + 1u] = ids1;
    }
    vec4 dir = HAS_DIRECT ? direct_pixel(px, g0, g1) : vec4(0.0);
    float ao = 1.0;
    if (HAS_AO && g1.y != NO_HIT) {
        uint n = max(PC.u0.z, 1u);
        ao = 1.0 - ao_blocked(px, g0, g1, 0u, n) / float(n);
    }
    vec4 c = resolve_pixel(g0, g1, dir, ao, vec4(0.0));
#ifdef DISPLAY_OUT
    // one sample: its colour is the frame's (accumulate's c / 1), and the float image is not kept
    if (PC.u0.y <= 1u) {
        display_store(px, i, c);
        return;
    }
#endif
    accumulate(i, c);
#ifdef DISPLAY_OUT
    if (PC.u0.x + 1u == PC.u0.y) display_store(px, i, acc_img[i]); // the last sample: the frame's colour
#endif
}
