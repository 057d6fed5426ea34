// probes/shaders/path_common.glsl - what the path tracer (probe.comp) and the
// photon tracer (photons/shaders/photon.comp) share: random numbers, rays
// through the scene, surfaces, and the materials of probes/pathtrace.c
// (Lambert, GGX metal, dielectric glass with Fresnel, the walk through a
// glass voxel). Include after trace_common.glsl and after declaring
//   bool MATS (a spec constant: some attribute record is metal or glass),
//   emit_attr[] (per colors[] entry the emission's terms, svo/svo.h vx_material_emitted_terms: colour * w + xyz),
//   mats[] (per colors[] entry two vec4, layout of probes/probe_gpu.c),
//   ems[] (emissive voxels, five vec4 each, layout of probes/probe_gpu.c),
// and define uvec2 rng_seed() (the seed's two words) somewhere in the shader.
uvec2 rng_seed();
// PT_PREC: `precise` where the includer defines it so, with PATH_PRECISE (probe.comp's kernels: every float
// operation of the path as written, no contraction into fused multiply-adds, so that its pipelines give the
// same bits on NVIDIA), else nothing (photon.comp)
#ifndef PT_PREC
#define PT_PREC
#endif
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
    g_key = pcg4d(uvec4(a, b, c, rng_seed().x ^ (rng_seed().y * 0x9E3779B9u)));
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

struct Surf { vec3 p, n, alb, emit; float cell; uint attr; };

bool cast_ray(vec3 o, vec3 d, float tmax, out Hit h) {
    h.t = tmax;
    h.inst = NO_HIT;
    h.color = 0xFFFFFFFFu;
    h.attr = NO_HIT;
    g_iter = 0u;
    return trace_scene(o, d, 0.0, false, h);
}

bool occluded_to(vec3 o, vec3 d, float tmax) {
    Hit h;
    h.t = tmax;
    h.inst = NO_HIT;
    g_iter = 0u;
    return trace_scene(o, d, 0.0, true, h);
}
bool occluded(vec3 o, vec3 d) { return occluded_to(o, d, BIG); }

Surf surface(vec3 o, vec3 d, Hit h) {
    PT_PREC Surf s;
    Inst I = insts[h.inst];
    vec4 row = h.axis == 0 ? I.r0 : (h.axis == 1 ? I.r1 : I.r2);
    s.n = normalize(row.xyz * h.nsign);
    PT_PREC vec3 p = o + d * h.t;
    // off the surface (as the tracer's shadow rays; float needs more than the CPU's 1e-6 cell)
    s.p = p + s.n * (I.cell * 1e-3 + 4e-6 * max(max(abs(p.x), abs(p.y)), abs(p.z)));
    s.alb = HAS_COLOR ? unpack_rgb(h.color) : vec3(1.0);
    // records past the table emit nothing (a scene without emission binds a table of one record)
    vec4 e = h.attr < uint(emit_attr.length()) ? emit_attr[h.attr] : vec4(0.0);
    s.emit = s.alb * e.w + e.xyz;
    s.cell = I.cell;
    s.attr = h.attr;
    return s;
}

#include "sampling.glsl" // basis, cosine_dir, cone_dir (shared with the pass shaders)

PT_PREC float lum(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }
PT_PREC float mis(float a, float b) { return a * a / (a * a + b * b); }

