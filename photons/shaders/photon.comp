#version 450
// photons/shaders/photon.comp - GPU photon mapping (photons/photons.h): one
// shader, one binding layout, the step chosen by the spec constant STEP:
//   STEP 0 clear:   zero the bucket counts (the buckets this pass's stored photons use)
//   STEP 6 reset:   zero the counters (before the trace)
//   STEP 1 trace:   one invocation per photon: emit from a source picked by
//                   power, trace through the BVH and octrees with the path
//                   tracer's materials (path_common.glsl), store a photon at
//                   every non-glass surface it reaches, Russian roulette
//   STEP 2 count:   per stored photon, count it into its hash bucket
//   STEP 3 alloc:   per bucket, claim a contiguous range of the sorted array
//   STEP 4 scatter: per stored photon, copy it into its bucket's range
//   STEP 5 gather:  per pixel, the camera's path to its last surface (through
//                   glass and glossy reflection) and the estimate wherever it
//                   is not a plain Lambert sum; the rest goes to STEP 7 as a
//                   record in Photons (free after the scatter)
//   STEP 7 density: per pixel, the record's Lambert sums over both maps, added
//                   into Out (a small kernel: the gather loop runs at the
//                   occupancy of its own registers, not the tracer's)
//   STEP 9 size:    one invocation, after the trace: the buckets this pass
//                   uses and the group counts of the steps after it, from the
//                   photons stored (the pass is one submission: photons.c)
// Coordinates are world minus the frame's reference point (as the tracer's).
// Layouts: photons/photons.c.
// Built twice: as it is (photon.comp.h, every step) and with PHOTON_SMALL
// (photon_small.comp.h), whose main leaves out the trace and the camera's
// paths, so that the module holds no walk: photons.c makes the small steps'
// pipelines from it. A driver translates a whole module before specialising
// it, and lavapipe took 1.1-1.6 s for each of the nine steps' pipelines of the
// whole module, the zeroing steps as the trace (gi=photons: 12 of an svo_render's
// 16.6 s on a small scene).
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_ballot : require

// GROUP (spec constant 7): invocations per workgroup (vx_photon_desc.workgroup)
layout(local_size_x_id = 7, local_size_y = 1, local_size_z = 1) in;

#include "trace_common.glsl"

layout(constant_id = 5) const int STEP = 0;
layout(constant_id = 6) const bool MATS = false; // some attribute record is metal or glass (binding 9)
const int S_CLEAR = 0, S_TRACE = 1, S_COUNT = 2, S_ALLOC = 3, S_SCATTER = 4, S_GATHER = 5, S_RESET = 6, S_DENSITY = 7,
          S_SIZE = 9; // (8: the trace and the camera's paths in one pipeline, before they ran side by side)

layout(std430, binding = 7) readonly buffer Params {
    uvec4 a;      // x: photons emitted this pass, y: capacity (stored photons), z: stored bounces,
                  // w: buckets (2^k) this pass (set after the trace from the photons stored)
    uvec4 seed;   // x, y: seed words, z: pass, w: sources
    vec4 r;       // x: global radius, y: caustic radius, z: 1 / (pi rg^2), w: 1 / (pi rc^2)
    uvec4 img;    // x: width, y: height, z: 1: average into Out with pass z of the seed (running mean), w: full
    vec4 sphere;  // xyz: centre of the scene's bounding sphere, w: its radius
    vec4 sky;     // rgb: sky radiance (render/shaders/sky.glsl zen), w: emissive voxels' total power (sum lum(rad) area)
    uvec4 cnt;    // x: emissive voxels, y: 2 (loops_intact), z: final gather rays (0: none),
                  // w: 1: a light stands for the emissive voxels (the direct pass shades them)
    vec4 skyh;    // the sky by direction (sky.glsl): horizon rgb, w: kind (0 uniform: sky.rgb)
    vec4 skyg;    // ground rgb, w: map intensity
    vec4 skym;    // map: rotation, width, height
    vec4 fx;      // the gather's fixed-point units (fx_add): x per unit of BSDF times power, y per unit of power
    uvec4 tr;     // x: invocations of the trace (each traces photons i, i + x, ...), y: 1: count only (a photon's
                  // stores into Cells, none stored: photons.c's pass over the capacity), z: the photons the
                  // sources can bring: 1 F_LIGHT ones, 2 F_DIRECT ones (G_LIGHTS sums of neither are 0),
                  // w: 1: more than one instance (kernel_factors looks for other models' faces)
    uvec4 fu;     // x: the density step's records' first vec4 in Photons, y: 0,
                  // z: the gather's and the density step's workgroups (S_SIZE)
} P;
layout(std430, binding = 8) readonly buffer Emit { vec4 emit_attr[]; };
layout(std430, binding = 9) readonly buffer Mats { vec4 mats[]; };
// per source six vec4: (position, type), (unit direction, range), (power / probability rgb, cdf),
// (spot scale, spot offset, 1 - cos of the emission cone, radius), (unit tangent, size0), (size1, direct, 0, 0);
// the sky: e.xyz 1 / its mean radiance
layout(std430, binding = 10) readonly buffer Sources { vec4 src[]; };
// per exposed face of an emissive voxel (photons.c's face table) five vec4: (corner, area), (edge u, the
// alias table's probability), (edge v, bits of the alias), (outward unit normal, the cell's edge across
// the face), (radiance, 0)
layout(std430, binding = 11) readonly buffer Emitters { vec4 ems[]; };
// stored photons, two vec4 each: (position, bits of the packed normal with the flags in its low bits),
// (power rgb, bits of the packed incoming direction with F_FIRST in its lowest): see store(); a gather
// decides on the first vec4 alone whether a photon counts. From the gather step on (the photons are in
// Sorted then): three vec4 per pixel for the density step (gather_pixel)
layout(std430, binding = 12) buffer Photons { vec4 ph[]; };
// the stored photons by bucket, split: [0, capacity) their first vec4 (position, normal, flags: all a
// gather reads of a photon that does not count), [capacity, 2 capacity) their second
layout(std430, binding = 13) buffer Sorted { vec4 sorted[]; };
// per bucket: count, then (after alloc) start; while counting (Params tr.y), the photons' stores, two a uvec2
layout(std430, binding = 14) buffer Cells { uvec2 cells[]; };
layout(std430, binding = 15) buffer Out { vec4 outv[]; };
// x: photons stored (may pass the capacity: photons.c then traces the pass again), y: sorted so far, z: the loop guard
// fired; from ctr[4] on, S_SIZE's output, group counts (x, y, z) of indirect dispatches: [4..6] the buckets' steps
// (clear, alloc) and [7] the buckets (copied into Params a.w), [8..10] the stored photons' steps (count, scatter),
// [12..14] the pixels' steps (gather, density); all 0 when the stores passed the capacity
layout(std430, binding = 16) buffer Counters { uint ctr[]; };
// the sky's environment map, RGB per texel, row 0 at +z (a placeholder unless the sky is a map)
layout(std430, binding = 17) readonly buffer Env { float env[]; };
// The models' cells, a bit each (photons.c make_occ): occ[model] its first word (0xFFFFFFFF: none; the
// octree walk then), bit x + side (y + side z) from there whether the cell is set, and where the scene
// has glass, as many words after them whether it is glass
layout(std430, binding = 18) readonly buffer Occ { uint occ[]; };
// The glass walk's next cell (path_common.glsl glass_walk): a bit where the model has them
bool photon_glass_cell(uint mi, uvec3 c, out uint level);
#define GLASS_CELL(mi, c, level) photon_glass_cell(mi, c, level)

#include "path_common.glsl"
#define SKY_TEXEL(i) env[i]
#include "sky.glsl"
// the sky's radiance towards unit d (uniform, or by direction: the path tracer's sky_eval)
vec3 sky_radiance(vec3 d) { return sky_eval(P.sky, P.skyh, P.skyg, P.skym, d); }
// A uniform 32-bit word of the invocation's random stream (path_common.glsl's rnd() keeps 24 bits).
uint rnd_word() {
    g_ctr++;
    return pcg4d(uvec4(g_key.x, g_key.y, g_key.z ^ g_ctr, g_key.w)).x;
}

uvec2 rng_seed() { return P.seed.xy; }
Surf g_s; // the vertex being shaded (one copy: GLSL passes structs by value)

const uint T_DIRECTIONAL = 0u, T_POINT = 1u, T_SPOT = 2u, T_SPHERE = 3u, T_RECT = 4u, T_SKY = 5u, T_VOXELS = 6u;
// in the normal's code: the caustic map; brought by a light the direct pass shades (first surface);
// a caustic photon from a light no camera ray can meet (not the sky nor an emissive voxel: see G_LIGHTS)
const uint F_CAUSTIC = 1u, F_DIRECT = 2u, F_LIGHT = 4u, F_BITS = 7u;
const uint F_FIRST = 1u;                 // in the direction's code

