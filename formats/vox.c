/* formats/vox.c - MagicaVoxel .vox reader, scene-graph flattening, rotation
 * bytes, placement and validation. The writer is in vox_write.c.
 *
 * Every read goes through a vx_rd bounded by the enclosing chunk, so no
 * declared length can reach outside its parent. Strings and dictionaries are
 * borrowed views into the input while a chunk is parsed; whatever the scene
 * keeps is copied. */
#include "formats/vox.h"

#include <limits.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define ZLIB_CONST /* next_in as a const pointer: the input is borrowed */
#include <zlib.h>

/* Longest STRING accepted: names and values in real files are a few dozen
 * bytes; a cap keeps a corrupt length from being treated as text. */
#define VOX_MAX_STRING (1u << 16)
/* Deepest nTRN/nGRP nesting followed (the traversal recurses). */
#define VOX_MAX_DEPTH 256
/* Largest |t| of a composed translation: keeps every placed cell (t plus at
 * most 256 cells of pivot offset) inside int32 with a wide margin. */
#define VOX_MAX_T (1 << 30)
/* Transform nodes visited by one flattening beyond the file's own count:
 * MagicaVoxel instances a group by pointing several transforms at it, so a
 * corrupt file of shared groups nested n deep would visit 2^n of them. */
#define VOX_MAX_VISITS ((uint64_t)VX_VOX_MAX_INSTANCES)
/* The flattenings' work (a node visit plus the keys it scans) beyond each
 * frame's own node_count + key_count, summed over every frame of a read:
 * without it a small corrupt file of nested shared groups and 65,536
 * keyframes would make 65,536 walks of VOX_MAX_VISITS nodes (hours). About
 * 1 s on dev; a real file's shared groups stay far below it. */
#define VOX_MAX_EXTRA_WORK ((uint64_t)1 << 26)
/* Rotation byte of the identity: row 0 -> column 0, row 1 -> column 1. */
#define VOX_ROT_IDENTITY 4u
/* Cells a TDCZ stream is inflated into at a time: the grid itself (up to
 * 16 MiB at 256^3) is never held, only its voxels. */
#define TDCZ_WINDOW ((size_t)1 << 16)

const uint32_t vx_vox_default_palette[256] = {
    0x00000000, 0xffffffff, 0xffccffff, 0xff99ffff, 0xff66ffff, 0xff33ffff, 0xff00ffff, 0xffffccff, 0xffccccff, 0xff99ccff, 0xff66ccff, 0xff33ccff, 0xff00ccff, 0xffff99ff, 0xffcc99ff, 0xff9999ff,
    0xff6699ff, 0xff3399ff, 0xff0099ff, 0xffff66ff, 0xffcc66ff, 0xff9966ff, 0xff6666ff, 0xff3366ff, 0xff0066ff, 0xffff33ff, 0xffcc33ff, 0xff9933ff, 0xff6633ff, 0xff3333ff, 0xff0033ff, 0xffff00ff,
    0xffcc00ff, 0xff9900ff, 0xff6600ff, 0xff3300ff, 0xff0000ff, 0xffffffcc, 0xffccffcc, 0xff99ffcc, 0xff66ffcc, 0xff33ffcc, 0xff00ffcc, 0xffffcccc, 0xffcccccc, 0xff99cccc, 0xff66cccc, 0xff33cccc,
    0xff00cccc, 0xffff99cc, 0xffcc99cc, 0xff9999cc, 0xff6699cc, 0xff3399cc, 0xff0099cc, 0xffff66cc, 0xffcc66cc, 0xff9966cc, 0xff6666cc, 0xff3366cc, 0xff0066cc, 0xffff33cc, 0xffcc33cc, 0xff9933cc,
    0xff6633cc, 0xff3333cc, 0xff0033cc, 0xffff00cc, 0xffcc00cc, 0xff9900cc, 0xff6600cc, 0xff3300cc, 0xff0000cc, 0xffffff99, 0xffccff99, 0xff99ff99, 0xff66ff99, 0xff33ff99, 0xff00ff99, 0xffffcc99,
    0xffcccc99, 0xff99cc99, 0xff66cc99, 0xff33cc99, 0xff00cc99, 0xffff9999, 0xffcc9999, 0xff999999, 0xff669999, 0xff339999, 0xff009999, 0xffff6699, 0xffcc6699, 0xff996699, 0xff666699, 0xff336699,
    0xff006699, 0xffff3399, 0xffcc3399, 0xff993399, 0xff663399, 0xff333399, 0xff003399, 0xffff0099, 0xffcc0099, 0xff990099, 0xff660099, 0xff330099, 0xff000099, 0xffffff66, 0xffccff66, 0xff99ff66,
    0xff66ff66, 0xff33ff66, 0xff00ff66, 0xffffcc66, 0xffcccc66, 0xff99cc66, 0xff66cc66, 0xff33cc66, 0xff00cc66, 0xffff9966, 0xffcc9966, 0xff999966, 0xff669966, 0xff339966, 0xff009966, 0xffff6666,
    0xffcc6666, 0xff996666, 0xff666666, 0xff336666, 0xff006666, 0xffff3366, 0xffcc3366, 0xff993366, 0xff663366, 0xff333366, 0xff003366, 0xffff0066, 0xffcc0066, 0xff990066, 0xff660066, 0xff330066,
    0xff000066, 0xffffff33, 0xffccff33, 0xff99ff33, 0xff66ff33, 0xff33ff33, 0xff00ff33, 0xffffcc33, 0xffcccc33, 0xff99cc33, 0xff66cc33, 0xff33cc33, 0xff00cc33, 0xffff9933, 0xffcc9933, 0xff999933,
    0xff669933, 0xff339933, 0xff009933, 0xffff6633, 0xffcc6633, 0xff996633, 0xff666633, 0xff336633, 0xff006633, 0xffff3333, 0xffcc3333, 0xff993333, 0xff663333, 0xff333333, 0xff003333, 0xffff0033,
    0xffcc0033, 0xff990033, 0xff660033, 0xff330033, 0xff000033, 0xffffff00, 0xffccff00, 0xff99ff00, 0xff66ff00, 0xff33ff00, 0xff00ff00, 0xffffcc00, 0xffcccc00, 0xff99cc00, 0xff66cc00, 0xff33cc00,
    0xff00cc00, 0xffff9900, 0xffcc9900, 0xff999900, 0xff669900, 0xff339900, 0xff009900, 0xffff6600, 0xffcc6600, 0xff996600, 0xff666600, 0xff336600, 0xff006600, 0xffff3300, 0xffcc3300, 0xff993300,
    0xff663300, 0xff333300, 0xff003300, 0xffff0000, 0xffcc0000, 0xff990000, 0xff660000, 0xff330000, 0xff0000ee, 0xff0000dd, 0xff0000bb, 0xff0000aa, 0xff000088, 0xff000077, 0xff000055, 0xff000044,
    0xff000022, 0xff000011, 0xff00ee00, 0xff00dd00, 0xff00bb00, 0xff00aa00, 0xff008800, 0xff007700, 0xff005500, 0xff004400, 0xff002200, 0xff001100, 0xffee0000, 0xffdd0000, 0xffbb0000, 0xffaa0000,
    0xff880000, 0xff770000, 0xff550000, 0xff440000, 0xff220000, 0xff110000, 0xffeeeeee, 0xffdddddd, 0xffbbbbbb, 0xffaaaaaa, 0xff888888, 0xff777777, 0xff555555, 0xff444444, 0xff222222, 0xff111111,
};

/* ---- rotations and placement ---------------------------------------------- */

bool vx_vox_rot_from_byte(uint8_t b, int32_t rot[9]) {
    unsigned i0 = b & 3u, i1 = (b >> 2) & 3u;
    if ((b & 0x80u) || i0 == 3 || i1 == 3 || i0 == i1) return false;
    unsigned i2 = 3u - i0 - i1;
    if (rot) {
        for (int k = 0; k < 9; k++) rot[k] = 0;
        rot[0 + i0] = (b & 0x10u) ? -1 : 1;
        rot[3 + i1] = (b & 0x20u) ? -1 : 1;
        rot[6 + i2] = (b & 0x40u) ? -1 : 1;
    }
    return true;
}

bool vx_vox_rot_to_byte(const int32_t rot[9], uint8_t* out) {
    if (!rot) return false;
    unsigned idx[3], neg = 0, used = 0;
    for (unsigned r = 0; r < 3; r++) {
        int found = -1;
        for (unsigned c = 0; c < 3; c++) {
            int32_t v = rot[r * 3 + c];
            if (v == 0) continue;
            if ((v != 1 && v != -1) || found >= 0) return false;
            found = (int)c;
            if (v < 0) neg |= 1u << r;
        }
        if (found < 0 || (used & (1u << found))) return false;
        used |= 1u << found;
        idx[r] = (unsigned)found;
    }
    if (out) *out = (uint8_t)(idx[0] | (idx[1] << 2) | (neg << 4));
    return true;
}

static int64_t floor_half(int64_t w) { return w >= 0 ? w / 2 : -((-w + 1) / 2); }

