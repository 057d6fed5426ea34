/* formats/voxmesh.c - greedy meshing of a voxel set (formats/voxmesh.h).
 *
 * 1. The cells go into an open-addressing hash set (63-bit keys x | y<<21 |
 *    z<<42), so each of the six neighbours of a cell is one probe.
 * 2. Every exposed face becomes a record whose sort key is (axis, direction,
 *    plane, v, u); the records are sorted.
 * 3. A plane whose faces fill at least 1/16 of their bounding rectangle
 *    is meshed greedily on a mask of that rectangle: each unused face, in
 *    row-major order, starts a quad that grows along u while the colour
 *    holds, then along v while the whole row segment matches. A sparser
 *    plane is swept row by row (v): consecutive faces of one colour make a
 *    run [u0, u1); a run equal in u0, u1 and colour to a quad that ended on
 *    the row before extends that quad, otherwise it starts one.
 * Time O(n log n) for n cells; memory about 16 bytes per cell for the set,
 * 16 per exposed face and 8 per mask cell (at most 16 per face of a plane).
 */
#include "formats/voxmesh.h"

#include <stdlib.h>
#include <string.h>

typedef struct face {
    uint64_t lo;   /* v << 21 | u */
    uint32_t hi;   /* (axis * 2 + positive) << 22 | plane */
    uint32_t rgba;
} face;

static int face_cmp(const void* pa, const void* pb) {
    const face* a = (const face*)pa;
    const face* b = (const face*)pb;
    if (a->hi != b->hi) return a->hi < b->hi ? -1 : 1;
    return a->lo < b->lo ? -1 : a->lo > b->lo;
}

static uint64_t cell_key(uint32_t x, uint32_t y, uint32_t z) {
    return ((uint64_t)x | (uint64_t)y << 21 | (uint64_t)z << 42) + 1; /* 0 marks an empty slot */
}

typedef struct cell_set {
    uint64_t* keys;
    size_t mask;
    int shift;
} cell_set;

static size_t set_slot(const cell_set* s, uint64_t key) {
    return (size_t)((key * 0x9E3779B97F4A7C15ull) >> s->shift) & s->mask;
}

/* Inserts key; false if it was there already. */
static bool set_insert(cell_set* s, uint64_t key) {
    for (size_t i = set_slot(s, key);; i = (i + 1) & s->mask) {
        if (s->keys[i] == key) return false;
        if (!s->keys[i]) {
            s->keys[i] = key;
            return true;
        }
    }
}

static bool set_has(const cell_set* s, uint64_t key) {
    for (size_t i = set_slot(s, key);; i = (i + 1) & s->mask) {
        if (s->keys[i] == key) return true;
        if (!s->keys[i]) return false;
    }
}