// True unless llvmpipe's loop guard fired in this SIMD group (probes/shaders/probe.comp explains it).
bool loops_intact() {
    uint n = 0u;
    for (uint i = 0u; i < P.cnt.y; i++) n += 1u;
    return n == P.cnt.y;
}

uint item() { return gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x; }

vec3 uniform_sphere(float u1, float u2) {
    float z = 1.0 - 2.0 * u1, s = sqrt(max(0.0, 1.0 - z * z)), phi = 2.0 * PI * u2;
    return vec3(s * cos(phi), s * sin(phi), z);
}

// A point of the disk of radius R through c perpendicular to unit w.
vec3 disk_point(vec3 c, vec3 w, float R, float u1, float u2) {
    vec3 t, b;
    basis(w, t, b);
    float r = R * sqrt(u1), phi = 2.0 * PI * u2;
    return c + r * (cos(phi) * t + sin(phi) * b);
}

// ---- the hashed grid (cell = the map's gather radius) ----
uint bucket(ivec3 c, uint map) {
    uint h = uint(c.x) * 73856093u ^ uint(c.y) * 19349663u ^ uint(c.z) * 83492791u ^ map * 2654435761u;
    h ^= h >> 15u;
    h *= 0x2C1B3C6Du;
    h ^= h >> 12u;
    return h & (P.a.w - 1u);
}
ivec3 cell_of(vec3 p, float r) { return ivec3(floor(p / r)); }
uint photon_bucket(vec4 a) {
    uint map = floatBitsToUint(a.w) & F_CAUSTIC;
    return bucket(cell_of(a.xyz, map != 0u ? P.r.y : P.r.x), map);
}

// ---- emission ----
// Samples a source by its cdf and a ray leaving it; phi: the photon's power. false: nothing emitted.
bool emit(out vec3 o, out vec3 d, out vec3 phi, out uint flags, out uint type, out vec3 lpos, out float range) {
    float u = rnd();
    uint n = P.seed.w, i = 0u;
    while (i + 1u < n && src[6u * i + 2u].w <= u) i++;
    vec4 a = src[6u * i], b = src[6u * i + 1u], c = src[6u * i + 2u], e = src[6u * i + 3u];
    vec4 tg = src[6u * i + 4u], f = src[6u * i + 5u];
    type = uint(a.w);
    flags = (f.y != 0.0 ? F_DIRECT : 0u) | (type < T_SKY ? F_LIGHT : 0u);
    phi = c.xyz / float(P.a.x);
    lpos = a.xyz;
    range = b.w;
    float u1 = rnd(), u2 = rnd(), u3 = rnd(), u4 = rnd();
    vec3 C = P.sphere.xyz;
    float R = P.sphere.w;
    if (type == T_DIRECTIONAL || type == T_SKY) {
        // towards the light: b (directional), or a direction of the sphere (sky); enter through the
        // disk of the scene's bounding sphere seen from there
        vec3 w = type == T_SKY ? uniform_sphere(u3, u4) : b.xyz;
        o = disk_point(C + 2.0 * R * w, w, R, u1, u2);
        d = -w;
        if (type == T_SKY && P.skyh.w != 0.0) phi *= sky_radiance(w) * e.xyz; // by direction, over the mean
        if (type == T_DIRECTIONAL && e.z > 0.0) d = cone_dir(-w, e.z, rnd(), rnd());
    } else if (type == T_POINT) {
        o = a.xyz;
        d = uniform_sphere(u1, u2);
    } else if (type == T_SPOT) {
        o = a.xyz;
        d = cone_dir(b.xyz, e.z, u1, u2);
        float sp = clamp(dot(d, b.xyz) * e.x + e.y, 0.0, 1.0);
        phi *= sp * sp;
    } else if (type == T_SPHERE) {
        vec3 nrm = uniform_sphere(u1, u2);
        o = a.xyz + nrm * e.w * (1.0 + 1e-4);
        d = cosine_dir(nrm, u3, u4);
    } else if (type == T_RECT) {
        vec3 t2 = cross(b.xyz, tg.xyz);
        o = a.xyz + (u1 - 0.5) * tg.w * tg.xyz + (u2 - 0.5) * f.x * t2;
        d = cosine_dir(b.xyz, u3, u4);
    } else { // emissive voxels: an exposed face (its neighbour cell empty) picked by its power
        // Walker's alias table (photons.c alias_table): a uniform slot of a 32-bit word (rnd() keeps 24
        // bits: too few for 2^24 faces), its face or its alias
        uint lo, slot;
        umulExtended(rnd_word(), P.cnt.x, slot, lo);
        lo = rnd() < ems[5u * slot + 1u].w ? slot : floatBitsToUint(ems[5u * slot + 2u].w);
        vec3 nrm = ems[5u * lo + 3u].xyz, rad = ems[5u * lo + 4u].xyz;
        float edge = ems[5u * lo + 3u].w;
        // the face's radiance over the luminance the pick was proportional to
        phi *= rad / max(lum(rad), 1e-30);
        o = ems[5u * lo].xyz + u1 * ems[5u * lo + 1u].xyz + u2 * ems[5u * lo + 2u].xyz + nrm * (1e-3 * edge);
        d = cosine_dir(nrm, u3, u4);
        // a face against another model's voxel still emits here (the table knows its own model's cells
        // only): a first hit at once (range < 0: its distance) kills the photon, as the path tracer never
        // sees that face
        range = -2e-3 * edge;
    }
    return phi.x > 0.0 || phi.y > 0.0 || phi.z > 0.0;
}

void store(vec3 p, vec3 wi, vec3 n, vec3 phi, uint flags, bool first) {
    if (P.tr.y != 0u) return; // counting: trace_photons writes the photon's count
    // one atomic per stored photon on one counter: the H200 takes them faster than one per subgroup
    // by ballot in this loop (22.6 against 30.6 ms for 10M photons: docs/PERFORMANCE.md)
    uint k = atomicAdd(ctr[0], 1u);
    if (k >= P.a.y) return; // over the capacity: photons.c traces the pass again with the photons that fit
    // incoming direction and normal as 2 x snorm16 octahedral codes; the flags in the normal's low
    // bits (voxel normals are axis-aligned: three bits of its u code change nothing), F_FIRST (the
    // photon's first surface, for vx_photon_power) in the direction's lowest bit (1/32767 of u)
    uint nb = (packSnorm2x16(oct_encode(n)) & ~F_BITS) | flags;
    uint wb = (packSnorm2x16(oct_encode(wi)) & ~1u) | (first ? F_FIRST : 0u);
    ph[2u * k] = vec4(p, uintBitsToFloat(nb));
    ph[2u * k + 1u] = vec4(phi, uintBitsToFloat(wb));
}

