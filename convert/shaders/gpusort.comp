#version 450
/* convert/shaders/gpusort.comp - one pass of a stable LSD radix sort of
 * (64-bit key, 32-bit value) pairs by the 4-bit digit at `shift`: MODE 0
 * counts each tile's digits into hist[digit * ntiles + tile]; the host
 * scans hist (gpuscan.comp); MODE 1 scatters each tile's items to their
 * digit's offset plus their rank among the tile's items of that digit in
 * input order (stable: each thread holds 4 consecutive items, ranks come
 * from an exclusive scan over (digit, thread)). */
layout(local_size_x = 256) in;
layout(constant_id = 0) const uint MODE = 0;
layout(push_constant) uniform Push { uint n, shift, ntiles; } pc;

layout(std430, binding = 0) readonly buffer KI { uvec2 kin[]; };
layout(std430, binding = 1) readonly buffer VI { uint vin[]; };
layout(std430, binding = 2) writeonly buffer KO { uvec2 kout[]; };
layout(std430, binding = 3) writeonly buffer VO { uint vout[]; };
layout(std430, binding = 4) buffer H { uint hist[]; };

shared uint cnt[16];
shared uint rank[16 * 256];
shared uint part[256];

uint digit(uvec2 k) { return pc.shift < 32u ? (k.x >> pc.shift) & 15u : (k.y >> (pc.shift - 32u)) & 15u; }

void main() {
    uint tile = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    uint t = gl_LocalInvocationID.x;
    uint base = tile * 1024u + t * 4u;
    if (MODE == 0u) {
        if (t < 16u) cnt[t] = 0u;
        barrier();
        for (uint q = 0u; q < 4u; q++)
            if (base + q < pc.n) atomicAdd(cnt[digit(kin[base + q])], 1u);
        barrier();
        if (t < 16u && tile < pc.ntiles) hist[t * pc.ntiles + tile] = cnt[t];
        return;
    }
    uvec2 k[4];
    uint v[4], dg[4];
    uint mine[16];
    for (uint d = 0u; d < 16u; d++) mine[d] = 0u;
    for (uint q = 0u; q < 4u; q++) {
        dg[q] = 16u;
        if (base + q < pc.n) {
            k[q] = kin[base + q];
            v[q] = vin[base + q];
            dg[q] = digit(k[q]);
        }
    }
    for (uint d = 0u; d < 16u; d++) {
        uint c = 0u;
        for (uint q = 0u; q < 4u; q++) c += dg[q] == d ? 1u : 0u;
        rank[d * 256u + t] = c;
    }
    barrier();
    /* exclusive scan of rank[4096]: 16 consecutive entries per thread */
    uint s = 0u;
    for (uint q = 0u; q < 16u; q++) s += rank[t * 16u + q];
    part[t] = s;
    barrier();
    for (uint off = 1u; off < 256u; off <<= 1) {
        uint add = t >= off ? part[t - off] : 0u;
        barrier();
        part[t] += add;
        barrier();
    }
    uint run = part[t] - s;
    for (uint q = 0u; q < 16u; q++) {
        uint x = rank[t * 16u + q];
        rank[t * 16u + q] = run;
        run += x;
    }
    barrier();
    for (uint q = 0u; q < 4u; q++) {
        uint d = dg[q];
        if (d == 16u) continue;
        uint dst = hist[d * pc.ntiles + tile] + (rank[d * 256u + t] - rank[d * 256u]) + mine[d];
        mine[d]++;
        kout[dst] = k[q];
        vout[dst] = v[q];
    }
}
