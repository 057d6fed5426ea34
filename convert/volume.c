/* convert/volume.c - OpenVDB grids -> svo scene (see convert/volume.h). */
#include "convert/volume.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "formats/vdb.h"

typedef enum { MODE_FOG, MODE_SURFACE, MODE_SOLID } cell_mode;

/* One set cell or tile: the aligned cube [p, p + 2^level). */
typedef struct item {
    int32_t p[3];
    uint8_t level;
    float value;
    uint32_t rgba;
} item;

typedef struct collect {
    const vx_allocator* alloc;
    vx_vdb_file* file;
    uint32_t grid;
    int64_t color; /* grid index or -1 */
    cell_mode mode;
    bool threshold_set;
    double threshold;
    uint32_t max_level; /* D: region size and largest tile */
    uint64_t max_items; /* 0: no limit */
    item* items;
    size_t count, cap;
    vx_result failure; /* VX_OK unless a push failed */
} collect;

static bool inside(double v) { return v < 0.0; }

static uint8_t srgb8(double c) {
    if (!(c > 0.0)) return 0; /* also NaN */
    if (c >= 1.0) return 255;
    double s = c <= 0.0031308 ? 12.92 * c : 1.055 * pow(c, 1.0 / 2.4) - 0.055;
    return (uint8_t)(s * 255.0 + 0.5);
}

static uint32_t color_at(collect* c, const int32_t p[3], uint32_t* log2dim) {
    double v[3] = {0, 0, 0};
    bool active = false;
    *log2dim = 0;
    vx_vdb_probe(c->file, (uint32_t)c->color, p, v, &active, log2dim);
    return (uint32_t)srgb8(v[0]) | ((uint32_t)srgb8(v[1]) << 8) | ((uint32_t)srgb8(v[2]) << 16) | 0xFF000000u;
}

static bool push_raw(collect* c, const int32_t p[3], uint32_t level, double value, uint32_t rgba) {
    if (c->max_items && c->count >= c->max_items) {
        c->failure = VX_ERR_LIMIT;
        return false;
    }
    if (c->count == c->cap && !vx_grow(c->alloc, (void**)&c->items, &c->cap, c->count + 1, sizeof(item))) {
        c->failure = VX_ERR_NOMEM;
        return false;
    }
    item* it = &c->items[c->count++];
    memcpy(it->p, p, sizeof it->p);
    it->level = (uint8_t)level;
    it->value = (float)value;
    it->rgba = rgba;
    return true;
}

/* Adds a cube, cutting it where it is larger than a region or where the
 * colour grid is not constant over it. */
static bool push(collect* c, const int32_t p[3], uint32_t level, double value) {
    uint32_t rgba = 0;
    bool split = level > c->max_level;
    if (!split && c->color >= 0) {
        uint32_t l2 = 0;
        rgba = color_at(c, p, &l2);
        split = l2 < level; /* the colour's constant cube does not cover ours */
    }
    if (!split) return push_raw(c, p, level, value, rgba);
    const int32_t h = (int32_t)1 << (level - 1);
    for (int o = 0; o < 8; o++) {
        const int32_t q[3] = {p[0] + (o & 1) * h, p[1] + ((o >> 1) & 1) * h, p[2] + ((o >> 2) & 1) * h};
        if (!push(c, q, level - 1, value)) return false;
    }
    return true;
}

static bool outside_at(collect* c, int32_t x, int32_t y, int32_t z) {
    const int32_t q[3] = {x, y, z};
    double v[3] = {0, 0, 0};
    vx_vdb_probe(c->file, c->grid, q, v, NULL, NULL);
    return !inside(v[0]);
}

/* Index space ends at INT32_MIN/MAX; a neighbour beyond it is treated as
 * outside (the background there is unreachable for OpenVDB too). */