// The trace: invocation i traces photons i, i + T, i + 2T, ... (T: P.tr.x invocations), starting the
// next one as soon as its photon ends, so that the lanes of a SIMD group keep tracing while one photon
// of the group takes many bounces (path regeneration); every photon's random stream is its own
// (seeded by its index), so which invocation traces it changes nothing.
void trace_photons() {
    uint id = item(), T = P.tr.x;
    if (id >= T || id >= P.a.x) return; // (the dispatch rounds T up to whole workgroups)
    vec3 o, d, phi, lpos;
    uint flags, type;
    float range;
    bool alive = false, done = false, specular = false; // specular: the path went through glass since its last diffuse or glossy vertex
    uint stored = 0u;
    int events = 0;
    // inside glass (probes/shaders/probe.comp path()): the walk the next event runs from o along d
    bool in_glass = false;
    uint g_inst = 0u;
    uvec3 g_cell = uvec3(0u);
    float g_ior = 1.5, g_alpha = 0.0;
    for (uint guard = 0u; guard < 65536u; guard++) {
        if (!alive) {
            if (guard > 0u) {
                // counting (a pass whose stores passed the capacity): photon id's stores, two per uvec2 of Cells
                if (P.tr.y != 0u) cells[id >> 1u][id & 1u] = stored;
                id += T;
                if (id >= P.a.x) {
                    done = true;
                    break;
                }
            }
            rng_init(0x50000000u + P.seed.z, id, 0u);
            alive = emit(o, d, phi, flags, type, lpos, range);
            specular = false, stored = 0u, events = 0, in_glass = false;
            continue;
        }
        if (events >= 256 || stored > P.a.z) {
            alive = false;
            continue;
        }
        Hit h;
        bool stopped = false; // h: an opaque voxel's face met from inside glass (WALK_STOP), at o
        if (MATS && in_glass) { // (MATS: a scene without glass compiles none of this)
            vec3 p = o;
            uint w_inst;
            uvec3 w_cell;
            uint wr = glass_walk(g_inst, g_cell, g_ior, g_alpha, p, d, phi, o, h, w_inst, w_cell);
            stopped = wr == WALK_STOP;
            if (stopped) g_inst = w_inst, g_cell = w_cell; // where a bounce off the voxel walks on
            in_glass = false;
            if (wr == WALK_ABSORBED) {
                alive = false;
                continue;
            }
        }
        // one cast in the loop's body (lavapipe runs both sides of a branch, masked)
        if (!stopped && !cast_ray(o, d, BIG, h)) {
            alive = false;
            continue;
        }
        if (events++ == 0) { // (never after a walk: the glass was entered at an earlier event)
            if (range < 0.0 && h.t < -range) { // a buried voxel face
                alive = false;
                continue;
            }
            if ((type == T_POINT || type == T_SPOT) && range > 0.0) {
                // glTF's range window, as the path tracer's next-event estimation applies it
                float q = h.t / range, w = max(0.0, 1.0 - q * q * q * q);
                phi *= w * w;
            }
        }
        g_s = surface(o, d, h);
        Bsdf B = bsdf_of(g_s);
        vec3 wo = -d;
        if (B.kind == B_GLASS) {
            vec3 wi;
            bool refr;
            float w;
            alive = dielectric(g_s.n, wo, B.eta, B.alpha, wi, refr, w);
            if (!alive) continue;
            phi *= w;
            specular = true;
            if (!refr) {
                o = g_s.p;
                d = wi;
                continue;
            }
            glass_enter(h, g_s, B, wi, o, d, phi, g_inst, g_cell, g_ior, g_alpha);
            in_glass = true; // the walk runs at the next event
            continue;
        }
        // a surface that scatters: the photon is stored (caustic when only glass came before it since
        // the light, direct when it came straight from a light the direct pass shades)
        uint f = stored > 0u ? 0u : (specular ? F_CAUSTIC | (flags & F_LIGHT) : flags & F_DIRECT);
        store(g_s.p, wo, g_s.n, phi, f, stored == 0u && !specular);
        stored++;
        vec3 w;
        float pdf;
        alive = bsdf_sample(B, wo, d, w, pdf);
        if (!alive) continue;
        // Russian roulette on the throughput: survivors keep about the power they had
        float q = min(1.0, max(w.x, max(w.y, w.z)));
        alive = rnd() < q;
        phi *= w / q;
        specular = false;
        o = g_s.p;
        in_glass = stopped; // a bounce off a voxel set in glass goes back into the glass
    }
    // ctr[2]: which step's loops were cut (1 the trace, 2 the camera paths and gathers, 4 the density step), so
    // that the host's error names it
    if (!done || !loops_intact()) atomicOr(ctr[2], 1u); // photons left untraced
}

// Which photons a gather takes: every one; all but those the direct pass's light brought to their
// first surface; only photons at their first surface (and not the direct pass's); only photons at
// their first surface, the direct pass's too (a full image's direct light under a final gather).
// G_LIGHTS: at a glossy surface, whose specular lobe follows a ray (gather_pixel), the light that ray
// cannot find: global photons the direct pass's lights brought (F_DIRECT) and caustic photons from a
// light no ray meets (F_LIGHT: sun, point, spot, sphere, rect).
const int G_ALL = 0, G_INDIRECT = 1, G_FIRST = 2, G_FIRST_ANY = 3, G_LIGHTS = 4;

// Order-independent sums. The photons of a bucket lie in the order the atomic counters gave them,
// which changes from run to run; float sums in that order would too. Each photon's term is a float
// that depends on the photon alone; it is added as a 64-bit fixed-point number (hi, lo words; unit
// 1 / P.fx.x, about 2^-32 of one emitted photon's power), whose sum is exact and so the same in any
// order: the same seed gives the same image bitwise (photons.h).
// (no loop over the channels: llvmpipe's loop guard counts every iteration of a loop)
void fx_add1(inout uint hi, inout uint lo, float t, float scale) {
    float v = t * scale;
    uint carry;
    if (v > 0.0 && v < 4294967296.0) { // the common case: one word (the same value as below with h = 0)
        lo = uaddCarry(lo, uint(v), carry);
        hi += carry;
        return;
    }
    v = v > 0.0 ? min(v, 4.0e18) : 0.0; // NaN and negatives add nothing; 4e18 < 2^62: no overflow
    float h = floor(v * (1.0 / 4294967296.0)); // exact: a power of two
    lo = uaddCarry(lo, uint(v - h * 4294967296.0), carry); // v - h 2^32 is exact (< 2^32, a multiple of v's ulp)
    hi += uint(h) + carry;
}
void fx_add(inout uvec3 hi, inout uvec3 lo, vec3 t, float scale) {
    fx_add1(hi.x, lo.x, t.x, scale);
    fx_add1(hi.y, lo.y, t.y, scale);
    fx_add1(hi.z, lo.z, t.z, scale);
}
vec3 fx_value(uvec3 hi, uvec3 lo, float scale) { return (vec3(hi) * 4294967296.0 + vec3(lo)) / scale; }
// The words fx_add adds for t: fx_add(hi, lo, t, scale) is lo += w.lo (its carry into hi), hi += w.hi.
void fx_words(vec3 t, float scale, out uvec3 whi, out uvec3 wlo) {
    whi = uvec3(0u), wlo = uvec3(0u);
    fx_add(whi, wlo, t, scale); // from zero: no carry, the same words
}
void fx_add_words(inout uvec3 hi, inout uvec3 lo, uvec3 whi, uvec3 wlo) {
    uvec3 carry;
    lo = uaddCarry(lo, wlo, carry);
    hi += whi + carry;
}

// The sum over the photons of map `map` within radius r of x whose normal lies within 25 degrees of n
// (ncode: n's packed code) of power (lambert) or BSDF B towards wo times power, exact (fixed point: units
// of P.fx.y or P.fx.x). Of the 27 cells around x (cell = r) those whose box lies farther than r from x
// are skipped (on a surface about a tenth of the photons), and a bucket that two cells share is read
// once: every photon within r lies in one of the cells left, so each counts once (before, a photon
// counted only in its own cell: a floor per axis for every photon within r).
// (photon_sum_fx: photons part, part + parts, ... of each bucket alone, into the fixed-point words shi, slo:
// the density step's lanes share a pixel's photons that way)
void photon_sum_fx(vec3 x, vec3 n, uint ncode, bool lambert, Bsdf B, vec3 wo, uint map, float r, int sel, uint part,
                   uint parts, inout uvec3 shi, inout uvec3 slo) {
    float scale = lambert ? P.fx.y : P.fx.x;
    ivec3 lo = cell_of(x - r, r), hi = cell_of(x + r, r);
    float r2 = r * r;
    // a cell's box is [c r, (c + 1) r] up to the rounding of floor(p / r): grown by a margin for that
    float m = r * 1e-3 + 1e-6 * max(max(abs(x.x), abs(x.y)), abs(x.z)), rm2 = (r + m) * (r + m);
    uint seen[27];
    int nseen = 0;
    for (int cz = lo.z; cz <= hi.z; cz++) {
        float dz = max(max(float(cz) * r - x.z, x.z - float(cz + 1) * r), 0.0);
        for (int cy = lo.y; cy <= hi.y; cy++) {
            float dy = max(max(float(cy) * r - x.y, x.y - float(cy + 1) * r), 0.0);
            for (int cx = lo.x; cx <= hi.x; cx++) {
                float dx = max(max(float(cx) * r - x.x, x.x - float(cx + 1) * r), 0.0);
                if (dx * dx + dy * dy + dz * dz > rm2) continue; // no point of this cell within r
                uint bk = bucket(ivec3(cx, cy, cz), map);
                bool dup = false;
                for (int j = 0; j < nseen; j++) dup = dup || seen[j] == bk;
                if (dup || nseen >= 27) continue;
                seen[nseen++] = bk;
                uvec2 cl = cells[bk];
                for (uint k = cl.y + part; k < cl.y + cl.x; k += parts) {
                    vec4 a = sorted[k];
                    vec3 v = a.xyz - x;
                    if (dot(v, v) > r2) continue;
                    uint nb = floatBitsToUint(a.w);
                    if ((nb & F_CAUSTIC) != map) continue; // another map's photon in this bucket
                    if ((sel == G_INDIRECT || sel == G_FIRST) && (nb & F_DIRECT) != 0u) continue;
                    if (sel == G_LIGHTS && (nb & (map != 0u ? F_LIGHT : F_DIRECT)) == 0u) continue;
                    // another face (a wall's back, a step): normals within 25 degrees; the same code (a
                    // voxel face's normal, most photons) needs no decoding
                    if ((nb & ~F_BITS) != ncode && dot(oct_decode(unpackSnorm2x16(nb & ~F_BITS)), n) < 0.9) continue;
                    vec4 b = sorted[P.a.y + k]; // read only for the photons that count
                    uint wb = floatBitsToUint(b.w);
                    if ((sel == G_FIRST || sel == G_FIRST_ANY) && (wb & F_FIRST) == 0u) continue;
                    if (lambert) {
                        // f = albedo / pi for every photon: each came from the front of its own face,
                        // within 25 degrees of this one
                        fx_add(shi, slo, b.xyz, scale);
                    } else {
                        float pdf;
                        fx_add(shi, slo, bsdf_eval(B, wo, oct_decode(unpackSnorm2x16(wb)), pdf) * b.xyz, scale);
                    }
                }
            }
        }
    }
}
vec3 photon_sum(vec3 x, vec3 n, uint ncode, bool lambert, Bsdf B, vec3 wo, uint map, float r, int sel) {
    uvec3 shi = uvec3(0u), slo = uvec3(0u);
    photon_sum_fx(x, n, ncode, lambert, B, wo, map, r, sel, 0u, 1u, shi, slo);
    return fx_value(shi, slo, lambert ? P.fx.y : P.fx.x);
}