void vx_vox_place(const int32_t rot[9], const int32_t t[3], const uint32_t size[3], const uint32_t v[3],
                  int32_t out[3]) {
    /* In doubled coordinates the cell centre v + 1/2 - floor(s/2) is the odd
     * integer 2v + 1 - 2 floor(s/2); a signed permutation keeps it odd, so
     * the world value never lies on a cell boundary and floor is exact. */
    int64_t c[3];
    for (int k = 0; k < 3; k++) c[k] = 2 * (int64_t)v[k] + 1 - 2 * (int64_t)(size[k] / 2);
    for (int r = 0; r < 3; r++) {
        int64_t w = 2 * (int64_t)t[r];
        for (int k = 0; k < 3; k++) w += (int64_t)rot[r * 3 + k] * c[k];
        out[r] = (int32_t)floor_half(w);
    }
}

/* ---- reader state ------------------------------------------------------------ */

typedef struct vox_str {
    const uint8_t* p;
    uint32_t n;
} vox_str;

/* One nTRN frame or one nSHP model entry. */
typedef struct vox_key {
    uint32_t f;      /* _f, 0 if absent */
    uint32_t model;  /* nSHP */
    uint8_t rot;     /* nTRN, validated */
    int32_t t[3];    /* nTRN */
} vox_key;

enum { NODE_UNSEEN = 0, NODE_ON_PATH, NODE_DONE };

typedef struct vox_node {
    vx_vox_node_type type;
    int32_t id;
    uint64_t off; /* chunk offset, for messages */
    bool hidden;
    uint8_t state;
    int32_t layer;
    int32_t child;         /* nTRN */
    uint32_t first, count; /* keys (nTRN, nSHP) or kids (nGRP) */
    char name[64];
} vox_node;

typedef struct vox_idmap {
    int32_t id;
    uint32_t node;
} vox_idmap;

typedef struct vox_ctx {
    vx_vox_read_desc d; /* defaults resolved */
    const vx_allocator* a;
    vx_error* err;
    char chunk_id[5];
    uint64_t chunk_off;
    vx_vox_scene s;
    size_t model_cap, inst_cap, layer_cap, mat_cap;
    vox_node* nodes;
    size_t node_count, node_cap;
    vox_key* keys;
    size_t key_count, key_cap;
    int32_t* kids;
    size_t kid_count, kid_cap;
    vox_idmap* idmap;   /* node ids, sorted */
    vox_idmap* layermap; /* layer id -> hidden (node = 0/1), sorted */
    size_t layermap_count;
    bool size_pending;
    uint32_t pending[3];
    uint64_t pending_off;
    uint64_t voxels_total;
    uint64_t visits; /* transform nodes visited by the current flattening */
    uint64_t work;   /* its node visits plus the keys they scan */
    uint64_t extra_work; /* beyond each flattening's node_count + key_count, whole read (VOX_MAX_EXTRA_WORK) */
    bool have_pack;
    uint32_t pack_models;
} vox_ctx;

#define TRY(x)                                 \
    do {                                       \
        vx_result r_ = (x);                    \
        if (r_ != VX_OK) return r_;            \
    } while (0)

#if defined(__GNUC__)
#define VOX_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define VOX_PRINTF(a, b)
#endif

/* Every message names the chunk and where it starts; off is the exact spot. */
static VOX_PRINTF(4, 5) vx_result cfail(vox_ctx* c, vx_result code, uint64_t off, const char* fmt, ...) {
    char msg[192];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return vx_fail(c->err, code, off, "%s chunk at byte %llu: %s", c->chunk_id, (unsigned long long)c->chunk_off, msg);
}

static void set_chunk(vox_ctx* c, const uint8_t id[4], uint64_t off) {
    for (int k = 0; k < 4; k++) c->chunk_id[k] = (id[k] >= 0x20 && id[k] < 0x7f) ? (char)id[k] : '?';
    c->chunk_id[4] = 0;
    c->chunk_off = off;
}

static void set_node_chunk(vox_ctx* c, const vox_node* n) {
    static const char* const names[] = {"????", "nTRN", "nGRP", "nSHP"};
    memcpy(c->chunk_id, names[n->type <= 3 ? n->type : 0], 5);
    c->chunk_off = n->off;
}

/* Untrusted text in messages: printable ASCII only, and short. */
static const char* show(vox_str s, char buf[24]) {
    uint32_t n = s.n < 20 ? s.n : 20, k;
    for (k = 0; k < n; k++) buf[k] = (s.p[k] >= 0x20 && s.p[k] < 0x7f) ? (char)s.p[k] : '?';
    if (s.n > n) buf[k++] = '~';
    buf[k] = 0;
    return buf;
}

/* The readers below always write their outputs (zero on failure) so the
 * compiler can see every variable initialised along the error paths. */
static vx_result rd_u32(vox_ctx* c, vx_rd* r, uint32_t* v, const char* what) {
    *v = 0;
    if (!vx_rd_u32le(r, v))
        return cfail(c, VX_ERR_TRUNCATED, vx_rd_pos(r), "%s: chunk ends (%zu bytes left, need 4)", what, vx_rd_left(r));
    return VX_OK;
}

static vx_result rd_i32(vox_ctx* c, vx_rd* r, int32_t* v, const char* what) {
    uint32_t u;
    *v = 0;
    TRY(rd_u32(c, r, &u, what));
    *v = (int32_t)u;
    return VX_OK;
}

static vx_result rd_str(vox_ctx* c, vx_rd* r, vox_str* s, const char* what) {
    uint64_t at = vx_rd_pos(r);
    uint32_t n;
    s->p = NULL;
    s->n = 0;
    TRY(rd_u32(c, r, &n, what));
    if (n > VOX_MAX_STRING)
        return cfail(c, VX_ERR_LIMIT, at, "%s: string of %u bytes (limit %u)", what, n, VOX_MAX_STRING);
    if (n > vx_rd_left(r))
        return cfail(c, VX_ERR_TRUNCATED, at, "%s: string of %u bytes, %zu bytes left", what, n, vx_rd_left(r));
    s->p = r->p + r->off;
    s->n = n;
    r->off += n;
    return VX_OK;
}

/* A pair needs at least its two 4-byte lengths, which bounds the count by
 * the bytes left before anything is iterated. */
static vx_result rd_dict_count(vox_ctx* c, vx_rd* r, uint32_t* n, const char* what) {
    uint64_t at = vx_rd_pos(r);
    TRY(rd_u32(c, r, n, what));
    if (*n > vx_rd_left(r) / 8)
        return cfail(c, VX_ERR_TRUNCATED, at, "%s: dictionary of %u pairs cannot fit in the %zu bytes left", what, *n,
                     vx_rd_left(r));
    return VX_OK;
}

static vx_result rd_pair(vox_ctx* c, vx_rd* r, vox_str* k, vox_str* v, const char* what) {
    v->p = NULL;
    v->n = 0;
    TRY(rd_str(c, r, k, what));
    return rd_str(c, r, v, what);
}

static vx_result skip_dict(vox_ctx* c, vx_rd* r, const char* what) {
    uint32_t n;
    TRY(rd_dict_count(c, r, &n, what));
    for (uint32_t i = 0; i < n; i++) {
        vox_str k, v;
        TRY(rd_pair(c, r, &k, &v, what));
    }
    return VX_OK;
}

static bool str_is(vox_str s, const char* lit) {
    size_t n = strlen(lit);
    return s.n == n && memcmp(s.p, lit, n) == 0;
}

static void copy_name(char dst[64], vox_str s) {
    uint32_t n = s.n < 63 ? s.n : 63;
    memcpy(dst, s.p, n);
    dst[n] = 0;
}

/* `count` space-separated decimal integers in [lo, hi], nothing else. */
static bool parse_ints(vox_str s, int64_t* out, int count, int64_t lo, int64_t hi) {
    uint32_t i = 0;
    for (int k = 0; k < count; k++) {
        while (i < s.n && s.p[i] == ' ') i++;
        bool neg = false;
        if (i < s.n && (s.p[i] == '-' || s.p[i] == '+')) neg = s.p[i++] == '-';
        if (i >= s.n || s.p[i] < '0' || s.p[i] > '9') return false;
        int64_t v = 0;
        while (i < s.n && s.p[i] >= '0' && s.p[i] <= '9') {
            v = v * 10 + (s.p[i++] - '0');
            if (v > ((int64_t)1 << 40)) return false;
        }
        v = neg ? -v : v;
        if (v < lo || v > hi) return false;
        out[k] = v;
        if (k + 1 < count && (i >= s.n || s.p[i] != ' ')) return false;
    }
    while (i < s.n && s.p[i] == ' ') i++;
    return i == s.n;
}

static vx_result nomem(vox_ctx* c, const char* what) {
    return vx_fail(c->err, VX_ERR_NOMEM, VX_NO_OFFSET, "%s chunk at byte %llu: out of memory for %s", c->chunk_id,
                   (unsigned long long)c->chunk_off, what);
}

/* Grows *p to hold `more` further elements after `count`. */
static vx_result grow(vox_ctx* c, void** p, size_t* cap, size_t count, size_t more, size_t elem, const char* what) {
    size_t need;
    if (!vx_add_size(count, more, &need) || !vx_grow(c->a, p, cap, need, elem)) return nomem(c, what);
    return VX_OK;
}

/* ---- chunks ------------------------------------------------------------------- */

