/* svo/svo_emissive.c - emissive voxels as lights (vx_svo_emissive_lights):
 * face-connected clusters of emissive cells (those wider than a block cut
 * at the aligned blocks) become one sphere light each that carries the
 * cluster's emitted power. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "svo/svo_internal.h"

static const double pi = 3.14159265358979323846;

vx_svo_emissive_desc vx_svo_emissive_desc_defaults(void) {
    /* block 2: the lowest error against the path tracer in bench/emissive_bench
     * (docs/PERFORMANCE.md section 11), below one light per voxel and far
     * below 8 */
    return (vx_svo_emissive_desc){.block = 2, .max_cells = (uint64_t)1 << 24, .max_lights = 1u << 22};
}

bool vx_svo_model_cell_set(const vx_svo_model* m, uint32_t x, uint32_t y, uint32_t z) {
    if (x >= m->size[0] || y >= m->size[1] || z >= m->size[2] || m->root == VX_SVO_ROOT_EMPTY) return false;
    if (m->root == VX_SVO_ROOT_LEAF) return true;
    uint32_t i = m->root;
    for (uint32_t l = m->depth; l-- > 0;) {
        uint32_t d = m->nodes[i];
        uint32_t o = ((x >> l) & 1u) | ((y >> l) & 1u) << 1 | ((z >> l) & 1u) << 2;
        uint32_t valid = vx_svo_desc_valid(d), leaf = vx_svo_desc_leaf(d);
        if (!(valid >> o & 1u)) return false;
        if (leaf >> o & 1u) return true;
        uint32_t p = vx_svo_desc_ptr(d), block = vx_svo_desc_far(d) ? m->nodes[i - p] : i - p;
        i = block + vx__popc8(valid & ~leaf & ((1u << o) - 1u));
    }
    return true; /* not reached for a valid tree: level 1 children are leaves */
}

uint32_t vx_svo_model_cell_leaf(const vx_svo_model* m, uint32_t x, uint32_t y, uint32_t z) {
    if (x >= m->size[0] || y >= m->size[1] || z >= m->size[2] || m->root == VX_SVO_ROOT_EMPTY) return UINT32_MAX;
    if (m->root == VX_SVO_ROOT_LEAF) return m->depth;
    uint32_t i = m->root;
    for (uint32_t l = m->depth; l-- > 0;) {
        if (i >= m->node_count) return UINT32_MAX; /* not a valid tree: no crash */
        uint32_t d = m->nodes[i];
        uint32_t o = ((x >> l) & 1u) | ((y >> l) & 1u) << 1 | ((z >> l) & 1u) << 2;
        uint32_t valid = vx_svo_desc_valid(d), leaf = vx_svo_desc_leaf(d);
        if (!(valid >> o & 1u)) return UINT32_MAX;
        if (leaf >> o & 1u) return l;
        uint32_t p = vx_svo_desc_ptr(d), block = vx_svo_desc_far(d) ? m->nodes[i - p] : i - p;
        i = block + vx__popc8(valid & ~leaf & ((1u << o) - 1u));
    }
    return 0; /* not reached for a valid tree: level 1 children are leaves */
}

/* The extreme cell coordinate along axis of the subtree at node (a cube of
 * 2^level cells from base on that axis): the least cell start below best
 * (hi false) or the greatest cell end above best (hi true). The children on
 * the extreme side go first, so best cuts most subtrees: the walk visits
 * about the nodes that straddle the box's face, not the tree. */
static uint32_t cell_extreme(const vx_svo_model* m, uint32_t node, uint32_t level, uint32_t base, int axis, bool hi,
                             uint32_t best) {
    if (level == 0 || node >= m->node_count) return best; /* not in a valid model: no crash */
    uint32_t d = m->nodes[node], valid = vx_svo_desc_valid(d), leaf = vx_svo_desc_leaf(d);
    uint32_t half = 1u << (level - 1);
    for (uint32_t k = 0; k < 2; k++) {
        uint32_t h = hi ? 1u - k : k, lb = base + h * half, ub = lb + half;
        if (hi ? ub <= best : lb >= best) break;
        for (uint32_t o = 0; o < 8; o++) {
            if (((o >> axis) & 1u) != h || !((valid >> o) & 1u)) continue;
            if ((leaf >> o) & 1u) {
                best = hi ? ub : lb;
                break;
            }
            uint32_t p = vx_svo_desc_ptr(d);
            if (p > node) return best;
            uint32_t block = vx_svo_desc_far(d) ? m->nodes[node - p] : node - p;
            best = cell_extreme(m, block + vx__popc8(valid & ~leaf & ((1u << o) - 1u)), level - 1, lb, axis, hi, best);
            if (best == (hi ? ub : lb)) break;
        }
    }
    return best;
}