static bool has_outside_neighbour(collect* c, const int32_t p[3]) {
    static const int d[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
    for (int k = 0; k < 6; k++) {
        int64_t q[3];
        bool out_of_range = false;
        for (int a = 0; a < 3; a++) {
            q[a] = (int64_t)p[a] + d[k][a];
            if (q[a] < INT32_MIN || q[a] > INT32_MAX) out_of_range = true;
        }
        if (out_of_range || outside_at(c, (int32_t)q[0], (int32_t)q[1], (int32_t)q[2])) return true;
    }
    return false;
}

/* The cells of a square of 2^k x 2^k on one face of an interior tile that
 * have their outside neighbour across that face outside. When the cell
 * across the square's corner lies in a constant cube at least as large as
 * the square (cubes are aligned), the whole square shares its answer, so
 * the work follows the output rather than the tile's area. */
static bool surface_square(collect* c, const int32_t o[3], uint32_t level, int axis, int side, int64_t u0,
                           int64_t w0, uint32_t k, double x) {
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    const int64_t n = (int64_t)1 << level;
    int64_t q[3];
    q[axis] = (int64_t)o[axis] + (side ? n : -1);
    q[a1] = (int64_t)o[a1] + u0;
    q[a2] = (int64_t)o[a2] + w0;
    bool outside = true; /* beyond index space counts as outside */
    uint32_t l2 = 0;
    if (q[axis] >= INT32_MIN && q[axis] <= INT32_MAX) {
        const int32_t qi[3] = {(int32_t)q[0], (int32_t)q[1], (int32_t)q[2]};
        double v[3] = {0, 0, 0};
        vx_vdb_probe(c->file, c->grid, qi, v, NULL, &l2);
        outside = !inside(v[0]);
    } else {
        l2 = 31;
    }
    if (l2 >= k) {
        if (!outside) return true;
        const int64_t m = (int64_t)1 << k;
        for (int64_t u = 0; u < m; u++)
            for (int64_t w = 0; w < m; w++) {
                int32_t p[3];
                p[axis] = (int32_t)(o[axis] + (side ? n - 1 : 0));
                p[a1] = (int32_t)(o[a1] + u0 + u);
                p[a2] = (int32_t)(o[a2] + w0 + w);
                if (!push(c, p, 0, x)) return false;
            }
        return true;
    }
    const int64_t h = (int64_t)1 << (k - 1);
    for (int s = 0; s < 4; s++)
        if (!surface_square(c, o, level, axis, side, u0 + (s & 1) * h, w0 + (s >> 1) * h, k - 1, x)) return false;
    return true;
}

static bool on_value(void* user, const int32_t o[3], uint32_t level, bool active, const double v[3]) {
    collect* c = (collect*)user;
    const double x = v[0];
    switch (c->mode) {
        case MODE_FOG:
            if (!active) return true;
            if (c->threshold_set ? !(x >= c->threshold) : !(x > 0.0)) return true;
            return push(c, o, level, x);
        case MODE_SOLID:
            if (!inside(x)) return true;
            return push(c, o, level, x);
        case MODE_SURFACE:
            if (!active || !inside(x)) return true;
            if (level == 0) return has_outside_neighbour(c, o) ? push(c, o, 0, x) : true;
            /* An active interior tile (rare in level sets): only cells on
             * its faces can touch the outside. */
            for (int axis = 0; axis < 3; axis++)
                for (int side = 0; side < 2; side++)
                    if (!surface_square(c, o, level, axis, side, 0, 0, level, x)) return false;
            return true;
    }
    return true;
}

/* floor(x / 2^s) without relying on the sign behaviour of >> */
static int64_t floor_shift(int64_t x, uint32_t s) { return x >= 0 ? x >> s : -((-x - 1) >> s) - 1; }

typedef struct keyed {
    int64_t r[3];
    size_t index;
} keyed;

static int cmp_keyed(const void* a, const void* b) {
    const keyed* x = (const keyed*)a;
    const keyed* y = (const keyed*)b;
    for (int k = 2; k >= 0; k--)
        if (x->r[k] != y->r[k]) return x->r[k] < y->r[k] ? -1 : 1;
    return x->index < y->index ? -1 : (x->index > y->index); /* stable: keeps input order */
}

/* Index of grid i among the grids before it with the same name: 0 for the
 * first, N for the one OpenVDB calls "NAME[N]" (io::File's convention for a
 * name that occurs more than once; the file keeps the plain name for each).
 * -1 when grid i is out of range. */
static int same_name_index(vx_vdb_file* f, uint32_t i) {
    const char* name = vx_vdb_grid_name(f, i);
    if (!name) return -1;
    int k = 0;
    for (uint32_t j = 0; j < i; j++) {
        const char* o = vx_vdb_grid_name(f, j);
        if (o && strcmp(o, name) == 0) k++;
    }
    return k;
}

/* "NAME[N]" -> base length and N (true), else false. */
static bool split_indexed_name(const char* name, size_t* base_len, uint32_t* index) {
    size_t n = strlen(name);
    if (n < 4 || name[n - 1] != ']') return false;
    size_t open = n - 1;
    while (open > 0 && name[open - 1] >= '0' && name[open - 1] <= '9') open--;
    if (open == 0 || open == n - 1 || name[open - 1] != '[' || n - 1 - open > 9) return false;
    uint32_t v = 0;
    for (size_t k = open; k < n - 1; k++) v = v * 10u + (uint32_t)(name[k] - '0');
    *base_len = open - 1;
    *index = v;
    return true;
}

/* The grid named name (NULL: the first float or double grid). A name that
 * several grids share selects the first of them; "NAME[N]" selects the
 * N-th after it (N counted from 0), as OpenVDB's io::File::readGrid does,
 * unless a grid is literally named so. */
static int find_grid(vx_vdb_file* f, const char* name, vx_vdb_grid_info* info, vx_error* err) {
    uint32_t n = vx_vdb_grid_count(f);
    for (uint32_t i = 0; i < n; i++) {
        if (vx_vdb_grid_get_info(f, i, info, err) != VX_OK) return -2;
        const char* full = vx_vdb_grid_name(f, i);
        if (name ? full && strcmp(full, name) == 0
                 : (info->value_type == VX_VDB_TYPE_FLOAT || info->value_type == VX_VDB_TYPE_DOUBLE))
            return (int)i;
    }
    size_t base_len;
    uint32_t want;
    if (!name || !split_indexed_name(name, &base_len, &want)) return -1;
    uint32_t seen = 0;
    for (uint32_t i = 0; i < n; i++) {
        const char* full = vx_vdb_grid_name(f, i);
        if (!full || strlen(full) != base_len || memcmp(full, name, base_len) != 0 || seen++ != want) continue;
        return vx_vdb_grid_get_info(f, i, info, err) == VX_OK ? (int)i : -2;
    }
    return -1;
}

/* OpenVDB point data (points::PointDataGrid: "Tree_ptdataidx32_5_4_3"). */
static bool is_points_type(const char* type) { return strncmp(type, "Tree_ptdataidx", 14) == 0; }

static bool has_points_grid(vx_vdb_file* f) {
    uint32_t n = vx_vdb_grid_count(f);
    for (uint32_t i = 0; i < n; i++) {
        vx_vdb_grid_info gi;
        if (vx_vdb_grid_get_info(f, i, &gi, NULL) == VX_OK && is_points_type(gi.type)) return true;
    }
    return false;
}

/* "'a' Tree_float_5_4_3, 'a[1]' Tree_float_5_4_3, ...": repeated names
 * with the index that selects them. */
static void list_grids(vx_vdb_file* f, char* buf, size_t cap) {
    size_t used = 0;
    buf[0] = 0;
    uint32_t n = vx_vdb_grid_count(f);
    for (uint32_t i = 0; i < n && used + 1 < cap; i++) {
        vx_vdb_grid_info gi;
        if (vx_vdb_grid_get_info(f, i, &gi, NULL) != VX_OK) continue;
        int k = same_name_index(f, i);
        char suffix[16] = "";
        if (k > 0) snprintf(suffix, sizeof suffix, "[%d]", k);
        int w = snprintf(buf + used, cap - used, "%s'%s%s' %s", i ? ", " : "", gi.name, suffix, gi.type);
        if (w < 0) break;
        used += (size_t)w < cap - used ? (size_t)w : cap - used - 1;
    }
}

typedef struct group_arrays {
    uint64_t* keys;
    uint8_t* level;
    float* density;
    uint32_t* rgba;
} group_arrays;

/* Receives one region's cells (in region order: z, then y, then x) with
 * the region index, ready for vx_svo_build_model; origin is where the
 * model's cell 0 lies in index space. */
typedef vx_result (*region_fn)(void* user, const int64_t region[3], const int64_t origin[3], const vx_svo_voxels* vox,
                               vx_error* err);

/* OpenVDB centres voxel ijk on the point ijk; our cell g spans [g, g+1]. */
static void world_from_index(const vx_vdb_grid_info* info, double out[12]) {
    for (int row = 0; row < 3; row++) {
        const double* m = &info->index_to_world[row * 4];
        for (int k = 0; k < 4; k++) out[row * 4 + k] = m[k];
        out[row * 4 + 3] = m[3] - 0.5 * (m[0] + m[1] + m[2]);
    }
}

/* Orders the cells by region (z, y, x, then input order) into order[].
 * The regions of a grid are few and dense, so a counting sort over their
 * bounding box does it in linear time; a sparse spread of regions (a box
 * much larger than the cell count) falls back to qsort. Same order both
 * ways. Returns false when out of memory. */
static bool order_by_region(const vx_allocator* a, keyed* order, size_t n) {
    int64_t lo[3], hi[3];
    for (int k = 0; k < 3; k++) lo[k] = hi[k] = order[0].r[k];
    for (size_t i = 1; i < n; i++)
        for (int k = 0; k < 3; k++) {
            if (order[i].r[k] < lo[k]) lo[k] = order[i].r[k];
            if (order[i].r[k] > hi[k]) hi[k] = order[i].r[k];
        }
    uint64_t ext[3], cells = 1;
    bool dense = true;
    for (int k = 0; k < 3 && dense; k++) {
        ext[k] = (uint64_t)(hi[k] - lo[k]) + 1; /* regions are cells >> D, D >= 1: no overflow */
        if (ext[k] > 4 * (uint64_t)n + 64 || cells > (4 * (uint64_t)n + 64) / ext[k]) dense = false;
        else cells *= ext[k];
    }
    if (!dense) {
        qsort(order, n, sizeof *order, cmp_keyed);
        return true;
    }
    size_t* start = (size_t*)vx_calloc(a, (size_t)cells + 1, sizeof *start);
    keyed* sorted = (keyed*)vx_calloc(a, n, sizeof *sorted);
    if (!start || !sorted) {
        vx_free(a, start);
        vx_free(a, sorted);
        return false;
    }
#define VX__REGION_SLOT(e) \
    ((size_t)(((uint64_t)((e)->r[2] - lo[2]) * ext[1] + (uint64_t)((e)->r[1] - lo[1])) * ext[0] + (uint64_t)((e)->r[0] - lo[0])))
    for (size_t i = 0; i < n; i++) start[VX__REGION_SLOT(&order[i]) + 1]++;
    for (size_t j = 1; j <= cells; j++) start[j] += start[j - 1];
    for (size_t i = 0; i < n; i++) sorted[start[VX__REGION_SLOT(&order[i])]++] = order[i];
#undef VX__REGION_SLOT
    memcpy(order, sorted, n * sizeof *order);
    vx_free(a, sorted);
    vx_free(a, start);
    return true;
}

/* Selects the cells of the grid d names (or the first float grid), cuts
 * them into regions and hands each region to fn. *info_out gets the grid's
 * info. */
static vx_result convert_grid(const vx_conv_vdb_desc* d, vx_vdb_file* f, vx_vdb_grid_info* info_out, region_fn fn,
                              void* user, vx_conv_stats* st, vx_error* err) {
    const vx_allocator* a = d->alloc;
    vx_vdb_grid_info info, cinfo;
    char names[160];
    int gi = find_grid(f, d->grid, &info, err);
    if (gi == -2) return err ? err->code : VX_ERR_BAD_FORMAT;
    if (gi < 0) {
        list_grids(f, names, sizeof names);
        if (d->grid)
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "vdb: no grid named '%s' (grids: %s)", d->grid,
                           names[0] ? names : "none");
        return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "vdb: no float or double grid%s (grids: %s)",
                       has_points_grid(f) ? "; OpenVDB points grids are not converted" : "", names[0] ? names : "none");
    }
    if (is_points_type(info.type))
        return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET,
                       "vdb: grid '%s' is an OpenVDB points grid (%s); points are not converted, only float or double grids",
                       info.name, info.type);
    if (info.value_type != VX_VDB_TYPE_FLOAT && info.value_type != VX_VDB_TYPE_DOUBLE)
        return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "vdb: grid '%s' has type %s; need a float or double grid",
                       info.name, info.type);
    if (!info.linear)
        return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET,
                       "vdb: grid '%s' has a non-linear (frustum) transform; only affine transforms are supported",
                       info.name);
    for (int k = 0; k < 12; k++)
        if (!isfinite(info.index_to_world[k]))
            return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "vdb: grid '%s' has a non-finite transform",
                           info.name);
    *info_out = info;
    int64_t color = -1;
    if (d->color_grid) {
        int ci = find_grid(f, d->color_grid, &cinfo, err);
        if (ci == -2) return err ? err->code : VX_ERR_BAD_FORMAT;
        if (ci < 0) {
            list_grids(f, names, sizeof names);
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "vdb: no colour grid named '%s' (grids: %s)",
                           d->color_grid, names);
        }
        if (cinfo.value_type != VX_VDB_TYPE_VEC3F && cinfo.value_type != VX_VDB_TYPE_VEC3D)
            return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "vdb: colour grid '%s' has type %s; need a vec3 grid",
                           cinfo.name, cinfo.type);
        color = ci;
    }

    uint32_t D = d->max_model_depth ? d->max_model_depth : VX_SVO_MAX_DEPTH;
    uint32_t bd = d->build.max_depth ? d->build.max_depth : VX_SVO_MAX_DEPTH;
    if (bd < D) D = bd;
    if (d->brick_depth && d->brick_depth < D) D = d->brick_depth;
    if (D > VX_SVO_MAX_DEPTH) D = VX_SVO_MAX_DEPTH;
    if (D == 0) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "vdb: model depth must be at least 1");

    double t0 = vx_time_now();
    collect c = {0};
    c.alloc = a;
    c.file = f;
    c.grid = (uint32_t)gi;
    c.color = color;
    c.mode = d->solid ? MODE_SOLID : info.grid_class == VX_VDB_CLASS_LEVEL_SET ? MODE_SURFACE : MODE_FOG;
    c.threshold_set = d->threshold_set;
    c.threshold = d->threshold;
    c.max_level = D;
    c.max_items = d->max_cells;
    vx_result r = vx_vdb_iterate(f, c.grid, c.mode == MODE_SOLID ? VX_VDB_ITER_ALL : VX_VDB_ITER_ACTIVE, on_value,
                                 &c, err);
    if (r == VX_OK && c.failure == VX_ERR_LIMIT)
        r = vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "vdb: grid '%s': more than %llu cells and tiles (max_cells)",
                    info.name, (unsigned long long)d->max_cells);
    else if (r == VX_OK && c.failure != VX_OK)
        r = vx_fail(err, c.failure, VX_NO_OFFSET, "vdb: out of memory collecting cells");
    if (r != VX_OK) {
        vx_free(a, c.items);
        return r;
    }

    /* Group the cubes by region of 2^D cells; one model each. Regions
     * start at the lowest cell rounded down to the largest tile (so tiles
     * never straddle a region), not at index 0: a grid around the origin
     * stays one model. */
    keyed* order = NULL;
    bool single = true;
    int64_t base[3] = {0, 0, 0}, r0[3] = {0, 0, 0};
    uint32_t lg = 0;
    for (size_t i = 0; i < c.count; i++) {
        if (c.items[i].level > lg) lg = c.items[i].level;
        for (int k = 0; k < 3; k++)
            if (i == 0 || c.items[i].p[k] < base[k]) base[k] = c.items[i].p[k];
    }
    for (int k = 0; k < 3; k++) base[k] = floor_shift(base[k], lg) * ((int64_t)1 << lg);
    if (d->brick_depth) /* bricks at fixed places: the same in every frame of a sequence */
        for (int k = 0; k < 3; k++) base[k] = 0;
    for (size_t i = 0; i < c.count; i++)
        for (int k = 0; k < 3; k++) {
            int64_t rk = floor_shift(c.items[i].p[k] - base[k], D);
            if (i == 0) r0[k] = rk;
            else if (rk != r0[k]) single = false;
        }
    if (!single) {
        order = (keyed*)vx_calloc(a, c.count, sizeof *order);
        if (order) {
            for (size_t i = 0; i < c.count; i++) {
                for (int k = 0; k < 3; k++) order[i].r[k] = floor_shift(c.items[i].p[k] - base[k], D);
                order[i].index = i;
            }
        }
        if (!order || !order_by_region(a, order, c.count)) {
            vx_free(a, order);
            vx_free(a, c.items);
            return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "vdb: out of memory sorting %zu cells", c.count);
        }
    }
    if (st) st->seconds_voxelize += vx_time_now() - t0;

    group_arrays g = {0};
    const bool want_density = d->density;
    const bool want_color = color >= 0;

    for (size_t begin = 0; begin < c.count && r == VX_OK;) {
        size_t end = c.count;
        if (order) {
            end = begin + 1;
            while (end < c.count && memcmp(order[end].r, order[begin].r, sizeof order[begin].r) == 0) end++;
        }
        const size_t n = end - begin;
        int64_t lo[3] = {INT64_MAX, INT64_MAX, INT64_MAX}, hi[3] = {INT64_MIN, INT64_MIN, INT64_MIN};
        uint32_t lmax = 0;
        bool any_tile = false;
        for (size_t i = begin; i < end; i++) {
            const item* it = &c.items[order ? order[i].index : i];
            for (int k = 0; k < 3; k++) {
                if (it->p[k] < lo[k]) lo[k] = it->p[k];
                int64_t e = (int64_t)it->p[k] + ((int64_t)1 << it->level);
                if (e > hi[k]) hi[k] = e;
            }
            if (it->level > lmax) lmax = it->level;
            if (it->level) any_tile = true;
        }
        /* Tiles stay aligned in model space when the origin is a multiple
         * of the largest tile; it stays inside the region since the region
         * start is a multiple of 2^lg >= 2^lmax. */
        int64_t origin[3], region[3];
        uint32_t size[3];
        for (int k = 0; k < 3; k++) {
            origin[k] = floor_shift(lo[k], lmax) * ((int64_t)1 << lmax);
            size[k] = (uint32_t)(hi[k] - origin[k]);
            region[k] = order ? order[begin].r[k] : r0[k];
        }
        g.keys = (uint64_t*)vx_calloc(a, n, sizeof *g.keys);
        g.level = any_tile ? (uint8_t*)vx_calloc(a, n, 1) : NULL;
        g.density = want_density ? (float*)vx_calloc(a, n, sizeof *g.density) : NULL;
        g.rgba = want_color ? (uint32_t*)vx_calloc(a, n, sizeof *g.rgba) : NULL;
        if (!g.keys || (any_tile && !g.level) || (want_density && !g.density) || (want_color && !g.rgba)) {
            r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "vdb: out of memory for a model of %zu cells", n);
            break;
        }
        for (size_t i = begin; i < end; i++) {
            const item* it = &c.items[order ? order[i].index : i];
            const size_t j = i - begin;
            g.keys[j] = vx_svo_morton((uint32_t)(it->p[0] - origin[0]), (uint32_t)(it->p[1] - origin[1]),
                                      (uint32_t)(it->p[2] - origin[2]));
            if (g.level) g.level[j] = it->level;
            if (g.density) g.density[j] = it->value;
            if (g.rgba) g.rgba[j] = it->rgba;
        }
        vx_svo_voxels vox = {0};
        memcpy(vox.size, size, sizeof size);
        vox.count = n;
        vox.keys = g.keys;
        vox.level = g.level;
        vox.attrs = (want_density ? VX_ATTR_DENSITY : 0u) | (want_color ? VX_ATTR_RGBA8 : 0u);
        vox.density = g.density;
        vox.rgba = g.rgba;
        r = fn(user, region, origin, &vox, err);

        vx_free(a, g.keys);
        vx_free(a, g.level);
        vx_free(a, g.density);
        vx_free(a, g.rgba);
        memset(&g, 0, sizeof g);
        begin = end;
    }
    vx_free(a, order);
    vx_free(a, c.items);
    if (r == VX_OK && c.count == 0)
        vx_log(d->logger, VX_LOG_WARN, "vdb.empty", "vdb: grid '%s': no cells selected", info.name);
    return r;
}

