/* render/shadow_map.c - the directional light's conservative depth map that
 * clips trace.comp's shadow rays (issue 21).
 *
 * Every shadow ray of a directional light is parallel to the light direction
 * L, so it projects to one point of the light's orthographic view. Per texel
 * of that view the map holds the largest s = dot(x - O, L) of any geometry
 * whose octree node's projection touches the texel (shaders/smap.comp); a
 * shadow ray from p moves towards larger s, so it can meet geometry only
 * for t <= s_max - s(p), and none at all where s_max < s(p) or the texel is
 * empty. The tracer's loop gets that as its tmax; the result is the
 * unclipped ray's (bit for bit: tests/render/test_render_smap.c). Two more
 * layers (smap.comp says how they are made): the second largest s and the
 * one solid cube that gave the largest, which a shadow ray from that cube's
 * own face cannot meet; and the top of solid cubes that cover a whole
 * texel, below which a shadow ray surely meets one.
 *
 * Nodes: per model, the octree's nodes at the level whose side is about one
 * texel in the world (and collapsed leaves above it), listed once, at the
 * scene's first build (render_scene.c reads the words back from the GPU:
 * the scene keeps no host copy of the models), from the plain node words
 * or the compact layout's geometry (list_tree: either gives the same
 * cells), or made ahead on the host (vx_render_sun_nodes_make); each build
 * projects every drawn instance's copy of its model's list. A build is one
 * submission (a fill, two dispatches) per light direction and instances.
 *
 * The margin: the build and the kernel compute projections in float from
 * coordinates of at most about the scene's size R (plus the frame reference's
 * distance from the map's origin, which the kernel adds per frame): a few
 * 2^-24 R each. The walk itself steps through each model's cube in [1,2]^3
 * float coordinates, whose rounding is 2^-23 of the cube (at most twice
 * the model's extent) per operation, with tiny direction components replaced
 * by 2^-23 (a drift of at most 2^-22 of the cube). 2^-13 R is 2^9 times the
 * sum of these, so a cell the walk enters is inside the widened texel
 * rectangle and below the widened s_max, and a cube whose shrunk projection
 * holds a texel holds the shadow rays that start in it. */
#include <math.h>
#include <string.h>

#include "render/compact.h"
#include "render/render_internal.h"
#include "render/trace.h"
#include "smap.comp.h"

const uint32_t* vx__spirv_smap(size_t* bytes) {
    *bytes = sizeof vx__smap_spv_arr;
    return vx__smap_spv_arr;
}

/* GPU layouts of smap.comp */
typedef struct smap_node {
    uint32_t x, y, z, level;
} smap_node;
typedef struct smap_inst {
    float pu[4], pv[4], ps[4];
    float q[3][4], qd[4];
    uint32_t range[4];
} smap_inst;
typedef struct smap_push {
    uint32_t mode, count, insts, side;
    float margin_tex, margin;
} smap_push;

/* smap_node.level's flag: the cube is a leaf (solid) */
#define SOLID 0x100u

/* A growing node list. */
typedef struct node_list {
    smap_node* v;
    size_t n, cap;
    size_t limit; /* count only past it (n keeps counting) */
    const vx_allocator* alloc;
    bool nomem;
} node_list;

static void list_add(node_list* l, uint32_t x, uint32_t y, uint32_t z, uint32_t level) {
    if (l->n < l->cap && l->n < l->limit) { /* the common case without a call (a list has 10^5-10^6 nodes) */
        l->v[l->n++] = (smap_node){x, y, z, level};
        return;
    }
    if (l->n < l->limit) {
        void* v = l->v;
        if (!vx_grow(l->alloc, &v, &l->cap, l->n + 1, sizeof *l->v)) {
            l->nomem = true;
            l->limit = 0;
        } else {
            l->v = v;
            l->v[l->n] = (smap_node){x, y, z, level};
        }
    }
    l->n++;
}

/* A model's tree as the listing reads it: a plain model's node words
 * (svo/svo.h), or model mi of a compact layout (render/compact.h), whose
 * nodes are slots and whose level-1 and level-2 nodes are bricks. */
