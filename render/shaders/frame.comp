#version 450
// render/shaders/frame.comp - the gbuffer, direct and resolve passes merged
// into one dispatch per sample (render/pipeline.c merges them when nothing
// between them needs their images: no ao, no gi, no intermediate shown, and
// the caller did not ask for separate passes). The same functions as the
// three shaders (pass_bodies.glsl), with the values in registers.
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

#include "trace_common.glsl"
#include "passes_common.glsl"

layout(constant_id = 5) const uint FLAGS = 0u; // as resolve.comp (direct only)
layout(constant_id = 6) const bool DOF = false;
const uint SHOW = 0u;
const bool PHYS = false;
#include "pass_bodies.glsl"

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
    vec4 dir = HAS_DIRECT ? direct_pixel(g0, g1) : vec4(0.0);
    accumulate(i, resolve_pixel(g0, g1, dir, 1.0, vec4(0.0)));
}
