#version 450
// render/shaders/probe.comp - the light field probes' GPU passes on the
// octree tracer (float variant only), with the lighting model of
// probes/light.c (see probes/probes.h): diffuse albedo, one directional light
// with shadow rays, a uniform sky, emissive attributes.
//   PMODE 0 (bake): one invocation per (texel, probe): the texel centre ray's
//     distance and normal, and the radiance summed over spp jittered paths.
//   PMODE 1..6 (gi, pathtrace, gi-indirect, pathtrace-indirect, lightfield,
//     lightfield-indirect): one invocation per pixel, as probes/render_gi.c
//     and probes/lightfield.c.
// Random numbers: every path draws from its own counter-based stream keyed by
// (seed, probe or pixel, texel or row, sample), so results do not depend on
// the dispatch order or batch size. Layouts: probes/probe_gpu.c.
//
// Loop limit: llvmpipe (lavapipe) compiles a shader with a guard against
// endless loops: one counter per SIMD group of 8 invocations (256-bit
// vectors), shared by every loop of the shader and decremented at each
// iteration (gallivm's LP_MAX_TGSI_LOOP_ITERATIONS = 65535, lp_exec_endloop).
// Once a group's loops have run 65535 iterations in all, every loop exits at
// the end of its current iteration, silently. A pixel (or texel) looping over
// all its samples in one invocation then stops after the sample during which
// the limit was reached, and the 8 pixels of its group (a run along a row)
// divide a partial sum by spp (issue 10: on the Cornell box at 160x120 the
// busiest groups fit fewer than 256 samples). So bake() and render() trace at
// most P.seed.w samples per dispatch and keep each texel's or pixel's running
// sum and sample count in the output buffer (the same float additions in the
// same order however the samples are split, so the result does not depend on
// the split a device needs); before they store, they check that the guard
// never fired (loops_intact). Where it fired, they store nothing and raise a
// flag, and the host repeats the dispatch with half the samples. Hardware
// GPUs have no such guard (a dispatch runs to its end or the device is lost).
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

#include "trace_common.glsl"

layout(constant_id = 5) const int PMODE = 0;
const int P_BAKE = 0, P_GI = 1, P_PT = 2, P_GI_IND = 3, P_PT_IND = 4, P_LF = 5, P_LF_IND = 6;

layout(std430, binding = 7) readonly buffer Params {
    vec4 light;    // xyz: unit, towards the light
    vec4 sun;      // rgb: irradiance on a surface facing the light
    vec4 sky;      // rgb: radiance
    uvec4 a;       // x: res (bake) / width, y: spp, z: bounces, w: first probe (bake) / height
    uvec4 seed;    // x, y: seed low and high words, z: probes in this dispatch (bake), w: samples per dispatch
    uvec4 grid;    // xyz: probes per axis, w: probe count
    vec4 origin;   // xyz: grid origin relative to the reference point, w: dist_max
    vec4 spacing;  // xyz: spacing, w: minimum spacing
    uvec4 lf;      // light field: x: res (bake: 1 in the first dispatch), y: low res, z: words per probe
                   // in LfMaps; w: 2 (loops_intact)
    vec4 lf_lo;    // xyz: scene bounds relative to the reference point, w: distance step
    vec4 lf_hi;    // xyz: scene bounds (max)
} P;
layout(std430, binding = 8) readonly buffer Emit { float emit_attr[]; };  // per colors[] entry
layout(std430, binding = 9) readonly buffer Probes { vec4 probes[]; };    // xyz: position - reference, w: state
// [0] flags (x: the loop guard fired, y: samples left), then per texel of
// each probe (bake): the running sum (rgb, w: distance or -1), the normal
// (xyz, w: 1 on a hit) and (samples done, 0, 0, 0); per pixel (render): the
// running sum (rgb, w: samples that hit) and (samples done, 0, 0, 0)
layout(std430, binding = 10) buffer Out { vec4 outv[]; };
// per probe: irradiance (10x10x3) then, after all probes, moments (18x18x2)
layout(std430, binding = 11) readonly buffer Maps { float maps[]; };
// light field modes, per probe: distance u16 ((res+2)^2, padded to a word),
// min-distance u16 ((low+2)^2, padded), normal oct16 ((res+2)^2), radiance
// half RGB ((res+2)^2 * 3, padded)
layout(std430, binding = 12) readonly buffer LfMaps { uint lfw[]; };