typedef struct tree {
    const vx_svo_model* m; /* plain, else NULL */
    const vx_compact_scene* c;
    uint32_t root, depth, count; /* the root's word or slot; node words or slots */
} tree;

/* Node `at` (of a level above 2 in a compact tree): its valid and leaf
 * masks and the reference of its inner children (UINT32_MAX: none). */
static void tree_node(const tree* t, uint32_t at, uint32_t* valid, uint32_t* leaf, uint32_t* blk) {
    uint32_t desc = t->m ? t->m->nodes[at] : t->c->geom[2 * (size_t)at];
    *valid = (desc >> 8) & 0xFFu, *leaf = desc & 0xFFu;
    if (!t->m) {
        *blk = t->c->geom[2 * (size_t)at + 1];
        return;
    }
    uint32_t p = desc >> 17;
    *blk = UINT32_MAX;
    if ((*valid & ~*leaf) && p >= 1 && p <= at) {
        *blk = at - p;
        if (desc & 0x10000u) *blk = t->m->nodes[*blk];
    }
}

/* Inner child k (in octant order) of a level-lv node whose tree_node blk is blk. */
static uint32_t tree_child(const tree* t, uint32_t lv, uint32_t blk, uint32_t k) {
    if (t->m) return blk == UINT32_MAX ? UINT32_MAX : blk + k;
    return vx__compact_child(t->c, lv, blk, k);
}

/* A compact brick (level lv <= 2, above `level`) at x, y, z: its cells a
 * 64-bit mask, octant o2's in bits 8 o2 .. 8 o2 + 7 (a model of depth 1:
 * bits 0..7). A full brick or full octant is a solid cube listed as it is
 * (what a plain model's leaf of that size is: the compact geometry keeps
 * cubes of 4^3 and 2^3 cells as masks, however the model's colours
 * collapsed them; eph_monu1's list at 512 texels: 61,770 nodes without
 * this, 16,984 with it, 26,308 from the plain model), else its octants or
 * cells at `level`. */
static void list_brick(const uint32_t* sl, uint32_t x, uint32_t y, uint32_t z, uint32_t lv, uint32_t level, node_list* l) {
    uint64_t mask = sl[0] | (uint64_t)sl[1] << 32;
    if (lv == 1) mask &= 0xFFu;
    if (mask == (lv == 2 ? ~0ull : 0xFFull)) {
        list_add(l, x, y, z, lv | SOLID);
        return;
    }
    if (lv <= level) {
        list_add(l, x, y, z, lv);
        return;
    }
    for (uint32_t o2 = 0; o2 < (lv == 2 ? 8u : 1u); o2++) {
        uint32_t oct = (uint32_t)(mask >> (8 * o2)) & 0xFFu;
        if (!oct) continue;
        uint32_t bx = x + (o2 & 1u) * 2, by = y + ((o2 >> 1) & 1u) * 2, bz = z + ((o2 >> 2) & 1u) * 2;
        if (lv == 2 && (oct == 0xFFu || level >= 1)) {
            list_add(l, bx, by, bz, 1 | (oct == 0xFFu ? SOLID : 0));
            continue;
        }
        for (uint32_t o1 = 0; o1 < 8; o1++)
            if ((oct >> o1) & 1u) list_add(l, bx + (o1 & 1u), by + ((o1 >> 1) & 1u), bz + ((o1 >> 2) & 1u), SOLID);
    }
}

/* The nodes of tree t at `level` (cubes of 2^level cells) and its leaves
 * above it, into l. A word or slot out of range ends that branch (the
 * scene was validated when read, a layout is built valid). */
