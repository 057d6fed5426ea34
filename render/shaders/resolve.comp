#version 450
// render/shaders/resolve.comp - combines the sample's G-buffer, direct, gi and
// ao images into its colour (or the intermediate SHOW asks for) and
// accumulates it: acc = c at sample 0, acc + c after, divided by the sample
// count at the last sample (the order trace.comp sums in, so the default pass
// list gives trace.comp's colour bit for bit). Specialised on the passes
// present (FLAGS), so an absent pass costs no load and no term.
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

#include "trace_common.glsl"
#include "passes_common.glsl"

layout(constant_id = 5) const uint FLAGS = 0u; // 1 direct, 2 gi, 4 ao, 8 emission, 16 radiometric light
layout(constant_id = 6) const uint SHOW = 0u;  // vx_show

const bool HAS_DIRECT = (FLAGS & 1u) != 0u, HAS_GI = (FLAGS & 2u) != 0u, HAS_AO = (FLAGS & 4u) != 0u;
const bool HAS_EMIT = (FLAGS & 8u) != 0u, PHYS = (FLAGS & 16u) != 0u;

void main() {
    uvec2 px;
    uint i;
    if (!pass_pixel(px, i)) return;
    uvec4 g1 = gb1[i];
    bool hit = g1.y != NO_HIT;
    vec3 alb = HAS_COLOR ? unpack_rgb(g1.x) : vec3(1.0);
    vec4 c = vec4(0.0);
    if (SHOW == 0u) {
        if (!hit) c = PHYS ? vec4(PC.f2.xyz, 0.0) : vec4(0.62, 0.75, 0.92, 0.0);
        else if (!PHYS) {
            float amb = F.light.w;
            float e = HAS_DIRECT ? direct_img[i].x : 0.0;
            if (HAS_AO) amb *= ao_img[i];
            c = vec4(alb * (amb + e), 1.0);
        } else {
            vec3 rad = vec3(0.0);
            if (HAS_EMIT && g1.w != NO_HIT) rad += alb * emit_attr[g1.w];
            if (HAS_DIRECT) rad += alb / PI * direct_img[i].xyz;
            if (HAS_GI) rad += gi_img[i].xyz * (HAS_AO ? ao_img[i] : 1.0);
            c = vec4(rad, 1.0);
        }
    } else if (SHOW == 1u) {
        c = hit ? vec4(alb, 1.0) : vec4(0.0);
    } else if (SHOW == 2u) {
        c = hit ? vec4(gb_normal(g1), 1.0) : vec4(0.0);
    } else if (SHOW == 3u) {
        float t = uintBitsToFloat(gb0[i].w);
        c = vec4(t, t, t, hit ? 1.0 : 0.0);
    } else if (SHOW == 4u) {
        c = HAS_DIRECT ? vec4(direct_img[i].xyz, hit ? 1.0 : 0.0) : vec4(0.0);
    } else if (SHOW == 5u) {
        c = HAS_GI ? vec4(gi_img[i].xyz, hit ? 1.0 : 0.0) : vec4(0.0);
    } else if (SHOW == 6u) {
        float a = HAS_AO ? ao_img[i] : 1.0;
        c = vec4(a, a, a, hit ? 1.0 : 0.0);
    } else if (SHOW == 7u) {
        c = hit ? vec4(inst_color(insts[g1.y].id), 1.0) : vec4(0.0);
    } else {
        float m = hit && g1.w != NO_HIT ? float(g1.w) : -1.0;
        c = vec4(m, m, m, hit ? 1.0 : 0.0);
    }
    uint s = PC.u0.x, n = max(PC.u0.y, 1u);
    vec4 a = s == 0u ? c : acc_img[i] + c;
    if (s + 1u == n) a = a / float(n);
    acc_img[i] = a;
}
