#version 450
#extension GL_GOOGLE_include_directive : require
// c.comp: a generated include (gen.glsl, from gen.in)
layout(local_size_x = 1) in;
layout(std430, binding = 0) buffer Out { float v[]; };
#include "gen.glsl"
void main() { v[0] = gen_val(); }