static void list_tree(const tree* t, uint32_t level, node_list* l) {
    if (t->root == VX_SVO_ROOT_EMPTY) return;
    if (t->root == VX_SVO_ROOT_LEAF || level >= t->depth) {
        list_add(l, 0, 0, 0, t->depth | (t->root == VX_SVO_ROOT_LEAF ? SOLID : 0));
        return;
    }
    typedef struct item {
        uint32_t at, x, y, z, lv;
    } item;
    item stack[8 * 33]; /* a walk in depth order holds at most 7 a level */
    int sp = 0;
    stack[sp++] = (item){t->root, 0, 0, 0, t->depth};
    /* past the limit the caller takes a coarser level: stop at once */
    while (sp > 0 && l->n <= l->limit) {
        item it = stack[--sp];
        if (it.at >= t->count) continue;
        if (t->c && it.lv <= 2) {
            list_brick(t->c->geom + 2 * (size_t)it.at, it.x, it.y, it.z, it.lv, level, l);
            continue;
        }
        uint32_t valid, leaf, blk;
        tree_node(t, it.at, &valid, &leaf, &blk);
        uint32_t cl = it.lv - 1, half = 1u << cl;
        uint32_t k = 0;
        for (uint32_t o = 0; o < 8; o++) {
            if (!((valid >> o) & 1u)) continue;
            uint32_t cx = it.x + (o & 1u) * half, cy = it.y + ((o >> 1) & 1u) * half, cz = it.z + ((o >> 2) & 1u) * half;
            if ((leaf >> o) & 1u) {
                list_add(l, cx, cy, cz, cl | SOLID);
                continue;
            }
            uint32_t cw = tree_child(t, it.lv, blk, k++);
            /* (a compact brick is read even at the list's level: full, it is a solid cube) */
            if (cl <= level && !(t->c && cl <= 2)) list_add(l, cx, cy, cz, cl);
            else if (sp < (int)(sizeof stack / sizeof stack[0])) stack[sp++] = (item){cw, cx, cy, cz, cl};
        }
    }
}

void vx__smap_free(vx_gpu* g, vx__smap* sm) {
    if (!sm) return;
    vx__buffer_destroy(g, &sm->nodes);
    vx__buffer_destroy(g, &sm->insts);
    vx__buffer_destroy(g, &sm->map);
    if (sm->model_first) vx_free(sm->alloc, sm->model_first);
    memset(sm, 0, sizeof *sm);
}

static double scene_diag(const double lo[3], const double hi[3]) {
    double d = 0;
    for (int k = 0; k < 3; k++) d += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    return sqrt(d);
}

/* The host's part of vx__smap_list: sm's side, diagonal, model starts and
 * levels, and the node list into *nodes (NULL where there is none; the
 * caller frees it). */
static vx_result smap_list_host(const vx_allocator* alloc, const vx_svo_scene* s, const vx_compact_scene* c,
                                const uint32_t* inst_model,
                                const float* inst_cell, uint32_t inst_count, const double lo[3], const double hi[3],
                                uint32_t side, uint32_t per_cell, uint32_t max_side, vx__smap* sm, smap_node** nodes,
                                vx_error* err) {
    *nodes = NULL;
    sm->alloc = alloc;
    uint32_t mc = c ? c->model_count : s->model_count;
    if (side == 1 || inst_count == 0 || mc == 0) return VX_OK;
    double t0 = vx_time_now();
    double diag = scene_diag(lo, hi);
    if (!(diag > 0) || !isfinite(diag)) return VX_OK;
    if (!side) {
        /* per_cell texels a side of the finest cell where that takes at most
         * 2048 a side (64 MiB): a shadow ray from a cube's face skips its
         * walk where the texel holds no other cube above it, or is shadowed
         * where one covers it whole (finer texels: more such pixels) */
        double cmin = INFINITY;
        for (uint32_t i = 0; i < inst_count; i++)
            if (inst_cell[i] > 0) cmin = fmin(cmin, inst_cell[i]);
        uint32_t most = max_side ? max_side : VX__SMAP_SIDE;
        double want = isfinite(cmin) ? per_cell * diag / cmin : most;
        side = 64;
        while (side < most && side < want) side *= 2;
    }
    if (side < 16) side = 16;
    if (side > 16384) side = 16384;
    /* the node side in the world: about a texel (the map spans at most the diagonal) */
    double tau = diag / side;
    /* per model the smallest cell of its instances */
    sm->model_first = vx_calloc(alloc, 2 * (size_t)mc + 1, sizeof *sm->model_first);
    double* mcell = vx_calloc(alloc, mc, sizeof *mcell);
    if (!sm->model_first || !mcell) {
        vx_free(alloc, mcell);
        vx_free(alloc, sm->model_first);
        sm->model_first = NULL;
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for the shadow map's nodes");
    }
    for (uint32_t i = 0; i < inst_count; i++) {
        uint32_t mi = inst_model[i];
        if (mi >= mc) continue;
        if (mcell[mi] == 0 || inst_cell[i] < mcell[mi]) mcell[mi] = inst_cell[i];
    }
    /* at most VX__SMAP_MAX_NODES nodes: coarser levels until they fit */
    node_list l = {.alloc = alloc};
    uint32_t* lev = &sm->model_first[mc + 1];
    for (int coarser = 0; coarser < 64; coarser++) {
        l.n = 0;
        l.limit = VX__SMAP_MAX_NODES;
        l.nomem = false;
        for (uint32_t mi = 0; mi < mc && !l.nomem && l.n <= l.limit; mi++) {
            sm->model_first[mi] = (uint32_t)(l.n < l.limit ? l.n : l.limit);
            lev[mi] = 0;
            if (mcell[mi] <= 0) continue;
            double q = log2(tau / mcell[mi]);
            int lv = (q > 0 ? (int)floor(q) : 0) + coarser;
            lev[mi] = (uint32_t)(lv > 31 ? 31 : lv);
            tree tr = {.c = c};
            if (c) tr.root = c->models[mi].root, tr.depth = c->models[mi].depth, tr.count = c->slot_count;
            else tr.m = &s->models[mi], tr.root = tr.m->root, tr.depth = tr.m->depth, tr.count = tr.m->node_count;
            list_tree(&tr, lev[mi], &l);
        }
        if (l.nomem || l.n <= VX__SMAP_MAX_NODES) break;
    }
    vx_free(alloc, mcell);
    if (l.nomem || l.n > VX__SMAP_MAX_NODES) {
        vx_free(alloc, l.v);
        vx_free(alloc, sm->model_first);
        sm->model_first = NULL;
        return VX_OK; /* no map: unclipped shadow rays */
    }
    sm->model_first[mc] = (uint32_t)l.n;
    sm->node_count = (uint32_t)l.n;
    sm->model_count = mc;
    sm->side = side;
    sm->diag = diag;
    sm->list_seconds = vx_time_now() - t0;
    *nodes = l.v;
    return VX_OK;
}

