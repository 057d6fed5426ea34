#version 450
// d.comp: includes nothing
layout(local_size_x = 1) in;
layout(std430, binding = 0) buffer Out { float v[]; };
void main() { v[0] = 5.0; }