PT_PREC float ggx_d(float a2, float z) {
    float c = z * z * (a2 - 1.0) + 1.0;
    return a2 / (PI * c * c);
}
PT_PREC float ggx_lambda(float a2, float z) {
    PT_PREC float z2 = z * z;
    if (z2 >= 1.0) return 0.0;
    if (!(z2 > 0.0)) return 1e30;
    return 0.5 * (-1.0 + sqrt(1.0 + a2 * (1.0 - z2) / z2));
}
PT_PREC vec3 ggx_vndf(float alpha, vec3 wo, float u1, float u2) {
    vec3 vh = normalize(vec3(alpha * wo.xy, wo.z));
    float l2 = dot(vh.xy, vh.xy);
    vec3 t1 = l2 > 0.0 ? vec3(-vh.y, vh.x, 0.0) / sqrt(l2) : vec3(1.0, 0.0, 0.0);
    vec3 t2 = cross(vh, t1);
    float r = sqrt(u1), phi = 2.0 * PI * u2;
    float p1 = r * cos(phi), p2 = r * sin(phi), s = 0.5 * (1.0 + vh.z);
    p2 = (1.0 - s) * sqrt(max(0.0, 1.0 - p1 * p1)) + s * p2;
    vec3 nh = p1 * t1 + p2 * t2 + sqrt(max(0.0, 1.0 - p1 * p1 - p2 * p2)) * vh;
    return normalize(vec3(alpha * nh.xy, max(0.0, nh.z)));
}
#include "dielectric.glsl" // fresnel_dielectric (shared with the pass pipeline's glass seen directly)

const int B_LAMBERT = 0, B_GLOSSY = 1, B_GLASS = 2;
struct Bsdf { int kind; vec3 alb, kd, f0; float alpha, a2, ps, eta; vec3 n, t, b; };

Bsdf bsdf_of(Surf s) {
    PT_PREC Bsdf B;
    B.kind = B_LAMBERT;
    B.alb = s.alb;
    B.kd = vec3(0.0);
    B.f0 = vec3(0.0);
    B.alpha = 0.0;
    B.a2 = 0.0;
    B.ps = 0.0;
    B.eta = 1.0;
    B.n = s.n;
    basis(s.n, B.t, B.b);
    if (MATS && s.attr != NO_HIT) {
        vec4 m0 = mats[2u * s.attr], m1 = mats[2u * s.attr + 1u];
        if (m0.x == 1.0) {
            B.kind = B_GLOSSY;
            float mt = m0.z, f0d = 0.08 * m0.w;
            B.kd = (1.0 - mt) * (1.0 - f0d) * s.alb;
            B.f0 = (1.0 - mt) * f0d + mt * s.alb;
            B.alpha = max(m0.y, 1e-3);
            B.a2 = B.alpha * B.alpha;
            B.ps = 0.5 * (1.0 + mt);
        } else if (m0.x == 2.0 && m1.y > 0.0 && (m1.y >= 1.0 || rnd() < m1.y)) {
            B.kind = B_GLASS;
            B.alpha = m0.y;
            B.a2 = B.alpha * B.alpha;
            B.eta = m1.x;
        }
    }
    return B;
}

PT_PREC vec3 to_local(Bsdf B, vec3 v) { return vec3(dot(v, B.t), dot(v, B.b), dot(v, B.n)); }

PT_PREC vec3 bsdf_eval(Bsdf B, vec3 wo_w, vec3 wi_w, PT_PREC out float pdf) {
    vec3 wo = to_local(B, wo_w), wi = to_local(B, wi_w);
    pdf = 0.0;
    if (wi.z <= 0.0 || wo.z <= 0.0) return vec3(0.0);
    if (B.kind == B_LAMBERT) {
        pdf = wi.z / PI;
        return B.alb / PI;
    }
    vec3 h = normalize(wo + wi);
    float d = ggx_d(B.a2, h.z), lo = ggx_lambda(B.a2, wo.z), li = ggx_lambda(B.a2, wi.z);
    float g2 = 1.0 / (1.0 + lo + li), s5 = pow(clamp(1.0 - dot(wi, h), 0.0, 1.0), 5.0); // dot can pass 1 by rounding: pow(< 0) is NaN
    pdf = B.ps * d / (1.0 + lo) / (4.0 * wo.z) + (1.0 - B.ps) * wi.z / PI;
    return B.kd / PI + (B.f0 + (1.0 - B.f0) * s5) * (d * g2 / (4.0 * wo.z * wi.z));
}