/* The GPU's part: the node buffer of a host list (sm->side set), which it frees. */
static vx_result smap_list_upload(vx_gpu* g, vx__smap* sm, smap_node* nodes, vx_error* err) {
    if (!sm->side) {
        vx_free(sm->alloc, nodes);
        return VX_OK;
    }
    double t0 = vx_time_now();
    size_t n = sm->node_count;
    /* host-visible: the list is written in place, without a staging buffer and
     * a submission of its own; each build reads it once */
    vx_result r = vx__buffer_create(g, (n ? n : 1) * sizeof(smap_node), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true,
                                    "shadow map nodes", &sm->nodes, err);
    if (!r && n) r = vx__buffer_upload(g, &sm->nodes, nodes, n * sizeof(smap_node), err);
    vx_free(sm->alloc, nodes);
    if (r) {
        vx__smap_free(g, sm);
        return r;
    }
    sm->list_seconds += vx_time_now() - t0;
    return VX_OK;
}

vx_result vx__smap_list(vx_gpu* g, const vx_allocator* alloc, const vx_svo_scene* s, const vx_compact_scene* c,
                        const uint32_t* inst_model,
                        const float* inst_cell, uint32_t inst_count, const double lo[3], const double hi[3],
                        uint32_t side, uint32_t per_cell, uint32_t max_side, vx__smap* sm, vx_error* err) {
    vx__smap_free(g, sm);
    smap_node* nodes = NULL;
    vx_result r = smap_list_host(alloc, s, c, inst_model, inst_cell, inst_count, lo, hi, side, per_cell, max_side, sm,
                                 &nodes, err);
    return r ? r : smap_list_upload(g, sm, nodes, err);
}

/* A list made on the host before the device (vx_render_sun_nodes_make): the
 * host part's result and what it was made for. */
struct vx__smap_pre {
    vx__smap sm; /* side, diag, model_count, model_first (taken by the adopting scene), node_count */
    smap_node* nodes;
    uint32_t side_req, per_cell, max_side;
    const vx_allocator* alloc;
};

