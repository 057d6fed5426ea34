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
// most P.seed.w samples per dispatch and keep each texel's or sample block's
// running sum and sample count in the output buffer (the same float additions in the
// same order however the samples are split, so the result does not depend on
// the split a device needs); before they store, they check that the guard
// never fired (loops_intact). Where it fired, they store nothing and raise a
// flag, and the host repeats the dispatch with half the samples. Hardware
// GPUs have no such guard (a dispatch runs to its end or the device is lost).
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

// Every kernel of probe.comp (probes.cmake: the bake's probe and probe_one, the render passes' probe_pt, PT_PRECISE)
// computes every float operation of the path and of the octree walk precise (PT_PREC, path_common.glsl; WPREC,
// trace_common.glsl), so the driver may not contract them into fused multiply-adds. The NVIDIA compiler (driver
// 580) compiles each pipeline on its own and contracted them differently: with the sun's depth map (SMAP) and
// without it 54 of 2,073,600 values of a path-traced Cornell box image differed (issue 21, H200; with the path
// precise and not the walk, 45), eph_monu1's bake 88 bytes of its .probes, and the plain and the compact layout's
// bakes of the animated demo 150 hit distances one step apart (issue 18, H200, branch rdr4; lavapipe, which never
// contracts, gave the same bits each time). The map only clips shadow rays (render/shaders/smap_lookup.glsl: its
// margin keeps the clip conservative), so with the arithmetic fixed the bytes are the same (branch bakeq).
#define PT_PREC precise
#define WALK_PRECISE
#define PATH_PRECISE
// CELL_HITS (trace_common.glsl): the bake's walks find their hits in cell-level leaves, so that the plain and
// the compact layout's bakes give the same bytes (a leaf of the plain layout can be a cube of cells that the
// compact geometry cuts otherwise; issue 18, branch bakex). Not in the render passes' kernel (PT_PRECISE).
#ifndef PT_PRECISE
#define CELL_HITS
#endif
// BEAM (constant 5, trace_common.glsl): the bake's camera rays start their walk at their texel
// block's distance from probe_beam.comp (binding 11), where BEAM > 1 (the block side in texels)
#define TRACE_BEAM
#include "trace_common.glsl"

layout(constant_id = 6) const bool MATS = false; // some attribute record is metal or glass (binding 13)
// bits 0-7: the pass (PMODE); bit 8 (LIGHTS): the scene has lights of binding 14 or emissive voxels of
// binding 15 (P.cnt.x or P.cnt.y > 0): without, their loops and the emitter sampling leave the kernel
// (fewer registers; the sun and sky stay)
layout(constant_id = 7) const uint PCONST = 0x100u;
const int PMODE = int(PCONST & 0xFFu);
const bool LIGHTS = (PCONST & 0x100u) != 0u;
// bit 9 (STRAT, the bake only): a texel's first-bounce directions are stratified over its samples, sample s
// in the s-th point of a shifted Hammersley set whose shift the 32 texels of a tile share up to a jitter
// within half a stratum: each sample's direction stays cosine-distributed (the shift is uniform), a
// texel's samples cover the hemisphere evenly, and the bounce rays of a SIMD group leave in nearby
// directions (bake())
const bool STRAT = (PCONST & 0x200u) != 0u;
// bit 10 (GLASS, the render passes only): some record is glass that transmits: render()'s glass events (the
// probe modes' glass lobe) are compiled in (on lavapipe, which runs every branch's code for every pixel, they
// cost gi=probes 3x where the scene has glass). Set only with MATS (glass is one of its materials); not
// `MATS && ...`: glslang 11 emits `&&` of spec constants out of order, and the bake's module came out invalid
const bool GLASS = (PCONST & 0x400u) != 0u;
// bit 11 (METAL, the render passes only): some record is metal: render()'s metal event (the probe modes'
// metal lobes) is compiled in; set only with MATS. A scene without metal compiles the code it ran before.
const bool METAL = (PCONST & 0x800u) != 0u;
// the most metal events of a render sample's chain (probes/light.h VX__METAL_CHAIN, the same number and why):
// the size of render()'s arrays of the chain's metal surfaces, and the metal events a path() follows without
// spending a bounce (probes/pathtrace.c vx__path)
const int METAL_CHAIN = 4;
#ifndef PT_PRECISE
// bits 16-23 (the bake's kernel only, not PT_PRECISE's): its bounces plus one, a constant of the pipeline (0:
// P.a.z): the path's loop specialised for the bake's count (H200, the Cornell box's goal bake: GPU trace 0.260 ->
// 0.258 and 0.261 -> 0.259 s in two sessions, 72 registers either way, the same bytes)
const uint BAKE_BOUNCES = (PCONST >> 16) & 0xFFu;
#endif
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
    uvec4 cnt;     // x: lights (binding 14), y: emissive voxels (binding 15), z: 1: no jitter in the pixel,
                   // w: 1: some light stands for emissive voxels (VX_LIGHT_FROM_VOXELS)
    vec4 pt;       // x: total emitted power of the emissive voxels (sum of lum(radiance) * area)
    vec4 skyh;     // the path tracer's sky: horizon rgb, w: 0 uniform (sky), 1 gradient (sky: zenith), 2 map
    vec4 skyg;     // ground rgb, w: map intensity
    vec4 skym;     // map: rotation (radians about +z), width, height
    uvec4 rw;      // render: x: rows in the row table (0: every row, no table), y: samples per block,
                   // z: first block of this round, w: blocks in a round
    uvec4 rk;      // render: x: 0 trace the round's blocks, 1 add them to the pixels; y: 1 in a round's
                   // first dispatch (the blocks' state is not written yet)
    vec4 smo;      // the sun's depth map (SMAP): xyz its origin relative to the reference point, w the margin
    uvec4 smn;     // x: its texels a side, y: entries of its instance table
} P;
layout(std430, binding = 8) readonly buffer Emit { vec4 emit_attr[]; };  // per colors[] entry
layout(std430, binding = 9) readonly buffer Probes { vec4 probes[]; };    // xyz: position - reference, w: state
// [0] flags (x: the loop guard fired, y: samples left), then per texel of
// each probe (bake): the running sum (rgb, w: distance or -1), the normal
// (xyz, w: 1 on a hit) and (samples done, 0, 0, 0); render: the row table,
// then per pixel the running sum (rgb, w: samples that hit) and (samples
// done, 0, 0, 0), then the round's blocks (see render())
layout(std430, binding = 10) buffer Out { vec4 outv[]; };
// per probe: irradiance (10x10x3) then, after all probes, moments (18x18x2); the bake with BEAM > 1: per
// probe of the dispatch and block of BEAM x BEAM texels, the block's start distance (probe_beam.comp)
layout(std430, binding = 11) readonly buffer Maps { float maps[]; };
// light field modes, per probe: distance u16 ((res+2)^2, padded to a word),
// min-distance u16 ((low+2)^2, padded), normal oct16 ((res+2)^2), radiance
// half RGB ((res+2)^2 * 3, padded)
layout(std430, binding = 12) readonly buffer LfMaps { uint lfw[]; };
// path tracer (probes/pathtrace.c): per colors[] entry two vec4 (type, GGX alpha, metalness, specular),
// (ior, transmission, 0, 0), when MATS
layout(std430, binding = 13) readonly buffer Mats { vec4 mats[]; };
// per light five vec4: (position - reference, type), (unit direction, range), (colour * intensity, radius),
// (spot scale, spot offset, angular diameter, size0), (unit tangent orthogonal to the direction, size1)
layout(std430, binding = 14) readonly buffer Lights { vec4 lights[]; };
// per emissive voxel four vec4: (corner - reference, area), (axis 0, cdf), (axis 1, 0), (axis 2, 0), then
// (radiance, 0)
layout(std430, binding = 15) readonly buffer Emitters { vec4 ems[]; };
// the environment map's texels, RGB per texel, row 0 at +z (a placeholder unless the sky is a map)
layout(std430, binding = 16) readonly buffer Env { float env[]; };