const float PI = 3.14159265358979323846;
const float BIG = 3.0e38;

// ---- random numbers (Jarzynski & Olano 2020, pcg4d) ----
uvec4 pcg4d(uvec4 v) {
    v = v * 1664525u + 1013904223u;
    v.x += v.y * v.w; v.y += v.z * v.x; v.z += v.x * v.y; v.w += v.y * v.z;
    v ^= v >> 16u;
    v.x += v.y * v.w; v.y += v.z * v.x; v.z += v.x * v.y; v.w += v.y * v.z;
    return v;
}
uvec4 g_key;
uint g_ctr;
void rng_init(uint a, uint b, uint c) {
    g_key = pcg4d(uvec4(a, b, c, P.seed.x ^ (P.seed.y * 0x9E3779B9u)));
    g_ctr = 0u;
}
float rnd() {
    g_ctr++;
    uvec4 h = pcg4d(uvec4(g_key.x, g_key.y, g_key.z ^ g_ctr, g_key.w));
    return float(h.x >> 8) * (1.0 / 16777216.0);
}

// ---- octahedral mapping (probes/oct.c) ----
float sgn(float v) { return v < 0.0 ? -1.0 : 1.0; }
vec3 oct_decode(vec2 uv) {
    vec3 p = vec3(uv, 1.0 - abs(uv.x) - abs(uv.y));
    if (p.z < 0.0) p.xy = vec2((1.0 - abs(uv.y)) * sgn(uv.x), (1.0 - abs(uv.x)) * sgn(uv.y));
    return normalize(p);
}
vec2 oct_encode(vec3 d) {
    vec2 p = d.xy / (abs(d.x) + abs(d.y) + abs(d.z));
    if (d.z < 0.0) p = vec2((1.0 - abs(p.y)) * sgn(p.x), (1.0 - abs(p.x)) * sgn(p.y));
    return p;
}

// ---- the lighting model (probes/light.c) ----
struct Surf { vec3 p, n, alb, emit; };

bool cast_ray(vec3 o, vec3 d, float tmax, out Hit h) {
    h.t = tmax;
    h.inst = NO_HIT;
    h.color = 0xFFFFFFFFu;
    h.attr = NO_HIT;
    g_iter = 0u;
    return trace_scene(o, d, 0.0, false, h);
}

bool occluded(vec3 o, vec3 d) {
    Hit h;
    h.t = BIG;
    h.inst = NO_HIT;
    g_iter = 0u;
    return trace_scene(o, d, 0.0, true, h);
}

Surf surface(vec3 o, vec3 d, Hit h) {
    Surf s;
    Inst I = insts[h.inst];
    vec4 row = h.axis == 0 ? I.r0 : (h.axis == 1 ? I.r1 : I.r2);
    s.n = normalize(row.xyz * h.nsign);
    vec3 p = o + d * h.t;
    // off the surface (as the tracer's shadow rays; float needs more than the CPU's 1e-6 cell)
    s.p = p + s.n * (I.cell * 1e-3 + 4e-6 * max(max(abs(p.x), abs(p.y)), abs(p.z)));
    s.alb = HAS_COLOR ? unpack_rgb(h.color) : vec3(1.0);
    float e = h.attr != NO_HIT ? emit_attr[h.attr] : 0.0;
    s.emit = s.alb * e;
    return s;
}

vec3 direct(Surf s) {
    float ndl = dot(s.n, P.light.xyz);
    if (ndl <= 0.0 || !(P.sun.x > 0.0 || P.sun.y > 0.0 || P.sun.z > 0.0)) return vec3(0.0);
    if (occluded(s.p, P.light.xyz)) return vec3(0.0);
    return s.alb / PI * P.sun.xyz * ndl;
}