vx_result vx__smap_pre_make(const vx_allocator* alloc, const vx_svo_scene* s, const vx_compact_scene* c,
                            const uint32_t* inst_model,
                            const float* inst_cell, uint32_t inst_count, const double lo[3], const double hi[3],
                            uint32_t side, uint32_t per_cell, uint32_t max_side, vx__smap_pre** out, vx_error* err) {
    *out = NULL;
    vx__smap_pre* p = vx_calloc(alloc, 1, sizeof *p);
    if (!p) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    p->side_req = side, p->per_cell = per_cell, p->max_side = max_side, p->alloc = alloc;
    vx_result r = smap_list_host(alloc, s, c, inst_model, inst_cell, inst_count, lo, hi, side, per_cell, max_side, &p->sm,
                                 &p->nodes, err);
    if (r) {
        vx__smap_pre_free(p);
        return r;
    }
    *out = p;
    return VX_OK;
}

bool vx__smap_pre_fits(const vx__smap_pre* p, uint32_t side, uint32_t per_cell, uint32_t max_side) {
    return p && p->side_req == side && p->per_cell == per_cell && p->max_side == max_side;
}

vx_result vx__smap_pre_use(vx_gpu* g, vx__smap_pre* p, vx__smap* sm, vx_error* err) {
    vx__smap_free(g, sm);
    *sm = p->sm;
    smap_node* nodes = p->nodes;
    memset(&p->sm, 0, sizeof p->sm);
    p->nodes = NULL;
    return smap_list_upload(g, sm, nodes, err);
}

void vx__smap_pre_free(vx__smap_pre* p) {
    if (!p) return;
    const vx_allocator* a = p->alloc;
    vx_free(a, p->sm.model_first);
    vx_free(a, p->nodes);
    vx_free(a, p);
}

/* The unit light L and two unit axes U, V across it (the map's texel axes). */
static void light_basis(const float light[3], double L[3], double U[3], double V[3]) {
    double n = 0;
    for (int k = 0; k < 3; k++) L[k] = light[k], n += L[k] * L[k];
    n = sqrt(n);
    for (int k = 0; k < 3; k++) L[k] /= n;
    /* U orthogonal to L, away from L's largest component */
    int a = 0;
    for (int k = 1; k < 3; k++)
        if (fabs(L[k]) < fabs(L[a])) a = k;
    double e[3] = {0, 0, 0};
    e[a] = 1;
    U[0] = L[1] * e[2] - L[2] * e[1], U[1] = L[2] * e[0] - L[0] * e[2], U[2] = L[0] * e[1] - L[1] * e[0];
    n = sqrt(U[0] * U[0] + U[1] * U[1] + U[2] * U[2]);
    for (int k = 0; k < 3; k++) U[k] /= n;
    V[0] = L[1] * U[2] - L[2] * U[1], V[1] = L[2] * U[0] - L[0] * U[2], V[2] = L[0] * U[1] - L[1] * U[0];
}

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

