// tests/render/test_pipeline_cache.c: a pipeline that is cheap to build and
// says which one ran: it writes its specialisation constant to out[0].
#version 450
layout(local_size_x = 1) in;
layout(constant_id = 0) const uint VALUE = 0u;
layout(std430, binding = 0) buffer Out { uint v[]; } o;
void main() { o.v[0] = VALUE; }
