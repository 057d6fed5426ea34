/* formats/voxmesh.c - greedy meshing of a voxel set (formats/voxmesh.h).
 *
 * The cells are grouped into bricks of 64^3 (a hash map from brick to its
 * cells; input in Morton order, as the .svo decoder gives it, is already
 * grouped and needs no reordering). Each brick is meshed on its own, which
 * is what lets the work run on every core and stay in cache:
 * 1. Boundary layers: every brick records the occupancy of its six faces
 *    (64 x 64 bits each), so a neighbour can tell whether its own boundary
 *    faces are covered without touching the other brick's cells.
 * 2. The brick's occupancy is held three times as 64 x 64 words of 64 bits,
 *    each with the bits along a different axis (x-, y- and z-rows). The
 *    exposed faces of a plane perpendicular to axis a are then one AND-NOT
 *    per row between the plane's layer and its neighbour layer, already
 *    laid out as rows of v with bits along u (no transposes).
 * 3. Greedy merging on those masks: each face, in row-major order, starts a
 *    quad that grows along u while the bits and the colour hold (a count of
 *    trailing ones when the set has one colour), then along v while the
 *    whole row segment matches.
 * Time O(n) for n cells plus O(64^2) per brick and plane direction; memory
 * 3 KB per brick, 1.1 MB per thread, 4 bytes per cell when the input is not
 * grouped by brick. Threads split the bricks into contiguous ranges of about
 * equal cell counts and their quads are concatenated in brick order, so the
 * output does not depend on the thread count. */
#define _POSIX_C_SOURCE 200809L
#include "formats/voxmesh.h"

#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define BS 64 /* brick side: one 64-bit word per row */
#define MAX_THREADS 16
/* Below this many cells one thread does everything, which keeps the
 * allocation order fixed (the allocation-failure tests count on it). */
#define PARALLEL_CELLS ((size_t)1 << 18)

/* Boundary layers of a brick: [axis][0] is the layer at coordinate 0 along
 * the axis, [axis][1] at 63, in the row layout the faces of that axis use
 * (rows of v, bits along u; see plane_faces). */
typedef struct brick {
    uint64_t key; /* bx | by << 15 | bz << 30, + 1 (0 marks an empty map slot) */
    size_t first, count; /* range in the cell order */
    uint64_t layer[3][2][BS];
} brick;

typedef struct brick_map {
    uint32_t* slot; /* brick index + 1, 0 empty */
    size_t mask;
} brick_map;

typedef struct mesher {
    const vx_allocator* alloc;
    const uint32_t* xyz;
    const uint32_t* rgba;
    const uint32_t* material; /* NULL: no material ids (quads merge on colour alone) */
    const size_t* order; /* cell order grouped by brick, NULL: the input order is */
    brick* bricks;
    size_t brick_count;
    brick_map map;
    unsigned threads;
    /* per thread */
    size_t range[MAX_THREADS + 1]; /* bricks [range[t], range[t+1]) */
    vx_voxmesh_quad* quads[MAX_THREADS];
    size_t quad_count[MAX_THREADS], quad_cap[MAX_THREADS];
    uint64_t faces[MAX_THREADS];
    size_t dup[MAX_THREADS]; /* smallest cell index given twice, SIZE_MAX none */
    bool nomem[MAX_THREADS];
    atomic_uint next_thread;
    int phase; /* 1 boundary layers, 2 meshing, 3 concatenation */
    size_t moved, move_count; /* phase 3: quads [moved, moved + move_count) of the
                                 output come from threads 1.. and are copied */
} mesher;

static uint64_t brick_key(const uint32_t* c) {
    return ((uint64_t)(c[0] / BS) | (uint64_t)(c[1] / BS) << 15 | (uint64_t)(c[2] / BS) << 30) + 1;
}

static size_t map_slot(const brick_map* m, uint64_t key) {
    return (size_t)(key * 0x9E3779B97F4A7C15ull >> 32) & m->mask;
}

/* Index of the brick with this key, or SIZE_MAX. */
static size_t map_find(const mesher* ms, uint64_t key) {
    for (size_t i = map_slot(&ms->map, key);; i = (i + 1) & ms->map.mask) {
        uint32_t s = ms->map.slot[i];
        if (!s) return SIZE_MAX;
        if (ms->bricks[s - 1].key == key) return s - 1;
    }
}