// bsdf_sample with its three numbers given (u0 picks the lobe, u1 and u2 the direction in it)
bool bsdf_sample_u(Bsdf B, vec3 wo_w, float u0, float u1, float u2, PT_PREC out vec3 wi_w, PT_PREC out vec3 w,
                   PT_PREC out float pdf) {
    vec3 wo = to_local(B, wo_w);
    w = vec3(0.0);
    pdf = 0.0;
    if (B.kind == B_LAMBERT || u0 >= B.ps) {
        wi_w = cosine_dir(B.n, u1, u2);
    } else {
        if (wo.z <= 0.0) return false;
        vec3 m = ggx_vndf(B.alpha, wo, u1, u2);
        vec3 wi = 2.0 * dot(wo, m) * m - wo;
        wi_w = normalize(wi.x * B.t + wi.y * B.b + wi.z * B.n);
    }
    vec3 f = bsdf_eval(B, wo_w, wi_w, pdf);
    PT_PREC float cs = dot(wi_w, B.n);
    if (!(pdf > 0.0) || cs <= 0.0) return false;
    w = f * cs / pdf;
    return true;
}

bool bsdf_sample(Bsdf B, vec3 wo_w, out vec3 wi_w, out vec3 w, out float pdf) {
    float u0 = rnd(), u1 = rnd(), u2 = rnd();
    return bsdf_sample_u(B, wo_w, u0, u1, u2, wi_w, w, pdf);
}

// a glossy vertex's two lobes apart: each lobe's f and its own sampler's pdf (probes/pathtrace.c glossy_lobes)
void glossy_lobes(Bsdf B, vec3 wo_w, vec3 wi_w, PT_PREC out vec3 fs, PT_PREC out float pss, PT_PREC out vec3 fd,
                  PT_PREC out float pdd) {
    vec3 wo = to_local(B, wo_w), wi = to_local(B, wi_w);
    fs = vec3(0.0), fd = vec3(0.0), pss = 0.0, pdd = 0.0;
    if (wi.z <= 0.0 || wo.z <= 0.0) return;
    vec3 h = normalize(wo + wi);
    float d = ggx_d(B.a2, h.z), lo = ggx_lambda(B.a2, wo.z), li = ggx_lambda(B.a2, wi.z);
    float g2 = 1.0 / (1.0 + lo + li), s5 = pow(clamp(1.0 - dot(wi, h), 0.0, 1.0), 5.0); // (bsdf_eval: pow(< 0))
    fs = (B.f0 + (1.0 - B.f0) * s5) * (d * g2 / (4.0 * wo.z * wi.z));
    fd = B.kd / PI;
    pss = d / (1.0 + lo) / (4.0 * wo.z);
    pdd = wi.z / PI;
}

// a glossy vertex's direction by one lobe (probes/pathtrace.c glossy_sample): the specular lobe where u0 < ps,
// else the Lambert lobe; w = the lobe's f cos / (its pick probability * pdf), pdf that denominator
bool glossy_sample_u(Bsdf B, vec3 wo_w, float u0, float u1, float u2, PT_PREC out vec3 wi_w, PT_PREC out vec3 w,
                     PT_PREC out float pdf, out bool spec) {
    vec3 wo = to_local(B, wo_w);
    w = vec3(0.0);
    pdf = 0.0;
    spec = u0 < B.ps;
    if (!spec) {
        wi_w = cosine_dir(B.n, u1, u2);
    } else {
        if (wo.z <= 0.0) return false;
        vec3 m = ggx_vndf(B.alpha, wo, u1, u2);
        vec3 wi = 2.0 * dot(wo, m) * m - wo;
        wi_w = normalize(wi.x * B.t + wi.y * B.b + wi.z * B.n);
    }
    PT_PREC vec3 fs, fd;
    PT_PREC float pss, pdd;
    glossy_lobes(B, wo_w, wi_w, fs, pss, fd, pdd);
    pdf = spec ? B.ps * pss : (1.0 - B.ps) * pdd;
    PT_PREC float cs = dot(wi_w, B.n);
    if (!(pdf > 0.0) || cs <= 0.0) return false;
    w = (spec ? fs : fd) * cs / pdf;
    return true;
}

