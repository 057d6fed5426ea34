/* render/compact_trace.c - a CPU traversal of the compact layout
 * (render/compact.h): the CPU reference's rays and rules (render/cpu_trace.c,
 * double precision, a DDA that steps over the largest empty block holding
 * the current cell), with every question about a cell answered by a descent
 * of the compact geometry DAG instead of the reference's occupancy table of
 * the decoded voxels, and the colour decoded from the attribute index the
 * descent sums (vx_compact_rgba). So the (instance, cell, colour) it returns
 * checks the layout, not a second copy of the reference: the reference never
 * reads the compact arrays. */
#include <math.h>
#include <string.h>

#include "render/compact.h"
#include "render/instance_ray.h"
#include "render/trace.h"

static uint32_t popc(uint32_t m) { return (uint32_t)__builtin_popcount(m); }

/* Cell (x, y, z) of model m, inside its cube. Returns the level k of the
 * smallest block holding the cell that has set cells (the reference's
 * table: the block of level k - 1 around the cell is empty), or, when the
 * cell is set, true in *full with its attribute index in *index and k the
 * level of the full cube it lies in (0 inside bricks). */
static uint32_t probe(const vx_compact_scene* c, const vx_compact_model* m, uint32_t x, uint32_t y, uint32_t z,
                      bool* full, uint32_t* index) {
    *full = false;
    uint32_t L = m->depth;
    if (m->root == VX_SVO_ROOT_LEAF) {
        *full = true;
        *index = (uint32_t)vx_svo_morton(x, y, z);
        return L;
    }
    uint32_t n = m->root;
    uint64_t base = 0;
    for (; L >= 3; L--) {
        const uint32_t* sl = c->geom + 2 * (size_t)n;
        uint32_t valid = (sl[0] >> 8) & 0xFFu, leaf = sl[0] & 0xFFu, inner = valid & ~leaf;
        uint32_t s = L - 1, o = ((x >> s) & 1u) | (((y >> s) & 1u) << 1) | (((z >> s) & 1u) << 2);
        if (!((valid >> o) & 1u)) return L;
        uint32_t below = (1u << o) - 1u, k = popc(inner & below);
        base += ((uint64_t)popc(leaf & below) << (3 * s)) + vx__compact_inner_before(c, L, sl[1], k);
        if ((leaf >> o) & 1u) {
            uint32_t mask = (1u << s) - 1u;
            *full = true;
            *index = (uint32_t)(base + vx_svo_morton(x & mask, y & mask, z & mask));
            return s;
        }
        n = vx__compact_child(c, L, sl[1], k);
    }
    /* a brick: 4^3 cells (level 2) or 2^3 (a model of depth 1) */
    uint64_t mask = c->geom[2 * (size_t)n] | (uint64_t)c->geom[2 * (size_t)n + 1] << 32;
    uint32_t r = (1u << L) - 1u, bit = (uint32_t)vx_svo_morton(x & r, y & r, z & r);
    if (L == 2 && !((mask >> (bit & ~7u)) & 0xFFu)) return 2;
    if (!((mask >> bit) & 1u)) return 1;
    *full = true;
    *index = (uint32_t)(base + (uint64_t)__builtin_popcountll(mask & ((1ull << bit) - 1u)));
    return 0;
}

typedef struct khit {
    double t;
    int64_t cell[3];
    uint32_t index;
    uint32_t steps;
    bool amb;
} khit;

/* The reference's walk (cpu_trace.c cm_trace: its box entry and steps, render/instance_ray.h and
 * vx__grid_step_out), with probe() for its table. */
static bool trace_model(const vx_compact_scene* c, const vx_compact_model* m, const uint32_t size[3],
                        const double o[3], const double d[3], double t1, khit* h) {
    if (m->root == VX_SVO_ROOT_EMPTY) return false;
    vx__box_entry en;
    if (!vx__box_enter(size, o, d, 0.0, t1, &en)) return false;
    int64_t cell[3] = {en.cell[0], en.cell[1], en.cell[2]};
    double tx = en.tx;
    bool amb = en.amb;
    double t = en.te;
    for (uint32_t steps = 0; steps < 100000000u; steps++) {
        bool full;
        uint32_t index = 0;
        uint32_t k = probe(c, m, (uint32_t)cell[0], (uint32_t)cell[1], (uint32_t)cell[2], &full, &index);
        h->steps = steps + 1;
        if (full) {
            if (!(t <= h->t)) return false;
            h->t = t;
            memcpy(h->cell, cell, sizeof cell);
            h->index = index;
            h->amb = amb;
            return true;
        }
        int64_t B = (int64_t)1 << (k - 1);
        if (!vx__grid_step_out(cell, B, o, d, tx, size, &t, &amb)) return false;
    }
    return false;
}

