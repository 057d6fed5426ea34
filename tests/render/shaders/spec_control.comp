#version 450
// test_spirv_valid's control (test_control): valid as compiled (N 4) and invalid once specialised with N 1 and B
// true (an array of length 0), so the specialised check is seen to fail where it must.
layout(local_size_x = 1) in;
layout(constant_id = 0) const uint N = 4u;
layout(constant_id = 1) const bool B = true;
const uint LEN = B ? N - 1u : 1u;
shared uint a[LEN];
layout(std430, binding = 0) buffer Out { uint v[]; };
void main() {
    a[0] = 1u;
    barrier();
    v[0] = a[0] + uint(a.length());
}