// one event at a dielectric interface (n faces the incident side, eta = n_other / n_this)
bool dielectric(vec3 n, vec3 wo_w, float eta, float alpha, PT_PREC out vec3 wi_w, out bool refracted,
                PT_PREC out float weight) {
    weight = 1.0;
    refracted = true;
    wi_w = -wo_w;
#ifdef PATH_PRECISE
    precise float em1 = eta - 1.0;
    if (abs(em1) < 1e-6) return true; // index-matched: no interface
#else
    if (abs(eta - 1.0) < 1e-6) return true; // index-matched: no interface
#endif
    vec3 t, b;
    basis(n, t, b);
    PT_PREC vec3 wo = vec3(dot(wo_w, t), dot(wo_w, b), dot(wo_w, n));
    if (wo.z <= 0.0) return false;
    bool rough = alpha >= 1e-3;
    float u1 = rnd(), u2 = rnd(), u3 = rnd();
    vec3 m = rough ? ggx_vndf(alpha, wo, u1, u2) : vec3(0.0, 0.0, 1.0);
    PT_PREC float c = dot(wo, m);
    if (c <= 0.0) return false;
    float fr = fresnel_dielectric(c, eta);
    PT_PREC vec3 wi;
    if (u3 < fr) {
        wi = 2.0 * c * m - wo;
        refracted = false;
    } else {
        float e = 1.0 / eta, k2 = 1.0 - e * e * (1.0 - c * c);
        wi = -e * wo + (e * c - sqrt(max(0.0, k2))) * m;
    }
    if (rough) {
        float a2 = alpha * alpha;
        if (refracted ? wi.z >= 0.0 : wi.z <= 0.0) return false;
        float li = ggx_lambda(a2, abs(wi.z)), lo = ggx_lambda(a2, wo.z);
        weight = refracted ? 1.0 / (1.0 + li) : (1.0 + lo) / (1.0 + lo + li);
    }
    wi_w = normalize(wi.x * t + wi.y * b + wi.z * n);
    return true;
}

bool is_glass(uint attr) {
    return MATS && attr != NO_HIT && mats[2u * attr].x == 2.0 && mats[2u * attr + 1u].y > 0.0;
}

#include "cell_leaf.glsl" // model_cell_leaf, glass_walk_steps
// The attribute (index into colors[]) of cell c of model mi, c inside its cube: NO_HIT where the cell is
// empty or the model has no attributes (cell_leaf.glsl model_cell_leaf).
uint model_cell_attr(uint mi, uvec3 c) {
    uint level;
    return model_cell_leaf(mi, c, level);
}

// Inside a glass voxel (cell of instance inst) at p along d: to the face where the glass ends
// (probes/pathtrace.c glass_walk). WALK_ABSORBED: glass_walk_steps of the model where it starts.
// WALK_OUT: o and d the ray that left. WALK_STOP: an opaque voxel across a face of the glass (a glass
// block on a floor, a voxel set in glass) or, where the scene has several instances, another instance's
// voxel inside the glass box (a model placed overlapping a glass one): o the point on its face, sh that
// face seen from inside the glass (t 0, the voxel's colour and record, the instance and axis that give
// its normal), gi and gc the glass cell it was met from, where a bounce off it walks on. Each step leaves the box of the octree leaf that holds the current cell
// (a uniform glass block at once, cell_leaf.glsl; else the cell), its exit measured along the straight
// stretch from its start p (t: how far the walk is along it), so the exit from the glass does not depend
// on the boxes taken on the way: the compact layout, which walks cell by cell, gives the same bits. The
// next cell is looked up in the instance's own model first: a glass cell there is what the short ray below
// would meet, at a fraction of its cost (no BVH, no ray set-up; a photon crosses some 20 cells of a
// sphere); the ray decides the rest (empty cells, other instances, the model's edge).
// (GLASS_CELL(mi, c, level): whether cell c of model mi is glass, and its leaf's level (0 where not
// known); a shader that keeps the cells as bits defines its own)
#ifndef GLASS_CELL
bool glass_cell_leaf(uint mi, uvec3 c, out uint level) { return is_glass(model_cell_leaf(mi, c, level)); }
#define GLASS_CELL(mi, c, level) glass_cell_leaf(mi, c, level)
#endif
const uint WALK_ABSORBED = 0u, WALK_OUT = 1u, WALK_STOP = 2u;
// A refraction into the glass of surface s (hit h, met along o + t d, its BSDF B) towards wi
// (probes/pathtrace.c glass_enter): the colour at entry into thr, o just inside the face, d = wi, and the
// glass cell gc of instance gi, the glass's index and roughness, where the walk starts at the next event.
void glass_enter(Hit h, Surf s, Bsdf B, vec3 wi, PT_PREC inout vec3 o, PT_PREC inout vec3 d, PT_PREC inout vec3 thr,
                 out uint gi, out uvec3 gc, out float ior, out float alpha) {
    thr *= B.alb;
    // (through a temporary: `o = o + ...` sent glslang 11's propagation of precise into an endless growth, 8 GB
    // in seconds)
    PT_PREC vec3 pe = o + d * h.t - s.n * (1e-3 * s.cell);
    o = pe;
    d = wi;
    gi = h.inst, gc = h.cell, ior = mats[2u * s.attr + 1u].x, alpha = B.alpha;
}