static void add_build_stats(vx_svo_build_stats* sum, const vx_svo_build_stats* b) {
    sum->input_voxels += b->input_voxels;
    sum->voxels += b->voxels;
    sum->desc_plain += b->desc_plain;
    sum->desc_collapsed += b->desc_collapsed;
    sum->desc_dag += b->desc_dag;
    sum->far_pointers += b->far_pointers;
    sum->attr_records += b->attr_records;
    sum->bytes += b->bytes;
}

/* Builds one region's model: the build time and statistics go to st. */
static vx_result build_region(const vx_conv_vdb_desc* d, const vx_svo_voxels* vox, vx_svo_model* model,
                              vx_svo_build_stats* bs, vx_conv_stats* st, vx_error* err) {
    vx_svo_build_desc bdesc = d->build;
    if (!bdesc.alloc) bdesc.alloc = d->alloc;
    memset(model, 0, sizeof *model);
    memset(bs, 0, sizeof *bs);
    double t0 = vx_time_now();
    vx_result r = vx_svo_build_model(&bdesc, vox, model, bs, err);
    if (st) st->seconds_build += vx_time_now() - t0;
    if (r != VX_OK) {
        vx_error_prefix(err, "vdb");
        return r;
    }
    if (st) add_build_stats(&st->build, bs);
    return VX_OK;
}

