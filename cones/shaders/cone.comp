#version 450
// cones/shaders/cone.comp - the gi pass of voxel cone tracing (cones/cones.h):
// per pixel the pixel-centre primary ray (as the G-buffer's), then diffuse
// cones from its surface through the radiance volume. Writes gi_img: the
// indirect radiance albedo * sum w_i L_i and, in alpha, the cone AO (with
// CP.ctl.y == 1 the AO in every channel).
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

#include "trace_common.glsl"
#include "passes_common.glsl"
const bool DOF = false, PHYS = true;
const uint FLAGS = 0u, SHOW = 0u;
#include "pass_bodies.glsl"
#include "cone_common.glsl"

void main() {
    uvec2 px;
    uint i;
    if (!pass_pixel(px, i)) return;
    uvec4 g0, g1, ids0, ids1;
    gbuffer_pixel(px, 0u, g0, g1, ids0, ids1);
    if (g1.y == NO_HIT) {
        gi_img[i] = vec4(0.0, 0.0, 0.0, 1.0);
        return;
    }
    vec3 nw = gb_normal(g1);
    vec3 alb = HAS_COLOR ? unpack_rgb(g1.x) : vec3(1.0);
    vec3 p = uintBitsToFloat(g0.xyz);
    vec3 q = (p - CP.origin.xyz) / CP.origin.w + nw * CP.cone.y;
    float ao;
    // a new turn of the cone set per accumulated sample (golden angle)
    vec3 L = cone_gather(q, nw, float(PC.u0.x) * 2.399963, PC.f2.xyz, ao);
    gi_img[i] = CP.ctl.y == 1u ? vec4(ao) : vec4(alb * L, ao);
}
