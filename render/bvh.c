/* render/bvh.c - binned SAH BVH over instance bounds (Wald, "On fast
 * construction of SAH-based bounding volume hierarchies", 2007): centroids
 * are binned into 16 bins along the widest axis, so each level costs O(n) and the whole
 * build O(n log n). Node bounds are rounded outward to float so that the
 * GPU's boxes always contain the double-precision ones. */
#include <float.h>
#include <math.h>
#include <string.h>

#include "render/render.h"

#define BINS 16

typedef struct box {
    double lo[3], hi[3];
} box;

static void box_empty(box* b) {
    for (int k = 0; k < 3; k++) b->lo[k] = INFINITY, b->hi[k] = -INFINITY;
}
static void box_grow(box* b, const double lo[3], const double hi[3]) {
    for (int k = 0; k < 3; k++) {
        if (lo[k] < b->lo[k]) b->lo[k] = lo[k];
        if (hi[k] > b->hi[k]) b->hi[k] = hi[k];
    }
}
static double box_area(const box* b) {
    double d[3];
    for (int k = 0; k < 3; k++) d[k] = b->hi[k] > b->lo[k] ? b->hi[k] - b->lo[k] : 0;
    return d[0] * d[1] + d[1] * d[2] + d[2] * d[0];
}

static float down_f(double v) {
    float f = (float)v;
    if ((double)f > v) f = nextafterf(f, -INFINITY);
    return f;
}
static float up_f(double v) {
    float f = (float)v;
    if ((double)f < v) f = nextafterf(f, INFINITY);
    return f;
}

typedef struct task {
    uint32_t node, first, count;
} task;

vx_result vx_bvh_build(const double* lo, const double* hi, uint32_t n, const vx_allocator* alloc, vx_bvh* out,
                       vx_error* err) {
    memset(out, 0, sizeof *out);
    out->alloc = alloc;
    if (n == 0) return VX_OK;
    if (n > (UINT32_MAX - 1) / 2) return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "too many instances for the BVH");
    for (size_t i = 0; i < 3 * (size_t)n; i++)
        if (!isfinite(lo[i]) || !isfinite(hi[i]) || lo[i] > hi[i])
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "instance %zu has invalid bounds", i / 3);
    uint32_t cap = 2 * n - 1;
    vx_bvh_node* nodes = vx_calloc(alloc, cap, sizeof *nodes);
    uint32_t* items = vx_calloc(alloc, n, sizeof *items);
    double* cen = vx_calloc(alloc, 3 * (size_t)n, sizeof *cen);
    task* stack = vx_calloc(alloc, 64 + (size_t)n, sizeof *stack);
    if (!nodes || !items || !cen || !stack) {
        vx_free(alloc, nodes), vx_free(alloc, items), vx_free(alloc, cen), vx_free(alloc, stack);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for a BVH of %u instances", n);
    }
    for (uint32_t i = 0; i < n; i++) {
        items[i] = i;
        for (int k = 0; k < 3; k++) cen[3 * i + k] = 0.5 * (lo[3 * i + k] + hi[3 * i + k]);
    }
    uint32_t used = 1, sp = 0;
    stack[sp++] = (task){0, 0, n};
    while (sp) {
        task t = stack[--sp];
        box b, cb;
        box_empty(&b), box_empty(&cb);
        for (uint32_t i = t.first; i < t.first + t.count; i++) {
            uint32_t it = items[i];
            box_grow(&b, &lo[3 * it], &hi[3 * it]);
            box_grow(&cb, &cen[3 * it], &cen[3 * it]);
        }
        vx_bvh_node* nd = &nodes[t.node];
        for (int k = 0; k < 3; k++) nd->lo[k] = down_f(b.lo[k]), nd->hi[k] = up_f(b.hi[k]);
        /* best binned split over all three axes */
        double best = INFINITY;
        int best_axis = -1, best_bin = 0;
        /* bin along the widest centroid axis only (Wald 2007): a third of
         * the work for nearly the same tree quality */
        int wide = 0;
        for (int ax = 1; ax < 3; ax++)
            if (cb.hi[ax] - cb.lo[ax] > cb.hi[wide] - cb.lo[wide]) wide = ax;
        for (int ax = wide; ax == wide && t.count > 1; ax++) {
            double ext = cb.hi[ax] - cb.lo[ax];
            if (!(ext > 0)) continue;
            box bb[BINS];
            uint32_t cnt[BINS] = {0};
            for (int k = 0; k < BINS; k++) box_empty(&bb[k]);
            double scale = BINS / ext;
            for (uint32_t i = t.first; i < t.first + t.count; i++) {
                uint32_t it = items[i];
                int k = (int)((cen[3 * it + ax] - cb.lo[ax]) * scale);
                if (k >= BINS) k = BINS - 1;
                if (k < 0) k = 0;
                cnt[k]++;
                box_grow(&bb[k], &lo[3 * it], &hi[3 * it]);
            }
            double right_area[BINS];
            uint32_t right_cnt[BINS];
            box acc;
            box_empty(&acc);
            uint32_t c = 0;
            for (int k = BINS - 1; k > 0; k--) {
                box_grow(&acc, bb[k].lo, bb[k].hi);
                c += cnt[k];
                right_area[k] = box_area(&acc);
                right_cnt[k] = c;
            }
            box_empty(&acc);
            c = 0;
            for (int k = 0; k < BINS - 1; k++) {
                box_grow(&acc, bb[k].lo, bb[k].hi);
                c += cnt[k];
                if (c == 0 || right_cnt[k + 1] == 0) continue;
                double cost = box_area(&acc) * c + right_area[k + 1] * right_cnt[k + 1];
                if (cost < best) best = cost, best_axis = ax, best_bin = k;
            }
        }
        /* A leaf holds one instance: the walk then tests each instance's box,
         * nearest first, and skips those past the nearest hit, before the
         * instance's transform and model walk (leaves of up to 4 walked their
         * instances in stored order: on the H200, 2048^3 sphere in 968 and 3,944
         * regions, 3-9% slower close-ups; docs/PERFORMANCE.md, issue 18, many
         * instances). */
        uint32_t mid;
        if (t.count == 1) {
            nd->first = t.first, nd->count = t.count;
            continue;
        }
        if (best_axis >= 0) {
            double ext = cb.hi[best_axis] - cb.lo[best_axis];
            double scale = BINS / ext;
            uint32_t i = t.first, j = t.first + t.count;
            while (i < j) {
                uint32_t it = items[i];
                int k = (int)((cen[3 * it + best_axis] - cb.lo[best_axis]) * scale);
                if (k >= BINS) k = BINS - 1;
                if (k <= best_bin)
                    i++;
                else {
                    items[i] = items[--j];
                    items[j] = it;
                }
            }
            mid = i - t.first;
            if (mid == 0 || mid == t.count) mid = t.count / 2;
        } else {
            mid = t.count / 2; /* all centroids coincide */
        }
        nd->first = used;
        nd->count = 0;
        uint32_t l = used, r = used + 1;
        used += 2;
        stack[sp++] = (task){r, t.first + mid, t.count - mid};
        stack[sp++] = (task){l, t.first, mid};
    }
    vx_free(alloc, cen);
    vx_free(alloc, stack);
    out->nodes = nodes;
    out->node_count = used;
    out->items = items;
    out->item_count = n;
    return VX_OK;
}