static vx_result chunk_size(vox_ctx* c, vx_rd* r) {
    if (c->size_pending)
        return cfail(c, VX_ERR_BAD_FORMAT, c->chunk_off, "the SIZE chunk at byte %llu has no XYZI or TDCZ chunk",
                     (unsigned long long)c->pending_off);
    uint32_t v[3];
    TRY(rd_u32(c, r, &v[0], "size x"));
    TRY(rd_u32(c, r, &v[1], "size y"));
    TRY(rd_u32(c, r, &v[2], "size z"));
    for (int k = 0; k < 3; k++) {
        if (v[k] == 0)
            return cfail(c, VX_ERR_BAD_FORMAT, c->chunk_off + 12, "model size %u x %u x %u has a zero side", v[0], v[1],
                         v[2]);
        if (v[k] > c->d.max_dim)
            return cfail(c, VX_ERR_LIMIT, c->chunk_off + 12, "model size %u x %u x %u exceeds max_dim %u", v[0], v[1],
                         v[2], c->d.max_dim);
    }
    memcpy(c->pending, v, sizeof v);
    c->pending_off = c->chunk_off;
    c->size_pending = true;
    return VX_OK;
}

static vx_result chunk_xyzi(vox_ctx* c, vx_rd* r) {
    if (!c->size_pending)
        return cfail(c, VX_ERR_BAD_FORMAT, c->chunk_off, "voxels without a preceding SIZE chunk");
    c->size_pending = false;
    uint64_t at = vx_rd_pos(r);
    uint32_t n;
    TRY(rd_u32(c, r, &n, "voxel count"));
    if (n > vx_rd_left(r) / 4)
        return cfail(c, VX_ERR_TRUNCATED, at, "%u voxels declared, %zu bytes left", n, vx_rd_left(r));
    if (n > c->d.max_voxels - c->voxels_total)
        return cfail(c, VX_ERR_LIMIT, at, "%u more voxels exceed max_voxels %llu in all models", n,
                     (unsigned long long)c->d.max_voxels);
    c->voxels_total += n;
    TRY(grow(c, (void**)&c->s.models, &c->model_cap, c->s.model_count, 1, sizeof(vx_vox_model), "models"));
    vx_vox_model m = {{c->pending[0], c->pending[1], c->pending[2]}, 0, NULL};
    if (n > 0) {
        size_t bytes;
        if (!vx_mul_size(n, 4, &bytes) || !(m.xyzi = (uint8_t*)vx_alloc(c->a, bytes))) return nomem(c, "voxels");
    }
    uint32_t outside = 0, zero = 0;
    const uint8_t* src = r->p + r->off;
    for (uint32_t i = 0; i < n; i++, src += 4) {
        if (src[0] >= m.size[0] || src[1] >= m.size[1] || src[2] >= m.size[2]) { outside++; continue; }
        if (src[3] == 0) { zero++; continue; }
        memcpy(m.xyzi + (size_t)m.voxel_count * 4, src, 4);
        m.voxel_count++;
    }
    r->off += (size_t)n * 4;
    if (outside)
        vx_log(c->d.logger, VX_LOG_WARN, "vox.voxel_outside_model",
               "XYZI chunk at byte %llu: dropped %u voxels outside the %u x %u x %u model", (unsigned long long)c->chunk_off,
               outside, m.size[0], m.size[1], m.size[2]);
    if (zero)
        vx_log(c->d.logger, VX_LOG_WARN, "vox.voxel_index_zero", "XYZI chunk at byte %llu: dropped %u voxels with colour index 0",
               (unsigned long long)c->chunk_off, zero);
    c->s.models[c->s.model_count++] = m;
    return VX_OK;
}

/* ---- Teardown's TDCZ ------------------------------------------------------------ */

/* zlib's own state (about 40 KiB a stream) comes from the reader's
 * allocator, so a --max-memory budget counts it as well. */
static voidpf tdcz_zalloc(voidpf opaque, uInt items, uInt size) {
    void* p = vx_calloc(((const vox_ctx*)opaque)->a, items, size);
    return p ? p : Z_NULL;
}

static void tdcz_zfree(voidpf opaque, voidpf p) { vx_free(((const vox_ctx*)opaque)->a, p); }

/* One inflation of a TDCZ stream (src, n at byte src_off) of the grid
 * size[0..2], x fastest, one colour index a cell. The cells come out TDCZ_WINDOW
 * at a time into win; the non-zero ones are counted (*found) and, with out
 * (room for cap records), written as x, y, z, i records. The stream is whole
 * once it has given `cells` bytes: Teardown's writer stops there, with no
 * final block and no Adler-32, so inflate never says Z_STREAM_END; whatever
 * follows those bytes is not read. */
static vx_result tdcz_pass(vox_ctx* c, const uint8_t* src, size_t n, uint64_t src_off, const uint32_t size[3],
                           size_t cells, uint8_t* win, uint8_t* out, uint64_t cap, uint64_t* found) {
    z_stream z;
    memset(&z, 0, sizeof z);
    z.zalloc = tdcz_zalloc;
    z.zfree = tdcz_zfree;
    z.opaque = c;
    *found = 0;
    int zr = inflateInit(&z);
    if (zr == Z_MEM_ERROR) return nomem(c, "the zlib inflater");
    if (zr != Z_OK) return cfail(c, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "zlib's inflateInit failed (%d)", zr);
    z.next_in = src;
    /* a chunk's content is at most UINT32_MAX bytes, which uInt holds */
    z.avail_in = n > UINT_MAX ? UINT_MAX : (uInt)n;
    size_t done = 0;
    uint64_t k = 0;
    uint32_t x = 0, y = 0, zz = 0;
    vx_result res = VX_OK;
    while (done < cells) {
        size_t want = cells - done < TDCZ_WINDOW ? cells - done : TDCZ_WINDOW;
        z.next_out = win;
        z.avail_out = (uInt)want;
        zr = inflate(&z, Z_NO_FLUSH);
        /* the bytes inflate gave are good even where it then stopped on
         * what follows them (a corrupt tail after the last cell) */
        size_t got = want - z.avail_out;
        for (size_t i = 0; i < got; i++) {
            if (win[i]) {
                if (out && k < cap) {
                    uint8_t* p = out + k * 4;
                    p[0] = (uint8_t)x, p[1] = (uint8_t)y, p[2] = (uint8_t)zz, p[3] = win[i];
                }
                k++;
            }
            if (++x == size[0]) {
                x = 0;
                if (++y == size[1]) y = 0, zz++;
            }
        }
        done += got;
        /* a refused allocation fails the read even where the cells came
         * out (inflate's window is allocated as it returns), so that a
         * memory budget refuses a file the same way every time */
        if (zr == Z_MEM_ERROR) {
            res = nomem(c, "the zlib inflater");
            break;
        }
        if (done == cells || zr == Z_OK) continue;
        uint64_t at = src_off + (n - z.avail_in);
        if (zr == Z_STREAM_END || zr == Z_BUF_ERROR)
            res = cfail(c, VX_ERR_TRUNCATED, at, "the compressed voxels end after %zu of %zu cells", done, cells);
        else
            res = cfail(c, VX_ERR_BAD_FORMAT, at, "zlib error in the compressed voxels after %zu of %zu cells: %s", done,
                        cells, z.msg ? z.msg : zr == Z_NEED_DICT ? "a preset dictionary is needed" : "invalid stream");
        break;
    }
    inflateEnd(&z);
    *found = k;
    return res;
}

/* TDCZ (Teardown): the model of the SIZE chunk before it as a dense grid,
 * content = its three sizes again (u32 each), then a zlib stream of
 * size_x * size_y * size_z colour indices, cell x + y sx + z sx sy, 0 empty.
 * Two inflations: the first counts the voxels, so max_voxels and the
 * allocator's budget see the exact record size before it is allocated. */
static vx_result chunk_tdcz(vox_ctx* c, vx_rd* r) {
    if (!c->size_pending)
        return cfail(c, VX_ERR_BAD_FORMAT, c->chunk_off, "voxels without a preceding SIZE chunk");
    c->size_pending = false;
    uint64_t at = vx_rd_pos(r);
    uint32_t v[3];
    TRY(rd_u32(c, r, &v[0], "size x"));
    TRY(rd_u32(c, r, &v[1], "size y"));
    TRY(rd_u32(c, r, &v[2], "size z"));
    if (memcmp(v, c->pending, sizeof v) != 0)
        return cfail(c, VX_ERR_BAD_FORMAT, at, "sizes %u x %u x %u differ from the %u x %u x %u of the SIZE chunk at byte %llu",
                     v[0], v[1], v[2], c->pending[0], c->pending[1], c->pending[2], (unsigned long long)c->pending_off);
    /* the records hold coordinates in bytes, as XYZI's do (max_dim may be set higher) */
    if (v[0] > 256 || v[1] > 256 || v[2] > 256)
        return cfail(c, VX_ERR_LIMIT, at, "model size %u x %u x %u: cells beyond 256 a side do not fit the voxel records",
                     v[0], v[1], v[2]);
    size_t cells;
    if (!vx_mul_size(v[0], v[1], &cells) || !vx_mul_size(cells, v[2], &cells))
        return cfail(c, VX_ERR_LIMIT, at, "model size %u x %u x %u: the cell count overflows", v[0], v[1], v[2]);
    uint64_t src_off = vx_rd_pos(r);
    const uint8_t* src = r->p + r->off;
    size_t n = vx_rd_left(r);
    r->off += n;
    TRY(grow(c, (void**)&c->s.models, &c->model_cap, c->s.model_count, 1, sizeof(vx_vox_model), "models"));
    uint8_t* win = (uint8_t*)vx_alloc(c->a, cells < TDCZ_WINDOW ? cells : TDCZ_WINDOW);
    if (!win) return nomem(c, "the voxel window");
    vx_vox_model m = {{v[0], v[1], v[2]}, 0, NULL};
    uint64_t count = 0, again = 0;
    size_t bytes = 0;
    vx_result res = tdcz_pass(c, src, n, src_off, v, cells, win, NULL, 0, &count);
    if (res == VX_OK && count > c->d.max_voxels - c->voxels_total)
        res = cfail(c, VX_ERR_LIMIT, src_off, "%llu more voxels exceed max_voxels %llu in all models",
                    (unsigned long long)count, (unsigned long long)c->d.max_voxels);
    if (res == VX_OK && count > 0) {
        if (!vx_mul_size((size_t)count, 4, &bytes) || !(m.xyzi = (uint8_t*)vx_alloc(c->a, bytes)))
            res = nomem(c, "voxels");
        else
            res = tdcz_pass(c, src, n, src_off, v, cells, win, m.xyzi, count, &again);
        /* inflate is deterministic; a difference would be a zlib fault */
        if (res == VX_OK && again != count)
            res = cfail(c, VX_ERR_BAD_FORMAT, src_off, "the stream gave %llu voxels, then %llu", (unsigned long long)count,
                        (unsigned long long)again);
    }
    vx_free(c->a, win);
    if (res != VX_OK) {
        vx_free(c->a, m.xyzi);
        return res;
    }
    m.voxel_count = (uint32_t)count; /* at most 256^3 cells */
    c->voxels_total += count;
    c->s.models[c->s.model_count++] = m;
    return VX_OK;
}

