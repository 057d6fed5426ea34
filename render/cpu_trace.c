/* render/cpu_trace.c - the CPU reference tracer: double precision, a brute
 * force loop over the instances and, per model, a 3D-DDA over the decoded
 * voxels. Empty space is skipped with an occupancy hash of every level
 * (a cell's largest empty enclosing block is stepped over at once), so
 * octrees 20 levels deep stay affordable; the stepping rule is the plain
 * DDA's: leave the current block through the nearest planes, all tied axes
 * at once. Shares nothing with the GPU path but the camera set-up. */
#include <math.h>
#include <string.h>

#include "render/instance_ray.h"
#include "render/trace.h"

typedef struct centry {
    uint64_t key; /* (block key << 5 | level) + 1; 0 = free slot */
    uint32_t attr;
    uint32_t full;
} centry;

typedef struct cmodel {
    const vx_svo_model* m;
    centry* tab;
    size_t cap, used;
    bool failed;
    const vx_allocator* alloc;
} cmodel;

static uint64_t hash64(uint64_t k) {
    k ^= k >> 33;
    k *= 0xff51afd7ed558ccdULL;
    k ^= k >> 33;
    k *= 0xc4ceb9fe1a85ec53ULL;
    k ^= k >> 33;
    return k;
}

static centry* cm_find(const cmodel* c, uint64_t block, uint32_t level) {
    uint64_t key = ((block << 5) | level) + 1;
    size_t i = hash64(key) & (c->cap - 1);
    while (c->tab[i].key) {
        if (c->tab[i].key == key) return &c->tab[i];
        i = (i + 1) & (c->cap - 1);
    }
    return NULL;
}

static bool cm_grow(cmodel* c) {
    size_t ncap = c->cap ? c->cap * 2 : 1024;
    centry* nt = vx_calloc(c->alloc, ncap, sizeof *nt);
    if (!nt) return false;
    for (size_t i = 0; i < c->cap; i++) {
        if (!c->tab[i].key) continue;
        size_t j = hash64(c->tab[i].key) & (ncap - 1);
        while (nt[j].key) j = (j + 1) & (ncap - 1);
        nt[j] = c->tab[i];
    }
    vx_free(c->alloc, c->tab);
    c->tab = nt;
    c->cap = ncap;
    return true;
}

/* Inserts; returns false if it was present already. */
static bool cm_put(cmodel* c, uint64_t block, uint32_t level, uint32_t attr, bool full) {
    if ((c->used + 1) * 2 > c->cap && !cm_grow(c)) {
        c->failed = true;
        return false;
    }
    uint64_t key = ((block << 5) | level) + 1;
    size_t i = hash64(key) & (c->cap - 1);
    while (c->tab[i].key) {
        if (c->tab[i].key == key) {
            if (full) c->tab[i].full = 1, c->tab[i].attr = attr;
            return false;
        }
        i = (i + 1) & (c->cap - 1);
    }
    c->tab[i] = (centry){key, attr, full};
    c->used++;
    return true;
}

/* key >> 3 * level, also for the level above a 21-deep root (shift >= 64) */
static uint64_t block_of(uint64_t key, uint32_t level) { return 3 * level >= 64 ? 0 : key >> (3 * level); }

static void add_leaf(cmodel* c, uint32_t x, uint32_t y, uint32_t z, uint32_t level, uint32_t attr) {
    uint64_t k = vx_svo_morton(x, y, z);
    cm_put(c, block_of(k, level), level, attr, true);
    for (uint32_t j = level + 1; j <= c->m->depth + 1; j++)
        if (!cm_put(c, block_of(k, j), j, 0, false)) break;
}

static bool decode_cb(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    cmodel* c = user;
    add_leaf(c, x, y, z, 0, attr);
    return !c->failed;
}

