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

layout(constant_id = 5) const uint FLAGS = 0u; // 1 direct, 2 gi, 4 ao, 8 emission, 16 radiometric light, 32 sky, 64 metal, 128 glass
layout(constant_id = 6) const uint SHOW = 0u;  // vx_show
const bool PHYS = (FLAGS & 16u) != 0u;
const bool DOF = false;
#define MAT_BINDING 23 // the records' materials where some is metal or glass (pass_bodies.glsl METAL, GLASS)
#include "pass_bodies.glsl"
#include "display_out.glsl"

void main() {
    uvec2 px;
    uint i;
    if (!pass_pixel(px, i)) return;
    vec4 dir = HAS_DIRECT ? direct_img[i] : vec4(0.0);
    float ao = HAS_AO ? ao_img[i] : 1.0;
    vec4 gi = HAS_GI ? gi_img[i] : vec4(0.0);
    vec4 c = resolve_pixel(gb0[i], gb1[i], dir, ao, gi);
#ifdef DISPLAY_OUT
    // one sample: its colour is the frame's (accumulate's c / 1), and the float image is not kept
    if (PC.u0.y <= 1u) {
        display_store(px, i, c);
        return;
    }
#endif
    accumulate(i, c);
#ifdef DISPLAY_OUT
    if (PC.u0.x + 1u == PC.u0.y) display_store(px, i, acc_img[i]); // the last sample: the frame's colour
#endif
}