#include "path_common.glsl"

// The sun's depth map (render/gpu.h vx__render_scene_sun_map; the bake only, SMAP: constant 11):
// the sun's shadow rays end where nothing lies further towards the light, or are decided without a
// walk; the same answers as the whole ray's. Without the map's rule for a ray from the one solid cube
// that gave the texel's bound (smap_tmax's inst, cell, entered): a ray leaving its own cube's face cannot
// meet it, but on the H200 a few of the walked rays did (the walk's answer there), so with the rule
// eph_monu1's bake differed in 64 of 105.6 M bytes with and without the map, 168 over the compact layout
// (lavapipe: none), and without it in none (issue 18, branch smap3). The clip at the texel's largest
// bound keeps the own cube inside the walk, so the map decides as the whole walk does.
#define SMAP_BINDING 17
#include "smap_lookup.glsl"
bool sun_occluded(vec3 p) {
    if (SMAP) {
        float t = smap_tmax(p, P.light.xyz, P.smo, P.smn.x, P.smn.y, NO_HIT, uvec3(0u), false);
        if (t < 0.0) return t == -2.0;
        return occluded_to(p, P.light.xyz, t);
    }
    return occluded(p, P.light.xyz);
}

uvec2 rng_seed() { return P.seed.xy; }

// ---- the lighting model (probes/light.c) and the path tracer (probes/pathtrace.c) ----
PT_PREC vec3 direct(Surf s) {
    float ndl = dot(s.n, P.light.xyz);
    if (ndl <= 0.0 || !(P.sun.x > 0.0 || P.sun.y > 0.0 || P.sun.z > 0.0)) return vec3(0.0);
    if (occluded(s.p, P.light.xyz)) return vec3(0.0);
    return s.alb / PI * P.sun.xyz * ndl;
}
// direct() with the BRDF f in place of alb / pi where own (metal: probes/light.c vx__direct_f); one shadow
// ray either way (render() inlines it once)
PT_PREC vec3 direct_f(Surf s, bool own, vec3 f) {
    float ndl = dot(s.n, P.light.xyz);
    if (ndl <= 0.0 || !(P.sun.x > 0.0 || P.sun.y > 0.0 || P.sun.z > 0.0)) return vec3(0.0);
    if (occluded(s.p, P.light.xyz)) return vec3(0.0);
    return (own ? f : s.alb / PI) * P.sun.xyz * ndl;
}

Surf g_s; // the vertex being shaded (GLSL passes structs by value; one copy)

// the frame's sphere and rect lights along a ray, nearest before tmax (probes/pathtrace.c area_hit)
bool area_hit(vec3 o, vec3 d, float tmax, out vec3 le, PT_PREC out float pdf) {
    bool found = false;
    le = vec3(0.0);
    pdf = 0.0;
    for (uint i = 0u; LIGHTS && i < P.cnt.x; i++) {
        vec4 a = lights[5u * i], b = lights[5u * i + 1u], c = lights[5u * i + 2u];
        uint type = uint(a.w);
        PT_PREC float t = BIG, p = 0.0;
        if (type == 3u) {
            vec3 v = a.xyz - o;
            float d2 = dot(v, v), r2 = c.w * c.w, bb = dot(v, d);
            if (d2 <= r2 || bb <= 0.0) continue;
            float disc = r2 - (d2 - bb * bb);
            if (disc < 0.0) continue;
            t = bb - sqrt(disc);
            float s2 = r2 / d2, omc = s2 / (1.0 + sqrt(1.0 - s2));
            p = 1.0 / (2.0 * PI * omc);
        } else if (type == 4u) {
            vec4 dd = lights[5u * i + 3u], e = lights[5u * i + 4u];
            float dn = dot(d, b.xyz);
            if (dn >= 0.0) continue;
            t = dot(a.xyz - o, b.xyz) / dn;
            if (!(t > 0.0)) continue;
            PT_PREC vec3 y = o + d * t - a.xyz, t2 = cross(b.xyz, e.xyz);
            PT_PREC float area = dd.w * e.w;
            precise float hd = 0.5 * dd.w, he = 0.5 * e.w;
            if (!(area > 0.0) || abs(dot(y, e.xyz)) > hd || abs(dot(y, t2)) > he) continue;
            p = t * t / (area * -dn);
        } else {
            continue;
        }
        if (t < tmax) {
            tmax = t;
            found = true;
            pdf = p;
            le = c.xyz;
        }
    }
    return found;
}

// the BSDF towards a sampled light direction l and the sample's weight (probes/pathtrace.c nee_f): against the
// BSDF sampling of each lobe that goes on (go_d: the Lambert lobe or vertex, go_s: a glossy vertex's specular
// lobe), whole for a lobe that ends the path, nothing there where end_zero (the emissive voxels); a glossy
// vertex's lobes weighed apart and folded into f (w = 1); precise, as its callers' sums were before (the weight
// leaves through an out parameter, which precise does not follow: test_spirv_precise)
PT_PREC vec3 nee_f(Bsdf B, vec3 wo, vec3 l, float pdf, bool go_d, bool go_s, bool end_zero, PT_PREC out float w) {
    if (!(MATS && B.kind == B_GLOSSY)) {
        PT_PREC float bp;
        vec3 f = bsdf_eval(B, wo, l, bp);
        if (end_zero) w = go_d ? mis(pdf, bp) / pdf : 0.0;
        else w = pdf > 0.0 ? (go_d ? mis(pdf, bp) / pdf : 1.0 / pdf) : 1.0;
        return f;
    }
    PT_PREC vec3 fs, fd;
    PT_PREC float pss, pdd, ws = 1.0, wd = 1.0;
    glossy_lobes(B, wo, l, fs, pss, fd, pdd);
    if (pdf > 0.0 || end_zero) {
        ws = go_s ? mis(pdf, B.ps * pss) / pdf : (end_zero ? 0.0 : 1.0 / pdf);
        wd = go_d ? mis(pdf, (1.0 - B.ps) * pdd) / pdf : (end_zero ? 0.0 : 1.0 / pdf);
    }
    w = 1.0;
    return fs * ws + fd * wd;
}

