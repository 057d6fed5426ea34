/* svo/svo_build.c - voxels -> minimized Laine-Karras octree (vx_svo_build_model).
 *
 * Pipeline: (1) one sequential pass checks every entry, interns its attribute
 * tuple into a small record table and packs (Morton key, level, record id)
 * into one u64; (2) a stable LSD radix sort over only the key bits (skipped
 * when the input is already in Morton order), so equal keys keep their input
 * order and the last one wins; (3) ONE streaming bottom-up pass keeps a
 * pending node per level and finalizes a node as soon as the key prefix
 * changes: collapse check, representative attribute, hash-consing (DAG);
 * (4) node blocks are laid out in creation order, which is a post-order
 * (children first), so every child pointer points backwards. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <string.h>

#include "svo/svo_internal.h"

typedef vx__svo_rec rec;

/* Node record in the pool, addressed by its word offset (the node id):
 *   [0] valid | leaf << 8   [1] representative record   [2] block position
 *   [3 + j] child j (octant order over valid): record id for a leaf child,
 *           node id for a non-leaf child. */
enum { N_HDR = 0, N_REP = 1, N_BLOCK = 2, N_KIDS = 3 };
#define NO_BLOCK 0xFFFFFFFFu

typedef struct pending {
    uint64_t prefix;
    uint32_t valid, leaf;
    uint32_t ch[8], cattr[8];
    uint64_t plain[8];
    bool active;
} pending;

typedef struct bld {
    const vx_allocator* a;
    uint32_t attrs;
    bool collapse, dag;
    uint32_t limit; /* largest near pointer (vx_svo_build_desc.testing.far_limit when building) */
    /* One channel only: attribute references in nodes and runs are the
     * 32-bit values themselves, so representatives need no interning. */
    bool direct;
    /* With direct: the channel whose values the references are (attrs in
     * the builder) and the others' one value each (the reader, where a
     * model's other channels are constant: vx__svo_unpack_desc.const_attrs;
     * zero in the builder). */
    uint32_t vattr;
    vx__svo_rec cst;
    rec* recs;
    size_t nrec, caprec;
    uint32_t* rhash; /* record id + 1, 0 = empty */
    size_t rhcap;
    uint32_t* pool;
    size_t npool, cappool;
    uint32_t* nhash; /* node id + 1 */
    size_t nhcap, nnodes;
    uint64_t ncollapsed;
    pending lv[VX_SVO_MAX_DEPTH + 2];
    uint32_t depth;
    /* With the layout on a second thread (build_layout_thread): the pool is
     * allocated once at a bound (never moved), the appended nodes published
     * here; NULL when the layout runs after the build. */
    vx__svo_gate* pub;
    size_t laid; /* pool words already laid out */
    /* The caller laid the attribute runs out (vx__svo_pool.runs): each
     * node's N_BLOCK holds its run's first record until its block is laid
     * out, the records are in place, the layout writes only blocks. */
    bool runs_given;
    /* The caller laid the blocks out too (vx__svo_pool.laid): the words are
     * in place, root is the root's representative, laid_desc the
     * descriptor words (vx_svo_build_stats.desc_dag). */
    bool laid_given;
    uint64_t laid_desc;
    /* The split form's runs stream (vx__svo_unpack_desc.runs; NULL: none):
     * the layout takes each node's run from it (run_take), read at
     * outw.runs_pos, instead of looking it up (run_intern). */
    const uint8_t* runs;
    size_t runs_n;
    unsigned threads; /* threads the record arrays may be filled on (vx__svo_interned.threads; 0, 1: this one) */
    /* finish_model may hand the record ids over as the rgba array (direct
     * RGBA8): the reader's, where nothing reads them afterwards (the
     * builder's runs_check does) */
    bool give_ids;
    /* result */
    bool root_is_leaf, have_root;
    uint32_t root; /* node id or record id when root_is_leaf */
    uint64_t root_plain;
    vx_error* err;
    vx_result fail;
} bld;

static inline uint64_t mix64(uint64_t h) {
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdull;
    h ^= h >> 33;
    h *= 0xc4ceb9fe1a85ec53ull;
    h ^= h >> 33;
    return h;
}
static uint64_t hash_words(const uint32_t* w, size_t n, uint64_t seed) {
    uint64_t h = seed ^ (n * 0x9E3779B97F4A7C15ull);
    size_t i = 0;
    for (; i + 1 < n; i += 2) h = mix64(h ^ ((uint64_t)w[i] | ((uint64_t)w[i + 1] << 32))) + i;
    if (i < n) h = mix64(h ^ w[i] ^ 0xABCDull << 40);
    return mix64(h);
}