/* Leaf walk for models whose collapsed leaves are too large to expand. */
static void walk(cmodel* c, uint32_t word, uint32_t level, uint32_t x, uint32_t y, uint32_t z, int guard) {
    const vx_svo_model* m = c->m;
    if (guard > 24 || word >= m->node_count || c->failed) return;
    uint32_t d = m->nodes[word];
    uint32_t valid = vx_svo_desc_valid(d), leaf = vx_svo_desc_leaf(d);
    uint32_t blk = word - vx_svo_desc_ptr(d);
    if (vx_svo_desc_far(d) && blk < m->node_count) blk = m->nodes[blk];
    uint32_t nl = (uint32_t)__builtin_popcount(valid & ~leaf);
    uint32_t a = (m->attrs && blk + nl < m->node_count) ? m->nodes[blk + nl] : 0;
    uint32_t half = 1u << (level - 1);
    for (uint32_t o = 0; o < 8; o++) {
        if (!((valid >> o) & 1)) continue;
        uint32_t cx = x + (o & 1) * half, cy = y + ((o >> 1) & 1) * half, cz = z + ((o >> 2) & 1) * half;
        if ((leaf >> o) & 1)
            add_leaf(c, cx, cy, cz, level - 1, a + (uint32_t)__builtin_popcount(valid & ((1u << o) - 1)));
        else
            walk(c, blk + (uint32_t)__builtin_popcount(valid & ~leaf & ((1u << o) - 1)), level - 1, cx, cy, cz,
                 guard + 1);
    }
}

static vx_result cm_build(cmodel* c, const vx_svo_model* m, const vx_allocator* alloc, vx_error* err) {
    memset(c, 0, sizeof *c);
    c->m = m;
    c->alloc = alloc;
    if (!cm_grow(c)) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    if (m->root == VX_SVO_ROOT_EMPTY) return VX_OK;
    if (m->root == VX_SVO_ROOT_LEAF) {
        add_leaf(c, 0, 0, 0, m->depth, m->root_attr);
    } else if (m->voxel_count <= (1u << 22)) {
        /* the svo library's decoder: an independent reading of the nodes */
        vx_result r = vx_svo_decode_model(m, decode_cb, c, err);
        if (r) return r;
    } else {
        walk(c, m->root, m->depth, 0, 0, 0, 0);
    }
    if (c->failed) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for the CPU reference");
    return VX_OK;
}

static bool neg(double v) { return signbit(v) != 0; }

bool vx__grid_step_out(int64_t cell[3], int64_t B, const double o[3], const double d[3], double tx,
                       const uint32_t size[3], double* t, bool* amb) {
    int64_t lo[3];
    double ta[3], texit = INFINITY;
    for (int a = 0; a < 3; a++) {
        lo[a] = cell[a] & ~(B - 1);
        if (d[a] == 0)
            ta[a] = INFINITY;
        else
            ta[a] = ((double)(d[a] > 0 ? lo[a] + B : lo[a]) - o[a]) / d[a];
        texit = fmin(texit, ta[a]);
    }
    if (!(texit < tx)) return false;
    /* near ties count too: the double ray itself is rounded */
    double near = 1e-9 * fmax(1, fabs(texit));
    if ((fabs(ta[0] - texit) <= near) + (fabs(ta[1] - texit) <= near) + (fabs(ta[2] - texit) <= near) > 1) *amb = true;
    for (int a = 0; a < 3; a++) {
        if (ta[a] == texit) {
            cell[a] = d[a] > 0 ? lo[a] + B : lo[a] - 1;
        } else {
            int64_t q = vx__cell_of(o[a] + d[a] * texit, d[a]);
            if (q < lo[a]) q = lo[a];
            if (q > lo[a] + B - 1) q = lo[a] + B - 1;
            cell[a] = q;
        }
        if (cell[a] < 0 || cell[a] >= (int64_t)size[a]) return false;
    }
    *t = texit;
    return true;
}

typedef struct chit {
    double t;
    int64_t cell[3];
    int axis;
    double nsign;
    uint32_t attr;
    uint32_t steps;
    bool amb;
} chit;