vec3 cosine_dir(vec3 n, float u1, float u2) {
    float sg = n.z < 0.0 ? -1.0 : 1.0;
    float a = -1.0 / (sg + n.z), b = n.x * n.y * a;
    vec3 t = vec3(1.0 + sg * n.x * n.x * a, sg * b, -sg * n.x);
    vec3 bt = vec3(b, sg + n.y * n.y * a, -n.y);
    float r = sqrt(u1), phi = 2.0 * PI * u2;
    return normalize(r * cos(phi) * t + r * sin(phi) * bt + sqrt(max(0.0, 1.0 - u1)) * n);
}

vec3 path(vec3 o, vec3 d, uint bounces) {
    vec3 thr = vec3(1.0), acc = vec3(0.0);
    for (uint depth = 0u;; depth++) {
        Hit h;
        if (!cast_ray(o, d, BIG, h)) {
            acc += thr * P.sky.xyz;
            break;
        }
        Surf s = surface(o, d, h);
        acc += thr * (s.emit + direct(s));
        if (depth >= bounces) break;
        float u1 = rnd(), u2 = rnd();
        d = cosine_dir(s.n, u1, u2);
        o = s.p;
        thr *= s.alb;
        if (thr == vec3(0.0)) break;
    }
    return acc;
}

// ---- irradiance probes (probes/render_gi.c) ----
vec2 map_xy(vec3 d, uint n) {
    vec2 uv = oct_encode(d);
    return (uv + 1.0) * 0.5 * float(n) + 0.5;
}
vec3 sample_irr(uint k, vec3 d) {
    const uint n = 8u, nb = 10u;
    vec2 xy = map_xy(d, n);
    uvec2 i0 = min(uvec2(floor(xy)), uvec2(n));
    vec2 f = xy - vec2(i0);
    uint base = k * nb * nb * 3u;
    vec3 v[4];
    for (int c = 0; c < 4; c++) {
        uint x = i0.x + uint(c & 1), y = i0.y + uint(c >> 1);
        uint at = base + (y * nb + x) * 3u;
        v[c] = vec3(maps[at], maps[at + 1u], maps[at + 2u]);
    }
    return mix(mix(v[0], v[1], f.x), mix(v[2], v[3], f.x), f.y);
}
vec2 sample_mom(uint k, vec3 d) {
    const uint n = 16u, nb = 18u;
    vec2 xy = map_xy(d, n);
    uvec2 i0 = min(uvec2(floor(xy)), uvec2(n));
    vec2 f = xy - vec2(i0);
    uint base = P.grid.w * 300u + k * nb * nb * 2u;
    vec2 v[4];
    for (int c = 0; c < 4; c++) {
        uint x = i0.x + uint(c & 1), y = i0.y + uint(c >> 1);
        uint at = base + (y * nb + x) * 2u;
        v[c] = vec2(maps[at], maps[at + 1u]);
    }
    return mix(mix(v[0], v[1], f.x), mix(v[2], v[3], f.x), f.y);
}