/* RGBA entry i-1 is colour index i. MagicaVoxel writes 256 entries (the
 * last one unused); Teardown writes 255 (1020 bytes), which still give
 * every index. A shorter palette leaves the indices it lacks at the
 * default palette's colours, as ogt_vox does; only a partial entry is
 * refused. */
static vx_result chunk_rgba(vox_ctx* c, vx_rd* r) {
    size_t n = vx_rd_left(r);
    if (n < 1024 && n % 4 != 0)
        return cfail(c, VX_ERR_TRUNCATED, vx_rd_pos(r) + n - n % 4,
                     "palette of %zu bytes ends inside an entry (4 bytes each, 256 at most)", n);
    size_t entries = n / 4 < 255 ? n / 4 : 255;
    memcpy(c->s.palette, vx_vox_default_palette, sizeof c->s.palette);
    c->s.palette[0] = 0;
    for (size_t i = 1; i <= entries; i++) vx_rd_u32le(r, &c->s.palette[i]);
    c->s.has_rgba = true;
    return VX_OK;
}

static vx_result chunk_imap(vox_ctx* c, vx_rd* r) {
    if (!vx_rd_bytes(r, c->s.imap, 256))
        return cfail(c, VX_ERR_TRUNCATED, vx_rd_pos(r), "index map needs 256 bytes, chunk has %zu", vx_rd_left(r));
    c->s.has_imap = true;
    return VX_OK;
}

static vx_result push_node(vox_ctx* c, const vox_node* n) {
    TRY(grow(c, (void**)&c->nodes, &c->node_cap, c->node_count, 1, sizeof *n, "scene nodes"));
    c->nodes[c->node_count++] = *n;
    return VX_OK;
}

/* _f keys select frames; they are frame numbers, never negative. */
static vx_result parse_frame_key(vox_ctx* c, vox_str v, uint32_t* f, int32_t node, uint64_t at) {
    int64_t x;
    char b[24];
    if (!parse_ints(v, &x, 1, 0, INT32_MAX))
        return cfail(c, VX_ERR_BAD_FORMAT, at, "node %d: invalid frame number _f '%s'", node, show(v, b));
    *f = (uint32_t)x;
    return VX_OK;
}

/* Every scene graph node starts with its id and an attribute dictionary;
 * _name and _hidden are the keys a node of any type may carry (a shape's
 * _hidden is read but not used: MagicaVoxel hides through transforms). */
static vx_result rd_node_head(vox_ctx* c, vx_rd* r, vox_node* n) {
    uint32_t pairs;
    TRY(rd_i32(c, r, &n->id, "node id"));
    TRY(rd_dict_count(c, r, &pairs, "node attributes"));
    for (uint32_t i = 0; i < pairs; i++) {
        vox_str k, v;
        TRY(rd_pair(c, r, &k, &v, "node attributes"));
        if (str_is(k, "_name")) copy_name(n->name, v);
        else if (str_is(k, "_hidden")) n->hidden = str_is(v, "1");
    }
    return VX_OK;
}

static vx_result chunk_ntrn(vox_ctx* c, vx_rd* r) {
    vox_node n = {.type = VX_VOX_NODE_TRN, .off = c->chunk_off};
    uint32_t pairs, frames;
    int32_t reserved;
    TRY(rd_node_head(c, r, &n));
    TRY(rd_i32(c, r, &n.child, "child node id"));
    TRY(rd_i32(c, r, &reserved, "reserved id"));
    TRY(rd_i32(c, r, &n.layer, "layer id"));
    uint64_t at = vx_rd_pos(r);
    TRY(rd_u32(c, r, &frames, "frame count"));
    if (frames == 0) return cfail(c, VX_ERR_BAD_FORMAT, at, "node %d: no frames", n.id);
    if (frames > vx_rd_left(r) / 4)
        return cfail(c, VX_ERR_TRUNCATED, at, "node %d: %u frames cannot fit in the %zu bytes left", n.id, frames,
                     vx_rd_left(r));
    TRY(grow(c, (void**)&c->keys, &c->key_cap, c->key_count, frames, sizeof(vox_key), "frames"));
    n.first = (uint32_t)c->key_count;
    n.count = frames;
    for (uint32_t fi = 0; fi < frames; fi++) {
        vox_key key = {.rot = VOX_ROT_IDENTITY};
        TRY(rd_dict_count(c, r, &pairs, "frame attributes"));
        for (uint32_t i = 0; i < pairs; i++) {
            vox_str k, v;
            int64_t x[3];
            char b[24];
            at = vx_rd_pos(r);
            TRY(rd_pair(c, r, &k, &v, "frame attributes"));
            if (str_is(k, "_r")) {
                if (!parse_ints(v, x, 1, 0, 255) || !vx_vox_rot_from_byte((uint8_t)x[0], NULL))
                    return cfail(c, VX_ERR_BAD_FORMAT, at, "node %d frame %u: invalid rotation _r '%s'", n.id, fi,
                                 show(v, b));
                key.rot = (uint8_t)x[0];
            } else if (str_is(k, "_t")) {
                if (!parse_ints(v, x, 3, INT32_MIN, INT32_MAX))
                    return cfail(c, VX_ERR_BAD_FORMAT, at, "node %d frame %u: invalid translation _t '%s'", n.id, fi,
                                 show(v, b));
                for (int j = 0; j < 3; j++) key.t[j] = (int32_t)x[j];
            } else if (str_is(k, "_f")) {
                TRY(parse_frame_key(c, v, &key.f, n.id, at));
            }
        }
        c->keys[c->key_count++] = key;
    }
    return push_node(c, &n);
}

static vx_result chunk_ngrp(vox_ctx* c, vx_rd* r) {
    vox_node n = {.type = VX_VOX_NODE_GRP, .off = c->chunk_off, .layer = -1};
    uint32_t count;
    TRY(rd_node_head(c, r, &n));
    uint64_t at = vx_rd_pos(r);
    TRY(rd_u32(c, r, &count, "child count"));
    if (count > vx_rd_left(r) / 4)
        return cfail(c, VX_ERR_TRUNCATED, at, "node %d: %u children cannot fit in the %zu bytes left", n.id, count,
                     vx_rd_left(r));
    TRY(grow(c, (void**)&c->kids, &c->kid_cap, c->kid_count, count, sizeof(int32_t), "group children"));
    n.first = (uint32_t)c->kid_count;
    n.count = count;
    for (uint32_t i = 0; i < count; i++) rd_i32(c, r, &c->kids[c->kid_count++], "child id"); /* fits: checked */
    return push_node(c, &n);
}

static vx_result chunk_nshp(vox_ctx* c, vx_rd* r) {
    vox_node n = {.type = VX_VOX_NODE_SHP, .off = c->chunk_off, .layer = -1};
    uint32_t pairs, count;
    TRY(rd_node_head(c, r, &n));
    uint64_t at = vx_rd_pos(r);
    TRY(rd_u32(c, r, &count, "model count"));
    if (count == 0) return cfail(c, VX_ERR_BAD_FORMAT, at, "node %d: no models", n.id);
    if (count > vx_rd_left(r) / 8)
        return cfail(c, VX_ERR_TRUNCATED, at, "node %d: %u models cannot fit in the %zu bytes left", n.id, count,
                     vx_rd_left(r));
    TRY(grow(c, (void**)&c->keys, &c->key_cap, c->key_count, count, sizeof(vox_key), "shape models"));
    n.first = (uint32_t)c->key_count;
    n.count = count;
    for (uint32_t mi = 0; mi < count; mi++) {
        vox_key key = {.rot = VOX_ROT_IDENTITY};
        int32_t model;
        at = vx_rd_pos(r);
        TRY(rd_i32(c, r, &model, "model id"));
        if (model < 0) return cfail(c, VX_ERR_BAD_FORMAT, at, "node %d: negative model id %d", n.id, model);
        key.model = (uint32_t)model;
        TRY(rd_dict_count(c, r, &pairs, "model attributes"));
        for (uint32_t i = 0; i < pairs; i++) {
            vox_str k, v;
            at = vx_rd_pos(r);
            TRY(rd_pair(c, r, &k, &v, "model attributes"));
            if (str_is(k, "_f")) TRY(parse_frame_key(c, v, &key.f, n.id, at));
        }
        c->keys[c->key_count++] = key;
    }
    return push_node(c, &n);
}

