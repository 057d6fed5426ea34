#version 450
// cones/shaders/cone.comp - the gi pass of voxel cone tracing (cones/cones.h):
// per pixel the pixel-centre primary ray (as the G-buffer's), then diffuse
// cones from its surface through the radiance volume. Writes gi_img: the
// indirect radiance albedo * sum w_i L_i and, in alpha, the cone AO (with
// CP.ctl.y == 1 the AO in every channel).
//   STAGE 0: everything at every pixel.
//   STAGE 1 (half resolution): the diffuse cones at pixel (2x, 2y) of each
//     2 x 2 block: its sum w_i L_i and AO, point and normal into half[].
//   STAGE 2: every pixel's diffuse light from the (up to 4) half-resolution
//     samples around it that lie on its surface (normals within 18 degrees,
//     the sample within half a level-0 voxel of its tangent plane), weighted
//     bilinearly; a pixel with none traces its own cones. The albedo, the
//     specular cone and the cone shadows stay per pixel.
// SPEC (metal records): f = kd / pi + GGX; the gi image is kd * sum w_i L_i
// + the specular cone's radiance (along the mirror direction, half angle
// from the roughness) times the lobe's directional albedo f0 A + B.
// SHADOWS: the direct light (the sun and every frame light) with a cone
// towards each source (its angular size) for the visibility, albedo / pi *
// E added to the gi image (the frame has no direct pass then).
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

// built with WALK_PRECISE (the walk not contracted; the rule and why: cmake/shaders.cmake), as gbuffer.comp,
// whose primary ray this kernel traces again (gbuffer_pixel)
#include "trace_common.glsl"
#include "passes_common.glsl"
const bool DOF = false, PHYS = true;
const uint FLAGS = 0u, SHOW = 0u;
// Glass (pass_bodies.glsl GLASS: LIGHTS bit 10, cones/cones.c glass_lights): the gi image of a glass pixel
// holds its glass lobe whole (render/pipeline.h), pass_bodies.glsl's glass_lobe with the cones' light added at
// each surface seen through the glass (GLASS_SEEN_GI). Its records are cone_common.glsl's cmat (binding 15,
// the same buffer under pass_bodies.glsl's name).
#define MAT_BINDING 15
vec3 cone_seen_gi(uvec4 s0, uvec4 s1);
#define GLASS_SEEN_GI cone_seen_gi
#include "pass_bodies.glsl"
#include "cone_common.glsl"

// The cones' indirect light leaving a surface seen through glass (G-buffer-like s0, s1): albedo times the
// diffuse cones' sum (as a pixel's, without the half-resolution samples).
vec3 cone_seen_gi(uvec4 s0, uvec4 s1) {
    vec3 nw = gb_normal(s1);
    vec3 q = (uintBitsToFloat(s0.xyz) - CP.origin.xyz) / CP.origin.w + nw * CP.cone.y;
    float ao;
    vec3 alb = HAS_COLOR ? unpack_rgb(s1.x) : vec3(1.0);
    return alb * cone_gather(q, nw, float(PC.u0.x) * 2.399963, PC.f2.xyz, ao);
}

layout(constant_id = 5) const uint STAGE = 0u;
// STAGE 1's samples: 2 uvec4 per half-resolution pixel (passes_common.glsl's
// binding 7): (sum w_i L_i, AO), (point relative to the reference, the
// normal as packSnorm2x16 of x, y and the sign of z; a miss: +inf)
#define half_px gb0

// The view direction towards a point p (relative to the frame reference).
vec3 view_dir(vec3 p) {
    if (F.rx.w != 0.0) return F.fwd.xyz;
    return normalize(p + F.fwd.w * F.fwd.xyz); // the eye at -t_start * fwd
}

// The direct light at p (normal nw) with cone visibility: the sun (its
// angular radius CP.spec.x as 1 - cos) and every frame light, each a cone
// from the surface towards the source's centre as wide as the source seen
// from p (a rect by the disc of its area), as far as the source.
vec3 cone_direct(vec3 p, vec3 nw, vec3 q, uvec2 px) {
    float s = CP.origin.w;
    vec3 e = vec3(0.0);
    float ndl = dot(nw, F.light.xyz);
    if (ndl > 0.0 && any(greaterThan(PC.f1.xyz, vec3(0.0)))) {
        float om = CP.spec.x, tn = sqrt(max(om * (2.0 - om), 0.0)) / max(1.0 - om, 1e-6);
        e += PC.f1.xyz * ndl * cone_transmit(q, F.light.xyz, tn, CP.cone.y, ndl, 1e30);
    }
    for (uint k = 0u; k < PC.u1.z; k++) {
        vec3 le, sd;
        float st;
        if (!light_eval(k, p, nw, s, false, px, le, sd, st)) continue;
        Light L = lights[k];
        uint type = uint(L.a.w);
        vec3 d;
        float tn, len;
        if (type == 0u) {
            float om = L.c.w;
            d = L.b.xyz, len = 1e30;
            tn = sqrt(max(om * (2.0 - om), 0.0)) / max(1.0 - om, 1e-6);
        } else {
            vec3 v = L.a.xyz - p;
            float dist = length(v);
            float r = type == 4u ? sqrt(4.0 * length(L.e.xyz) * length(L.f.xyz) / PI) : L.c.w;
            d = dist > 0.0 ? v / dist : nw, len = (dist - r) / s;
            tn = r > 0.0 && dist > r ? r / sqrt(dist * dist - r * r) : 0.0;
        }
        float dn = dot(d, nw);
        if (st > 0.0 && len > 0.0) le *= cone_transmit(q, d, tn, CP.cone.y, max(dn, 0.0), len);
        e += le;
    }
    return e;
}

