#version 450
// render/shaders/ao.comp - ray-traced ambient occlusion: PC.u0.z
// cosine-weighted rays of length PC.f0.z (world units) from just off the
// surface; writes the unoccluded share (1: open, 0: fully occluded). Rays
// stop at the first hit (any-hit traversal), so short rays stay cheap.
// The rays may come in several dispatches (rays PC.u1.x .. +PC.u1.y): the
// image holds the blocked count until the last one turns it into the share.
// Ray k's directions depend on k alone, so the split does not change the
// result; it exists for llvmpipe, which silently ends every loop of a group
// of invocations after 65535 iterations in all (see probes/shaders/probe.comp).
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

#include "pass_grid.glsl"
#include "trace_common.glsl"
#include "passes_common.glsl"

const bool DOF = false, PHYS = false;
const uint FLAGS = 0u, SHOW = 0u;
#include "pass_bodies.glsl"

void main() {
    uvec2 px;
    uint i;
    if (!pass_pixel(px, i)) return;
    uvec4 g1 = gb1[i];
    if (g1.y == NO_HIT) {
        ao_img[i] = 1.0;
        return;
    }
    uint n = max(PC.u0.z, 1u), first = PC.u1.x, count = PC.u1.y;
    float blocked = (first == 0u ? 0.0 : ao_img[i]) + ao_blocked(px, gb0[i], g1, first, count);
    ao_img[i] = first + count >= n ? 1.0 - blocked / float(n) : blocked;
}