static vx_result chunk_layr(vox_ctx* c, vx_rd* r) {
    vx_vox_layer l = {0};
    uint32_t pairs;
    int32_t reserved;
    TRY(rd_i32(c, r, &l.id, "layer id"));
    TRY(rd_dict_count(c, r, &pairs, "layer attributes"));
    for (uint32_t i = 0; i < pairs; i++) {
        vox_str k, v;
        uint64_t at = vx_rd_pos(r);
        TRY(rd_pair(c, r, &k, &v, "layer attributes"));
        if (str_is(k, "_name")) copy_name(l.name, v);
        else if (str_is(k, "_hidden")) l.hidden = str_is(v, "1");
        else if (str_is(k, "_color")) {
            int64_t x[3];
            char b[24];
            if (!parse_ints(v, x, 3, 0, 255))
                return cfail(c, VX_ERR_BAD_FORMAT, at, "layer %d: invalid colour _color '%s'", l.id, show(v, b));
            l.rgba = (uint32_t)x[0] | (uint32_t)x[1] << 8 | (uint32_t)x[2] << 16 | 0xff000000u;
        }
    }
    TRY(rd_i32(c, r, &reserved, "reserved id"));
    TRY(grow(c, (void**)&c->s.layers, &c->layer_cap, c->s.layer_count, 1, sizeof l, "layers"));
    c->s.layers[c->s.layer_count++] = l;
    return VX_OK;
}

/* MATL ids are palette indices; MagicaVoxel writes 1..256 where 256 is the
 * index 0 slot, so ids wrap modulo 256. */
static bool material_id(vox_ctx* c, int32_t id, uint32_t* out) {
    if (id < 0 || id > 256) {
        vx_log(c->d.logger, VX_LOG_WARN, "vox.material_id", "%s chunk at byte %llu: material id %d is not 0..256, skipped",
               c->chunk_id, (unsigned long long)c->chunk_off, id);
        return false;
    }
    *out = (uint32_t)id & 0xffu;
    return true;
}

static vx_result push_material(vox_ctx* c, uint32_t id, const char* dict, size_t size) {
    if (size > UINT32_MAX) return cfail(c, VX_ERR_LIMIT, c->chunk_off, "material dictionary of %zu bytes", size);
    TRY(grow(c, (void**)&c->s.materials, &c->mat_cap, c->s.material_count, 1, sizeof(vx_vox_material), "materials"));
    char* copy = (char*)vx_alloc(c->a, size);
    if (!copy) return nomem(c, "a material");
    if (size) memcpy(copy, dict, size);
    c->s.materials[c->s.material_count++] = (vx_vox_material){id, (uint32_t)size, copy};
    return VX_OK;
}

static vx_result chunk_matl(vox_ctx* c, vx_rd* r) {
    int32_t id;
    uint32_t pairs, mid;
    TRY(rd_i32(c, r, &id, "material id"));
    vx_rd start = *r;
    size_t size = 0;
    TRY(rd_dict_count(c, r, &pairs, "material properties"));
    for (uint32_t i = 0; i < pairs; i++) {
        vox_str k, v;
        uint64_t at = vx_rd_pos(r);
        TRY(rd_pair(c, r, &k, &v, "material properties"));
        if (memchr(k.p, 0, k.n) || memchr(v.p, 0, v.n))
            return cfail(c, VX_ERR_BAD_FORMAT, at, "material %d: property with a NUL byte", id);
        size += (size_t)k.n + v.n + 2; /* bounded by the chunk size plus 2 per pair */
    }
    if (!material_id(c, id, &mid)) return VX_OK;
    if (size > UINT32_MAX) return cfail(c, VX_ERR_LIMIT, c->chunk_off, "material dictionary of %zu bytes", size);
    TRY(grow(c, (void**)&c->s.materials, &c->mat_cap, c->s.material_count, 1, sizeof(vx_vox_material), "materials"));
    char* dict = (char*)vx_alloc(c->a, size);
    if (!dict) return nomem(c, "a material");
    /* second pass over bytes the first pass validated */
    size_t o = 0;
    vx_rd_u32le(&start, &pairs);
    for (uint32_t i = 0; i < pairs; i++) {
        vox_str s2[2];
        for (int j = 0; j < 2; j++) {
            rd_str(c, &start, &s2[j], "");
            memcpy(dict + o, s2[j].p, s2[j].n);
            o += s2[j].n;
            dict[o++] = 0;
        }
    }
    c->s.materials[c->s.material_count++] = (vx_vox_material){mid, (uint32_t)size, dict};
    return VX_OK;
}

/* The old MATT chunk becomes the MATL dictionary it corresponds to. */
static vx_result chunk_matt(vox_ctx* c, vx_rd* r) {
    static const char* const types[] = {"_diffuse", "_metal", "_glass", "_emit"};
    static const char* const props[] = {"_plastic", "_rough", "_spec", "_ior", "_att", "_flux", "_glow"};
    int32_t id;
    uint32_t type, bits, mid;
    float weight;
    TRY(rd_i32(c, r, &id, "material id"));
    uint64_t at = vx_rd_pos(r);
    TRY(rd_u32(c, r, &type, "material type"));
    if (type > 3) return cfail(c, VX_ERR_BAD_FORMAT, at, "material %d: unknown type %u", id, type);
    if (!vx_rd_f32le(r, &weight))
        return cfail(c, VX_ERR_TRUNCATED, vx_rd_pos(r), "material %d: weight missing", id);
    TRY(rd_u32(c, r, &bits, "property bits"));
    char dict[512];
    size_t o = 0;
    o += (size_t)snprintf(dict + o, sizeof dict - o, "_type%c%s%c_weight%c%g%c", 0, types[type], 0, 0, (double)weight, 0);
    for (int b = 0; b < 7; b++) {
        if (!(bits & (1u << b))) continue;
        float v;
        if (!vx_rd_f32le(r, &v))
            return cfail(c, VX_ERR_TRUNCATED, vx_rd_pos(r), "material %d: value of property bit %d missing", id, b);
        o += (size_t)snprintf(dict + o, sizeof dict - o, "%s%c%g%c", props[b], 0, (double)v, 0);
    }
    if (bits & 0x80u) o += (size_t)snprintf(dict + o, sizeof dict - o, "_total_power%c1%c", 0, 0);
    if (!material_id(c, id, &mid)) return VX_OK;
    return push_material(c, mid, dict, o);
}

static vx_result chunk_note(vox_ctx* c, vx_rd* r) {
    uint32_t n;
    uint64_t at = vx_rd_pos(r);
    TRY(rd_u32(c, r, &n, "note count"));
    if (n > vx_rd_left(r) / 4)
        return cfail(c, VX_ERR_TRUNCATED, at, "%u notes cannot fit in the %zu bytes left", n, vx_rd_left(r));
    for (uint32_t i = 0; i < n; i++) {
        vox_str s;
        TRY(rd_str(c, r, &s, "note"));
    }
    c->s.note_count = n > UINT32_MAX - c->s.note_count ? UINT32_MAX : c->s.note_count + n;
    return VX_OK;
}

static vx_result read_chunk(vox_ctx* c, const uint8_t id[4], vx_rd* r) {
    if (!memcmp(id, "SIZE", 4)) return chunk_size(c, r);
    if (!memcmp(id, "XYZI", 4)) return chunk_xyzi(c, r);
    if (!memcmp(id, "TDCZ", 4)) return chunk_tdcz(c, r);
    if (c->size_pending)
        return cfail(c, VX_ERR_BAD_FORMAT, c->chunk_off, "expected the XYZI or TDCZ chunk of the SIZE chunk at byte %llu",
                     (unsigned long long)c->pending_off);
    if (!memcmp(id, "RGBA", 4)) return chunk_rgba(c, r);
    if (!memcmp(id, "nTRN", 4)) return chunk_ntrn(c, r);
    if (!memcmp(id, "nGRP", 4)) return chunk_ngrp(c, r);
    if (!memcmp(id, "nSHP", 4)) return chunk_nshp(c, r);
    if (!memcmp(id, "LAYR", 4)) return chunk_layr(c, r);
    if (!memcmp(id, "MATL", 4)) return chunk_matl(c, r);
    if (!memcmp(id, "MATT", 4)) return chunk_matt(c, r);
    if (!memcmp(id, "IMAP", 4)) return chunk_imap(c, r);
    if (!memcmp(id, "NOTE", 4)) return chunk_note(c, r);
    if (!memcmp(id, "PACK", 4)) {
        TRY(rd_u32(c, r, &c->pack_models, "model count"));
        c->have_pack = true;
        return VX_OK;
    }
    if (!memcmp(id, "rOBJ", 4)) {
        TRY(skip_dict(c, r, "render attributes"));
        c->s.robj_count++;
        return VX_OK;
    }
    if (!memcmp(id, "rCAM", 4)) {
        int32_t cam;
        TRY(rd_i32(c, r, &cam, "camera id"));
        TRY(skip_dict(c, r, "camera attributes"));
        c->s.camera_count++;
        return VX_OK;
    }
    if (!memcmp(id, "META", 4)) return skip_dict(c, r, "meta attributes");
    vx_log(c->d.logger, VX_LOG_WARN, "vox.unknown_chunk", "%s chunk at byte %llu: unknown chunk skipped (%zu bytes)",
           c->chunk_id, (unsigned long long)c->chunk_off, vx_rd_left(r));
    return VX_OK;
}