vx_result vx_voxmesh_build(const vx_allocator* alloc, const uint32_t* xyz, const uint32_t* rgba, size_t count,
                           vx_voxmesh* out, vx_error* err) {
    if (!out || (!xyz && count)) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "voxmesh: NULL argument");
    for (size_t i = 0; i < 3 * count; i++)
        if (xyz[i] >= VX_VOXMESH_MAX_COORD)
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "voxmesh: cell %zu has coordinate %u (at most %u)",
                           i / 3, xyz[i], VX_VOXMESH_MAX_COORD - 1);

    vx_result r = VX_OK;
    cell_set set = {0};
    size_t cap = 16;
    int bits = 4;
    while (cap / 2 < count) {
        if (cap > SIZE_MAX / 4) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "voxmesh: %zu cells", count);
        cap *= 2;
        bits++;
    }
    set.keys = (uint64_t*)vx_calloc(alloc, cap, sizeof(uint64_t));
    set.mask = cap - 1;
    set.shift = 64 - bits;
    face* faces = NULL;
    size_t nf = 0, fcap = 0;
    vx_voxmesh_quad* quads = NULL;
    size_t nq = 0, qcap = 0;
    size_t *open_prev = NULL, *open_cur = NULL;
    size_t oprev_cap = 0, ocur_cap = 0;
    uint64_t* mask = NULL;
    size_t mask_cap = 0;
    if (!set.keys) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "voxmesh: out of memory for %zu cells", count);

    for (size_t i = 0; i < count; i++)
        if (!set_insert(&set, cell_key(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]))) {
            r = vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "voxmesh: cell (%u %u %u) given twice", xyz[3 * i],
                        xyz[3 * i + 1], xyz[3 * i + 2]);
            goto done;
        }

    /* exposed faces */
    for (size_t i = 0; i < count; i++) {
        const uint32_t* c = xyz + 3 * i;
        for (uint32_t axis = 0; axis < 3; axis++) {
            uint32_t ua = (axis + 1) % 3, va = (axis + 2) % 3;
            for (uint32_t pos = 0; pos < 2; pos++) {
                uint32_t n[3] = {c[0], c[1], c[2]};
                bool outside;
                if (pos) outside = ++n[axis] >= VX_VOXMESH_MAX_COORD;
                else outside = n[axis]-- == 0;
                if (!outside && set_has(&set, cell_key(n[0], n[1], n[2]))) continue;
                if (nf == fcap && !vx_grow(alloc, (void**)&faces, &fcap, nf + 1, sizeof(face))) {
                    r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "voxmesh: out of memory for %zu faces", nf + 1);
                    goto done;
                }
                faces[nf].hi = (axis * 2 + pos) << 22 | (c[axis] + pos);
                faces[nf].lo = (uint64_t)c[va] << 21 | c[ua];
                faces[nf].rgba = rgba ? rgba[i] : 0;
                nf++;
            }
        }
    }
    vx_free(alloc, set.keys);
    set.keys = NULL;
    if (nf > 1) qsort(faces, nf, sizeof(face), face_cmp);

    /* greedy merge, plane by plane, row by row */
    for (size_t i = 0; i < nf;) {
        uint32_t hi = faces[i].hi;
        size_t j = i;
        while (j < nf && faces[j].hi == hi) j++;
        /* Dense plane (its faces' bounding rectangle at most 16 cells per
         * face, plus 4096): classic greedy on a mask. Each unused face in
         * row-major order starts a quad that grows along u while the colour
         * holds, then along v while the whole row segment matches. */
        uint32_t umin = UINT32_MAX, umax = 0;
        for (size_t k = i; k < j; k++) {
            uint32_t u = (uint32_t)(faces[k].lo & 0x1FFFFF);
            if (u < umin) umin = u;
            if (u > umax) umax = u;
        }
        uint32_t vmin = (uint32_t)(faces[i].lo >> 21), vmax = (uint32_t)(faces[j - 1].lo >> 21);
        uint64_t w = (uint64_t)umax - umin + 1, h = (uint64_t)vmax - vmin + 1;
        if (w * h <= 16 * (uint64_t)(j - i) + 4096) {
            size_t cells = (size_t)(w * h);
            if (!vx_grow(alloc, (void**)&mask, &mask_cap, cells, sizeof(uint64_t))) {
                r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "voxmesh: out of memory");
                goto done;
            }
            memset(mask, 0, cells * sizeof(uint64_t));
            /* bit 32: face present and unused; low 32 bits: colour */
            for (size_t k = i; k < j; k++)
                mask[(size_t)(((faces[k].lo >> 21) - vmin) * w + ((faces[k].lo & 0x1FFFFF) - umin))] =
                    (uint64_t)1 << 32 | faces[k].rgba;
            for (size_t y = 0; y < h; y++)
                for (size_t x = 0; x < w; x++) {
                    uint64_t m0 = mask[y * w + x];
                    if (!(m0 >> 32)) continue;
                    size_t qw = 1, qh = 1;
                    while (x + qw < w && mask[y * w + x + qw] == m0) qw++;
                    for (; y + qh < h; qh++) {
                        size_t k = 0;
                        while (k < qw && mask[(y + qh) * w + x + k] == m0) k++;
                        if (k < qw) break;
                    }
                    for (size_t yy = y; yy < y + qh; yy++) memset(mask + yy * w + x, 0, qw * sizeof(uint64_t));
                    if (nq == qcap && !vx_grow(alloc, (void**)&quads, &qcap, nq + 1, sizeof(vx_voxmesh_quad))) {
                        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "voxmesh: out of memory for %zu quads", nq + 1);
                        goto done;
                    }
                    quads[nq++] = (vx_voxmesh_quad){.axis = (uint8_t)(hi >> 23),
                                                    .positive = (hi >> 22) & 1,
                                                    .plane = hi & 0x3FFFFF,
                                                    .u0 = umin + (uint32_t)x,
                                                    .u1 = umin + (uint32_t)(x + qw),
                                                    .v0 = vmin + (uint32_t)y,
                                                    .v1 = vmin + (uint32_t)(y + qh),
                                                    .rgba = (uint32_t)m0};
                }
            i = j;
            continue;
        }
        /* Sparse plane: runs of a row merged with equal quads of the row
         * before. */
        size_t n_prev = 0;
        uint64_t prev_v = UINT64_MAX; /* row of open_prev's quads */
        for (size_t k = i; k < j;) {
            uint64_t v = faces[k].lo >> 21;
            size_t n_cur = 0, p = 0;
            bool continues = prev_v != UINT64_MAX && prev_v + 1 == v;
            while (k < j && faces[k].lo >> 21 == v) {
                uint32_t u0 = (uint32_t)(faces[k].lo & 0x1FFFFF), col = faces[k].rgba, u1 = u0 + 1;
                k++;
                while (k < j && faces[k].lo >> 21 == v && (uint32_t)(faces[k].lo & 0x1FFFFF) == u1 &&
                       faces[k].rgba == col) {
                    u1++;
                    k++;
                }
                size_t q = SIZE_MAX;
                if (continues) {
                    while (p < n_prev && quads[open_prev[p]].u0 < u0) p++;
                    if (p < n_prev && quads[open_prev[p]].u0 == u0 && quads[open_prev[p]].u1 == u1 &&
                        quads[open_prev[p]].rgba == col)
                        q = open_prev[p++];
                }
                if (q == SIZE_MAX) {
                    if (nq == qcap && !vx_grow(alloc, (void**)&quads, &qcap, nq + 1, sizeof(vx_voxmesh_quad))) {
                        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "voxmesh: out of memory for %zu quads", nq + 1);
                        goto done;
                    }
                    q = nq++;
                    quads[q] = (vx_voxmesh_quad){.axis = (uint8_t)(hi >> 23),
                                                 .positive = (hi >> 22) & 1,
                                                 .plane = hi & 0x3FFFFF,
                                                 .u0 = u0,
                                                 .u1 = u1,
                                                 .v0 = (uint32_t)v,
                                                 .v1 = (uint32_t)v + 1,
                                                 .rgba = col};
                } else {
                    quads[q].v1 = (uint32_t)v + 1;
                }
                if (n_cur == ocur_cap && !vx_grow(alloc, (void**)&open_cur, &ocur_cap, n_cur + 1, sizeof(size_t))) {
                    r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "voxmesh: out of memory");
                    goto done;
                }
                open_cur[n_cur++] = q;
            }
            size_t* t = open_prev;
            open_prev = open_cur;
            open_cur = t;
            size_t tc = oprev_cap;
            oprev_cap = ocur_cap;
            ocur_cap = tc;
            n_prev = n_cur;
            prev_v = v;
        }
        i = j;
    }
    /* quads come out in (plane, v0, u0) order: the documented order */
    out->quad_count = nq;
    out->quads = quads;
    out->faces = nf;
    out->alloc = alloc;
    quads = NULL;

done:
    vx_free(alloc, set.keys);
    vx_free(alloc, faces);
    vx_free(alloc, quads);
    vx_free(alloc, open_prev);
    vx_free(alloc, open_cur);
    vx_free(alloc, mask);
    return r;
}

void vx_voxmesh_free(vx_voxmesh* m) {
    if (!m) return;
    vx_free(m->alloc, m->quads);
    memset(m, 0, sizeof *m);
}
