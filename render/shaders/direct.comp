#version 450
// render/shaders/direct.comp - the direct-light pass: the sun, or the
// frame's lights through the light grid of cull.comp, with ray-traced
// shadows; see direct_pixel in pass_bodies.glsl.
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

#include "pass_grid.glsl"
#include "trace_common.glsl"
#include "passes_common.glsl"

layout(constant_id = 6) const bool PHYS = false;
const bool DOF = false;
const uint FLAGS = 0u, SHOW = 0u;
#define SMAP_BINDING 20 // the sun's depth map (direct_pixel; render/pipeline.c)
#define MAT_BINDING 23  // the records' materials where some is metal or glass (pass_bodies.glsl METAL, GLASS)
#include "smap_lookup.glsl"
#include "pass_bodies.glsl"

void main() {
    uvec2 px;
    uint i;
    if (!pass_pixel(px, i)) return;
    direct_img[i] = direct_pixel(px, gb0[i], gb1[i]);
}