static bool oom(bld* b, const char* what) {
    if (b->fail == VX_OK) b->fail = vx_fail(b->err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo build: out of memory (%s)", what);
    return false;
}

/* ---- attribute records -------------------------------------------------------- */

static bool rhash_grow(bld* b) {
    size_t ncap = b->rhcap ? b->rhcap * 2 : 1024;
    uint32_t* t = (uint32_t*)vx_calloc(b->a, ncap, sizeof *t);
    if (!t) return oom(b, "record table");
    for (size_t i = 0; i < b->nrec; i++) {
        size_t j = (size_t)hash_words((const uint32_t*)&b->recs[i], 4, 7) & (ncap - 1);
        while (t[j]) j = (j + 1) & (ncap - 1);
        t[j] = (uint32_t)i + 1;
    }
    vx_free(b->a, b->rhash);
    b->rhash = t;
    b->rhcap = ncap;
    return true;
}

/* Returns the id of r, adding it when new; UINT32_MAX on failure. */
/* A caller's tuple as the builder stores it: the channels the model lacks
 * (and the padding) zero, so equal records compare and hash equal. */
static rec rec_masked(const rec* in, uint32_t attrs) {
    rec r = *in;
    r.pad = 0;
    if (!(attrs & VX_ATTR_PALETTE)) r.palette = 0;
    if (!(attrs & VX_ATTR_RGBA8)) r.rgba = 0;
    if (!(attrs & VX_ATTR_NORMAL)) r.normal = 0;
    if (!(attrs & VX_ATTR_MATERIAL)) r.material = 0;
    if (!(attrs & VX_ATTR_DENSITY)) r.density = 0;
    return r;
}

static uint32_t rec_intern(bld* b, const rec* r) {
    if ((b->nrec + 1) * 2 > b->rhcap && !rhash_grow(b)) return UINT32_MAX;
    size_t j = (size_t)hash_words((const uint32_t*)r, 4, 7) & (b->rhcap - 1);
    while (b->rhash[j]) {
        uint32_t id = b->rhash[j] - 1;
        if (memcmp(&b->recs[id], r, sizeof *r) == 0) return id;
        j = (j + 1) & (b->rhcap - 1);
    }
    if (b->nrec >= 0xFFFFFFF0u) {
        b->fail = vx_fail(b->err, VX_ERR_LIMIT, VX_NO_OFFSET, "svo build: more than 2^32 distinct attribute records");
        return UINT32_MAX;
    }
    if (!vx_grow(b->a, (void**)&b->recs, &b->caprec, b->nrec + 1, sizeof(rec))) {
        oom(b, "records");
        return UINT32_MAX;
    }
    b->recs[b->nrec] = *r;
    b->rhash[j] = (uint32_t)b->nrec + 1;
    return (uint32_t)b->nrec++;
}

void vx__oct_decode(uint32_t v, float n[3]) {
    float u = (float)(int16_t)(uint16_t)(v & 0xFFFFu) / 32767.0f;
    float w = (float)(int16_t)(uint16_t)(v >> 16) / 32767.0f;
    if (u < -1.0f) u = -1.0f;
    if (w < -1.0f) w = -1.0f;
    float z = 1.0f - fabsf(u) - fabsf(w);
    if (z < 0.0f) {
        float ou = u;
        u = (1.0f - fabsf(w)) * (ou >= 0.0f ? 1.0f : -1.0f);
        w = (1.0f - fabsf(ou)) * (w >= 0.0f ? 1.0f : -1.0f);
    }
    float len = sqrtf(u * u + w * w + z * z);
    if (len > 0.0f) {
        u /= len;
        w /= len;
        z /= len;
    }
    n[0] = u;
    n[1] = w;
    n[2] = z;
}

static uint32_t snorm16(float f) {
    if (!(f >= -1.0f)) f = -1.0f;
    if (f > 1.0f) f = 1.0f;
    long q = lroundf(f * 32767.0f);
    return (uint32_t)(uint16_t)(int16_t)q;
}

uint32_t vx__oct_encode(const float n[3]) {
    float s = fabsf(n[0]) + fabsf(n[1]) + fabsf(n[2]);
    if (!(s > 0.0f)) return snorm16(0.0f) | (snorm16(0.0f) << 16); /* degenerate: +Z */
    float u = n[0] / s, w = n[1] / s;
    if (n[2] < 0.0f) {
        float ou = u;
        u = (1.0f - fabsf(w)) * (ou >= 0.0f ? 1.0f : -1.0f);
        w = (1.0f - fabsf(ou)) * (w >= 0.0f ? 1.0f : -1.0f);
    }
    return snorm16(u) | (snorm16(w) << 16);
}

/* The rule documented in svo.h, applied channel by channel. When every valid
 * child carries the same record that record is the representative (so a
 * collapsed leaf and the node it replaces agree exactly). */
static uint32_t rec_value(uint32_t attrs, const rec* r) {
    switch (attrs) {
    case VX_ATTR_PALETTE: return r->palette;
    case VX_ATTR_RGBA8: return r->rgba;
    case VX_ATTR_NORMAL: return r->normal;
    case VX_ATTR_MATERIAL: return r->material;
    default: {
        union { float f; uint32_t u; } c = {r->density};
        return c.u;
    }
    }
}
/* Sets the one channel attrs of r to v (the others as they are). */
static void rec_put_value(uint32_t attrs, uint32_t v, rec* r) {
    switch (attrs) {
    case VX_ATTR_PALETTE: r->palette = (uint8_t)v; break;
    case VX_ATTR_RGBA8: r->rgba = v; break;
    case VX_ATTR_NORMAL: r->normal = v; break;
    case VX_ATTR_MATERIAL: r->material = (uint16_t)v; break;
    default: {
        union { uint32_t u; float f; } c = {v};
        r->density = c.f;
    }
    }
}
static void rec_from_value(uint32_t attrs, uint32_t v, rec* r) {
    memset(r, 0, sizeof *r);
    rec_put_value(attrs, v, r);
}


/* The LOD rule for indices (palette, material): the most frequent of the n
 * (<= 8) children's values, ties to the smallest. */
static unsigned most_frequent(const unsigned* v, unsigned n) {
    unsigned best = 0, bestn = 0;
    for (unsigned i = 0; i < n; i++) {
        unsigned k = 0;
        for (unsigned j = 0; j < n; j++) k += v[j] == v[i];
        if (k > bestn || (k == bestn && v[i] < best)) best = v[i], bestn = k;
    }
    return best;
}

/* The rule of svo.h over n (1..8) children, channel by channel; equal
 * children give themselves back exactly (see above). */
void vx__svo_rec_mean(uint32_t attrs, const vx__svo_rec* const* c, unsigned n, vx__svo_rec* out) {
    bool same = true;
    for (unsigned i = 1; i < n; i++) same = same && memcmp(c[i], c[0], sizeof *c[0]) == 0;
    if (same) {
        *out = *c[0];
        return;
    }
    rec r;
    memset(&r, 0, sizeof r);
    if (attrs & (VX_ATTR_PALETTE | VX_ATTR_MATERIAL)) {
        unsigned v[8];
        if (attrs & VX_ATTR_PALETTE) {
            for (unsigned i = 0; i < n; i++) v[i] = c[i]->palette;
            r.palette = (uint8_t)most_frequent(v, n);
        }
        if (attrs & VX_ATTR_MATERIAL) {
            for (unsigned i = 0; i < n; i++) v[i] = c[i]->material;
            r.material = (uint16_t)most_frequent(v, n);
        }
    }
    if (attrs & VX_ATTR_RGBA8) {
        uint32_t o = 0;
        for (unsigned ch = 0; ch < 4; ch++) {
            unsigned sum = 0;
            for (unsigned i = 0; i < n; i++) sum += (c[i]->rgba >> (8 * ch)) & 0xFFu;
            o |= ((sum + n / 2) / n) << (8 * ch); /* rounded, ties up */
        }
        r.rgba = o;
    }
    if (attrs & VX_ATTR_NORMAL) {
        float m[3] = {0, 0, 0};
        for (unsigned i = 0; i < n; i++) {
            float v[3];
            vx__oct_decode(c[i]->normal, v);
            m[0] += v[0], m[1] += v[1], m[2] += v[2];
        }
        r.normal = vx__oct_encode(m);
    }
    if (attrs & VX_ATTR_DENSITY) {
        double s = 0;
        for (unsigned i = 0; i < n; i++) s += c[i]->density;
        r.density = (float)(s / n);
    }
    *out = r;
}

static uint32_t representative(bld* b, const uint32_t* ids, unsigned n) {
    bool same = true;
    for (unsigned i = 1; i < n; i++) same = same && ids[i] == ids[0];
    if (same) return ids[0];
    /* one channel whose values are the ids (every split read of a textured
     * mesh: RGBA8 with a constant material): vx__svo_rec_mean's rule on the
     * values themselves, without a record per child (a twelfth of the
     * 4096^3 helmet's read went to the records and the call) */
    if (b->direct && b->vattr == VX_ATTR_RGBA8) {
        /* x / n for x <= 8 * 255 + 4 as (x * ceil(2^16 / n)) >> 16: the
         * error is below x / 2^16 < 1/32 and x / n's fraction at most 7/8,
         * so the quotient is exact; the four divisions were a fifth of this
         * function's samples on the 4096^3 helmet */
        static const uint32_t RCP[9] = {0, 65536, 32768, 21846, 16384, 13108, 10923, 9363, 8192};
        uint32_t r = RCP[n]; /* (n is 2..8 here: a node has 1..8 children, one is `same`) */
        /* the four channel sums two to a word (bytes 0 and 2, then 1 and 3):
         * each sum is at most 8 * 255 + 4 < 2^16, so the halves never carry
         * into each other; a mask and an add a child per pair where a shift,
         * a mask and an add per channel were */
        uint32_t ev = 0, od = 0, half = (uint32_t)(n / 2) * 0x00010001u;
        for (unsigned i = 0; i < n; i++) ev += ids[i] & 0x00FF00FFu, od += ids[i] >> 8 & 0x00FF00FFu;
        ev += half, od += half; /* rounded, ties up (as vx__svo_rec_mean) */
        return ((ev & 0xFFFFu) * r) >> 16 | (((od & 0xFFFFu) * r) >> 16) << 8 | (((ev >> 16) * r) >> 16) << 16 |
               (((od >> 16) * r) >> 16) << 24;
    }
    if (b->direct && (b->vattr == VX_ATTR_PALETTE || b->vattr == VX_ATTR_MATERIAL)) {
        unsigned v[8];
        for (unsigned i = 0; i < n; i++) v[i] = ids[i];
        return most_frequent(v, n);
    }
    rec r;
    const rec* c[8];
    rec tmp[8];
    for (unsigned i = 0; i < n; i++) {
        if (b->direct) {
            rec_from_value(b->vattr, ids[i], &tmp[i]);
            c[i] = &tmp[i];
        } else {
            c[i] = &b->recs[ids[i]];
        }
    }
    /* direct: the one channel (the rule works channel by channel; a constant
     * channel's representative is its value) */
    vx__svo_rec_mean(b->direct ? b->vattr : b->attrs, c, n, &r);
    return b->direct ? rec_value(b->vattr, &r) : rec_intern(b, &r);
}

/* ---- tuples interned by the caller, on several threads ------------------------------------- */

/* Tuple j has id j: each chunk of ids copies its tuples (channels outside
 * attrs zeroed) into recs, then claims a slot of the presized table for each
 * with a compare-and-swap; a slot's tuple is copied before its id is
 * published there, and a tuple equal to one already placed is reported. */
typedef struct pre_job {
    bld* b;
    const vx__svo_interned* pre;
    size_t chunk;
    uint32_t dup_a, dup_b; /* ids of two equal tuples (dup_b 0: none) */
    pthread_mutex_t lock;
} pre_job;

static void pre_chunk(void* ctx, unsigned thread, uint32_t c) {
    (void)thread;
    pre_job* j = (pre_job*)ctx;
    bld* b = j->b;
    size_t lo = (size_t)c * j->chunk, hi = lo + j->chunk < j->pre->count ? lo + j->chunk : j->pre->count;
    for (size_t i = lo; i < hi; i++) {
        rec r = j->pre->tab[i];
        r.pad = 0;
        if (!(b->attrs & VX_ATTR_PALETTE)) r.palette = 0;
        if (!(b->attrs & VX_ATTR_RGBA8)) r.rgba = 0;
        if (!(b->attrs & VX_ATTR_NORMAL)) r.normal = 0;
        if (!(b->attrs & VX_ATTR_MATERIAL)) r.material = 0;
        if (!(b->attrs & VX_ATTR_DENSITY)) r.density = 0;
        b->recs[i] = r;
    }
    size_t mask = b->rhcap - 1;
    for (size_t i = lo; i < hi; i++) {
        size_t h = (size_t)hash_words((const uint32_t*)&b->recs[i], 4, 7) & mask;
        for (;;) {
            uint32_t cur = __atomic_load_n(&b->rhash[h], __ATOMIC_ACQUIRE);
            if (cur == 0 && __atomic_compare_exchange_n(&b->rhash[h], &cur, (uint32_t)i + 1, false, __ATOMIC_ACQ_REL,
                                                        __ATOMIC_ACQUIRE))
                break;
            if (memcmp(&b->recs[cur - 1], &b->recs[i], sizeof(rec)) == 0) {
                pthread_mutex_lock(&j->lock);
                if (!j->dup_b) j->dup_a = cur - 1 < i ? cur - 1 : (uint32_t)i, j->dup_b = cur - 1 < i ? (uint32_t)i : cur - 1;
                pthread_mutex_unlock(&j->lock);
                break;
            }
            h = (h + 1) & mask;
        }
    }
}

/* Interns pre's tuples (ids 0..count-1) into b's empty, presized tables on
 * up to `threads` threads; false when they do not fit (the caller then
 * interns them one by one) or two are equal (b->fail set). */
static bool intern_pre(bld* b, const vx__svo_interned* pre, unsigned threads) {
    if (b->nrec || !b->rhash || b->rhcap < 2 * pre->count + 2 || pre->count > 0xFFFFFFF0u ||
        !vx_grow(b->a, (void**)&b->recs, &b->caprec, pre->count, sizeof(rec)))
        return false;
    pre_job j = {b, pre, 1u << 16, 0, 0, PTHREAD_MUTEX_INITIALIZER};
    size_t chunks = (pre->count + j.chunk - 1) / j.chunk;
    vx_run_jobs(threads, (uint32_t)chunks, pre_chunk, &j);
    pthread_mutex_destroy(&j.lock);
    b->nrec = pre->count;
    if (j.dup_b) {
        b->fail = vx_fail(b->err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo build: interned tuples %u and %u are equal", j.dup_a,
                          j.dup_b);
        return false;
    }
    return true;
}

/* ---- nodes ----------------------------------------------------------------------------- */

static bool nhash_grow(bld* b) {
    size_t ncap = b->nhcap ? b->nhcap * 2 : 4096;
    uint32_t* t = (uint32_t*)vx_calloc(b->a, ncap, sizeof *t);
    if (!t) return oom(b, "node table");
    size_t off = 0;
    while (off < b->npool) {
        uint32_t n = N_KIDS + vx__popc8(b->pool[off]);
        size_t j = (size_t)hash_words(b->pool + off + N_KIDS, n - N_KIDS, b->pool[off]) & (ncap - 1);
        while (t[j]) j = (j + 1) & (ncap - 1);
        t[j] = (uint32_t)off + 1;
        off += n;
    }
    vx_free(b->a, b->nhash);
    b->nhash = t;
    b->nhcap = ncap;
    return true;
}

static uint32_t pool_append(bld* b, uint32_t hdr, const uint32_t* kids, unsigned nk, uint32_t rep);
/* Adds (or with the DAG on, finds) the node; returns its id or UINT32_MAX. */
static uint32_t node_intern(bld* b, uint32_t hdr, const uint32_t* kids, unsigned nk, uint32_t rep) {
    size_t j = 0;
    if (b->dag) {
        if ((b->nnodes + 1) * 2 > b->nhcap && !nhash_grow(b)) return UINT32_MAX;
        j = (size_t)hash_words(kids, nk, hdr) & (b->nhcap - 1);
        while (b->nhash[j]) {
            const uint32_t* n = b->pool + (b->nhash[j] - 1);
            if (n[N_HDR] == hdr && memcmp(n + N_KIDS, kids, nk * sizeof *kids) == 0) return b->nhash[j] - 1;
            j = (j + 1) & (b->nhcap - 1);
        }
    }
    uint32_t id = pool_append(b, hdr, kids, nk, rep);
    if (id != UINT32_MAX && b->dag) b->nhash[j] = id + 1;
    return id;
}

/* Appends a node to the pool without looking for an equal one. */
static uint32_t pool_append(bld* b, uint32_t hdr, const uint32_t* kids, unsigned nk, uint32_t rep) {
    size_t need = b->npool + N_KIDS + nk;
    if (need >= 0xFFFFFFF0u || (b->pub && need > b->cappool)) { /* the second: the bound was wrong; never move the pool */
        b->fail = vx_fail(b->err, VX_ERR_LIMIT, VX_NO_OFFSET, "svo build: node pool exceeds %s words",
                          b->pub ? "its bound" : "2^32");
        return UINT32_MAX;
    }
    if (!vx_grow(b->a, (void**)&b->pool, &b->cappool, need, sizeof(uint32_t))) {
        oom(b, "node pool");
        return UINT32_MAX;
    }
    uint32_t id = (uint32_t)b->npool;
    uint32_t* n = b->pool + id;
    n[N_HDR] = hdr;
    n[N_REP] = rep;
    n[N_BLOCK] = NO_BLOCK;
    memcpy(n + N_KIDS, kids, nk * sizeof *kids);
    b->npool = need;
    b->nnodes++;
    if (b->pub) vx__svo_gate_publish(b->pub, need);
    return id;
}

static void push_child(bld* b, unsigned l, uint64_t prefix_child, bool leaf, uint32_t ref, uint32_t attr, uint64_t plain) {
    if (l > b->depth) { /* the child is the root */
        b->have_root = true;
        b->root_is_leaf = leaf;
        b->root = ref;
        b->root_plain = plain;
        return;
    }
    pending* p = &b->lv[l];
    if (!p->active) {
        p->active = true;
        p->prefix = prefix_child >> 3;
        p->valid = p->leaf = 0;
    }
    unsigned o = (unsigned)(prefix_child & 7u);
    p->valid |= 1u << o;
    if (leaf) p->leaf |= 1u << o;
    p->ch[o] = ref;
    p->cattr[o] = attr;
    p->plain[o] = plain;
}

static bool finalize(bld* b, unsigned l) {
    pending* p = &b->lv[l];
    p->active = false;
    uint64_t plain = 1;
    uint32_t ids[8], kids[8];
    unsigned n = 0;
    for (unsigned o = 0; o < 8; o++)
        if (p->valid >> o & 1u) {
            ids[n] = p->cattr[o];
            kids[n] = p->ch[o];
            plain += p->plain[o];
            n++;
        }
    if (b->collapse && p->valid == 0xFFu && p->leaf == 0xFFu) {
        bool same = true;
        for (unsigned i = 1; i < 8; i++) same = same && ids[i] == ids[0];
        if (same) {
            push_child(b, l + 1, p->prefix, true, ids[0], ids[0], plain);
            return true;
        }
    }
    uint32_t rep = b->attrs ? representative(b, ids, n) : 0;
    if (rep == UINT32_MAX && !b->direct) return false; /* direct values may be 0xFFFFFFFF (opaque white) */
    uint32_t id = node_intern(b, p->valid | (p->leaf << 8), kids, n, rep);
    if (id == UINT32_MAX) return false;
    b->ncollapsed++;
    push_child(b, l + 1, p->prefix, false, id, rep, plain);
    return true;
}

/* ---- sorting ------------------------------------------------------------------------------ */

#define RADIX_BITS 8
#define RADIX_SIZE (1u << RADIX_BITS)

/* Stable LSD radix sort of v[0..n) by bits [lo, lo + nbits) only; tmp has n
 * slots. Returns the array holding the result (v or tmp). */
static uint64_t* radix_u64(uint64_t* v, uint64_t* tmp, size_t n, unsigned lo, unsigned nbits, size_t* cnt) {
    unsigned passes = (nbits + RADIX_BITS - 1) / RADIX_BITS;
    memset(cnt, 0, sizeof(size_t) * RADIX_SIZE * passes);
    for (size_t i = 0; i < n; i++)
        for (unsigned p = 0; p < passes; p++) cnt[p * RADIX_SIZE + ((v[i] >> (lo + p * RADIX_BITS)) & (RADIX_SIZE - 1))]++;
    for (unsigned p = 0; p < passes; p++) {
        size_t* c = cnt + p * RADIX_SIZE;
        unsigned sh = lo + p * RADIX_BITS;
        if (c[(v[0] >> sh) & (RADIX_SIZE - 1)] == n) continue; /* one bucket: nothing moves */
        size_t sum = 0;
        for (unsigned d = 0; d < RADIX_SIZE; d++) {
            size_t t = c[d];
            c[d] = sum;
            sum += t;
        }
        for (size_t i = 0; i < n; i++) tmp[c[(v[i] >> sh) & (RADIX_SIZE - 1)]++] = v[i];
        uint64_t* s = v;
        v = tmp;
        tmp = s;
    }
    return v;
}

/* Cache-friendly stable sort: one MSD pass on the top 11 significant key
 * bits scatters into buckets of a few hundred KB, each then sorted by LSD
 * passes while it sits in cache (plain LSD over 100M entries is bound by
 * memory traffic). kdiff = OR of (key ^ first key): the significant bits. */
static uint64_t* sort_packed(uint64_t* v, uint64_t* tmp, size_t n, unsigned lo, uint64_t kdiff, size_t* cnt) {
    if (!kdiff) return v;
    unsigned hb = 64u - (unsigned)__builtin_clzll(kdiff); /* significant key bits */
    const unsigned mb = 11;
    if (n < ((size_t)1 << 18) || hb <= mb + 8) return radix_u64(v, tmp, n, lo, hb, cnt);
    unsigned msh = lo + hb - mb;
    size_t* c = (size_t*)memset(cnt, 0, sizeof(size_t) * ((size_t)1 << mb));
    for (size_t i = 0; i < n; i++) c[(v[i] >> msh) & ((1u << mb) - 1)]++;
    size_t start[(1u << 11) + 1], sum = 0;
    for (unsigned d = 0; d < (1u << mb); d++) {
        start[d] = sum;
        sum += c[d];
    }
    start[1u << mb] = n;
    for (unsigned d = 0; d < (1u << mb); d++) c[d] = start[d];
    for (size_t i = 0; i < n; i++) tmp[c[(v[i] >> msh) & ((1u << mb) - 1)]++] = v[i];
    for (unsigned d = 0; d < (1u << mb); d++) {
        size_t s0 = start[d], len = start[d + 1] - s0;
        if (len == 0) continue;
        uint64_t* r = len > 1 ? radix_u64(tmp + s0, v + s0, len, lo, hb - mb, cnt) : tmp + s0;
        if (r != v + s0) memcpy(v + s0, r, len * sizeof *v);
    }
    return v;
}

/* Entries that do not fit in one u64 (deep trees with many records). */
typedef struct ent {
    uint64_t key;
    uint32_t aid, level;
} ent;

static ent* radix_ent(ent* v, ent* tmp, size_t n, unsigned nbits, size_t* cnt) {
    unsigned passes = (nbits + RADIX_BITS - 1) / RADIX_BITS;
    memset(cnt, 0, sizeof(size_t) * RADIX_SIZE * passes);
    for (size_t i = 0; i < n; i++)
        for (unsigned p = 0; p < passes; p++) cnt[p * RADIX_SIZE + ((v[i].key >> (p * RADIX_BITS)) & (RADIX_SIZE - 1))]++;
    for (unsigned p = 0; p < passes; p++) {
        size_t* c = cnt + p * RADIX_SIZE;
        unsigned sh = p * RADIX_BITS;
        if (c[(v[0].key >> sh) & (RADIX_SIZE - 1)] == n) continue;
        size_t sum = 0;
        for (unsigned d = 0; d < RADIX_SIZE; d++) {
            size_t t = c[d];
            c[d] = sum;
            sum += t;
        }
        for (size_t i = 0; i < n; i++) tmp[c[(v[i].key >> sh) & (RADIX_SIZE - 1)]++] = v[i];
        ent* s = v;
        v = tmp;
        tmp = s;
    }
    return v;
}

/* ---- layout ------------------------------------------------------------------------------- */

typedef struct outw {
    uint32_t* w;
    size_t n, cap;
    uint32_t* ids; /* attribute run record ids */
    size_t nid, capid;
    /* run start + 1 in bits 0..27, its length in 28..31, and the upper half
     * of its hash in 32..63: a probe compares that before it reads the run
     * (the compare was a cache miss into ids for every probe of a new run) */
    uint64_t* runh;
    size_t runcap, nrun;
    uint64_t far;
    /* blocks that are a lone attribute index (all children leaves): the
     * word position of the last copy of each index that a parent appended
     * now could still reach (lone_find), so equal ones are stored once where
     * parents can reach them. Entries (index + 1) << 32 | position, 0 empty,
     * lonecap of them, open addressing; those out of reach are dropped when
     * half the slots are used (lone_add). */
    uint64_t* lone;
    size_t nlone, lonecap;
    /* the uniform runs in runh (len copies of one record), by record: which
     * lengths are stored and where, so that a short uniform run finds a
     * longer one with one probe instead of one per length (run_intern) */
    struct uni_run* uni;
    size_t unicap, nuni;
    size_t runs_pos, runs_taken; /* bld.runs: the next byte, the runs taken */
} outw;

typedef struct uni_run {
    uint32_t key;  /* the record (a value when direct: any 32 bits) */
    uint32_t lens; /* bit len - 1: a run of len copies is stored; bit 31: the entry is used */
    uint32_t start[8];
} uni_run;

/* The push where the words have no room (grows them; false at the limit or
 * without memory): out of line, so that out_push's common case inlines
 * into lay_block (a call per word was a fortieth of the helmet's read). */
static bool __attribute__((noinline)) out_push_slow(bld* b, outw* o, uint32_t v) {
    if (o->n >= 0xFFFFFFF0u) {
        b->fail = vx_fail(b->err, VX_ERR_LIMIT, VX_NO_OFFSET, "svo build: more than 2^32 node words");
        return false;
    }
    if (!vx_grow(b->a, (void**)&o->w, &o->cap, o->n + 1, sizeof(uint32_t))) return oom(b, "node words");
    o->w[o->n++] = v;
    return true;
}
static inline bool out_push(bld* b, outw* o, uint32_t v) {
    if (o->n < o->cap && o->n < 0xFFFFFFF0u) { /* the common case without a call (vx_grow) per word */
        o->w[o->n++] = v;
        return true;
    }
    return out_push_slow(b, o, v);
}

/* Appends (or with the DAG on, reuses) a run of records; UINT32_MAX on failure. */
static uint32_t run_intern_exact(bld* b, outw* o, const uint32_t* ids, unsigned n, bool add, const uint64_t* hp);

/* The run table (outw.runh) is indexed by the high half of a run's hash,
 * the half its entries keep: growing it moves entries without hashing
 * their runs again (each a read at a random place in ids). Which equal run
 * a lookup finds does not depend on the table (only the first of equal runs
 * is stored), so neither do the words. */
static inline size_t run_slot(uint64_t h, size_t cap) { return (size_t)(h >> 32) & (cap - 1); }

/* n (<= 8) ids equal: inline, where memcmp was a call per probe */
static inline bool same_ids(const uint32_t* a, const uint32_t* b, unsigned n) {
    uint32_t d = 0;
    for (unsigned i = 0; i < n; i++) d |= a[i] ^ b[i];
    return d == 0;
}

/* The uniform-run entry of record v (claimed when absent); NULL when the
 * table cannot grow (b->fail set). */
static uni_run* uni_find(bld* b, outw* o, uint32_t v) {
    if ((o->nuni + 1) * 2 > o->unicap) {
        size_t ncap = o->unicap ? o->unicap * 2 : 1024;
        uni_run* t = (uni_run*)vx_calloc(b->a, ncap, sizeof *t);
        if (!t) return oom(b, "uniform runs"), NULL;
        for (size_t i = 0; i < o->unicap; i++)
            if (o->uni[i].lens) {
                size_t q = (size_t)mix64(o->uni[i].key) & (ncap - 1);
                while (t[q].lens) q = (q + 1) & (ncap - 1);
                t[q] = o->uni[i];
            }
        vx_free(b->a, o->uni);
        o->uni = t;
        o->unicap = ncap;
    }
    size_t q = (size_t)mix64(v) & (o->unicap - 1);
    while (o->uni[q].lens && o->uni[q].key != v) q = (q + 1) & (o->unicap - 1);
    if (!o->uni[q].lens) {
        o->uni[q].key = v;
        o->uni[q].lens = 1u << 31;
        o->nuni++;
    }
    return &o->uni[q];
}

/* A run of one repeated value is also found inside any longer run of that
 * value (records are indexed from the run start), which is common with
 * palette colours: try the longer uniform runs first, longest first (the
 * uniform-run table says which are stored: the probes of runh for each
 * length, which that table replaces, found the same runs). */
/* hp: the run's hash_words(ids, n, 3) when the caller has it (run_prefetch), or NULL. */
/* add false: find only (UINT32_MAX when no stored run serves). */
static uint32_t run_intern(bld* b, outw* o, const uint32_t* ids, unsigned n, const uint64_t* hp, bool add) {
    if (b->dag && n < 8) {
        bool uni = true;
        for (unsigned i = 1; i < n; i++) uni = uni && ids[i] == ids[0];
        if (uni) {
            uni_run* e = uni_find(b, o, ids[0]);
            if (!e) return UINT32_MAX;
            uint32_t longer = (e->lens & 0xFFu) >> n; /* bit k: length n + 1 + k */
            if (longer) return e->start[n + (31u - (unsigned)__builtin_clz(longer))];
        }
    }
    return run_intern_exact(b, o, ids, n, add, hp);
}

/* With add false: UINT32_MAX when the run is not stored yet. */
/* The run's records appended to the model's (not stored in the run table);
 * its first record's index, UINT32_MAX on failure. */
static uint32_t run_append(bld* b, outw* o, const uint32_t* ids, unsigned n) {
    if (o->nid + n >= 0xFFFFFFF0u) {
        b->fail = vx_fail(b->err, VX_ERR_LIMIT, VX_NO_OFFSET, "svo build: more than 2^32 attribute records");
        return UINT32_MAX;
    }
    if (!vx_grow(b->a, (void**)&o->ids, &o->capid, o->nid + n, sizeof(uint32_t))) return oom(b, "records"), UINT32_MAX;
    uint32_t st = (uint32_t)o->nid;
    memcpy(o->ids + o->nid, ids, n * sizeof *ids);
    o->nid += n;
    return st;
}

/* The run table at the size run_intern_exact's growth reaches for `runs`
 * runs (4096 doubled while more than half would be full), so that it is
 * never grown and rehashed; huge: advised as 2 MB pages (its probes land at
 * random). Nothing where it cannot be had: the table grows as usual. */
static void run_table_presize(bld* b, outw* o, size_t runs, bool huge) {
    size_t cap = 4096;
    while (cap / 2 < runs + 1 && cap <= SIZE_MAX / 16) cap *= 2;
    o->runh = (uint64_t*)vx_alloc(b->a, cap * sizeof *o->runh);
    if (!o->runh) return;
    if (huge) vx__svo_advise_huge(o->runh, cap * sizeof *o->runh);
    memset(o->runh, 0, cap * sizeof *o->runh);
    o->runcap = cap;
}

static uint32_t run_intern_exact(bld* b, outw* o, const uint32_t* ids, unsigned n, bool add, const uint64_t* hp) {
    uint64_t h = 0;
    size_t j = 0;
    if (b->dag) {
        if ((o->nrun + 1) * 2 > o->runcap) {
            size_t ncap = o->runcap ? o->runcap * 2 : 4096;
            uint64_t* t = (uint64_t*)vx_calloc(b->a, ncap, sizeof *t);
            if (!t) return oom(b, "attribute runs"), UINT32_MAX;
            for (size_t i = 0; i < o->runcap; i++)
                if (o->runh[i]) {
                    uint64_t e = o->runh[i];
                    size_t k = run_slot(e, ncap);
                    while (t[k]) k = (k + 1) & (ncap - 1);
                    t[k] = e;
                }
            vx_free(b->a, o->runh);
            o->runh = t;
            o->runcap = ncap;
        }
        h = hp ? *hp : hash_words(ids, n, 3);
        j = run_slot(h, o->runcap);
        uint64_t want = (h & 0xFFFFFFFF00000000ull) | (uint64_t)n << 28;
        while (o->runh[j]) {
            uint64_t e = o->runh[j];
            uint32_t st = ((uint32_t)e & 0x0FFFFFFFu) - 1;
            if ((e & 0xFFFFFFFFF0000000ull) == want && same_ids(o->ids + st, ids, n)) return st;
            j = (j + 1) & (o->runcap - 1);
        }
        if (!add) return UINT32_MAX;
    }
    /* beyond what the run table can address (0x0FFFFFF0 records): stop sharing, keep going */
    if (b->dag && o->nid + n < 0x0FFFFFF0u) {
        o->runh[j] = (h & 0xFFFFFFFF00000000ull) | ((uint64_t)n << 28) | ((uint32_t)o->nid + 1);
        o->nrun++;
        bool uni = true;
        for (unsigned i = 1; i < n; i++) uni = uni && ids[i] == ids[0];
        if (uni) { /* the first stored run of these n copies: the one runh finds from now on */
            uni_run* e = uni_find(b, o, ids[0]);
            if (!e) return UINT32_MAX;
            e->lens |= 1u << (n - 1);
            e->start[n - 1] = (uint32_t)o->nid;
        }
    }
    return run_append(b, o, ids, n);
}

/* The node's run from the runs stream (bld.runs, FORMAT.md 3.7): one byte a
 * node, 0: a new run, appended and not stored (no later run is equal to
 * it: 70% of the 4096^3 helmet's runs), 1: a new run, appended and stored
 * (a later run finds it), 2: a run found among the stored ones (it must
 * be). The reader's run table then holds the runs that are found again
 * only (1.2 M of the helmet's 20.2 M, where it held 15.4 M), and a run is
 * looked up only where one is found; the lookup and the store are
 * run_intern's, so the words and records are the layout's of 3.5. A
 * damaged stream is refused, never read past. UINT32_MAX on failure. */
/* hp: as run_intern's */
static uint32_t run_take(bld* b, outw* o, const uint32_t* ids, unsigned n, const uint64_t* hp) {
    if (o->runs_pos >= b->runs_n) {
        b->fail = vx_fail(b->err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo: section NODE: the runs stream ends before the tree does (%zu runs)",
                          o->runs_taken);
        return UINT32_MAX;
    }
    uint8_t f = b->runs[o->runs_pos++];
    o->runs_taken++;
    if (f == 1) return run_intern_exact(b, o, ids, n, true, hp);
    if (f == 2) {
        uint32_t a = run_intern(b, o, ids, n, hp, false);
        if (a == UINT32_MAX && b->fail == VX_OK)
            b->fail = vx_fail(b->err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET,
                              "svo: section NODE: the runs stream's run %zu is to be found among the stored runs, but none is equal",
                              o->runs_taken - 1);
        return a;
    }
    if (f != 0) {
        b->fail = vx_fail(b->err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo: section NODE: the runs stream's run %zu is %u (not 0, 1 or 2)",
                          o->runs_taken - 1, f);
        return UINT32_MAX;
    }
    return run_append(b, o, ids, n);
}

static inline bool node_has_block(const bld* b, const uint32_t* n) {
    uint32_t valid = n[N_HDR] & 0xFFu, leaf = (n[N_HDR] >> 8) & 0xFFu;
    return (valid & ~leaf) != 0 || b->attrs != 0;
}

/* What a layout pass does to each node: all of it (LAY_ALL), or one of its
 * two halves on two threads (the pool path, pool_take): LAY_RUNS interns the
 * node's attribute run and leaves its index in the node's N_BLOCK word,
 * LAY_BLOCKS then writes the block from it. The runs depend only on the
 * representatives, the blocks only on the runs and the children's blocks,
 * and each half keeps the pool order: the words are the one pass's. */
enum { LAY_ALL, LAY_RUNS, LAY_BLOCKS };

/* Writes the block of every node in creation order (children first), far
 * slots right before the block whose descriptors need them. */
/* Touches the run-table slots that node `at`'s run will probe (run_intern:
 * the uniform-run entry, the run table), so that the misses of the nodes
 * ahead overlap the work on the current one: with large tables each probe
 * is a miss to memory. A hint only: nothing is written. */
/* *h: the run's hash (run_intern takes it: one hash per run, not two). */
/* With the runs stream (bld.runs), *rp is the node's byte there: a run that
 * is only appended (0) probes nothing. */
static size_t run_prefetch(const bld* b, const outw* o, size_t at, uint64_t* h, size_t* rp) {
    const uint32_t* n = b->pool + at;
    uint32_t valid = n[N_HDR] & 0xFFu, leaf = (n[N_HDR] >> 8) & 0xFFu;
    unsigned nk = vx__popc8(valid);
    *h = 0;
    if (!b->runs || (*rp < b->runs_n && b->runs[(*rp)++] != 0)) {
        uint32_t ids[8];
        bool uni = true;
        for (unsigned oc = 0, j = 0; oc < 8; oc++) {
            if (!(valid >> oc & 1u)) continue;
            uint32_t ref = n[N_KIDS + j];
            ids[j] = (leaf >> oc & 1u) ? ref : b->pool[ref + N_REP];
            uni = uni && ids[j] == ids[0];
            j++;
        }
        if (uni && nk < 8 && o->unicap) __builtin_prefetch(&o->uni[(size_t)mix64(ids[0]) & (o->unicap - 1)]);
        *h = hash_words(ids, nk, 3);
        if (o->runcap) __builtin_prefetch(&o->runh[run_slot(*h, o->runcap)]);
    }
    return at + N_KIDS + nk;
}

/* The lone-block table (outw.lone): a parent reaches back at most `limit`
 * words, and each copy of a lone block is a word, so fewer than `limit`
 * (2^15 - 1) copies are in reach at any time: a table of at most 2^17 slots
 * (1 MB, in cache) answers exactly what an array over every record index
 * answered (the last copy, reusable while in reach: a copy out of reach
 * stays so, as the words only grow), where that array (4 bytes a record:
 * 295 MB for the 4096^3 helmet, cleared as it grew) was a cache miss a lone
 * block. It starts at LONE_MIN slots (a small model's read stays small). */
enum { LONE_MIN = 1 << 10, LONE_MAX = 1 << 17 };
static size_t lone_slot(const outw* o, uint32_t a) {
    size_t m = o->lonecap - 1, q = (size_t)mix64(a) & m;
    uint64_t key = (uint64_t)(a + 1) << 32;
    while (o->lone[q] && (o->lone[q] & 0xFFFFFFFF00000000ull) != key) q = (q + 1) & m;
    return q; /* a's entry, or the empty slot that ends its probe */
}
/* Puts a's first entry at its empty slot q. At half the slots used, the
 * entries out of reach are dropped and the others placed again, in a table
 * of twice the slots while they fill a quarter (up to LONE_MAX: they are
 * fewer than limit, a quarter of it); false without memory. */
static bool lone_add(bld* b, outw* o, uint32_t a, uint32_t limit, size_t q) {
    o->lone[q] = (uint64_t)(a + 1) << 32 | (uint32_t)o->n;
    if (++o->nlone < o->lonecap / 2) return true;
    size_t cap = o->lonecap, nk = 0;
    uint64_t* old = o->lone;
    for (size_t i = 0; i < cap; i++) { /* the kept entries to the front, in slot order */
        uint64_t e = old[i];
        if (e && o->n - (uint32_t)e + 64 < limit) old[nk++] = e;
    }
    size_t ncap = nk >= cap / 4 && cap < LONE_MAX ? cap * 2 : cap;
    uint64_t* t = (uint64_t*)vx_calloc(b->a, ncap, sizeof *t);
    if (!t) return oom(b, "block table");
    o->lone = t;
    o->lonecap = ncap;
    for (size_t i = 0; i < nk; i++) t[lone_slot(o, (uint32_t)(old[i] >> 32) - 1)] = old[i];
    o->nlone = nk;
    vx_free(b->a, old);
    return true;
}

/* Writes one node's block: the far slots its descriptors need, a descriptor
 * per non-leaf child (cb: the child's block, NO_BLOCK for none; cd: its
 * masks, valid | leaf << 8), then its run's index `a` (with attributes);
 * *blk is where the block starts, or the earlier copy of a lone block
 * reused. The one place both layouts (layout_nodes over the pool, unp_lay
 * in the reader's reconstruction) write blocks, so their words are equal. */
static bool lay_block(bld* b, outw* o, uint32_t a, const uint32_t* cb, const uint32_t* cd, unsigned nn, uint32_t* blk) {
    uint32_t limit = b->limit;
    if (nn == 0 && b->dag) {
        /* the block is the word `a` alone, position-independent: reuse a
         * recent copy while parents can still reach it without a far slot */
        if (!o->lone) {
            if (!(o->lone = (uint64_t*)vx_calloc(b->a, LONE_MIN, sizeof *o->lone))) return oom(b, "block table");
            o->lonecap = LONE_MIN;
        }
        size_t q = lone_slot(o, a);
        uint64_t e = o->lone[q];
        if (e && o->n - (uint32_t)e + 64 < limit) {
            *blk = (uint32_t)e;
            return true;
        }
        if (e) o->lone[q] = (uint64_t)(a + 1) << 32 | (uint32_t)o->n;
        else if (!lone_add(b, o, a, limit, q)) return false;
    }
    /* far slots needed: a fixpoint since each slot shifts the descriptors */
    size_t cur = o->n;
    unsigned nfar = 0;
    bool far[8];
    for (int it = 0; it < 10; it++) {
        unsigned cnt = 0;
        for (unsigned k = 0; k < nn; k++) {
            far[k] = cb[k] != NO_BLOCK && (cur + nfar + k) - cb[k] > limit;
            cnt += far[k];
        }
        if (cnt == nfar) break;
        nfar = cnt;
    }
    unsigned fi = 0;
    for (unsigned k = 0; k < nn; k++)
        if (far[k] && !out_push(b, o, cb[k])) return false;
    size_t bstart = cur + nfar;
    for (unsigned k = 0; k < nn; k++) {
        uint32_t d;
        size_t pos = bstart + k;
        if (cb[k] == NO_BLOCK) d = vx_svo_desc_make(0, false, cd[k] & 0xFFu, cd[k] >> 8);
        else if (far[k]) d = vx_svo_desc_make((uint32_t)(pos - (cur + fi++)), true, cd[k] & 0xFFu, cd[k] >> 8);
        else d = vx_svo_desc_make((uint32_t)(pos - cb[k]), false, cd[k] & 0xFFu, cd[k] >> 8);
        if (!out_push(b, o, d)) return false;
    }
    o->far += nfar;
    if (b->attrs && !out_push(b, o, a)) return false;
    *blk = (uint32_t)bstart;
    return true;
}

static bool layout_nodes(bld* b, outw* o, size_t* off_io, size_t end, int mode) {
    size_t off = *off_io;
    /* the prefetch cursor runs PF_AHEAD nodes ahead (with attribute runs to intern) */
    enum { PF_AHEAD = 12, PF_QUEUE = 16 };
    bool pf_on = b->dag && b->attrs && mode != LAY_BLOCKS;
    size_t pf = off, pfr = o->runs_pos; /* pfr: the runs stream's byte of the node at pf (with attributes one a node) */
    /* the hashes of the runs prefetched, in node order (with attributes
     * every node has a block and a run: one each) */
    uint64_t hq[PF_QUEUE];
    unsigned qin = 0, qout = 0;
    for (unsigned k = 0; pf_on && k < PF_AHEAD && pf < end; k++) pf = run_prefetch(b, o, pf, &hq[qin++ % PF_QUEUE], &pfr);
    while (off < end) {
        if (pf_on && pf < end) pf = run_prefetch(b, o, pf, &hq[qin++ % PF_QUEUE], &pfr);
        uint32_t* n = b->pool + off;
        uint32_t valid = n[N_HDR] & 0xFFu, leaf = (n[N_HDR] >> 8) & 0xFFu;
        unsigned nk = vx__popc8(valid);
        size_t next = off + N_KIDS + nk;
        if (!node_has_block(b, n)) {
            off = next;
            continue;
        }
        /* the non-leaf children and their blocks */
        uint32_t cb[8], cd[8];
        unsigned nn = 0, j = 0;
        uint32_t runids[8];
        for (unsigned oc = 0; oc < 8; oc++) {
            if (!(valid >> oc & 1u)) continue;
            uint32_t ref = n[N_KIDS + j++];
            if (leaf >> oc & 1u) {
                runids[j - 1] = ref;
            } else {
                const uint32_t* c = b->pool + ref;
                runids[j - 1] = c[N_REP];
                if (mode != LAY_RUNS) cb[nn] = c[N_BLOCK]; /* the other thread writes it meanwhile */
                cd[nn] = c[N_HDR];
                nn++;
            }
        }
        uint32_t a = 0;
        if (b->attrs && mode == LAY_BLOCKS) {
            a = n[N_BLOCK];
        } else if (b->attrs) {
            const uint64_t* hp = pf_on ? &hq[qout++ % PF_QUEUE] : NULL;
            a = b->runs ? run_take(b, o, runids, nk, hp) : run_intern(b, o, runids, nk, hp, true);
            if (a == UINT32_MAX) return false;
        }
        if (mode == LAY_RUNS) {
            n[N_BLOCK] = a;
            off = next;
            continue;
        }
        uint32_t blk;
        if (!lay_block(b, o, a, cb, cd, nn, &blk)) return false;
        n[N_BLOCK] = blk;
        off = next;
    }
    *off_io = off;
    return true;
}

/* ---- the layout on a second thread -------------------------------------------------------- */

/* Blocks are written in pool order and a node's block needs only its
 * children's, which come earlier in the pool: so the layout can follow the
 * build on another thread, node by node as they are appended, and the
 * result is the sequential one. The producer never moves the pool (it is
 * allocated at a bound), reads no N_BLOCK word and writes nodes only before
 * publishing them; the layout writes only N_BLOCK words and its own outw. */
/* A stage sleeps until this many more pool words are there to lay out
 * (about a millisecond of the builder's or the decoder's work, 256 KB of
 * pool: still in cache), so that on two cores the threads take turns in
 * slices rather than word by word; the builder publishes every PUB_STEP. */
enum { LAY_WAKE = 1 << 16, LAY_PUB_STEP = 1 << 12 };
typedef struct lay_job {
    bld lb; /* a copy of the builder for the layout: pool, attrs, dag, limit; its own failure */
    outw* o;
    vx__svo_gate pub;  /* pool words the builder has appended (the first stage follows these); closed by lay_join */
    vx__svo_gate* src; /* what this thread follows: &pub, or the runs stage's done */
    vx__svo_gate done; /* pool words this thread is through; closed when it ends */
    int mode;          /* LAY_ALL, or a stage: LAY_RUNS, LAY_BLOCKS */
    bool gates;        /* pub and done initialised (lay_prep; lay_free destroys them) */
    vx_error err;
    pthread_t th;
    bool started;
} lay_job;

static void* lay_main(void* arg) {
    lay_job* j = (lay_job*)arg;
    size_t off = 0;
    for (;;) {
        size_t end = vx__svo_gate_wait(j->src, off, LAY_WAKE);
        if (end <= off) break; /* closed: everything published is laid out */
        if (!layout_nodes(&j->lb, j->o, &off, end, j->mode)) break;
        vx__svo_gate_publish(&j->done, off);
    }
    j->lb.laid = off;
    vx__svo_gate_close(&j->done, off); /* a failure too: the next stage stops where this one did */
    return NULL;
}

/* Initialises j's gates (before any thread that uses them starts). */
static void lay_prep(lay_job* j) {
    vx__svo_gate_init(&j->pub, LAY_PUB_STEP);
    vx__svo_gate_init(&j->done, 0);
    j->gates = true;
    j->started = false;
}
/* After the joins of every stage: no thread reads the gates any more. */
static void lay_free(lay_job* j) {
    if (!j->gates) return;
    vx__svo_gate_destroy(&j->pub);
    vx__svo_gate_destroy(&j->done);
    j->gates = false;
}

/* Words of pool the build of n entries (no tiles) can need: at most
 * min(n, 8^(depth-l)) nodes at level l, each N_KIDS words plus its children,
 * a child being a node or an entry. */
static size_t pool_bound(size_t n, uint32_t depth) {
    double nodes = 0;
    for (uint32_t l = 1; l <= depth; l++) {
        double cubes = pow(8.0, (double)(depth - l));
        nodes += cubes < (double)n ? cubes : (double)n;
    }
    double words = (N_KIDS + 1) * nodes + (double)n + 16;
    return words < 4.0e9 ? (size_t)words : 0;
}

static bool lay_run(lay_job* j, bld* b, outw* o);
/* Starts the layout thread over b's pool, allocated at the bound; false
 * (and nothing started) when either cannot be had: the layout then runs
 * after the build as usual. */
static bool lay_start(lay_job* j, bld* b, outw* o, size_t n) {
    size_t words = pool_bound(n, b->depth);
    if (!words || b->pool) return false;
    b->pool = (uint32_t*)vx_alloc(b->a, words * sizeof *b->pool);
    if (!b->pool) return false;
    b->cappool = words;
    return lay_run(j, b, o);
}

/* Prepares j to follow src in mode; starts its thread (false: none started). */
static bool lay_thread(lay_job* j, bld* b, outw* o, vx__svo_gate* src, int mode) {
    j->o = o; /* j's gates: initialised by the caller (another thread may read them first) */
    j->src = src ? src : &j->pub;
    j->mode = mode;
    memset(&j->err, 0, sizeof j->err);
    j->lb = *b;
    j->lb.err = &j->err;
    j->lb.fail = VX_OK;
    j->started = pthread_create(&j->th, NULL, lay_main, j) == 0;
    return j->started;
}

/* Starts the layout thread over b's pool as it is (allocated at its final
 * size: it never moves); false when no thread could be started. */
static bool lay_run(lay_job* j, bld* b, outw* o) {
    if (!j->gates) lay_prep(j);
    if (!lay_thread(j, b, o, NULL, LAY_ALL)) return false; /* the pool stays, growable as usual */
    b->pub = &j->pub;
    return true;
}

static void lay_join(lay_job* j, bld* b, bool propagate);
/* The layout in two stages on two threads, runs (ja) then blocks (jb),
 * both following the builder; one thread (lay_run) when the second cannot
 * be started. The pool must not move. */
static bool lay_run2(lay_job* ja, lay_job* jb, bld* b, outw* o) {
    lay_prep(ja);
    lay_prep(jb);
    if (!lay_thread(jb, b, o, &ja->done, LAY_BLOCKS)) return lay_run(ja, b, o);
    if (!lay_thread(ja, b, o, NULL, LAY_RUNS)) {
        vx__svo_gate_close(&ja->done, 0);
        lay_join(jb, b, false); /* it has laid nothing out: b->laid stays 0 */
        return false;
    }
    b->pub = &ja->pub;
    return true;
}

/* Lets the layout thread finish what was published and joins it; with
 * propagate, its failure becomes b's. */
static void lay_join(lay_job* j, bld* b, bool propagate) {
    if (!j->started) return;
    if (j->src == &j->pub) vx__svo_gate_close(&j->pub, b->npool); /* the builder's nodes are all written */
    pthread_join(j->th, NULL);
    j->started = false;
    b->pub = NULL;
    b->laid = j->lb.laid;
    if (propagate && j->lb.fail != VX_OK && b->fail == VX_OK) {
        b->fail = j->lb.fail;
        if (b->err) *b->err = j->err;
    }
}

/* The blocks of the nodes not laid out yet, then the root descriptor. */
static bool layout(bld* b, outw* o) {
    uint32_t limit = b->limit;
    if (!layout_nodes(b, o, &b->laid, b->npool, b->runs_given ? LAY_BLOCKS : LAY_ALL)) return false;
    /* the root descriptor goes last */
    const uint32_t* r = b->pool + b->root;
    uint32_t blk = r[N_BLOCK], hdr = r[N_HDR];
    if (blk == NO_BLOCK) return out_push(b, o, vx_svo_desc_make(0, false, hdr & 0xFFu, hdr >> 8));
    if (o->n - blk > limit) {
        if (!out_push(b, o, blk)) return false;
        o->far++;
        return out_push(b, o, vx_svo_desc_make(1, true, hdr & 0xFFu, hdr >> 8));
    }
    return out_push(b, o, vx_svo_desc_make((uint32_t)(o->n - blk), false, hdr & 0xFFu, hdr >> 8));
}

enum { REC_CHUNK = 1 << 15 };

/* body(ctx, lo, hi) over [0, n) in chunks of REC_CHUNK, on b's threads
 * when n is large (the GPU path's big regions), else on this one. */
typedef struct par_job {
    void (*body)(void* ctx, size_t lo, size_t hi);
    void* ctx;
    size_t n;
} par_job;
static void par_chunk(void* arg, unsigned thread, uint32_t c) {
    (void)thread;
    par_job* j = (par_job*)arg;
    size_t lo = (size_t)c * REC_CHUNK, hi = lo + REC_CHUNK < j->n ? lo + REC_CHUNK : j->n;
    j->body(j->ctx, lo, hi);
}
static void par_for(const bld* b, size_t n, void (*body)(void* ctx, size_t lo, size_t hi), void* ctx) {
    if (b->threads > 1 && n >= ((size_t)1 << 17) && (n + REC_CHUNK - 1) / REC_CHUNK <= UINT32_MAX) {
        par_job j = {body, ctx, n};
        vx_run_jobs(b->threads, (uint32_t)((n + REC_CHUNK - 1) / REC_CHUNK), par_chunk, &j);
    } else if (n) {
        body(ctx, 0, n);
    }
}
/* The record arrays of the model from o's record ids. */
typedef struct rec_fill {
    const bld* b;
    const uint32_t* ids; /* the record ids (outw.ids), or with own the rgba array they became */
    bool own;            /* m->rgba is ids: filled already */
    vx_svo_model* m;
} rec_fill;
static void rec_fill_range(void* ctx, size_t lo, size_t hi) {
    const rec_fill* f = (const rec_fill*)ctx;
    const bld* b = f->b;
    vx_svo_model* m = f->m;
    uint32_t* rgba = f->own ? NULL : m->rgba;
    if (b->direct) {
        /* records are the one channel's values (the ids), the others the
         * constants: a loop per array, each a copy or a fill the compiler
         * vectorises, where a record was made and taken apart per element
         * (the 4096^3 helmet's 74 M material copies of one value) */
        const uint32_t* v = f->ids;
        const rec c = b->cst;
        uint32_t va = b->vattr;
        if (m->palette)
            for (size_t i = lo; i < hi; i++) m->palette[i] = va == VX_ATTR_PALETTE ? (uint8_t)v[i] : c.palette;
        if (rgba)
            for (size_t i = lo; i < hi; i++) rgba[i] = va == VX_ATTR_RGBA8 ? v[i] : c.rgba;
        if (m->normal)
            for (size_t i = lo; i < hi; i++) m->normal[i] = va == VX_ATTR_NORMAL ? v[i] : c.normal;
        if (m->material)
            for (size_t i = lo; i < hi; i++) m->material[i] = va == VX_ATTR_MATERIAL ? (uint16_t)v[i] : c.material;
        if (m->density)
            for (size_t i = lo; i < hi; i++) {
                rec dv = c;
                rec_put_value(va, v[i], &dv);
                m->density[i] = dv.density;
            }
        return;
    }
    for (size_t i = lo; i < hi; i++) {
        const rec* r = &b->recs[f->ids[i]];
        if (m->palette) m->palette[i] = r->palette;
        if (rgba) rgba[i] = r->rgba;
        if (m->normal) m->normal[i] = r->normal;
        if (m->material) m->material[i] = r->material;
        if (m->density) m->density[i] = r->density;
    }
}

/* The output side shared by the builder and the .svo reader (vx__svo_unpack):
 * lays out the pool (unless the root is a leaf or the model is empty), picks
 * root_attr and fills m's words and record arrays. On failure m owns nothing
 * new and b->fail is set. */
static bool finish_model(bld* b, outw* o, vx_svo_model* m, bool empty) {
    if (!empty) {
        uint32_t root_rec;
        if (b->root_is_leaf) {
            m->root = VX_SVO_ROOT_LEAF;
            root_rec = b->root;
        } else if (b->laid_given) {
            m->root = (uint32_t)(o->n - 1);
            root_rec = b->root;
        } else {
            if (!layout(b, o)) return false;
            m->root = (uint32_t)(o->n - 1);
            root_rec = b->pool[b->root + N_REP];
        }
        if (b->attrs) {
            size_t at = o->nid;
            for (size_t i = 0; i < o->nid; i++)
                if (o->ids[i] == root_rec) { at = i; break; }
            if (at == o->nid && run_intern(b, o, &root_rec, 1, NULL, true) == UINT32_MAX) return false;
            m->root_attr = (uint32_t)at;
        }
    }
    m->node_count = (uint32_t)o->n;
    m->nodes = o->w;
    o->w = NULL;
    m->attr_count = b->attrs ? (uint32_t)o->nid : 0;
    size_t na = m->attr_count;
    bool ok = true;
    if (b->attrs & VX_ATTR_PALETTE) ok = ok && (m->palette = (uint8_t*)vx_alloc(b->a, na * 1)) != NULL;
    /* where the record ids are the RGBA8 values themselves (direct), they are
     * the rgba array: handed over, not copied into fresh pages (the 4096^3
     * helmet's 74 M records: 295 MB written, faulted in and read once less) */
    bool own = b->give_ids && b->direct && b->vattr == VX_ATTR_RGBA8 && o->ids && na;
    if (own) {
        m->rgba = o->ids;
        o->ids = NULL;
        o->capid = 0;
    } else if (b->attrs & VX_ATTR_RGBA8) {
        ok = ok && (m->rgba = (uint32_t*)vx_alloc(b->a, na * 4)) != NULL;
    }
    if (b->attrs & VX_ATTR_NORMAL) ok = ok && (m->normal = (uint32_t*)vx_alloc(b->a, na * 4)) != NULL;
    if (b->attrs & VX_ATTR_MATERIAL) ok = ok && (m->material = (uint16_t*)vx_alloc(b->a, na * 2)) != NULL;
    if (b->attrs & VX_ATTR_DENSITY) ok = ok && (m->density = (float*)vx_alloc(b->a, na * 4)) != NULL;
    if (!ok) {
        vx_svo_model_free(b->a, m);
        if (b->fail == VX_OK)
            b->fail = vx_fail(b->err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo build: cannot allocate %zu attribute records", na);
        return false;
    }
    /* filled once, a page fault per 4 KB otherwise (the 4096^3 helmet's
     * 74 M materials: 148 MB) */
    vx__svo_advise_huge(m->palette, na);
    if (!own) vx__svo_advise_huge(m->rgba, na * 4);
    vx__svo_advise_huge(m->normal, na * 4);
    vx__svo_advise_huge(m->material, na * 2);
    vx__svo_advise_huge(m->density, na * 4);
    rec_fill f = {b, own ? m->rgba : o->ids, own, m};
    if (!own || b->attrs != VX_ATTR_RGBA8) /* (the rgba array alone: nothing left to fill) */
        par_for(b, na, rec_fill_range, &f); /* many records (a large region from the GPU): on the builder's threads */
    return true;
}

/* ---- a tree built by the caller (vx__svo_interned.pool) ------------------------------------- */

/* The records of the caller's attribute runs (vx__svo_pool.runs): tuple
 * ids in range, as values when direct. */
typedef struct rec_take {
    const bld* b;
    const uint32_t* in;
    uint32_t* out;
    atomic_bool bad;
} rec_take;
static void rec_take_range(void* ctx, size_t lo, size_t hi) {
    rec_take* t = (rec_take*)ctx;
    const bld* b = t->b;
    bool bad = false;
    for (size_t k = lo; k < hi; k++) {
        uint32_t id = t->in[k];
        bad = bad || id >= b->nrec;
        t->out[k] = id >= b->nrec ? 0 : b->direct ? rec_value(b->attrs, &b->recs[id]) : id;
    }
    if (bad) atomic_store(&t->bad, true);
}
static bool records_take(bld* b, const vx__svo_pool* p, outw* o) {
    if (!vx_grow(b->a, (void**)&o->ids, &o->capid, p->nrecs ? p->nrecs : 1, sizeof *o->ids)) return oom(b, "records");
    rec_take t = {b, p->recs, o->ids, false};
    par_for(b, p->nrecs, rec_take_range, &t);
    if (atomic_load(&t.bad)) {
        size_t k = 0;
        while (p->recs[k] < b->nrec) k++;
        b->fail = vx_fail(b->err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo build: pool record %zu: tuple %u of %zu", k, p->recs[k],
                          b->nrec);
        return false;
    }
    o->nid = p->nrecs;
    b->runs_given = true;
    return true;
}

/* The caller's laid-out blocks (vx__svo_pool.laid): the model's words and
 * records as given; the builder keeps only the root's record. */
static bool laid_take(bld* b, const vx__svo_pool* p, outw* o) {
    if (!b->attrs || !b->dag || !p->reps || !p->runs || !p->laid_count || p->laid_count >= 0xFFFFFFF0u || b->limit != VX__SVO_PTR_MAX ||
        p->nrecs >= 0x0FFFFFF0u) {
        b->fail = vx_fail(b->err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                          "svo build: blocks laid out by the caller need attributes, the DAG, given runs and near pointers up to %u",
                          VX__SVO_PTR_MAX);
        return false;
    }
    if (p->root_rep >= b->nrec || p->root_leaf) {
        b->fail = vx_fail(b->err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo build: laid-out blocks with root tuple %u of %zu", p->root_rep,
                          b->nrec);
        return false;
    }
    if (!records_take(b, p, o)) return false;
    if (!vx_grow(b->a, (void**)&o->w, &o->cap, p->laid_count + 2, sizeof *o->w)) return oom(b, "node words");
    memcpy(o->w, p->laid, p->laid_count * sizeof *o->w);
    o->n = p->laid_count;
    o->far = p->laid_far;
    b->laid_given = true;
    b->laid_desc = p->laid_desc;
    b->have_root = true;
    b->root_is_leaf = false;
    b->root = b->direct ? rec_value(b->attrs, &b->recs[p->root_rep]) : p->root_rep;
    b->root_plain = p->plain;
    b->ncollapsed = p->collapsed;
    return true;
}

/* The caller's model whole (vx__svo_pool.filled): its words and its
 * records copied (on b's threads: at 4096^3 a region holds 19 M records),
 * the root's record appended when no run holds it, as finish_model does. */
typedef struct span_copy {
    uint8_t* dst[4];
    const uint8_t* src[4];
    size_t unit[4], n[4], first[5]; /* first: each array's first chunk */
} span_copy;
static void span_copy_chunk(void* ctx, unsigned thread, uint32_t c) {
    (void)thread;
    const span_copy* s = (const span_copy*)ctx;
    int k = 0;
    while (c >= s->first[k + 1]) k++;
    size_t lo = (size_t)(c - s->first[k]) * REC_CHUNK, hi = lo + REC_CHUNK < s->n[k] ? lo + REC_CHUNK : s->n[k];
    memcpy(s->dst[k] + lo * s->unit[k], s->src[k] + lo * s->unit[k], (hi - lo) * s->unit[k]);
}
static bool filled_ok(const bld* b, const vx__svo_pool* p) {
    uint32_t at = b->attrs;
    return at && !(at & ~(uint32_t)(VX_ATTR_RGBA8 | VX_ATTR_NORMAL | VX_ATTR_MATERIAL)) && b->dag && p->reps && p->runs &&
           p->laid && p->laid_count && p->laid_count < 0xFFFFFFF0u && b->limit == VX__SVO_PTR_MAX && p->nrecs < 0x0FFFFFF0u &&
           p->root_attr <= p->nrecs && (!(at & VX_ATTR_RGBA8) || p->attr_rgba) && (!(at & VX_ATTR_NORMAL) || p->attr_normal) &&
           (!(at & VX_ATTR_MATERIAL) || p->attr_material);
}
static bool filled_bad(bld* b) {
    b->fail = vx_fail(b->err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                      "svo build: filled records need laid-out blocks, rgba/normal/material channels, the DAG, runs, "
                      "near pointers up to %u and the root's record among them or next",
                      VX__SVO_PTR_MAX);
    return false;
}
static bool filled_take(bld* b, const vx__svo_pool* p, vx_svo_model* m) {
    if (!filled_ok(b, p)) return filled_bad(b);
    size_t nr = p->nrecs, na = nr + (p->root_attr == nr);
    bool ok = (m->nodes = (uint32_t*)vx_alloc(b->a, p->laid_count * sizeof *m->nodes)) != NULL;
    if (b->attrs & VX_ATTR_RGBA8) ok = ok && (m->rgba = (uint32_t*)vx_alloc(b->a, na * 4)) != NULL;
    if (b->attrs & VX_ATTR_NORMAL) ok = ok && (m->normal = (uint32_t*)vx_alloc(b->a, na * 4)) != NULL;
    if (b->attrs & VX_ATTR_MATERIAL) ok = ok && (m->material = (uint16_t*)vx_alloc(b->a, na * 2)) != NULL;
    if (!ok) {
        vx_free(b->a, m->nodes), vx_free(b->a, m->rgba), vx_free(b->a, m->normal), vx_free(b->a, m->material);
        m->nodes = NULL, m->rgba = m->normal = NULL, m->material = NULL;
        return oom(b, "the model's words and records");
    }
    /* the four arrays in chunks, one set of jobs (one team of threads) */
    span_copy c = {{(uint8_t*)m->nodes, (uint8_t*)m->rgba, (uint8_t*)m->normal, (uint8_t*)m->material},
                   {(const uint8_t*)p->laid, (const uint8_t*)p->attr_rgba, (const uint8_t*)p->attr_normal,
                    (const uint8_t*)p->attr_material},
                   {4, 4, 4, 2},
                   {p->laid_count, nr, nr, nr},
                   {0}};
    size_t total = 0;
    for (int k = 0; k < 4; k++) {
        if (!c.dst[k]) c.n[k] = 0;
        vx__svo_advise_huge(c.dst[k], c.n[k] * c.unit[k]); /* 2 MB pages: the 4096^3 copies 59 -> 48 ms (H200 host) */
        c.first[k] = total;
        total += (c.n[k] + REC_CHUNK - 1) / REC_CHUNK;
    }
    c.first[4] = total;
    size_t all = p->laid_count + 3 * nr;
    vx_run_jobs(b->threads > 1 && all >= ((size_t)1 << 17) ? b->threads : 1, (uint32_t)total, span_copy_chunk, &c);
    if (na > nr) { /* the root's representative, appended */
        if (m->rgba) m->rgba[nr] = p->root_tuple.rgba;
        if (m->normal) m->normal[nr] = p->root_tuple.normal;
        if (m->material) m->material[nr] = p->root_tuple.material;
    }
    m->node_count = (uint32_t)p->laid_count;
    m->root = (uint32_t)(p->laid_count - 1);
    m->root_attr = p->root_attr;
    m->attr_count = (uint32_t)na;
    return true;
}
/* With check_pool: the caller's filled records against the model built
 * here (the same records in the same order, the same root record). */
static bool filled_check(bld* b, const vx_svo_model* m, const vx__svo_pool* p) {
    if (!filled_ok(b, p)) return filled_bad(b);
    size_t nr = p->nrecs, na = nr + (p->root_attr == nr);
    if (m->attr_count != na || m->root_attr != p->root_attr) {
        b->fail = vx_fail(b->err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                          "svo build: filled records: %zu records, root record %u against the builder's %u and %u", na,
                          p->root_attr, m->attr_count, m->root_attr);
        return false;
    }
    for (size_t k = 0; k < na; k++) {
        bool last = k == nr;
        uint32_t rgba = last ? p->root_tuple.rgba : p->attr_rgba ? p->attr_rgba[k] : 0;
        uint32_t nrm = last ? p->root_tuple.normal : p->attr_normal ? p->attr_normal[k] : 0;
        uint16_t mat = last ? p->root_tuple.material : p->attr_material ? p->attr_material[k] : 0;
        if ((m->rgba && m->rgba[k] != rgba) || (m->normal && m->normal[k] != nrm) || (m->material && m->material[k] != mat)) {
            b->fail = vx_fail(b->err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                              "svo build: filled record %zu of %zu differs from the builder's (rgba %08x, normal %08x, material %u)",
                              k, na, rgba, nrm, mat);
            return false;
        }
    }
    return true;
}

/* Takes the caller's pool (the streaming pass's nodes, in its order): each
 * node checked (masks, children in range, node children earlier nodes), its
 * representative computed and interned as finalize() does, and published
 * to the layout thread when one runs. b's tuples are interned (ids =
 * tuple ids); in the direct case leaf children become their values. */
static bool pool_take(bld* b, const vx__svo_pool* p, bool thread, lay_job* lj, lay_job* lj2, outw* o) {
    size_t cnt = p->count;
    if (cnt >= 0xFFFFFFF0u) {
        b->fail = vx_fail(b->err, VX_ERR_LIMIT, VX_NO_OFFSET, "svo build: node pool exceeds 2^32 words");
        return false;
    }
    uint8_t* isnode = (uint8_t*)vx_calloc(b->a, cnt / 8 + 1, 1);
    b->pool = (uint32_t*)vx_alloc(b->a, (cnt ? cnt : 1) * sizeof *b->pool);
    if (!isnode || !b->pool) {
        vx_free(b->a, isnode);
        return oom(b, "node pool");
    }
    b->cappool = cnt;
    /* the layout's tables and outputs sized for the nodes to come (at most
     * one run and one block per node, at most the pool's words), not grown
     * and rehashed step by step; where an allocation fails they grow as usual */
    if (b->dag && cnt && !o->runh) run_table_presize(b, o, cnt / (N_KIDS + 1) + 2, false);
    if (cnt) {
        vx_grow(b->a, (void**)&o->w, &o->cap, cnt + 2, sizeof *o->w);
        vx_grow(b->a, (void**)&o->ids, &o->capid, cnt, sizeof *o->ids);
    }
    /* the attribute runs laid out by the caller: the records as given (in
     * range; each node's run checked against its children below) */
    bool runs = p->runs && p->reps && b->attrs && b->dag && p->nrecs < 0x0FFFFFF0u && cnt;
    if (runs && !records_take(b, p, o)) {
        vx_free(b->a, isnode);
        return false;
    }
    if (thread && cnt) {
        b->pub = NULL;
        if (!runs) {
            lay_run2(lj, lj2, b, o); /* no thread: the layout runs afterwards */
        } else {
            lay_prep(lj);
            if (lay_thread(lj, b, o, NULL, LAY_BLOCKS)) b->pub = &lj->pub;
        }
    }
    const uint32_t* w = p->words;
    size_t off = 0;
    bool ok = true;
    while (off < cnt) {
        uint32_t hdr = w[off], valid = hdr & 0xFFu, leaf = (hdr >> 8) & 0xFFu;
        unsigned nk = vx__popc8(valid);
        if (valid == 0 || (hdr >> 16) || (leaf & ~valid) || off + N_KIDS + nk > cnt) {
            b->fail = vx_fail(b->err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo build: pool node at word %zu: header 0x%x", off, hdr);
            ok = false;
            break;
        }
        uint32_t ids[8], kids[8];
        unsigned j = 0;
        for (unsigned oc = 0; oc < 8 && ok; oc++) {
            if (!(valid >> oc & 1u)) continue;
            uint32_t ref = w[off + N_KIDS + j];
            if (leaf >> oc & 1u) {
                if (ref >= b->nrec) {
                    b->fail = vx_fail(b->err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo build: pool node at word %zu: tuple %u of %zu", off,
                                      ref, b->nrec);
                    ok = false;
                    break;
                }
                kids[j] = ids[j] = b->direct ? rec_value(b->attrs, &b->recs[ref]) : ref;
            } else {
                if (ref >= off || !(isnode[ref >> 3] >> (ref & 7u) & 1u)) {
                    b->fail = vx_fail(b->err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                                      "svo build: pool node at word %zu: child %u is not an earlier node", off, ref);
                    ok = false;
                    break;
                }
                kids[j] = ref;
                ids[j] = b->pool[ref + N_REP];
            }
            j++;
        }
        if (!ok) break;
        uint32_t rep = 0;
        if (b->attrs && p->reps) { /* computed by the caller */
            rep = w[off + N_REP];
            if (rep >= b->nrec) {
                b->fail = vx_fail(b->err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo build: pool node at word %zu: representative %u of %zu",
                                  off, rep, b->nrec);
                ok = false;
                break;
            }
            if (b->direct) rep = rec_value(b->attrs, &b->recs[rep]);
        } else if (b->attrs) {
            rep = representative(b, ids, nk);
            if (rep == UINT32_MAX && !b->direct) {
                ok = false;
                break;
            }
        }
        uint32_t blk = NO_BLOCK;
        if (runs) { /* the node's run: its records are its children's tuples */
            blk = w[off + N_BLOCK];
            bool same = blk <= p->nrecs && p->nrecs - blk >= nk;
            for (unsigned k = 0; same && k < nk; k++) same = o->ids[blk + k] == ids[k];
            if (!same) {
                b->fail = vx_fail(b->err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                                  "svo build: pool node at word %zu: run at record %u is not its children's", off, blk);
                ok = false;
                break;
            }
        }
        uint32_t* n = b->pool + off;
        n[N_HDR] = hdr;
        n[N_REP] = rep;
        n[N_BLOCK] = blk;
        memcpy(n + N_KIDS, kids, nk * sizeof *kids);
        isnode[off >> 3] |= (uint8_t)(1u << (off & 7u));
        off += N_KIDS + nk;
        b->npool = off;
        b->nnodes++;
        if (b->pub) vx__svo_gate_publish(b->pub, off);
    }
    if (ok) {
        b->have_root = true;
        b->root_is_leaf = p->root_leaf;
        b->root_plain = p->plain;
        b->ncollapsed = p->collapsed;
        if (p->root_leaf) {
            if (p->root >= b->nrec || cnt) {
                b->fail = vx_fail(b->err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo build: pool of %zu words with a leaf root %u", cnt,
                                  p->root);
                ok = false;
            } else {
                b->root = b->direct ? rec_value(b->attrs, &b->recs[p->root]) : p->root;
            }
        } else if (p->root >= cnt || !(isnode[p->root >> 3] >> (p->root & 7u) & 1u)) {
            b->fail = vx_fail(b->err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo build: pool root %u is not a node", p->root);
            ok = false;
        } else {
            b->root = p->root;
        }
    }
    vx_free(b->a, isnode);
    return ok;
}

/* The builder's own pool against the caller's: header and children of each
 * node, the root and the counts; the first difference fails, named with the
 * node's height (1: every child a leaf). */
static bool pool_check(bld* b, const vx__svo_pool* p) {
    uint8_t* ht = (uint8_t*)vx_calloc(b->a, b->npool ? b->npool : 1, 1);
    if (!ht) return oom(b, "pool check");
    size_t off = 0;
    const char* what = NULL;
    while (off < b->npool) {
        const uint32_t* n = b->pool + off;
        uint32_t valid = n[N_HDR] & 0xFFu, leaf = (n[N_HDR] >> 8) & 0xFFu;
        unsigned nk = vx__popc8(valid), h = 1;
        for (unsigned j = 0, oc = 0; oc < 8; oc++) {
            if (!(valid >> oc & 1u)) continue;
            if (!(leaf >> oc & 1u) && ht[n[N_KIDS + j]] + 1u > h) h = ht[n[N_KIDS + j]] + 1u;
            j++;
        }
        ht[off] = (uint8_t)h;
        if (off + N_KIDS + nk > p->count) what = "missing";
        else if (p->words[off] != n[N_HDR]) what = "header";
        else if (p->reps && b->attrs &&
                 (p->words[off + N_REP] >= b->nrec ||
                  (b->direct ? rec_value(b->attrs, &b->recs[p->words[off + N_REP]]) : p->words[off + N_REP]) != n[N_REP]))
            what = "representative";
        else {
            for (unsigned j = 0, oc = 0; oc < 8 && !what; oc++) {
                if (!(valid >> oc & 1u)) continue;
                uint32_t mine = n[N_KIDS + j], theirs = p->words[off + N_KIDS + j];
                if ((leaf >> oc & 1u) && b->direct) theirs = theirs < b->nrec ? rec_value(b->attrs, &b->recs[theirs]) : ~mine;
                if (mine != theirs) what = (leaf >> oc & 1u) ? "leaf child's tuple" : "child node id";
                j++;
            }
        }
        if (what) {
            b->fail = vx_fail(b->err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                              "svo build: the given pool differs from the builder's at node %zu (height %u): %s", off, h, what);
            vx_free(b->a, ht);
            return false;
        }
        off += N_KIDS + nk;
    }
    vx_free(b->a, ht);
    uint32_t theirs = p->root; /* a leaf root: a tuple id, the builder's a value when direct */
    if (p->root_leaf && b->direct) theirs = p->root < b->nrec ? rec_value(b->attrs, &b->recs[p->root]) : ~b->root;
    if (p->count != b->npool) what = "pool size";
    else if (p->root_leaf != b->root_is_leaf || theirs != b->root) what = "root";
    else if (p->plain != b->root_plain || p->collapsed != b->ncollapsed) what = "node counts";
    if (what) {
        b->fail = vx_fail(b->err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo build: the given pool differs from the builder's: %s", what);
        return false;
    }
    return true;
}

/* The caller's attribute runs (vx__svo_pool.runs) against the builder's
 * own layout: the same records, and each node's run at the same first
 * record (the last word of the node's block, m's words). */
static bool runs_check(bld* b, const outw* o, const vx_svo_model* m, const vx__svo_pool* p) {
    if (!b->attrs || !b->dag || !p->reps) return true;
    const char* what = NULL;
    size_t at = 0;
    if (o->nid < p->nrecs || o->nid > p->nrecs + 1) what = "record count";
    for (size_t k = 0; !what && k < p->nrecs; k++) {
        uint32_t id = p->recs[k], mine = o->ids[k];
        if (id >= b->nrec || (b->direct ? rec_value(b->attrs, &b->recs[id]) : id) != mine) what = "record", at = k;
    }
    for (size_t off = 0; !what && off < b->npool && off < p->count;) {
        const uint32_t* n = b->pool + off;
        uint32_t valid = n[N_HDR] & 0xFFu, leaf = (n[N_HDR] >> 8) & 0xFFu;
        uint32_t blk = n[N_BLOCK], nn = vx__popc8(valid & ~leaf);
        if (blk == NO_BLOCK || (size_t)blk + nn >= m->node_count || m->nodes[blk + nn] != p->words[off + N_BLOCK])
            what = "node's run", at = off;
        off += N_KIDS + vx__popc8(valid);
    }
    if (what) {
        b->fail = vx_fail(b->err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo build: the given attribute runs differ from the builder's: %s at %zu",
                          what, at);
        return false;
    }
    return true;
}

/* ---- entry point ---------------------------------------------------------------------------- */

static const char* attr_name(uint32_t bit) {
    switch (bit) {
    case VX_ATTR_PALETTE: return "palette";
    case VX_ATTR_RGBA8: return "rgba";
    case VX_ATTR_NORMAL: return "normal";
    case VX_ATTR_MATERIAL: return "material";
    default: return "density";
    }
}

static void bld_free(bld* b) {
    vx_free(b->a, b->recs);
    vx_free(b->a, b->rhash);
    vx_free(b->a, b->pool);
    vx_free(b->a, b->nhash);
}

static unsigned bits_for(uint64_t maxval) {
    unsigned k = 0;
    while (k < 64 && (maxval >> k) != 0) k++;
    return k;
}

static vx_result build(const vx_svo_build_desc* desc, const vx_svo_voxels* in, const vx__svo_interned* pre,
                       vx_svo_model* out, vx_svo_build_stats* stats, vx_error* err);

/* The model's check (svo.h vx_svo_model_check), as the reader sets it for a
 * model it read: what this builder makes is valid by construction, so a
 * writer need not validate it, and with the DAG and no far limit its words
 * are what the structural form's reconstruction (3.5's layout over the pool
 * in completion order) gives back from its symbols: the writer codes it
 * without the rebuild that proves the form (docs/PERFORMANCE.md issue 18,
 * eleventh step). Not for a tree the caller gave (a GPU build's pool or
 * blocks): those are taken as given, not made here. A model changed after
 * the build no longer matches the digest and is validated as any other. */
static void stamp_check(const bld* b, vx_svo_model* m, bool given_tree) {
    memset(&m->check, 0, sizeof m->check);
    if (given_tree) return;
    vx_svo_model_cell_box(m, m->check.min, m->check.max);
    if (m->root < m->node_count && b->dag && b->limit == VX__SVO_PTR_MAX) m->check.structural = 1u << 16 | VX__SVO_PTR_MAX;
    m->check.digest = vx_svo_model_digest(m);
}

vx_result vx_svo_build_model(const vx_svo_build_desc* desc, const vx_svo_voxels* in, vx_svo_model* out,
                             vx_svo_build_stats* stats, vx_error* err) {
    return build(desc, in, NULL, out, stats, err);
}

vx_result vx__svo_build_interned(const vx_svo_build_desc* desc, const vx_svo_voxels* in, const vx__svo_interned* pre,
                                 vx_svo_model* out, vx_svo_build_stats* stats, vx_error* err) {
    if (!in || !pre) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo build: null argument");
    bool given = pre->pool && pre->pool->reps && !pre->check_pool; /* the tree given: entries optional */
    bool filled = given && pre->pool->filled; /* and its records: no tuple read */
    if (!in->attrs || in->level || (in->count && ((!pre->rec && !given) || (pre->count && !pre->tab && !filled))))
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo build: interned entries need attrs, ids and no tiles");
    return build(desc, in, pre, out, stats, err);
}

/* pre: the tuples interned by the caller (vx__svo_build_interned), else NULL. */
/* The caller's distinct tuples as b's records (masked to its channels). */
typedef struct tab_copy {
    bld* b;
    const vx__svo_rec* tab;
} tab_copy;
static void tab_copy_range(void* ctx, size_t lo, size_t hi) {
    tab_copy* t = (tab_copy*)ctx;
    for (size_t j = lo; j < hi; j++) t->b->recs[j] = rec_masked(&t->tab[j], t->b->attrs);
}

static vx_result build(const vx_svo_build_desc* desc, const vx_svo_voxels* in, const vx__svo_interned* pre,
                       vx_svo_model* out, vx_svo_build_stats* stats, vx_error* err) {
    vx_svo_build_desc d;
    if (desc) d = *desc;
    else memset(&d, 0, sizeof d);
    if (!in || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo build: null argument");
    uint32_t max_depth = d.max_depth ? d.max_depth : VX_SVO_MAX_DEPTH;
    if (max_depth > VX_SVO_MAX_DEPTH)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo build: max_depth %u above %u", max_depth, VX_SVO_MAX_DEPTH);
    uint32_t mx = 0;
    for (int i = 0; i < 3; i++) {
        if (in->size[i] < 1 || in->size[i] > (1u << VX_SVO_MAX_DEPTH))
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo build: size[%d] = %u outside 1..2^21", i, in->size[i]);
        if (in->size[i] > mx) mx = in->size[i];
    }
    uint32_t depth = 0;
    while ((1u << depth) < mx) depth++;
    if (depth > max_depth)
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "svo build: size %u needs depth %u, max_depth is %u", mx, depth,
                       max_depth);
    if (in->attrs & ~(uint32_t)VX_ATTR_ALL)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo build: unknown attribute bits 0x%x", in->attrs);
    const void* chans[5] = {in->palette, in->rgba, in->normal, in->material, in->density};
    for (unsigned c = 0; c < 5; c++) {
        bool want = in->attrs >> c & 1u && !pre; /* interned: the tuples come in pre */
        if (want && !chans[c] && in->count)
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo build: attrs names %s but the array is NULL",
                           attr_name(1u << c));
        if (!want && chans[c])
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo build: %s array given but not named in attrs",
                           attr_name(1u << c));
    }
    /* a tree given with its representatives (a GPU build) stands for its
     * entries: they may be left out (count only; keys and ids NULL) */
    bool bare = pre && pre->pool && pre->pool->reps && !pre->check_pool && !in->keys;
    if (in->count && !in->keys && !bare) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo build: keys is NULL");

    bld b;
    memset(&b, 0, sizeof b);
    b.a = d.alloc;
    b.attrs = in->attrs;
    b.collapse = !d.no_collapse;
    b.dag = !d.no_dag;
    b.depth = depth;
    b.limit = vx__svo_far_limit(&d.testing);
    b.err = err;
    b.direct = in->attrs && (in->attrs & (in->attrs - 1)) == 0;
    b.vattr = in->attrs;
    b.threads = pre ? pre->threads : 0;
    vx_svo_build_stats st;
    memset(&st, 0, sizeof st);
    st.input_voxels = in->count;

    vx_svo_model m;
    memset(&m, 0, sizeof m);
    m.size[0] = in->size[0], m.size[1] = in->size[1], m.size[2] = in->size[2];
    m.depth = depth;
    m.attrs = in->attrs;
    m.root = VX_SVO_ROOT_EMPTY;

    size_t n = in->count;
    uint64_t* packed = NULL;
    uint64_t* tmp = NULL;
    ent* ents = NULL;
    ent* etmp = NULL;
    size_t* cnt = NULL;
    outw o;
    memset(&o, 0, sizeof o);
    lay_job lj, lj2; /* the layout thread, or the layout's runs and blocks stages (pool_take) */
    lj.started = lj2.started = lj.gates = lj2.gates = false;
    vx_result res = VX_OK;

    if (n == 0) goto finish_empty;
    /* the whole model given (a GPU build with its records filled): copied
     * as it is; the entries are not read */
    if (pre && pre->pool && pre->pool->filled && !pre->check_pool) {
        if (!filled_take(&b, pre->pool, &m)) { res = b.fail; goto done; }
        st.voxels = n;
        st.desc_plain = pre->pool->plain;
        st.desc_collapsed = pre->pool->collapsed;
        st.far_pointers = pre->pool->laid_far;
        m.voxel_count = n;
        b.laid_given = true;
        b.laid_desc = pre->pool->laid_desc;
        goto finish;
    }
    packed = bare ? NULL : vx_mul_size(n, sizeof *packed, &(size_t){0}) ? (uint64_t*)vx_alloc(b.a, n * sizeof *packed) : NULL;
    if (!packed && !bare) {
        res = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo build: cannot allocate %zu entries", n);
        goto done;
    }
    /* pass 1: check entries, intern records (into packed[i] for now) */
    {
        bool sorted = true, strict = true;
        uint64_t prev = 0;
        rec last;
        uint32_t last_id = UINT32_MAX;
        memset(&last, 0, sizeof last);
        if (!b.attrs) {
            rec z;
            memset(&z, 0, sizeof z);
            rec_intern(&b, &z);
            if (b.fail) { res = b.fail; goto done; }
        }
        /* with the tree and its representatives given (a GPU build), the
         * tuples are distinct and every id is given: tuple j is record j, no
         * table needed */
        bool given = pre && pre->pool && pre->pool->reps && !pre->check_pool;
        if (given) {
            if (!vx_grow(b.a, (void**)&b.recs, &b.caprec, pre->count ? pre->count : 1, sizeof(rec))) {
                res = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo build: cannot allocate %zu records", pre->count);
                goto done;
            }
            tab_copy tc = {&b, pre->tab};
            par_for(&b, pre->count, tab_copy_range, &tc);
            b.nrec = pre->count;
        }
        /* interned by the caller: tuple j gets id j, once; the tables sized
         * for them and the nodes to come (a surface has about n / 4 nodes, as
         * many new representatives at most), not grown and rehashed step by
         * step (at 4096^3 a region holds 19 M tuples) */
        if (pre && !given) {
            size_t want = pre->count + n / 4, cap = 1024, ncap = 4096;
            while (cap < 2 * want + 2 && cap < ((size_t)1 << 40)) cap *= 2;
            while (ncap < 2 * (n / 4) + 2 && ncap < ((size_t)1 << 40)) ncap *= 2;
            b.rhash = (uint32_t*)vx_calloc(b.a, cap, sizeof *b.rhash);
            b.nhash = b.dag ? (uint32_t*)vx_calloc(b.a, ncap, sizeof *b.nhash) : NULL;
            if (b.rhash && b.nrec == 0) b.rhcap = cap; /* else (cannot happen: attrs != 0) it grows as usual */
            else vx_free(b.a, b.rhash), b.rhash = NULL;
            if (b.nhash) b.nhcap = ncap;
            vx_grow(b.a, (void**)&b.recs, &b.caprec, want, sizeof(rec)); /* a hint: on failure it grows later */
        }
        /* interned by the caller: tuple j gets id j, once (many on several threads) */
        unsigned ith = pre && pre->threads > 1 && pre->count >= ((size_t)1 << 18) ? pre->threads : 1;
        if (ith > 1 && !intern_pre(&b, pre, ith) && b.fail) { res = b.fail; goto done; }
        for (size_t j = b.nrec; pre && j < pre->count; j++) {
            rec r = rec_masked(&pre->tab[j], b.attrs);
            uint32_t id = rec_intern(&b, &r);
            if (id == UINT32_MAX) { res = b.fail; goto done; }
            if (id != j) {
                res = vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo build: interned tuples %u and %zu are equal", id, j);
                goto done;
            }
        }
        bool full[3];
        for (int a = 0; a < 3; a++) full[a] = in->size[a] == (1u << depth);
        unsigned kb0 = 3 * depth < 63 ? 3 * depth : 63;
        for (size_t i = 0; i < n && !bare; i++) {
            uint64_t k = in->keys[i];
            uint32_t L = in->level ? in->level[i] : 0;
            if (L > depth) {
                res = vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo build: entry %zu: tile level %u above depth %u", i, L,
                              depth);
                goto done;
            }
            uint64_t side = (uint64_t)1 << L;
            /* axes whose size is the whole cube only need the key-range test */
            uint32_t x = full[0] ? 0 : vx__compact3(k), y = full[1] ? 0 : vx__compact3(k >> 1), z = full[2] ? 0 : vx__compact3(k >> 2);
            if ((k >> kb0) || x + side > in->size[0] || y + side > in->size[1] || z + side > in->size[2]) {
                x = vx__compact3(k), y = vx__compact3(k >> 1), z = vx__compact3(k >> 2);
                if (L == 0)
                    res = vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                                  "svo build: entry %zu: cell (%u, %u, %u) outside the model size %ux%ux%u", i, x, y, z,
                                  in->size[0], in->size[1], in->size[2]);
                else
                    res = vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                                  "svo build: entry %zu: tile of 2^%u cells at (%u, %u, %u) outside the model size %ux%ux%u", i,
                                  L, x, y, z, in->size[0], in->size[1], in->size[2]);
                goto done;
            }
            if (L && (k & (((uint64_t)1 << (3 * L)) - 1))) {
                res = vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                              "svo build: entry %zu: tile of 2^%u cells at (%u, %u, %u) is not aligned to its size", i, L, x, y, z);
                goto done;
            }
            sorted = sorted && k >= prev;
            strict = strict && (i == 0 || k > prev);
            prev = k;
            uint32_t id = 0;
            if (pre) {
                id = pre->rec[i];
                if (id >= pre->count) {
                    res = vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo build: entry %zu: tuple %u of %zu", i, id,
                                  pre->count);
                    goto done;
                }
            } else if (b.attrs) {
                rec r;
                memset(&r, 0, sizeof r);
                if (in->palette) r.palette = in->palette[i];
                if (in->rgba) r.rgba = in->rgba[i];
                if (in->normal) r.normal = in->normal[i];
                if (in->material) r.material = in->material[i];
                if (in->density) r.density = in->density[i];
                if (last_id != UINT32_MAX && memcmp(&r, &last, sizeof r) == 0) id = last_id;
                else {
                    id = rec_intern(&b, &r);
                    if (id == UINT32_MAX) { res = b.fail; goto done; }
                    last = r;
                    last_id = id;
                }
            }
            packed[i] = id;
            if (d.progress.func && (i & 0xFFFFFu) == 0 && !vx_progress_report(&d.progress, "check", i, n)) {
                res = vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "cancelled");
                goto done;
            }
        }
        /* the tree built by the caller: representatives and layout only */
        if (pre && pre->pool && !pre->check_pool) {
            if (!strict) {
                res = vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo build: a given pool needs strictly increasing keys");
                goto done;
            }
            st.voxels = n;
            if (pre->pool->laid) {
                if (!laid_take(&b, pre->pool, &o)) { res = b.fail; goto done; }
                goto built;
            }
            if (!pool_take(&b, pre->pool, pre->layout_thread, &lj, &lj2, &o)) { res = b.fail; goto done; }
            lay_join(&lj, &b, true); /* the runs stage first: the blocks stage follows it */
            lay_join(&lj2, &b, true);
            if (b.fail) { res = b.fail; goto done; }
            goto built;
        }
        /* pass 2: pack (key, level, record) and sort by the key bits only */
        unsigned ab = bits_for(b.nrec ? b.nrec - 1 : 0), lb = in->level ? 5 : 0, kb = 3 * depth;
        if (kb + ab + lb <= 64) {
            unsigned s = ab + lb;
            uint64_t kdiff = 0, k0 = in->keys[0];
            for (size_t i = 0; i < n; i++) {
                uint64_t L = in->level ? in->level[i] : 0;
                kdiff |= in->keys[i] ^ k0;
                packed[i] = (kb ? in->keys[i] << s : 0) | (L << ab) | packed[i];
            }
            if (!sorted && kb) {
                tmp = (uint64_t*)vx_alloc(b.a, n * sizeof *tmp);
                cnt = (size_t*)vx_alloc(b.a, sizeof(size_t) * 2048 * 8);
                if (!tmp || !cnt) {
                    res = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo build: cannot allocate the sort buffer");
                    goto done;
                }
                uint64_t* r = sort_packed(packed, tmp, n, s, kdiff, cnt);
                if (r != packed) {
                    uint64_t* t = packed;
                    packed = r;
                    tmp = t;
                }
                vx_free(b.a, tmp);
                tmp = NULL;
            }
        } else {
            ents = (ent*)vx_calloc(b.a, n, sizeof *ents);
            if (!ents) {
                res = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo build: cannot allocate %zu entries", n);
                goto done;
            }
            for (size_t i = 0; i < n; i++) {
                ents[i].key = in->keys[i];
                ents[i].aid = (uint32_t)packed[i];
                ents[i].level = in->level ? in->level[i] : 0;
            }
            vx_free(b.a, packed);
            packed = NULL;
            if (!sorted) {
                etmp = (ent*)vx_alloc(b.a, n * sizeof *etmp);
                cnt = (size_t*)vx_alloc(b.a, sizeof(size_t) * RADIX_SIZE * 8);
                if (!etmp || !cnt) {
                    res = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo build: cannot allocate the sort buffer");
                    goto done;
                }
                ent* r = radix_ent(ents, etmp, n, kb, cnt);
                if (r != ents) {
                    ent* t = ents;
                    ents = r;
                    etmp = t;
                }
                vx_free(b.a, etmp);
                etmp = NULL;
            }
        }
        /* pass 3: stream bottom-up (the layout following on a second thread
         * where the caller has a core to spare; else it runs afterwards) */
        if (pre && pre->layout_thread && n >= ((size_t)1 << 16)) lay_start(&lj, &b, &o, n);
        unsigned s = ab + lb;
        uint64_t amask = ((uint64_t)1 << ab) - 1;
        uint64_t lastkey = 0, covered_end = 0;
        bool first = true;
        for (size_t i = 0; i < n; i++) {
            uint64_t k;
            uint32_t L, aid;
            if (packed) {
                uint64_t v = packed[i];
                k = kb ? v >> s : 0;
                L = (uint32_t)((v >> ab) & (lb ? 31u : 0u));
                aid = (uint32_t)(v & amask);
            } else {
                k = ents[i].key;
                L = ents[i].level;
                aid = ents[i].aid;
            }
            if (i + 1 < n) {
                uint64_t k2;
                uint32_t L2;
                if (packed) {
                    k2 = kb ? packed[i + 1] >> s : 0;
                    L2 = (uint32_t)((packed[i + 1] >> ab) & (lb ? 31u : 0u));
                } else {
                    k2 = ents[i + 1].key;
                    L2 = ents[i + 1].level;
                }
                if (k2 == k) {
                    if (L2 == L) continue; /* duplicate: the later entry wins */
                    res = vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                                  "svo build: a tile of 2^%u cells and one of 2^%u cells start at the same cell (%u, %u, %u)",
                                  L, L2, vx__compact3(k), vx__compact3(k >> 1), vx__compact3(k >> 2));
                    goto done;
                }
            }
            if (!first && k < covered_end) {
                res = vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                              "svo build: entry at cell (%u, %u, %u) lies inside an earlier tile", vx__compact3(k),
                              vx__compact3(k >> 1), vx__compact3(k >> 2));
                goto done;
            }
            covered_end = k + ((uint64_t)1 << (3 * L));
            st.voxels += (uint64_t)1 << (3 * L);
            if (!first) {
                uint64_t diff = k ^ lastkey;
                unsigned top = (63u - (unsigned)__builtin_clzll(diff)) / 3u;
                if (top > depth) top = depth;
                for (unsigned l = 1; l <= top; l++)
                    if (b.lv[l].active && !finalize(&b, l)) { res = b.fail; goto done; }
            }
            first = false;
            lastkey = k;
            if (b.direct) aid = rec_value(b.attrs, &b.recs[aid]);
            if (L == depth) push_child(&b, depth + 1, 0, true, aid, aid, 0);
            else push_child(&b, L + 1, k >> (3 * L), true, aid, aid, 0);
            if (d.progress.func && (i & 0xFFFFFu) == 0 && !vx_progress_report(&d.progress, "build", i, n)) {
                res = vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "cancelled");
                goto done;
            }
        }
        for (unsigned l = 1; l <= depth; l++)
            if (b.lv[l].active && !finalize(&b, l)) { res = b.fail; goto done; }
        lay_join(&lj, &b, true);
        if (b.fail) { res = b.fail; goto done; }
        if (pre && pre->pool && !pool_check(&b, pre->pool)) { res = b.fail; goto done; }
    }