static bool map_rehash(mesher* ms, size_t cap) {
    uint32_t* slot = (uint32_t*)vx_calloc(ms->alloc, cap, sizeof(uint32_t));
    if (!slot) return false;
    vx_free(ms->alloc, ms->map.slot);
    ms->map.slot = slot;
    ms->map.mask = cap - 1;
    for (size_t b = 0; b < ms->brick_count; b++) {
        size_t i = map_slot(&ms->map, ms->bricks[b].key);
        while (slot[i]) i = (i + 1) & ms->map.mask;
        slot[i] = (uint32_t)b + 1;
    }
    return true;
}

/* Index of the brick with this key, added (with count 0) if new; SIZE_MAX
 * when out of memory. */
static size_t map_add(mesher* ms, uint64_t key, size_t* brick_cap) {
    size_t i = map_slot(&ms->map, key);
    for (;; i = (i + 1) & ms->map.mask) {
        uint32_t s = ms->map.slot[i];
        if (!s) break;
        if (ms->bricks[s - 1].key == key) return s - 1;
    }
    if (ms->brick_count >= UINT32_MAX - 1) return SIZE_MAX;
    if (!vx_grow(ms->alloc, (void**)&ms->bricks, brick_cap, ms->brick_count + 1, sizeof(brick))) return SIZE_MAX;
    brick* b = &ms->bricks[ms->brick_count];
    memset(b, 0, sizeof *b);
    b->key = key;
    ms->map.slot[i] = (uint32_t)ms->brick_count + 1;
    ms->brick_count++;
    if (2 * ms->brick_count > ms->map.mask + 1) {
        if (ms->map.mask + 1 > SIZE_MAX / 4 || !map_rehash(ms, 2 * (ms->map.mask + 1))) return SIZE_MAX;
    }
    return ms->brick_count - 1;
}

static size_t cell_at(const mesher* ms, size_t k) { return ms->order ? ms->order[k] : k; }

/* Phase 1: the brick's six boundary layers (and the count check for cells
 * given twice is left to phase 2, which sees every cell). */
static void brick_layers(mesher* ms, brick* b) {
    for (size_t k = b->first; k < b->first + b->count; k++) {
        const uint32_t* c = ms->xyz + 3 * cell_at(ms, k);
        uint32_t x = c[0] % BS, y = c[1] % BS, z = c[2] % BS;
        /* x layers: rows z, bits y; y layers: rows x, bits z; z layers: rows y, bits x */
        if (x == 0 || x == BS - 1) b->layer[0][x != 0][z] |= (uint64_t)1 << y;
        if (y == 0 || y == BS - 1) b->layer[1][y != 0][x] |= (uint64_t)1 << z;
        if (z == 0 || z == BS - 1) b->layer[2][z != 0][y] |= (uint64_t)1 << x;
    }
}

typedef struct scratch {
    /* occ[a][c][r]: the cells with coordinate c along axis a, row r, bits
     * along u = (a+1)%3 and rows along v = (a+2)%3, i.e. exactly the layout
     * of plane c's faces (a = 0: rows z, bits y; a = 1: rows x, bits z;
     * a = 2: rows y, bits x). */
    uint64_t occ[3][BS][BS];
    uint32_t* colour; /* BS^3, index x + 64 y + 4096 z; only set cells are read */
    uint32_t* mat;    /* the same for material ids (when the mesher has them) */
} scratch;

static inline bool emit(mesher* ms, unsigned t, vx_voxmesh_quad q) {
    if (__builtin_expect(ms->quad_count[t] == ms->quad_cap[t], 0) &&
        !vx_grow(ms->alloc, (void**)&ms->quads[t], &ms->quad_cap[t], ms->quad_count[t] + 1, sizeof q))
        return false;
    ms->quads[t][ms->quad_count[t]++] = q;
    return true;
}


/* Phase 2: the quads of one brick. False when out of memory or a cell is
 * given twice (recorded in ms). */