static void name_instance(vx_svo_instance* in, const char* name) {
    size_t len = strlen(name);
    if (len >= sizeof in->name) len = sizeof in->name - 1; /* names are cut, not refused */
    memcpy(in->name, name, len);
}

/* A single grid: one model and one instance per region. */
typedef struct scene_sink {
    const vx_conv_vdb_desc* d;
    vx_svo_scene* s;
    size_t model_cap, inst_cap;
    vx_conv_stats* st;
    const char* name;
} scene_sink;

static vx_result scene_region(void* user, const int64_t region[3], const int64_t origin[3], const vx_svo_voxels* vox,
                              vx_error* err) {
    (void)region;
    scene_sink* k = (scene_sink*)user;
    vx_svo_scene* s = k->s;
    const vx_allocator* a = k->d->alloc;
    if (!vx_grow(a, (void**)&s->models, &k->model_cap, (size_t)s->model_count + 1, sizeof *s->models) ||
        !vx_grow(a, (void**)&s->instances, &k->inst_cap, (size_t)s->instance_count + 1, sizeof *s->instances))
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "vdb: out of memory for model %u", s->model_count);
    vx_svo_model model;
    vx_svo_build_stats bs;
    vx_result r = build_region(k->d, vox, &model, &bs, k->st, err);
    if (r != VX_OK) return r;
    vx_svo_instance* in = &s->instances[s->instance_count];
    memset(in, 0, sizeof *in);
    in->xform[0] = in->xform[5] = in->xform[10] = 1.0;
    in->xform[3] = (double)origin[0];
    in->xform[7] = (double)origin[1];
    in->xform[11] = (double)origin[2];
    in->model = s->model_count;
    in->layer = UINT32_MAX;
    name_instance(in, k->name);
    s->models[s->model_count++] = model;
    s->instance_count++;
    return VX_OK;
}