static bool cm_trace(const cmodel* c, const double o[3], const double d[3], double t0, double t1, bool any, chit* h) {
    const vx_svo_model* m = c->m;
    if (m->root == VX_SVO_ROOT_EMPTY) return false;
    vx__box_entry en;
    if (!vx__box_enter(m->size, o, d, t0, t1, &en)) return false;
    int64_t cell[3] = {en.cell[0], en.cell[1], en.cell[2]};
    double tx = en.tx;
    bool amb = en.amb;
    double t = en.te;
    for (uint32_t steps = 0; steps < 100000000u; steps++) {
        uint64_t key = vx_svo_morton((uint32_t)cell[0], (uint32_t)cell[1], (uint32_t)cell[2]);
        uint32_t k = 0;
        const centry* e = NULL;
        for (; k <= m->depth + 1; k++) {
            e = cm_find(c, block_of(key, k), k);
            if (e) break;
        }
        if (!e) return false; /* nothing anywhere (cannot happen for a non-empty model) */
        h->steps = steps + 1;
        if (e->full) {
            if (!(t <= h->t)) return false;
            h->t = t;
            if (any) return true;
            int64_t B = (int64_t)1 << k;
            double best = -INFINITY;
            int axis = 0;
            for (int a = 0; a < 3; a++) {
                int64_t lo = cell[a] & ~(B - 1);
                double plane = neg(d[a]) ? (double)(lo + B) : (double)lo;
                double ta = d[a] == 0 ? -INFINITY : (plane - o[a]) / d[a];
                if (ta > best) best = ta, axis = a;
            }
            memcpy(h->cell, cell, sizeof cell);
            h->axis = axis;
            h->nsign = neg(d[axis]) ? 1.0 : -1.0;
            h->attr = e->attr;
            h->amb = amb;
            return true;
        }
        /* step over the largest empty block containing the cell (level k-1) */
        int64_t B = (int64_t)1 << (k - 1);
        if (!vx__grid_step_out(cell, B, o, d, tx, m->size, &t, &amb)) return false;
    }
    return false;
}

typedef struct cscene {
    const vx_svo_scene* s;
    cmodel* models;
    vx__inst_map* inst;
    uint32_t n;
} cscene;

/* skip: a scene instance index passed over (UINT32_MAX: none; vx_render_cast_skip) */
static bool trace_scene(const cscene* cs, const double o[3], const double d[3], bool any, chit* best, uint32_t* which,
                        uint32_t* steps, uint32_t skip) {
    bool found = false;
    for (uint32_t i = 0; i < cs->n; i++) {
        const vx__inst_map* in = &cs->inst[i];
        if (in->id == skip) continue;
        double om[3], dm[3];
        vx__inst_ray(in, o, d, om, dm);
        chit h = *best;
        h.steps = 0;
        bool hit = cm_trace(&cs->models[in->model], om, dm, 0.0, best->t, any, &h);
        *steps += h.steps;
        if (hit) {
            *best = h;
            *which = i;
            found = true;
            if (any) return true;
        }
    }
    return found;
}

vx_result vx__inst_maps(const vx_svo_scene* s, vx__inst_map* out, uint32_t* n, vx_error* err) {
    *n = 0;
    vx_result r = vx__check_scene(s, err);
    if (r) return r;
    uint32_t k = 0;
    for (uint32_t i = 0; i < s->instance_count; i++) {
        if (!vx_svo_instance_drawn(s, i)) continue;
        vx__inst_map* ci = &out[k++];
        double w[12];
        vx_svo_instance_world(s, &s->instances[i], w);
        vx__affine_inverse(w, ci->inv); /* invertible: vx__check_scene */
        ci->model = s->instances[i].model;
        ci->id = i;
        ci->cell = 0;
        for (int c = 0; c < 3; c++) ci->cell = fmax(ci->cell, sqrt(w[c] * w[c] + w[4 + c] * w[4 + c] + w[8 + c] * w[8 + c]));
        ci->cell = (double)(float)ci->cell;
    }
    *n = k;
    return VX_OK;
}