uint glass_walk(uint inst, uvec3 cell, float ior, float alpha, PT_PREC vec3 p, PT_PREC inout vec3 d,
                PT_PREC inout vec3 thr, PT_PREC out vec3 o, out Hit sh, out uint gi, out uvec3 gc) {
    uvec3 c = cell;
    uint lv;
    if (!GLASS_CELL(insts[inst].model, c, lv)) lv = 0u;
    o = p;
    PT_PREC float t = 0.0;
    uint limit = glass_walk_steps(insts[inst].model);
    for (uint step = 0u; step < limit; step++) {
        Inst I = insts[inst];
        // the leaf's box [lo, hi), within the model's cube
        float side = exp2(float(model_at(I.model).depth));
        vec3 lo = vec3(c & ~uvec3((1u << lv) - 1u)), hi = min(lo + exp2(float(lv)), vec3(side));
        PT_PREC vec3 om = vec3(dot(I.r0.xyz, p) + I.r0.w, dot(I.r1.xyz, p) + I.r1.w, dot(I.r2.xyz, p) + I.r2.w);
        PT_PREC vec3 dm = vec3(dot(I.r0.xyz, d), dot(I.r1.xyz, d), dot(I.r2.xyz, d));
        PT_PREC float te = BIG;
        int ax = -1;
        for (int a = 0; a < 3; a++) {
            if (dm[a] == 0.0) continue;
            PT_PREC float ta = ((dm[a] > 0.0 ? hi[a] : lo[a]) - om[a]) / dm[a];
            if (ta < te) { te = ta; ax = a; }
        }
        if (ax < 0) return WALK_ABSORBED;
        te = max(te, t);
        // another instance's voxel inside the box (a box of one cell: met at its faces, below)
        if (USE_BVH && lv > 0u && te > t) {
            Hit g;
            // (precise: test_spirv_precise checks the walk's every float operation)
            PT_PREC vec3 a = p + d * t;
            PT_PREC float len = te - t;
            if (other_instance_hit(inst, a, d, len, g) && !is_glass(g.attr)) {
                sh = g;
                o = a + d * g.t;
                sh.t = 0.0;
                gi = inst;
                gc = c;
                return WALK_STOP;
            }
        }
        vec4 row = ax == 0 ? I.r0 : (ax == 1 ? I.r1 : I.r2);
        PT_PREC vec3 nf = normalize(row.xyz) * (dm[ax] > 0.0 ? 1.0 : -1.0);
        PT_PREC vec3 q = p + d * te;
        PT_PREC float eps = 1e-3 * I.cell + 4e-6 * max(max(abs(q.x), abs(q.y)), abs(q.z));
        PT_PREC vec3 qi = q + d * eps;
        PT_PREC vec3 mq = floor(vec3(dot(I.r0.xyz, qi) + I.r0.w, dot(I.r1.xyz, qi) + I.r1.w, dot(I.r2.xyz, qi) + I.r2.w));
        uint nl;
        // a cell outside the box (else the ray decides: no step back into it)
        if (all(greaterThanEqual(mq, vec3(0.0))) && all(lessThan(mq, vec3(side))) &&
            !(all(greaterThanEqual(mq, lo)) && all(lessThan(mq, hi))) && GLASS_CELL(I.model, uvec3(mq), nl)) {
            c = uvec3(mq);
            lv = nl;
            t = te + eps;
            continue;
        }
        Hit g;
        if (cast_ray(qi, d, eps, g)) {
            if (!is_glass(g.attr)) { // an opaque voxel against the glass: its face, lit only through the glass
                sh = g;
                sh.t = 0.0;
                sh.inst = inst; // the face is the glass cell's: its normal from the glass instance's axes
                sh.axis = ax;
                sh.nsign = dm[ax] > 0.0 ? -1.0 : 1.0;
                o = q;
                gi = inst;
                gc = c;
                return WALK_STOP;
            }
            inst = g.inst;
            c = g.cell;
            if (!GLASS_CELL(insts[inst].model, c, lv)) lv = 0u;
            t = te + eps;
            continue;
        }
        vec3 wi;
        bool refr;
        float w;
#ifdef PATH_PRECISE
        precise float eta = 1.0 / ior;
        if (!dielectric(-nf, -d, eta, alpha, wi, refr, w)) return WALK_ABSORBED;
#else
        if (!dielectric(-nf, -d, 1.0 / ior, alpha, wi, refr, w)) return WALK_ABSORBED;
#endif
        thr *= w;
        d = wi;
        if (refr) {
            o = q + nf * eps;
            return WALK_OUT;
        }
        // reflected inside: a new stretch from just inside the face
        p = q - nf * eps;
        t = 0.0;
    }
    return WALK_ABSORBED;
}