built:
    vx_free(b.a, packed);
    packed = NULL;
    vx_free(b.a, ents);
    ents = NULL;
    vx_free(b.a, b.nhash);
    b.nhash = NULL;
    vx_free(b.a, b.rhash);
    b.rhash = NULL;

    if (!b.have_root) goto finish_empty; /* cannot happen with n > 0 */
    st.desc_plain = b.root_plain;
    st.desc_collapsed = b.ncollapsed;
    if (!finish_model(&b, &o, &m, false)) { res = b.fail; goto done; }
    if (pre && pre->pool && pre->check_pool && pre->pool->laid &&
        (m.node_count != pre->pool->laid_count || memcmp(m.nodes, pre->pool->laid, (size_t)m.node_count * 4) ||
         o.far != pre->pool->laid_far)) {
        size_t at = 0;
        while (at < m.node_count && at < pre->pool->laid_count && m.nodes[at] == pre->pool->laid[at]) at++;
        res = b.fail = vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                               "svo build: the given blocks differ from the builder's at word %zu (%u words against %zu, far %llu against %llu)",
                               at, m.node_count, pre->pool->laid_count, (unsigned long long)o.far,
                               (unsigned long long)pre->pool->laid_far);
        vx_svo_model_free(b.a, &m);
        goto done;
    }
    if (pre && pre->pool && pre->check_pool && pre->pool->filled && !filled_check(&b, &m, pre->pool)) {
        vx_svo_model_free(b.a, &m);
        res = b.fail;
        goto done;
    }
    if (pre && pre->pool && pre->check_pool && pre->pool->runs && !runs_check(&b, &o, &m, pre->pool)) {
        vx_svo_model_free(b.a, &m);
        res = b.fail;
        goto done;
    }
    st.far_pointers = o.far;
    m.voxel_count = st.voxels;
    goto finish;