void main() {
    uvec2 px;
    uint i;
    uvec2 hd = (F.dims.xy + 1u) / 2u;
    if (STAGE == 1u) {
        uvec2 h = gl_GlobalInvocationID.xy;
        if (h.x >= hd.x || h.y >= hd.y) return;
        px = h * 2u;
        i = h.y * hd.x + h.x;
    } else if (!pass_pixel(px, i)) {
        return;
    }
    uvec4 g0, g1, ids0, ids1;
    gbuffer_pixel(px, 0u, g0, g1, ids0, ids1);
    if (g1.y == NO_HIT) {
        if (STAGE == 1u) half_px[2u * i + 1u] = uvec4(0x7F800000u);
        else gi_img[i] = vec4(0.0, 0.0, 0.0, 1.0);
        return;
    }
    vec3 nw = gb_normal(g1);
    vec3 p = uintBitsToFloat(g0.xyz);
    vec3 q = (p - CP.origin.xyz) / CP.origin.w + nw * CP.cone.y;
    float rot = float(PC.u0.x) * 2.399963; // a new turn of the cone set per accumulated sample (golden angle)
    float ao = 0.0;
    vec3 L = vec3(0.0);
    if (STAGE == 1u) {
        L = cone_gather(q, nw, rot, PC.f2.xyz, ao);
        half_px[2u * i] = uvec4(floatBitsToUint(L), floatBitsToUint(ao));
        half_px[2u * i + 1u] = uvec4(g0.xyz, packSnorm2x16(nw.xy) | (nw.z < 0.0 ? 1u : 0u));
        return;
    }
    if (STAGE == 2u) {
        // the samples at half-resolution pixels h0 .. h0 + 1 (full pixels 2 h)
        uvec2 h0 = px / 2u;
        bvec2 odd = bvec2((px.x & 1u) != 0u, (px.y & 1u) != 0u);
        float wsum = 0.0;
        float tol = 0.5 * CP.origin.w;
        for (uint k = 0u; k < 4u; k++) {
            uvec2 o = uvec2(k & 1u, k >> 1);
            if ((o.x == 1u && !odd.x) || (o.y == 1u && !odd.y)) continue;
            uvec2 h = h0 + o;
            if (h.x >= hd.x || h.y >= hd.y) continue;
            uint j = h.y * hd.x + h.x;
            uvec4 b = half_px[2u * j + 1u];
            if (b.x == 0x7F800000u) continue;
            vec2 nxy = unpackSnorm2x16(b.w & ~1u);
            vec3 ns = vec3(nxy, sqrt(max(0.0, 1.0 - dot(nxy, nxy))) * ((b.w & 1u) != 0u ? -1.0 : 1.0));
            vec3 ps = uintBitsToFloat(b.xyz);
            if (dot(ns, nw) < 0.95 || abs(dot(ps - p, nw)) > tol) continue;
            uvec4 a = half_px[2u * j];
            L += uintBitsToFloat(a.xyz);
            ao += uintBitsToFloat(a.w);
            wsum += 1.0;
        }
        if (wsum > 0.0) L /= wsum, ao /= wsum;
        else L = cone_gather(q, nw, rot, PC.f2.xyz, ao);
    } else {
        L = cone_gather(q, nw, rot, PC.f2.xyz, ao);
    }
    if (CP.ctl.y == 1u) {
        gi_img[i] = vec4(ao);
        return;
    }
    vec3 alb = HAS_COLOR ? unpack_rgb(g1.x) : vec3(1.0);
    vec3 g = alb * L;
    if (SPEC && g1.w < CP.ctl.w) {
        vec4 m = cmat[g1.w];
        if (m.x == 1.0) {
            float mt = m.z, f0d = 0.08 * m.w, alpha = max(m.y * m.y, 1e-3);
            vec3 kd = (1.0 - mt) * (1.0 - f0d) * alb, f0 = (1.0 - mt) * f0d + mt * alb;
            vec3 v = view_dir(p);
            float nv = max(dot(nw, -v), 1e-4);
            vec3 r = reflect(v, nw);
            float tn = min(CP.spec.y * alpha, CP.spec.z), occ;
            vec3 sk = PC.f2.w > 0.0 ? frame_sky(r) : PC.f2.xyz;
            vec3 Ls = cone_march(q, r, tn, CP.cone.y, max(dot(r, nw), 0.0), sk, occ);
            vec2 ab = env_brdf(nv, m.y);
            g = kd * L + Ls * (f0 * ab.x + ab.y);
        }
    }
    if (SHADOWS) g += alb / PI * cone_direct(gb_offset_point(p, nw, g1.y), nw, q, px);
    vec4 gm;
    if (GLASS && glass_of(g1.w, gm)) g = (1.0 - gm.w) * g + glass_lobe(px, g0, g1, gm); // the Lambert share, the glass lobe
    gi_img[i] = vec4(g, ao);
}
