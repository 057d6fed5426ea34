#version 450
// bake4_floor.c's trivial kernel: writes its constant 0
layout(local_size_x = 64) in;
layout(constant_id = 0) const uint V = 1u;
layout(std430, binding = 0) buffer Out { uint o[]; };
void main() { o[gl_GlobalInvocationID.x] = V; }