vec3 irradiance_at(vec3 p_in, vec3 n, vec3 vd) {
    float smin = P.spacing.w;
    vec3 p = p_in + (n * 0.2 - vd * 0.1) * smin;
    ivec3 base;
    vec3 alpha;
    for (int k = 0; k < 3; k++) {
        float g = (p[k] - P.origin[k]) / P.spacing[k];
        float top = float(P.grid[k]) - 1.0;
        g = clamp(g, 0.0, top);
        float f = min(floor(g), max(top - 1.0, 0.0));
        base[k] = int(f);
        alpha[k] = top > 0.0 ? g - f : 0.0;
    }
    vec3 sum = vec3(0.0);
    float wsum = 0.0;
    for (int c = 0; c < 8; c++) {
        ivec3 idx;
        float tri = 1.0;
        bool skip = false;
        for (int k = 0; k < 3; k++) {
            int o = (c >> k) & 1;
            idx[k] = base[k] + o;
            if (idx[k] >= int(P.grid[k])) skip = true;
            tri *= o != 0 ? alpha[k] : 1.0 - alpha[k];
        }
        if (skip) continue;
        uint pi = uint(idx.x) + P.grid.x * (uint(idx.y) + P.grid.y * uint(idx.z));
        vec4 pr = probes[pi];
        if (pr.w == 2.0) continue; // VX_PROBE_DISABLED
        vec3 to = pr.xyz - p;
        float r = length(to);
        vec3 dir = r > 0.0 ? to / r : vec3(0.0, 0.0, 1.0);
        float wn = 0.5 * (dot(dir, n) + 1.0);
        float w = wn * wn + 0.2;
        vec2 mom = sample_mom(pi, -dir);
        if (r > mom.x) {
            float var = abs(mom.y - mom.x * mom.x);
            float dd = r - mom.x;
            float cheb = var / (var + dd * dd);
            w *= max(cheb * cheb * cheb, 0.0);
        }
        w = max(w, 1e-6);
        if (w < 0.2) w = w * w * w / (0.2 * 0.2);
        w *= tri;
        sum += w * sample_irr(pi, n);
        wsum += w;
    }
    return wsum > 0.0 ? sum / wsum : vec3(0.0);
}


// ---- light field tracing (probes/lightfield.c: the walk, its rules and why) ----
uint lf_u16(uint word_at, uint i) { return (lfw[word_at + (i >> 1u)] >> (16u * (i & 1u))) & 0xFFFFu; }
uint lf_base(uint k) { return k * P.lf.z; }
uint lf_bsq(uint n) { return (n + 2u) * (n + 2u); }
uint lf_dist(uint k, uint at) { return lf_u16(lf_base(k), at); }
uint lf_low(uint k, uint at) { return lf_u16(lf_base(k) + (lf_bsq(P.lf.x) + 1u) / 2u, at); }
uint lf_nrm(uint k, uint at) {
    return lfw[lf_base(k) + (lf_bsq(P.lf.x) + 1u) / 2u + (lf_bsq(P.lf.y) + 1u) / 2u + at];
}
vec3 lf_rad(uint k, uint at) {
    uint b = lf_base(k) + (lf_bsq(P.lf.x) + 1u) / 2u + (lf_bsq(P.lf.y) + 1u) / 2u + lf_bsq(P.lf.x);
    return vec3(unpackHalf2x16(lf_u16(b, 3u * at)).x, unpackHalf2x16(lf_u16(b, 3u * at + 1u)).x,
                unpackHalf2x16(lf_u16(b, 3u * at + 2u)).x);
}
vec3 lf_unpack16(uint v) { return oct_decode(max(unpackSnorm2x16(v), vec2(-1.0))); }