// ---- the kernel's area: the surface within r that can hold the photons a gather counts ----
// Area of {0 <= X <= x, 0 <= Y <= y} inside the disk of radius r about the origin (x, y >= 0).
float disk_quad(float x, float y, float r) {
    x = min(x, r), y = min(y, r);
    if (x * x + y * y <= r * r) return x * y;
    float x1 = sqrt(max(r * r - y * y, 0.0)); // where the circle crosses height y (x1 < x)
    return y * x1 + 0.5 * (x * sqrt(max(r * r - x * x, 0.0)) - x1 * sqrt(max(r * r - x1 * x1, 0.0)) +
                           r * r * (asin(min(x / r, 1.0)) - asin(min(x1 / r, 1.0))));
}
float disk_corner(float x, float y, float r) { return sign(x) * sign(y) * disk_quad(abs(x), abs(y), r); }
// Area of the unit square [q, q + 1] inside the disk of radius r about c.
float disk_square(vec2 c, vec2 q, float r) {
    vec2 lo = q - c, hi = q + 1.0 - c;
    return disk_corner(hi.x, hi.y, r) - disk_corner(lo.x, hi.y, r) - disk_corner(hi.x, lo.y, r) + disk_corner(lo.x, lo.y, r);
}
// Whether cell q of model mi is set: a bit where the model has its occupancy bits (one load), else a walk
// down its octree (model_cell_attr: some 6 dependent loads at 64^3; kernel_factors makes about 66 lookups
// a pixel at the seed's Cornell setting, which cost 1 of its 7.2 ms as walks)
// (and its leaf's level: 0 from the bits, which keep cells)
bool photon_glass_cell(uint mi, uvec3 c, out uint level) {
    level = 0u;
    uint base = occ[mi];
    if (base == 0xFFFFFFFFu) return is_glass(model_cell_leaf(mi, c, level));
    uint s = 1u << model_at(mi).depth, i = c.x + s * (c.y + s * c.z);
    return ((occ[base + (s * s * s + 31u) / 32u + (i >> 5u)] >> (i & 31u)) & 1u) != 0u;
}
bool cell_solid(uint mi, ivec3 q, float side) {
    if (!all(greaterThanEqual(q, ivec3(0))) || !all(lessThan(vec3(q), vec3(side)))) return false;
    uint base = occ[mi];
    if (base == 0xFFFFFFFFu) return model_cell_attr(mi, uvec3(q)) != NO_HIT;
    uint s = uint(side), i = uint(q.x) + s * (uint(q.y) + s * uint(q.z));
    return ((occ[base + (i >> 5u)] >> (i & 31u)) & 1u) != 0u;
}

// The photons a gather at g_s counts lie within r of it on faces of its orientation, and the estimate
// divides their power by the area they can lie on. Dividing by the disk pi r^2 assumed an unbroken
// plane: where the surface ends within r (a floor's edge, a wall's foot, a strip one voxel high) the
// disk's part beyond it holds no photons, and that light was lost (the caustic scene's floor kept 0.978
// of its photons' power at radius 1.1, 0.989 at 0.55: its 1.1% deficit against the path tracer). This
// is the area of the faces of g_s's orientation within r (the model's cells around the hit: per column
// of cells whose unit square meets the disk, the nearest face of that orientation within r above or
// below the hit's plane, its square's part of the disk at that height), over pi r^2: a factor 1 (exactly)
// on an unbroken plane, above 1 near an edge. For the global (x) and caustic (y) radii. Cells outside the
// hit's model are looked for in the others by a short ray (face_elsewhere) where the scene has more than one
// instance, and count as empty otherwise. Left at 1
// (the plain disk) where the model has no attributes (no cell lookups) or the radius passes KERNEL_CELLS
// cells (the columns grow as its square: 13^2 at 6).
const float KERNEL_CELLS = 6.0;
// With more than one instance (P.tr.w), a column whose cells are empty in the hit's model may hold another
// model's face in the hit's plane (two models side by side make one floor): a short ray down the normal
// onto the column's square finds it (a face of this orientation half a cell below the ray's start).
bool face_elsewhere(Inst I, Hit h, ivec3 q, int ax, int e) {
    vec3 m = vec3(q) + 0.5;
    m[ax] = float(q[ax]) + (e > 0 ? 1.0 : 0.0) + 0.5 * float(e); // half a cell off the plane, on its open side
    m -= vec3(I.r0.w, I.r1.w, I.r2.w);
    vec3 w = I.cell * I.cell * (m.x * I.r0.xyz + m.y * I.r1.xyz + m.z * I.r2.xyz); // model to world (rows: R / cell)
    Hit g;
    if (!cast_ray(w, -g_s.n, I.cell, g)) return false;
    Inst J = insts[g.inst];
    vec4 row = g.axis == 0 ? J.r0 : (g.axis == 1 ? J.r1 : J.r2);
    return abs(float(g.t) - 0.5 * I.cell) < 0.25 * I.cell && dot(normalize(row.xyz * g.nsign), g_s.n) > 0.9;
}
vec2 kernel_factors(Hit h) {
    Inst I = insts[h.inst];
    uint mi = I.model;
    if (!HAS_COLOR || (model_at(mi).flags & 1u) == 0u || max(P.r.x, P.r.y) > KERNEL_CELLS * I.cell) return vec2(1.0);
    float side = exp2(float(model_at(mi).depth));
    vec3 p = g_s.p;
    vec3 om = vec3(dot(I.r0.xyz, p) + I.r0.w, dot(I.r1.xyz, p) + I.r1.w, dot(I.r2.xyz, p) + I.r2.w);
    int ax = h.axis, u = (ax + 1) % 3, v = (ax + 2) % 3;
    ivec3 e = ivec3(0);
    e[ax] = h.nsign > 0.0 ? 1 : -1;
    vec2 rm = vec2(P.r.x, P.r.y) / I.cell, rm2 = rm * rm;
    float R = max(rm.x, rm.y);
    vec2 c = vec2(om[u], om[v]), missing = vec2(0.0), extra = vec2(0.0);
    ivec3 base = ivec3(h.cell);
    for (int iu = int(floor(c.x - R)); iu <= int(floor(c.x + R)); iu++) {
        float du = max(max(float(iu) - c.x, c.x - float(iu + 1)), 0.0);
        for (int iv = int(floor(c.y - R)); iv <= int(floor(c.y + R)); iv++) {
            float dv = max(max(float(iv) - c.y, c.y - float(iv + 1)), 0.0);
            float d2 = du * du + dv * dv;
            if (d2 >= R * R) continue; // the square lies outside both disks
            ivec3 q = base;
            q[u] = iu, q[v] = iv;
            bool s0 = cell_solid(mi, q, side), s1 = cell_solid(mi, q + e, side);
            if (s0 && !s1) continue; // a face in the hit's plane: part of pi r^2
            if (P.tr.w != 0u && !s0 && !s1 && face_elsewhere(I, h, q, ax, e[ax])) continue; // another model's
            vec2 sq = vec2(float(iu), float(iv));
            for (int k = 0; k < 2; k++)
                if (d2 < rm2[k]) missing[k] += disk_square(c, sq, rm[k]);
            // the nearest face of this orientation above (the plane's cell solid, the face buried) or below
            int dz = 0;
            for (int step = 1; float(step) < R; step++) {
                if (s0 ? !cell_solid(mi, q + (step + 1) * e, side) : cell_solid(mi, q - step * e, side)) {
                    dz = step;
                    break;
                }
            }
            for (int k = 0; k < 2 && dz > 0; k++) {
                float rz2 = rm2[k] - float(dz * dz);
                if (rz2 > d2) extra[k] += disk_square(c, sq, sqrt(rz2));
            }
        }
    }
    vec2 full = PI * rm2, area = full - missing + extra;
    return vec2(missing.x == 0.0 && extra.x == 0.0 ? 1.0 : full.x / max(area.x, 1e-3 * full.x),
                missing.y == 0.0 && extra.y == 0.0 ? 1.0 : full.y / max(area.y, 1e-3 * full.y));
}

