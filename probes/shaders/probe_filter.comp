#version 450
// probes/shaders/probe_filter.comp - the GPU bake's filtering: a batch of
// probe.comp's bake output (per texel the radiance sum, the centre ray's
// distance and normal) into exactly the maps the .probes file stores, as
// probes/bake.c's vx__probe_finish computes them from the same values (the
// CPU reference): radiance halfs, oct16 normals and distance codes with
// borders, the min-distance map, the cosine-convolved irradiance and the
// distance moments. Float here, double there: sums and the moments' weights
// differ by float rounding; quantisation (distance codes, halfs, snorm16)
// rounds the same values the same way except within rounding of a tie.
// Three stages (push constant `stage`), a barrier between them:
//   0 texels: one invocation per pair of bordered texels of a probe: the
//     radiance, normal and distance words, and per interior texel (L, D)
//     for stage 1;
//   1 reduce: one workgroup per irradiance texel (64), moment texel (256)
//     and min-distance texel (low_res^2) of a probe: sums into Small;
//   2 pack:   one workgroup per probe: the small maps with their borders.
// Packed layout per probe, in words (probe_gpu.c unpacks it): radiance
// ((res+2)^2 * 3 halfs), normals ((res+2)^2), distances ((res+2)^2 halfs),
// min distances ((low+2)^2 halfs, padded to a word), irradiance (10x10x3
// halfs), moments (18x18x2 floats).
layout(local_size_x = 256) in;

layout(push_constant) uniform Push {
    uint stage, res, spp, first;  // first: the batch's first probe (index into Probes)
    uint count, per, low, small;  // probes in the batch, words per probe, low res, Small words per probe
    uint o_nrm, o_dist, o_low, o_irr;
    uint o_mom;
    float step_hi, step_lo, dist_max; // distance step = step_hi + step_lo (a double split in two floats)
} PC;

layout(std430, binding = 0) readonly buffer Probes { vec4 probes[]; };   // w: state (2: disabled)
layout(std430, binding = 1) readonly buffer Raw { vec4 raw[]; };         // probe.comp's Out: flags, 3 per texel
// res^2 texel centre directions (xyz) and solid angles (w), then the 64
// irradiance and the 256 moment texel directions
layout(std430, binding = 2) readonly buffer Tables { vec4 tab[]; };
layout(std430, binding = 3) buffer Texels { vec4 texl[]; };  // per interior texel: radiance, decoded distance
layout(std430, binding = 4) buffer Small { float small[]; }; // per probe: irradiance 64x3, moments 256x2, low codes
layout(std430, binding = 5) buffer Packed { uint packed[]; };

const uint IRR = 8u, MOM = 16u, MISS = 0xFFFFu;

// vx_probe_half: IEEE half, round to nearest even, bit for bit
uint half_of(float f) {
    uint x = floatBitsToUint(f);
    uint sgn = (x >> 16) & 0x8000u, mant = x & 0x7FFFFFu;
    int e = int((x >> 23) & 0xFFu);
    if (e == 0xFF) return sgn | 0x7C00u | (mant != 0u ? 0x200u : 0u);
    int he = e - 127 + 15;
    if (he >= 0x1F) return sgn | 0x7C00u;
    if (he <= 0) {
        if (he < -10) return sgn;
        mant |= 0x800000u;
        uint sh = uint(14 - he);
        uint hm = mant >> sh, rem = mant & ((1u << sh) - 1u), hf = 1u << (sh - 1u);
        if (rem > hf || (rem == hf && (hm & 1u) != 0u)) hm++;
        return sgn | hm;
    }
    uint hm = mant >> 13, rem = mant & 0x1FFFu;
    uint h = sgn | (uint(he) << 10) | hm;
    if (rem > 0x1000u || (rem == 0x1000u && (hm & 1u) != 0u)) h++;
    return h;
}

// x's top 12 significant bits (the rest, x - hi, fits in 12 bits too):
// products of such halves are exact in float
float hi12(float x) { return uintBitsToFloat(floatBitsToUint(x) & 0xFFFFF000u); }

// Dekker's exact product: a * b == p + e. No fused multiply-add needed
// (llvmpipe may evaluate fma() unfused), `precise` against reassociation.
void two_prod(float a, float b, out float p, out float e) {
    precise float ah = hi12(a), al = a - ah, bh = hi12(b), bl = b - bh;
    precise float pp = a * b;
    precise float ee = ((ah * bh - pp) + ah * bl + al * bh) + al * bl;
    p = pp;
    e = ee;
}

// a / b rounded as the host's IEEE division: the quotient corrected by the
// exact residual a - q b
float div_rn(float a, float b) {
    precise float q = a / b;
    float p, e;
    two_prod(q, b, p, e);
    precise float r = (a - p) - e; // a - p exact (Sterbenz: q b is within a factor 2 of a)
    precise float q2 = q + r / b;
    return q2;
}