static vx_result read_children(vox_ctx* c, vx_rd* r) {
    while (vx_rd_left(r) > 0) {
        uint64_t at = vx_rd_pos(r);
        uint8_t id[4];
        uint32_t n = 0, m = 0;
        if (vx_rd_left(r) < 12)
            return vx_fail(c->err, VX_ERR_TRUNCATED, at, "MAIN chunk at byte 8: chunk header at byte %llu needs 12 bytes, %zu left",
                           (unsigned long long)at, vx_rd_left(r));
        vx_rd_bytes(r, id, 4);
        vx_rd_u32le(r, &n);
        vx_rd_u32le(r, &m);
        set_chunk(c, id, at);
        vx_rd content;
        if (!vx_rd_sub(r, n, &content))
            return cfail(c, VX_ERR_TRUNCATED, at + 4, "content of %u bytes declared, %zu bytes left in MAIN", n,
                         vx_rd_left(r));
        if (!vx_rd_skip(r, m))
            return cfail(c, VX_ERR_TRUNCATED, at + 8, "children of %u bytes declared, %zu bytes left in MAIN", m,
                         vx_rd_left(r));
        TRY(read_chunk(c, id, &content));
    }
    if (c->size_pending) {
        c->chunk_off = c->pending_off;
        memcpy(c->chunk_id, "SIZE", 5);
        return cfail(c, VX_ERR_BAD_FORMAT, c->pending_off, "no XYZI or TDCZ chunk follows");
    }
    return VX_OK;
}

/* ---- scene graph ---------------------------------------------------------------- */

static int cmp_idmap(const void* a, const void* b) {
    const vox_idmap *x = (const vox_idmap*)a, *y = (const vox_idmap*)b;
    if (x->id != y->id) return x->id < y->id ? -1 : 1;
    return x->node < y->node ? -1 : x->node > y->node;
}

static int64_t find_id(const vox_idmap* map, size_t n, int32_t id) {
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (map[mid].id < id) lo = mid + 1;
        else hi = mid;
    }
    return lo < n && map[lo].id == id ? (int64_t)lo : -1;
}

static int64_t find_node(vox_ctx* c, int32_t id) {
    int64_t k = find_id(c->idmap, c->node_count, id);
    return k < 0 ? -1 : (int64_t)c->idmap[k].node;
}

static bool layer_hidden(vox_ctx* c, int32_t id) {
    int64_t k = find_id(c->layermap, c->layermap_count, id);
    return k >= 0 && c->layermap[k].node != 0;
}

/* The last key at or before frame; the earliest key when all are later. */
static const vox_key* pick_key(vox_ctx* c, const vox_node* n) {
    const vox_key *best = NULL, *first = NULL;
    for (uint32_t i = 0; i < n->count; i++) {
        const vox_key* k = &c->keys[n->first + i];
        if (k->f <= c->d.frame && (!best || k->f >= best->f)) best = k;
        if (!first || k->f < first->f) first = k;
    }
    return best ? best : first;
}

/* A node may have several parents (MagicaVoxel's group instances: several
 * transforms pointing at one group, each placing a copy of it); only a node
 * on the current path closes a cycle. */
static vx_result enter(vox_ctx* c, const vox_node* parent, vox_node* n) {
    if (n->state != NODE_ON_PATH) {
        n->state = NODE_ON_PATH;
        return VX_OK;
    }
    set_node_chunk(c, parent);
    return cfail(c, VX_ERR_BAD_FORMAT, parent->off, "node %d: child node %d closes a cycle", parent->id, n->id);
}

static vx_result visit_trn(vox_ctx* c, uint32_t ni, int depth, const int32_t R[9], const int64_t t[3], bool hidden) {
    vox_node* n = &c->nodes[ni];
    if (depth > VOX_MAX_DEPTH) {
        set_node_chunk(c, n);
        return cfail(c, VX_ERR_BAD_FORMAT, n->off, "node %d: scene graph deeper than %d levels", n->id, VOX_MAX_DEPTH);
    }
    if (++c->visits > VOX_MAX_VISITS + c->node_count) {
        set_node_chunk(c, n);
        return cfail(c, VX_ERR_LIMIT, n->off, "node %d: shared groups place more than %llu transform nodes", n->id,
                     (unsigned long long)(VOX_MAX_VISITS + c->node_count));
    }
    /* this node's keys and its child's (a shape's models, a group's kids) */
    int64_t ci = find_node(c, n->child);
    uint64_t w = 1u + n->count, base = (uint64_t)c->node_count + c->key_count;
    if (ci >= 0) w += c->nodes[ci].count;
    c->work += w;
    if (c->work > base) {
        c->extra_work += c->work - w >= base ? w : c->work - base;
        if (c->extra_work > VOX_MAX_EXTRA_WORK) {
            set_node_chunk(c, n);
            return cfail(c, VX_ERR_LIMIT, n->off,
                         "node %d: shared groups make the scene graph's walk over all frames longer than %llu node "
                         "visits and keys beyond the file's own", n->id, (unsigned long long)VOX_MAX_EXTRA_WORK);
        }
    }
    const vox_key* k = pick_key(c, n);
    int32_t Rl[9], Rn[9];
    int64_t tn[3];
    vx_vox_rot_from_byte(k->rot, Rl);
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) {
            int32_t s = 0;
            for (int q = 0; q < 3; q++) s += R[i * 3 + q] * Rl[q * 3 + j];
            Rn[i * 3 + j] = s;
        }
        tn[i] = t[i];
        for (int q = 0; q < 3; q++) tn[i] += (int64_t)R[i * 3 + q] * k->t[q];
    }
    for (int i = 0; i < 3; i++) {
        if (tn[i] > VOX_MAX_T || tn[i] < -VOX_MAX_T) {
            set_node_chunk(c, n);
            return cfail(c, VX_ERR_LIMIT, n->off, "node %d: translation %lld %lld %lld beyond +-%d", n->id,
                         (long long)tn[0], (long long)tn[1], (long long)tn[2], VOX_MAX_T);
        }
    }
    bool h = hidden || n->hidden || layer_hidden(c, n->layer);
    if (ci < 0) {
        set_node_chunk(c, n);
        return cfail(c, VX_ERR_BAD_FORMAT, n->off, "node %d: child node %d does not exist", n->id, n->child);
    }
    vox_node* ch = &c->nodes[ci];
    if (ch->type == VX_VOX_NODE_TRN) {
        set_node_chunk(c, n);
        return cfail(c, VX_ERR_BAD_FORMAT, n->off, "node %d: child node %d is a transform node, expected a group or shape",
                     n->id, ch->id);
    }
    if (ch->type == VX_VOX_NODE_SHP) {
        /* Shapes are how MagicaVoxel instances a model: several transforms
         * may point at one. They are leaves, so sharing cannot multiply. */
        if (!h || c->d.keep_hidden) {
            if (c->s.instance_count >= VX_VOX_MAX_INSTANCES) {
                set_node_chunk(c, n);
                return cfail(c, VX_ERR_LIMIT, n->off, "node %d: the scene graph places more than %u shapes", n->id,
                             VX_VOX_MAX_INSTANCES);
            }
            TRY(grow(c, (void**)&c->s.instances, &c->inst_cap, c->s.instance_count, 1, sizeof(vx_vox_instance),
                     "instances"));
            vx_vox_instance* in = &c->s.instances[c->s.instance_count++];
            memset(in, 0, sizeof *in);
            in->model = pick_key(c, ch)->model;
            memcpy(in->rot, Rn, sizeof Rn);
            for (int i = 0; i < 3; i++) in->t[i] = (int32_t)tn[i];
            in->layer = n->layer;
            /* its own layer's flag stays with the layer (an editor's layer
             * show shows it, a writer does not hide its transform too) */
            in->hidden = hidden || n->hidden;
            memcpy(in->name, n->name, sizeof in->name);
        }
    } else {
        /* a group reached again (another transform's copy) is walked again */
        TRY(enter(c, n, ch));
        bool hg = h || ch->hidden;
        for (uint32_t i = 0; i < ch->count; i++) {
            int32_t kid = c->kids[ch->first + i];
            int64_t gi = find_node(c, kid);
            if (gi < 0 || c->nodes[gi].type != VX_VOX_NODE_TRN) {
                set_node_chunk(c, ch);
                return cfail(c, VX_ERR_BAD_FORMAT, ch->off, "node %d: child node %d %s", ch->id, kid,
                             gi < 0 ? "does not exist" : "is not a transform node");
            }
            TRY(enter(c, ch, &c->nodes[gi]));
            TRY(visit_trn(c, (uint32_t)gi, depth + 1, Rn, tn, hg));
            c->nodes[gi].state = NODE_DONE;
        }
        ch->state = NODE_DONE;
    }
    return VX_OK;
}

