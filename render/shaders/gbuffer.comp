#version 450
// render/shaders/gbuffer.comp - the G-buffer pass: one primary ray per pixel
// and sample through the BVH and the octrees (trace_common.glsl), the same
// rays as trace.comp (sample 0 the pixel centre, then an R2 sequence), or with
// DOF a thin lens: the origin jittered over a disc of radius PC.f0.x in the
// image plane's axes, aimed at the point where the pinhole ray meets the
// focus plane PC.f0.y in front of the eye. Float variant only.
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

#include "trace_common.glsl"
#include "passes_common.glsl"

layout(constant_id = 5) const bool DOF = false;

void main() {
    uvec2 px;
    uint i;
    if (!pass_pixel(px, i)) return;
    uint W = F.dims.x, H = F.dims.y, s = PC.u0.x;
    bool ortho = F.rx.w != 0.0;
    float t_start = F.fwd.w;
    vec2 off = vec2(0.0);
    if (s > 0u) off = fract(vec2(0.5) + float(s) * vec2(0.7548776662466927, 0.5698402909980532)) - 0.5;
    float u = ((float(px.x) + 0.5 + off.x) / float(W)) * 2.0 - 1.0;
    float v = 1.0 - ((float(px.y) + 0.5 + off.y) / float(H)) * 2.0;
    vec3 o, d;
    float t_off;
    if (ortho) {
        o = u * F.rx.xyz + v * F.uy.xyz;
        d = F.fwd.xyz;
        t_off = t_start;
    } else {
        vec3 du = F.fwd.xyz + u * F.rx.xyz + v * F.uy.xyz;
        float len = length(du);
        d = du / len;
        o = t_start * (u * F.rx.xyz + v * F.uy.xyz);
        t_off = t_start * len;
        if (DOF) {
            // eye at -t_start * fwd relative to the reference point
            vec3 eye = -t_start * F.fwd.xyz;
            vec3 focus_pt = eye + d * (PC.f0.y / dot(d, F.fwd.xyz));
            float r = PC.f0.x * sqrt(pass_rnd(px, 7u, 0u)), phi = 2.0 * PI * pass_rnd(px, 7u, 1u);
            vec3 lens = eye + r * cos(phi) * normalize(F.rx.xyz) + r * sin(phi) * normalize(F.uy.xyz);
            d = normalize(focus_pt - lens);
            float tp = t_start / dot(d, F.fwd.xyz); // to the reference plane
            o = lens + d * tp;
            t_off = tp;
        }
    }
    g_iter = 0u;
    Hit h;
    h.t = 3.0e38;
    h.inst = NO_HIT;
    h.color = 0xFFFFFFFFu;
    h.attr = NO_HIT;
    bool hit = trace_scene(o, d, 0.0, false, h);
    if (hit) {
        vec3 p = o + d * h.t;
        float depth = float(t_off + h.t);
        gb0[i] = uvec4(floatBitsToUint(p.x), floatBitsToUint(p.y), floatBitsToUint(p.z), floatBitsToUint(depth));
        uint face = uint(h.axis) | (h.nsign < 0.0 ? 4u : 0u);
        gb1[i] = uvec4(h.color, h.inst, face, h.attr);
    } else {
        gb0[i] = uvec4(0u, 0u, 0u, 0x7F800000u);
        gb1[i] = uvec4(0u, NO_HIT, 0u, NO_HIT);
    }
    if (WRITE_HITS && s == 0u) {
        gb2[2u * i] = uvec4(hit ? insts[h.inst].id : NO_HIT, h.cell);
        gb2[2u * i + 1u] = uvec4(floatBitsToUint(hit ? float(t_off + h.t) : 0.0), g_iter, 0u, 0u);
    }
}
