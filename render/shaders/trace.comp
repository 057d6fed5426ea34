#version 450
// render/shaders/trace.comp - primary (+ shadow) rays through a BVH over
// instances, then each model's octree in the manner of Laine & Karras,
// "Efficient Sparse Voxel Octrees" (2010): the model cube is mapped to
// [1,2]^3, the ray is mirrored so that every direction component is
// negative, positions are float bit patterns whose mantissa bits are the
// octree path, so a pop finds its level from the highest differing bit.
// Layouts must match render/render_internal.h.
//
// Built twice: as is (float) and with -DPRECISE (render/render.cmake). The
// float variant keeps 23 - depth bits below a cell, too few past ~16 levels
// (see VX_RENDER_PRECISE_DEPTH in render/render.h); the PRECISE variant, used
// only for scenes with such models, generates the ray from the frame's double
// camera and the instances' double matrices and runs the same traversal in
// float64 (positions stay multiples of 2^-23, exact in a double, and the pop
// takes the octree path from their integer offsets instead of float bits).
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

// One sample a pixel (F.dims.z <= 1; render_scene.c): the samples' loop then
// has the constant trip count 1 and the compiler drops it. lavapipe (Mesa
// 22.3), which runs every instruction of a loop's body masked, ran the kernel
// inside that loop at 0.58 (rays that miss everything) to 0.85 (close-ups)
// of the rays per CPU second it reaches without it (issue 21's eleventh
// sitting); the H200 is indifferent.
layout(constant_id = 6) const bool ONE_SAMPLE = false;
// The screen cull's second pass (vx__render_dispatch): one invocation per
// pixel outside F.rect (the conservative pixel rectangle of the scene's box,
// which the first pass traces), writing its miss without tracing: the same
// code with the trace replaced by a miss, so the same bits.
layout(constant_id = 12) const bool MISS_PASS = false;

#ifndef PRECISE
#define TRACE_BEAM
#endif
#define TRACE_SENTINEL
#define TRACE_NOGUARD
#define TRACE_LEAN
#define TRACE_LEAN_BVH
#define TRACE_LEAN_DEEP2
#define TRACE_INST_UBO
#define TRACE_FLAT_ITEMS
#define TRACE_CULL
#define TRACE_TILES
#ifndef PRECISE
#define TRACE_STACK_SELECTS
#define TRACE_PATH
// models with a grid (render/grid.h) walk it: grid_walk.glsl, constant 13 GRID, binding 14
#define TRACE_GRID
#define TRACE_GRID_UBO
#endif
#include "trace_common.glsl"

layout(std430, binding = 7) writeonly buffer Pixels { vec4 pixels[]; };
// the depth mode's pixels: depth and coverage (r = g = b in that mode), half the bytes a pixel (vx_render_frame
// widens them); the same binding
layout(std430, binding = 7) writeonly buffer PixelsDepth { vec2 pixels_depth[]; };
layout(std430, binding = 8) writeonly buffer Hits { uvec4 hits[]; }; // 2 per pixel
#ifdef TRACE_BEAM
// beam.comp's eye distance per block (binding 9 is the float64 variant's)
layout(std430, binding = 10) readonly buffer Beam { float beam_s[]; };
#endif

#ifndef PRECISE
// The directional light's depth map (bindings 11-13, SMAP: constant 11). The
// frame block gives the origin relative to the frame's reference
// (grid_lo.xyz), the margin (grid_lo.w), the side (dims2.x) and the entries
// of its instance table (dims2.y).
#define SMAP_BINDING 11
#include "smap_lookup.glsl"
#endif