// light sampling at a non-delta vertex (probes/pathtrace.c nee); go_d, go_s: which lobes go on (nee_f)
vec3 nee(Bsdf B, vec3 wo, bool go_d, bool go_s, bool skip_direct) {
    PT_PREC vec3 out_l = vec3(0.0);
    float bp;
    bool go = go_d || (MATS && B.kind == B_GLOSSY && go_s); // some lobe goes on
    Surf s = g_s;
    if (!skip_direct && (P.sun.x > 0.0 || P.sun.y > 0.0 || P.sun.z > 0.0) && dot(s.n, P.light.xyz) > 0.0 &&
        !sun_occluded(s.p)) {
        vec3 f = bsdf_eval(B, wo, P.light.xyz, bp);
        out_l += f * P.sun.xyz * dot(s.n, P.light.xyz);
    }
    for (uint i = 0u; LIGHTS && i < P.cnt.x; i++) {
        vec4 a = lights[5u * i], b = lights[5u * i + 1u], c = lights[5u * i + 2u], dd = lights[5u * i + 3u];
        uint type = uint(a.w);
        PT_PREC vec3 e = c.xyz, l;
        PT_PREC float pdf = 0.0, tmax = BIG, g = 1.0;
        if (skip_direct) continue; // the direct pass's (probes/pathtrace.c)
        if (type == 0u) {
            if (dd.z >= 1e-6) { // CONE_MIN of probes/pathtrace.c
                float h = 0.5 * dd.z, sn = sin(h), sq = sin(0.5 * h), omc = 2.0 * sq * sq;
                e = c.xyz / (PI * sn * sn);
                l = cone_dir(b.xyz, omc, rnd(), rnd());
                pdf = 1.0 / (2.0 * PI * omc);
            } else {
                l = b.xyz;
            }
        } else if (type == 1u || type == 2u) {
            vec3 v = a.xyz - s.p;
            float d2 = dot(v, v), dist = sqrt(d2);
            if (!(dist > 0.0)) continue;
            l = v / dist;
            g = 1.0 / max(d2, 1e-4 * s.cell * s.cell);
            if (b.w > 0.0) {
                float q = dist / b.w, w = max(0.0, 1.0 - q * q * q * q);
                g *= w * w;
            }
            if (type == 2u) {
                float sp = clamp(-dot(l, b.xyz) * dd.x + dd.y, 0.0, 1.0);
                g *= sp * sp;
            }
            tmax = dist * (1.0 - 1e-6);
        } else if (type == 3u) {
            vec3 v = a.xyz - s.p;
            PT_PREC float d2 = dot(v, v), r2 = c.w * c.w;
            if (d2 <= r2 || !(r2 > 0.0)) continue;
            float dist = sqrt(d2), s2 = r2 / d2, omc = s2 / (1.0 + sqrt(1.0 - s2));
            l = cone_dir(v / dist, omc, rnd(), rnd());
            pdf = 1.0 / (2.0 * PI * omc);
            float bb = dot(v, l), disc = r2 - (d2 - bb * bb);
            tmax = (bb - sqrt(max(0.0, disc))) * (1.0 - 1e-6);
        } else {
            vec4 ee = lights[5u * i + 4u];
            PT_PREC float area = dd.w * ee.w;
            if (!(area > 0.0)) continue;
            float u = rnd() - 0.5, w = rnd() - 0.5;
            vec3 v = a.xyz + u * dd.w * ee.xyz + w * ee.w * cross(b.xyz, ee.xyz) - s.p;
            float d2 = dot(v, v), dist = sqrt(d2);
            if (!(dist > 0.0)) continue;
            l = v / dist;
            PT_PREC float cl = -dot(l, b.xyz);
            if (cl <= 0.0) continue;
            pdf = d2 / (area * cl);
            tmax = dist * (1.0 - 1e-6);
        }
        PT_PREC float cs = dot(s.n, l);
        if (cs <= 0.0 || !(g > 0.0) || isinf(g) || occluded_to(s.p, l, tmax)) continue;
        float w;
        vec3 f = nee_f(B, wo, l, pdf, go_d, go_s, false, w);
        out_l += f * e * (g * cs * w);
    }
    if (LIGHTS && P.cnt.y > 0u && go && !(skip_direct && P.cnt.w != 0u)) { // not at the last vertex (probes/pathtrace.c)
        vec3 y, n, rad;
        float edge;
        emitter_point(P.cnt.y, y, n, rad, edge);
        PT_PREC vec3 v = y - s.p;
        PT_PREC float d2 = dot(v, v), dist = sqrt(d2);
        if (dist > 0.0) {
            PT_PREC vec3 l = v / dist;
            PT_PREC float cy = -dot(l, n), cs = dot(s.n, l);
            precise float tl = dist - 1e-3 * edge;
            if (cy > 0.0 && cs > 0.0 && !occluded_to(s.p, l, tl)) {
                float pdf = lum(rad) / P.pt.x * d2 / cy, w;
                vec3 f = nee_f(B, wo, l, pdf, go_d, go_s, true, w);
                out_l += f * rad * (cs * w);
            }
        }
    }
    return out_l;
}

// sky radiance towards unit d (render/shaders/sky.glsl: vx_sky_radiance in float)
#define SKY_TEXEL(i) env[i]
#include "sky.glsl"
vec3 sky_radiance(vec3 d) { return sky_eval(P.sky, P.skyh, P.skyg, P.skym, d); }

// The bake's camera ray (path()'s first) starts its walk here: its texel block's beam distance
// (probe_beam.comp); 0 for every other ray and pass.
float g_path_tskip = 0.0;
// STRAT: the first bounce's two direction numbers (u1, u2 of bsdf_sample), set per sample by bake()
vec2 g_bounce_u = vec2(0.0);

