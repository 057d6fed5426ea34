// render/shaders/grid_walk.glsl - the grid walk (issue 21): trace.comp's walk of a model that has a grid
// (render/grid.h: bricks of 8^3 cells as 512 bits, nodes of 8^3 entries above them, a dense root on top; an
// empty entry holds its Chebyshev distance to the nearest occupied one), by a hierarchical DDA instead of
// the octree's descent: a brick's cells by the plain DDA (one word load and bit test a cell), an empty
// entry left with its whole empty cube in one step, an occupied one entered at the cell the ray is in.
// Stop 75's prototype (bench/shaders/brickgrid.comp) traced every view of issue 21's table with fewer
// steps than ESVO at about its cost a step. Included by trace_common.glsl in the float kernels that define
// TRACE_GRID (trace.comp, the pass pipeline's tracing kernels): other kernels and models without a grid (LOD
// rays, deep models, the compact layout, those past the grid budget: render_scene.c) take trace_model's
// octree walk.

// GRID: 0 no model has a grid (the walk is compiled out); else bits 0-1 k >= 1: the grids' roots are at
// level at most k (render/grid.h vx__grid_top), a constant so that where every root is at level 1 the
// lookups below the root fold away and the loop is the two-level walk; bit 2 (GRID_ALL): every model that
// holds a cell has a grid, so the octree walk is compiled out; bit 3 (GRID_EXACT): every grid's root is at
// level k (k >= 2), a constant too (terrain4096's root at level 2: its lookups and shifts fixed); bit 4
// (GRID_UNION, trace_common.glsl, where GRID is declared): trace.comp's kernel of one instance walks the
// union grid of several instances (a converter's regions, or on a CPU device turned instances: render_scene.c
// grid_union), a hit's cell then mapped to its instance and model cell; bit 5
// (GRID_CUBE): some grid covers a cube other than its model's (render/grid.h vx__grid_cube: its cells' box's,
// smaller), so each walk takes its cube from its header's box and its model's depth (grid_cube); without it
// every grid's cube is its model's from cell 0 and that code is compiled out (stop 85, H100: deriving it in
// every walk cost 1-5% of the rays/s on the scenes whose cubes it does not change); bit 6 (GRID_OCT) below
const uint GRID_TOP = GRID & 3u;
const bool GRID_CUBE = (GRID & 32u) != 0u;
const bool GRID_ALL = (GRID & 4u) != 0u;
const bool GRID_EXACT = (GRID & 8u) != 0u;
// bit 6 (GRID_OCT): an empty entry is left by its empty cube toward the ray's octant (render/grid.h
// VX__GRID_OCT_SHIFT: its distance plus the octant's extent), not only by the cube around it; set where some grid's
// root is at least 64 entries a side (render_scene.c grid_bits). Stop 88 (H200, bench/results/p88d_h200.txt): the
// terrains' views 1.14-1.35x their rays/s, the corpus's small roots (16-32 a side) 0.92-1.00x (fewer steps saved
// than the skip's extra work costs: eph_dragon's oblique 9.9 -> 9.1 steps at 0.99x), so they keep the cube around
// the entry (the words' extents not read)
const bool GRID_OCT = (GRID & 64u) != 0u;
// words 0 .. model count - 1: each model's grid address (NO_HIT: none), then the grids, each a 4-word header
// (its cells' box, render_scene.c prepare_grids; word 3 its bricks' record key, render/grid.h vx__grid_records)
// and the grid (render/grid.h) from its root. Binding 14 in
// trace.comp; the pass kernels, whose 14 is taken, name theirs (GRID_BINDING, render/pipeline.c)
#ifndef GRID_BINDING
#define GRID_BINDING 14
#endif
layout(std430, binding = GRID_BINDING) readonly buffer Grid { uint gwords[]; };
// whether a hit's record (Hit.color, Hit.attr) is looked up: trace.comp's colour and albedo modes (its depth,
// normal and instance images and hits record have no use for it); the pass kernels always (materials, glass)
#ifdef GRID_RECORD_ALWAYS
const bool GRID_RECORD = true;
#else
const bool GRID_RECORD = MODE == MODE_COLOR || MODE == MODE_ALBEDO;
#endif

