#version 450
// cones/shaders/filter.comp - level PC.u2.x of the radiance volume from the
// level below (cones/cones.h, "filter"), one invocation per voxel.
// Isotropic: the mean of the 8 children (children past the level's end are
// empty). Anisotropic, per side: in each of the 4 columns along the side's
// axis the child on that side composited over the one behind it
// (c = c_f + (1 - a_f) c_b, a = a_f + (1 - a_f) a_b), then the columns' mean.
//   STAGE 0: every voxel of the level (PC.u2.x).
//   STAGE 1: only the level's occupied voxels, llist[PC.u2.y + gid] (as many
//     as llist[level]): after a light change every other voxel is empty and
//     stays as STAGE 0 left it.
//   STAGE 2: the occupied list of level PC.u2.x (from PC.u2.y) from the one
//     below (level 0: List; else from PC.u2.z): each parent once, by its
//     occupancy bit (flags, one per voxel of the pyramid, by vol_index).
//   STAGE 5: level PC.u2.x copied into vol[] (vx_cone_gi_read_level).
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

#include "trace_common.glsl"
#include "passes_common.glsl"
const bool DOF = false, PHYS = true;
const uint FLAGS = 0u, SHOW = 0u;
#include "pass_bodies.glsl"
#include "cone_common.glsl"

layout(constant_id = 5) const uint STAGE = 0u;
#define flags cl
#define llist lidx

vec4 child(uint l, uvec3 c, uint e) {
    uvec3 n = CP.dims[l].xyz;
    if (any(greaterThanEqual(c, n))) return vec4(0.0);
    return vol_get(l, c, e);
}

void main() {
    uint gid = gl_GlobalInvocationID.y * (gl_NumWorkGroups.x * 64u) + gl_GlobalInvocationID.x;
    uint l = PC.u2.x;
    uvec4 d = CP.dims[l];
    if (STAGE == 2u) {
        uint child;
        uvec4 dc = CP.dims[l - 1u];
        if (l == 1u) {
            if (gid >= list[0]) return;
            child = list[1u + gid];
        } else {
            if (gid >= llist[l - 1u]) return;
            child = llist[PC.u2.z + gid];
        }
        uvec3 cc = uvec3(child % dc.x, (child / dc.x) % dc.y, child / (dc.x * dc.y));
        uvec3 pc = cc / 2u;
        uint bit = vol_index(l, pc);
        uint m = 1u << (bit & 31u);
        if ((atomicOr(flags[bit >> 5], m) & m) == 0u) llist[PC.u2.y + atomicAdd(llist[l], 1u)] = (pc.z * d.y + pc.y) * d.x + pc.x;
        return;
    }
    if (STAGE == 5u) {
        if (gid >= d.x * d.y * d.z) return;
        uvec3 c = uvec3(gid % d.x, (gid / d.x) % d.y, gid / (d.x * d.y));
        for (uint e = 0u; e < ENTRIES; e++) {
            vec4 v = vol_get(l, c, e);
            vol[gid * ENTRIES + e] = uvec2(packHalf2x16(v.xy), packHalf2x16(v.zw));
        }
        return;
    }
    uint vox = gid;
    if (STAGE == 1u) {
        if (gid >= llist[l]) return;
        vox = llist[PC.u2.y + gid];
    } else if (gid >= d.x * d.y * d.z) {
        return;
    }
    uvec3 c = uvec3(vox % d.x, (vox / d.x) % d.y, vox / (d.x * d.y));
    uvec3 b = c * 2u;
    if (ENTRIES == 1u) {
        vec4 sum = vec4(0.0);
        for (uint k = 0u; k < 8u; k++) sum += child(l - 1u, b + uvec3(k & 1u, (k >> 1) & 1u, (k >> 2) & 1u), 0u);
        vol_put(l, c, 0u, sum * 0.125);
        return;
    }
    for (uint side = 0u; side < 6u; side++) {
        uint axis = side >> 1;
        uint front = (side & 1u) == 0u ? 1u : 0u; // the +x side's front child is the upper one
        vec4 sum = vec4(0.0);
        for (uint k = 0u; k < 4u; k++) {
            uvec3 cf, cb;
            uint p = k & 1u, q = k >> 1;
            if (axis == 0u) cf = uvec3(front, p, q), cb = uvec3(1u - front, p, q);
            else if (axis == 1u) cf = uvec3(p, front, q), cb = uvec3(p, 1u - front, q);
            else cf = uvec3(p, q, front), cb = uvec3(p, q, 1u - front);
            vec4 f = child(l - 1u, b + cf, side), bk = child(l - 1u, b + cb, side);
            sum += f + (1.0 - f.a) * bk;
        }
        vol_put(l, c, side, sum * 0.25);
    }
}