static vx_result cscene_build(cscene* cs, const vx_svo_scene* s, const vx_allocator* alloc, vx_error* err) {
    memset(cs, 0, sizeof *cs);
    cs->s = s;
    cs->models = vx_calloc(alloc, s->model_count ? s->model_count : 1, sizeof *cs->models);
    cs->inst = vx_calloc(alloc, s->instance_count ? s->instance_count : 1, sizeof *cs->inst);
    if (!cs->models || !cs->inst) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    vx_result r = vx__inst_maps(s, cs->inst, &cs->n, err);
    for (uint32_t i = 0; !r && i < cs->n; i++) {
        uint32_t mi = cs->inst[i].model;
        if (!cs->models[mi].tab) r = cm_build(&cs->models[mi], &s->models[mi], alloc, err);
    }
    return r;
}

static void cscene_free(cscene* cs, const vx_allocator* alloc) {
    if (cs->models)
        for (uint32_t i = 0; i < cs->s->model_count; i++) vx_free(alloc, cs->models[i].tab);
    vx_free(alloc, cs->models);
    vx_free(alloc, cs->inst);
}

vx_result vx_render_cpu(const vx_svo_scene* s, const vx_render_desc* desc, const vx_allocator* alloc,
                        vx_render_image* out, vx_error* err) {
    if (!s || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    double t_begin = vx_time_now();
    double lo[3], hi[3];
    vx_svo_scene_world_bounds(s, lo, hi);
    vx__frame f;
    vx_result r = vx__frame_setup(lo, hi, desc, &f, err);
    if (r) return r;
    bool want_hits = desc && desc->want_hits;
    cscene cs;
    if ((r = cscene_build(&cs, s, alloc, err))) {
        cscene_free(&cs, alloc);
        return r;
    }
    size_t npx = (size_t)f.width * f.height;
    vx_render_image img = {.width = f.width, .height = f.height, .mode = f.mode, .alloc = alloc};
    img.pixels = vx_calloc(alloc, npx, 16);
    if (want_hits) img.hits = vx_calloc(alloc, npx, sizeof *img.hits);
    if (!img.pixels || (want_hits && !img.hits)) {
        cscene_free(&cs, alloc);
        vx_render_image_free(&img);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for a %ux%u image", f.width, f.height);
    }
    for (uint32_t y = 0; y < f.height; y++) {
        for (uint32_t x = 0; x < f.width; x++) {
            double acc[4] = {0};
            for (uint32_t sidx = 0; sidx < f.spp; sidx++) {
                double ox, oy;
                vx__sample_offset(sidx, &ox, &oy);
                double u = ((x + 0.5 + ox) / f.width) * 2 - 1, v = 1 - ((y + 0.5 + oy) / f.height) * 2;
                double P[3], o[3], d[3];
                double t_off = vx__frame_ray(&f, u, v, P, o, d);
                chit h = {.t = INFINITY};
                uint32_t which = 0, steps = 0;
                bool hit = trace_scene(&cs, o, d, false, &h, &which, &steps, UINT32_MAX);
                double c[4] = {0};
                double nw[3] = {0};
                const vx__inst_map* in = hit ? &cs.inst[which] : NULL;
                if (hit) {
                    const double* row = &in->inv[4 * h.axis];
                    double l = sqrt(row[0] * row[0] + row[1] * row[1] + row[2] * row[2]);
                    for (int k = 0; k < 3; k++) nw[k] = h.nsign * row[k] / l;
                }
                if (f.mode == VX_RENDER_COLOR || f.mode == VX_RENDER_ALBEDO) {
                    if (!hit) {
                        c[0] = VX__SKY_R, c[1] = VX__SKY_G, c[2] = VX__SKY_B;
                    } else {
                        const vx_svo_model* m = &s->models[in->model];
                        uint32_t col = m->attrs ? vx_svo_attr_rgba(s, m, h.attr) : 0xFFFFFFFFu;
                        double alb[3] = {(col & 0xFF) / 255.0, ((col >> 8) & 0xFF) / 255.0, ((col >> 16) & 0xFF) / 255.0};
                        double shade = 1;
                        if (f.mode == VX_RENDER_COLOR) {
                            double ndl = fmax(0, nw[0] * f.light[0] + nw[1] * f.light[1] + nw[2] * f.light[2]);
                            double vis = 0;
                            if (ndl > 0) {
                                double prel[3], pmax = 0;
                                for (int k = 0; k < 3; k++) prel[k] = P[k] + d[k] * h.t, pmax = fmax(pmax, fabs(prel[k]));
                                double eps = in->cell * 1e-3 + 4e-6 * pmax;
                                double ps[3];
                                for (int k = 0; k < 3; k++) ps[k] = o[k] + d[k] * h.t + nw[k] * eps;
                                chit sh = {.t = INFINITY};
                                uint32_t sw, ss = 0;
                                vis = trace_scene(&cs, ps, f.light, true, &sh, &sw, &ss, UINT32_MAX) ? 0 : 1;
                            }
                            shade = f.ambient + (1 - f.ambient) * ndl * vis;
                        }
                        for (int k = 0; k < 3; k++) c[k] = alb[k] * shade;
                        c[3] = 1;
                    }
                } else if (f.mode == VX_RENDER_NORMAL) {
                    c[0] = nw[0], c[1] = nw[1], c[2] = nw[2], c[3] = hit;
                } else if (f.mode == VX_RENDER_DEPTH) {
                    double t = hit ? t_off + h.t : INFINITY;
                    c[0] = c[1] = c[2] = t, c[3] = hit;
                } else if (f.mode == VX_RENDER_INSTANCE) {
                    if (hit) {
                        float rgb[3];
                        vx__instance_color(in->id, rgb);
                        c[0] = rgb[0], c[1] = rgb[1], c[2] = rgb[2], c[3] = 1;
                    }
                } else {
                    float rgb[3];
                    vx__heat_color(steps, rgb);
                    c[0] = rgb[0], c[1] = rgb[1], c[2] = rgb[2], c[3] = 1;
                }
                for (int k = 0; k < 4; k++) acc[k] += c[k];
                if (want_hits && sidx == 0) {
                    vx_render_hit* hh = &img.hits[(size_t)y * f.width + x];
                    hh->instance = hit ? in->id : VX_RENDER_NO_HIT;
                    for (int k = 0; k < 3; k++) hh->cell[k] = hit ? (uint32_t)h.cell[k] : 0;
                    hh->t = hit ? (float)(t_off + h.t) : 0;
                    hh->iterations = steps;
                    hh->flags = hit && h.amb ? VX_RENDER_HIT_AMBIGUOUS : 0;
                }
            }
            float* px = &img.pixels[4 * ((size_t)y * f.width + x)];
            for (int k = 0; k < 4; k++) px[k] = (float)(acc[k] / f.spp);
        }
    }
    cscene_free(&cs, alloc);
    img.gpu_seconds = vx_time_now() - t_begin;
    img.rays = (uint64_t)npx * f.spp;
    *out = img;
    return VX_OK;
}

/* ---- single-ray queries ------------------------------------------------------------- */

struct vx_render_caster {
    cscene cs;
    const vx_allocator* alloc;
};

vx_result vx_render_caster_create(const vx_svo_scene* s, const vx_allocator* alloc, vx_render_caster** out,
                                  vx_error* err) {
    if (!s || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    vx_render_caster* c = vx_calloc(alloc, 1, sizeof *c);
    if (!c) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    c->alloc = alloc;
    vx_result r = cscene_build(&c->cs, s, alloc, err);
    if (r) {
        cscene_free(&c->cs, alloc);
        vx_free(alloc, c);
        return r;
    }
    *out = c;
    return VX_OK;
}

void vx_render_caster_destroy(vx_render_caster* c) {
    if (!c) return;
    cscene_free(&c->cs, c->alloc);
    vx_free(c->alloc, c);
}

/* Whether the model cell next to cell across axis a (on the side ns) is filled. */
static bool cell_solid(const cmodel* c, const int64_t cell[3], int a, double ns) {
    int64_t q[3] = {cell[0], cell[1], cell[2]};
    q[a] += ns > 0 ? 1 : -1;
    for (int k = 0; k < 3; k++)
        if (q[k] < 0 || q[k] >= (int64_t)c->m->size[k]) return false;
    uint64_t key = vx_svo_morton((uint32_t)q[0], (uint32_t)q[1], (uint32_t)q[2]);
    for (uint32_t k = 0; k <= c->m->depth + 1; k++) {
        const centry* e = cm_find(c, block_of(key, k), k);
        if (e) return e->full != 0;
    }
    return false;
}

bool vx_render_cast(const vx_render_caster* c, const double o[3], const double d[3], double tmax, bool any,
                    vx_render_ray_hit* hit) {
    return vx_render_cast_skip(c, o, d, tmax, any, VX_RENDER_NO_HIT, hit);
}

bool vx_render_cast_skip(const vx_render_caster* c, const double o[3], const double d[3], double tmax, bool any,
                         uint32_t skip_instance, vx_render_ray_hit* hit) {
    chit h = {.t = tmax};
    uint32_t which = 0, steps = 0;
    if (!trace_scene(&c->cs, o, d, any, &h, &which, &steps, skip_instance)) return false;
    if (!hit) return true;
    const vx__inst_map* in = &c->cs.inst[which];
    const vx_svo_scene* s = c->cs.s;
    const vx_svo_model* m = &s->models[in->model];
    /* A ray that crosses an edge exactly enters the diagonal cell and the
     * tracer names the first tied axis; for shading, prefer a tied axis
     * whose face is exposed (the neighbour across it is empty). */
    const cmodel* cm = &c->cs.models[in->model];
    double om[3], dm[3];
    vx__inst_ray(in, o, d, om, dm);
    if (cell_solid(cm, h.cell, h.axis, h.nsign)) {
        for (int a = 0; a < 3; a++) {
            if (a == h.axis || dm[a] == 0) continue;
            double plane = (double)(dm[a] < 0 ? h.cell[a] + 1 : h.cell[a]);
            double ta = (plane - om[a]) / dm[a];
            double ns = dm[a] < 0 ? 1.0 : -1.0;
            if (fabs(ta - h.t) <= 1e-9 * fmax(1, fabs(h.t)) && !cell_solid(cm, h.cell, a, ns)) {
                h.axis = a, h.nsign = ns;
                break;
            }
        }
    }
    const double* row = &in->inv[4 * h.axis];
    double l = sqrt(row[0] * row[0] + row[1] * row[1] + row[2] * row[2]);
    hit->t = h.t;
    for (int k = 0; k < 3; k++) hit->normal[k] = h.nsign * row[k] / l, hit->cell[k] = (uint32_t)h.cell[k];
    hit->cell_size = in->cell;
    hit->instance = in->id;
    hit->rgba = m->attrs ? vx_svo_attr_rgba(s, m, h.attr) : 0xFFFFFFFFu;
    hit->palette = (m->attrs & VX_ATTR_PALETTE) && h.attr < m->attr_count ? m->palette[h.attr] : 0;
    hit->material = vx_svo_attr_material(m, h.attr);
    return true;
}

/* ---- grid cells of a scene (dense baseline) ----------------------------------------- */

typedef struct grid_ctx {
    double w[12];
    vx__grid_cell_fn fn;
    void* user;
} grid_ctx;

static bool grid_cb(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    (void)attr;
    grid_ctx* g = user;
    double p[3] = {x + 0.5, y + 0.5, z + 0.5}, q[3];
    vx__affine_apply(g->w, p, q);
    g->fn(g->user, (int64_t)floor(q[0]), (int64_t)floor(q[1]), (int64_t)floor(q[2]));
    return true;
}

vx_result vx__scene_grid_cells(const vx_svo_scene* s, vx__grid_cell_fn fn, void* user, vx_error* err) {
    for (uint32_t i = 0; i < s->instance_count; i++) {
        if (!vx_svo_instance_drawn(s, i)) continue;
        grid_ctx g = {.fn = fn, .user = user};
        vx_svo_instance_world(s, &s->instances[i], g.w);
        vx_result r = vx_svo_decode_model(&s->models[s->instances[i].model], grid_cb, &g, err);
        if (r) return r;
    }
    return VX_OK;
}