// vx__dist_code: nearest code of a hit at distance t (the step a double:
// hi + lo), the quotient corrected by the residual t - q step, exact to
// about 2^-23 step
uint dist_code(float t) {
    precise float q = roundEven(t / PC.step_hi);
    for (int k = 0; k < 2; k++) {
        float p, e;
        two_prod(q, PC.step_hi, p, e);
        precise float r = ((t - p) - e) - q * PC.step_lo;
        precise float half_step = 0.5 * PC.step_hi, rl = r - 0.5 * PC.step_lo, rh = r + 0.5 * PC.step_lo;
        if (rl > half_step) q += 1.0;
        else if (rh < -half_step) q -= 1.0;
    }
    return uint(min(max(q, 0.0), float(MISS - 1u)));
}

uint snorm16(float v) { return uint(int(roundEven(clamp(v, -1.0, 1.0) * 32767.0))) & 0xFFFFu; }

// vx_probe_oct_pack16
uint oct_pack16(vec3 d) {
    float l1 = abs(d.x) + abs(d.y) + abs(d.z);
    float u = d.x / l1, v = d.y / l1;
    if (d.z < 0.0) {
        float fu = (1.0 - abs(v)) * (u < 0.0 ? -1.0 : 1.0), fv = (1.0 - abs(u)) * (v < 0.0 ? -1.0 : 1.0);
        u = fu, v = fv;
    }
    return snorm16(u) | (snorm16(v) << 16);
}

// vx_probe_border_src: the interior texel bordered texel (bi, bj) of an n x n map repeats
uvec2 border_src(uint n, uint bi, uint bj) {
    int i = int(bi) - 1, j = int(bj) - 1, N = int(n);
    bool bu = i < 0 || i >= N, bv = j < 0 || j >= N;
    if (bu && bv) {
        i = i < 0 ? N - 1 : 0;
        j = j < 0 ? N - 1 : 0;
    } else if (bu) {
        i = i < 0 ? 0 : N - 1;
        j = N - 1 - j;
    } else if (bv) {
        j = j < 0 ? 0 : N - 1;
        i = N - 1 - i;
    }
    return uvec2(i, j);
}

bool disabled(uint slot) { return probes[PC.first + slot].w == 2.0; }

struct Texel {
    vec3 L;
    uint code, nrm;
    float D;
};

// probes/probe_gpu.c finish_one: texel t of the batch's probe `slot`
Texel texel_of(uint slot, uint t) {
    uint at = 1u + 3u * (slot * PC.res * PC.res + t);
    vec4 acc = raw[at], geo = raw[at + 1u];
    Texel x;
    float s = float(PC.spp);
    x.L = vec3(div_rn(acc.x, s), div_rn(acc.y, s), div_rn(acc.z, s));
    if (acc.w >= 0.0 && geo.w > 0.0) {
        x.code = dist_code(acc.w);
        x.nrm = oct_pack16(geo.xyz);
        x.D = float(x.code) * PC.step_hi + float(x.code) * PC.step_lo;
    } else {
        x.code = MISS;
        x.nrm = 0u;
        x.D = PC.dist_max;
    }
    return x;
}

shared vec4 red[256];

void texels() {
    uint n = PC.res, nb = n + 2u, pair = gl_GlobalInvocationID.x, slot = gl_GlobalInvocationID.y;
    if (pair >= nb * nb / 2u || slot >= PC.count) return;
    uint base = slot * PC.per;
    if (disabled(slot)) {
        packed[base + 3u * pair] = 0u;
        packed[base + 3u * pair + 1u] = 0u;
        packed[base + 3u * pair + 2u] = 0u;
        packed[base + PC.o_nrm + 2u * pair] = 0u;
        packed[base + PC.o_nrm + 2u * pair + 1u] = 0u;
        packed[base + PC.o_dist + pair] = 0u;
        return;
    }
    uint h[6], nrm[2], code[2];
    for (uint k = 0u; k < 2u; k++) {
        uint b = 2u * pair + k, bi = b % nb, bj = b / nb;
        uvec2 s = border_src(n, bi, bj);
        uint t = s.y * n + s.x;
        Texel x = texel_of(slot, t);
        h[3u * k] = half_of(x.L.x), h[3u * k + 1u] = half_of(x.L.y), h[3u * k + 2u] = half_of(x.L.z);
        nrm[k] = x.nrm, code[k] = x.code;
        if (bi == s.x + 1u && bj == s.y + 1u) texl[slot * n * n + t] = vec4(x.L, x.D);
    }
    packed[base + 3u * pair] = h[0] | (h[1] << 16);
    packed[base + 3u * pair + 1u] = h[2] | (h[3] << 16);
    packed[base + 3u * pair + 2u] = h[4] | (h[5] << 16);
    packed[base + PC.o_nrm + 2u * pair] = nrm[0];
    packed[base + PC.o_nrm + 2u * pair + 1u] = nrm[1];
    packed[base + PC.o_dist + pair] = code[0] | (code[1] << 16);
}

// c^50 (DDGI's moment lobe) by squaring: c^32 c^16 c^2
float pow50(float c) {
    float c2 = c * c, c4 = c2 * c2, c8 = c4 * c4, c16 = c8 * c8, c32 = c16 * c16;
    return c32 * c16 * c2;
}

