#version 450
// cones/shaders/voxelize.comp - level 0 of the radiance volume from the
// octrees (cones/cones.h, "voxelize"). Each voxel is crossed by S x S
// axis-parallel rays from each of its six faces, over the voxel's length
// only (from just outside the face to just before the opposite one).
//   STAGE 0, per voxel: the opacity seen from each side (the share of its
//     rays that hit anything) written with zero radiance; voxels with a hit
//     are appended to the list.
//   STAGE 1, per listed voxel: the hits again, recorded per side: the
//     visible surface's mean point (at the nearest hit's depth, a hair
//     towards the viewer), normal, albedo and emission, and the share of
//     rays that see a surface rather than an interior (a ray whose start is
//     already inside a solid cell: its side is covered by the neighbour, and
//     the voxel's own cells behind that are opaque but unseen).
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

// built with WALK_PRECISE (the face rays' walk not contracted; the rule and why: cmake/shaders.cmake)
#include "trace_common.glsl"
#include "passes_common.glsl"
const bool DOF = false, PHYS = true;
const uint FLAGS = 0u, SHOW = 0u;
// Glass (pass_bodies.glsl GLASS, cones/cones.c glass_lights; its records cone_common.glsl's cmat, binding 15):
// a ray that meets glass counts 1 - transmission of a hit, and the glass is no surface of the voxel, so
// that the cones see through it (the light of a room behind a window, of the sky through a greenhouse)
#define MAT_BINDING 15
#include "pass_bodies.glsl"
#include "cone_common.glsl"

// What a hit on attribute record attr counts: 1, or 1 - transmission for glass.
float hit_weight(uint attr) {
    vec4 gm;
    return GLASS && glass_of(attr, gm) ? 1.0 - gm.w : 1.0;
}

layout(constant_id = 5) const uint STAGE = 0u;

const float EPS = 1e-3; // the rays start EPS voxels outside the face

void main() {
    uint gid = gl_GlobalInvocationID.y * (gl_NumWorkGroups.x * 64u) + gl_GlobalInvocationID.x;
    uvec4 d0 = CP.dims[0];
    uint vox;
    if (STAGE == 0u) {
        if (gid >= d0.x * d0.y * d0.z) return;
        vox = gid;
    } else {
        if (gid >= list[0]) return;
        vox = list[1u + gid];
    }
    uvec3 c = uvec3(vox % d0.x, (vox / d0.x) % d0.y, vox / (d0.x * d0.y));
    float s = CP.origin.w;
    vec3 lo = CP.origin.xyz + vec3(c) * s;
    uint S = CP.info.z;
    float alpha[6];
    bool any_hit = false;
    for (uint side = 0u; side < 6u; side++) {
        uint axis = side >> 1;
        float sg = (side & 1u) == 0u ? 1.0 : -1.0;
        vec3 e = axis == 0u ? vec3(1, 0, 0) : (axis == 1u ? vec3(0, 1, 0) : vec3(0, 0, 1));
        vec3 u = axis == 0u ? vec3(0, 1, 0) : vec3(1, 0, 0);
        vec3 v = axis == 2u ? vec3(0, 1, 0) : vec3(0, 0, 1);
        // the face's plane, EPS outside; rays go -sg along the axis for s
        vec3 face = lo + e * (sg > 0.0 ? s * (1.0 + EPS) : -s * EPS);
        float hits = 0.0;
        uint seen = 0u;
        float tmin = 3.0e38;
        vec3 lat = vec3(0.0), nrm = vec3(0.0), alb = vec3(0.0), emit = vec3(0.0);
        for (uint j = 0u; j < S * S; j++) {
            vec3 o = face + (u * (float(j % S) + 0.5) + v * (float(j / S) + 0.5)) * (s / float(S));
            Hit h;
            h.t = s;
            h.inst = NO_HIT;
            h.color = 0xFFFFFFFFu;
            h.attr = NO_HIT;
            g_iter = 0u; // the traversal's guard counts per ray
            if (!trace_scene(o, -sg * e, 0.0, false, h)) continue;
            float w = hit_weight(h.attr);
            if (h.t < 0.5 * EPS * s) {
                // the ray starts inside a solid cell of the neighbour: this
                // side is covered there; whatever the voxel holds behind it
                // is an interior (opaque, not seen), if anything: the rest of
                // the ray from EPS inside the face decides (in glass: its
                // nearest hit, weighed as above)
                Hit hi;
                hi.t = s * (1.0 - 2.0 * EPS);
                hi.inst = NO_HIT;
                hi.attr = NO_HIT;
                g_iter = 0u;
                if (trace_scene(o - sg * e * (2.0 * EPS * s), -sg * e, 0.0, w == 1.0, hi)) hits += w == 1.0 ? 1.0 : hit_weight(hi.attr);
                continue;
            }
            hits += w;
            if (STAGE == 0u || w < 1.0) continue;
            seen++;
            tmin = min(tmin, h.t);
            lat += o;
            nrm += gb_normal(uvec4(0u, h.inst, uint(h.axis) | (h.nsign < 0.0 ? 4u : 0u), 0u));
            vec3 a = HAS_COLOR ? unpack_rgb(h.color) : vec3(1.0);
            alb += a;
            // vx_material_emitted_terms; records past the table (one record without emission) emit nothing
            if (h.attr < uint(emit_attr.length())) emit += a * emit_attr[h.attr].w + emit_attr[h.attr].xyz;
        }
        alpha[side] = hits / float(S * S);
        any_hit = any_hit || hits > 0.0;
        if (STAGE == 1u) {
            uint r = (gid * 6u + side) * 5u;
            float k = max(float(seen), 1.0);
            vec3 p = lat / k - sg * e * tmin;
            p += sg * e * (2e-3 * s + 4e-6 * max(max(abs(p.x), abs(p.y)), abs(p.z)));
            rec[r] = vec4(p - CP.origin.xyz, alpha[side]);
            rec[r + 1u] = vec4(seen > 0u ? normalize(nrm) : sg * e, float(seen) / float(S * S));
            rec[r + 2u] = vec4(alb / k, 0.0);
            rec[r + 3u] = vec4(emit / k, 0.0);
            rec[r + 4u] = vec4(0.0);
        }
    }
    if (STAGE == 1u) return;
    if (ENTRIES == 1u) {
        float a = (alpha[0] + alpha[1] + alpha[2] + alpha[3] + alpha[4] + alpha[5]) / 6.0;
        vol_put(0u, c, 0u, vec4(0.0, 0.0, 0.0, a));
    } else {
        for (uint side = 0u; side < 6u; side++) vol_put(0u, c, side, vec4(0.0, 0.0, 0.0, alpha[side]));
    }
    if (any_hit) list[1u + atomicAdd(list[0], 1u)] = vox;
}