bool lf_enc_octant(vec3 q, vec3 s, out vec2 uv) {
    float l1 = dot(s, q);
    uv = vec2(0.0);
    if (!(l1 > 0.0)) return false;
    vec2 p = q.xy / l1;
    if (s.z < 0.0) p = vec2((1.0 - s.y * p.y) * s.x, (1.0 - s.x * p.x) * s.y);
    uv = p;
    return true;
}
float lf_t_of_dir(vec3 q0, vec3 d, vec3 w, float fb) {
    vec3 cdw = cross(d, w);
    float den = dot(cdw, cdw);
    return den > 0.0 ? -dot(cross(q0, w), cdw) / den : fb;
}
bool g_first;
// 0 free, 1 hit, 2 unknown
int lf_texel(uint k, ivec2 f, vec3 q0, vec3 d, float t0, float t1, out float th) {
    uint n = P.lf.x;
    uint at = uint(f.y + 1) * (n + 2u) + uint(f.x + 1);
    bool first = g_first;
    g_first = false;
    th = t0;
    uint code = lf_dist(k, at);
    if (code == 0xFFFFu) return 0;
    float step = P.lf_lo.w, D = float(code) * step;
    vec3 w = oct_decode((2.0 * vec2(f) + 1.0) / float(n) - 1.0);
    vec3 N = lf_unpack16(lf_nrm(k, at));
    float c0 = dot(q0 - D * w, N), sd = dot(d, N);
    float s0 = c0 + t0 * sd, s1 = c0 + t1 * sd;
    float thick = 2.0 * step + D / float(n);
    if (D <= thick) return 2;
    float near = thick + D * 4.25 / float(n);
    if (s0 >= 0.0 && s1 < 0.0) {
        th = t0 + (t1 - t0) * (s0 / (s0 - s1));
        return length(q0 + th * d - D * w) <= near ? 1 : 2;
    }
    if (s0 < -thick) return 2;
    if (s0 < 0.0 && sd < 0.0) return (first || length(q0 + t0 * d - D * w) > near) ? 2 : 1;
    float cosw = abs(dot(w, N));
    float ang = acos(min(cosw, 1.0)) + 4.25 / float(n);
    if (ang < 1.5 && max(length(q0 + t0 * d), length(q0 + t1 * d)) > D * cosw / cos(ang) + thick) return 2;
    return 0;
}

struct Dda { ivec2 i, s; vec2 nx, dl; };
Dda dda_init(vec2 A, vec2 B, float a0, int m) {
    Dda g;
    vec2 e = B - A, p = A + a0 * e;
    g.s = ivec2(e.x > 0.0 ? 1 : (e.x < 0.0 ? -1 : 0), e.y > 0.0 ? 1 : (e.y < 0.0 ? -1 : 0));
    vec2 fl = floor(p);
    if (fl.x == p.x && g.s.x < 0) fl.x -= 1.0;
    if (fl.y == p.y && g.s.y < 0) fl.y -= 1.0;
    fl = clamp(fl, vec2(0.0), vec2(float(m - 1)));
    g.i = ivec2(fl);
    g.dl = vec2(g.s.x != 0 ? 1.0 / abs(e.x) : BIG, g.s.y != 0 ? 1.0 / abs(e.y) : BIG);
    g.nx = vec2(g.s.x != 0 ? ((fl.x + (g.s.x > 0 ? 1.0 : 0.0)) - A.x) / e.x : BIG,
                g.s.y != 0 ? ((fl.y + (g.s.y > 0 ? 1.0 : 0.0)) - A.y) / e.y : BIG);
    return g;
}
float dda_step(inout Dda g) {
    if (g.nx.x < g.nx.y) {
        float a = g.nx.x;
        g.i.x += g.s.x;
        g.nx.x += g.dl.x;
        return a;
    }
    float a = g.nx.y;
    g.i.y += g.s.y;
    g.nx.y += g.dl.y;
    return a;
}