static double node_area(const vx_bvh_node* nd) {
    double d[3];
    for (int k = 0; k < 3; k++) d[k] = nd->hi[k] > nd->lo[k] ? (double)nd->hi[k] - nd->lo[k] : 0;
    return d[0] * d[1] + d[1] * d[2] + d[2] * d[0];
}

double vx_bvh_cost(const vx_bvh* b) {
    if (!b || !b->node_count) return 0;
    double root = node_area(&b->nodes[0]), c = 0;
    if (!(root > 0)) return 0;
    for (uint32_t i = 0; i < b->node_count; i++) {
        const vx_bvh_node* nd = &b->nodes[i];
        c += node_area(nd) / root * (nd->count ? (double)nd->count : 0.125);
    }
    return c;
}

double vx_bvh_refit(vx_bvh* b, const double* lo, const double* hi, uint32_t n) {
    if (!b || n != b->item_count) return -1;
    for (size_t i = 0; i < 3 * (size_t)n; i++)
        if (!isfinite(lo[i]) || !isfinite(hi[i]) || lo[i] > hi[i]) return -1;
    /* children follow their parent (the build hands out indices in order), so the last node first */
    for (uint32_t i = b->node_count; i-- > 0;) {
        vx_bvh_node* nd = &b->nodes[i];
        if (nd->count) {
            box bx;
            box_empty(&bx);
            for (uint32_t k = nd->first; k < nd->first + nd->count; k++)
                box_grow(&bx, &lo[3 * b->items[k]], &hi[3 * b->items[k]]);
            for (int k = 0; k < 3; k++) nd->lo[k] = down_f(bx.lo[k]), nd->hi[k] = up_f(bx.hi[k]);
        } else {
            const vx_bvh_node *l = &b->nodes[nd->first], *r = &b->nodes[nd->first + 1];
            for (int k = 0; k < 3; k++) nd->lo[k] = fminf(l->lo[k], r->lo[k]), nd->hi[k] = fmaxf(l->hi[k], r->hi[k]);
        }
    }
    return vx_bvh_cost(b);
}

void vx_bvh_levels(const vx_bvh* b, uint32_t* order, uint32_t* level_start, uint32_t* levels) {
    *levels = 0;
    if (!b || !b->node_count) {
        level_start[0] = 0;
        return;
    }
    /* breadth first: a level's children are appended after it */
    uint32_t at = 0, end = 1, nl = 0;
    order[0] = 0;
    level_start[0] = 0;
    while (at < end) {
        uint32_t next = end;
        for (uint32_t i = at; i < end; i++) {
            const vx_bvh_node* nd = &b->nodes[order[i]];
            if (!nd->count) order[next++] = nd->first, order[next++] = nd->first + 1;
        }
        level_start[++nl] = end;
        at = end, end = next;
    }
    *levels = nl;
}

void vx_bvh_free(vx_bvh* b) {
    if (!b) return;
    vx_free(b->alloc, b->nodes);
    vx_free(b->alloc, b->items);
    memset(b, 0, sizeof *b);
}
