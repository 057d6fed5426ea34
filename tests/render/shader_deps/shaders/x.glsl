// included by a.comp from its own folder; includes y.glsl
#include "y.glsl"
float x_val() { return y_val() + 1.0; }
