#version 450
// render/shaders/gbuffer.comp - the G-buffer pass: one primary ray per pixel
// and sample through the BVH and the octrees (trace_common.glsl), the same
// rays as trace.comp (sample 0 the pixel centre, then an R2 sequence), or with
// DOF a thin lens: the origin jittered over a disc of radius PC.f0.x in the
// image plane's axes, aimed at the point where the pinhole ray meets the
// focus plane PC.f0.y in front of the eye. Float variant only.
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

// built with WALK_PRECISE (the walk not contracted; the rule and why: cmake/shaders.cmake)
// the lean walk where it applies (trace_common.glsl LEAN: no ids, GPU form),
// in the BVH kernels (several instances) too, as trace.comp's (issue 21, gbvh);
// (H200: this kernel of several instances 64 -> 56 registers, its pass 1.9-3.4% less time)
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

layout(constant_id = 5) const bool DOF = false;
const bool PHYS = false;
const uint FLAGS = 0u, SHOW = 0u;
#include "pass_bodies.glsl"

void main() {
    uvec2 px;
    uint i;
    if (!pass_pixel(px, i)) return;
    uvec4 g0, g1, ids0, ids1;
    gbuffer_pixel(px, PC.u0.x, g0, g1, ids0, ids1);
    gb0[i] = g0;
    gb1[i] = g1;
    if (WRITE_HITS && PC.u0.x == 0u) {
        gb2[2u * i] = ids0;
        gb2[2u * i + 1u] = ids1;
    }
}