const int LF_HIT = 0, LF_MISS = 1, LF_UNKNOWN = 2;
int lf_trace_probe(uint k, vec3 o, vec3 d, inout float t, float t_end, out uint texel) {
    uint n = P.lf.x, lr = P.lf.y;
    texel = 0u;
    vec3 q0 = o - probes[k].xyz;
    g_first = true;
    float ts[5];
    int nt = 0;
    ts[nt++] = t;
    for (int a = 0; a < 3; a++) {
        if (d[a] == 0.0) continue;
        float tb = -q0[a] / d[a];
        if (tb > t && tb < t_end) ts[nt++] = tb;
    }
    for (int i = 1; i < nt; i++)
        for (int j = i; j > 0 && ts[j] < ts[j - 1]; j--) {
            float x = ts[j];
            ts[j] = ts[j - 1];
            ts[j - 1] = x;
        }
    ts[nt++] = t_end;
    float fpc = float(n / lr);
    int per = int(n / lr);
    for (int sg = 0; sg + 1 < nt; sg++) {
        float ta = ts[sg], tb = ts[sg + 1];
        if (!(tb > ta)) continue;
        vec3 qm = q0 + 0.5 * (ta + tb) * d;
        vec3 s = vec3(qm.x < 0.0 ? -1.0 : 1.0, qm.y < 0.0 ? -1.0 : 1.0, qm.z < 0.0 ? -1.0 : 1.0);
        vec3 qa = q0 + ta * d, qb = q0 + tb * d;
        vec2 ua, ub;
        float e = min(1e-4, 0.5 * (tb - ta));
        if (!lf_enc_octant(qa, s, ua)) qa = q0 + (ta + e) * d;
        if (!lf_enc_octant(qb, s, ub)) qb = q0 + (tb - e) * d;
        if (!lf_enc_octant(qa, s, ua) || !lf_enc_octant(qb, s, ub) || any(isnan(vec4(ua, ub))) ||
            any(isinf(vec4(ua, ub)))) {
            t = ta;
            return LF_UNKNOWN;
        }
        vec2 A = (ua + 1.0) * 0.5 * float(lr), B = (ub + 1.0) * 0.5 * float(lr);
        vec2 Af = A * fpc, Bf = B * fpc, ef = Bf - Af;
        bool radial = abs(ef.x) + abs(ef.y) < 1e-6;
        Dda gc = dda_init(A, B, 0.0, int(lr));
        float ac0 = 0.0, tc0 = ta;
        for (uint guard = 0u; ac0 < 1.0 && guard < 4u * lr + 8u; guard++) {
            // a step can land one cell past the map's edge (the segment ends on it up to
            // rounding); a texel index from there read outside the probe's maps (NaN
            // halves on lavapipe, other probes' radiance elsewhere): stay on the map
            ivec2 c = clamp(gc.i, ivec2(0), ivec2(int(lr) - 1));
            float ac1 = radial ? 1.0 : min(dda_step(gc), 1.0);
            float tc1 = tb;
            if (ac1 < 1.0)
                tc1 = min(max(lf_t_of_dir(q0, d, oct_decode((Af + ac1 * ef) / float(n) * 2.0 - 1.0), tc0), tc0), tb);
            uint lc = lf_low(k, uint(c.y + 1) * (lr + 2u) + uint(c.x + 1));
            float dmin = lc == 0xFFFFu ? BIG : float(lc) * P.lf_lo.w;
            float rmax = max(length(q0 + tc0 * d), length(q0 + tc1 * d));
            if (g_first || rmax >= dmin * (1.0 - 8.0 / float(n))) {
                Dda gf = dda_init(Af, Bf, ac0, int(n));
                float af0 = ac0, tf0 = tc0;
                ivec2 lo = c * per, hi = lo + per - 1;
                for (uint g2 = 0u; af0 < ac1 && g2 < 4u * uint(per) + 8u; g2++) {
                    ivec2 f = clamp(clamp(gf.i, lo, hi), ivec2(0), ivec2(int(n) - 1));
                    float af1 = radial ? ac1 : min(dda_step(gf), ac1);
                    float tf1 = tc1;
                    if (af1 < ac1)
                        tf1 = min(max(lf_t_of_dir(q0, d, oct_decode((Af + af1 * ef) / float(n) * 2.0 - 1.0), tf0), tf0),
                                  tc1);
                    float th;
                    int r = lf_texel(k, f, q0, d, tf0, tf1, th);
                    if (r == 1) {
                        t = th;
                        texel = uint(f.y + 1) * (n + 2u) + uint(f.x + 1);
                        return LF_HIT;
                    }
                    if (r == 2) {
                        t = tf0;
                        return LF_UNKNOWN;
                    }
                    af0 = af1;
                    tf0 = tf1;
                    if (radial) break;
                }
            }
            ac0 = ac1;
            tc0 = tc1;
            if (radial) break;
        }
    }
    t = t_end;
    return LF_MISS;
}