#include "model_cell_leaf.glsl"

// Where a model's grid address and its cells' box come from, decided once: trace.comp with one instance
// (TRACE_GRID_UBO, !USE_BVH) has them in its frame block (render_scene.c fill_single_instance: as floats, so that
// a ray loads neither the table's word nor the header before its walk's first); every other kernel and scene
// reads the grid table's word and the grid's 4-word header (render_scene.c prepare_grids).
#ifdef TRACE_GRID_UBO
const bool GRID_FRAME = !USE_BVH;
uint grid_frame_root() { return F.grid0; }
vec3 grid_frame_lo() { return F.gbox_lo; }
vec3 grid_frame_hi() { return F.gbox_hi; }
uint grid_union_table() { return F.gunion; }
#else
const bool GRID_FRAME = false;
uint grid_frame_root() { return NO_HIT; }
vec3 grid_frame_lo() { return vec3(0.0); }
vec3 grid_frame_hi() { return vec3(0.0); }
uint grid_union_table() { return 0u; }
#endif
// model mi's grid: its root's word address in gwords (NO_HIT: none, the octree walk)
uint grid_address(uint mi) { return GRID_FRAME ? grid_frame_root() : gwords[mi]; }

// render/grid.c vx__grid_top(depth, 0) for the depths that have grids
uint grid_top(uint depth) { return depth <= 10u ? 1u : (depth <= 13u ? 2u : 3u); }

// GRID_CUBE: a grid's cube from its header's cells' box [blo, bhi) and its model's depth (render/grid.h
// vx__grid_cube, the same rule): from its corner org, blo rounded down to whole bricks (exact: integers below
// 2^16), the smallest 2^depth >= 8 that reaches bhi, where smaller than the model's cube; else the model's
// (org 0). The walk runs in the cube's cells (the model's less org).
uint grid_cube(vec3 blo, vec3 bhi, uint mdepth, out vec3 org) {
    // precise as the rest of the walk (test_spirv_precise): exact here either way, integers below 2^16
    precise vec3 o = floor(blo * 0.125) * 8.0;
    precise vec3 ext = max(bhi - o, vec3(8.0));
    uvec3 e = uvec3(ext) - 1u;
    uint d = max(uint(findMSB(max(max(e.x, e.y), e.z)) + 1), 3u), md = max(mdepth, 3u);
    org = o;
    if (d >= md) {
        org = vec3(0.0);
        d = md;
    }
    return d;
}