static vx_result convert_file(const vx_conv_vdb_desc* d, vx_vdb_file* f, vx_svo_scene* out, vx_conv_stats* st,
                              vx_error* err) {
    vx_svo_scene s;
    vx_svo_scene_init(&s, d->alloc);
    vx_vdb_grid_info info;
    memset(&info, 0, sizeof info);
    scene_sink k = {.d = d, .s = &s, .st = st, .name = info.name};
    vx_result r = convert_grid(d, f, &info, scene_region, &k, st, err);
    if (r != VX_OK) {
        vx_svo_scene_free(&s);
        return r;
    }
    world_from_index(&info, s.world_from_grid);
    vx_svo_scene_update_bounds(&s);
    if (st) {
        st->models = s.model_count;
        st->instances = s.instance_count;
    }
    *out = s;
    return VX_OK;
}

/* Parses the bytes and converts; *free_data (if set) is released as soon
 * as OpenVDB has its own copy, so the raw file and the grids are not both
 * held while cells are collected. */
static vx_result convert_bytes(const vx_conv_vdb_desc* desc, const void* data, size_t size, uint8_t** free_data,
                               vx_svo_scene* out, vx_conv_stats* stats, vx_error* err) {
    vx_conv_vdb_desc d = {0};
    if (desc) d = *desc;
    vx_conv_stats st = {0};
    double t0 = vx_time_now();
    vx_vdb_file* f = NULL;
    vx_result r = vx_vdb_read(data, size, &f, err);
    if (free_data) {
        vx_free(d.alloc, *free_data);
        *free_data = NULL;
    }
    st.seconds_read = vx_time_now() - t0;
    if (r != VX_OK) return r;
    r = convert_file(&d, f, out, &st, err);
    vx_vdb_file_free(f);
    if (r == VX_OK && stats) {
        st.peak_bytes = vx_peak_rss();
        *stats = st;
    }
    return r;
}