// Radiance leaving the surface g_s towards wo from the photons of map `map` within radius r (norm:
// 1 / (pi r^2)). A Lambert surface's BSDF is the same for every photon in front of it: the photons'
// powers are summed and multiplied by albedo / pi once, with no BSDF per photon.
vec3 gather(Bsdf B, vec3 wo, uint map, float r, float norm, int sel) {
    bool lambert = B.kind == B_LAMBERT;
    if (lambert && dot(wo, B.n) <= 0.0) return vec3(0.0); // bsdf_eval's wo.z <= 0
    uint ncode = packSnorm2x16(oct_encode(g_s.n)) & ~F_BITS;
    vec3 sum = photon_sum(g_s.p, g_s.n, ncode, lambert, B, wo, map, r, sel) * norm;
    return lambert ? sum * (B.alb / PI) : sum;
}

// Final gather: the light at the camera's first surface g_s that bounced at least once, from `rays`
// BSDF-sampled rays, each ending at the next surface that is not glass with the whole photon estimate
// there (both maps, direct photons too; glass on the way is followed by Fresnel choice, as the camera's
// path is). Light straight from the sky and emissive voxels is the first surface's photons' (G_FIRST),
// and through glass its caustic photons': rays that had to find a small bright emitter would be noisy,
// so a ray that leaves the scene or meets an emitter adds nothing of it. (A ray that met glass ended
// here before, and the light of the walls seen through glass was lost: cornell's final gather came out
// 4.6% dark.)
vec3 final_gather(Bsdf B, vec3 wo, uint rays) {
    Surf s0 = g_s;
    vec3 sum = vec3(0.0);
    for (uint i = 0u; i < rays; i++) {
        vec3 d, thr;
        float pdf;
        if (!bsdf_sample(B, wo, d, thr, pdf)) continue;
        vec3 o = s0.p;
        bool in_glass = false, stopped = false;
        uint g_inst = 0u;
        uvec3 g_cell = uvec3(0u);
        float g_ior = 1.5, g_alpha = 0.0;
        for (int events = 0; events < 32; events++) {
            Hit h;
            stopped = false;
            if (MATS && in_glass) { // the walk through the glass entered below; it may end on an opaque voxel in it
                vec3 p = o;
                uint w_inst;
                uvec3 w_cell;
                uint wr = glass_walk(g_inst, g_cell, g_ior, g_alpha, p, d, thr, o, h, w_inst, w_cell);
                in_glass = false;
                stopped = wr == WALK_STOP;
                if (stopped) g_inst = w_inst, g_cell = w_cell; // where a bounce off the voxel walks on
                if (wr == WALK_ABSORBED) break;
            }
            if (!stopped && !cast_ray(o, d, BIG, h)) break; // (one cast in the loop's body)
            g_s = surface(o, d, h);
            Bsdf B2 = bsdf_of(g_s);
            if (B2.kind != B_GLASS) {
                // (a face met from inside glass: no kernel correction, its neighbours are glass)
                vec2 kf = stopped ? vec2(1.0) : kernel_factors(h);
                sum += thr * (gather(B2, -d, 0u, P.r.x, P.r.z * kf.x, G_ALL) +
                              gather(B2, -d, F_CAUSTIC, P.r.y, P.r.w * kf.y, G_ALL));
                break;
            }
            vec3 wi;
            bool refr;
            float w;
            if (!dielectric(g_s.n, -d, B2.eta, B2.alpha, wi, refr, w)) break;
            thr *= w;
            if (!refr) {
                o = g_s.p;
                d = wi;
                continue;
            }
            glass_enter(h, g_s, B2, wi, o, d, thr, g_inst, g_cell, g_ior, g_alpha);
            in_glass = true;
        }
    }
    g_s = s0;
    return sum / float(rays);
}

// The specular lobe of glossy B alone (S.kd = 0): a direction by the GGX visible normals, weight
// f cos / pdf = F G2 / G1. false: no direction (below the surface).
bool specular_sample(Bsdf S, vec3 wo_w, out vec3 wi_w, out vec3 w) {
    vec3 wo = to_local(S, wo_w);
    float u1 = rnd(), u2 = rnd();
    w = vec3(0.0);
    wi_w = S.n;
    if (wo.z <= 0.0) return false;
    vec3 m = ggx_vndf(S.alpha, wo, u1, u2);
    vec3 wi = 2.0 * dot(wo, m) * m - wo;
    if (wi.z <= 0.0) return false;
    wi_w = normalize(wi.x * S.t + wi.y * S.b + wi.z * S.n);
    float lo = ggx_lambda(S.a2, wo.z), li = ggx_lambda(S.a2, wi.z), s5 = pow(clamp(1.0 - dot(wi, m), 0.0, 1.0), 5.0);
    w = (S.f0 + (1.0 - S.f0) * s5) * ((1.0 + lo) / (1.0 + lo + li));
    return dot(wi_w, S.n) > 0.0;
}

