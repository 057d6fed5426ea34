#version 450
// render/shaders/probe.comp - the light field probes' GPU passes on the
// octree tracer (float variant only), with the lighting model of
// probes/light.c (see probes/probes.h): diffuse albedo, one directional light
// with shadow rays, a uniform sky, emissive attributes.
//   PMODE 0 (bake): one invocation per (texel, probe): the texel centre ray's
//     distance and normal, and the radiance averaged over spp jittered paths.
//   PMODE 1..4 (gi, pathtrace, gi-indirect, pathtrace-indirect): one
//     invocation per pixel, as probes/render_gi.c.
// Random numbers: every path draws from its own counter-based stream keyed by
// (seed, probe or pixel, texel or row, sample), so results do not depend on
// the dispatch order or batch size. Layouts: probes/probe_gpu.c.
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

#include "trace_common.glsl"

layout(constant_id = 5) const int PMODE = 0;
const int P_BAKE = 0, P_GI = 1, P_PT = 2, P_GI_IND = 3, P_PT_IND = 4;

layout(std430, binding = 7) readonly buffer Params {
    vec4 light;    // xyz: unit, towards the light
    vec4 sun;      // rgb: irradiance on a surface facing the light
    vec4 sky;      // rgb: radiance
    uvec4 a;       // x: res (bake) / width, y: spp, z: bounces, w: first probe (bake) / height
    uvec4 seed;    // x, y: seed low and high words, z: probes in this dispatch (bake)
    uvec4 grid;    // xyz: probes per axis, w: probe count
    vec4 origin;   // xyz: grid origin relative to the reference point, w: dist_max
    vec4 spacing;  // xyz: spacing, w: minimum spacing
} P;
layout(std430, binding = 8) readonly buffer Emit { float emit_attr[]; };  // per colors[] entry
layout(std430, binding = 9) readonly buffer Probes { vec4 probes[]; };    // xyz: position - reference, w: state
layout(std430, binding = 10) writeonly buffer Out { vec4 outv[]; };
// per probe: irradiance (10x10x3) then, after all probes, moments (18x18x2)
layout(std430, binding = 11) readonly buffer Maps { float maps[]; };

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

void bake() {
    uint res = P.a.x, texel = gl_GlobalInvocationID.x, slot = gl_GlobalInvocationID.y;
    if (texel >= res * res || slot >= P.seed.z) return;
    uint probe = P.a.w + slot;
    vec4 pr = probes[probe];
    uint at = 2u * (slot * res * res + texel);
    if (pr.w == 2.0) {
        outv[at] = vec4(0.0);
        outv[at + 1u] = vec4(0.0);
        return;
    }
    uint i = texel % res, j = texel / res;
    vec3 o = pr.xyz;
    vec2 uvc = (2.0 * vec2(i, j) + 1.0) / float(res) - 1.0;
    Hit h;
    vec4 geo = vec4(0.0);
    float dist = -1.0;
    if (cast_ray(o, oct_decode(uvc), P.origin.w, h)) {
        Inst I = insts[h.inst];
        vec4 row = h.axis == 0 ? I.r0 : (h.axis == 1 ? I.r1 : I.r2);
        geo = vec4(normalize(row.xyz * h.nsign), 1.0);
        dist = h.t;
    }
    vec3 acc = vec3(0.0);
    uint spp = P.a.y;
    for (uint s = 0u; s < spp; s++) {
        rng_init(probe, texel, s);
        vec2 uv = (2.0 * (vec2(i, j) + vec2(rnd(), rnd()))) / float(res) - 1.0;
        acc += path(o, oct_decode(uv), P.a.z);
    }
    outv[at] = vec4(acc / float(spp), dist);
    outv[at + 1u] = geo;
}

void render() {
    uint W = P.a.x, H = P.a.w;
    uint idx = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u;
    if (idx >= W * H) return;
    uint x = idx % W, y = idx / W;
    uint spp = max(P.a.y, 1u);
    bool ortho = F.rx.w != 0.0;
    float t_start = F.fwd.w;
    vec4 acc = vec4(0.0);
    for (uint s = 0u; s < spp; s++) {
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
            if (PMODE == P_GI || PMODE == P_PT) c = P.sky.xyz;
        } else {
            Surf sf = surface(o, d, h);
            if (PMODE == P_GI || PMODE == P_PT) c += sf.emit + direct(sf);
            if (PMODE == P_GI || PMODE == P_GI_IND) {
                c += sf.alb / PI * irradiance_at(sf.p, sf.n, d);
            } else if (P.a.z > 0u) {
                float u1 = rnd(), u2 = rnd();
                c += sf.alb * path(sf.p, cosine_dir(sf.n, u1, u2), P.a.z - 1u);
            }
            acc.w += 1.0;
        }
        acc.xyz += c;
    }
    outv[y * W + x] = acc / float(spp);
}

void main() {
    if (PMODE == P_BAKE) bake();
    else render();
}