float lf_exit(vec3 o, vec3 d) {
    float tn = 0.0, tf = BIG;
    for (int k = 0; k < 3; k++) {
        if (d[k] == 0.0) {
            if (o[k] < P.lf_lo[k] || o[k] > P.lf_hi[k]) return 0.0;
            continue;
        }
        float a = (P.lf_lo[k] - o[k]) / d[k], b = (P.lf_hi[k] - o[k]) / d[k];
        tn = max(tn, min(a, b));
        tf = min(tf, max(a, b));
    }
    return tf >= tn ? tf : 0.0;
}

vec3 lf_radiance(vec3 o, vec3 d) {
    float t_end = lf_exit(o, d);
    if (!(t_end > 0.0)) return P.sky.xyz;
    ivec3 base;
    for (int k = 0; k < 3; k++) {
        float g = (o[k] - P.origin[k]) / P.spacing[k], top = float(P.grid[k]) - 1.0;
        g = clamp(g, 0.0, top);
        base[k] = int(min(floor(g), max(top - 1.0, 0.0)));
    }
    uint cand[8];
    float cd[8];
    int nc = 0;
    for (int c = 0; c < 8; c++) {
        ivec3 idx = base + ivec3(c & 1, (c >> 1) & 1, (c >> 2) & 1);
        if (any(greaterThanEqual(idx, ivec3(P.grid.xyz)))) continue;
        uint pi = uint(idx.x) + P.grid.x * (uint(idx.y) + P.grid.y * uint(idx.z));
        if (probes[pi].w == 2.0) continue;
        vec3 dv = probes[pi].xyz - o;
        float r = dot(dv, dv);
        int j = nc++;
        for (; j > 0 && cd[j - 1] > r; j--) {
            cand[j] = cand[j - 1];
            cd[j] = cd[j - 1];
        }
        cand[j] = pi;
        cd[j] = r;
    }
    float t = 0.0;
    for (int c = 0; c < nc; c++) {
        uint texel;
        int st = lf_trace_probe(cand[c], o, d, t, t_end, texel);
        if (st == LF_HIT) return lf_rad(cand[c], texel);
        if (st == LF_MISS) return P.sky.xyz;
    }
    // no probe could answer: the octree, shaded with the irradiance probes
    Hit h;
    if (!cast_ray(o, d, BIG, h)) return P.sky.xyz;
    Surf sf = surface(o, d, h);
    return sf.emit + direct(sf) + sf.alb / PI * irradiance_at(sf.p, sf.n, d);
}

// True unless llvmpipe's loop guard fired in this SIMD group (see the header):
// a loop of P.lf.w == 2 iterations that the compiler cannot count; once the
// guard has fired it runs once.
bool loops_intact() {
    uint n = 0u;
    for (uint i = 0u; i < P.lf.w; i++) n += 1u;
    return n == P.lf.w;
}

void bake() {
    uint res = P.a.x, texel = gl_GlobalInvocationID.x, slot = gl_GlobalInvocationID.y;
    if (texel >= res * res || slot >= P.seed.z) return;
    uint probe = P.a.w + slot;
    vec4 pr = probes[probe];
    uint spp = max(P.a.y, 1u);
    uint at = 1u + 3u * (slot * res * res + texel);
    if (pr.w == 2.0) {
        outv[at] = vec4(0.0);
        outv[at + 1u] = vec4(0.0);
        outv[at + 2u] = vec4(float(spp), 0.0, 0.0, 0.0);
        return;
    }
    bool fresh = P.lf.x != 0u; // the first dispatch: the state is not written yet
    uint s0 = fresh ? 0u : uint(outv[at + 2u].x), s1 = min(s0 + P.seed.w, spp);
    if (s0 >= spp) return;
    uint i = texel % res, j = texel / res;
    vec3 o = pr.xyz;
    vec4 acc = vec4(0.0, 0.0, 0.0, -1.0), geo = vec4(0.0); // acc.w: distance (-1: none)
    if (s0 == 0u) {
        vec2 uvc = (2.0 * vec2(i, j) + 1.0) / float(res) - 1.0;
        Hit h;
        if (cast_ray(o, oct_decode(uvc), P.origin.w, h)) {
            Inst I = insts[h.inst];
            vec4 row = h.axis == 0 ? I.r0 : (h.axis == 1 ? I.r1 : I.r2);
            geo = vec4(normalize(row.xyz * h.nsign), 1.0);
            acc.w = h.t;
        }
    } else {
        acc = outv[at];
        geo = outv[at + 1u];
    }
    uint s = s0;
    for (; s < s1; s++) {
        rng_init(probe, texel, s);
        vec2 uv = (2.0 * (vec2(i, j) + vec2(rnd(), rnd()))) / float(res) - 1.0;
        acc.xyz += path(o, oct_decode(uv), P.a.z);
    }
    // identical values from every invocation that writes them
    if (s != s1 || !loops_intact()) {
        if (fresh) outv[at + 2u] = vec4(0.0); // a valid state: no samples yet
        outv[0].x = 1.0;
        outv[0].y = 1.0;
        return;
    }
    outv[at] = acc;
    outv[at + 1u] = geo;
    outv[at + 2u] = vec4(float(s1), 0.0, 0.0, 0.0);
    if (s1 < spp) outv[0].y = 1.0;
}