vx_result vx_conv_vdb_memory(const vx_conv_vdb_desc* desc, const void* data, size_t size, vx_svo_scene* out,
                             vx_conv_stats* stats, vx_error* err) {
    if (!out || (!data && size)) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "vdb: NULL argument");
    return convert_bytes(desc, data, size, NULL, out, stats, err);
}

vx_result vx_conv_vdb_file(const vx_conv_vdb_desc* desc, const char* path, vx_svo_scene* out, vx_conv_stats* stats,
                           vx_error* err) {
    if (!path || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "vdb: NULL argument");
    const vx_allocator* a = desc ? desc->alloc : NULL;
    double t0 = vx_time_now();
    uint8_t* data = NULL;
    size_t size = 0;
    vx_result r = vx_file_read(path, a, 0, &data, &size, err);
    if (r != VX_OK) return r;
    double tread = vx_time_now() - t0;
    vx_conv_stats st = {0};
    r = convert_bytes(desc, data, size, &data, out, &st, err);
    if (r == VX_OK && stats) {
        st.seconds_read += tread;
        *stats = st;
    }
    return r;
}

/* ---- sequences ----------------------------------------------------------------------- */

/* Where a frame placed one model: its brick (region index) and origin. */
typedef struct placement {
    int64_t brick[3];
    uint32_t frame, model;
    double origin[3];
} placement;

static int cmp_region(const int64_t* p, const int64_t* q) {
    for (int k = 2; k >= 0; k--) /* the order convert_grid hands regions out in */
        if (p[k] != q[k]) return p[k] < q[k] ? -1 : 1;
    return 0;
}

static int cmp_placement(const void* a, const void* b) {
    const placement *p = (const placement*)a, *q = (const placement*)b;
    for (int k = 0; k < 3; k++) /* instances by brick, x first */
        if (p->brick[k] != q->brick[k]) return p->brick[k] < q->brick[k] ? -1 : 1;
    return p->frame < q->frame ? -1 : p->frame > q->frame;
}

/* The sequence's models without repeats: a model equal to a stored one is
 * freed and the stored index used (open addressing on vx_svo_model_hash;
 * each model's hash is kept, so growing the table hashes nothing again). */
typedef struct model_set {
    const vx_allocator* a;
    vx_svo_scene* s;
    size_t model_cap, hash_cap;
    uint64_t* hash; /* per stored model */
    uint32_t* slot; /* model index + 1, 0 = empty */
    size_t cap;
} model_set;

static vx_result model_set_add(model_set* ms, vx_svo_model* m, uint32_t* index, vx_error* err) {
    if (2 * ((size_t)ms->s->model_count + 1) > ms->cap) {
        size_t cap = ms->cap ? ms->cap * 2 : 64;
        uint32_t* slot = (uint32_t*)vx_calloc(ms->a, cap, sizeof *slot);
        if (!slot) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "vdb sequence: out of memory");
        for (uint32_t i = 0; i < ms->s->model_count; i++) {
            size_t h = (size_t)ms->hash[i] & (cap - 1);
            while (slot[h]) h = (h + 1) & (cap - 1);
            slot[h] = i + 1;
        }
        vx_free(ms->a, ms->slot);
        ms->slot = slot, ms->cap = cap;
    }
    const uint64_t hash = vx_svo_model_hash(m);
    size_t h = (size_t)hash & (ms->cap - 1);
    for (; ms->slot[h]; h = (h + 1) & (ms->cap - 1))
        if (ms->hash[ms->slot[h] - 1] == hash && vx_svo_model_equal(&ms->s->models[ms->slot[h] - 1], m)) {
            *index = ms->slot[h] - 1;
            vx_svo_model_free(ms->a, m);
            return VX_OK;
        }
    const size_t need = (size_t)ms->s->model_count + 1;
    if (!vx_grow(ms->a, (void**)&ms->s->models, &ms->model_cap, need, sizeof *ms->s->models) ||
        !vx_grow(ms->a, (void**)&ms->hash, &ms->hash_cap, need, sizeof *ms->hash))
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "vdb sequence: out of memory");
    *index = ms->s->model_count;
    ms->hash[*index] = hash;
    ms->s->models[ms->s->model_count++] = *m;
    memset(m, 0, sizeof *m);
    ms->slot[h] = *index + 1;
    return VX_OK;
}

