#version 450
// render/shaders/post.comp - the passes that run once on the averaged image.
//   OP 0 (aa's edge filter): where the luma contrast among the 4 neighbours
//     exceeds PC.f1.w, the pixel is blended half-way with their mean (a
//     cheap filter in the spirit of FXAA's edge test, on top of the jittered
//     accumulation); acc -> out2.
//   OP 1 (tonemap, in place on acc or on out2 with SRC2): times 2^exposure,
//     Narkowicz's fit of the ACES filmic curve, then the sRGB transfer
//     function; alpha kept.
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

#include "trace_common.glsl"
#include "passes_common.glsl"
#include "display_out.glsl"

layout(constant_id = 5) const uint OP = 0u;
layout(constant_id = 6) const bool SRC2 = false;

uint py_x(uvec2 p, uint W, uint H, int dx, int dy) {
    int x = clamp(int(p.x) + dx, 0, int(W) - 1), y = clamp(int(p.y) + dy, 0, int(H) - 1);
    return uint(y) * W + uint(x);
}

float luma(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

vec3 aces(vec3 x) {
    return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

vec3 srgb(vec3 c) {
    vec3 lo = 12.92 * c, hi = 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055;
    return mix(hi, lo, lessThanEqual(c, vec3(0.0031308)));
}

void main() {
    uvec2 px;
    uint i;
    if (!pass_pixel(px, i)) return;
    uint W = F.dims.x, H = F.dims.y;
    if (OP == 0u) {
        vec4 c = acc_img[i];
        vec3 l = acc_img[py_x(px, W, H, -1, 0)].xyz;
        vec3 r = acc_img[py_x(px, W, H, 1, 0)].xyz;
        vec3 u = acc_img[py_x(px, W, H, 0, -1)].xyz;
        vec3 d = acc_img[py_x(px, W, H, 0, 1)].xyz;
        float lc = luma(c.xyz);
        float mx = max(max(max(luma(l), luma(r)), max(luma(u), luma(d))), lc);
        float mn = min(min(min(luma(l), luma(r)), min(luma(u), luma(d))), lc);
        if (mx - mn > PC.f1.w * max(mx, 1e-4)) c.xyz = 0.5 * c.xyz + 0.125 * (l + r + u + d);
        out2_img[i] = c;
#ifdef DISPLAY_OUT
        display_store(px, i, c); // aa is the last pass (no tonemap)
#endif
    } else {
        vec4 c = SRC2 ? out2_img[i] : acc_img[i];
        c.xyz = srgb(aces(max(c.xyz, vec3(0.0)) * PC.f0.w));
        if (SRC2) out2_img[i] = c;
        else acc_img[i] = c;
#ifdef DISPLAY_OUT
        display_store(px, i, c);
#endif
    }
}