static bool brick_mesh(mesher* ms, unsigned t, const brick* b, scratch* s) {
    uint32_t origin[3] = {(uint32_t)((b->key - 1) & 0x7FFF) * BS, (uint32_t)((b->key - 1) >> 15 & 0x7FFF) * BS,
                          (uint32_t)((b->key - 1) >> 30 & 0x7FFF) * BS};
    bool ok = true;
    for (size_t k = b->first; k < b->first + b->count; k++) {
        size_t i = cell_at(ms, k);
        const uint32_t* c = ms->xyz + 3 * i;
        uint32_t x = c[0] % BS, y = c[1] % BS, z = c[2] % BS;
        if (s->occ[2][z][y] >> x & 1) {
            if (i < ms->dup[t]) ms->dup[t] = i;
            ok = false;
            continue;
        }
        s->occ[0][x][z] |= (uint64_t)1 << y;
        s->occ[1][y][x] |= (uint64_t)1 << z;
        s->occ[2][z][y] |= (uint64_t)1 << x;
        if (ms->rgba) s->colour[x + BS * y + BS * BS * z] = ms->rgba[i];
        if (ms->material) s->mat[x + BS * y + BS * BS * z] = ms->material[i];
    }
    /* neighbour bricks' layers facing this one: [axis][0] the brick below, [1] above */
    const uint64_t* nb[3][2];
    for (int a = 0; a < 3; a++)
        for (int p = 0; p < 2; p++) {
            uint32_t bc[3] = {origin[0], origin[1], origin[2]};
            nb[a][p] = NULL;
            if (!p && bc[a] == 0) continue;
            if (p && bc[a] + BS >= VX_VOXMESH_MAX_COORD) continue;
            bc[a] = p ? bc[a] + BS : bc[a] - BS;
            size_t n = map_find(ms, brick_key(bc));
            if (n != SIZE_MAX) nb[a][p] = ms->bricks[n].layer[a][!p];
        }
    static const uint32_t stride[3] = {1, BS, BS * BS};
    for (uint32_t a = 0; ok && a < 3; a++) {
        uint32_t ua = (a + 1) % 3, va = (a + 2) % 3;
        uint32_t su = stride[ua], sv = stride[va];
        for (uint32_t p = 0; ok && p < 2; p++)
            for (uint32_t c = 0; ok && c < BS; c++) {
                const uint64_t* cur = s->occ[a][c];
                const uint64_t* other = p ? (c + 1 < BS ? s->occ[a][c + 1] : nb[a][1])
                                          : (c > 0 ? s->occ[a][c - 1] : nb[a][0]);
                uint64_t f[BS], any = 0;
                for (int r = 0; r < BS; r++) {
                    f[r] = cur[r] & ~(other ? other[r] : 0);
                    any |= f[r];
                }
                if (!any) continue;
                const uint32_t* col = ms->rgba ? s->colour + c * stride[a] : NULL;
                /* a quad covers cells of one colour and one material: the
                 * material id joins the colour in every comparison */
                const uint32_t* mt = ms->material ? s->mat + c * stride[a] : NULL;
                for (uint32_t v = 0; v < BS; v++) {
                    uint64_t row = f[v];
                    while (row) {
                        uint32_t u = (uint32_t)__builtin_ctzll(row), w;
                        uint32_t rgba = col ? col[u * su + v * sv] : 0;
                        uint32_t mid = mt ? mt[u * su + v * sv] : 0;
                        if (!col && !mt) {
                            uint64_t ones = ~(row >> u);
                            w = ones ? (uint32_t)__builtin_ctzll(ones) : BS - u;
                        } else {
                            w = 1;
                            while (u + w < BS && (row >> (u + w) & 1) && (!col || col[(u + w) * su + v * sv] == rgba) &&
                                   (!mt || mt[(u + w) * su + v * sv] == mid))
                                w++;
                        }
                        uint64_t run = (w == BS ? ~(uint64_t)0 : (((uint64_t)1 << w) - 1)) << u;
                        uint32_t h = 1;
                        while (v + h < BS && (f[v + h] & run) == run) {
                            bool same = true;
                            for (uint32_t k = 0; k < w && same && (col || mt); k++) {
                                size_t at = (u + k) * su + (v + h) * sv;
                                same = (!col || col[at] == rgba) && (!mt || mt[at] == mid);
                            }
                            if (!same) break;
                            f[v + h] &= ~run;
                            h++;
                        }
                        row &= ~run;
                        ms->faces[t] += (uint64_t)w * h; /* every face lies in exactly one quad */
                        vx_voxmesh_quad q = {.axis = (uint8_t)a,
                                             .positive = p != 0,
                                             .plane = origin[a] + c + p,
                                             .u0 = origin[ua] + u,
                                             .u1 = origin[ua] + u + w,
                                             .v0 = origin[va] + v,
                                             .v1 = origin[va] + v + h,
                                             .rgba = rgba,
                                             .material = mid};
                        if (!emit(ms, t, q)) {
                            ms->nomem[t] = true;
                            ok = false;
                            break;
                        }
                    }
                }
            }
    }
    /* clear what this brick set (cheaper than clearing 96 KB) */
    for (size_t k = b->first; k < b->first + b->count; k++) {
        const uint32_t* c = ms->xyz + 3 * cell_at(ms, k);
        uint32_t x = c[0] % BS, y = c[1] % BS, z = c[2] % BS;
        s->occ[0][x][z] = s->occ[1][y][x] = s->occ[2][z][y] = 0;
    }
    return ok;
}