finish_empty:
    m.root = VX_SVO_ROOT_EMPTY;
    if (!finish_model(&b, &o, &m, true)) { res = b.fail; goto done; }
finish:
    {
        /* descriptor words written: one per non-leaf child of a stored node, plus the root */
        uint64_t ndesc = 0;
        if (b.laid_given) {
            ndesc = b.laid_desc;
        } else if (m.root != VX_SVO_ROOT_EMPTY && m.root != VX_SVO_ROOT_LEAF) {
            size_t off = 0;
            ndesc = 1;
            while (off < b.npool) {
                const uint32_t* nd = b.pool + off;
                if (nd[N_BLOCK] != NO_BLOCK) ndesc += vx__popc8((nd[N_HDR] & 0xFFu) & ~(nd[N_HDR] >> 8));
                off += N_KIDS + vx__popc8(nd[N_HDR]);
            }
        }
        /* with the DAG off this equals desc_collapsed: each node has one parent */
        st.desc_dag = ndesc;
        if (pre && pre->pool && pre->check_pool && pre->pool->laid && ndesc != pre->pool->laid_desc) {
            res = vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo build: the given blocks' descriptors: %llu against %llu",
                          (unsigned long long)pre->pool->laid_desc, (unsigned long long)ndesc);
            vx_svo_model_free(b.a, &m);
            goto done;
        }
        st.attr_records = m.attr_count;
        unsigned rb = 0;
        if (b.attrs & VX_ATTR_PALETTE) rb += 1;
        if (b.attrs & VX_ATTR_RGBA8) rb += 4;
        if (b.attrs & VX_ATTR_NORMAL) rb += 4;
        if (b.attrs & VX_ATTR_MATERIAL) rb += 2;
        if (b.attrs & VX_ATTR_DENSITY) rb += 4;
        st.bytes = (uint64_t)m.node_count * 4 + (uint64_t)m.attr_count * rb;
    }
    stamp_check(&b, &m, pre && pre->pool);
    *out = m;
    if (stats) *stats = st;
    res = VX_OK;
