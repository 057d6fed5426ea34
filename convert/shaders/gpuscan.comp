#version 450
/* convert/shaders/gpuscan.comp - exclusive prefix sums of uint in place,
 * blocks of 2048: MODE 0 scans each block and writes its total to
 * sums[block]; the host scans sums the same way (recursively); MODE 1 adds
 * the scanned sums[block] to each block's entries. */
layout(local_size_x = 256) in;
layout(constant_id = 0) const uint MODE = 0;
layout(push_constant) uniform Push { uint n; } pc;
layout(std430, binding = 0) buffer D { uint data[]; };
layout(std430, binding = 1) buffer S { uint sums[]; };
shared uint part[256];

void main() {
    uint block = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    uint t = gl_LocalInvocationID.x;
    uint base = block * 2048u + t * 8u;
    if (MODE == 1u) {
        uint add = sums[block];
        for (uint q = 0u; q < 8u; q++)
            if (base + q < pc.n) data[base + q] += add;
        return;
    }
    uint x[8];
    uint s = 0u;
    for (uint q = 0u; q < 8u; q++) {
        x[q] = base + q < pc.n ? data[base + q] : 0u;
        s += x[q];
    }
    part[t] = s;
    barrier();
    for (uint off = 1u; off < 256u; off <<= 1) {
        uint add = t >= off ? part[t - off] : 0u;
        barrier();
        part[t] += add;
        barrier();
    }
    uint run = part[t] - s;
    for (uint q = 0u; q < 8u; q++) {
        if (base + q < pc.n) data[base + q] = run;
        run += x[q];
    }
    if (t == 255u) sums[block] = part[255];
}