void vx_svo_model_cell_box(const vx_svo_model* m, uint32_t lo[3], uint32_t hi[3]) {
    for (int k = 0; k < 3; k++) lo[k] = hi[k] = 0;
    if (m->root == VX_SVO_ROOT_EMPTY) return;
    for (int k = 0; k < 3; k++) {
        if (m->root == VX_SVO_ROOT_LEAF || m->depth == 0) {
            hi[k] = m->size[k];
            continue;
        }
        lo[k] = cell_extreme(m, m->root, m->depth, 0, k, false, UINT32_MAX);
        hi[k] = cell_extreme(m, m->root, m->depth, 0, k, true, 0);
        if (hi[k] > m->size[k]) hi[k] = m->size[k]; /* a collapsed leaf past the size */
        if (lo[k] > hi[k]) lo[k] = hi[k];
    }
}

typedef struct ecell {
    uint64_t key; /* Morton key of the cell */
    float L[3];   /* emitted radiance */
    uint32_t parent;
} ecell;

typedef struct collect {
    const vx_svo_scene* s;
    const vx_svo_model* m;
    const float* emit_by_id; /* vx_material_emitted_terms per material id, 4 floats each */
    uint32_t id_count;
    ecell* cells;
    size_t n, cap, max;
    bool nomem, limit;
    const vx_allocator* A;
} collect;

static bool collect_cell(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t a) {
    collect* c = (collect*)user;
    const vx_svo_model* m = c->m;
    uint32_t id = vx_svo_attr_material(m, a); /* models with neither channel are not visited (emissive_lights) */
    const float* e = id < c->id_count ? c->emit_by_id + 4 * (size_t)id : NULL;
    if (!e || !(e[0] > 0 || e[1] > 0 || e[2] > 0 || e[3] > 0)) return true;
    if (c->n == c->max) return c->limit = true, false;
    if (c->n == c->cap) {
        size_t cap = c->cap ? c->cap * 2 : 256;
        ecell* nc = (ecell*)vx_alloc(c->A, cap * sizeof *nc);
        if (!nc) return c->nomem = true, false;
        if (c->n) memcpy(nc, c->cells, c->n * sizeof *nc);
        vx_free(c->A, c->cells);
        c->cells = nc, c->cap = cap;
    }
    /* the voxel's colour as the renderers read it (bytes / 255), times the emission, or the emission colour
     * (vx_material_emitted as its terms) */
    uint32_t rgba = vx_svo_attr_rgba(c->s, m, a);
    ecell* ce = &c->cells[c->n++];
    ce->key = vx_svo_morton(x, y, z);
    for (int k = 0; k < 3; k++) ce->L[k] = (float)((rgba >> (8 * k) & 0xFFu) / 255.0 * e[3] + e[k]);
    ce->parent = (uint32_t)(c->n - 1);
    return true;
}

static int key_cmp(const void* a, const void* b) {
    uint64_t x = ((const ecell*)a)->key, y = ((const ecell*)b)->key;
    return x < y ? -1 : x > y;
}
static size_t find(const ecell* c, size_t n, uint64_t key) {
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (c[mid].key < key) lo = mid + 1;
        else hi = mid;
    }
    return lo < n && c[lo].key == key ? lo : SIZE_MAX;
}
static uint32_t root_of(ecell* c, uint32_t i) {
    while (c[i].parent != i) i = c[i].parent = c[c[i].parent].parent;
    return i;
}

/* A cell's group: its component and, for components wider than a block,
 * its block's Morton key + 1 (0 for narrow components). */
