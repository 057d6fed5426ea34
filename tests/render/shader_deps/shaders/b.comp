#version 450
#extension GL_GOOGLE_include_directive : require
// b.comp: y.glsl only where WITH_Y is defined (b_on), so an edit of y.glsl rebuilds b_on and not b_off
layout(local_size_x = 1) in;
layout(std430, binding = 0) buffer Out { float v[]; };
#ifdef WITH_Y
#include "y.glsl"
#else
float y_val() { return 0.0; }
#endif
void main() { v[0] = y_val(); }