void gather_pixel() {
    // a workgroup of 64 takes a tile of 8 x 8 pixels: their gathers read the same cells
    uint it = item(), W = P.img.x, H = P.img.y, tiles_x = (W + 7u) / 8u, t = it / 64u, l = it % 64u;
    uint x = (t % tiles_x) * 8u + l % 8u, y = (t / tiles_x) * 8u + l / 8u;
    if (x >= W || y >= H) return;
    uint idx = x + y * W;
    rng_init(0x60000000u + P.seed.z, x, y);
    bool ortho = F.rx.w != 0.0;
    float u = ((float(x) + 0.5) / float(W)) * 2.0 - 1.0, v = 1.0 - ((float(y) + 0.5) / float(H)) * 2.0;
    vec3 o, d;
    if (ortho) {
        o = u * F.rx.xyz + v * F.uy.xyz;
        d = F.fwd.xyz;
    } else {
        d = normalize(F.fwd.xyz + u * F.rx.xyz + v * F.uy.xyz);
        o = F.fwd.w * (u * F.rx.xyz + v * F.uy.xyz);
    }
    bool full = P.img.w != 0u;
    vec3 thr = vec3(1.0), L = vec3(0.0);
    bool after_glossy = false;
    // the density step's record: the point, its normal's code with (deferred, sel) in its low bits, the
    // factor of the sums (throughput times albedo / pi), the light found here
    vec4 rec0 = vec4(0.0), rec1 = vec4(0.0);
    float rec2w = 0.0; // the caustic radius' kernel factor (rec1.w the global one's)
    bool in_glass = false, stopped = false;
    uint g_inst = 0u;
    uvec3 g_cell = uvec3(0u);
    float g_ior = 1.5, g_alpha = 0.0;
    for (int events = 0; events < 64; events++) {
        Hit h;
        stopped = false;
        if (MATS && in_glass) { // the walk through the glass entered below; it may end on an opaque voxel in it
            vec3 p = o;
            uint w_inst;
            uvec3 w_cell;
            uint wr = glass_walk(g_inst, g_cell, g_ior, g_alpha, p, d, thr, o, h, w_inst, w_cell);
            in_glass = false;
            stopped = wr == WALK_STOP;
            if (stopped) g_inst = w_inst, g_cell = w_cell; // where a bounce off the voxel walks on
            if (wr == WALK_ABSORBED) break;
        }
        if (!stopped && !cast_ray(o, d, BIG, h)) {
            if (events > 0 || full) L += thr * sky_radiance(d);
            break;
        }
        g_s = surface(o, d, h);
        // the pass pipeline's direct pass adds the first surface's emission and direct light; behind
        // glass the estimate has to give all of it
        bool first = events == 0;
        // after a glossy surface an emissive voxel's light came from its photons (G_LIGHTS) when a
        // light stands for the voxels (their photons are F_DIRECT)
        if ((!first || full) && !(after_glossy && P.cnt.w != 0u)) L += thr * g_s.emit;
        after_glossy = false;
        Bsdf B = bsdf_of(g_s);
        vec3 wo = -d;
        if (B.kind == B_GLASS) {
            vec3 wi;
            bool refr;
            float w;
            if (!dielectric(g_s.n, wo, B.eta, B.alpha, wi, refr, w)) break;
            thr *= w;
            if (!refr) {
                o = g_s.p;
                d = wi;
                continue;
            }
            glass_enter(h, g_s, B, wi, o, d, thr, g_inst, g_cell, g_ior, g_alpha);
            in_glass = true; // the walk runs at the next event
            continue;
        }
        int sel = !first || full ? G_ALL : G_INDIRECT;
        // (a face met from inside glass: no kernel correction, its neighbours are glass)
        vec2 kf = stopped ? vec2(1.0) : kernel_factors(h);
        if (B.kind == B_GLOSSY) {
            // A glossy surface (as Jensen's photon mapping treats it): the diffuse lobe from the photons,
            // the specular lobe by a ray. The photon estimate divides by the disk pi r^2 but finds only
            // the photons on facets of the surface's orientation, which on a curved voxel surface (a
            // staircase of faces) cover part of that disk: cornell's metal sphere came out 40% dark, and
            // its sharp lobe met few photons (noise). The ray sees emitters and the sky itself; the light
            // of the lights it cannot meet comes from photons here (G_LIGHTS), the direct pass's lights
            // at the camera's first surface excepted (the direct pass shades them).
            Bsdf D = B, S = B;
            D.kind = B_LAMBERT;
            D.alb = B.kd;
            S.kd = vec3(0.0);
            if (B.kd != vec3(0.0))
                L += thr * (gather(D, wo, F_CAUSTIC, P.r.y, P.r.w * kf.y, sel) + gather(D, wo, 0u, P.r.x, P.r.z * kf.x, sel));
            // (each only where the sources can bring such photons: a sum over none is 0; at the seed's
            // Cornell setting, lit by voxels alone, these loops went over the caustic on the metal sphere,
            // every photon rejected: docs/PERFORMANCE.md)
            if ((P.tr.z & 1u) != 0u) L += thr * gather(S, wo, F_CAUSTIC, P.r.y, P.r.w * kf.y, G_LIGHTS);
            if ((!first || full) && (P.tr.z & 2u) != 0u) L += thr * gather(S, wo, 0u, P.r.x, P.r.z * kf.x, G_LIGHTS);
            vec3 w;
            if (!specular_sample(S, wo, d, w)) break;
            thr *= w;
            o = g_s.p;
            after_glossy = true;
            in_glass = stopped; // off a voxel set in glass, back into the glass
            continue;
        }
        // the final gather at the camera's first surface; in a full image the light that came straight
        // from a source (the direct pass's too) is that surface's first-surface photons
        if (first && P.cnt.z > 0u) {
            L += gather(B, wo, F_CAUSTIC, P.r.y, P.r.w * kf.y, sel) + gather(B, wo, 0u, P.r.x, P.r.z * kf.x, full ? G_FIRST_ANY : G_FIRST) +
                 final_gather(B, wo, P.cnt.z);
        } else if (B.kind == B_LAMBERT) {
            // both maps' sums in the density step
            if (dot(wo, B.n) > 0.0) {
                uint ncode = packSnorm2x16(oct_encode(g_s.n)) & ~F_BITS;
                rec0 = vec4(g_s.p, uintBitsToFloat(ncode | 1u | (sel == G_INDIRECT ? 2u : 0u)));
                rec1 = vec4(thr * (B.alb / PI), kf.x);
                rec2w = kf.y;
            }
        } else {
            L += thr * (gather(B, wo, F_CAUSTIC, P.r.y, P.r.w * kf.y, sel) + gather(B, wo, 0u, P.r.x, P.r.z * kf.x, sel));
        }
        break;
    }
    if (!loops_intact()) {
        atomicOr(ctr[2], 2u);
        return;
    }
    uint ri = P.fu.x + 3u * idx;
    ph[ri] = rec0;
    ph[ri + 1u] = rec1;
    ph[ri + 2u] = vec4(L, rec2w);
}

// ---- the density step: a workgroup takes a tile of 8 x 8 pixels, DPARTS lanes a pixel ----
// A pixel's sums may be shared by DPARTS lanes (the workgroup's size over 64: photons.c density_parts),
// each testing its part of the photons, their fixed-point sums added at the end (exact: the same value in
// any split). At the seed's Cornell setting the step is one wave of 4096 tiles whose time the tiles on the
// densest photons set (the ceiling by the light, the caustic): 4 lanes a pixel give each such tile 4
// times the lanes (H200: 3.33 -> 1.91 ms); where the tiles fill several waves they cost more than they
// give (1920x1080: 1.39 -> 2.78 ms on the caustic scene), and photons.c takes 1 (docs/PERFORMANCE.md).
const uint DLANES = gl_WorkGroupSize.x, DPARTS = DLANES / 64u;
// Sized by TLANES: the density step's workgroup there, 1 in the other steps. The whole
// shader declares these arrays: at 256 lanes in every step (14 KB a workgroup of 64) they halved the trace's
// occupancy (H200, the seed's setting: 8.8 against 3.3 ms); sized by each step's workgroup (56 bytes a lane)
// they still took shared memory, and with it L1 cache, from the trace's octree walks.
const uint TLANES = STEP == S_DENSITY ? gl_WorkGroupSize.x : 1u;
// a chunk of photons: the first halves, and the power as the words fx_add1 adds (the low words in t_b,
// the high ones in t_shi, free until parts_add), made once a photon where every pixel made them again
shared vec4 t_a[TLANES];
shared uvec4 t_b[TLANES];
// the tile's box of cells: a bit each (at most NEEDW * 32 cells), a slot each where they are at most SLOTS,
// else a slot each of the cells the pixels need (at most SLOTS, listed in t_cell by the bits). BIGBOX: only
// where a pixel has several lanes (few tiles: the step's time is its slowest tiles'); with one lane a pixel
// (1920x1080, many waves of tiles) the boxes of 5 a side and the arrays as before (the caustic scene's 10M
// pass, H200: density 1.36 ms with the big boxes and the order below, 1.33 without them, main's 1.17).
// The slot arrays are declared at full size in every step, as they always were: sized to the density step
// alone (1 element elsewhere) the trace with the camera's paths beside it took 3.32 ms against 3.20 (seed's
// setting, H200), and with 2.5 KB more in every step 3.90: the trace's speed follows its pipelines' shared
// memory (the driver's split of it against L1), not in one direction (docs/PERFORMANCE.md, ninth sitting).
const uint SLOTS = 128u;
const uint BIGW = STEP == S_DENSITY ? gl_WorkGroupSize.x : 0u; // (glslang 11 emits `&&` of spec constants out of order)
const bool BIGBOX = BIGW > 64u;
const uint NEEDW = BIGW > 64u ? 32u : SLOTS / 32u, LISTS = BIGW > 64u ? SLOTS : 1u;
shared uint t_bk[SLOTS], t_start[SLOTS], t_cnt[SLOTS], t_pre[SLOTS + 1u], t_need[NEEDW], t_g8[SLOTS / 8u], t_n[2], t_big[2];
// t_wpre rounded up: LISTS / 4 is 0 outside BIGBOX, an array of length 0 (invalid SPIR-V once specialised:
// the validation layer refused every photon pipeline, VUID-VkPipelineShaderStageCreateInfo-pSpecializationInfo-06719)
shared uint t_cell[LISTS], t_wpre[(LISTS + 3u) / 4u]; // (NEEDW where BIGBOX)
shared int t_lo[3], t_hi[3];
shared uint t_blo[3], t_bhi[3]; // the tile's points' box (fkey: floats as ordered uints)
// the tile's pixels' normal codes (least, greatest), their selections (bit 0 G_INDIRECT, bit 1 G_ALL) and
// the normal of the least code as its pixels decoded it
shared uint t_cmin, t_cmax, t_sel;
shared vec3 t_nrm;
shared uvec3 t_shi[TLANES], t_slo[TLANES]; // the parts' sums (t_shi: also the chunk's)