/* Flattens the graph for c->d.frame into s->instances (from scratch). */
static vx_result flatten(vox_ctx* c, int64_t root) {
    static const int32_t I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    static const int64_t zero[3] = {0, 0, 0};
    for (size_t i = 0; i < c->node_count; i++) c->nodes[i].state = NODE_UNSEEN;
    c->s.instance_count = 0;
    c->visits = 0;
    c->work = 0;
    c->nodes[root].state = NODE_ON_PATH;
    return visit_trn(c, (uint32_t)root, 0, I, zero, false);
}

/* Frames of the animation: the largest _f key + 1 (every node's keys: a
 * node's keys hold until its next one, so the last key starts the last
 * frame that differs). */
static uint64_t graph_frames(const vox_ctx* c) {
    uint64_t last = 0;
    for (size_t i = 0; i < c->key_count; i++)
        if (c->keys[i].f > last) last = c->keys[i].f;
    return last + 1;
}

/* all_frames: every frame flattened into frame_instances (root < 0: no
 * scene graph, the one instance shows model f), then `instances` is frame
 * d.frame again. */
static vx_result flatten_all(vox_ctx* c, int64_t root) {
    vx_vox_scene* s = &c->s;
    uint32_t want = c->d.frame, F = s->frame_count, n = 0;
    for (uint32_t f = 0; f < F; f++) {
        c->d.frame = f;
        if (root >= 0) {
            TRY(flatten(c, root));
        } else { /* no scene graph: frame f shows model f */
            s->instances[0].model = f;
        }
        if (f == 0) {
            n = s->instance_count;
            if ((uint64_t)F * n > VX_VOX_FRAMES_MAX_BYTES / sizeof(vx_vox_instance))
                return vx_fail(c->err, VX_ERR_LIMIT, VX_NO_OFFSET, "%u frames of %u instances exceed %llu bytes (convert single frames)",
                               F, n, (unsigned long long)VX_VOX_FRAMES_MAX_BYTES);
            s->frame_instances = (vx_vox_instance*)vx_calloc(c->a, (size_t)F * n + 1, sizeof(vx_vox_instance));
            if (!s->frame_instances) return nomem(c, "the animation frames");
        } else if (s->instance_count != n) { /* the same graph: cannot happen, but never index past */
            return vx_fail(c->err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "frame %u has %u instances, frame 0 has %u", f, s->instance_count, n);
        }
        if (n) memcpy(s->frame_instances + (size_t)f * n, s->instances, (size_t)n * sizeof(vx_vox_instance));
    }
    c->d.frame = want;
    if (want < F) {
        if (n) memcpy(s->instances, s->frame_instances + (size_t)want * n, (size_t)n * sizeof(vx_vox_instance));
        return VX_OK;
    }
    if (root >= 0) return flatten(c, root);
    s->instances[0].model = want; /* checked by the caller */
    return VX_OK;
}

static vx_result build_instances(vox_ctx* c) {
    vx_vox_scene* s = &c->s;
    s->frame_count = 1;
    memcpy(c->chunk_id, "MAIN", 5);
    c->chunk_off = 8;
    if (c->have_pack && c->pack_models != s->model_count)
        vx_log(c->d.logger, VX_LOG_WARN, "vox.pack_count", "PACK chunk declares %u models, the file has %u", c->pack_models,
               s->model_count);
    if (c->node_count == 0) {
        if (s->model_count == 0 && c->d.frame == 0) return VX_OK;
        if (c->d.frame >= s->model_count)
            return vx_fail(c->err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                           "frame %u: the file has %u models and no scene graph", c->d.frame, s->model_count);
        TRY(grow(c, (void**)&s->instances, &c->inst_cap, 0, 1, sizeof(vx_vox_instance), "instances"));
        vx_vox_instance* in = &s->instances[s->instance_count++];
        memset(in, 0, sizeof *in);
        in->model = c->d.frame;
        in->rot[0] = in->rot[4] = in->rot[8] = 1;
        in->layer = -1;
        s->frame_count = s->model_count ? s->model_count : 1;
        if (!c->d.all_frames || s->frame_count < 2) return VX_OK;
        if (s->frame_count > VX_VOX_MAX_FRAMES)
            return vx_fail(c->err, VX_ERR_LIMIT, VX_NO_OFFSET, "%u frames (models without a scene graph), the limit is %u",
                           s->frame_count, VX_VOX_MAX_FRAMES);
        return flatten_all(c, -1);
    }
    s->has_scene_graph = true;
    s->node_count = c->node_count > UINT32_MAX ? UINT32_MAX : (uint32_t)c->node_count;
    c->idmap = (vox_idmap*)vx_calloc(c->a, c->node_count, sizeof(vox_idmap));
    if (!c->idmap) return nomem(c, "the node table");
    for (size_t i = 0; i < c->node_count; i++) c->idmap[i] = (vox_idmap){c->nodes[i].id, (uint32_t)i};
    qsort(c->idmap, c->node_count, sizeof(vox_idmap), cmp_idmap);
    for (size_t i = 1; i < c->node_count; i++) {
        if (c->idmap[i].id == c->idmap[i - 1].id) {
            const vox_node* n = &c->nodes[c->idmap[i].node];
            set_node_chunk(c, n);
            return cfail(c, VX_ERR_BAD_FORMAT, n->off, "node id %d is used by two nodes", n->id);
        }
    }
    for (size_t i = 0; i < c->node_count; i++) {
        const vox_node* n = &c->nodes[i];
        if (n->type != VX_VOX_NODE_SHP) continue;
        for (uint32_t k = 0; k < n->count; k++) {
            if (c->keys[n->first + k].model >= s->model_count) {
                set_node_chunk(c, n);
                return cfail(c, VX_ERR_BAD_FORMAT, n->off, "node %d: model id %u out of range (%u models)", n->id,
                             c->keys[n->first + k].model, s->model_count);
            }
        }
    }
    if (s->layer_count) {
        c->layermap = (vox_idmap*)vx_calloc(c->a, s->layer_count, sizeof(vox_idmap));
        if (!c->layermap) return nomem(c, "the layer table");
        for (uint32_t i = 0; i < s->layer_count; i++) c->layermap[i] = (vox_idmap){s->layers[i].id, s->layers[i].hidden};
        qsort(c->layermap, s->layer_count, sizeof(vox_idmap), cmp_idmap);
        /* several LAYR chunks with one id: hidden if any says so */
        size_t o = 0;
        for (uint32_t i = 0; i < s->layer_count; i++) {
            if (o && c->layermap[o - 1].id == c->layermap[i].id) c->layermap[o - 1].node |= c->layermap[i].node;
            else c->layermap[o++] = c->layermap[i];
        }
        c->layermap_count = o;
    }
    int64_t root = find_node(c, 0);
    if (root < 0 || c->nodes[root].type != VX_VOX_NODE_TRN)
        return vx_fail(c->err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "scene graph: node 0 %s",
                       root < 0 ? "(the root) does not exist" : "(the root) is not a transform node");
    uint64_t frames = graph_frames(c);
    s->frame_count = frames > UINT32_MAX ? UINT32_MAX : (uint32_t)frames;
    if (!c->d.all_frames || frames < 2) return flatten(c, root);
    if (frames > VX_VOX_MAX_FRAMES)
        return vx_fail(c->err, VX_ERR_LIMIT, VX_NO_OFFSET, "keyframes up to frame %llu, the limit is %u frames",
                       (unsigned long long)(frames - 1), VX_VOX_MAX_FRAMES);
    return flatten_all(c, root);
}

/* ---- entry points ------------------------------------------------------------------ */

void vx_vox_scene_free(vx_vox_scene* s) {
    if (!s) return;
    const vx_allocator* a = s->alloc;
    for (uint32_t i = 0; i < s->model_count; i++) vx_free(a, s->models[i].xyzi);
    for (uint32_t i = 0; i < s->material_count; i++) vx_free(a, s->materials[i].dict);
    vx_free(a, s->models);
    vx_free(a, s->instances);
    vx_free(a, s->frame_instances);
    vx_free(a, s->groups);
    vx_free(a, s->frame_groups);
    vx_free(a, s->layers);
    vx_free(a, s->materials);
    memset(s, 0, sizeof *s);
}

static void ctx_free_temp(vox_ctx* c) {
    vx_free(c->a, c->nodes);
    vx_free(c->a, c->keys);
    vx_free(c->a, c->kids);
    vx_free(c->a, c->idmap);
    vx_free(c->a, c->layermap);
}