done:
    lay_join(&lj, &b, false); /* an early exit: stop the layout before freeing what it reads */
    lay_join(&lj2, &b, false);
    lay_free(&lj);
    lay_free(&lj2);
    vx_free(b.a, packed);
    vx_free(b.a, tmp);
    vx_free(b.a, ents);
    vx_free(b.a, etmp);
    vx_free(b.a, cnt);
    vx_free(b.a, o.w);
    vx_free(b.a, o.ids);
    vx_free(b.a, o.runh);
    vx_free(b.a, o.lone);
    vx_free(b.a, o.uni);
    bld_free(&b);
    return res;
}

/* ---- reconstruction from depth-first symbols (the .svo reader) ------------------------------- */

/* A completed node as its back-references need it, in one 16-byte record:
 * a back-reference names a node anywhere before, a cache miss, and these
 * were three (the id, the pool's representative, the height). */
typedef struct unp_node {
    uint32_t id, rep; /* pool id (with unp.fused: the node's block, NO_BLOCK for none), representative record */
    uint64_t xt;      /* bits 0-47 the height and, with want_xt, the extent (xt_pack); 48-63 valid | leaf << 8 */
} unp_node;

/* With unp.fused, a completed node waiting for its block. The layout
 * follows the reconstruction in three stages, each in completion order, so
 * that what each stage loads from the large tables was fetched by an
 * earlier one: at the push the run's hash and the run table's slot (the
 * lead run_prefetch had over the pool); UNP_MID nodes later, where the run
 * is to be found, the records of the stored run that slot names (the
 * comparison's load); UNP_RUN nodes later the run itself (its records'
 * index `a`: run_take / run_intern) and, for a lone block, the lone-block
 * table's slot of `a`; UNP_AHEAD nodes later the block (lay_block). On the
 * 4096^3 helmet the lone table's slot was half of lay_block's samples and
 * the records' comparison most of run_intern_exact's. A node's children
 * are always laid out before it (they are completed first), and the runs
 * and the blocks each keep the pool's order: the words are the one pass's. */