vx_result vx_compact_render_cpu(const vx_compact_scene* c, const vx_svo_scene* s, const vx_render_desc* desc,
                                const vx_allocator* alloc, vx_render_image* out, vx_error* err) {
    if (!c || !s || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    if (c->model_count != s->model_count)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "the compact scene has %u models, the scene %u",
                       c->model_count, s->model_count);
    if (desc && desc->mode != VX_RENDER_ALBEDO)
        return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "mode %s: only albedo", vx_render_mode_name(desc->mode));
    double t_begin = vx_time_now();
    vx_result r = vx__check_scene(s, err);
    if (r) return r;
    double lo[3], hi[3];
    vx_svo_scene_world_bounds(s, lo, hi);
    vx__frame f;
    if ((r = vx__frame_setup(lo, hi, desc, &f, err))) return r;
    uint32_t ni = 0;
    vx__inst_map* maps = vx_calloc(alloc, s->instance_count ? s->instance_count : 1, sizeof *maps);
    size_t npx = (size_t)f.width * f.height;
    vx_render_image img = {.width = f.width, .height = f.height, .mode = f.mode, .alloc = alloc};
    img.pixels = vx_calloc(alloc, npx, 16);
    img.hits = vx_calloc(alloc, npx, sizeof *img.hits);
    if (!maps || !img.pixels || !img.hits) {
        vx_free(alloc, maps);
        vx_render_image_free(&img);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for a %ux%u image", f.width, f.height);
    }
    vx__inst_maps(s, maps, &ni, NULL); /* checked above */
    for (uint32_t y = 0; y < f.height; y++)
        for (uint32_t x = 0; x < f.width; x++) {
            /* the centre ray of the pixel, as vx_render_cpu makes it */
            double u = ((x + 0.5) / f.width) * 2 - 1, v = 1 - ((y + 0.5) / f.height) * 2;
            double P[3], o[3], d[3];
            double t_off = vx__frame_ray(&f, u, v, P, o, d);
            khit best = {.t = INFINITY};
            uint32_t which = UINT32_MAX, steps = 0;
            for (uint32_t i = 0; i < ni; i++) {
                double om[3], dm[3];
                vx__inst_ray(&maps[i], o, d, om, dm);
                uint32_t mi = maps[i].model;
                khit h = best;
                h.steps = 0;
                bool hit = trace_model(c, &c->models[mi], s->models[mi].size, om, dm, best.t, &h);
                steps += h.steps;
                if (hit) best = h, which = i;
            }
            float* px = &img.pixels[4 * ((size_t)y * f.width + x)];
            vx_render_hit* hh = &img.hits[(size_t)y * f.width + x];
            hh->iterations = steps;
            if (which == UINT32_MAX) {
                px[0] = VX__SKY_R, px[1] = VX__SKY_G, px[2] = VX__SKY_B, px[3] = 0;
                hh->instance = VX_RENDER_NO_HIT;
                continue;
            }
            uint32_t col = vx_compact_rgba(c, maps[which].model, best.index);
            px[0] = (float)((col & 0xFF) / 255.0), px[1] = (float)(((col >> 8) & 0xFF) / 255.0);
            px[2] = (float)(((col >> 16) & 0xFF) / 255.0), px[3] = 1;
            hh->instance = maps[which].id;
            for (int k = 0; k < 3; k++) hh->cell[k] = (uint32_t)best.cell[k];
            hh->t = (float)(t_off + best.t);
            hh->flags = best.amb ? VX_RENDER_HIT_AMBIGUOUS : 0;
        }
    vx_free(alloc, maps);
    img.gpu_seconds = vx_time_now() - t_begin;
    img.rays = npx;
    *out = img;
    return VX_OK;
}