void shade(uvec2 px) {
    uint W = F.dims.x, H = F.dims.y;
    uint spp = ONE_SAMPLE ? 1u : max(F.dims.z, 1u);
    // the lean kernels (LEAN) hold one register across the walk for it, not px's two
    uint pix_i = LEAN ? px.y * W + px.x : 0u;
    // The camera ray, its t and the shading are precise (no contraction or
    // reassociation): trace_compact.comp computes them with the same expressions and
    // must give the same bits (test_compact_gpu), but the NVIDIA compiler
    // (driver 580) contracted the two kernels' copies differently (issue 18:
    // up to 2,917 of 15,360 pixels differed on the H200). Once per pixel.
    precise vec4 acc = vec4(0.0);
    uint shadow_rec = 0u; // sample 0's shadow ray: bit 31 cast, the rest its loop iterations (the hits record)
    bool ortho = F.rx.w != 0.0;
    float t_start = F.fwd.w;
    for (uint s = 0u; s < spp; s++) {
        vec2 off = vec2(0.0);
        if (s > 0u) off = fract(vec2(0.5) + float(s) * vec2(0.7548776662466927, 0.5698402909980532)) - 0.5;
        precise float u = ((float(px.x) + 0.5 + off.x) / float(W)) * 2.0 - 1.0;
        precise float v = 1.0 - ((float(px.y) + 0.5 + off.y) / float(H)) * 2.0;
        precise RVEC3 o, d;
        precise REAL t_off;
#ifdef PRECISE
        // the camera in double, as the CPU reference computes it
        dvec2 offd = dvec2(off);
        double ud = ((double(px.x) + 0.5 + offd.x) / double(W)) * 2.0 - 1.0;
        double vd = 1.0 - ((double(px.y) + 0.5 + offd.y) / double(H)) * 2.0;
        if (ortho) {
            o = ud * F.prx.xyz + vd * F.puy.xyz;
            d = F.pfwd.xyz;
            t_off = F.pfwd.w;
        } else {
            dvec3 du = F.pfwd.xyz + ud * F.prx.xyz + vd * F.puy.xyz;
            double len = length(du);
            d = du / len;
            o = F.pfwd.w * (ud * F.prx.xyz + vd * F.puy.xyz);
            t_off = F.pfwd.w * len;
        }
#else
        if (ortho) {
            o = u * F.rx.xyz + v * F.uy.xyz;
            d = F.fwd.xyz;
            t_off = t_start;
        } else {
            vec3 du = F.fwd.xyz + u * F.rx.xyz + v * F.uy.xyz;
            precise float len = length(du);
            d = du / len;
            o = t_start * (u * F.rx.xyz + v * F.uy.xyz);
            t_off = t_start * len;
        }
#endif
        g_iter = 0u;
#ifdef TRACE_BEAM
        if (BEAM > 1u) {
            // slightly before the block's bound: the two passes round differently
            float s_blk = beam_s[(px.y / BEAM) * ((W + BEAM - 1u) / BEAM) + px.x / BEAM];
            g_tskip = (s_blk - t_off) * 0.9999;
        }
#endif
        Hit h;
        h.t = 3.0e38;
        h.inst = NO_HIT;
        h.color = 0xFFFFFFFFu;
        h.cell = uvec3(0u); // a miss's hits record is written too
        // several instances: the walk from the pixel's tile's node, or no
        // walk where the tile's rays meet no leaf's box (vx__frame_tiles)
        // one instance: the start below the root for the tile's rays
        // (frame_paths in render_scene.c), 0xFFFF none
        uint start = 0u, tile = 0xFFFFu;
        if (!MISS_PASS) {
            uint ti = min((px.y >> F.tile_info.x) * F.tile_info.y + (px.x >> F.tile_info.x), 1023u);
            tile = (F.tiles[ti >> 3u][(ti >> 1u) & 3u] >> ((ti & 1u) * 16u)) & 0xFFFFu;
            if (USE_BVH) start = tile;
        }
        g_start = start;
#ifdef TRACE_PATH
        g_path = USE_BVH || tile >= uint(PATHS) ? 0xFFFFu : tile; // the primary ray's (trace_model)
#endif
        bool hit = MISS_PASS || start == 0xFFFFu ? false : trace_scene(o, d, 0.0, false, h);
        g_start = 0u; // the shadow ray's walk from the root
#ifdef TRACE_PATH
        g_path = 0xFFFFu;
#endif
        uint prim_iter = g_iter;
        precise vec4 c = vec4(0.0);
        precise vec3 nw = vec3(0.0);
        if (hit) {
            Inst I = inst_at(h.inst);
            vec4 row = h.axis == 0 ? I.r0 : (h.axis == 1 ? I.r1 : I.r2);
            nw = normalize(row.xyz * h.nsign); // inverse transpose times e_axis
        }
        if (MODE == MODE_COLOR || MODE == MODE_ALBEDO) {
            if (!hit) c = vec4(0.62, 0.75, 0.92, 0.0);
            else {
                vec3 alb = HAS_COLOR ? unpack_rgb(h.color) : vec3(1.0);
                if (MODE == MODE_ALBEDO) c = vec4(alb, 1.0);
                else {
                    float amb = F.light.w;
                    precise float ndl = max(dot(nw, F.light.xyz), 0.0);
                    float vis = 0.0;
                    if (ndl > 0.0) {
                        precise RVEC3 p = o + d * h.t;
                        float cell = inst_at(h.inst).cell;
                        precise RVEC3 ps = p + nw * (cell * 1e-3 + 4e-6 * max(max(abs(p.x), abs(p.y)), abs(p.z)));
#ifdef TRACE_BEAM
                        g_tskip = 0.0; // the beam bounds the primary rays only
#endif
                        Hit sh;
                        sh.t = 3.0e38;
                        sh.inst = NO_HIT;
#ifndef PRECISE
                        // the loop gets only a tmax (or no ray where nothing lies towards the light)
                        if (SMAP) sh.t = smap_tmax(ps, F.light.xyz, F.grid_lo, F.dims2.x, F.dims2.y, h.inst, h.cell, h.t > 0.0);
                        if (sh.t < 0.0) vis = sh.t == -2.0 ? 0.0 : 1.0;
                        else
#endif
                        vis = trace_scene(ps, RVEC3(F.light.xyz), 0.0, true, sh) ? 0.0 : 1.0;
                        if (WRITE_HITS && s == 0u) shadow_rec = 0x80000000u | (g_iter - prim_iter);
                    }
                    c = vec4(alb * (amb + (1.0 - amb) * ndl * vis), 1.0);
                }
            }
        } else if (MODE == MODE_NORMAL) {
            c = vec4(nw, hit ? 1.0 : 0.0);
        } else if (MODE == MODE_DEPTH) {
            precise float t = hit ? float(t_off + h.t) : uintBitsToFloat(0x7F800000u);
            c = vec4(t, t, t, hit ? 1.0 : 0.0);
        } else if (MODE == MODE_INSTANCE) {
            c = hit ? vec4(inst_color(inst_at(h.inst).id), 1.0) : vec4(0.0);
        } else {
            c = vec4(heat(g_iter), 1.0);
        }
        acc += c;
        if (WRITE_HITS && s == 0u) {
            uint base = 2u * (px.y * W + px.x);
            precise float t_hit = hit ? float(t_off + h.t) : 0.0;
            hits[base] = uvec4(hit ? inst_at(h.inst).id : NO_HIT, h.cell);
            hits[base + 1u] = uvec4(floatBitsToUint(t_hit), prim_iter, 0u, shadow_rec);
        }
    }
    if (MODE == MODE_DEPTH) pixels_depth[LEAN ? pix_i : px.y * W + px.x] = acc.xw / float(spp);
    else pixels[LEAN ? pix_i : px.y * W + px.x] = acc / float(spp);
}

#include "screen_cull.glsl"

void main() {
    if (MISS_PASS) {
        uvec2 px;
        if (cull_miss_pixel(F.rect, F.dims.x, F.dims.y, px)) shade(px);
        return;
    }
    // the rectangle's pixels only. Several pixels an invocation (a loop over
    // 2 or 4 rows 8 apart) lost 3-33% on the H200 and 3-11% on lavapipe
    // (issue 21's twelfth sitting; bench/results/issue21_s12_ppi.patch)
    uvec2 px = F.rect.xy + gl_GlobalInvocationID.xy;
    if (px.x < F.rect.z && px.y < F.rect.w) shade(px);
}