enum { UNP_RING = 16, UNP_MID = 4, UNP_RUN = 8, UNP_AHEAD = 11 };
typedef struct unp_pend {
    uint32_t hdr, at; /* valid | leaf << 8; the node's index in done[] */
    unsigned nk, nn;  /* children; non-leaf children */
    uint32_t ids[8];  /* the run: each child's record (a leaf) or representative */
    uint32_t kid[8];  /* the non-leaf children's indices in done[] */
    uint32_t cd[8];   /* and their masks */
    uint64_t h;       /* the run's hash where it is looked up (run_take's hp) */
    uint32_t a;       /* the run's first record (the run stage's result) */
    bool find;        /* the run is looked up where it may be found (runs byte 2, or no runs stream) */
} unp_pend;

typedef struct unp {
    bld* b;
    const vx__svo_src* src;
    unp_node* done; /* the completed nodes in completion order: back-references count from the end */
    size_t ndone, capdone;
    uint64_t words, max_words;
    vx_error* err;
    /* with vx__svo_unpack_desc.tree: extents in done[].xt; those of height 7 and above here */
    bool want_xt;
    bool ref_index; /* vx__svo_unpack_desc.ref_index */
    bool ref_pf;    /* ref_index with the split streams: the references ahead fetched (ref_ahead) */
    size_t la[3];   /* each reference stream's lookahead position (stream 7 + i) */
    vx__svo_extent* big;
    size_t nbig, capbig;
    /* The layout fused into the reconstruction (no layout thread): each
     * completed node's block written from its children's (done[].id) a few
     * nodes after its completion, in completion order, which is the pool's
     * order, with layout_nodes' code (lay_block, run_take / run_intern), so
     * the words are the pool path's; the pool itself (a quarter of a large
     * model's memory, written once and read twice) is never made. */
    bool fused;
    bld lb; /* b's settings for the layout, with its own failure (as a layout thread's) */
    vx_error lerr;
    outw* o;
    unp_pend ring[UNP_RING];
    size_t rin, rmid, rrun, rout; /* nodes pushed, their records fetched, their runs taken, laid out */
    size_t pfr;        /* the runs stream's byte of the next node pushed */
    bool pf_on;        /* runs are looked up (the DAG and attributes): hash and prefetch at the push */
    bool lay_dead;     /* the layout failed: the reconstruction goes on, its own error first (as with a layout thread) */
    bool leaves_failed; /* unp_leaves failed (out of memory) */
} unp;

