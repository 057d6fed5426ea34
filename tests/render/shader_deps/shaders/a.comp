#version 450
#extension GL_GOOGLE_include_directive : require
// a.comp: a nested include (x.glsl -> y.glsl) and one from an INCLUDES folder (z.glsl)
layout(local_size_x = 1) in;
layout(std430, binding = 0) buffer Out { float v[]; };
#include "x.glsl"
#include "z.glsl"
void main() { v[0] = x_val() + z_val(); }