// A point of an emissive voxel's surface, the voxel picked by power among the first `count` of ems[]
// (their cdf), its face by area, the point uniform on the face: y, the face's outward normal n, the
// voxel's radiance rad and the length of the face's normal edge (an offset scale).
void emitter_point(uint count, PT_PREC out vec3 y, out vec3 n, out vec3 rad, out float edge) {
    float u = rnd();
    uint lo = 0u, hi = count - 1u;
    while (lo < hi) {
        uint mid = lo + (hi - lo) / 2u;
        if (ems[5u * mid + 1u].w <= u) lo = mid + 1u;
        else hi = mid;
    }
    vec4 c0 = ems[5u * lo];
    vec3 ax[3] = vec3[3](ems[5u * lo + 1u].xyz, ems[5u * lo + 2u].xyz, ems[5u * lo + 3u].xyz);
    rad = ems[5u * lo + 4u].xyz;
    PT_PREC float fa0 = 2.0 * length(cross(ax[1], ax[2])), fa1 = 2.0 * length(cross(ax[2], ax[0]));
    PT_PREC float pick = rnd() * c0.w;
#ifdef PATH_PRECISE
    precise float fa01 = fa0 + fa1;
    int a = pick < fa0 ? 0 : (pick < fa01 ? 1 : 2);
#else
    int a = pick < fa0 ? 0 : (pick < fa0 + fa1 ? 1 : 2);
#endif
    float side = rnd() < 0.5 ? 0.0 : 1.0;
    float u1 = rnd(), u2 = rnd();
    vec3 ea = ax[a], eb = ax[(a + 1) % 3], ec = ax[(a + 2) % 3];
    y = c0.xyz + side * ea + u1 * eb + u2 * ec;
    n = normalize(cross(eb, ec));
    if ((dot(n, ea) > 0.0) != (side == 1.0)) n = -n;
    edge = length(ea);
}