// As trace_model (same arguments and Hit), for model mi whose root is at word groot of gwords. The walk
// runs in the model's cells from the box entry point with the direction normalised and mirrored to be
// positive (a mirrored axis's stored index is the walked one xor (2^depth - 1)); the hit's cell is the
// first set cell walked, its axis the entry plane crossed last, its t that plane's crossing (exact models:
// the cell's entry against the hi/lo origin, entry_tau).
// The float arithmetic is `precise` (not contracted) in every kernel: trace.comp's colour mode and the pass
// kernels (WALK_PRECISE, cmake/shaders.cmake) must give the same t bits (test_passes), and a compiler may
// contract the setup's o + d te or length(d) in one and not the other (stop 77: 3 floats of a 5-sample frame
// apart on the H100). The loop's own arithmetic is explicit fma, min and max: nothing there to contract.
bool trace_model_grid(uint mi, uint groot, vec3 o, vec3 o_lo, vec3 d, float t0, float t1, bool any_hit, inout Hit h) {
    if (GRID_ALL && groot == NO_HIT) return false; // (a model without cells)
    Model m = model_at(mi);
    // the header (render_scene.c prepare_grids): the cells' box, which the ray is clipped to (tighter than
    // Model.box, the model's extent: a slab of cells in a large cube is walked only where it lies); GRID_FRAME:
    // the frame block's copy as floats
    vec3 blo = grid_frame_lo(), bhi = grid_frame_hi();
    if (!GRID_FRAME) {
        uvec3 hw = uvec3(gwords[groot], gwords[groot + 1u], gwords[groot + 2u]);
        blo = vec3(hw.x & 0xFFFFu, hw.x >> 16, hw.y & 0xFFFFu), bhi = vec3(hw.y >> 16, hw.z & 0xFFFFu, hw.z >> 16);
    }
    groot += 4u;
    precise vec2 tb = box_t(o, safe_inv(d), blo, bhi);
    precise float te = max(tb.x, t0), tx = min(tb.y, t1);
    if (!(te < tx)) return false;
    // the walk's cells: the grid's cube's (GRID_CUBE: its corner gorg; oa less it is exact, oa within the box,
    // below 2^16)
    vec3 gorg = vec3(0.0);
    uint depth = GRID_CUBE ? grid_cube(blo, bhi, m.depth, gorg) : max(m.depth, 3u);
    precise vec3 oa = o + d * te;
    if (GRID_CUBE) oa = oa - gorg;
    precise float L = length(d);
    precise vec3 dl = d / L;
    // tiny components would overflow the coefficients: at least 2^-23 (the octree walk's eps); a mirrored
    // axis keeps its sign, so -0 walks as negative, as safe_inv makes it
    precise vec3 ad = max(abs(dl), vec3(exp2(-23.0)));
    precise vec3 invd = 1.0 / ad;
    precise float tl1 = (tx - te) * L; // the ray's end in the walk's units
    uint top = GRID_TOP == 1u || GRID_EXACT ? GRID_TOP : grid_top(depth);
    uint R = 1u << (depth - 3u * top), N = 1u << depth;
    // The walk's coordinates start at the start cell's (mirrored) lower corner, not at the cube's: mirrored
    // about the cube's far side (2^depth - x), a start near the near side kept 2^(depth - 24) of a cell and
    // its cell decisions went wrong at depth 12 (test_render_gpu test_deep_float); from the start cell the
    // crossing times lose about (cells walked) 2^-24 of a cell. c0: the start cell (a ray on a plane lies in
    // the cell its direction leads into, as safe_inv displaces it), fr the start's offset in it (mirrored).
    bvec3 neg = bvec3(sign_neg(dl.x), sign_neg(dl.y), sign_neg(dl.z));
    precise vec3 c0 = clamp(mix(floor(oa), ceil(oa) - 1.0, neg), vec3(0.0), vec3(float(N - 1u)));
    precise vec3 fr = clamp(mix(oa - c0, (c0 + 1.0) - oa, neg), vec3(0.0), vec3(1.0));
    uvec3 flip = mix(uvec3(0u), uvec3(N - 1u), neg);
    uvec3 f0 = uvec3(c0) ^ flip; // the start cell, mirrored
    // Exact models (DEEP kernels): the hi/lo origin from the start cell's corner, oq = (o - c0) + o_lo, made here
    // so that the hit's exact t after the loop needs oq and d only, not o and o_lo: entry_tau (entry_tau.glsl)
    // of the hit cell's box in the start cell's frame, [rel, rel + 1], from oq (its planes' differences
    // rel - oq exact integers less oq)
    precise vec3 oq = vec3(0.0);
    if (DEEP >= 1 && (m.flags & 2u) != 0u) oq = (o - (GRID_CUBE ? c0 + gorg : c0)) + o_lo;
    ivec3 if0 = ivec3(f0);
    precise vec3 bias = -fr * invd;
    uint bflip = (flip.x & 7u) | ((flip.y & 7u) << 3) | ((flip.z & 7u) << 6); // a brick's bit index, mirrored
    // The mirrored axes as 3 bits across the loop, their index masks made where used: FLIP_SH(s) = flip >> s,
    // a mirrored axis's index at level s / 3 xor all ones (one register, not flip's three: stop 77, H100, 0.5-2%
    // more rays/s on the .vox scenes' views, and with the lookups below it 6% more on terrain4096's)
    uint negm = (neg.x ? 1u : 0u) | (neg.y ? 2u : 0u) | (neg.z ? 4u : 0u);
#define FLIP_SH(s) \
    mix(uvec3(0u), uvec3(((R << (3u * top)) - 1u) >> (s)), notEqual(uvec3(negm) & uvec3(1u, 2u, 4u), uvec3(0u)))

    precise float t = 0.0;
    // The coarse walk is on level-1 cells (bricks) whatever the root's level: at each coarse step the cell's
    // entry is looked up from the root down (top - 1 node loads below the root's, the upper ones cached), and
    // an empty entry at level k skips its empty cube at that level. So no level is kept across the loop and
    // none is climbed on leaving a node (stop 77, H100: terrain4096, root level 2, 6.6 steps a close-up ray
    // against 9.0 for the walk that kept its level, 1.13-1.23x its rays/s); where every root is at level 1,
    // GRID_TOP's constant folds the lookups away (the two-level loop).
    uint top3 = 3u * (top - 1u); // the shift from level-1 cells to the root's
    uvec3 f = f0;      // the cell (in a brick)
    uvec3 P = f >> 3u; // its level-1 cell
    bool fine = false;
    uint base0 = 0u; // the brick the walk is in
    uint steps = 0u;
    bool hit = false;
    // The loop's four parts (macros, so that each loop below is one text with them; comments here, as a
    // macro cannot hold them):
    // GRID_FINE: a brick's cells by the plain DDA; leaving it, the level-1 cell beside it (a hit past the ray's
    // end is refused after the loop: at most a brick's steps). The cell's 2^3 block (aligned; mirrored axes keep
    // the pairs): its 8 bits are rows y & 2 and +1, columns x & 6 and +1 of this word and of the word of the other
    // z of its pair (a word index's bit 1 is z's bit 0). An empty block is left in one step, where the cell by
    // cell walk would leave it: the planes crossed by the block's exit time tmin (tf its far planes; a lower
    // cell's far plane tc, the cell's own, is the block's middle one), the same cells and t as that walk's steps,
    // 0 pixels apart (stop 79, H100: 25-30% fewer steps on the .vox scenes' close-ups, 0.99-1.09x their rays/s,
    // the helmet 1.08-1.15x; a 4^3 block instead or after it, an extra load of 4 words: slower,
    // bench/results/p79c_h100.txt).
    // GRID_LOOKUP: P's entry w from the root down, s3 the shift from level-1 cells to w's level (a root at level
    // 1 holds the bricks).
    // GRID_ENTER: w is a brick: the cell the ray is in.
    // GRID_SKIP: w is empty at level s3 / 3 + 1: leave its empty cube [Pk - dist + 1, Pk + dist), or with
    // GRID_OCT its empty cube toward the ray's octant, [Pk, Pk + dist) in the walk's (mirrored) cells, dist its
    // distance plus the octant's extent (render/grid.h; stored coordinates: a mirrored axis is a negative
    // direction, negm's bit); either within its node below the root, in level-1 cells. The walk moves up only,
    // so both are left by their upper planes. Out of the cells' box or past the ray's end, the walk ends.
#define GRID_FINE \
            uint i = (((f.z & 7u) << 6) | ((f.y & 7u) << 3) | (f.x & 7u)) ^ bflip;                                  \
            uint wd = gwords[base0 + (i >> 5)];                                                                     \
            if (((wd >> (i & 31u)) & 1u) != 0u) { hit = true; break; }                                              \
            precise vec3 tc = fma(vec3(ivec3(f) - if0 + 1), invd, bias);                                            \
            precise float tmin;                                                                                     \
            if (((wd | gwords[base0 + ((i >> 5) ^ 2u)]) & (0x303u << (i & 0x16u))) == 0u) {                         \
                uvec3 fb = f | 1u;                                                                                  \
                precise vec3 tf = fma(vec3(ivec3(fb) - if0 + 1), invd, bias);                                       \
                tmin = min(min(tf.x, tf.y), tf.z);                                                                  \
                f = mix(mix(f, fb, lessThanEqual(tc, vec3(tmin))), fb + 1u, lessThanEqual(tf, vec3(tmin)));         \
            } else {                                                                                                \
                tmin = min(min(tc.x, tc.y), tc.z);                                                                  \
                f += uvec3(lessThanEqual(tc, vec3(tmin)));                                                          \
            }                                                                                                       \
            t = max(t, tmin);                                                                                       \
            uvec3 Pn = f >> 3u;                                                                                     \
            if (Pn == P) continue;                                                                                  \
            fine = false;                                                                                           \
            if (t >= tl1) break;                                                                                    \
            P = Pn;
#define GRID_LOOKUP \
            uvec3 q = (P >> top3) ^ FLIP_SH(3u * top);                                                              \
            uint w = gwords[groot + (q.z * R + q.y) * R + q.x];                                                     \
            uint s3 = top3;                                                                                         \
            if (w < 0x80000000u && top == 3u) {                                                                     \
                q = ((P >> 3u) ^ FLIP_SH(6u)) & 7u;                                                                 \
                w = gwords[w + (q.x | (q.y << 3) | (q.z << 6))];                                                    \
                s3 = 3u;                                                                                            \
            }                                                                                                       \
            if (w < 0x80000000u && top >= 2u) {                                                                     \
                q = (P ^ FLIP_SH(3u)) & 7u;                                                                         \
                w = gwords[w + (q.x | (q.y << 3) | (q.z << 6))];                                                    \
                s3 = 0u;                                                                                            \
            }
#define GRID_ENTER \
                uvec3 lo8 = P << 3u;                                                                                \
                uvec3 c = f0 + uvec3(max(fma(vec3(t), ad, fr), vec3(0.0)));                                         \
                fine = true;                                                                                        \
                base0 = w;                                                                                          \
                f = clamp(c, lo8, lo8 + 7u);
#define GRID_SKIP \
            uint dist = GRID_OCT ? (w & 0x7Fu) + ((w >> (7u + 3u * negm)) & 7u) : w & 0x7Fu;                         \
            uvec3 Pk = P >> s3;                                                                                     \
            uvec3 up = Pk + dist;                                                                                   \
            if (s3 < top3) up = min(up, (Pk | 7u) + 1u);                                                            \
            up <<= s3;                                                                                              \
            precise vec3 tc = fma(vec3(ivec3(up << 3u) - if0), invd, bias);                                         \
            precise float tmin = min(min(tc.x, tc.y), tc.z);                                                        \
            t = max(t, tmin);                                                                                       \
            uvec3 Pn = P;                                                                                           \
            if (dist > 1u || s3 > 0u)                                                                               \
                Pn = clamp((f0 + uvec3(max(fma(vec3(tmin), ad, fr), vec3(0.0)))) >> 3u, P, up - 1u);                \
            Pn = mix(Pn, up, lessThanEqual(tc, vec3(tmin)));                                                        \
            if (t >= tl1) break;                                                                                    \
            P = Pn;
    // Where a root may lie above level 1 (GRID_TOP >= 2: the lookup makes 2 or 3 dependent loads), a ray that
    // enters a brick takes its first cell step in the same iteration (lanes entering bricks join those in
    // bricks): terrain4096 (root level 2) 1.07-1.15x its rays/s on the H100, 0 pixels apart; on the scenes whose
    // roots are at level 1 the same loop was up to 14% slower, so they keep the if-else loop (stop 79,
    // bench/results/p79d_h100.txt and p79e_h100.txt).
    if (GRID_TOP >= 2u) {
        while (steps < MAX_ITER) {
            steps++;
            if (!fine) {
                GRID_LOOKUP
                if (w < 0x80000000u) {
                    GRID_ENTER
                } else {
                    GRID_SKIP
                    if (max(max(P.x, P.y), P.z) >= (R << top3)) break; // out of the root
                    continue;
                }
            }
            GRID_FINE
            if (max(max(P.x, P.y), P.z) >= (R << top3)) break;
        }
    } else {
        while (steps < MAX_ITER) {
            steps++;
            if (fine) {
                GRID_FINE
            } else {
                GRID_LOOKUP
                if (w < 0x80000000u) {
                    GRID_ENTER
                    continue;
                }
                GRID_SKIP
            }
            if (max(max(P.x, P.y), P.z) >= (R << top3)) break; // out of the root
        }
    }
#undef GRID_FINE
#undef GRID_LOOKUP
#undef GRID_ENTER
#undef GRID_SKIP
    if (MODE == MODE_ITER || WRITE_HITS) g_iter += steps; // (the iteration image, the hits' step counts)
    if (!hit) return false;
    flip = FLIP_SH(0u);
#undef FLIP_SH
    uvec3 cell = f ^ flip; // (in the grid's cube; the model's after the exact t below)
    // the hit cell's entry: the last of its entry planes crossed (mirrored: its lower planes), in the walk's
    // units from the box entry; 0 where the ray starts in it. Exact models (deeper than VX_RENDER_EXACT_DEPTH,
    // DEEP kernels) take t from the cell's planes against the hi/lo origin instead (entry_tau, from oq made at
    // the setup), as trace_model; elsewhere o, d and o_lo need not live across the loop (registers, occupancy).
    precise vec3 tent = fma(vec3(ivec3(f) - if0), invd, bias);
    // an axis the ray runs along (its component under 2^-23, walked as 2^-23: invd at 2^23) crosses none of
    // the cell's planes, so it is never the hit's, as in the CPU reference (render/cpu_trace.c: -inf). Without
    // this, a ray on a cell edge that enters its cell across the box's face ties its -0 there with the face
    // axis's -0, and the first axis won: straight-down rays on x = 7.0 shaded with the x face's normal
    // (test_sky's top face, 0.485 off, found when lavapipe took the grid walk by default in stop 87)
    tent = mix(tent, vec3(uintBitsToFloat(0xFF800000u)), greaterThanEqual(invd, vec3(exp2(23.0))));
    int axis = 0;
    precise float ta = tent.x;
    if (tent.y > ta) { axis = 1; ta = tent.y; }
    if (tent.z > ta) { axis = 2; ta = tent.z; }
    precise float th = te + max(ta, 0.0) / L;
    if (DEEP >= 1 && (m.flags & 2u) != 0u)
        th = max(entry_tau(oq, vec3(0.0), d, vec3(ivec3(cell) - ivec3(f0 ^ flip)), 1.0), te);
    if (!(th <= h.t)) return false;
    h.t = th;
    if (any_hit) return true;
    // the model's cell (GRID_CUBE): the cube's corner again from the header (the frame block's box, or the
    // header's words: cheaper to load again than to hold across the loop)
    if (GRID_CUBE) {
        vec3 clo = grid_frame_lo(), chi = grid_frame_hi(), corg;
        if (!GRID_FRAME) {
            uvec3 hw = uvec3(gwords[groot - 4u], gwords[groot - 3u], gwords[groot - 2u]);
            clo = vec3(hw.x & 0xFFFFu, hw.x >> 16, hw.y & 0xFFFFu), chi = vec3(hw.y >> 16, hw.z & 0xFFFFu, hw.z >> 16);
        }
        grid_cube(clo, chi, m.depth, corg);
        cell += uvec3(corg);
    }
    uint fa = axis == 0 ? flip.x : (axis == 1 ? flip.y : flip.z); // mirrored: the direction's sign bit set
    uint mflags = m.flags;
    if (GRID_UNION) {
        // the union (render_scene.c grid_union), its table's word 0: regions (below bit 31: the hit cell's
        // cube of 2^shift cells holds one instance; its entry: the instance and its model's offset in the
        // union's cells) or turned instances
        uint tb = grid_union_table();
        uint t0 = gwords[tb];
        if (t0 < 0x80000000u) {
            uvec3 rc = cell >> t0;
            uint e = tb + 4u + 4u * ((rc.z * gwords[tb + 2u] + rc.y) * gwords[tb + 1u] + rc.x);
            h.inst = gwords[e];
            cell -= uvec3(gwords[e + 1u], gwords[e + 2u], gwords[e + 3u]);
        } else {
            // turned instances (render_scene.c prepare_union_turned): the hit brick's owner word, the instance
            // whose cells fill it or (bit 31) the address of its set cells' instances, 16 bits each in bit order
            uint ow = gwords[gwords[tb + 1u] + (base0 >> 4)];
            if (ow >= 0x80000000u) {
                uint i = (cell.z & 7u) << 6 | (cell.y & 7u) << 3 | (cell.x & 7u), rank = 0u;
                for (uint k = 0u; k < (i >> 5); k++) rank += uint(bitCount(gwords[base0 + k]));
                rank += uint(bitCount(gwords[base0 + (i >> 5)] & ((1u << (i & 31u)) - 1u)));
                ow = (gwords[(ow & 0x7FFFFFFFu) + (rank >> 1)] >> (16u * (rank & 1u))) & 0xFFFFu;
            }
            uint e = tb + 4u + 4u * ow, w0 = gwords[e];
            h.inst = w0 & 0xFFFFu;
            // model axis c: union axis ax[c], sign bit sg[c]; p_c = s_c u_ax[c] + o_c
            uvec3 ax = uvec3(w0 >> 16, w0 >> 18, w0 >> 20) & 3u;
            bvec3 sg = notEqual(uvec3(w0 >> 22, w0 >> 23, w0 >> 24) & 1u, uvec3(0u));
            ivec3 u = ivec3(cell);
            ivec3 up = ivec3(u[ax.x], u[ax.y], u[ax.z]);
            cell = uvec3(mix(up, -up, sg) + ivec3(gwords[e + 1u], gwords[e + 2u], gwords[e + 3u]));
            uint ua = uint(axis);
            int ma = ax.x == ua ? 0 : (ax.y == ua ? 1 : 2);
            // the face's side: the ray's sign along the hit axis, negated on a mirrored model axis
            if (sg[ma]) fa = fa != 0u ? 0u : 1u;
            axis = ma;
        }
        mi = INST_AT(h.inst).model;
        mflags = model_at(mi).flags;
    }
    h.cell = cell;
    h.axis = axis;
    h.nsign = fa != 0u ? 1.0 : -1.0;
    h.color = 0xFFFFFFFFu;
    h.attr = NO_HIT;
    // the record: one descent of the octree (from the brick), only where the kernel reads it (GRID_RECORD)
    if (HAS_COLOR && GRID_RECORD && (mflags & 1u) != 0u) {
        // from the hit brick's record word where the grid has them (the header's word 3, its record key: brick
        // word address w has its record at key + (w >> 4); 0 none, render/grid.h): the last 3 levels, not all
        uint rk = gwords[groot - 1u], a, level;
        if (rk != 0u) a = model_cell_leaf_brick(mi, cell, gwords[rk + (base0 >> 4)]);
        else a = model_cell_leaf(mi, cell, level);
        if (a != NO_HIT) {
            h.attr = a;
            h.color = colors[a];
        }
    }
    return true;
}