vx_result vx__smap_build(vx_gpu* g, vx__smap* sm, const float light[3], const double (*world)[12],
                         const uint32_t* inst_model, uint32_t inst_count, const double lo[3], const double hi[3],
                         vx_error* err) {
    sm->valid = false;
    if (!sm->side) return VX_OK;
    /* the map's memory only where a frame uses it */
    vx_result r = vx__buffer_ensure(g, &sm->map, (16 + 4 * (VkDeviceSize)sm->side * sm->side) * 4, "shadow map", err);
    if (r) return r;
    if (!(fabsf(light[0]) + fabsf(light[1]) + fabsf(light[2]) > 0)) return VX_OK;
    double t0 = vx_time_now();
    double L[3], U[3], V[3], O[3];
    light_basis(light, L, U, V);
    for (int k = 0; k < 3; k++) O[k] = 0.5 * (lo[k] + hi[k]);
    /* the map spans the scene box's projection, square texels, a texel of room */
    double umin = INFINITY, umax = -INFINITY, vmin = INFINITY, vmax = -INFINITY;
    for (int c = 0; c < 8; c++) {
        double x[3] = {((c & 1) ? hi[0] : lo[0]) - O[0], ((c & 2) ? hi[1] : lo[1]) - O[1], ((c & 4) ? hi[2] : lo[2]) - O[2]};
        double u = dot3(x, U), v = dot3(x, V);
        umin = fmin(umin, u), umax = fmax(umax, u), vmin = fmin(vmin, v), vmax = fmax(vmax, v);
    }
    double margin = ldexp(sm->diag, -13);
    double ext = fmax(umax - umin, vmax - vmin) + 4 * margin;
    double inv = (sm->side - 2) / ext;
    umin -= 2 * margin + 1 / inv, vmin -= 2 * margin + 1 / inv;
    /* the header the trace kernel reads: rows giving texel u, v from x - O, then L */
    float hdr[16] = {0};
    for (int k = 0; k < 3; k++) hdr[k] = (float)(U[k] * inv), hdr[4 + k] = (float)(V[k] * inv), hdr[8 + k] = light[k];
    hdr[3] = (float)(-umin * inv), hdr[7] = (float)(-vmin * inv), hdr[11] = (float)margin;
    hdr[12] = (float)sm->side;
    /* per instance: its model cells to (u, v, s) */
    uint32_t n = 0;
    /* the instances, then the header (copied into the map by the build's submission) */
    smap_inst* si = vx_calloc(sm->alloc, (inst_count ? inst_count : 1) + 1, sizeof *si);
    if (!si) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for the shadow map");
    uint64_t work = 0;
    for (uint32_t i = 0; i < inst_count; i++) {
        uint32_t mi = inst_model[i];
        if (mi >= sm->model_count) continue;
        uint32_t first = sm->model_first[mi], cnt = sm->model_first[mi + 1] - first;
        if (!cnt) continue;
        const double* w = world[i];
        double t[3] = {w[3] - O[0], w[7] - O[1], w[11] - O[2]};
        const double* B[3] = {U, V, L};
        double sc[3] = {inv, inv, 1};
        double off[3] = {-umin * inv, -vmin * inv, 0};
        float* row[3] = {si[n].pu, si[n].pv, si[n].ps};
        for (int r = 0; r < 3; r++) {
            for (int c = 0; c < 3; c++)
                row[r][c] = (float)(sc[r] * (B[r][0] * w[c] + B[r][1] * w[4 + c] + B[r][2] * w[8 + c]));
            row[r][3] = (float)(sc[r] * dot3(B[r], t) + off[r]);
        }
        /* the inverse (model cells from texel u, v and world s) for the face planes */
        double P[9], Q[9];
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++) P[3 * r + c] = sc[r] * (B[r][0] * w[c] + B[r][1] * w[4 + c] + B[r][2] * w[8 + c]);
        double det = P[0] * (P[4] * P[8] - P[5] * P[7]) - P[1] * (P[3] * P[8] - P[5] * P[6]) + P[2] * (P[3] * P[7] - P[4] * P[6]);
        uint32_t use = 0;
        if (det != 0 && isfinite(det)) {
            Q[0] = (P[4] * P[8] - P[5] * P[7]) / det, Q[1] = (P[2] * P[7] - P[1] * P[8]) / det, Q[2] = (P[1] * P[5] - P[2] * P[4]) / det;
            Q[3] = (P[5] * P[6] - P[3] * P[8]) / det, Q[4] = (P[0] * P[8] - P[2] * P[6]) / det, Q[5] = (P[2] * P[3] - P[0] * P[5]) / det;
            Q[6] = (P[3] * P[7] - P[4] * P[6]) / det, Q[7] = (P[1] * P[6] - P[0] * P[7]) / det, Q[8] = (P[0] * P[4] - P[1] * P[3]) / det;
            double p0[3] = {row[0][3], row[1][3], row[2][3]};
            for (int k = 0; k < 3; k++) {
                for (int c = 0; c < 3; c++) si[n].q[k][c] = (float)Q[3 * k + c];
                si[n].q[k][3] = 0;
                si[n].qd[k] = (float)-(Q[3 * k] * p0[0] + Q[3 * k + 1] * p0[1] + Q[3 * k + 2] * p0[2]);
                /* a face plane bounds s only where it is steep enough that the
                 * float rounding of the bound stays far below the margin: its
                 * s-slope at least 1/20 of its gradient (u, v per world unit) */
                double gu = Q[3 * k] * inv, gv = Q[3 * k + 1] * inv, gs = Q[3 * k + 2];
                if (fabs(gs) >= 0.05 * (fabs(gu) + fabs(gv) + fabs(gs))) use |= 1u << k;
            }
        }
        memcpy(&si[n].qd[3], &use, 4);
        si[n].range[0] = first, si[n].range[1] = cnt, si[n].range[2] = (uint32_t)work, si[n].range[3] = i;
        work += cnt;
        n++;
    }
    if (work >= 0x7FFFFFFFull) { /* top's work items + 1 below bit 31 */
        vx_free(sm->alloc, si);
        return VX_OK; /* too many: no map */
    }
    /* host-visible, written in place: no staging buffer and submission per upload */
    VkDeviceSize hdr_at = (VkDeviceSize)(n ? n : 1) * sizeof *si, isz = hdr_at + sizeof hdr;
    memcpy((uint8_t*)si + hdr_at, hdr, sizeof hdr);
    if (!(sm->insts.buf && sm->insts.size >= isz)) {
        vx__buffer_destroy(g, &sm->insts);
        r = vx__buffer_create(g, isz, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true, "shadow map instances", &sm->insts, err);
    }
    if (!r) r = vx__buffer_upload(g, &sm->insts, si, isz, err);
    vx_free(sm->alloc, si);
    if (r) return r;
    size_t spv_size;
    const uint32_t* spv = vx__spirv_smap(&spv_size);
    vx_gpu_compute_pipeline_desc pd = {.spirv = spv, .spirv_size = spv_size, .binding_count = 3,
                                       .push_constant_size = sizeof(smap_push), .label = "shadow map"};
    for (int i = 0; i < 3; i++) pd.bindings[i] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    vx__pipeline* p;
    if ((r = vx__pipeline_get(g, 0x5AA90001u, &pd, &p, err))) return r;
    vx__seq seq;
    if ((r = vx__seq_begin(g, &seq, err))) return r;
    uint32_t texels = sm->side * sm->side;
    smap_push pc[3] = {{0}};
    /* the texels cleared by a fill (memset speed on a CPU device, where a
     * clearing dispatch took 0.2 s per 2048^2 map) */
    vx__seq_copy(g, &seq, &sm->insts, hdr_at, &sm->map, 0, sizeof hdr);
    vx__seq_fill(g, &seq, &sm->map, 64, 4 * (VkDeviceSize)texels * 4, 0);
    for (int m = 1; m < 3; m++)
        pc[m] = (smap_push){.mode = (uint32_t)m, .count = (uint32_t)work, .insts = n, .side = sm->side,
                            .margin_tex = (float)(margin * inv), .margin = (float)margin};
    for (int m = 1; m < 3 && !r; m++) {
        uint32_t groups = (pc[m].count + 63) / 64, gx = groups < 65535 ? groups : 65535;
        vx__dispatch_desc dd = {.pipeline = p,
                                .buffer_count = 3,
                                .buffers = {&sm->nodes, &sm->insts, &sm->map},
                                .groups = {gx ? gx : 1, gx ? (groups + gx - 1) / gx : 1, 1},
                                .push = &pc[m],
                                .push_size = sizeof pc[m],
                                .label = m ? "shadow map" : "shadow map clear"};
        if (!work) break;
        r = vx__seq_dispatch(g, &seq, &dd, NULL, 0, err);
    }
    if (r) {
        vx__seq_abandon(g, &seq);
        return r;
    }
    if ((r = vx__seq_submit(g, &seq, err))) return r;
    sm->build_gpu_seconds = 0;
    for (uint32_t k = 0; k < seq.count; k++) sm->build_gpu_seconds += seq.seconds[k];
    sm->build_seconds = vx_time_now() - t0;
    sm->builds++;
    sm->insts_built = n;
    memcpy(sm->light, light, sizeof sm->light);
    for (int k = 0; k < 3; k++) sm->origin[k] = O[k], sm->axis_u[k] = U[k], sm->axis_v[k] = V[k];
    sm->u0 = umin, sm->v0 = vmin, sm->texel = 1 / inv;
    sm->margin = margin;
    sm->valid = true;
    return VX_OK;
}