/* The reader's check of the rebuilt tree (vx__svo_check_rebuilt) without a
 * walk over its words: what the validation of FORMAT.md 3.1 finds there,
 * the reconstruction either guarantees or computes per node as it goes.
 *
 * Rules 3 and 4 (per descriptor, at every level it is reached at: valid !=
 * 0, leaf within valid, pointers backwards and in range, far slots, blocks
 * before their descriptor, records in range; every word has one role and
 * is reachable) hold by construction, for any symbol stream: a zero mask is
 * refused when decoded and a leaf mask is decoded within its valid mask;
 * the layout (layout_nodes) writes each block after the blocks of the
 * node's children (the pool is in completion order and a reference names
 * a completed node), a near pointer only where the distance is at most the
 * limit (<= 2^15 - 1), else a far slot appended just before the block
 * (its pointer is at most 16) holding an earlier position; a record index
 * is the start of a run of at least popcount(valid) records it stored; a
 * lone block reused is the one word of the same index at a position the
 * limit can still reach; every word it appends is a far slot, descriptor or
 * index of the block of a pool node, and every pool node but the root is
 * the child of a later one (a node is completed only as a new child, and
 * the last completed is the root), so all are reachable and each word has
 * the one role it was written with (a block shared between nodes is read
 * in the same shape: only lone blocks are shared, by nodes without
 * non-leaf children). What remains of rule 3 is the level: a node reached
 * at level l must have no non-leaf child at level 1, i.e. its height h (1
 * when its children are all leaves, else 1 + their largest) must be <= l.
 * A new child is read at l - 1, so by induction its height is <= l - 1;
 * a back-reference can name a node of any height: checked here (the
 * builder shares equal nodes across levels, e.g. one of eight leaves at
 * levels 1 and 2, so the levels need not be equal). Rule 5 (cells inside
 * the size, as many as declared) needs the root's extent: a node's shape
 * placed one level higher is the same with every cube doubled, so each
 * node keeps its cells and box at its own height and a parent scales its
 * children's into its own; the root's is scaled to the depth. Rules 1 and
 * 2 (the head) are checked on the model as usual. tests/svo/test_svo_pack.c
 * (test_rebuilt_checks) reads mutated streams and runs the full validation
 * on every model read. */
typedef struct xt_node {
    unsigned h;
    uint64_t cells;
    uint32_t mn[3], mx[3];
} xt_node;
/* done[].xt, bits 0-47: heights up to XT_SMALL with the extent in the
 * word (h in bits 0-2, cells - 1 in 3-17: cells <= 8^5; the box's min in
 * 18-32 and max - 1 in 33-47, 5 bits each: 0..32), greater ones as 7 in
 * bits 0-2, h in 3-7 and the index of their extent in big (8-47). Bits
 * 48-63 hold the node's masks, which its parents' descriptors need (the
 * fused layout): one 16-byte record still. */
enum { XT_SMALL = 5 };
#define XT_BITS 0x0000FFFFFFFFFFFFull
static inline unsigned xt_height(uint64_t code) {
    unsigned t = (unsigned)(code & 7u);
    return t == 7u ? (unsigned)(code >> 3 & 31u) : t;
}

static bool xt_pack(unp* u, const xt_node* x, uint64_t* code) {
    if (x->h <= XT_SMALL) {
        *code = x->h | (x->cells - 1) << 3 | (uint64_t)x->mn[0] << 18 | (uint64_t)x->mn[1] << 23 | (uint64_t)x->mn[2] << 28 |
                (uint64_t)(x->mx[0] - 1) << 33 | (uint64_t)(x->mx[1] - 1) << 38 | (uint64_t)(x->mx[2] - 1) << 43;
        return true;
    }
    if (!vx_grow(u->b->a, (void**)&u->big, &u->capbig, u->nbig + 1, sizeof *u->big)) return oom(u->b, "node extents");
    vx__svo_extent* e = &u->big[u->nbig];
    e->cells = x->cells;
    memcpy(e->min, x->mn, sizeof e->min);
    memcpy(e->max, x->mx, sizeof e->max);
    *code = 7u | (uint64_t)x->h << 3 | (uint64_t)u->nbig++ << 8;
    return true;
}

static void xt_unpack(const unp* u, uint64_t code, xt_node* x) {
    x->h = xt_height(code);
    if (x->h <= XT_SMALL) {
        x->cells = (code >> 3 & 0x7FFFu) + 1;
        for (int i = 0; i < 3; i++) {
            x->mn[i] = (uint32_t)(code >> (18 + 5 * i)) & 31u;
            x->mx[i] = ((uint32_t)(code >> (33 + 5 * i)) & 31u) + 1;
        }
        return;
    }
    const vx__svo_extent* e = &u->big[(code & XT_BITS) >> 8];
    x->cells = e->cells;
    memcpy(x->mn, e->min, sizeof x->mn);
    memcpy(x->mx, e->max, sizeof x->mx);
}

static bool unp_fail(unp* u, vx_result r) {
    if (u->b->fail == VX_OK) u->b->fail = r;
    return false;
}

/* The split form's symbols read straight from its streams (vx__svo_src.cur):
 * false where the symbol is not there as it is (the stream's end, a leaf
 * mask outside valid, a reference of two bytes or more, a channel without a
 * stream), and the caller asks next(), which reads at the same position and
 * gives it or the error. A call per symbol was a tenth of the 4096^3
 * helmet's read. */
static inline unsigned unp_class(unsigned level) { return level >= 4 ? 3 : level - 1; }
static inline bool cur_byte(vx__svo_split_cur* c, unsigned s, uint32_t* v) {
    if (c->pos[s] >= c->n[s]) return false;
    *v = c->data[s][c->pos[s]++];
    return true;
}
static inline bool cur_leaf(vx__svo_split_cur* c, unsigned level, uint32_t valid, uint32_t* v) {
    unsigned s = 3 + unp_class(level);
    if (c->pos[s] >= c->n[s] || (c->data[s][c->pos[s]] & ~valid)) return false;
    *v = c->data[s][c->pos[s]++];
    return true;
}
/* A reference of up to 5 bytes in the shortest form within 32 bits (the
 * 4096^3 helmet's are mostly 3-4 bytes: node indices); anything else to
 * next(), which gives the same value or the error. */
static inline bool cur_ref(vx__svo_split_cur* c, unsigned level, uint32_t* v) {
    unsigned s = 6 + unp_class(level);
    size_t q = c->pos[s], n = c->n[s];
    const uint8_t* d = c->data[s];
    uint64_t x = 0;
    for (unsigned sh = 0; sh < 35; sh += 7) {
        if (q >= n) return false;
        uint8_t b = d[q++];
        x |= (uint64_t)(b & 0x7Fu) << sh;
        if (!(b & 0x80u)) {
            if ((b == 0 && sh) || x > UINT32_MAX) return false;
            c->pos[s] = q;
            *v = (uint32_t)x;
            return true;
        }
    }
    return false;
}

/* The back-references a few ahead in each reference stream, fetched before
 * they are needed (with ref_index a reference names a completion index, so
 * where it points does not depend on the nodes completed meanwhile): each
 * is a load from anywhere in done[] (16 bytes a node, hundreds of MB), a
 * fifth of unp_visit's samples on the 4096^3 helmet. Hints only: a
 * damaged stream fetches some other entry or none. */
enum { UNP_REF_AHEAD = 8 };
static inline void ref_ahead(const unp_node* done, size_t cap, const vx__svo_split_cur* c, unsigned s, size_t* la) {
    size_t q = *la, n = c->n[s];
    const uint8_t* d = c->data[s];
    uint32_t x = 0;
    for (unsigned sh = 0; q < n && sh < 35; sh += 7) {
        uint8_t b = d[q++];
        x |= (uint32_t)(b & 0x7Fu) << sh;
        if (!(b & 0x80u)) break;
    }
    *la = q;
    if (x && x - 1 < cap) __builtin_prefetch(&done[x - 1]);
}
static inline bool cur_value(vx__svo_split_cur* c, unsigned ch, uint32_t* v) {
    unsigned s = c->cs[ch];
    if (!s || c->pos[s] >= c->vcount[s] || ch == 2 || ch == 4) return false; /* (normal and density have no stream) */
    size_t at = c->pos[s]++;
    const uint8_t* p = c->data[s];
    if (ch == 1) /* RGBA8: 4 bytes a value, least significant first */
        *v = (uint32_t)p[4 * at] | (uint32_t)p[4 * at + 1] << 8 | (uint32_t)p[4 * at + 2] << 16 | (uint32_t)p[4 * at + 3] << 24;
    else if (ch == 3) /* material */
        *v = (uint32_t)p[2 * at] | (uint32_t)p[2 * at + 1] << 8;
    else /* palette */
        *v = p[at];
    return true;
}

/* The fused layout's stages (unp.fused; unp_pend says which does what). A
 * failure stops the layout, not the reconstruction. */
/* The stored run that the node's run-table slot names first with the
 * run's tag: its records fetched for run_intern_exact's comparison. */
static void unp_mid(unp* u) {
    const unp_pend* e = &u->ring[u->rmid++ % UNP_RING];
    const outw* o = u->o;
    if (!e->find || !o->runcap) return;
    uint64_t want = (e->h & 0xFFFFFFFF00000000ull) | (uint64_t)e->nk << 28;
    for (size_t j = run_slot(e->h, o->runcap), k = 0; k < 4 && o->runh[j]; j = (j + 1) & (o->runcap - 1), k++)
        if ((o->runh[j] & 0xFFFFFFFFF0000000ull) == want) {
            uint32_t st = ((uint32_t)o->runh[j] & 0x0FFFFFFFu) - 1;
            if (st < o->nid) __builtin_prefetch(o->ids + st);
            return;
        }
}

/* The node's run: its first record's index into e->a, and the lone-block
 * table's slot of a lone block fetched. */
static void unp_run(unp* u) {
    unp_pend* e = &u->ring[u->rrun++ % UNP_RING];
    bld* lb = &u->lb;
    e->a = 0;
    if (u->lay_dead || !lb->attrs) return; /* (every node has a block where there are attributes) */
    const uint64_t* hp = u->pf_on ? &e->h : NULL;
    uint32_t a = lb->runs ? run_take(lb, u->o, e->ids, e->nk, hp) : run_intern(lb, u->o, e->ids, e->nk, hp, true);
    if (a == UINT32_MAX) {
        u->lay_dead = true;
        return;
    }
    e->a = a;
    const outw* o = u->o;
    if (e->nn == 0 && lb->dag && o->lone) __builtin_prefetch(&o->lone[(size_t)mix64(a) & (o->lonecap - 1)]);
}

/* The block of the oldest node whose run is taken, as layout_nodes writes
 * it (LAY_ALL), its position into done[].id. */
static void unp_lay(unp* u) {
    const unp_pend* e = &u->ring[u->rout++ % UNP_RING];
    if (u->lay_dead) return;
    bld* lb = &u->lb;
    uint32_t valid = e->hdr & 0xFFu, leaf = e->hdr >> 8;
    if (!((valid & ~leaf) != 0 || lb->attrs != 0)) { /* node_has_block */
        u->done[e->at].id = NO_BLOCK;
        return;
    }
    uint32_t cb[8];
    for (unsigned k = 0; k < e->nn; k++) cb[k] = u->done[e->kid[k]].id;
    if (!lay_block(lb, u->o, e->a, cb, e->cd, e->nn, &u->done[e->at].id)) u->lay_dead = true;
}

/* Queues the node just completed (done[at]) for the fused layout, hashing
 * its run and fetching the table slots that run will probe where it is
 * looked up (run_prefetch's hint), and moves the waiting nodes on by a
 * stage each. */
static void unp_push(unp* u, uint32_t hdr, size_t at, const uint32_t ids[8], unsigned nk, const uint32_t kid[8], const uint32_t cd[8],
                     unsigned nn) {
    unp_pend* e = &u->ring[u->rin++ % UNP_RING];
    e->hdr = hdr;
    e->at = (uint32_t)at;
    e->nk = nk;
    e->nn = nn;
    /* whole arrays (ids, kid and cd hold 8 each; the entries past nk and nn
     * are never read): a few vector moves where three calls of a variable
     * size were */
    memcpy(e->ids, ids, sizeof e->ids);
    memcpy(e->kid, kid, sizeof e->kid);
    memcpy(e->cd, cd, sizeof e->cd);
    e->h = 0;
    e->find = false;
    const bld* lb = &u->lb;
    uint8_t rf = 0;
    if (u->pf_on && (!lb->runs || (u->pfr < lb->runs_n && (rf = lb->runs[u->pfr++]) != 0))) {
        bool uni = true;
        for (unsigned j = 1; j < nk; j++) uni = uni && ids[j] == ids[0];
        const outw* o = u->o;
        if (uni && nk < 8 && o->unicap) __builtin_prefetch(&o->uni[(size_t)mix64(ids[0]) & (o->unicap - 1)]);
        e->h = hash_words(ids, nk, 3);
        e->find = !lb->runs || rf == 2;
        if (o->runcap) __builtin_prefetch(&o->runh[run_slot(e->h, o->runcap)]);
    }
    if (u->rin - u->rmid > UNP_MID) unp_mid(u);
    if (u->rin - u->rrun > UNP_RUN) unp_run(u);
    if (u->rin - u->rout > UNP_AHEAD) unp_lay(u);
}

/* The extent code (xt_pack's) of a node of height 1 with these children:
 * each child a cell, so the box's side along axis i is 0..1 or 1..2 by
 * whether an octant with bit i clear (the masks 0x55, 0x33, 0x0F) or set
 * holds one. */
static inline uint64_t xt_height1(uint32_t valid) {
    static const uint32_t LOW[3] = {0x55u, 0x33u, 0x0Fu};
    uint64_t code = 1u | (uint64_t)(vx__popc8(valid) - 1u) << 3;
    for (int i = 0; i < 3; i++) {
        code |= (uint64_t)!(valid & LOW[i]) << (18 + 5 * i);         /* min: 1 where no child is in the low half */
        code |= (uint64_t)((valid & ~LOW[i] & 0xFFu) != 0) << (33 + 5 * i); /* max - 1: 1 where one is in the high half */
    }
    return code;
}

/* A node at level 1 (its children all leaves: most of a model's nodes)
 * where the records are one channel's values (or there are none) and every
 * channel's stream holds this node's values: as unp_visit's loop would read
 * it, without a call or a branch per child and channel. The constant
 * channels' values are only stepped over (each equals the first:
 * vx__svo_split_constants). false where it does not apply (unp_visit then
 * reads the node); true where it did, with u->leaves_failed set where it
 * failed (out of memory). */