/* One frame's regions with a copy of their cells. The next frame compares
 * each of its regions with the same region here and takes the model of an
 * unchanged one without building it: the parts of a sequence that stand
 * still cost a comparison, not an octree build. Cells of a region are
 * stored from off on; level is 0 for plain cells. */
typedef struct frame_region {
    int64_t region[3], origin[3];
    uint32_t size[3];
    size_t n, off;
    uint32_t model;
    vx_svo_build_stats bs;
} frame_region;

typedef struct frame_cells {
    frame_region* r;
    size_t count, cap;
    uint64_t* keys;
    uint8_t* level;
    float* density;
    uint32_t* rgba;
    size_t cells, keys_cap, level_cap, density_cap, rgba_cap;
    size_t cursor; /* the next frame's walk through r (both in region order) */
} frame_cells;

static void frame_cells_free(const vx_allocator* a, frame_cells* fc) {
    vx_free(a, fc->r);
    vx_free(a, fc->keys);
    vx_free(a, fc->level);
    vx_free(a, fc->density);
    vx_free(a, fc->rgba);
}

static bool same_cells(const frame_cells* fc, const frame_region* p, const int64_t origin[3], const vx_svo_voxels* vox) {
    if (memcmp(p->origin, origin, sizeof p->origin) || memcmp(p->size, vox->size, sizeof p->size) || p->n != vox->count)
        return false;
    const size_t n = vox->count;
    if (memcmp(fc->keys + p->off, vox->keys, n * sizeof *vox->keys)) return false;
    for (size_t i = 0; i < n; i++)
        if (fc->level[p->off + i] != (vox->level ? vox->level[i] : 0)) return false;
    if (vox->density && memcmp(fc->density + p->off, vox->density, n * sizeof *vox->density)) return false;
    if (vox->rgba && memcmp(fc->rgba + p->off, vox->rgba, n * sizeof *vox->rgba)) return false;
    return true;
}

typedef struct seq_sink {
    const vx_conv_vdb_desc* d;
    model_set* ms;
    frame_cells *prev, *cur;
    placement* pl;
    size_t np, pl_cap;
    uint32_t frame;
    uint32_t reused; /* regions taken unchanged from the frame before */
    vx_conv_stats* st;
} seq_sink;

static vx_result seq_region(void* user, const int64_t region[3], const int64_t origin[3], const vx_svo_voxels* vox,
                            vx_error* err) {
    seq_sink* k = (seq_sink*)user;
    const vx_allocator* a = k->d->alloc;
    frame_cells *prev = k->prev, *cur = k->cur;
    while (prev->cursor < prev->count && cmp_region(prev->r[prev->cursor].region, region) < 0) prev->cursor++;
    const frame_region* p = prev->cursor < prev->count ? &prev->r[prev->cursor] : NULL;
    const size_t n = vox->count, off = cur->cells;
    if (!vx_grow(a, (void**)&k->pl, &k->pl_cap, k->np + 1, sizeof *k->pl) ||
        !vx_grow(a, (void**)&cur->r, &cur->cap, cur->count + 1, sizeof *cur->r) ||
        !vx_grow(a, (void**)&cur->keys, &cur->keys_cap, off + n, sizeof *cur->keys) ||
        !vx_grow(a, (void**)&cur->level, &cur->level_cap, off + n, sizeof *cur->level) ||
        (vox->density && !vx_grow(a, (void**)&cur->density, &cur->density_cap, off + n, sizeof *cur->density)) ||
        (vox->rgba && !vx_grow(a, (void**)&cur->rgba, &cur->rgba_cap, off + n, sizeof *cur->rgba)))
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "vdb sequence: out of memory");
    frame_region* c = &cur->r[cur->count];
    memset(c, 0, sizeof *c);
    if (p && !cmp_region(p->region, region) && same_cells(prev, p, origin, vox)) {
        c->model = p->model;
        c->bs = p->bs;
        if (k->st) add_build_stats(&k->st->build, &c->bs);
        k->reused++;
    } else {
        vx_svo_model model;
        vx_result r = build_region(k->d, vox, &model, &c->bs, k->st, err);
        if (r == VX_OK) r = model_set_add(k->ms, &model, &c->model, err);
        if (r != VX_OK) {
            vx_svo_model_free(a, &model); /* emptied by model_set_add where it was kept */
            return r;
        }
    }
    memcpy(c->region, region, sizeof c->region);
    memcpy(c->origin, origin, sizeof c->origin);
    memcpy(c->size, vox->size, sizeof c->size);
    c->n = n, c->off = off;
    memcpy(cur->keys + off, vox->keys, n * sizeof *vox->keys);
    if (vox->level) memcpy(cur->level + off, vox->level, n);
    else memset(cur->level + off, 0, n);
    if (vox->density) memcpy(cur->density + off, vox->density, n * sizeof *vox->density);
    if (vox->rgba) memcpy(cur->rgba + off, vox->rgba, n * sizeof *vox->rgba);
    cur->cells += n;
    cur->count++;

    placement* q = &k->pl[k->np++];
    q->frame = k->frame;
    q->model = c->model;
    for (int i = 0; i < 3; i++) q->brick[i] = region[i], q->origin[i] = (double)origin[i];
    return VX_OK;
}