static vx_result read_file_body(vox_ctx* c, const void* data, size_t size) {
    vx_rd r = vx_rd_make(data, size);
    uint8_t magic[4], id[4];
    uint32_t version, n, m;
    if (size < 8)
        return vx_fail(c->err, VX_ERR_TRUNCATED, 0, "file of %zu bytes is shorter than the 8-byte .vox header", size);
    vx_rd_bytes(&r, magic, 4);
    vx_rd_u32le(&r, &version);
    if (memcmp(magic, "VOX ", 4) != 0)
        return vx_fail(c->err, VX_ERR_BAD_FORMAT, 0, "not a MagicaVoxel file: magic is not 'VOX '");
    if (version < 150)
        return vx_fail(c->err, VX_ERR_UNSUPPORTED, 4, "file version %u is older than 150", version);
    if (version != 150 && version != 200)
        vx_log(c->d.logger, VX_LOG_WARN, "vox.version", "file version %u is not 150 or 200; reading it as 200", version);
    c->s.version = version;
    if (vx_rd_left(&r) < 12)
        return vx_fail(c->err, VX_ERR_TRUNCATED, 8, "MAIN chunk header needs 12 bytes, %zu left", vx_rd_left(&r));
    vx_rd_bytes(&r, id, 4);
    vx_rd_u32le(&r, &n);
    vx_rd_u32le(&r, &m);
    set_chunk(c, id, 8);
    if (memcmp(id, "MAIN", 4) != 0) return cfail(c, VX_ERR_BAD_FORMAT, 8, "the first chunk must be MAIN");
    vx_rd children;
    if (!vx_rd_skip(&r, n))
        return cfail(c, VX_ERR_TRUNCATED, 12, "content of %u bytes declared, %zu bytes left", n, vx_rd_left(&r));
    if (!vx_rd_sub(&r, m, &children))
        return cfail(c, VX_ERR_TRUNCATED, 16, "children of %u bytes declared, %zu bytes left", m, vx_rd_left(&r));
    if (vx_rd_left(&r))
        vx_log(c->d.logger, VX_LOG_WARN, "vox.trailing_bytes", "%zu bytes after the MAIN chunk ignored", vx_rd_left(&r));
    TRY(read_children(c, &children));
    return build_instances(c);
}

vx_result vx_vox_read(const vx_vox_read_desc* desc, const void* data, size_t size, vx_vox_scene* out, vx_error* err) {
    if (!out || (!data && size)) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "vx_vox_read: null argument");
    vox_ctx c;
    memset(&c, 0, sizeof c);
    if (desc) c.d = *desc;
    if (c.d.max_dim == 0) c.d.max_dim = 256;
    if (c.d.max_voxels == 0) c.d.max_voxels = (uint64_t)1 << 28;
    c.a = c.d.alloc;
    c.err = err;
    c.s.alloc = c.a;
    memcpy(c.s.palette, vx_vox_default_palette, sizeof c.s.palette);
    memcpy(c.chunk_id, "file", 5);
    vx_result r = read_file_body(&c, data ? data : "", size);
    ctx_free_temp(&c);
    if (r != VX_OK) {
        vx_vox_scene_free(&c.s);
        return r;
    }
    *out = c.s;
    return VX_OK;
}

vx_result vx_vox_read_file(const vx_vox_read_desc* desc, const char* path, vx_vox_scene* out, vx_error* err) {
    if (!path || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "vx_vox_read_file: null argument");
    const vx_allocator* a = desc ? desc->alloc : NULL;
    uint8_t* data;
    size_t size;
    vx_result r = vx_file_read(path, a, 0, &data, &size, err);
    if (r == VX_OK) {
        r = vx_vox_read(desc, data, size, out, err);
        vx_free(a, data);
    }
    if (r != VX_OK) vx_error_prefix(err, path);
    return r;
}

/* ---- validation ------------------------------------------------------------------------ */

static bool has_nul(const char* s, size_t n) { return memchr(s, 0, n) != NULL; }

/* A transform node's own checks, shared by shapes and groups ("instance" or
 * "group" in the message): a signed permutation, a translation within the
 * reader's limit, a NUL-terminated name. */
static vx_result check_node(const int32_t rot[9], const int32_t t[3], const char* name, size_t name_size, const char* what,
                            uint32_t f, uint32_t i, vx_error* err) {
    if (!vx_vox_rot_to_byte(rot, NULL))
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "frame %u %s %u: rotation is not a signed permutation", f, what, i);
    for (int k = 0; k < 3; k++)
        if (t[k] > VOX_MAX_T || t[k] < -VOX_MAX_T)
            return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "frame %u %s %u: translation %d beyond +-%d", f, what, i, t[k],
                           VOX_MAX_T);
    if (!has_nul(name, name_size))
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "%s %u: name is not NUL-terminated", what, i);
    return VX_OK;
}

vx_result vx_vox_validate(const vx_vox_scene* s, vx_error* err) {
    if (!s) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "vx_vox_validate: null scene");
    if ((s->model_count && !s->models) || (s->instance_count && !s->instances) || (s->layer_count && !s->layers) ||
        (s->material_count && !s->materials) || (s->group_count && !s->groups))
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "scene: a non-zero count with a null array");
    for (uint32_t i = 0; i < s->model_count; i++) {
        const vx_vox_model* m = &s->models[i];
        for (int k = 0; k < 3; k++)
            if (m->size[k] < 1 || m->size[k] > 256)
                return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "model %u: size %u x %u x %u is not 1..256", i,
                               m->size[0], m->size[1], m->size[2]);
        if (m->voxel_count && !m->xyzi)
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "model %u: %u voxels and no data", i, m->voxel_count);
        if (m->voxel_count > (uint32_t)INT32_MAX / 4)
            return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "model %u: %u voxels do not fit in a chunk", i, m->voxel_count);
        for (uint32_t v = 0; v < m->voxel_count; v++) {
            const uint8_t* p = m->xyzi + (size_t)v * 4;
            if (p[0] >= m->size[0] || p[1] >= m->size[1] || p[2] >= m->size[2] || p[3] == 0)
                return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                               "model %u voxel %u: (%u, %u, %u) index %u is outside the model or index 0", i, v, p[0], p[1],
                               p[2], p[3]);
        }
    }
    bool anim = s->frame_count > 1 && s->frame_instances;
    if (anim && s->frame_count > VX_VOX_MAX_FRAMES)
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "%u frames, the limit is %u", s->frame_count, VX_VOX_MAX_FRAMES);
    uint64_t records = (uint64_t)(anim ? s->frame_count : 1) * s->instance_count;
    const vx_vox_instance* all = anim ? s->frame_instances : s->instances;
    for (uint64_t j = 0; j < records; j++) {
        const vx_vox_instance* in = &all[j];
        uint32_t i = (uint32_t)(j % s->instance_count), f = (uint32_t)(j / s->instance_count);
        if (in->model >= s->model_count)
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "frame %u instance %u: model %u out of range (%u models)", f, i,
                           in->model, s->model_count);
        vx_result r = check_node(in->rot, in->t, in->name, sizeof in->name, "instance", f, i, err);
        if (r != VX_OK) return r;
        if (in->group > s->group_count)
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "frame %u instance %u: group %u out of range (%u groups)", f, i,
                           in->group, s->group_count);
        /* the graph holds one name, layer, hidden flag and parent per shape */
        if (f && (strcmp(in->name, all[i].name) || in->layer != all[i].layer || in->hidden != all[i].hidden ||
                  in->group != all[i].group))
            return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET,
                           "frame %u instance %u: name, layer, hidden flag or group differs from frame 0 (.vox keeps one per shape)",
                           f, i);
        if (in->group) {
            /* the reader's composed translation: R_group t + t_group */
            const vx_vox_group* g = (anim && s->frame_groups ? s->frame_groups + (size_t)f * s->group_count : s->groups) +
                                    (in->group - 1);
            for (int r = 0; r < 3; r++) {
                int64_t w = g->t[r];
                for (int k = 0; k < 3; k++) w += (int64_t)g->rot[r * 3 + k] * in->t[k];
                if (w > VOX_MAX_T || w < -VOX_MAX_T)
                    return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "frame %u instance %u: translation %lld in its group beyond +-%d",
                                   f, i, (long long)w, VOX_MAX_T);
            }
        }
    }
    uint64_t grecords = (uint64_t)(anim && s->frame_groups ? s->frame_count : 1) * s->group_count;
    const vx_vox_group* gall = anim && s->frame_groups ? s->frame_groups : s->groups;
    for (uint64_t j = 0; j < grecords; j++) {
        const vx_vox_group* g = &gall[j];
        uint32_t i = (uint32_t)(j % s->group_count), f = (uint32_t)(j / s->group_count);
        vx_result r = check_node(g->rot, g->t, g->name, sizeof g->name, "group", f, i, err);
        if (r != VX_OK) return r;
        if (f && (strcmp(g->name, gall[i].name) || g->layer != gall[i].layer || g->hidden != gall[i].hidden))
            return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET,
                           "frame %u group %u: name, layer or hidden flag differs from frame 0 (.vox keeps one per group)", f, i);
    }
    for (uint32_t i = 0; i < s->layer_count; i++)
        if (!has_nul(s->layers[i].name, sizeof s->layers[i].name))
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "layer %u: name is not NUL-terminated", i);
    for (uint32_t i = 0; i < s->material_count; i++) {
        const vx_vox_material* m = &s->materials[i];
        if (m->id > 255)
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "material %u: id %u is not 0..255", i, m->id);
        if (m->dict_size && !m->dict)
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "material %u: dictionary missing", i);
        /* whole key/value pairs of NUL-terminated strings */
        uint32_t strings = 0;
        for (uint32_t k = 0; k < m->dict_size; k++) strings += m->dict[k] == 0;
        if ((m->dict_size && m->dict[m->dict_size - 1] != 0) || strings % 2 != 0)
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                           "material %u: dictionary is not NUL-terminated key/value pairs", i);
    }
    return VX_OK;
}