// radiance along o + t d (probes/pathtrace.c vx__path); hit: the ray met a voxel
vec3 path(vec3 o, vec3 d, uint bounces, bool indirect, out bool hit_out) {
    PT_PREC vec3 thr = vec3(1.0), acc = vec3(0.0);
    hit_out = false;
    PT_PREC float prev_pdf = 0.0;
    uint depth = 0u; // diffuse and glossy bounces (metal events not counted)
    int metal = 0;   // metal events, up to METAL_CHAIN (probes/pathtrace.c vx__path)
    int vertex = 0;
    // Inside glass (probes/pathtrace.c vx__path): the walk the next event runs from o along d, in glass
    // cell g_cell of instance g_inst, after a refraction into the glass or a bounce off an opaque voxel
    // met from inside it
    bool in_glass = false;
    uint g_inst = 0u;
    uvec3 g_cell = uvec3(0u);
    float g_ior = 1.5, g_alpha = 0.0;
    for (int events = 0; events < 1024; events++) {
        Hit h;
        bool hit = true, stopped = false; // stopped: h is an opaque voxel's face met from inside glass, at o
        if (MATS && in_glass) { // (MATS: a scene without glass compiles none of this)
            PT_PREC vec3 p = o;
            uint w_inst;
            uvec3 w_cell;
            uint wr = glass_walk(g_inst, g_cell, g_ior, g_alpha, p, d, thr, o, h, w_inst, w_cell);
            // no light is sampled inside glass (a shadow ray starting in a glass voxel meets it), so what
            // the path finds after a walk counts whole, as after a delta event
            prev_pdf = 0.0;
            if (wr == WALK_ABSORBED) break;
            stopped = wr == WALK_STOP;
            if (stopped) g_inst = w_inst, g_cell = w_cell; // where a bounce off the voxel walks on
            in_glass = false;
        }
        // one cast in the loop's body: lavapipe runs both sides of a branch (masked), and a second inlined
        // trace_scene cost scenes without glass a quarter of their time there
        if (!stopped) {
            g_tskip = events == 0 ? g_path_tskip : 0.0;
            hit = cast_ray(o, d, BIG, h);
            g_tskip = 0.0;
        }
        bool skip = indirect && vertex == 0, skip_lights = indirect && vertex <= 1;
        vec3 le;
        float lp;
        if (!stopped && LIGHTS && P.cnt.x > 0u && area_hit(o, d, hit ? h.t : BIG, le, lp)) {
            if (!skip_lights) acc += thr * le * (prev_pdf > 0.0 ? mis(prev_pdf, lp) : 1.0);
            break;
        }
        if (!hit) {
            if (!skip) acc += thr * sky_radiance(d);
            for (uint i = 0u; LIGHTS && i < P.cnt.x && !(indirect && vertex <= 1); i++) {
                vec4 a = lights[5u * i], b = lights[5u * i + 1u], c = lights[5u * i + 2u], dd = lights[5u * i + 3u];
                if (uint(a.w) != 0u || !(dd.z >= 1e-6)) continue;
                PT_PREC float hh = 0.5 * dd.z, sn = sin(hh), sq = sin(0.5 * hh), omc = 2.0 * sq * sq;
                vec3 cr = cross(b.xyz, d);
                precise float sn2 = sn * sn;
                if (!(dot(b.xyz, d) > 0.0 && dot(cr, cr) < sn2)) continue;
                acc += thr * c.xyz / (PI * sn * sn) * (prev_pdf > 0.0 ? mis(prev_pdf, 1.0 / (2.0 * PI * omc)) : 1.0);
            }
            break;
        }
        if (vertex == 0) hit_out = true;
        g_s = surface(o, d, h);
        if (!skip && !(skip_lights && P.cnt.w != 0u) && (g_s.emit.x > 0.0 || g_s.emit.y > 0.0 || g_s.emit.z > 0.0)) {
            PT_PREC float w = 1.0;
            if (LIGHTS && prev_pdf > 0.0 && P.cnt.y > 0u) {
                float cy = abs(dot(d, g_s.n));
                w = cy > 0.0 ? mis(prev_pdf, lum(g_s.emit) / P.pt.x * h.t * h.t / cy) : 0.0;
            }
            acc += thr * g_s.emit * w;
        }
        vertex++;
        Bsdf B = bsdf_of(g_s);
        vec3 wo = -d;
        if (B.kind == B_GLASS) {
            vec3 wi;
            bool refr;
            PT_PREC float w;
            if (!dielectric(g_s.n, wo, B.eta, B.alpha, wi, refr, w)) break;
            prev_pdf = 0.0;
            // glass at the camera's first surface: the pipeline's direct pass gives only the glass's Lambert
            // share, so what the glass reflects and transmits is this path's whole (render/pipeline.h)
            if (vertex == 1) indirect = false;
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
        // Without lights nee() is the sun's term alone and draws no random numbers: its shadow ray is traced
        // after the bounce is sampled, so that the surface's frame is no longer live across it (fewer
        // registers); the same numbers and sums
        PT_PREC vec3 sun_f = vec3(0.0), thr_v = thr;
        bool sun_ray = false;
        // the lobes that go on (probes/pathtrace.c vx__path): a metal event (a metal record's specular lobe)
        // spends no bounce while metal events are left
        bool glossy = MATS && B.kind == B_GLOSSY, go_d = depth < bounces;
        bool go_s = go_d || (glossy && metal < METAL_CHAIN);
        // (inside glass, stopped, no light is sampled: above)
        if (!stopped && LIGHTS) {
            acc += thr * nee(B, wo, go_d, go_s, indirect && vertex == 1);
        } else if (!stopped && !(indirect && vertex == 1) && (P.sun.x > 0.0 || P.sun.y > 0.0 || P.sun.z > 0.0) &&
                   dot(g_s.n, P.light.xyz) > 0.0) {
            float bp;
            sun_f = bsdf_eval(B, wo, P.light.xyz, bp) * P.sun.xyz * dot(g_s.n, P.light.xyz);
            sun_ray = true;
        }
        if (!go_s) {
            if (sun_ray && !sun_occluded(g_s.p)) acc += thr_v * sun_f;
            break;
        }
        PT_PREC vec3 w;
        bool sampled, spec = false;
        // the stratified pair replaces u1 and u2 of the bake's first bounce; all three numbers are still
        // drawn, so that the later ones (Russian roulette, deeper bounces) are the independent path's
        bool strat = STRAT && PMODE == P_BAKE && depth == 0u && metal == 0;
        float u0 = rnd(), u1 = rnd(), u2 = rnd();
        if (strat) u1 = g_bounce_u.x, u2 = g_bounce_u.y;
        if (glossy) sampled = glossy_sample_u(B, wo, u0, u1, u2, d, w, prev_pdf, spec);
        else sampled = bsdf_sample_u(B, wo, u0, u1, u2, d, w, prev_pdf);
        vec3 p_v = g_s.p;
        if (sun_ray && !sun_occluded(p_v)) acc += thr_v * sun_f;
        if (!sampled) break;
        if (spec && metal < METAL_CHAIN) {
            metal++; // (a handful at most: no roulette)
            thr *= w;
        } else {
            if (!go_d) break; // the Lambert lobe, drawn where only the specular one goes on (nee: whole)
            thr *= w;
            depth++;
            if (depth >= 3u) { // VX__RR_DEPTH
                PT_PREC float q = min(0.95, max(thr.x, max(thr.y, thr.z)));
                if (!(rnd() < q)) break;
                thr /= q;
            }
        }
        if (thr == vec3(0.0)) break;
        o = g_s.p;
        in_glass = stopped; // a bounce off a voxel set in glass goes back into the glass
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
    // the octant segments: [t, t_end] cut where the ray crosses the probe's three axis planes, in order. A
    // crossing outside (t, t_end) counts as t_end (an empty segment, skipped below). Sorted by a three-element
    // network of min and max, not the CPU's insertion sort into a run-time-indexed array: lavapipe (Mesa 22.3)
    // ran that sort wrongly on some rays (a crossing duplicated, another lost, so a segment spanned two
    // octants and the probe answered "unknown"), which left the light field's GPU image 4-6% below the CPU's
    // (docs/TESTING.md, stop 73)
    vec3 cr = vec3(t_end);
    for (int a = 0; a < 3; a++) {
        float tb = d[a] == 0.0 ? t_end : -q0[a] / d[a];
        if (tb > t && tb < t_end) cr[a] = tb;
    }
    float c0 = min(cr.x, cr.y), c1 = max(cr.x, cr.y), c2 = cr.z;
    float m1 = min(c1, c2);
    c2 = max(c1, c2);
    c1 = max(c0, m1);
    c0 = min(c0, m1);
    float ts[5] = float[5](t, c0, c1, c2, t_end);
    int nt = 5;
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

// The texel block's start distance for rays from the probe (probe_beam.comp), slightly early as trace.comp's.
float beam_start(uint probe, uint i, uint j, uint res) {
    if (BEAM <= 1u) return 0.0;
    uint nb = res / BEAM;
    return maps[(probe - P.a.w) * nb * nb + (j / BEAM) * nb + i / BEAM] * 0.9999;
}

// The texel centre ray's distance (acc.w; -1: none within dist_max) and normal (geo; w: 1 on a hit).
void centre_ray(vec3 o, uint i, uint j, uint res, inout vec4 acc, inout vec4 geo) {
    Hit h;
    if (cast_ray(o, oct_decode((2.0 * vec2(i, j) + 1.0) / float(res) - 1.0), P.origin.w, h)) {
        Inst I = insts[h.inst];
        vec4 row = h.axis == 0 ? I.r0 : (h.axis == 1 ? I.r1 : I.r2);
        geo = vec4(normalize(row.xyz * h.nsign), 1.0);
        acc.w = h.t;
    }
}

void bake() {
    uint res = P.a.x, slot = gl_GlobalInvocationID.y, n = gl_GlobalInvocationID.x;
    if (n >= res * res || slot >= P.seed.z) return;
    // each 32 invocations (a SIMD group on NVIDIA) take a tile of 8 x 4 texels rather than a 32-texel run of
    // a row: their rays from the probe leave in nearby directions and meet nearby cells (res: a multiple of 16)
    uint tile = n / 32u, lane = n % 32u, tiles_x = res / 8u;
    uint texel = ((tile / tiles_x) * 4u + lane / 8u) * res + (tile % tiles_x) * 8u + lane % 8u;
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
    precise vec4 acc = vec4(0.0, 0.0, 0.0, -1.0);
    vec4 geo = vec4(0.0); // acc.w: distance (-1: none)
    if (s0 != 0u) acc = outv[at]; // a later dispatch: the sum so far (the distance and normal stay stored)
    uint s = s0;
    // the camera and centre rays start at their texel block's beam distance (path(): the first ray only)
    g_tskip = beam_start(probe, i, j, res);
    // the centre ray's distance and normal stored before the samples, not kept across their walks (H200, the
    // Cornell box's goal bake: fewer values spilled to shared memory, 3,328 -> 2,304 bytes a workgroup, 72
    // registers either way; GPU trace 0.259 -> 0.251 s, the same bytes; docs/PERFORMANCE.md, eleventh sitting)
    if (s0 == 0u) {
        centre_ray(o, i, j, res, acc, geo);
        outv[at + 1u] = geo;
        outv[at].w = acc.w;
    }
    g_path_tskip = g_tskip;
    g_tskip = 0.0;
    // STRAT: the tile's shift (shared by its 32 texels) plus the texel's jitter within half a stratum of a
    // sqrt(spp) x sqrt(spp) grid; the sum is uniform on the unit square for every texel. The jitter trades
    // the bounce rays' coherence against the correlation of a tile's texels, which the irradiance maps sum
    // (H200, Cornell box, 512 probes at R=128, 64 spp: GPU trace 0.492 s independent, 0.376 s without
    // jitter, 0.402 s with half a stratum, 0.421 s with a whole one; irradiance noise against the
    // independent estimator's at R=128 on lavapipe: 1.6x, 0.38x and 0.15x; docs/PERFORMANCE.md)
    precise vec2 shift = vec2(0.0);
    if (STRAT) {
        uvec4 kt = pcg4d(uvec4(probe, tile, 0x5354u, P.seed.x ^ (P.seed.y * 0x9E3779B9u)));
        uvec4 kl = pcg4d(uvec4(probe, texel, 0x4A49u, P.seed.x ^ (P.seed.y * 0x9E3779B9u)));
        precise float side = 0.5 / ceil(sqrt(float(spp)));
        shift = fract(vec2(kt.xy >> 8) * (1.0 / 16777216.0) + vec2(kl.xy >> 8) * (side / 16777216.0));
    }
    for (; s < s1; s++) {
        rng_init(probe, texel, s);
        // the s-th Hammersley point (s / spp, the radical inverse of s), shifted on the torus
        if (STRAT) {
            precise vec2 u = fract(vec2(float(s) / float(spp), float(bitfieldReverse(s)) * (1.0 / 4294967296.0)) + shift);
            g_bounce_u = u;
        }
        precise vec2 uv = (2.0 * (vec2(i, j) + vec2(rnd(), rnd()))) / float(res) - 1.0;
        bool hit;
#ifdef PT_PRECISE
        acc.xyz += path(o, oct_decode(uv), P.a.z, false, hit);
#else
        acc.xyz += path(o, oct_decode(uv), BAKE_BOUNCES != 0u ? BAKE_BOUNCES - 1u : P.a.z, false, hit);
#endif
    }
    // identical values from every invocation that writes them
    if (s != s1 || !loops_intact()) {
        if (fresh) outv[at + 2u] = vec4(0.0); // a valid state: no samples yet
        outv[0].x = 1.0;
        outv[0].y = 1.0;
        return;
    }
    outv[at].xyz = acc.xyz;
    outv[at + 2u] = vec4(float(s1), 0.0, 0.0, 0.0);
    if (s1 < spp) outv[0].y = 1.0;
}

#ifdef VX_ONE_WALK
// bake() and path() for a scene without lights, emitters of binding 14 or metal and glass records (LIGHTS and
// MATS off: probe_gpu.c picks this build then): every ray of the texel (its centre ray, each sample's camera
// and bounce rays and their sun rays) walks the octree at the one trace_scene call of a single loop, a state
// machine, rather than at four inlined copies of the walk. The same rays, random numbers and float operations
// in the same order as bake() (the same bytes); the driver compiles one walk instead of four, which on a
// machine whose shader cache is empty is most of the bake's set-up (docs/PERFORMANCE.md section 5).
const uint W_CENTRE = 0u, W_RAY = 1u, W_SUN = 2u, W_START = 3u, W_END = 4u;
void bake_one() {
    uint res = P.a.x, slot = gl_GlobalInvocationID.y, n = gl_GlobalInvocationID.x;
    if (n >= res * res || slot >= P.seed.z) return;
    uint tile = n / 32u, lane = n % 32u, tiles_x = res / 8u;
    uint texel = ((tile / tiles_x) * 4u + lane / 8u) * res + (tile % tiles_x) * 8u + lane % 8u;
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
    bool fresh = P.lf.x != 0u;
    uint s0 = fresh ? 0u : uint(outv[at + 2u].x), s1 = min(s0 + P.seed.w, spp);
    if (s0 >= spp) return;
    uint i = texel % res, j = texel / res;
    vec3 o = pr.xyz;
    precise vec4 acc = vec4(0.0, 0.0, 0.0, -1.0);
    vec4 geo = vec4(0.0);
    if (s0 != 0u) acc = outv[at];
    uint s = s0;
    float tskip0 = beam_start(probe, i, j, res);
    precise vec2 shift = vec2(0.0);
    if (STRAT) {
        uvec4 kt = pcg4d(uvec4(probe, tile, 0x5354u, P.seed.x ^ (P.seed.y * 0x9E3779B9u)));
        uvec4 kl = pcg4d(uvec4(probe, texel, 0x4A49u, P.seed.x ^ (P.seed.y * 0x9E3779B9u)));
        precise float side = 0.5 / ceil(sqrt(float(spp)));
        shift = fract(vec2(kt.xy >> 8) * (1.0 / 16777216.0) + vec2(kl.xy >> 8) * (side / 16777216.0));
    }
    uint bounces = BAKE_BOUNCES != 0u ? BAKE_BOUNCES - 1u : P.a.z;
    // the walk's ray: origin, direction, end, any hit, start (beam)
    vec3 ro = o, rd = vec3(0.0, 0.0, 1.0);
    float rt = BIG, rskip = 0.0;
    bool rany = false;
    uint st = W_START;
    if (s0 == 0u) {
        st = W_CENTRE;
        rd = oct_decode((2.0 * vec2(i, j) + 1.0) / float(res) - 1.0);
        rt = P.origin.w;
        rskip = tskip0;
    }
    // the path's state (path())
    precise vec3 thr = vec3(1.0), pacc = vec3(0.0), sun_f = vec3(0.0), thr_v = vec3(1.0), w = vec3(0.0), nd = vec3(0.0);
    precise float prev_pdf = 0.0;
    uint depth = 0u;
    int events = 0;
    bool sun_ray = false, last = false, sampled = false;
    Hit h;
    while (true) {
        if (st == W_START) {
            if (s >= s1) break;
            rng_init(probe, texel, s);
            if (STRAT) {
                precise vec2 u = fract(vec2(float(s) / float(spp), float(bitfieldReverse(s)) * (1.0 / 4294967296.0)) + shift);
                g_bounce_u = u;
            }
            precise vec2 uv = (2.0 * (vec2(i, j) + vec2(rnd(), rnd()))) / float(res) - 1.0;
            ro = o, rd = oct_decode(uv), rt = BIG, rany = false, rskip = tskip0;
            thr = vec3(1.0), pacc = vec3(0.0), prev_pdf = 0.0, depth = 0u, events = 0;
            st = W_RAY;
        }
        // the walk (cast_ray, occluded_to)
        h.t = rt;
        h.inst = NO_HIT;
        h.color = 0xFFFFFFFFu;
        h.attr = NO_HIT;
        g_iter = 0u;
        g_tskip = rskip;
        bool hit = trace_scene(ro, rd, 0.0, rany, h);
        g_tskip = 0.0;
        bool sun_done = false, occ = false;
        if (st == W_CENTRE) {
            if (hit) {
                Inst I = insts[h.inst];
                vec4 row = h.axis == 0 ? I.r0 : (h.axis == 1 ? I.r1 : I.r2);
                geo = vec4(normalize(row.xyz * h.nsign), 1.0);
                acc.w = h.t;
            }
            outv[at + 1u] = geo;
            outv[at].w = acc.w;
            st = W_START;
            continue;
        }
        if (st == W_SUN) {
            sun_done = true, occ = hit;
        } else { // W_RAY: path()'s vertex
            events++;
            if (!hit) {
                pacc += thr * sky_radiance(rd);
                st = W_END;
            } else {
                g_s = surface(ro, rd, h);
                if (g_s.emit.x > 0.0 || g_s.emit.y > 0.0 || g_s.emit.z > 0.0) pacc += thr * g_s.emit * 1.0;
                Bsdf B = bsdf_of(g_s);
                vec3 wo = -rd;
                sun_f = vec3(0.0), thr_v = thr;
                sun_ray = false;
                if ((P.sun.x > 0.0 || P.sun.y > 0.0 || P.sun.z > 0.0) && dot(g_s.n, P.light.xyz) > 0.0) {
                    float bp;
                    sun_f = bsdf_eval(B, wo, P.light.xyz, bp) * P.sun.xyz * dot(g_s.n, P.light.xyz);
                    sun_ray = true;
                }
                last = depth >= bounces;
                sampled = false;
                if (!last) {
                    if (STRAT && depth == 0u) {
                        float u0 = rnd();
                        rnd();
                        rnd();
                        sampled = bsdf_sample_u(B, wo, u0, g_bounce_u.x, g_bounce_u.y, nd, w, prev_pdf);
                    } else {
                        sampled = bsdf_sample(B, wo, nd, w, prev_pdf);
                    }
                }
                vec3 p_v = g_s.p;
                sun_done = true;
                if (sun_ray) {
                    float t = BIG;
                    if (SMAP) t = smap_tmax(p_v, P.light.xyz, P.smo, P.smn.x, P.smn.y, NO_HIT, uvec3(0u), false);
                    if (t < 0.0) {
                        occ = t == -2.0;
                    } else { // the sun's ray walks next
                        sun_done = false;
                        ro = p_v, rd = P.light.xyz, rt = t, rany = true, rskip = 0.0;
                        st = W_SUN;
                    }
                }
            }
        }
        if (sun_done) {
            if (sun_ray && !occ) pacc += thr_v * sun_f;
            st = W_END;
            if (!last && sampled) {
                thr *= w;
                depth++;
                bool go = true;
                if (depth >= 3u) { // VX__RR_DEPTH
                    float q = min(0.95, max(thr.x, max(thr.y, thr.z)));
                    if (!(rnd() < q)) go = false;
                    else thr /= q;
                }
                if (go && !(thr == vec3(0.0)) && events < 1024) {
                    ro = g_s.p, rd = nd, rt = BIG, rany = false, rskip = 0.0;
                    st = W_RAY;
                }
            }
        }
        if (st == W_END) {
            acc.xyz += pacc;
            s++;
            st = W_START;
        }
    }
    if (s != s1 || !loops_intact()) {
        if (fresh) outv[at + 2u] = vec4(0.0);
        outv[0].x = 1.0;
        outv[0].y = 1.0;
        return;
    }
    outv[at].xyz = acc.xyz;
    outv[at + 2u] = vec4(float(s1), 0.0, 0.0, 0.0);
    if (s1 < spp) outv[0].y = 1.0;
}
#endif

// The render's samples come in blocks of P.rw.y (a constant of the
// estimator, never of the device or the split): a pixel's value is the sum,
// in block order, of its blocks' sums, each block summed from zero in sample
// order. Blocks are independent, so one dispatch traces up to P.rw.w blocks of
// every pixel at once (many short invocations instead of one long one per
// pixel: the GPU's last wave no longer waits on the busiest pixels' whole
// sample count), and a second dispatch (P.rk.x == 1) adds them to the pixels
// in block order. The pixels are the image's rows or, with a row table
// (P.rw.x rows), only the rows it lists, compacted. Layout of Out: flags, the
// row table (4 rows per vec4, as floats), per pixel the running sum and the
// samples done, then per block of the round and pixel its sum and samples.
uint render_row(uint l) {
    return P.rw.x == 0u ? l : uint(outv[1u + l / 4u][l % 4u]);
}

void render() {
    uint W = P.a.x, H = P.a.w;
    uint nrows = P.rw.x == 0u ? H : P.rw.x;
    uint A = 1u + (P.rw.x + 3u) / 4u, npx = W * nrows; // the pixels' base, their count
    uint spp = max(P.a.y, 1u), B = max(P.rw.y, 1u);
    uint nblk = (spp + B - 1u) / B, R = min(P.rw.w, nblk - P.rw.z);
    uint idx = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u;
    uint S = A + 2u * npx; // the blocks' base
    if (P.rk.x == 1u) {
        if (idx >= npx) return;
        PT_PREC vec4 sum = P.rw.z == 0u ? vec4(0.0) : outv[A + 2u * idx];
        uint j = 0u;
        for (; j < R; j++) sum += outv[S + 2u * (j * npx + idx)];
        if (j != R || !loops_intact()) {
            outv[0].x = 1.0;
            return;
        }
        outv[A + 2u * idx] = sum;
        outv[A + 2u * idx + 1u] = vec4(float(min((P.rw.z + R) * B, spp)), 0.0, 0.0, 0.0);
        return;
    }
    if (idx >= npx * R) return;
    uint j = idx / npx, l = idx - j * npx, at = S + 2u * idx;
    uint b0 = (P.rw.z + j) * B, b1 = min(b0 + B, spp);
    bool fresh = P.rk.y != 0u;
    uint s0 = b0 + (fresh ? 0u : uint(outv[at + 1u].x)), s1 = min(s0 + P.seed.w, b1);
    if (s0 >= b1) return;
    uint x = l % W, y = render_row(l / W);
    bool ortho = F.rx.w != 0.0;
    float t_start = F.fwd.w;
    PT_PREC vec4 acc = s0 == b0 ? vec4(0.0) : outv[at];
    uint s = s0;
    for (; s < s1; s++) {
        rng_init(0x90000000u + y, x, s);
        PT_PREC vec2 off = vec2(0.0);
        if (spp > 1u && P.cnt.z == 0u) off = vec2(rnd(), rnd()) - 0.5;
        PT_PREC float u = ((float(x) + 0.5 + off.x) / float(W)) * 2.0 - 1.0;
        PT_PREC float v = 1.0 - ((float(y) + 0.5 + off.y) / float(H)) * 2.0;
        PT_PREC vec3 o, d;
        if (ortho) {
            o = u * F.rx.xyz + v * F.uy.xyz;
            d = F.fwd.xyz;
        } else {
            d = normalize(F.fwd.xyz + u * F.rx.xyz + v * F.uy.xyz);
            o = t_start * (u * F.rx.xyz + v * F.uy.xyz);
        }
        PT_PREC vec3 c = vec3(0.0);
        if (PMODE == P_PT || PMODE == P_PT_IND) {
            bool hit;
            acc.xyz += path(o, d, P.a.z, PMODE == P_PT_IND, hit);
            if (hit) acc.w += 1.0;
            continue;
        }
        // The camera's first surface and, where it is glass whose glass lobe is drawn, the path tracer's events
        // through the glass to the first surface that is not glass (probes/pathtrace.c vx__glass_lobe, the
        // same events and random numbers), shaded whole there, in the indirect modes too (the pass
        // pipeline's direct pass gives only the glass's Lambert share: render/pipeline.h); a path out of the
        // scene brings the sky. One loop and one cast in its body: lavapipe runs a branch's code masked for
        // every pixel, and a second inlined cast for the few glass pixels cost gi=probes 4.4x on a scene
        // with glass there, 3.2x with one. (GLASS: a scene without glass compiles no glass event.)
        // Metal (METAL; probes/render_gi.c render_pixel, the same events and numbers): a metal surface met
        // (directly, through glass, or by a metal's lobe; not from inside glass) is one more event of the
        // loop, up to METAL_CHAIN of them: its specular lobe's one direction (the path tracer's sampler) leads
        // the loop's next cast to the surface there (glass events may follow; a metal there is the chain's
        // next event), shaded whole times the samples' weights; the chain stops where its weight is zero.
        // Each metal surface itself (its direct light by the BRDF, its Lambert lobe's probe light times kd)
        // is kept in the arrays below and shaded after the loop by the same code as the last surface, in a
        // loop of rounds (the kernel inlines the shading once). Wrapping the event loop in a second loop
        // instead cost the demo island's gi=probes pass 5x on lavapipe even at one round.
        bool full = PMODE == P_GI || PMODE == P_LF;
        PT_PREC vec3 thr = vec3(1.0);
        int at = 1; // 0: the path left the scene along d; 1: sf, a surface; 2: sf met from inside glass
        bool glass = false, in_glass = false;
        uint g_inst = 0u;
        uvec3 g_cell = uvec3(0u);
        float g_ior = 1.5, g_alpha = 0.0;
        Hit h;
        Surf sf;
        // the metal events (METAL): their count, and per event the metal surface, the ray that met it, the
        // weight then, its Lambert lobe's kd and its BRDF towards the sun, and whether its direct light counts
        int nm = 0;
        bool m_full[METAL_CHAIN];
        Surf ms[METAL_CHAIN];
        PT_PREC vec3 m_d[METAL_CHAIN], m_thr[METAL_CHAIN], m_kd[METAL_CHAIN], m_fl[METAL_CHAIN];
        for (int ev = 0; ev < 65 + METAL_CHAIN * int((PCONST >> 11) & 1u); ev++) {
            bool stopped = false;
            if (GLASS && in_glass) {
                uint w_inst;
                uvec3 w_cell;
                PT_PREC vec3 p = o;
                uint wr = glass_walk(g_inst, g_cell, g_ior, g_alpha, p, d, thr, o, h, w_inst, w_cell);
                in_glass = false;
                if (wr == WALK_ABSORBED) {
                    at = 0, thr = vec3(0.0);
                    break;
                }
                stopped = wr == WALK_STOP;
            }
            if (!stopped && !cast_ray(o, d, BIG, h)) {
                at = 0;
                break;
            }
            sf = surface(o, d, h);
            if (ev == 0 && full) c += sf.emit;
            if (stopped) {
                at = 2;
                break;
            }
            if (METAL && nm < METAL_CHAIN && sf.attr != NO_HIT && mats[2u * sf.attr].x == 1.0) {
                Bsdf MB = bsdf_of(sf); // (metal draws no number)
                float pdf;
                ms[nm] = sf, m_d[nm] = d, m_thr[nm] = thr, m_full[nm] = full || glass, m_kd[nm] = MB.kd;
                m_fl[nm] = bsdf_eval(MB, -d, P.light.xyz, pdf);
                nm++;
                if (glass) c += thr * sf.emit; // (seen through glass or by a lobe: shaded whole)
                glass = true;                  // what the lobe meets is shaded whole
                // the specular lobe alone (probes/pathtrace.c vx__metal_spec): bsdf_sample's visible
                // normals with probability 1, the lobe's own pdf: w = F G2 / G1(wo)
                MB.ps = 1.0;
                MB.kd = vec3(0.0);
                vec3 wi;
                PT_PREC vec3 w;
                if (!bsdf_sample(MB, -d, wi, w, pdf)) {
                    at = 0, thr = vec3(0.0);
                    break;
                }
                thr *= w;
                if (!(thr.x > 0.0 || thr.y > 0.0 || thr.z > 0.0)) { // (nothing more reaches the eye)
                    at = 0, thr = vec3(0.0);
                    break;
                }
                o = sf.p;
                d = wi;
                continue;
            }
            if (!GLASS) break;
            Bsdf B = bsdf_of(sf);
            if (B.kind != B_GLASS) break;
            if (ev == (METAL ? 64 + nm : 64)) { // given up (the CPU's 64 glass events)
                at = 0, thr = vec3(0.0);
                break;
            }
            glass = true;
            vec3 wi;
            bool refr;
            PT_PREC float w;
            if (!dielectric(sf.n, -d, B.eta, B.alpha, wi, refr, w)) {
                at = 0, thr = vec3(0.0);
                break;
            }
            thr *= w;
            if (!refr) {
                o = sf.p;
                d = wi;
                continue;
            }
            glass_enter(h, sf, B, wi, o, d, thr, g_inst, g_cell, g_ior, g_alpha);
            in_glass = true;
        }
        if (METAL) {
            // round k < nm the chain's k-th metal surface, round nm the surface the loop ended at
            if (at == 0 && !glass) {
                if (PMODE == P_GI || PMODE == P_PT || PMODE == P_LF) c = P.sky.xyz;
            } else {
                if (at == 0) c += thr * sky_radiance(d);
                for (int k = 0; k <= nm; k++) {
                    bool m = k < nm;
                    if (!m && at == 0) break;
                    if (!m && glass) {
                        full = true;
                        c += thr * sf.emit;
                    }
                    int q = min(k, METAL_CHAIN - 1); // (the last round reads no array: an index in range)
                    Surf x = m ? ms[q] : sf;
                    PT_PREC vec3 xd = m ? m_d[q] : d, tk = m ? m_thr[q] : thr, wl = m ? m_kd[q] : sf.alb;
                    PT_PREC vec3 fl = m_fl[q];
                    bool xm = m;
                    if (!m && nm > 0 && sf.attr != NO_HIT && mats[2u * sf.attr].x == 1.0) {
                        // a metal the chain reached past its last event, or from inside glass: its own BRDF
                        // towards the sun and its Lambert lobe's kd, no lobe (render_gi.c; shaded as a diffuse
                        // surface, its whole colour lit by the sun, the statue came out 5-10x the path tracer's)
                        Bsdf SB = bsdf_of(sf); // (metal draws no number)
                        float pdf;
                        fl = bsdf_eval(SB, -d, P.light.xyz, pdf);
                        wl = SB.kd;
                        xm = true;
                    }
                    if ((m ? m_full[q] : full) && (m || at != 2)) c += tk * direct_f(x, xm, fl);
                    if (xm && !(wl.x > 0.0 || wl.y > 0.0 || wl.z > 0.0)) continue; // (a pure metal: no Lambert lobe)
                    if (PMODE == P_GI || PMODE == P_GI_IND) {
                        c += tk * (wl / PI * irradiance_at(x.p, x.n, xd));
                    } else if (PMODE == P_LF || PMODE == P_LF_IND) {
                        float u1 = rnd(), u2 = rnd();
                        c += tk * (wl * lf_radiance(x.p, cosine_dir(x.n, u1, u2)));
                    }
                }
                acc.w += 1.0;
            }
        } else { // a scene without metal: the code it ran before
            if (at == 0 && !glass) {
                if (PMODE == P_GI || PMODE == P_PT || PMODE == P_LF) c = P.sky.xyz;
            } else {
                if (at == 0) {
                    c += thr * sky_radiance(d);
                } else {
                    if (glass) {
                        full = true;
                        c += thr * sf.emit;
                    }
                    if (full && at != 2) c += thr * direct(sf); // (no light is sampled inside glass)
                    if (PMODE == P_GI || PMODE == P_GI_IND) {
                        c += thr * (sf.alb / PI * irradiance_at(sf.p, sf.n, d));
                    } else if (PMODE == P_LF || PMODE == P_LF_IND) {
                        float u1 = rnd(), u2 = rnd();
                        c += thr * (sf.alb * lf_radiance(sf.p, cosine_dir(sf.n, u1, u2)));
                    }
                }
                acc.w += 1.0;
            }
        }
        acc.xyz += c;
    }
    // identical values from every invocation that writes them
    if (s != s1 || !loops_intact()) {
        if (fresh) outv[at + 1u] = vec4(0.0); // a valid state: no samples yet
        outv[0].x = 1.0;
        outv[0].y = 1.0;
        return;
    }
    outv[at] = acc;
    outv[at + 1u] = vec4(float(s1 - b0), 0.0, 0.0, 0.0);
    if (s1 < b1) outv[0].y = 1.0;
}

// Each build holds one entry: the bake's kernel (probe) only bake(), the render passes' (probe_pt, PT_PRECISE)
// only render() (probe_gpu.c pipeline_of picks them so). The driver compiles the module it is given before
// the constants drop the other side, and a smaller module compiles sooner on a machine whose shader cache
// is empty (docs/PERFORMANCE.md section 5, the bake's twelfth sitting).
void main() {
#ifdef PT_PRECISE
    render();
#elif defined(VX_ONE_WALK)
    bake_one();
#else
    bake();
#endif
}