static bool unp_leaves(unp* u, uint32_t valid, uint32_t* out) {
    bld* b = u->b;
    vx__svo_split_cur* cur = u->src->cur;
    unsigned n = vx__popc8(valid);
    for (unsigned c = 0; c < 5; c++) {
        if (!(b->attrs >> c & 1u)) continue;
        unsigned s = cur->cs[c];
        if (!s || c == 2 || c == 4 || cur->vcount[s] - cur->pos[s] < n) return false; /* (normal and density have no stream) */
    }
    uint32_t ids[8] = {0};
    if (b->attrs) {
        unsigned c = (unsigned)__builtin_ctz(b->vattr), s = cur->cs[c];
        const uint8_t* p = cur->data[s];
        size_t at = cur->pos[s];
        if (c == 1) /* RGBA8: 4 bytes a value, least significant first */
            for (unsigned k = 0; k < n; k++)
                ids[k] = (uint32_t)p[4 * (at + k)] | (uint32_t)p[4 * (at + k) + 1] << 8 | (uint32_t)p[4 * (at + k) + 2] << 16 |
                         (uint32_t)p[4 * (at + k) + 3] << 24;
        else if (c == 3) /* material */
            for (unsigned k = 0; k < n; k++) ids[k] = (uint32_t)p[2 * (at + k)] | (uint32_t)p[2 * (at + k) + 1] << 8;
        else /* palette */
            for (unsigned k = 0; k < n; k++) ids[k] = p[at + k];
        for (unsigned ch = 0; ch < 5; ch++)
            if (b->attrs >> ch & 1u) cur->pos[cur->cs[ch]] += n;
    }
    uint32_t rep = b->attrs ? representative(b, ids, n) : 0, hdr = valid | valid << 8;
    uint32_t id = NO_BLOCK; /* fused: the block, written when the node is laid out */
    if (!u->fused && (id = pool_append(b, hdr, ids, n, rep)) == UINT32_MAX) return u->leaves_failed = true;
    if (u->ndone >= u->capdone && !vx_grow(b->a, (void**)&u->done, &u->capdone, u->ndone + 1, sizeof *u->done))
        return oom(b, "node list"), u->leaves_failed = true;
    unp_node* dn = &u->done[u->ndone];
    dn->id = id;
    dn->rep = rep;
    dn->xt = (u->want_xt ? xt_height1(valid) : 1u) | (uint64_t)hdr << 48;
    if (u->fused) unp_push(u, hdr, u->ndone, ids, n, ids, ids, 0);
    u->ndone++;
    *out = id;
    return true;
}

/* Reads one node (and, recursively, its new children) into the pool. */
static bool unp_visit(unp* u, unsigned level, uint32_t* out) {
    bld* b = u->b;
    uint32_t valid, leaf;
    vx_error* err = u->err;
    vx__svo_split_cur* cur = u->src->cur;
    if (!(cur && cur_byte(cur, unp_class(level), &valid)) && !u->src->next(u->src->user, VX__SYM_VALID, level, &valid, err))
        return unp_fail(u, err ? err->code : VX_ERR_BAD_FORMAT);
    if (valid == 0 || valid > 0xFFu)
        return unp_fail(u, vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo: section NODE: a node at level %u has valid mask 0x%x",
                                   level, valid));
    if (level == 1 && cur && (b->direct || !b->attrs) && unp_leaves(u, valid, out)) return !u->leaves_failed;
    if (level == 1) leaf = valid;
    else if (!(cur && cur_leaf(cur, level, valid, &leaf)) && !u->src->next(u->src->user, VX__SYM_LEAF, level | valid << 8, &leaf, err))
        return unp_fail(u, err ? err->code : VX_ERR_BAD_FORMAT);
    if (leaf & ~valid)
        return unp_fail(u, vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET,
                                   "svo: section NODE: leaf mask 0x%02x is not a subset of valid mask 0x%02x", leaf, valid));
    uint32_t kids[8] = {0}, ids[8] = {0}; /* (whole: unp_push copies all 8) */
    uint32_t cdm[8] = {0}; /* fused: the non-leaf children's masks (kids: their indices in done[], in order) */
    unsigned nn = 0;
    xt_node cx[8]; /* the children's heights and extents (done[].xt) */
    unsigned n = 0, h = 1;
    for (unsigned o = 0; o < 8; o++) {
        if (!(valid >> o & 1u)) continue;
        cx[n].h = 0; /* a leaf: one cell at height 0 */
        if (leaf >> o & 1u) {
            uint32_t id = 0;
            if (b->attrs) {
                rec r;
                memset(&r, 0, sizeof r);
                for (unsigned c = 0; c < 5; c++) {
                    if (!(b->attrs >> c & 1u)) continue;
                    uint32_t v;
                    if (!(cur && cur_value(cur, c, &v)) && !u->src->next(u->src->user, VX__SYM_VALUE, c, &v, err))
                        return unp_fail(u, err ? err->code : VX_ERR_BAD_FORMAT);
                    if (c == 0) r.palette = (uint8_t)v;
                    else if (c == 1) r.rgba = v;
                    else if (c == 3) r.material = (uint16_t)v;
                }
                id = b->direct ? rec_value(b->vattr, &r) : rec_intern(b, &r);
                if (id == UINT32_MAX && !b->direct) return false;
            }
            kids[n] = ids[n] = id;
        } else {
            /* every non-leaf child is one descriptor word of its parent's block */
            if (++u->words >= u->max_words)
                return unp_fail(u, vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET,
                                           "svo: section NODE: the tree has more descriptors than the %llu declared words",
                                           (unsigned long long)u->max_words));
            uint32_t ref, c;
            if (!(cur && cur_ref(cur, level, &ref)) && !u->src->next(u->src->user, VX__SYM_REF, level, &ref, err))
                return unp_fail(u, err ? err->code : VX_ERR_BAD_FORMAT);
            if (u->ref_pf) {
                unsigned rs = unp_class(level) - 1; /* (level >= 2 here) */
                ref_ahead(u->done, u->capdone, cur, 7 + rs, &u->la[rs]);
            }
            if (u->ref_index && ref) { /* 1 + the node's completion index: as a distance back */
                if (ref - 1 >= u->ndone)
                    return unp_fail(u, vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET,
                                               "svo: section NODE: reference to node %u but only %zu nodes precede it", ref - 1, u->ndone));
                ref = (uint32_t)(u->ndone - (ref - 1));
            }
            if (ref == 0) {
                if (!unp_visit(u, level - 1, &c)) return false; /* level >= 2 here: level 1 children are leaves */
            } else if (ref > u->ndone) {
                return unp_fail(u, vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET,
                                           "svo: section NODE: back-reference %u but only %zu nodes precede it", ref, u->ndone));
            }
            size_t di = u->ndone - (ref ? ref : 1); /* the new child: the last completed */
            const unp_node* cn = &u->done[di];
            c = cn->id;
            unsigned ch = xt_height(cn->xt);
            if (ch > level - 1) /* (the decoding thread, pipe_walk, stops at the same symbol) */
                return unp_fail(u, vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET,
                                           "svo: section NODE: back-reference %u at level %u names a node of %u levels", ref, level - 1,
                                           ch));
            if (ch + 1 > h) h = ch + 1;
            if (u->want_xt) xt_unpack(u, cn->xt, &cx[n]);
            if (u->fused) {
                kids[nn] = (uint32_t)di;
                cdm[nn++] = (uint32_t)(cn->xt >> 48);
            } else {
                kids[n] = c;
            }
            ids[n] = cn->rep;
        }
        n++;
    }
    uint32_t rep = b->attrs ? representative(b, ids, n) : 0;
    if (rep == UINT32_MAX && !b->direct) return false;
    uint32_t id = NO_BLOCK; /* fused: the block, written when the node is laid out */
    if (!u->fused && (id = pool_append(b, valid | leaf << 8, kids, n, rep)) == UINT32_MAX) return false;
    if (u->ndone >= u->capdone && !vx_grow(b->a, (void**)&u->done, &u->capdone, u->ndone + 1, sizeof *u->done))
        return oom(b, "node list");
    unp_node* dn = &u->done[u->ndone];
    dn->id = id;
    dn->rep = rep;
    dn->xt = h <= XT_SMALL ? h : 7u | (uint64_t)h << 3; /* the height (with want_xt, the extent below) */
    if (u->want_xt) {
        /* the node's extent at its height h: child k (octant o) scaled from
         * its height to h - 1 and moved to its octant */
        xt_node x = {h, 0, {UINT32_MAX, UINT32_MAX, UINT32_MAX}, {0, 0, 0}};
        for (unsigned o = 0, k = 0; o < 8; o++) {
            if (!(valid >> o & 1u)) continue;
            const xt_node* c = &cx[k++];
            unsigned sh = h - 1 - c->h;
            if (c->h == 0) {
                x.cells += (uint64_t)1 << (3 * sh);
            } else {
                x.cells += c->cells << (3 * sh);
            }
            for (int i = 0; i < 3; i++) {
                uint32_t at = (o >> i & 1u) << (h - 1);
                uint32_t lo = c->h == 0 ? 0 : c->mn[i], hi = c->h == 0 ? 1 : c->mx[i];
                if ((lo << sh) + at < x.mn[i]) x.mn[i] = (lo << sh) + at;
                if ((hi << sh) + at > x.mx[i]) x.mx[i] = (hi << sh) + at;
            }
        }
        if (!xt_pack(u, &x, &dn->xt)) return false;
    }
    dn->xt |= (uint64_t)(valid | leaf << 8) << 48;
    if (u->fused) unp_push(u, valid | leaf << 8, u->ndone, ids, n, kids, cdm, nn);
    u->ndone++;
    *out = id;
    return true;
}

vx_result vx__svo_unpack(const vx__svo_unpack_desc* d, const vx__svo_src* src, vx_svo_model* out, vx_error* err) {
    if (d->attrs & ~(uint32_t)(VX_ATTR_PALETTE | VX_ATTR_RGBA8 | VX_ATTR_MATERIAL) || d->depth < 1 ||
        d->depth > VX_SVO_MAX_DEPTH || d->limit < 1 || d->limit > VX__SVO_PTR_MAX)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo unpack: bad arguments");
    bld b;
    memset(&b, 0, sizeof b);
    b.a = d->alloc;
    b.attrs = d->attrs;
    b.dag = d->dag;
    b.collapse = true;
    b.limit = d->limit;
    b.depth = d->depth;
    b.err = err;
    b.runs = d->attrs ? d->runs : NULL; /* (a model without attributes has no runs) */
    b.give_ids = true;
    b.runs_n = d->runs_n;
    b.direct = d->attrs && (d->attrs & (d->attrs - 1)) == 0;
    b.vattr = d->attrs;
    {
        /* at most one channel varies: records are its values, the constant
         * ones filled in at the end. Equal records have equal values and the
         * representatives of constant channels are their values, so the runs,
         * the sharing and the words are those of the record table's ids (the
         * layout compares references only for equality). The 4096^3 helmet's
         * material is one value: its read no longer interns 74 M records. */
        uint32_t vary = d->attrs & ~d->const_attrs;
        if (d->attrs && !b.direct && (vary & (vary - 1)) == 0) {
            b.direct = true;
            b.vattr = vary ? vary : d->attrs & (0u - d->attrs);
            b.cst = d->const_rec;
        }
    }
    outw o;
    memset(&o, 0, sizeof o);
    unp u = {.b = &b, .src = src, .max_words = d->max_words, .err = err, .want_xt = d->tree != NULL, .ref_index = d->ref_index};
    vx_svo_model m;
    memset(&m, 0, sizeof m);
    vx_result res = VX_OK;
    if (!b.attrs) {
        rec z;
        memset(&z, 0, sizeof z);
        if (rec_intern(&b, &z) == UINT32_MAX) goto fail;
    }
    if (u.max_words == 0)
        return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo: section NODE: a tree declared with 0 words");
    if (d->max_records) {
        /* the words and records at their declared sizes (bounded by the
         * stream's bytes, check_declared; untouched pages cost no memory):
         * grown by doubling they were copied by realloc up to the mmap
         * threshold and faulted in a 4 KB page at a time, the kernel's
         * faults and clearing a quarter of the 4096^3 helmet's read on a
         * VM. Where it cannot be had they grow as before: same words. Before
         * any layout thread starts: it uses o. */
        size_t nw = (size_t)u.max_words, nr = (size_t)d->max_records;
        if (nw <= SIZE_MAX / 4 && (o.w = (uint32_t*)vx_alloc(b.a, nw * 4)) != NULL) {
            o.cap = nw;
            vx__svo_advise_huge(o.w, nw * 4);
        }
        if (b.attrs && nr <= SIZE_MAX / 4 && (o.ids = (uint32_t*)vx_alloc(b.a, nr * 4)) != NULL) {
            o.capid = nr;
            vx__svo_advise_huge(o.ids, nr * 4);
        }
        if (b.runs && b.dag) {
            /* the run table at the size it grows to: the runs stream's 1s
             * are the runs stored (run_take), so it never grows (each growth
             * a fresh table and every entry placed again), and 2 MB pages
             * for its probes at random (the 4096^3 helmet stores 1.2 M runs).
             * Which run a lookup finds does not depend on the table's size
             * (run_slot): same words. */
            size_t ones = 0;
            for (size_t i = 0; i < b.runs_n; i++) ones += b.runs[i] == 1;
            run_table_presize(&b, &o, ones, true);
        }
    }
    /* The layout follows the decoding on other threads (as it follows the
     * build): the pool is allocated once at its bound, at most max_words
     * nodes (each new non-root node is one of the declared words) of at most
     * N_KIDS + 8 words; untouched pages cost no memory. Where it cannot be
     * had, the layout runs after the decoding as before: same result. */
    lay_job lj, lj2;
    lj.started = lj2.started = lj.gates = lj2.gates = false;
    if (d->layout_threads) { /* 0 for models under vx__svo_parallel_words (the callers) */
        uint64_t words = (uint64_t)(N_KIDS + 8) * u.max_words + 16;
        if (words > 0xFFFFFFF0u) words = 0xFFFFFFF0u;
        b.pool = (uint32_t*)vx_alloc(b.a, (size_t)words * sizeof *b.pool);
        if (b.pool) {
            b.cappool = (size_t)words;
            /* with the runs stream the runs stage is a copy: one thread */
            bool two = d->layout_threads >= 2 && b.attrs && b.dag && !b.runs;
            if (!(two ? lay_run2(&lj, &lj2, &b, &o) : lay_run(&lj, &b, &o))) {
                vx_free(b.a, b.pool);
                b.pool = NULL;
                b.cappool = 0;
            }
        }
    }
    if (!lj.started) { /* no layout thread: the layout fused into the reconstruction */
        u.fused = true;
        u.o = &o;
        u.lb = b;
        u.lb.err = &u.lerr;
        u.lb.fail = VX_OK;
        memset(&u.lerr, 0, sizeof u.lerr);
        u.pf_on = b.dag && b.attrs;
    }
    if (src->cur) {
        /* every node read takes one valid mask: the list at its final size
         * (no growth, each a copy into fresh pages), in pages an earlier
         * model of this thread faulted in already where there is a scratch,
         * else fresh as 2 MB pages (vx__svo_scratch_get; the 4096^3 helmet
         * on one thread: 425 K faults a read, most of them this list's) */
        size_t nodes = 1, bytes = 0;
        for (unsigned i = 0; i < 4; i++) nodes += src->cur->n[i];
        if (nodes <= SIZE_MAX / sizeof *u.done) u.done = (unp_node*)vx__svo_scratch_get(d->scratch, b.a, nodes * sizeof *u.done, &bytes);
        u.capdone = u.done ? bytes / sizeof *u.done : 0;
    }
    if (u.ref_index && src->cur) { /* each reference stream's lookahead UNP_REF_AHEAD references ahead */
        u.ref_pf = true;
        for (unsigned i = 0; i < 3; i++) {
            u.la[i] = src->cur->pos[7 + i];
            for (unsigned k = 0; k < UNP_REF_AHEAD; k++) ref_ahead(NULL, 0, src->cur, 7 + i, &u.la[i]);
        }
    }
    bool visited = unp_visit(&u, d->depth, &b.root);
    lay_join(&lj, &b, visited); /* the runs stage first: the blocks stage follows it */
    lay_join(&lj2, &b, visited);
    lay_free(&lj);
    lay_free(&lj2);
    if (!visited || b.fail != VX_OK) goto fail;
    if (u.fused) {
        while (u.rrun < u.rin) unp_run(&u); /* (the runs in order, then the blocks: each stage keeps the order) */
        while (u.rout < u.rin) unp_lay(&u);
        /* the root's descriptor last, as layout() writes it */
        const unp_node* r = &u.done[u.ndone - 1];
        uint32_t blk = r->id, hdr = (uint32_t)(r->xt >> 48);
        if (!u.lay_dead) {
            bool ok;
            if (blk == NO_BLOCK) ok = out_push(&u.lb, &o, vx_svo_desc_make(0, false, hdr & 0xFFu, hdr >> 8));
            else if (o.n - blk > b.limit) ok = out_push(&u.lb, &o, blk) && (o.far++, out_push(&u.lb, &o, vx_svo_desc_make(1, true, hdr & 0xFFu, hdr >> 8)));
            else ok = out_push(&u.lb, &o, vx_svo_desc_make((uint32_t)(o.n - blk), false, hdr & 0xFFu, hdr >> 8));
            u.lay_dead = !ok;
        }
        if (u.lay_dead) {
            b.fail = u.lb.fail != VX_OK ? u.lb.fail : VX_ERR_NOMEM;
            if (err) *err = u.lerr;
            goto fail;
        }
        b.laid_given = true; /* finish_model: the words are laid out, b.root is the root's record */
        b.root = r->rep;
    }
    b.have_root = true;
    b.root_is_leaf = false;
    if (d->tree) { /* the root's extent at the depth (its height is at most the depth: unp_visit) */
        xt_node x;
        xt_unpack(&u, u.done[u.ndone - 1].xt, &x);
        unsigned sh = d->depth - x.h;
        d->tree->cells = x.cells << (3 * sh);
        for (int i = 0; i < 3; i++) d->tree->min[i] = x.mn[i] << sh, d->tree->max[i] = x.mx[i] << sh;
    }
    if (!finish_model(&b, &o, &m, false)) goto fail;
    if (b.runs && o.runs_pos != b.runs_n) {
        vx_svo_model_free(b.a, &m);
        res = vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo: section NODE: %zu bytes of the runs stream left over after its %zu runs",
                      b.runs_n - o.runs_pos, o.runs_taken);
        goto done;
    }
    out->nodes = m.nodes;
    out->node_count = m.node_count;
    out->root = m.root;
    out->root_attr = m.root_attr;
    out->attr_count = m.attr_count;
    out->palette = m.palette;
    out->rgba = m.rgba;
    out->material = m.material;
    goto done;
fail:
    res = b.fail != VX_OK ? b.fail : VX_ERR_BAD_FORMAT;
done:
    if (d->scratch) vx__svo_scratch_put(d->scratch, b.a, u.done, u.capdone * sizeof *u.done);
    else vx_free(b.a, u.done);
    vx_free(b.a, u.big);
    vx_free(b.a, o.w);
    vx_free(b.a, o.ids);
    vx_free(b.a, o.runh);
    vx_free(b.a, o.lone);
    vx_free(b.a, o.uni);
    bld_free(&b);
    return res;
}