static void* worker(void* arg) {
    mesher* ms = (mesher*)arg;
    unsigned t = atomic_fetch_add(&ms->next_thread, 1);
    if (t >= ms->threads) return NULL;
    if (ms->phase == 1) {
        for (size_t b = ms->range[t]; b < ms->range[t + 1]; b++) brick_layers(ms, &ms->bricks[b]);
        return NULL;
    }
    if (ms->phase == 3) {
        /* slice t of the quads that threads 1.. made, copied behind thread 0's
         * (the copy, and the zeroing of the fresh pages it writes, was a third
         * of a large mesh's time on one core) */
        size_t lo = ms->moved + ms->move_count * t / ms->threads;
        size_t hi = ms->moved + ms->move_count * (t + 1) / ms->threads;
        size_t start = ms->quad_count[0];
        for (unsigned src = 1; src < ms->threads && lo < hi; src++) {
            size_t end = start + ms->quad_count[src];
            if (lo < end) {
                size_t n = (hi < end ? hi : end) - lo;
                memcpy(ms->quads[0] + lo, ms->quads[src] + (lo - start), n * sizeof(vx_voxmesh_quad));
                lo += n;
            }
            start = end;
        }
        return NULL;
    }
    scratch* s = (scratch*)vx_calloc(ms->alloc, 1, sizeof(scratch));
    if (s && ms->rgba) s->colour = (uint32_t*)vx_calloc(ms->alloc, (size_t)BS * BS * BS, sizeof(uint32_t));
    if (s && ms->material) s->mat = (uint32_t*)vx_calloc(ms->alloc, (size_t)BS * BS * BS, sizeof(uint32_t));
    if (!s || (ms->rgba && !s->colour) || (ms->material && !s->mat)) {
        ms->nomem[t] = true;
    } else {
        for (size_t b = ms->range[t]; b < ms->range[t + 1]; b++)
            if (!brick_mesh(ms, t, &ms->bricks[b], s) && ms->nomem[t]) break;
    }
    if (s) vx_free(ms->alloc, s->colour);
    if (s) vx_free(ms->alloc, s->mat);
    vx_free(ms->alloc, s);
    return NULL;
}

static void run_phase(mesher* ms, int phase) {
    ms->phase = phase;
    atomic_store(&ms->next_thread, 0);
    vx_run_threads(ms->threads, worker, ms);
}

vx_result vx_voxmesh_build(const vx_allocator* alloc, const uint32_t* xyz, const uint32_t* rgba, size_t count,
                           vx_voxmesh* out, vx_error* err) {
    return vx_voxmesh_build_material(alloc, xyz, rgba, NULL, count, out, err);
}