// The Lambert sums (photon_sum's, exact) of the tile's pixels over map `map` within r, this lane's part
// added into shi, slo: the cells the pixels need (each pixel's own cells that pass photon_sum's box test)
// are gathered into one list of buckets (a bucket two cells share once), its photons read into shared
// memory in chunks of DLANES, and every pixel tests every photon of a chunk, each of its lanes a part. A
// pixel's own loop read its cells' photons from memory, each pixel again: at the seed's Cornell setting
// some 2700 tests for the 1000 photons that count. The tile's box of cells takes up to NEEDW * 32 cells
// (a tile across a depth step or seen at a grazing angle: the seed's floor and the spheres' edges, 7% of
// its tiles past the 5 a side the box had before, and 15% of the caustic map's, whose cells are a quarter
// as wide), of which the pixels may need at most SLOTS; a tile past either falls back to the own loops
// (the pixel's lanes taking every DPARTS-th photon).
uint fkey(float f) { // ordered as the floats are
    uint u = floatBitsToUint(f);
    return (u & 0x80000000u) != 0u ? ~u : u | 0x80000000u;
}
float fkey_inv(uint u) { return uintBitsToFloat((u & 0x80000000u) != 0u ? u & 0x7FFFFFFFu : ~u); }
void tile_sum(bool valid, vec3 x, vec3 n, uint ncode, uint map, float r, int sel, inout uvec3 shi, inout uvec3 slo) {
    uint lid = gl_LocalInvocationIndex, part = lid / 64u;
    if (lid < NEEDW) t_need[lid] = 0u;
    if (lid == 0u) {
        for (int k = 0; k < 3; k++) t_lo[k] = 0x7FFFFFFF, t_hi[k] = -0x7FFFFFFF, t_blo[k] = 0xFFFFFFFFu, t_bhi[k] = 0u;
        t_n[0] = 0u, t_n[1] = 0u, t_big[0] = 0u, t_big[1] = 0u;
        t_cmin = 0xFFFFFFFFu, t_cmax = 0u, t_sel = 0u;
    }
    barrier();
    ivec3 lo = cell_of(x - r, r), hi = cell_of(x + r, r);
    if (valid && part == 0u) {
        for (int k = 0; k < 3; k++) {
            atomicMin(t_lo[k], lo[k]), atomicMax(t_hi[k], hi[k]);
            atomicMin(t_blo[k], fkey(x[k])), atomicMax(t_bhi[k], fkey(x[k]));
        }
        atomicMin(t_cmin, ncode), atomicMax(t_cmax, ncode), atomicOr(t_sel, sel == G_INDIRECT ? 1u : 2u);
    }
    barrier();
    if (valid && part == 0u && ncode == t_cmin) t_nrm = n; // every such pixel decoded the same code the same way
    ivec3 ulo = ivec3(t_lo[0], t_lo[1], t_lo[2]), ext = ivec3(t_hi[0], t_hi[1], t_hi[2]) - ulo + 1;
    // Where every pixel of the tile has one normal code and one selection (a wall's tile: most), the tests
    // that depend on the photon alone, the normal's and the direct photons', are made once a photon when
    // the chunk is loaded (the same comparisons as each pixel's, on the same values), and the pixels' loop
    // tests the distance alone
    uint code = t_cmin, tsel = t_sel;
    bool uni = code == t_cmax && tsel != 3u;
    barrier(); // all have read the bounds: the next call's first lane may set them again
    if (ext.x <= 0) return; // no pixel of the tile needs a sum
    Bsdf B;                 // unused by the Lambert sums
    const int NBOX = int(NEEDW * 32u);
    if (BIGBOX ? (ext.x > NBOX || ext.y > NBOX || ext.z > NBOX || ext.x * ext.y * ext.z > NBOX) // (no overflow: the first three)
               : (ext.x > 5 || ext.y > 5 || ext.z > 5)) {
        if (valid) photon_sum_fx(x, n, ncode, true, B, vec3(0.0), map, r, sel, part, DPARTS, shi, slo);
        return;
    }
    int nc = ext.x * ext.y * ext.z;
    bool listed = BIGBOX && nc > int(SLOTS); // a slot each of the needed cells (else of every cell of the box)
    float m = r * 1e-3 + 1e-6 * max(max(abs(x.x), abs(x.y)), abs(x.z)), rm2 = (r + m) * (r + m), r2 = r * r;
    if (valid && part == 0u)
        for (int cz = lo.z; cz <= hi.z; cz++)
            for (int cy = lo.y; cy <= hi.y; cy++)
                for (int cx = lo.x; cx <= hi.x; cx++) {
                    float dz = max(max(float(cz) * r - x.z, x.z - float(cz + 1) * r), 0.0);
                    float dy = max(max(float(cy) * r - x.y, x.y - float(cy + 1) * r), 0.0);
                    float dx = max(max(float(cx) * r - x.x, x.x - float(cx + 1) * r), 0.0);
                    if (dx * dx + dy * dy + dz * dz > rm2) continue;
                    uint ci = uint((cx - ulo.x) + ext.x * ((cy - ulo.y) + ext.y * (cz - ulo.z)));
                    atomicOr(t_need[ci >> 5], 1u << (ci & 31u));
                }
    barrier();
    uint nlist = 0u;
    if (listed) {
        // the needed cells in the box's order: a word's first slot from the bits of the words before it, a
        // cell's from the bits before it in its word
        if (lid < NEEDW) {
            uint c = 0u;
            for (uint j = 0u; j < lid; j++) c += uint(bitCount(t_need[j]));
            t_wpre[lid] = c;
        }
        barrier();
        nlist = t_wpre[NEEDW - 1u] + uint(bitCount(t_need[NEEDW - 1u]));
        if (nlist > SLOTS) { // (uniform: every lane read the same words; the barrier: all have read them)
            barrier();
            if (valid) photon_sum_fx(x, n, ncode, true, B, vec3(0.0), map, r, sel, part, DPARTS, shi, slo);
            return;
        }
        for (uint i = lid; i < uint(nc); i += DLANES) {
            uint w = t_need[i >> 5], b = 1u << (i & 31u);
            if ((w & b) != 0u) t_cell[t_wpre[i >> 5] + uint(bitCount(w & (b - 1u)))] = i;
        }
        barrier();
    }
    // slot sl: cell sl of the tile's box (or the list's sl-th), its bucket once
    for (uint sl = lid; sl < SLOTS; sl += DLANES) {
        uint bk = 0xFFFFFFFFu;
        int il = listed ? (sl < nlist ? int(t_cell[sl]) : -1) : int(sl);
        if (listed ? il >= 0 : (il < nc && (t_need[sl >> 5] & (1u << (sl & 31u))) != 0u))
            bk = bucket(ulo + ivec3(il % ext.x, (il / ext.x) % ext.y, il / (ext.x * ext.y)), map);
        t_bk[sl] = bk;
    }
    barrier();
    for (uint sl = lid; sl < SLOTS; sl += DLANES) {
        uint bk = t_bk[sl], cnt = 0u, st = 0u;
        if (bk != 0xFFFFFFFFu) {
            bool dup = false;
            for (uint j = 0u; j < sl && !dup; j++) dup = t_bk[j] == bk;
            if (!dup) {
                uvec2 cl = cells[bk];
                cnt = cl.x, st = cl.y;
            }
        }
        t_start[sl] = st;
        t_cnt[sl] = cnt;
    }
    barrier();
    // the slots' starts in the list, in two steps (one lane's chain of 64 dependent adds held the workgroup
    // twice a tile): 16 lanes sum 8 slots' counts each, then a slot's start is the sums of the groups before
    // it and the counts before it in its own (at most 15 + 7 adds)
    if (lid < SLOTS / 8u) {
        uint s8 = 0u;
        for (uint j = 0u; j < 8u; j++) s8 += t_cnt[8u * lid + j];
        t_g8[lid] = s8;
    }
    barrier();
    for (uint sl = lid; sl <= SLOTS; sl += DLANES) {
        uint sum = 0u, g = sl / 8u;
        for (uint j = 0u; j < g; j++) sum += t_g8[j];
        for (uint j = 8u * g; j < sl; j++) sum += t_cnt[j];
        t_pre[sl] = sum;
    }
    barrier();
    uint total = t_pre[SLOTS];
    // The chunk keeps only the photons within r of the tile's points' box (grown by m: every photon the
    // test below takes lies in it), compacted in any order (the sums are exact: the same in any order):
    // the cells the tile reads span some 3 radii a side on a plane, the box about 2 plus the tile's width
    // (one box for all lanes: its margin from the box, as m is from the point)
    vec3 blo = vec3(fkey_inv(t_blo[0]), fkey_inv(t_blo[1]), fkey_inv(t_blo[2]));
    vec3 bhi = vec3(fkey_inv(t_bhi[0]), fkey_inv(t_bhi[1]), fkey_inv(t_bhi[2]));
    vec3 bm = max(abs(blo), abs(bhi));
    float mb = r * 1e-3 + 1e-6 * max(max(bm.x, bm.y), bm.z);
    blo -= r + mb, bhi += r + mb;
    uint chunk = 0u;
    for (uint off = 0u; off < total; off += DLANES, chunk ^= 1u) {
        uint g = off + lid;
        if (g < total) { // photon g of the list: in the slot a with t_pre[a] <= g < t_pre[a + 1]
            uint a = 0u, b = SLOTS;
            while (b - a > 1u) {
                uint h = (a + b) / 2u;
                if (t_pre[h] <= g) a = h;
                else b = h;
            }
            uint k = t_start[a] + (g - t_pre[a]);
            vec4 pa = sorted[k];
            // (another map's photon in these buckets counts for no pixel: left out here)
            uint nb = floatBitsToUint(pa.w);
            bool keep = all(greaterThanEqual(pa.xyz, blo)) && all(lessThanEqual(pa.xyz, bhi)) && (nb & F_CAUSTIC) == map;
            if (keep && uni) {
                if (tsel == 1u && (nb & F_DIRECT) != 0u) keep = false;
                if ((nb & ~F_BITS) != code && dot(oct_decode(unpackSnorm2x16(nb & ~F_BITS)), t_nrm) < 0.9) keep = false;
            }
            if (keep) {
                uint slot = atomicAdd(t_n[chunk], 1u);
                uvec3 whi, wlo;
                fx_words(sorted[P.a.y + k].xyz, P.fx.y, whi, wlo);
                // (where the tests are the distance's alone, the low words ride in the position's fourth:
                // two reads a photon; the high words, 0 but for a photon of over 32 emitted photons' power,
                // are read only in a chunk that has some)
                t_a[slot] = uni ? vec4(pa.xyz, uintBitsToFloat(wlo.x)) : pa;
                t_b[slot] = uni ? uvec4(wlo.yz, 0u, 0u) : uvec4(wlo, 0u);
                t_shi[slot] = whi;
                if (whi != uvec3(0u)) atomicOr(t_big[chunk], 1u);
            }
        }
        barrier();
        uint cn = t_n[chunk];
        if (valid && uni) {
            uint q = (cn + DPARTS - 1u) / DPARTS, j1 = min((part + 1u) * q, cn);
            bool big = t_big[chunk] != 0u;
            for (uint j = part * q; j < j1; j++) {
                vec4 pa = t_a[j];
                vec3 v = pa.xyz - x;
                if (dot(v, v) <= r2) fx_add_words(shi, slo, big ? t_shi[j] : uvec3(0u), uvec3(floatBitsToUint(pa.w), t_b[j].xy));
            }
        } else if (valid) { // this lane's part of the chunk (a SIMD group's lanes share a part: one read for all)
            uint q = (cn + DPARTS - 1u) / DPARTS, j1 = min((part + 1u) * q, cn);
            for (uint j = part * q; j < j1; j++) {
                vec4 pa = t_a[j];
                vec3 v = pa.xyz - x;
                if (dot(v, v) > r2) continue;
                uint nb = floatBitsToUint(pa.w);
                if (sel == G_INDIRECT && (nb & F_DIRECT) != 0u) continue;
                if ((nb & ~F_BITS) != ncode && dot(oct_decode(unpackSnorm2x16(nb & ~F_BITS)), n) < 0.9) continue;
                fx_add_words(shi, slo, t_shi[j], t_b[j].xyz);
            }
        }
        barrier();
        if (lid == 0u) t_n[chunk] = 0u, t_big[chunk] = 0u; // read by all before the barrier above; next filled two chunks on
    }
}