void reduce() {
    uint g = gl_WorkGroupID.x, slot = gl_WorkGroupID.y, lid = gl_LocalInvocationID.x;
    if (slot >= PC.count || disabled(slot)) return; // uniform per workgroup
    uint n = PC.res, nt = n * n, sb = slot * PC.small;
    vec4 s = vec4(0.0);
    if (g < IRR * IRR) {
        // E(n) = sum L(w) max(0, n.w) dw
        vec3 nn = tab[nt + g].xyz;
        for (uint t = lid; t < nt; t += 256u) {
            vec4 w = tab[t];
            float c = dot(nn, w.xyz);
            if (c <= 0.0) continue;
            s.xyz += texl[slot * nt + t].xyz * (c * w.w);
        }
    } else if (g < IRR * IRR + MOM * MOM) {
        vec3 nn = tab[nt + IRR * IRR + (g - IRR * IRR)].xyz;
        for (uint t = lid; t < nt; t += 256u) {
            vec4 w = tab[t];
            float c = dot(nn, w.xyz);
            if (c <= 0.75) continue; // cos^50 < 6e-7 beyond, as the CPU bake
            float wt = pow50(c) * w.w, D = texl[slot * nt + t].w;
            s += vec4(wt * D, wt * D * D, wt, 0.0);
        }
    } else {
        // the minimum distance code of a 16 x 16 block (res / low == 16)
        uint q = g - IRR * IRR - MOM * MOM, li = q % PC.low, lj = q / PC.low;
        uint i = li * 16u + lid % 16u, j = lj * 16u + lid / 16u, b = (j + 1u) * (n + 2u) + i + 1u;
        uint w = packed[slot * PC.per + PC.o_dist + b / 2u];
        s.x = float((b & 1u) != 0u ? w >> 16 : w & 0xFFFFu);
    }
    bool is_min = g >= IRR * IRR + MOM * MOM;
    red[lid] = s;
    barrier();
    for (uint k = 128u; k > 0u; k >>= 1) {
        if (lid < k) red[lid] = is_min ? min(red[lid], red[lid + k]) : red[lid] + red[lid + k];
        barrier();
    }
    if (lid != 0u) return;
    s = red[0];
    if (g < IRR * IRR) {
        for (uint k = 0u; k < 3u; k++) small[sb + 3u * g + k] = s[k];
    } else if (!is_min) {
        uint q = g - IRR * IRR;
        small[sb + 192u + 2u * q] = s.z > 0.0 ? s.x / s.z : PC.dist_max;
        small[sb + 192u + 2u * q + 1u] = s.z > 0.0 ? s.y / s.z : PC.dist_max * PC.dist_max;
    } else {
        small[sb + 704u + (g - IRR * IRR - MOM * MOM)] = s.x;
    }
}

void pack_small() {
    uint slot = gl_WorkGroupID.y, lid = gl_LocalInvocationID.x;
    if (slot >= PC.count) return;
    bool off = disabled(slot);
    uint base = slot * PC.per, sb = slot * PC.small, lr = PC.low, lb = (lr + 2u) * (lr + 2u);
    // min distances: halfs 2w, 2w+1 of word w (the last one's high half zero when lb is odd)
    for (uint w = lid; w < (lb + 1u) / 2u; w += 256u) {
        uint v = 0u;
        for (uint k = 0u; k < 2u && !off; k++) {
            uint b = 2u * w + k;
            if (b >= lb) break;
            uvec2 s = border_src(lr, b % (lr + 2u), b / (lr + 2u));
            v |= uint(small[sb + 704u + s.y * lr + s.x]) << (16u * k);
        }
        packed[base + PC.o_low + w] = v;
    }
    // irradiance halfs: 10 x 10 texels x 3
    for (uint w = lid; w < (IRR + 2u) * (IRR + 2u) * 3u / 2u; w += 256u) {
        uint v = 0u;
        for (uint k = 0u; k < 2u && !off; k++) {
            uint hidx = 2u * w + k, b = hidx / 3u, ch = hidx % 3u;
            uvec2 s = border_src(IRR, b % (IRR + 2u), b / (IRR + 2u));
            v |= half_of(small[sb + 3u * (s.y * IRR + s.x) + ch]) << (16u * k);
        }
        packed[base + PC.o_irr + w] = v;
    }
    // moments: 18 x 18 texels x 2 floats
    for (uint f = lid; f < (MOM + 2u) * (MOM + 2u) * 2u; f += 256u) {
        uint b = f / 2u;
        uvec2 s = border_src(MOM, b % (MOM + 2u), b / (MOM + 2u));
        packed[base + PC.o_mom + f] = off ? 0u : floatBitsToUint(small[sb + 192u + 2u * (s.y * MOM + s.x) + f % 2u]);
    }
}

void main() {
    if (PC.stage == 0u) texels();
    else if (PC.stage == 1u) reduce();
    else pack_small();
}
