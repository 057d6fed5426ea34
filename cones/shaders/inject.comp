#version 450
// cones/shaders/inject.comp - light into level 0 of the radiance volume
// (cones/cones.h, "inject"), one invocation per listed voxel.
//   STAGE 0: each side's recorded surface is lit: emission + albedo / pi *
//     (the sun, n.l, one shadow ray + every frame light with light_eval and
//     one shadow ray each) + (CP.ctl.z) the gathered indirect radiance;
//     written as the voxel's entries (isotropic: the mean radiance of the
//     visible surfaces times the mean opacity of the six sides).
//   STAGE 1: each visible surface gathers diffuse cones from the current
//     volume (the next bounce), kept in its record.
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

// built with WALK_PRECISE (the shadow rays' walk not contracted; the rule and why: cmake/shaders.cmake)
#include "trace_common.glsl"
#include "passes_common.glsl"
const bool DOF = false, PHYS = true;
const uint FLAGS = 0u, SHOW = 0u;
#include "pass_bodies.glsl"
#include "cone_common.glsl"

layout(constant_id = 5) const uint STAGE = 0u;

bool shadowed(vec3 p, vec3 d, float len) {
    Hit h;
    h.t = len;
    h.inst = NO_HIT;
    g_iter = 0u;
    return trace_scene(p, d, 0.0, true, h);
}

void main() {
    uint gid = gl_GlobalInvocationID.y * (gl_NumWorkGroups.x * 64u) + gl_GlobalInvocationID.x;
    if (gid >= list[0]) return;
    uint vox = list[1u + gid];
    uvec4 d0 = CP.dims[0];
    uvec3 c = uvec3(vox % d0.x, (vox / d0.x) % d0.y, vox / (d0.x * d0.y));
    float s = CP.origin.w;
    vec3 rad[6];
    float alpha_sum = 0.0, seen_sum = 0.0;
    vec3 rad_sum = vec3(0.0);
    for (uint side = 0u; side < 6u; side++) {
        uint r = (gid * 6u + side) * 5u;
        vec4 r0 = rec[r], r1 = rec[r + 1u];
        alpha_sum += r0.w;
        rad[side] = vec3(0.0);
        if (!(r1.w > 0.0)) continue;
        vec3 p = r0.xyz + CP.origin.xyz, n = r1.xyz;
        vec3 alb = rec[r + 2u].xyz;
        if (STAGE == 1u) {
            float ao;
            vec3 q = r0.xyz / s + n * CP.cone.y;
            rec[r + 4u] = vec4(alb * cone_gather(q, n, 0.0, PC.f2.xyz, ao), 0.0);
            continue;
        }
        vec3 e = vec3(0.0);
        float ndl = dot(n, F.light.xyz);
        if (ndl > 0.0 && any(greaterThan(PC.f1.xyz, vec3(0.0))) && !shadowed(p, F.light.xyz, 3.0e38))
            e += PC.f1.xyz * ndl;
        bool emissive = any(greaterThan(rec[r + 3u].xyz, vec3(0.0))); // not lit by its own lamp's sphere (light_eval)
        for (uint k = 0u; k < PC.u1.z; k++) {
            vec3 le, sd;
            float st;
            if (!light_eval(k, p, n, s, emissive, uvec2(gid, side), le, sd, st)) continue;
            if (st <= 0.0 || !shadowed(p, sd, st)) e += le;
        }
        vec3 L = rec[r + 3u].xyz + alb / PI * e;
        if (CP.ctl.z != 0u) L += rec[r + 4u].xyz;
        rad[side] = L * r1.w; // premultiplied by the share of rays that see it
        rad_sum += rad[side];
        seen_sum += r1.w;
    }
    if (STAGE == 1u) return;
    if (ENTRIES == 1u) {
        float a = alpha_sum / 6.0;
        vol_put(0u, c, 0u, vec4(seen_sum > 0.0 ? rad_sum / seen_sum * a : vec3(0.0), a));
    } else {
        // a side's rays that start inside solid cells see an interior; it is
        // given the voxel's mean surface radiance (as the isotropic entry),
        // not black: a cone reads sides by its direction's squares, so a
        // diagonal cone onto a slab also reads the sides along the slab, and
        // black there would darken the slab's lit face
        vec3 mean = seen_sum > 0.0 ? rad_sum / seen_sum : vec3(0.0);
        for (uint side = 0u; side < 6u; side++) {
            uint r = (gid * 6u + side) * 5u;
            float a = rec[r].w;
            vol_put(0u, c, side, vec4(rad[side] + max(a - rec[r + 1u].w, 0.0) * mean, a));
        }
    }
}