// The parts' sums of a pixel, added exactly into part 0's lanes (every lane takes part: barriers).
void parts_add(inout uvec3 shi, inout uvec3 slo) {
    uint lid = gl_LocalInvocationIndex;
    t_shi[lid] = shi, t_slo[lid] = slo;
    barrier();
    if (lid < 64u)
        for (uint q = 1u; q < DPARTS; q++) {
            uvec3 carry;
            slo = uaddCarry(slo, t_slo[lid + 64u * q], carry);
            shi += t_shi[lid + 64u * q] + carry;
        }
    barrier();
}

// The density step: a record's sums over both maps (the same tiles of 8 x 8 pixels as gather_pixel), the
// pixel's light written into Out. Every invocation of the workgroup runs tile_sum (its barriers).
void density_pixel() {
    uint it = item(), W = P.img.x, H = P.img.y, tiles_x = (W + 7u) / 8u, t = it / DLANES, l = (it % DLANES) % 64u;
    // several lanes a pixel (few tiles): the tiles from the last row up. The GPU starts workgroups about in
    // their order, and a step of one or two waves ends with its slowest tiles; at the seed's Cornell setting
    // the heavy ones (the floor under the light, its far edge, the caustic: big boxes, dense photons) lie low
    // in the image (H200: density 1.47 -> 1.25 ms; in the order of an estimate of each tile's photons, heaviest
    // first, 1.40: docs/PERFORMANCE.md)
    if (DPARTS > 1u && t < P.fu.z) t = P.fu.z - 1u - t;
    uint x = (t % tiles_x) * 8u + l % 8u, y = (t / tiles_x) * 8u + l / 8u;
    bool inside = x < W && y < H;
    uint idx = inside ? x + y * W : 0u;
    uint ri = P.fu.x + 3u * idx;
    vec4 rec0 = inside ? ph[ri] : vec4(0.0);
    uint bits = floatBitsToUint(rec0.w), ncode = bits & ~F_BITS;
    bool valid = inside && (bits & 1u) != 0u;
    int sel = (bits & 2u) != 0u ? G_INDIRECT : G_ALL;
    vec3 n = oct_decode(unpackSnorm2x16(ncode));
    uvec3 chi = uvec3(0u), clo = uvec3(0u), ghi = uvec3(0u), glo = uvec3(0u);
    tile_sum(valid, rec0.xyz, n, ncode, F_CAUSTIC, P.r.y, sel, chi, clo);
    tile_sum(valid, rec0.xyz, n, ncode, 0u, P.r.x, sel, ghi, glo);
    parts_add(chi, clo);
    parts_add(ghi, glo);
    if (!loops_intact()) atomicOr(ctr[2], 4u);
    if (!inside || gl_LocalInvocationIndex >= 64u) return;
    vec3 c = fx_value(chi, clo, P.fx.y), g = fx_value(ghi, glo, P.fx.y);
    vec4 rec1 = ph[ri + 1u], rec2 = ph[ri + 2u];
    vec3 L = rec2.xyz;
    if (valid) L += rec1.xyz * (c * (P.r.w * rec2.w) + g * (P.r.z * rec1.w));
    if (P.img.z == 0u || P.seed.z == 0u) { // the first pass overwrites (the buffer holds anything)
        outv[idx] = vec4(L, 1.0);
    } else { // a running mean over the passes: pass k weighs 1 / (k + 1)
        float k = float(P.seed.z);
        outv[idx] = vec4((outv[idx].xyz * k + L) / (k + 1.0), 1.0);
    }
}

void main() {
    uint i = item();
    if (STEP == S_CLEAR) {
        if (i < P.a.w) cells[i] = uvec2(0u);
    } else if (STEP == S_RESET) {
        if (i < 4u) ctr[i] = 0u;
    } else if (STEP == S_TRACE) {
#ifndef PHOTON_SMALL
        trace_photons();
#endif
    } else if (STEP == S_COUNT) {
        if (i >= min(ctr[0], P.a.y)) return;
        atomicAdd(cells[photon_bucket(ph[2u * i])].x, 1u);
    } else if (STEP == S_ALLOC) {
        // one atomic per subgroup on the one counter (was one per non-empty bucket: they queue on one
        // address); the subgroup's buckets take consecutive ranges in bucket order
        uint n = i < P.a.w ? cells[i].x : 0u, total = subgroupAdd(n), base = 0u;
        if (subgroupElect() && total > 0u) base = atomicAdd(ctr[1], total);
        base = subgroupBroadcastFirst(base) + subgroupExclusiveAdd(n);
        if (i < P.a.w) cells[i] = uvec2(0u, n > 0u ? base : 0u);
    } else if (STEP == S_SCATTER) {
        if (i >= min(ctr[0], P.a.y)) return;
        vec4 a = ph[2u * i], b = ph[2u * i + 1u];
        uint c = photon_bucket(a);
        uint k = cells[c].y + atomicAdd(cells[c].x, 1u);
        sorted[k] = a;
        sorted[P.a.y + k] = b;
    } else if (STEP == S_DENSITY) {
        density_pixel();
    } else if (STEP == S_SIZE) {
        if (i != 0u) return;
        // photons.c step(): items over 64-lane workgroups, x at most 4096 and y the rest
        uint stored = ctr[0], over = stored > P.a.y ? 0u : 1u;
        // the buckets: the least power of two at least twice the stored photons, within [64, P.a.w]
        uint n = 2u * stored, used = n <= 1u ? 1u : 1u << uint(findMSB(n - 1u) + 1);
        used = clamp(used, 64u, P.a.w);
        uvec3 items = uvec3(used, stored, P.fu.z * 64u) * over;
        for (int k = 0; k < 3; k++) {
            uint groups = (items[k] + 63u) / 64u, gx = min(groups, 4096u), gy = gx > 0u ? (groups + gx - 1u) / gx : 0u;
            ctr[4 + 4 * k] = gx;
            ctr[5 + 4 * k] = gy;
            ctr[6 + 4 * k] = gx > 0u ? 1u : 0u;
        }
        ctr[7] = used;
    } else {
#ifndef PHOTON_SMALL
        gather_pixel();
#endif
    }
}