vx_result vx_voxmesh_build_material(const vx_allocator* alloc, const uint32_t* xyz, const uint32_t* rgba,
                                    const uint32_t* material, size_t count, vx_voxmesh* out, vx_error* err) {
    if (!out || (!xyz && count)) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "voxmesh: NULL argument");
    memset(out, 0, sizeof *out);
    for (size_t i = 0; i < 3 * count; i++)
        if (xyz[i] >= VX_VOXMESH_MAX_COORD)
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "voxmesh: cell %zu has coordinate %u (at most %u)",
                           i / 3, xyz[i], VX_VOXMESH_MAX_COORD - 1);
    mesher* ms = (mesher*)vx_calloc(alloc, 1, sizeof(mesher));
    if (!ms) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "voxmesh: out of memory");
    ms->alloc = alloc;
    ms->xyz = xyz;
    ms->rgba = rgba;
    ms->material = material;
    vx_result r = VX_OK;
    size_t brick_cap = 0, *order = NULL;
    if (!map_rehash(ms, 64)) goto nomem;

    /* bricks, their cell counts, and whether the input is grouped by brick */
    bool grouped = true;
    size_t last = SIZE_MAX;
    uint64_t last_key = 0;
    for (size_t i = 0; i < count; i++) {
        uint64_t key = brick_key(xyz + 3 * i);
        if (key != last_key) {
            size_t before = ms->brick_count;
            size_t b = map_add(ms, key, &brick_cap);
            if (b == SIZE_MAX) goto nomem;
            if (b < before) grouped = false; /* a brick seen before, not just before */
            last = b;
            last_key = key;
        }
        ms->bricks[last].count++;
    }
    size_t first = 0;
    for (size_t b = 0; b < ms->brick_count; b++) {
        ms->bricks[b].first = first;
        first += ms->bricks[b].count;
    }
    if (!grouped) {
        order = (size_t*)vx_calloc(alloc, count, sizeof(size_t));
        size_t* fill = (size_t*)vx_calloc(alloc, ms->brick_count, sizeof(size_t));
        if (!order || !fill) {
            vx_free(alloc, fill);
            goto nomem;
        }
        last_key = 0;
        for (size_t i = 0; i < count; i++) {
            uint64_t key = brick_key(xyz + 3 * i);
            if (key != last_key) last = map_find(ms, key), last_key = key;
            order[ms->bricks[last].first + fill[last]++] = i;
        }
        vx_free(alloc, fill);
        ms->order = order;
    }

    /* threads over contiguous brick ranges of about equal cell counts */
    ms->threads = 1;
    if (count >= PARALLEL_CELLS) {
        long n = sysconf(_SC_NPROCESSORS_ONLN);
        ms->threads = n < 1 ? 1u : n > MAX_THREADS ? MAX_THREADS : (unsigned)n;
        if (ms->threads > ms->brick_count) ms->threads = ms->brick_count ? (unsigned)ms->brick_count : 1;
    }
    {
        size_t b = 0, done = 0;
        for (unsigned t = 0; t < ms->threads; t++) {
            ms->range[t] = b;
            size_t goal = count / ms->threads * (t + 1);
            while (b < ms->brick_count && (done < goal || t + 1 == ms->threads)) done += ms->bricks[b++].count;
            ms->dup[t] = SIZE_MAX;
        }
        ms->range[ms->threads] = ms->brick_count;
    }
    run_phase(ms, 1);
    run_phase(ms, 2);

    size_t dup = SIZE_MAX, total = 0;
    uint64_t faces = 0;
    bool nomem = false;
    for (unsigned t = 0; t < ms->threads; t++) {
        if (ms->dup[t] < dup) dup = ms->dup[t];
        nomem |= ms->nomem[t];
        total += ms->quad_count[t];
        faces += ms->faces[t];
    }
    if (dup != SIZE_MAX) {
        r = vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "voxmesh: cell (%u %u %u) given twice", xyz[3 * dup],
                    xyz[3 * dup + 1], xyz[3 * dup + 2]);
        goto done;
    }
    if (nomem) goto nomem;
    /* concatenate in brick order: thread 0's array grows to hold the rest,
     * which every thread copies a slice of */
    if (ms->threads > 1 && total > ms->quad_count[0]) {
        if (!vx_grow(alloc, (void**)&ms->quads[0], &ms->quad_cap[0], total, sizeof(vx_voxmesh_quad))) goto nomem;
        ms->moved = ms->quad_count[0];
        ms->move_count = total - ms->quad_count[0];
        run_phase(ms, 3);
        for (unsigned t = 1; t < ms->threads; t++) {
            vx_free(alloc, ms->quads[t]);
            ms->quads[t] = NULL;
        }
    }
    out->quad_count = total;
    out->quads = ms->quads[0];
    out->faces = faces;
    out->alloc = alloc;
    ms->quads[0] = NULL;
    goto done;
nomem:
    r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "voxmesh: out of memory for %zu cells", count);
done:
    for (unsigned t = 0; t < MAX_THREADS; t++) vx_free(alloc, ms->quads[t]);
    vx_free(alloc, ms->map.slot);
    vx_free(alloc, ms->bricks);
    vx_free(alloc, order);
    vx_free(alloc, ms);
    return r;
}

void vx_voxmesh_free(vx_voxmesh* m) {
    if (!m) return;
    vx_free(m->alloc, m->quads);
    memset(m, 0, sizeof *m);
}
