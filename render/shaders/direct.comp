#version 450
// render/shaders/direct.comp - the direct-light pass: the sun with a
// ray-traced shadow per pixel (the shadow ray of trace.comp). Writes what
// reaches the surface: in the colour model (1 - ambient) * n.l * visibility,
// in the radiometric model (PHYS) sun irradiance * n.l * visibility.
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

#include "trace_common.glsl"
#include "passes_common.glsl"

layout(constant_id = 6) const bool PHYS = false;

void main() {
    uvec2 px;
    uint i;
    if (!pass_pixel(px, i)) return;
    uvec4 g1 = gb1[i];
    if (g1.y == NO_HIT) {
        direct_img[i] = vec4(0.0);
        return;
    }
    vec3 nw = gb_normal(g1);
    float ndl = max(dot(nw, F.light.xyz), 0.0);
    float vis = 0.0;
    if (ndl > 0.0) {
        vec3 p = uintBitsToFloat(gb0[i].xyz);
        vec3 ps = gb_offset_point(p, nw, g1.y);
        Hit sh;
        sh.t = 3.0e38;
        sh.inst = NO_HIT;
        vis = trace_scene(ps, F.light.xyz, 0.0, true, sh) ? 0.0 : 1.0;
    }
    if (PHYS) direct_img[i] = vec4(PC.f1.xyz * ndl * vis, 1.0);
    else {
        float amb = F.light.w;
        direct_img[i] = vec4(vec3((1.0 - amb) * ndl * vis), 1.0);
    }
}