typedef struct grp {
    uint32_t comp, cell;
    uint64_t block;
} grp;
static int grp_cmp(const void* a, const void* b) {
    const grp *x = (const grp*)a, *y = (const grp*)b;
    if (x->comp != y->comp) return x->comp < y->comp ? -1 : 1;
    if (x->block != y->block) return x->block < y->block ? -1 : 1;
    return x->cell < y->cell ? -1 : x->cell > y->cell;
}

/* A cluster in model cells: its box and its emitted power per face axis
 * (radiance x face count, so that any instance map scales it by the area
 * of one face along that axis). */
typedef struct cluster {
    uint32_t lo[3], hi[3];
    double power[3][3]; /* [face axis][channel]: sum of L over exposed faces */
} cluster;

static void cross(const double a[3], const double b[3], double o[3]) {
    o[0] = a[1] * b[2] - a[2] * b[1], o[1] = a[2] * b[0] - a[0] * b[2], o[2] = a[0] * b[1] - a[1] * b[0];
}

vx_result vx_svo_emissive_lights(const vx_svo_scene* s, const vx_svo_emissive_desc* desc, vx_light** out,
                                 uint32_t* out_count, vx_error* err) {
    if (!s || !out || !out_count) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "emissive lights: NULL argument");
    *out = NULL;
    *out_count = 0;
    vx_svo_emissive_desc d = vx_svo_emissive_desc_defaults(), z = desc ? *desc : (vx_svo_emissive_desc){0};
    d.alloc = z.alloc;
    if (z.block) d.block = z.block;
    if (z.max_cells) d.max_cells = z.max_cells;
    if (z.max_lights) d.max_lights = z.max_lights;
    if (d.block & (d.block - 1))
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "emissive lights: block %u is not a power of two", d.block);
    const vx_allocator* A = d.alloc;
    /* emission by material id; a scene without an emissive material costs nothing more */
    uint32_t ids = 0;
    for (uint32_t i = 0; i < s->material_count; i++)
        if (vx_svo_material_resolve(&s->materials[i]).emission > 0 && s->materials[i].id < 65536 && s->materials[i].id + 1 > ids)
            ids = s->materials[i].id + 1;
    if (!ids) return VX_OK;
    float* emit = (float*)vx_calloc(A, 4 * (size_t)ids, sizeof *emit);
    if (!emit) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "emissive lights: out of memory");
    for (uint32_t i = 0; i < s->material_count; i++)
        if (s->materials[i].id < ids) {
            vx_material mt = vx_svo_material_resolve(&s->materials[i]);
            mt.emission = fmin(mt.emission, 1e30);
            vx_material_emitted_terms(&mt, emit + 4 * (size_t)s->materials[i].id);
        }
    vx_result r = VX_OK;
    vx_light* lights = NULL;
    size_t nl = 0, lcap = 0;
    collect c = {.s = s, .emit_by_id = emit, .id_count = ids, .max = d.max_cells, .A = A};
    cluster* cl = NULL;
    uint8_t* drawn = (uint8_t*)vx_calloc(A, s->model_count ? s->model_count : 1, 1); /* models some drawn instance uses */
    if (!drawn) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "emissive lights: out of memory");
    for (uint32_t i = 0; drawn && i < s->instance_count; i++)
        if (vx_svo_instance_drawn(s, i)) drawn[s->instances[i].model] = 1;
    for (uint32_t mi = 0; r == VX_OK && mi < s->model_count; mi++) {
        const vx_svo_model* m = &s->models[mi];
        if (!drawn[mi] || !(m->attrs & (VX_ATTR_PALETTE | VX_ATTR_MATERIAL))) continue;
        c.m = m, c.n = 0;
        r = vx_svo_decode_model(m, collect_cell, &c, err);
        if (r == VX_OK && c.nomem) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "emissive lights: out of memory");
        if (r == VX_OK && c.limit)
            r = vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "emissive lights: model %u has more than %llu emissive cells", mi,
                        (unsigned long long)d.max_cells);
        if (r != VX_OK || c.n == 0) continue;
        /* components: face neighbours (union-find, the smallest key leads) */
        qsort(c.cells, c.n, sizeof *c.cells, key_cmp);
        for (size_t i = 0; i < c.n; i++) c.cells[i].parent = (uint32_t)i;
        for (size_t i = 0; i < c.n; i++) {
            uint32_t p[3];
            vx_svo_demorton(c.cells[i].key, &p[0], &p[1], &p[2]);
            for (int a = 0; a < 3; a++) {
                uint32_t q[3] = {p[0], p[1], p[2]};
                q[a]++;
                size_t j = find(c.cells, c.n, vx_svo_morton(q[0], q[1], q[2]));
                if (j == SIZE_MAX) continue;
                uint32_t ra = root_of(c.cells, (uint32_t)i), rb = root_of(c.cells, (uint32_t)j);
                if (ra != rb) c.cells[ra > rb ? ra : rb].parent = ra < rb ? ra : rb;
            }
        }
        /* a component wider than a block on some axis is cut at the aligned
         * blocks: its cells group by (component, block) */
        size_t ncomp = 0, ncl = 0;
        uint32_t* slot = (uint32_t*)vx_alloc(A, c.n * sizeof *slot);
        uint32_t(*box)[6] = NULL;
        grp* gs = NULL;
        if (slot) {
            for (size_t i = 0; i < c.n; i++)
                if (root_of(c.cells, (uint32_t)i) == i) slot[i] = (uint32_t)ncomp++;
            box = (uint32_t(*)[6])vx_alloc(A, ncomp * sizeof *box);
            gs = (grp*)vx_alloc(A, c.n * sizeof *gs);
        }
        if (box && gs) {
            for (size_t k = 0; k < ncomp; k++) box[k][0] = box[k][1] = box[k][2] = UINT32_MAX, box[k][3] = box[k][4] = box[k][5] = 0;
            for (size_t i = 0; i < c.n; i++) {
                uint32_t* bb = box[slot[root_of(c.cells, (uint32_t)i)]], p[3];
                vx_svo_demorton(c.cells[i].key, &p[0], &p[1], &p[2]);
                for (int a = 0; a < 3; a++) bb[a] = p[a] < bb[a] ? p[a] : bb[a], bb[3 + a] = p[a] + 1 > bb[3 + a] ? p[a] + 1 : bb[3 + a];
            }
            unsigned lb = 0;
            while ((1u << lb) < d.block) lb++;
            for (size_t i = 0; i < c.n; i++) {
                uint32_t comp = slot[root_of(c.cells, (uint32_t)i)];
                const uint32_t* bb = box[comp];
                bool wide = bb[3] - bb[0] > d.block || bb[4] - bb[1] > d.block || bb[5] - bb[2] > d.block;
                gs[i] = (grp){comp, (uint32_t)i, wide ? (c.cells[i].key >> (3 * lb)) + 1 : 0};
            }
            qsort(gs, c.n, sizeof *gs, grp_cmp);
            for (size_t i = 0; i < c.n; i++) {
                if (i == 0 || gs[i].comp != gs[i - 1].comp || gs[i].block != gs[i - 1].block) ncl++;
                slot[gs[i].cell] = (uint32_t)(ncl - 1); /* now: the cell's cluster */
            }
        }
        vx_free(A, box);
        vx_free(A, gs);
        vx_free(A, cl);
        cl = slot && ncl ? (cluster*)vx_calloc(A, ncl, sizeof *cl) : NULL;
        if (!cl) {
            vx_free(A, slot);
            r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "emissive lights: out of memory");
            break;
        }
        for (size_t i = 0; i < ncl; i++)
            for (int a = 0; a < 3; a++) cl[i].lo[a] = UINT32_MAX;
        for (size_t i = 0; i < c.n; i++) {
            cluster* k = &cl[slot[i]];
            uint32_t p[3];
            vx_svo_demorton(c.cells[i].key, &p[0], &p[1], &p[2]);
            for (int a = 0; a < 3; a++) {
                if (p[a] < k->lo[a]) k->lo[a] = p[a];
                if (p[a] + 1 > k->hi[a]) k->hi[a] = p[a] + 1;
                /* a face emits when the cell beyond it is empty (inside the
                 * model; outside it nothing covers it) */
                for (int sgn = -1; sgn <= 1; sgn += 2) {
                    uint32_t q[3] = {p[0], p[1], p[2]};
                    if (sgn < 0 && q[a] == 0) {
                        for (int ch = 0; ch < 3; ch++) k->power[a][ch] += c.cells[i].L[ch];
                        continue;
                    }
                    q[a] += (uint32_t)sgn;
                    if (!vx_svo_model_cell_set(m, q[0], q[1], q[2]))
                        for (int ch = 0; ch < 3; ch++) k->power[a][ch] += c.cells[i].L[ch];
                }
            }
        }
        vx_free(A, slot);
        /* one sphere light per cluster and drawn instance of the model */
        for (uint32_t ii = 0; r == VX_OK && ii < s->instance_count; ii++) {
            if (s->instances[ii].model != mi || !vx_svo_instance_drawn(s, ii)) continue;
            double w[12];
            vx_svo_instance_world(s, &s->instances[ii], w);
            double col[3][3], area[3];
            for (int a = 0; a < 3; a++)
                for (int r3 = 0; r3 < 3; r3++) col[a][r3] = w[4 * r3 + a];
            for (int a = 0; a < 3; a++) { /* world area of one face across axis a */
                double x[3];
                cross(col[(a + 1) % 3], col[(a + 2) % 3], x);
                area[a] = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
            }
            for (size_t k = 0; k < ncl; k++) {
                if (nl == d.max_lights) {
                    r = vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "emissive lights: more than %u lights", d.max_lights);
                    break;
                }
                if (nl == lcap) {
                    size_t cap = lcap ? lcap * 2 : 64;
                    vx_light* nlg = (vx_light*)vx_alloc(A, cap * sizeof *nlg);
                    if (!nlg) {
                        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "emissive lights: out of memory");
                        break;
                    }
                    if (nl) memcpy(nlg, lights, nl * sizeof *nlg);
                    vx_free(A, lights);
                    lights = nlg, lcap = cap;
                }
                const cluster* q = &cl[k];
                vx_light* L = &lights[nl++];
                memset(L, 0, sizeof *L);
                L->type = VX_LIGHT_SPHERE;
                L->flags = VX_LIGHT_FROM_VOXELS;
                double ctr[3] = {(q->lo[0] + q->hi[0]) * 0.5, (q->lo[1] + q->hi[1]) * 0.5, (q->lo[2] + q->hi[2]) * 0.5};
                for (int r3 = 0; r3 < 3; r3++)
                    L->position[r3] = w[4 * r3] * ctr[0] + w[4 * r3 + 1] * ctr[1] + w[4 * r3 + 2] * ctr[2] + w[4 * r3 + 3];
                double rad = 0; /* the sphere through the box's corners (an affine map keeps the centre) */
                for (int cn = 0; cn < 8; cn++) {
                    double v[3] = {(cn & 1 ? q->hi[0] : q->lo[0]) - ctr[0], (cn & 2 ? q->hi[1] : q->lo[1]) - ctr[1],
                                   (cn & 4 ? q->hi[2] : q->lo[2]) - ctr[2]};
                    double t[3];
                    for (int r3 = 0; r3 < 3; r3++) t[r3] = w[4 * r3] * v[0] + w[4 * r3 + 1] * v[1] + w[4 * r3 + 2] * v[2];
                    rad = fmax(rad, sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]));
                }
                L->radius = rad;
                /* power: pi L A per face; a sphere of radiance Ls emits pi Ls 4 pi r^2 */
                double Ls[3], mx = 0;
                for (int ch = 0; ch < 3; ch++) {
                    double P = 0;
                    for (int a = 0; a < 3; a++) P += pi * q->power[a][ch] * area[a];
                    Ls[ch] = rad > 0 ? P / (4 * pi * pi * rad * rad) : 0;
                    mx = fmax(mx, Ls[ch]);
                }
                L->intensity = fmin(mx, 1e30);
                for (int ch = 0; ch < 3; ch++) L->color[ch] = mx > 0 ? Ls[ch] / mx : 0;
            }
        }
    }
    vx_free(A, drawn);
    vx_free(A, cl);
    vx_free(A, c.cells);
    vx_free(A, emit);
    if (r != VX_OK) {
        vx_free(A, lights);
        return r;
    }
    *out = lights;
    *out_count = (uint32_t)nl;
    return VX_OK;
}