void render() {
    uint W = P.a.x, H = P.a.w;
    uint idx = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u;
    if (idx >= W * H) return;
    uint x = idx % W, y = idx / W;
    uint spp = max(P.a.y, 1u);
    uint s0 = uint(outv[2u * idx + 2u].x), s1 = min(s0 + P.seed.w, spp);
    if (s0 >= spp) return;
    bool ortho = F.rx.w != 0.0;
    float t_start = F.fwd.w;
    vec4 acc = outv[2u * idx + 1u];
    uint s = s0;
    for (; s < s1; s++) {
        rng_init(0x90000000u + y, x, s);
        vec2 off = vec2(0.0);
        if (spp > 1u) off = vec2(rnd(), rnd()) - 0.5;
        float u = ((float(x) + 0.5 + off.x) / float(W)) * 2.0 - 1.0;
        float v = 1.0 - ((float(y) + 0.5 + off.y) / float(H)) * 2.0;
        vec3 o, d;
        if (ortho) {
            o = u * F.rx.xyz + v * F.uy.xyz;
            d = F.fwd.xyz;
        } else {
            d = normalize(F.fwd.xyz + u * F.rx.xyz + v * F.uy.xyz);
            o = t_start * (u * F.rx.xyz + v * F.uy.xyz);
        }
        vec3 c = vec3(0.0);
        Hit h;
        if (!cast_ray(o, d, BIG, h)) {
            if (PMODE == P_GI || PMODE == P_PT || PMODE == P_LF) c = P.sky.xyz;
        } else {
            Surf sf = surface(o, d, h);
            if (PMODE == P_GI || PMODE == P_PT || PMODE == P_LF) c += sf.emit + direct(sf);
            if (PMODE == P_GI || PMODE == P_GI_IND) {
                c += sf.alb / PI * irradiance_at(sf.p, sf.n, d);
            } else if (PMODE == P_LF || PMODE == P_LF_IND) {
                float u1 = rnd(), u2 = rnd();
                c += sf.alb * lf_radiance(sf.p, cosine_dir(sf.n, u1, u2));
            } else if (P.a.z > 0u) {
                float u1 = rnd(), u2 = rnd();
                c += sf.alb * path(sf.p, cosine_dir(sf.n, u1, u2), P.a.z - 1u);
            }
            acc.w += 1.0;
        }
        acc.xyz += c;
    }
    // identical values from every invocation that writes them
    if (s != s1 || !loops_intact()) {
        outv[0].x = 1.0;
        outv[0].y = 1.0;
        return;
    }
    outv[2u * idx + 1u] = acc;
    outv[2u * idx + 2u] = vec4(float(s1), 0.0, 0.0, 0.0);
    if (s1 < spp) outv[0].y = 1.0;
}

void main() {
    if (PMODE == P_BAKE) bake();
    else render();
}