/* Reads one frame's file and hands its regions to the sink. */
static vx_result seq_frame(const vx_conv_vdb_desc* d, const char* path, seq_sink* k, vx_vdb_grid_info* info,
                           vx_conv_stats* cs, vx_error* err) {
    double t0 = vx_time_now();
    uint8_t* data = NULL;
    size_t size = 0;
    vx_result r = vx_file_read(path, d->alloc, 0, &data, &size, err);
    if (r != VX_OK) return r;
    vx_vdb_file* f = NULL;
    r = vx_vdb_read(data, size, &f, err);
    vx_free(d->alloc, data);
    cs->seconds_read += vx_time_now() - t0;
    if (r != VX_OK) return r;
    r = convert_grid(d, f, info, seq_region, k, cs, err);
    vx_vdb_file_free(f);
    return r;
}

vx_result vx_conv_vdb_sequence(const vx_conv_vdb_desc* desc, const char* const* paths, uint32_t count, vx_svo_scene* out,
                               vx_conv_stats* stats, vx_error* err) {
    if (!paths || !out || count == 0) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "vdb sequence: no frames");
    vx_conv_vdb_desc d = {0};
    if (desc) d = *desc;
    if (!d.brick_depth) d.brick_depth = VX_CONV_VDB_SEQUENCE_BRICK_DEPTH;
    const vx_allocator* a = d.alloc;
    vx_conv_stats cs = {0};
    vx_svo_scene s;
    vx_svo_scene_init(&s, a);
    model_set ms = {.a = a, .s = &s};
    frame_cells fc[2];
    memset(fc, 0, sizeof fc);
    seq_sink k = {.d = &d, .ms = &ms, .prev = &fc[0], .cur = &fc[1], .st = &cs};
    vx_svo_instance named; /* the grid's name as instances carry it */
    memset(&named, 0, sizeof named);
    vx_result r = VX_OK;
    for (uint32_t f = 0; f < count && r == VX_OK; f++) {
        vx_vdb_grid_info info;
        memset(&info, 0, sizeof info);
        k.frame = f;
        if ((r = seq_frame(&d, paths[f], &k, &info, &cs, err)) != VX_OK) {
            char where[64];
            snprintf(where, sizeof where, "frame %u", f);
            vx_error_prefix(err, paths[f]);
            vx_error_prefix(err, where);
            break;
        }
        double w[12];
        world_from_index(&info, w);
        if (f == 0) memcpy(s.world_from_grid, w, sizeof s.world_from_grid);
        else if (memcmp(s.world_from_grid, w, sizeof s.world_from_grid))
            r = vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "frame %u (%s): its grid transform differs from frame 0's", f,
                        paths[f]);
        if (f == 0) name_instance(&named, info.name);
        frame_cells* t = k.prev; /* this frame is the next one's "before" */
        k.prev = k.cur, k.cur = t;
        k.cur->count = k.cur->cells = 0;
        k.prev->cursor = 0;
    }
    frame_cells_free(a, &fc[0]);
    frame_cells_free(a, &fc[1]);
    placement* pl = k.pl;
    const size_t np = k.np;
    /* one instance per brick any frame fills; hidden in the frames where the
     * brick is empty (with its first model and place) */
    uint32_t I = 0;
    if (r == VX_OK && np) {
        qsort(pl, np, sizeof *pl, cmp_placement);
        for (size_t i = 0; i < np; i++) I += i == 0 || memcmp(pl[i].brick, pl[i - 1].brick, sizeof pl[i].brick) != 0;
        s.instances = (vx_svo_instance*)vx_calloc(a, I, sizeof *s.instances);
        s.instance_count = I;
        if (!s.instances) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "vdb sequence: out of memory");
        if (r == VX_OK && count > 1) r = vx_svo_scene_alloc_frames(&s, count, err);
    }
    for (size_t i = 0, b = 0; r == VX_OK && i < np; b++) {
        size_t e = i + 1;
        while (e < np && !memcmp(pl[e].brick, pl[i].brick, sizeof pl[i].brick)) e++;
        vx_svo_instance first = {.model = pl[i].model, .layer = UINT32_MAX, .flags = VX_SVO_INSTANCE_HIDDEN};
        first.xform[0] = first.xform[5] = first.xform[10] = 1.0;
        for (int k3 = 0; k3 < 3; k3++) first.xform[4 * k3 + 3] = pl[i].origin[k3];
        memcpy(first.name, named.name, sizeof first.name);
        for (uint32_t f = 0; f < count; f++) *(vx_svo_instance*)&vx_svo_scene_frame_instances(&s, f)[b] = first;
        for (; i < e; i++) {
            vx_svo_instance* in = (vx_svo_instance*)&vx_svo_scene_frame_instances(&s, pl[i].frame)[b];
            in->flags = 0;
            in->model = pl[i].model;
            for (int k3 = 0; k3 < 3; k3++) in->xform[4 * k3 + 3] = pl[i].origin[k3];
        }
    }
    vx_free(a, pl);
    vx_free(a, ms.slot);
    vx_free(a, ms.hash);
    if (r != VX_OK) {
        vx_svo_scene_free(&s);
        return r;
    }
    vx_svo_scene_update_bounds(&s);
    cs.models = s.model_count;
    cs.instances = s.instance_count;
    cs.frames = vx_svo_scene_frames(&s);
    cs.peak_bytes = vx_peak_rss();
    if (stats) *stats = cs;
    *out = s;
    return VX_OK;
}
