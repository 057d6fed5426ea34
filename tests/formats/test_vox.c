/* tests/formats/test_vox.c - MagicaVoxel reader and writer: corpus round
 * trips, placement against a double-precision reference, synthetic scene
 * graphs, corrupt input (truncations, flips, overflowing sizes, graph errors)
 * and allocation failures. */
#define _DEFAULT_SOURCE
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <zlib.h>

#include "formats/vox.h"
#include "tests/fail_alloc.h"
#include "tests/test.h"

/* ---- chunk builder (independent of the writer under test) ---------------- */

static inline void tb_u32(vx_buf* b, uint32_t v) { vx_buf_u32le(b, v); }
static inline void tb_str(vx_buf* b, const char* s) {
    tb_u32(b, (uint32_t)strlen(s));
    vx_buf_append(b, s, strlen(s));
}
/* n pairs of const char* key, value */
static inline void tb_dict(vx_buf* b, int n, ...) {
    va_list ap;
    va_start(ap, n);
    tb_u32(b, (uint32_t)n);
    for (int i = 0; i < 2 * n; i++) tb_str(b, va_arg(ap, const char*));
    va_end(ap);
}
static inline size_t tb_begin(vx_buf* b, const char* id) {
    size_t at = b->size;
    vx_buf_append(b, id, 4);
    tb_u32(b, 0);
    tb_u32(b, 0);
    return at;
}
static inline void tb_end(vx_buf* b, size_t at) { vx_buf_put_u32le(b->data + at + 4, (uint32_t)(b->size - at - 12)); }
static inline void tb_file(vx_buf* b, uint32_t version) {
    memset(b, 0, sizeof *b);
    vx_buf_append(b, "VOX ", 4);
    tb_u32(b, version);
    tb_begin(b, "MAIN");
}
static inline void tb_finish(vx_buf* b) { vx_buf_put_u32le(b->data + 16, (uint32_t)(b->size - 20)); }
static inline void tb_model(vx_buf* b, uint32_t sx, uint32_t sy, uint32_t sz, uint32_t n, const uint8_t* xyzi) {
    size_t at = tb_begin(b, "SIZE");
    tb_u32(b, sx);
    tb_u32(b, sy);
    tb_u32(b, sz);
    tb_end(b, at);
    at = tb_begin(b, "XYZI");
    tb_u32(b, n);
    vx_buf_append(b, xyzi, (size_t)n * 4);
    tb_end(b, at);
}
/* nTRN with one frame; rot < 0 leaves _r out. name may be NULL. */
static inline void tb_trn(vx_buf* b, int32_t id, int32_t child, int32_t layer, bool hidden, const char* name, int rot,
                          int tx, int ty, int tz) {
    size_t at = tb_begin(b, "nTRN");
    tb_u32(b, (uint32_t)id);
    if (name && hidden) tb_dict(b, 2, "_name", name, "_hidden", "1");
    else if (name) tb_dict(b, 1, "_name", name);
    else if (hidden) tb_dict(b, 1, "_hidden", "1");
    else tb_dict(b, 0);
    tb_u32(b, (uint32_t)child);
    tb_u32(b, UINT32_MAX);
    tb_u32(b, (uint32_t)layer);
    tb_u32(b, 1);
    char r[16], t[64];
    snprintf(r, sizeof r, "%d", rot);
    snprintf(t, sizeof t, "%d %d %d", tx, ty, tz);
    if (rot >= 0) tb_dict(b, 2, "_r", r, "_t", t);
    else tb_dict(b, 1, "_t", t);
    tb_end(b, at);
}
static inline void tb_grp(vx_buf* b, int32_t id, bool hidden, int n, const int32_t* kids) {
    size_t at = tb_begin(b, "nGRP");
    tb_u32(b, (uint32_t)id);
    if (hidden) tb_dict(b, 1, "_hidden", "1");
    else tb_dict(b, 0);
    tb_u32(b, (uint32_t)n);
    for (int i = 0; i < n; i++) tb_u32(b, (uint32_t)kids[i]);
    tb_end(b, at);
}
static inline void tb_shp(vx_buf* b, int32_t id, int32_t model) {
    size_t at = tb_begin(b, "nSHP");
    tb_u32(b, (uint32_t)id);
    tb_dict(b, 0);
    tb_u32(b, 1);
    tb_u32(b, (uint32_t)model);
    tb_dict(b, 0);
    tb_end(b, at);
}
/* Groups shared `levels` deep from node 1 (a group with two transforms onto
 * the next group, under a transform node 0 written by the caller), a shape
 * of model 0 at the bottom: 2^levels copies of it. */
static inline void tb_shared_groups(vx_buf* b, int levels) {
    for (int lv = 0; lv < levels; lv++) {
        int32_t g = 1 + 3 * lv, two[2] = {g + 1, g + 2};
        tb_grp(b, g, false, 2, two);
        tb_trn(b, g + 1, g + 3, -1, false, NULL, -1, 1, 0, 0);
        tb_trn(b, g + 2, g + 3, -1, false, NULL, -1, 0, 1, 0);
    }
    tb_shp(b, 1 + 3 * levels, 0);
}
static inline void tb_layr(vx_buf* b, int32_t id, bool hidden) {
    size_t at = tb_begin(b, "LAYR");
    tb_u32(b, (uint32_t)id);
    if (hidden) tb_dict(b, 2, "_name", "layer", "_hidden", "1");
    else tb_dict(b, 1, "_name", "layer");
    tb_u32(b, UINT32_MAX);
    tb_end(b, at);
}

/* ---- placed voxel sets ------------------------------------------------------ */

typedef struct tv_cell {
    int32_t x, y, z;
    uint32_t rgba;
} tv_cell;

static inline int tv_cell_cmp(const void* a, const void* b) {
    const tv_cell *p = (const tv_cell*)a, *q = (const tv_cell*)b;
    if (p->x != q->x) return p->x < q->x ? -1 : 1;
    if (p->y != q->y) return p->y < q->y ? -1 : 1;
    if (p->z != q->z) return p->z < q->z ? -1 : 1;
    return p->rgba < q->rgba ? -1 : p->rgba > q->rgba;
}

/* Every voxel of every instance in world cells with its colour, sorted. */
static inline tv_cell* tv_placed(const vx_vox_scene* s, size_t* count) {
    size_t n = 0;
    for (uint32_t i = 0; i < s->instance_count; i++) n += s->models[s->instances[i].model].voxel_count;
    tv_cell* out = (tv_cell*)malloc((n ? n : 1) * sizeof *out);
    size_t o = 0;
    for (uint32_t i = 0; i < s->instance_count; i++) {
        const vx_vox_instance* in = &s->instances[i];
        const vx_vox_model* m = &s->models[in->model];
        for (uint32_t v = 0; v < m->voxel_count; v++) {
            const uint8_t* p = m->xyzi + (size_t)v * 4;
            uint32_t c[3] = {p[0], p[1], p[2]};
            int32_t w[3];
            vx_vox_place(in->rot, in->t, m->size, c, w);
            out[o++] = (tv_cell){w[0], w[1], w[2], s->palette[p[3]]};
        }
    }
    qsort(out, o, sizeof *out, tv_cell_cmp);
    *count = o;
    return out;
}

/* ---- scene comparison: returns a description of the first difference ------ */

static inline const char* tv_scene_diff(const vx_vox_scene* a, const vx_vox_scene* b) {
    if (a->model_count != b->model_count) return "model count";
    for (uint32_t i = 0; i < a->model_count; i++) {
        const vx_vox_model *p = &a->models[i], *q = &b->models[i];
        if (memcmp(p->size, q->size, sizeof p->size) || p->voxel_count != q->voxel_count) return "model size/count";
        if (p->voxel_count && memcmp(p->xyzi, q->xyzi, (size_t)p->voxel_count * 4)) return "model voxels";
    }
    if (a->has_rgba != b->has_rgba) return "has_rgba";
    if (memcmp(a->palette, b->palette, sizeof a->palette)) return "palette";
    if (a->has_imap != b->has_imap || (a->has_imap && memcmp(a->imap, b->imap, 256))) return "imap";
    if (a->instance_count != b->instance_count) return "instance count";
    for (uint32_t i = 0; i < a->instance_count; i++) {
        const vx_vox_instance *p = &a->instances[i], *q = &b->instances[i];
        if (p->model != q->model || memcmp(p->rot, q->rot, sizeof p->rot) || memcmp(p->t, q->t, sizeof p->t) ||
            p->layer != q->layer || p->hidden != q->hidden || strcmp(p->name, q->name))
            return "instance";
    }
    if (a->layer_count != b->layer_count) return "layer count";
    for (uint32_t i = 0; i < a->layer_count; i++) {
        const vx_vox_layer *p = &a->layers[i], *q = &b->layers[i];
        if (p->id != q->id || p->hidden != q->hidden || p->rgba != q->rgba || strcmp(p->name, q->name)) return "layer";
    }
    if (a->material_count != b->material_count) return "material count";
    for (uint32_t i = 0; i < a->material_count; i++) {
        const vx_vox_material *p = &a->materials[i], *q = &b->materials[i];
        if (p->id != q->id || p->dict_size != q->dict_size || memcmp(p->dict, q->dict, p->dict_size)) return "material";
    }
    return NULL;
}

/* Looks a key up in a material dictionary. */
static inline const char* tv_mat_get(const vx_vox_material* m, const char* key) {
    for (uint32_t k = 0; k < m->dict_size;) {
        const char* kk = m->dict + k;
        const char* vv = kk + strlen(kk) + 1;
        if (!strcmp(kk, key)) return vv;
        k = (uint32_t)(vv + strlen(vv) + 1 - m->dict);
    }
    return NULL;
}

/* ---- logger and allocators ---------------------------------------------------- */

typedef struct tlog {
    int count;
    char last_id[64];
    char last_msg[256];
} tlog;

static void tlog_fn(void* user, vx_log_level level, const char* id, const char* msg) {
    (void)level;
    tlog* l = (tlog*)user;
    l->count++;
    snprintf(l->last_id, sizeof l->last_id, "%s", id);
    snprintf(l->last_msg, sizeof l->last_msg, "%s", msg);
}

static uint64_t rng_s = 0x243F6A8885A308D3ull;
static uint64_t rng(void) {
    rng_s ^= rng_s << 13;
    rng_s ^= rng_s >> 7;
    rng_s ^= rng_s << 17;
    return rng_s;
}

static const char* corpus_files[] = {
    "eph_chr_knight.vox", "eph_dragon.vox", "eph_menger.vox", "eph_monu1.vox", "eph_teapot.vox",
    "ogt_chr_knight.vox", "ogt_doom.vox", "ogt_test_groups.vox", "ogt_test_multiple_model_scene.vox",
};
#define NCORPUS (sizeof corpus_files / sizeof corpus_files[0])

static uint8_t* load_corpus(const char* name, size_t* size) {
    char rel[256];
    snprintf(rel, sizeof rel, "vox/%s", name);
    const char* path = vx_test_corpus(rel);
    if (!path) return NULL;
    uint8_t* d = NULL;
    if (vx_file_read(path, NULL, 0, &d, size, NULL) != VX_OK) return NULL;
    return d;
}

static vx_result read_buf(const vx_buf* b, const vx_vox_read_desc* d, vx_vox_scene* s, vx_error* e) {
    return vx_vox_read(d, b->data, b->size, s, e);
}

/* Reads, expecting failure with `code` and a message containing `needle`. */
static void expect_fail(const vx_buf* b, vx_result code, const char* needle, const char* what) {
    vx_vox_scene s;
    vx_error e = {0};
    vx_result r = read_buf(b, NULL, &s, &e);
    fprintf(stderr, "  %-34s -> %s: %s\n", what, vx_result_str(r), e.msg);
    CHECKF(r == code, "%s: got %s, expected %s", what, vx_result_str(r), vx_result_str(code));
    CHECKF(strstr(e.msg, needle) != NULL, "%s: message lacks '%s'", what, needle);
    if (r == VX_OK) vx_vox_scene_free(&s);
}

/* ---- palette and rotations -------------------------------------------------------- */

static void test_default_palette(void) {
    /* Regenerated from its structure: the 6x6x6 colour cube (R outermost,
     * B innermost, levels ff..00) without black, then ramps of red, green,
     * blue and grey with the levels ee dd bb aa 88 77 55 44 22 11. */
    static const uint32_t lv[6] = {0xff, 0xcc, 0x99, 0x66, 0x33, 0x00};
    static const uint32_t ramp[10] = {0xee, 0xdd, 0xbb, 0xaa, 0x88, 0x77, 0x55, 0x44, 0x22, 0x11};
    uint32_t ref[256] = {0};
    int i = 1;
    for (int r = 0; r < 6; r++)
        for (int g = 0; g < 6; g++)
            for (int b = 0; b < 6; b++)
                if (i <= 215) ref[i++] = 0xff000000u | lv[b] << 16 | lv[g] << 8 | lv[r];
    for (int k = 0; k < 10; k++) ref[i++] = 0xff000000u | ramp[k];
    for (int k = 0; k < 10; k++) ref[i++] = 0xff000000u | ramp[k] << 8;
    for (int k = 0; k < 10; k++) ref[i++] = 0xff000000u | ramp[k] << 16;
    for (int k = 0; k < 10; k++) ref[i++] = 0xff000000u | ramp[k] * 0x010101u;
    CHECK(i == 256);
    for (int k = 0; k < 256; k++) CHECKF(vx_vox_default_palette[k] == ref[k], "entry %d", k);
    /* ogt_chr_knight was saved with the default palette: its RGBA entry i-1
     * is colour index i */
    size_t n;
    uint8_t* d = load_corpus("ogt_chr_knight.vox", &n);
    if (!d) SKIP("corpus vox/ogt_chr_knight.vox not found");
    vx_vox_scene s;
    REQUIRE(vx_vox_read(NULL, d, n, &s, NULL) == VX_OK);
    CHECK(s.has_rgba);
    CHECK(memcmp(s.palette + 1, vx_vox_default_palette + 1, 255 * 4) == 0);
    vx_vox_scene_free(&s);
    free(d);
}

static void test_rotations(void) {
    int valid = 0, mirrors = 0;
    int32_t seen[48][9];
    for (int b = 0; b < 256; b++) {
        int32_t m[9];
        if (!vx_vox_rot_from_byte((uint8_t)b, m)) continue;
        /* a signed permutation */
        int nz = 0, det;
        for (int k = 0; k < 9; k++) {
            nz += m[k] != 0;
            CHECK(m[k] >= -1 && m[k] <= 1);
        }
        CHECK(nz == 3);
        det = m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) + m[2] * (m[3] * m[7] - m[4] * m[6]);
        CHECK(det == 1 || det == -1);
        mirrors += det == -1;
        uint8_t back = 0;
        CHECK(vx_vox_rot_to_byte(m, &back));
        CHECKF(back == b, "byte %d -> %d", b, back);
        for (int j = 0; j < valid && valid < 48; j++) CHECK(memcmp(seen[j], m, sizeof m) != 0);
        if (valid < 48) memcpy(seen[valid], m, sizeof m);
        valid++;
    }
    CHECK(valid == 48);
    CHECK(mirrors == 24);
    /* the example of the format notes */
    int32_t ex[9] = {0, 1, 0, 0, 0, -1, -1, 0, 0}, m[9];
    uint8_t eb;
    CHECK(vx_vox_rot_to_byte(ex, &eb) && eb == ((1 << 0) | (2 << 2) | (0 << 4) | (1 << 5) | (1 << 6)));
    CHECK(vx_vox_rot_from_byte(eb, m) && memcmp(m, ex, sizeof m) == 0);
    /* identity is byte 4 */
    CHECK(vx_vox_rot_from_byte(4, m) && m[0] == 1 && m[4] == 1 && m[8] == 1);
    int32_t bad1[9] = {1, 1, 0, 0, 0, 1, 0, 0, 0}, bad2[9] = {2, 0, 0, 0, 1, 0, 0, 0, 1}, bad3[9] = {1, 0, 0, 1, 0, 0, 0, 0, 1};
    CHECK(!vx_vox_rot_to_byte(bad1, &eb) && !vx_vox_rot_to_byte(bad2, &eb) && !vx_vox_rot_to_byte(bad3, &eb));
}

static int valid_rot_byte(void) {
    for (;;) {
        uint8_t b = (uint8_t)(rng() & 0x7f);
        if (vx_vox_rot_from_byte(b, NULL)) return b;
    }
}

static void test_place_random(void) {
    for (int it = 0; it < 20000; it++) {
        int32_t R[9], t[3], out[3];
        uint32_t s[3], v[3];
        vx_vox_rot_from_byte((uint8_t)valid_rot_byte(), R);
        for (int k = 0; k < 3; k++) {
            s[k] = 1 + (uint32_t)(rng() % 256);
            if (it % 4 == 0) s[k] = 1 + (uint32_t)(rng() % 4); /* many tiny odd/even sizes */
            v[k] = (uint32_t)(rng() % s[k]);
            t[k] = (int32_t)(rng() % 4001) - 2000;
            if (it % 97 == 0) t[k] = (rng() & 1) ? (1 << 30) : -(1 << 30);
        }
        vx_vox_place(R, t, s, v, out);
        for (int r = 0; r < 3; r++) {
            double w = t[r];
            for (int k = 0; k < 3; k++) w += R[r * 3 + k] * ((double)v[k] + 0.5 - floor(s[k] / 2.0));
            CHECKF(out[r] == (int32_t)floor(w), "it %d row %d: %d vs %.1f", it, r, out[r], w);
        }
        if (vx_t_cur_failed) return;
    }
}

/* ---- corpus ------------------------------------------------------------------------ */

/* nGRP chunks counted by walking MAIN directly (independent of the reader). */
static int count_chunks(const uint8_t* d, size_t n, const char* id) {
    size_t off = 20;
    int c = 0;
    while (off + 12 <= n) {
        uint32_t a, b;
        memcpy(&a, d + off + 4, 4);
        memcpy(&b, d + off + 8, 4);
        c += memcmp(d + off, id, 4) == 0;
        off += 12 + (size_t)a + b;
    }
    return c;
}

static void roundtrip(const char* name, const vx_vox_scene* s, bool keep_hidden) {
    uint8_t* w = NULL;
    size_t wn = 0;
    vx_error e = {0};
    vx_result r = vx_vox_write(s, NULL, &w, &wn, &e);
    CHECKF(r == VX_OK, "%s: write: %s", name, e.msg);
    if (r != VX_OK) return;
    vx_vox_scene s2;
    r = vx_vox_read(&(vx_vox_read_desc){.keep_hidden = keep_hidden}, w, wn, &s2, &e);
    CHECKF(r == VX_OK, "%s: reread: %s", name, e.msg);
    if (r == VX_OK) {
        const char* diff = tv_scene_diff(s, &s2);
        CHECKF(diff == NULL, "%s: round trip differs in %s", name, diff);
        size_t n1, n2;
        tv_cell* p1 = tv_placed(s, &n1);
        tv_cell* p2 = tv_placed(&s2, &n2);
        CHECKF(n1 == n2 && memcmp(p1, p2, n1 * sizeof *p1) == 0, "%s: placed voxels differ", name);
        free(p1);
        free(p2);
        vx_vox_scene_free(&s2);
    }
    free(w);
}

static void test_corpus(void) {
    int found = 0;
    for (size_t f = 0; f < NCORPUS; f++) {
        size_t n;
        uint8_t* d = load_corpus(corpus_files[f], &n);
        if (!d) continue;
        found++;
        tlog lg = {0};
        vx_logger logger = {tlog_fn, &lg};
        vx_vox_scene s;
        vx_error e = {0};
        vx_result r = vx_vox_read(&(vx_vox_read_desc){.logger = &logger}, d, n, &s, &e);
        CHECKF(r == VX_OK, "%s: %s", corpus_files[f], e.msg);
        if (r != VX_OK) { free(d); continue; }
        uint64_t vox = 0;
        for (uint32_t i = 0; i < s.model_count; i++) vox += s.models[i].voxel_count;
        size_t placed;
        tv_cell* cells = tv_placed(&s, &placed);
        fprintf(stderr, "  %-34s models %3u voxels %7llu instances %3u placed %7zu layers %u materials %3u nodes %3u rgba %d "
                "imap %d robj %u warnings %d\n",
                corpus_files[f], s.model_count, (unsigned long long)vox, s.instance_count, placed, s.layer_count,
                s.material_count, s.node_count, s.has_rgba, s.has_imap, s.robj_count, lg.count);
        CHECK(s.model_count >= 1 && vox > 0 && s.instance_count >= 1 && placed > 0);
        CHECK(vx_vox_validate(&s, NULL) == VX_OK);
        CHECK(s.has_scene_graph == (count_chunks(d, n, "nTRN") > 0));
        CHECK(s.layer_count == (uint32_t)count_chunks(d, n, "LAYR"));
        free(cells);
        roundtrip(corpus_files[f], &s, false);
        if (!strcmp(corpus_files[f], "eph_menger.vox")) {
            CHECK(!s.has_rgba);
            CHECK(memcmp(s.palette, vx_vox_default_palette, sizeof s.palette) == 0);
            CHECK(s.models[0].size[0] == 81 && s.models[0].size[1] == 81 && s.models[0].size[2] == 81);
        }
        if (!strcmp(corpus_files[f], "ogt_test_multiple_model_scene.vox")) {
            CHECK(s.model_count < s.instance_count); /* instancing kept */
            CHECK(s.has_imap);
        }
        if (!strcmp(corpus_files[f], "ogt_test_groups.vox")) {
            CHECK(count_chunks(d, n, "nGRP") >= 2);
            CHECK(s.layer_count > 0 && s.material_count == 256);
            /* instances below nested groups: some transform composes more than
             * two translations, so at least one instance sits off-axis */
            vx_vox_scene sh;
            REQUIRE(vx_vox_read(&(vx_vox_read_desc){.keep_hidden = true}, d, n, &sh, NULL) == VX_OK);
            CHECK(sh.instance_count >= s.instance_count);
            roundtrip("ogt_test_groups.vox (keep_hidden)", &sh, true);
            vx_vox_scene_free(&sh);
        }
        vx_vox_scene_free(&s);
        free(d);
    }
    if (!found) SKIP("corpus vox/ not found");
}

/* ogt_chr_knight is a newer MagicaVoxel re-save of eph_chr_knight: same
 * cells, but inside a scene graph whose transform says _t "0 0 10". */
static void test_knight_resave(void) {
    size_t n1, n2;
    uint8_t* d1 = load_corpus("eph_chr_knight.vox", &n1);
    uint8_t* d2 = load_corpus("ogt_chr_knight.vox", &n2);
    if (!d1 || !d2) {
        free(d1);
        free(d2);
        SKIP("corpus knights not found");
    }
    vx_vox_scene a, b;
    REQUIRE(vx_vox_read(NULL, d1, n1, &a, NULL) == VX_OK);
    REQUIRE(vx_vox_read(NULL, d2, n2, &b, NULL) == VX_OK);
    CHECK(!a.has_scene_graph && b.has_scene_graph);
    size_t na, nb;
    tv_cell* pa = tv_placed(&a, &na);
    tv_cell* pb = tv_placed(&b, &nb);
    CHECK(na == nb && na == 398);
    for (size_t i = 0; i < na && i < nb; i++) {
        CHECKF(pa[i].x == pb[i].x && pa[i].y == pb[i].y && pa[i].z + 10 == pb[i].z, "cell %zu", i);
        if (vx_t_cur_failed) break;
    }
    free(pa);
    free(pb);
    vx_vox_scene_free(&a);
    vx_vox_scene_free(&b);
    free(d1);
    free(d2);
}

static void test_perf_monu1(void) {
    size_t n;
    uint8_t* d = load_corpus("eph_monu1.vox", &n);
    if (!d) SKIP("corpus vox/eph_monu1.vox not found");
    const int reps = 20;
    double best = 1e9;
    for (int i = 0; i < reps; i++) {
        vx_vox_scene s;
        double t0 = vx_time_now();
        vx_result r = vx_vox_read(NULL, d, n, &s, NULL);
        double t1 = vx_time_now();
        CHECK(r == VX_OK);
        if (r == VX_OK) vx_vox_scene_free(&s);
        if (t1 - t0 < best) best = t1 - t0;
    }
    fprintf(stderr, "  eph_monu1.vox read: best of %d %.3f ms (%zu bytes)\n", reps, best * 1e3, n);
    free(d);
}

/* ---- synthetic files ------------------------------------------------------------------ */

static void test_empty_and_one_voxel(void) {
    vx_buf b;
    vx_vox_scene s;
    tb_file(&b, 150);
    tb_model(&b, 3, 4, 5, 0, NULL);
    tb_finish(&b);
    REQUIRE(read_buf(&b, NULL, &s, NULL) == VX_OK);
    CHECK(s.model_count == 1 && s.models[0].voxel_count == 0 && s.instance_count == 1 && !s.has_scene_graph);
    CHECK(s.instances[0].rot[0] == 1 && s.instances[0].rot[4] == 1 && s.instances[0].rot[8] == 1 && s.instances[0].t[0] == 0);
    CHECK(!s.has_rgba && s.palette[1] == vx_vox_default_palette[1]);
    roundtrip("empty model", &s, false);
    vx_vox_scene_free(&s);
    vx_buf_free(&b);

    /* one voxel, plus one outside the model and one with index 0: dropped with warnings */
    const uint8_t xyzi[12] = {0, 0, 0, 7, 1, 0, 0, 9, 0, 0, 0, 0};
    tlog lg = {0};
    vx_logger logger = {tlog_fn, &lg};
    tb_file(&b, 150);
    tb_model(&b, 1, 1, 1, 3, xyzi);
    tb_finish(&b);
    REQUIRE(read_buf(&b, &(vx_vox_read_desc){.logger = &logger}, &s, NULL) == VX_OK);
    CHECK(s.models[0].voxel_count == 1 && s.models[0].xyzi[3] == 7);
    CHECK(lg.count == 2);
    fprintf(stderr, "  warning: %s: %s\n", lg.last_id, lg.last_msg);
    size_t n;
    tv_cell* c = tv_placed(&s, &n);
    CHECK(n == 1 && c[0].x == 0 && c[0].y == 0 && c[0].z == 0 && c[0].rgba == vx_vox_default_palette[7]);
    free(c);
    roundtrip("one voxel", &s, false);
    vx_vox_scene_free(&s);
    vx_buf_free(&b);
}

/* A level of the nested test: rotation byte and translation of a transform. */
typedef struct lvl {
    int rot;
    int t[3];
} lvl;

/* Reference: apply the transforms one by one, innermost first, in doubles. */
static void ref_place(const lvl* levels, int nl, const uint32_t s[3], const uint32_t v[3], int32_t out[3]) {
    double p[3];
    for (int k = 0; k < 3; k++) p[k] = v[k] + 0.5 - floor(s[k] / 2.0);
    for (int l = nl - 1; l >= 0; l--) {
        int32_t R[9];
        vx_vox_rot_from_byte((uint8_t)levels[l].rot, R);
        double q[3];
        for (int r = 0; r < 3; r++) q[r] = R[r * 3] * p[0] + R[r * 3 + 1] * p[1] + R[r * 3 + 2] * p[2] + levels[l].t[r];
        memcpy(p, q, sizeof p);
    }
    for (int k = 0; k < 3; k++) out[k] = (int32_t)floor(p[k]);
}

static void test_nested_groups(void) {
    /* T0 -> G1 -> { T2 -> G3 -> { T4 -> G5 -> { T6 -> S7 (model 0) } }, T8 -> S9 (model 1) } */
    uint8_t m0[5 * 4], m1[3 * 4];
    for (int i = 0; i < 5; i++) {
        m0[i * 4 + 0] = (uint8_t)(i % 4);
        m0[i * 4 + 1] = (uint8_t)(i % 3);
        m0[i * 4 + 2] = (uint8_t)(i % 6);
        m0[i * 4 + 3] = (uint8_t)(10 + i);
    }
    for (int i = 0; i < 3; i++) m1[i * 4 + 0] = (uint8_t)i, m1[i * 4 + 1] = 0, m1[i * 4 + 2] = 1, m1[i * 4 + 3] = 3;
    for (int trial = 0; trial < 50; trial++) {
        lvl L[4];
        for (int l = 0; l < 4; l++) {
            L[l].rot = valid_rot_byte();
            for (int k = 0; k < 3; k++) L[l].t[k] = (int)(rng() % 201) - 100;
        }
        int32_t g1[2] = {2, 8}, g3[1] = {4}, g5[1] = {6};
        vx_buf b;
        tb_file(&b, 150);
        tb_model(&b, 4, 3, 6, 5, m0); /* even and odd sides */
        tb_model(&b, 3, 1, 2, 3, m1);
        tb_trn(&b, 0, 1, -1, false, NULL, L[0].rot, L[0].t[0], L[0].t[1], L[0].t[2]);
        tb_grp(&b, 1, false, 2, g1);
        tb_trn(&b, 2, 3, 0, false, "mid", L[1].rot, L[1].t[0], L[1].t[1], L[1].t[2]);
        tb_grp(&b, 3, false, 1, g3);
        tb_trn(&b, 4, 5, 0, false, NULL, L[2].rot, L[2].t[0], L[2].t[1], L[2].t[2]);
        tb_grp(&b, 5, false, 1, g5);
        tb_trn(&b, 6, 7, 2, false, "deep", L[3].rot, L[3].t[0], L[3].t[1], L[3].t[2]);
        tb_shp(&b, 7, 0);
        tb_trn(&b, 8, 9, 1, false, "side", -1, 5, 6, 7);
        tb_shp(&b, 9, 1);
        tb_finish(&b);
        vx_vox_scene s;
        vx_error e = {0};
        vx_result r = read_buf(&b, NULL, &s, &e);
        CHECKF(r == VX_OK, "%s", e.msg);
        vx_buf_free(&b);
        if (r != VX_OK) return;
        REQUIRE(s.instance_count == 2);
        for (uint32_t i = 0; i < 2; i++) {
            const vx_vox_instance* in = &s.instances[i];
            const vx_vox_model* m = &s.models[in->model];
            lvl side[2] = {L[0], {4, {5, 6, 7}}};
            const lvl* chain = in->model == 0 ? L : side;
            int nl = in->model == 0 ? 4 : 2;
            CHECK(!strcmp(in->name, in->model == 0 ? "deep" : "side"));
            CHECK(in->layer == (in->model == 0 ? 2 : 1));
            for (uint32_t v = 0; v < m->voxel_count; v++) {
                uint32_t c[3] = {m->xyzi[v * 4], m->xyzi[v * 4 + 1], m->xyzi[v * 4 + 2]};
                int32_t got[3], want[3];
                vx_vox_place(in->rot, in->t, m->size, c, got);
                ref_place(chain, nl, m->size, c, want);
                CHECKF(!memcmp(got, want, sizeof got), "trial %d model %u voxel %u: (%d %d %d) vs (%d %d %d)", trial,
                       in->model, v, got[0], got[1], got[2], want[0], want[1], want[2]);
            }
        }
        if (trial == 0) roundtrip("nested groups", &s, false);
        vx_vox_scene_free(&s);
        if (vx_t_cur_failed) return;
    }
}

static void build_hidden(vx_buf* b) {
    /* T0 -> G1 -> { T2 hidden -> S3, T4 (layer 1 hidden) -> S5, T6 -> G7 hidden -> { T8 -> S9 }, T10 "vis" -> S11 } */
    const uint8_t v[4] = {0, 0, 0, 1};
    int32_t g1[4] = {2, 4, 6, 10}, g7[1] = {8};
    tb_file(b, 150);
    tb_model(b, 1, 1, 1, 1, v);
    tb_trn(b, 0, 1, -1, false, NULL, -1, 0, 0, 0);
    tb_grp(b, 1, false, 4, g1);
    tb_trn(b, 2, 3, 0, true, "hidden node", -1, 1, 0, 0);
    tb_shp(b, 3, 0);
    tb_trn(b, 4, 5, 1, false, "hidden layer", -1, 2, 0, 0);
    tb_shp(b, 5, 0);
    tb_trn(b, 6, 7, 0, false, NULL, -1, 3, 0, 0);
    tb_grp(b, 7, true, 1, g7);
    tb_trn(b, 8, 9, 0, false, "hidden group", -1, 0, 0, 0);
    tb_shp(b, 9, 0);
    tb_trn(b, 10, 11, 0, false, "vis", -1, 4, 0, 0);
    tb_shp(b, 11, 0);
    tb_layr(b, 0, false);
    tb_layr(b, 1, true);
    tb_finish(b);
}

static void test_hidden(void) {
    vx_buf b;
    vx_vox_scene s;
    build_hidden(&b);
    REQUIRE(read_buf(&b, NULL, &s, NULL) == VX_OK);
    CHECK(s.instance_count == 1 && !strcmp(s.instances[0].name, "vis") && !s.instances[0].hidden);
    CHECK(s.layer_count == 2 && s.layers[1].hidden && !s.layers[0].hidden);
    vx_vox_scene_free(&s);
    REQUIRE(read_buf(&b, &(vx_vox_read_desc){.keep_hidden = true}, &s, NULL) == VX_OK);
    CHECK(s.instance_count == 4);
    int hidden = 0;
    for (uint32_t i = 0; i < s.instance_count; i++) {
        hidden += s.instances[i].hidden;
        /* the shape on the hidden layer is hidden by the layer's flag alone (it carried hidden = true too:
         * showing the layer in svo_view did not show it, and a .vox written from it hid its transform) */
        bool by_node = strcmp(s.instances[i].name, "vis") && strcmp(s.instances[i].name, "hidden layer");
        CHECKF(s.instances[i].hidden == by_node, "instance '%s': hidden %d", s.instances[i].name, s.instances[i].hidden);
    }
    CHECK(hidden == 2);
    CHECK(!strcmp(s.instances[1].name, "hidden layer") && s.instances[1].layer == 1 && s.layers[1].hidden);
    CHECK(s.instances[2].t[0] == 3); /* hidden group's translation still composed */
    roundtrip("hidden (keep_hidden)", &s, true);
    /* written with _hidden on the transforms: a default read omits them again */
    uint8_t* w;
    size_t wn;
    REQUIRE(vx_vox_write(&s, NULL, &w, &wn, NULL) == VX_OK);
    vx_vox_scene s2;
    REQUIRE(vx_vox_read(NULL, w, wn, &s2, NULL) == VX_OK);
    CHECK(s2.instance_count == 1 && !strcmp(s2.instances[0].name, "vis"));
    vx_vox_scene_free(&s2);
    free(w);
    vx_vox_scene_free(&s);
    vx_buf_free(&b);
}

static void test_animation(void) {
    /* frames of T2 at _f 2, 5, 10 (none at 0: frame 0 takes the earliest);
     * S3 shows model 0 from frame 0 (no _f) and model 1 from frame 7 */
    const uint8_t v[4] = {0, 0, 0, 1};
    int32_t g1[1] = {2};
    vx_buf b;
    tb_file(&b, 200);
    tb_model(&b, 1, 1, 1, 1, v);
    tb_model(&b, 2, 2, 2, 1, v);
    tb_trn(&b, 0, 1, -1, false, NULL, -1, 0, 0, 0);
    tb_grp(&b, 1, false, 1, g1);
    size_t at = tb_begin(&b, "nTRN");
    tb_u32(&b, 2);
    tb_dict(&b, 0);
    tb_u32(&b, 3);
    tb_u32(&b, UINT32_MAX);
    tb_u32(&b, 0);
    tb_u32(&b, 3);
    tb_dict(&b, 2, "_f", "2", "_t", "1 0 0");
    tb_dict(&b, 2, "_t", "10 0 0", "_f", "5");
    tb_dict(&b, 3, "_f", "10", "_r", "17", "_t", "-20 3 4");
    tb_end(&b, at);
    at = tb_begin(&b, "nSHP");
    tb_u32(&b, 3);
    tb_dict(&b, 0);
    tb_u32(&b, 2);
    tb_u32(&b, 0);
    tb_dict(&b, 0);
    tb_u32(&b, 1);
    tb_dict(&b, 1, "_f", "7");
    tb_end(&b, at);
    tb_finish(&b);
    static const struct { uint32_t frame; int tx; uint32_t model; int rot; } exp[] = {
        {0, 1, 0, 4}, {3, 1, 0, 4}, {5, 10, 0, 4}, {6, 10, 0, 4}, {7, 10, 1, 4}, {9, 10, 1, 4}, {10, -20, 1, 17}, {1000, -20, 1, 17},
    };
    for (size_t i = 0; i < sizeof exp / sizeof exp[0]; i++) {
        vx_vox_scene s;
        vx_error e = {0};
        vx_result r = read_buf(&b, &(vx_vox_read_desc){.frame = exp[i].frame}, &s, &e);
        CHECKF(r == VX_OK, "%s", e.msg);
        if (r != VX_OK) continue;
        int32_t R[9];
        vx_vox_rot_from_byte((uint8_t)exp[i].rot, R);
        CHECK(s.version == 200);
        CHECKF(s.instance_count == 1 && s.instances[0].t[0] == exp[i].tx && s.instances[0].model == exp[i].model &&
                   !memcmp(s.instances[0].rot, R, sizeof R),
               "frame %u: t %d model %u", exp[i].frame, s.instances[0].t[0], s.instances[0].model);
        vx_vox_scene_free(&s);
    }
    vx_buf_free(&b);
}

static void test_pack_frames(void) {
    uint8_t v[3][4] = {{0, 0, 0, 1}, {1, 1, 1, 2}, {2, 2, 2, 3}};
    vx_buf b;
    tb_file(&b, 150);
    size_t at = tb_begin(&b, "PACK");
    tb_u32(&b, 3);
    tb_end(&b, at);
    for (int i = 0; i < 3; i++) tb_model(&b, 3, 3, 3, 1, v[i]);
    tb_finish(&b);
    for (uint32_t f = 0; f < 3; f++) {
        vx_vox_scene s;
        REQUIRE(read_buf(&b, &(vx_vox_read_desc){.frame = f}, &s, NULL) == VX_OK);
        CHECK(s.model_count == 3 && s.instance_count == 1 && s.instances[0].model == f && !s.has_scene_graph);
        size_t n;
        tv_cell* c = tv_placed(&s, &n);
        /* pivot floor(3/2) = 1: cell v lands at v - 1 */
        CHECK(n == 1 && c[0].x == (int)f - 1 && c[0].y == (int)f - 1 && c[0].z == (int)f - 1);
        free(c);
        vx_vox_scene_free(&s);
    }
    vx_vox_scene s;
    vx_error e = {0};
    CHECK(read_buf(&b, &(vx_vox_read_desc){.frame = 3}, &s, &e) == VX_ERR_INVALID_ARG);
    fprintf(stderr, "  frame 3 of 3 -> %s\n", e.msg);
    vx_buf_free(&b);
}

static void test_other_chunks(void) {
    const uint8_t v[4] = {0, 0, 0, 1};
    tlog lg = {0};
    vx_logger logger = {tlog_fn, &lg};
    vx_buf b;
    tb_file(&b, 201);
    tb_model(&b, 1, 1, 1, 1, v);
    size_t at = tb_begin(&b, "MATT");
    tb_u32(&b, 5);
    tb_u32(&b, 1); /* metal */
    vx_buf_f32le(&b, 0.5f);
    tb_u32(&b, (1u << 1) | (1u << 3) | (1u << 7)); /* roughness, IOR, isTotalPower */
    vx_buf_f32le(&b, 0.25f);
    vx_buf_f32le(&b, 0.75f);
    tb_end(&b, at);
    at = tb_begin(&b, "MATL");
    tb_u32(&b, 256);
    tb_dict(&b, 2, "_type", "_glass", "_alpha", "0.5");
    tb_end(&b, at);
    at = tb_begin(&b, "rOBJ");
    tb_dict(&b, 1, "_type", "_bg");
    tb_end(&b, at);
    at = tb_begin(&b, "rCAM");
    tb_u32(&b, 0);
    tb_dict(&b, 1, "_mode", "pers");
    tb_end(&b, at);
    at = tb_begin(&b, "NOTE");
    tb_u32(&b, 2);
    tb_str(&b, "a");
    tb_str(&b, "");
    tb_end(&b, at);
    at = tb_begin(&b, "META");
    tb_dict(&b, 1, "k", "v");
    tb_end(&b, at);
    at = tb_begin(&b, "IMAP");
    for (int i = 0; i < 256; i++) vx_buf_u8(&b, (uint8_t)(255 - i));
    tb_end(&b, at);
    at = tb_begin(&b, "ZZZZ");
    tb_u32(&b, 0xdeadbeef);
    tb_end(&b, at);
    at = tb_begin(&b, "RGBA");
    for (int i = 0; i < 256; i++) tb_u32(&b, 0xff000000u | (uint32_t)i);
    tb_end(&b, at);
    tb_finish(&b);
    vx_vox_scene s;
    vx_error e = {0};
    vx_result r = read_buf(&b, &(vx_vox_read_desc){.logger = &logger}, &s, &e);
    CHECKF(r == VX_OK, "%s", e.msg);
    if (r != VX_OK) return;
    CHECK(s.version == 201);
    CHECK(lg.count == 2); /* version 201 and chunk ZZZZ */
    CHECK(strstr(lg.last_msg, "ZZZZ") != NULL);
    CHECK(s.material_count == 2);
    if (s.material_count == 2) {
        const vx_vox_material* m = &s.materials[0];
        CHECK(m->id == 5);
        const char* ty = tv_mat_get(m, "_type");
        const char* we = tv_mat_get(m, "_weight");
        const char* ro = tv_mat_get(m, "_rough");
        const char* io = tv_mat_get(m, "_ior");
        const char* tp = tv_mat_get(m, "_total_power");
        CHECK(ty && !strcmp(ty, "_metal") && we && atof(we) == 0.5 && ro && atof(ro) == 0.25 && io && atof(io) == 0.75);
        CHECK(tp && !strcmp(tp, "1") && !tv_mat_get(m, "_spec"));
        CHECK(s.materials[1].id == 0); /* MATL 256 is the index-0 slot */
        const char* al = tv_mat_get(&s.materials[1], "_alpha");
        CHECK(al && !strcmp(al, "0.5"));
    }
    CHECK(s.robj_count == 1 && s.camera_count == 1 && s.note_count == 2);
    CHECK(s.has_imap && s.imap[0] == 255 && s.imap[255] == 0);
    CHECK(s.has_rgba && s.palette[0] == 0 && s.palette[1] == 0xff000000u && s.palette[255] == 0xff0000feu);
    roundtrip("other chunks", &s, false);
    vx_vox_scene_free(&s);
    vx_buf_free(&b);
}

/* ---- bad input ------------------------------------------------------------------------------- */

/* A corrupt file must fail cleanly; one that reads must give a valid scene. */
static void read_must_not_crash(const uint8_t* d, size_t n) {
    vx_vox_scene s;
    vx_error e = {0};
    if (vx_vox_read(&(vx_vox_read_desc){.keep_hidden = true}, d, n, &s, &e) == VX_OK) {
        CHECK(vx_vox_validate(&s, NULL) == VX_OK);
        vx_vox_scene_free(&s);
    } else {
        CHECK(e.msg[0] != 0);
    }
}

static void test_truncations(void) {
    int found = 0;
    long reads = 0;
    for (size_t f = 0; f < NCORPUS; f++) {
        size_t n;
        uint8_t* d = load_corpus(corpus_files[f], &n);
        if (!d) continue;
        found++;
        /* every prefix: MAIN declares more than is left, so this fails fast */
        for (size_t len = 0; len < n; len++) {
            vx_vox_scene s;
            vx_error e = {0};
            vx_result r = vx_vox_read(NULL, d, len, &s, &e);
            reads++;
            if (r == VX_OK) vx_vox_scene_free(&s);
            CHECKF(r == VX_ERR_TRUNCATED, "%s prefix %zu: %s", corpus_files[f], len, vx_result_str(r));
            if (r != VX_ERR_TRUNCATED) break;
        }
        /* prefixes with MAIN's size patched to fit reach every chunk parser;
         * an exact-size copy lets ASan see any read past the end */
        size_t step = n / 1500 + 1;
        for (size_t len = 20; len < n; len += step) {
            uint8_t* c = (uint8_t*)malloc(len);
            memcpy(c, d, len);
            vx_buf_put_u32le(c + 16, (uint32_t)(len - 20));
            read_must_not_crash(c, len);
            free(c);
            reads++;
        }
        free(d);
    }
    fprintf(stderr, "  %ld truncated reads\n", reads);
    if (!found) SKIP("corpus vox/ not found");
}

static void test_byte_flips(void) {
    static const char* files[] = {"eph_chr_knight.vox", "ogt_test_groups.vox", "ogt_test_multiple_model_scene.vox"};
    int found = 0;
    long ok = 0, total = 0;
    for (size_t f = 0; f < 3; f++) {
        size_t n;
        uint8_t* d = load_corpus(files[f], &n);
        if (!d) continue;
        found++;
        uint8_t* c = (uint8_t*)malloc(n);
        for (int it = 0; it < 1200; it++) {
            memcpy(c, d, n);
            int edits = 1 + (int)(rng() % 3);
            for (int k = 0; k < edits; k++) {
                size_t at = (size_t)(rng() % n);
                /* bias towards the scene graph, where the interesting checks are */
                if ((rng() & 1) && n > 2000) at = n - 1 - (size_t)(rng() % (n / 3));
                c[at] = (rng() & 1) ? (uint8_t)rng() : (uint8_t)(c[at] ^ (1u << (rng() % 8)));
            }
            vx_vox_scene s;
            if (vx_vox_read(&(vx_vox_read_desc){.keep_hidden = true}, c, n, &s, NULL) == VX_OK) {
                ok++;
                CHECK(vx_vox_validate(&s, NULL) == VX_OK);
                vx_vox_scene_free(&s);
            }
            total++;
        }
        free(c);
        free(d);
    }
    fprintf(stderr, "  %ld flipped files, %ld still read\n", total, ok);
    if (!found) SKIP("corpus vox/ not found");
}

static void small_graph(vx_buf* b, int32_t grp_kid, int32_t shp_model, int32_t trn2_child) {
    const uint8_t v[4] = {0, 0, 0, 1};
    tb_file(b, 150);
    tb_model(b, 2, 2, 2, 1, v);
    tb_trn(b, 0, 1, -1, false, NULL, -1, 0, 0, 0);
    tb_grp(b, 1, false, 1, &grp_kid);
    tb_trn(b, 2, trn2_child, 0, false, NULL, -1, 0, 0, 0);
    tb_shp(b, 3, shp_model);
    tb_finish(b);
}

static void test_bad_input(void) {
    const uint8_t v[8] = {0, 0, 0, 1, 1, 1, 1, 2};
    vx_buf b;
    /* sanity: the base graph reads */
    small_graph(&b, 2, 0, 3);
    expect_fail(&b, VX_OK, "", "valid small graph");
    vx_buf_free(&b);

    tb_file(&b, 150);
    tb_model(&b, 2, 2, 2, 2, v);
    tb_finish(&b);
    uint8_t* base = b.data;
    size_t xyzi_at = 20 + 24; /* after SIZE (12 + 12) */
    vx_buf_put_u32le(base + 16, 0x7FFFFFFFu);
    expect_fail(&b, VX_ERR_TRUNCATED, "MAIN", "MAIN children 0x7FFFFFFF");
    vx_buf_put_u32le(base + 16, 0xFFFFFFFFu);
    expect_fail(&b, VX_ERR_TRUNCATED, "MAIN", "MAIN children 0xFFFFFFFF");
    vx_buf_put_u32le(base + 12, 0xFFFFFFFFu);
    expect_fail(&b, VX_ERR_TRUNCATED, "MAIN", "MAIN content 0xFFFFFFFF");
    tb_finish(&b);
    vx_buf_put_u32le(base + 12, 0);
    vx_buf_put_u32le(base + xyzi_at + 4, 0x7FFFFFFFu);
    expect_fail(&b, VX_ERR_TRUNCATED, "XYZI", "XYZI content 0x7FFFFFFF");
    vx_buf_put_u32le(base + xyzi_at + 4, 0xFFFFFFFFu);
    expect_fail(&b, VX_ERR_TRUNCATED, "XYZI", "XYZI content 0xFFFFFFFF");
    vx_buf_put_u32le(base + xyzi_at + 4, 12);
    vx_buf_put_u32le(base + xyzi_at + 8, 0xFFFFFFFFu);
    expect_fail(&b, VX_ERR_TRUNCATED, "XYZI", "XYZI children 0xFFFFFFFF");
    vx_buf_put_u32le(base + xyzi_at + 8, 0);
    vx_buf_put_u32le(base + xyzi_at + 12, 3);
    expect_fail(&b, VX_ERR_TRUNCATED, "XYZI", "XYZI count beyond chunk");
    vx_buf_put_u32le(base + xyzi_at + 12, 0x40000001u);
    expect_fail(&b, VX_ERR_TRUNCATED, "XYZI", "XYZI count 0x40000001");
    vx_buf_put_u32le(base + xyzi_at + 12, 2);
    expect_fail(&b, VX_OK, "", "restored");
    vx_buf_put_u32le(base + 32, 257);
    expect_fail(&b, VX_ERR_LIMIT, "SIZE", "SIZE x 257");
    vx_buf_put_u32le(base + 32, 0);
    expect_fail(&b, VX_ERR_BAD_FORMAT, "SIZE", "SIZE x 0");
    vx_buf_put_u32le(base + 32, 2);
    {
        vx_vox_scene s;
        vx_error e = {0};
        CHECK(read_buf(&b, &(vx_vox_read_desc){.max_voxels = 1}, &s, &e) == VX_ERR_LIMIT && strstr(e.msg, "XYZI"));
        fprintf(stderr, "  %-34s -> %s\n", "max_voxels 1", e.msg);
        CHECK(read_buf(&b, &(vx_vox_read_desc){.max_dim = 1}, &s, &e) == VX_ERR_LIMIT && strstr(e.msg, "max_dim 1"));
        fprintf(stderr, "  %-34s -> %s\n", "max_dim 1", e.msg);
    }
    memcpy(base, "VOX!", 4);
    expect_fail(&b, VX_ERR_BAD_FORMAT, "VOX", "bad magic");
    memcpy(base, "VOX ", 4);
    vx_buf_put_u32le(base + 4, 100);
    expect_fail(&b, VX_ERR_UNSUPPORTED, "100", "version 100");
    vx_buf_put_u32le(base + 4, 150);
    memcpy(base + 20, "XYZI", 4); /* XYZI, XYZI: no SIZE first */
    expect_fail(&b, VX_ERR_BAD_FORMAT, "XYZI", "XYZI without SIZE");
    memcpy(base + 20, "SIZE", 4);
    memcpy(base + xyzi_at, "SIZE", 4);
    expect_fail(&b, VX_ERR_BAD_FORMAT, "SIZE", "SIZE without XYZI");
    vx_buf_free(&b);

    /* scene graph errors */
    small_graph(&b, 2, 0, 1); /* T2 -> G1 -> T2: cycle */
    expect_fail(&b, VX_ERR_BAD_FORMAT, "cycle", "cycle nTRN->nGRP->nTRN");
    vx_buf_free(&b);
    small_graph(&b, 7, 0, 3);
    expect_fail(&b, VX_ERR_BAD_FORMAT, "nGRP", "dangling group child");
    vx_buf_free(&b);
    small_graph(&b, 2, 0, 42);
    expect_fail(&b, VX_ERR_BAD_FORMAT, "nTRN", "dangling transform child");
    vx_buf_free(&b);
    small_graph(&b, 2, 1, 3);
    expect_fail(&b, VX_ERR_BAD_FORMAT, "nSHP", "nSHP model id out of range");
    vx_buf_free(&b);
    small_graph(&b, 3, 0, 3); /* group child is a shape */
    expect_fail(&b, VX_ERR_BAD_FORMAT, "not a transform", "group child of wrong type");
    vx_buf_free(&b);
    small_graph(&b, 2, 0, 0); /* transform child is a transform */
    expect_fail(&b, VX_ERR_BAD_FORMAT, "nTRN", "transform child of wrong type");
    vx_buf_free(&b);
    small_graph(&b, 0, 0, 3); /* G1 -> T0 (the root) -> G1 */
    expect_fail(&b, VX_ERR_BAD_FORMAT, "cycle", "cycle through the root");
    vx_buf_free(&b);
    {
        const uint8_t vv[4] = {0, 0, 0, 1};
        int32_t kids[2] = {2, 4};
        tb_file(&b, 150);
        tb_model(&b, 1, 1, 1, 1, vv);
        tb_trn(&b, 0, 1, -1, false, NULL, -1, 0, 0, 0);
        tb_grp(&b, 1, false, 2, kids);
        tb_trn(&b, 2, 3, 0, false, NULL, -1, 0, 0, 0);
        tb_trn(&b, 4, 3, 0, false, NULL, -1, 0, 0, 0);
        tb_shp(&b, 3, 0);
        tb_finish(&b);
        expect_fail(&b, VX_OK, "", "shape shared by two transforms");
        vx_vox_scene s;
        CHECK(read_buf(&b, NULL, &s, NULL) == VX_OK && s.instance_count == 2);
        vx_vox_scene_free(&s);
        vx_buf_free(&b);
        /* so is a group: MagicaVoxel's group instances (vengi's
         * test-transform.vox has four transforms on one group), one copy of
         * the group's shapes per transform, each under its own transform */
        int32_t g5[1] = {6};
        tb_file(&b, 150);
        tb_model(&b, 1, 1, 1, 1, vv);
        tb_trn(&b, 0, 1, -1, false, NULL, -1, 0, 0, 0);
        tb_grp(&b, 1, false, 2, kids);
        tb_trn(&b, 2, 5, 0, false, NULL, -1, 10, 0, 0);
        tb_trn(&b, 4, 5, 0, false, NULL, 0x11, 0, 20, 0); /* rows (-y, x, z): a quarter turn */
        tb_grp(&b, 5, false, 1, g5);
        tb_trn(&b, 6, 7, 0, false, NULL, -1, 1, 2, 3);
        tb_shp(&b, 7, 0);
        tb_finish(&b);
        expect_fail(&b, VX_OK, "", "group shared by two transforms");
        CHECK(read_buf(&b, NULL, &s, NULL) == VX_OK && s.instance_count == 2);
        if (s.instance_count == 2) {
            CHECK(s.instances[0].t[0] == 11 && s.instances[0].t[1] == 2 && s.instances[0].t[2] == 3);
            CHECK(s.instances[0].rot[0] == 1 && s.instances[0].rot[4] == 1 && s.instances[0].rot[8] == 1);
            CHECK(s.instances[1].t[0] == -2 && s.instances[1].t[1] == 21 && s.instances[1].t[2] == 3);
            CHECK(s.instances[1].rot[1] == -1 && s.instances[1].rot[3] == 1 && s.instances[1].rot[8] == 1);
        }
        vx_vox_scene_free(&s);
        vx_buf_free(&b);
        /* shared groups nested 24 deep would place 2^24 copies: a limit,
         * reached quickly (all hidden, so nothing is stored on the way) */
        tb_file(&b, 150);
        tb_model(&b, 1, 1, 1, 1, vv);
        tb_trn(&b, 0, 1, -1, true, NULL, -1, 0, 0, 0);
        tb_shared_groups(&b, 24);
        tb_finish(&b);
        expect_fail(&b, VX_ERR_LIMIT, "shared groups", "2^24 copies of shared groups");
        vx_buf_free(&b);
        /* 2^18 copies a frame stay under the frame's limit, but over 400
         * keyframed frames (all_frames) the walks add up: a limit too, not
         * minutes of walking (the root hidden: nothing stored on the way) */
        tb_file(&b, 150);
        tb_model(&b, 1, 1, 1, 1, vv);
        size_t at0 = tb_begin(&b, "nTRN");
        tb_u32(&b, 0);
        tb_dict(&b, 1, "_hidden", "1");
        tb_u32(&b, 1);
        tb_u32(&b, UINT32_MAX);
        tb_u32(&b, (uint32_t)-1);
        tb_u32(&b, 2);
        tb_dict(&b, 1, "_f", "0");
        tb_dict(&b, 1, "_f", "399");
        tb_end(&b, at0);
        tb_shared_groups(&b, 18);
        tb_finish(&b);
        {
            vx_vox_scene s2;
            vx_error e2 = {0};
            vx_result r2 = read_buf(&b, &(vx_vox_read_desc){.all_frames = true}, &s2, &e2);
            fprintf(stderr, "  %-34s -> %s: %s\n", "2^18 copies over 400 frames", vx_result_str(r2), e2.msg);
            CHECKF(r2 == VX_ERR_LIMIT && strstr(e2.msg, "over all frames"), "got %s: %s", vx_result_str(r2), e2.msg);
            if (r2 == VX_OK) vx_vox_scene_free(&s2);
            /* one frame of it is a real scene (262,144 hidden copies) */
            r2 = read_buf(&b, NULL, &s2, &e2);
            CHECKF(r2 == VX_OK, "%s", e2.msg);
            if (r2 == VX_OK) vx_vox_scene_free(&s2);
        }
        vx_buf_free(&b);
        tb_file(&b, 150);
        tb_model(&b, 1, 1, 1, 1, vv);
        tb_trn(&b, 0, 1, -1, false, NULL, -1, 0, 0, 0);
        tb_shp(&b, 1, 0);
        tb_shp(&b, 1, 0);
        tb_finish(&b);
        expect_fail(&b, VX_ERR_BAD_FORMAT, "used by two", "duplicate node id");
        vx_buf_free(&b);
        tb_file(&b, 150);
        tb_model(&b, 1, 1, 1, 1, vv);
        tb_trn(&b, 5, 1, -1, false, NULL, -1, 0, 0, 0);
        tb_shp(&b, 1, 0);
        tb_finish(&b);
        expect_fail(&b, VX_ERR_BAD_FORMAT, "root", "no root node 0");
        vx_buf_free(&b);
        tb_file(&b, 150);
        tb_model(&b, 1, 1, 1, 1, vv);
        tb_trn(&b, 0, 1, -1, false, NULL, 3, 0, 0, 0); /* row 0 index 3 */
        tb_shp(&b, 1, 0);
        tb_finish(&b);
        expect_fail(&b, VX_ERR_BAD_FORMAT, "nTRN", "invalid rotation _r 3");
        vx_buf_free(&b);
        tb_file(&b, 150);
        tb_model(&b, 1, 1, 1, 1, vv);
        int32_t k2 = 2;
        tb_trn(&b, 0, 1, -1, false, NULL, -1, 1 << 30, 0, 0);
        tb_grp(&b, 1, false, 1, &k2);
        tb_trn(&b, 2, 3, -1, false, NULL, -1, 1 << 30, 0, 0);
        tb_shp(&b, 3, 0);
        tb_finish(&b);
        expect_fail(&b, VX_ERR_LIMIT, "nTRN", "composed translation 2^31");
        vx_buf_free(&b);
        /* a deep chain T -> G -> T -> G ... beyond the depth limit */
        tb_file(&b, 150);
        tb_model(&b, 1, 1, 1, 1, vv);
        for (int i = 0; i < 600; i += 2) {
            int32_t kid = i + 2;
            tb_trn(&b, i, i + 1, -1, false, NULL, -1, 0, 0, 0);
            tb_grp(&b, i + 1, false, 1, &kid);
        }
        tb_trn(&b, 600, 601, -1, false, NULL, -1, 0, 0, 0);
        tb_shp(&b, 601, 0);
        tb_finish(&b);
        expect_fail(&b, VX_ERR_BAD_FORMAT, "deeper", "graph 300 levels deep");
        vx_buf_free(&b);
        /* dictionary and string lengths */
        tb_file(&b, 150);
        size_t at = tb_begin(&b, "rOBJ");
        tb_u32(&b, 0x7FFFFFFFu);
        tb_end(&b, at);
        tb_finish(&b);
        expect_fail(&b, VX_ERR_TRUNCATED, "rOBJ", "DICT count 0x7FFFFFFF");
        vx_buf_free(&b);
        tb_file(&b, 150);
        at = tb_begin(&b, "LAYR");
        tb_u32(&b, 0);
        tb_u32(&b, 1);
        tb_u32(&b, 0xFFFFFFF0u);
        tb_u32(&b, 0);
        tb_end(&b, at);
        tb_finish(&b);
        expect_fail(&b, VX_ERR_LIMIT, "LAYR", "STRING length 0xFFFFFFF0");
        vx_buf_free(&b);
        tb_file(&b, 150);
        at = tb_begin(&b, "RGBA");
        for (int i = 0; i < 255; i++) tb_u32(&b, 0);
        vx_buf_u8(&b, 1); /* 1021 bytes: a short palette must end on an entry */
        tb_end(&b, at);
        tb_finish(&b);
        expect_fail(&b, VX_ERR_TRUNCATED, "RGBA", "RGBA ending inside an entry");
        vx_buf_free(&b);
        tb_file(&b, 150);
        at = tb_begin(&b, "nTRN");
        tb_u32(&b, 0);
        tb_dict(&b, 0);
        tb_u32(&b, 1);
        tb_u32(&b, UINT32_MAX);
        tb_u32(&b, 0);
        tb_u32(&b, 0x10000000u);
        tb_end(&b, at);
        tb_finish(&b);
        expect_fail(&b, VX_ERR_TRUNCATED, "nTRN", "nTRN frame count 0x10000000");
        vx_buf_free(&b);
    }
}

static void test_validate_and_write_errors(void) {
    vx_vox_model m = {{2, 2, 2}, 1, (uint8_t[4]){0, 0, 0, 1}};
    vx_vox_instance in = {.model = 0, .rot = {1, 0, 0, 0, 1, 0, 0, 0, 1}, .layer = -1};
    vx_vox_scene s = {.model_count = 1, .models = &m, .instance_count = 1, .instances = &in};
    memcpy(s.palette, vx_vox_default_palette, sizeof s.palette);
    vx_error e = {0};
    CHECK(vx_vox_validate(&s, &e) == VX_OK);
    uint8_t* w = NULL;
    size_t wn;
    m.xyzi[0] = 2;
    CHECK(vx_vox_validate(&s, &e) == VX_ERR_INVALID_ARG && strstr(e.msg, "model 0"));
    CHECK(vx_vox_write(&s, NULL, &w, &wn, &e) == VX_ERR_INVALID_ARG && w == NULL);
    m.xyzi[0] = 0;
    m.xyzi[3] = 0;
    CHECK(vx_vox_validate(&s, &e) == VX_ERR_INVALID_ARG);
    m.xyzi[3] = 1;
    in.rot[0] = 2;
    CHECK(vx_vox_validate(&s, &e) == VX_ERR_INVALID_ARG && strstr(e.msg, "rotation"));
    in.rot[0] = 1;
    in.model = 1;
    CHECK(vx_vox_validate(&s, &e) == VX_ERR_INVALID_ARG && strstr(e.msg, "model 1"));
    in.model = 0;
    m.size[1] = 257;
    CHECK(vx_vox_validate(&s, &e) == VX_ERR_INVALID_ARG);
    m.size[1] = 2;
    CHECK(vx_vox_validate(NULL, &e) == VX_ERR_INVALID_ARG);
    /* write_file: atomic, read back equal; a missing folder is an I/O error */
    char path[] = "/tmp/vx_test_vox_XXXXXX";
    int fd = mkstemp(path);
    REQUIRE(fd >= 0);
    close(fd);
    CHECK(vx_vox_write_file(NULL, &s, path, &e) == VX_OK);
    vx_vox_scene r;
    CHECK(vx_vox_read_file(NULL, path, &r, &e) == VX_OK);
    if (!vx_t_cur_failed) {
        const char* diff = tv_scene_diff(&s, &r);
        CHECKF(!diff, "%s", diff);
        vx_vox_scene_free(&r);
    }
    remove(path);
    CHECK(vx_vox_write_file(NULL, &s, "/nonexistent-dir/x.vox", &e) == VX_ERR_IO);
    CHECK(vx_vox_read_file(NULL, "/nonexistent-dir/x.vox", &r, &e) == VX_ERR_IO);
}

/* ---- out of memory ------------------------------------------------------------------------------ */

static void oom_loop(const char* what, const uint8_t* d, size_t n, bool persistent) {
    long fails = 0;
    for (long at = 1;; at++) {
        tfail f = {.fail_at = at, .persistent = persistent};
        vx_allocator a = {tfail_alloc, tfail_free, &f};
        vx_vox_scene s;
        memset(&s, 0xAB, sizeof s);
        vx_error e = {0};
        vx_result r = vx_vox_read(&(vx_vox_read_desc){.alloc = &a}, d, n, &s, &e);
        if (r == VX_OK) {
            CHECK(!f.failed);
            /* and the writer under the same countdown */
            long wfails = 0;
            for (long wat = 1;; wat++) {
                tfail g = {.fail_at = wat, .persistent = persistent};
                vx_allocator ga = {tfail_alloc, tfail_free, &g};
                uint8_t* w = NULL;
                size_t wn = 0;
                vx_result wr = vx_vox_write(&s, &ga, &w, &wn, &e);
                if (wr == VX_OK) {
                    vx_free(&ga, w);
                    CHECK(g.live == 0);
                    break;
                }
                CHECKF(wr == VX_ERR_NOMEM && w == NULL && g.live == 0, "%s write fail at %ld: %s live %ld", what, wat,
                       vx_result_str(wr), g.live);
                wfails++;
                if (vx_t_cur_failed) break;
            }
            vx_vox_scene_free(&s);
            CHECK(f.live == 0);
            fprintf(stderr, "  %s (%s): %ld failing reads, %ld failing writes\n", what,
                    persistent ? "persistent" : "transient", fails, wfails);
            return;
        }
        fails++;
        CHECKF(r == VX_ERR_NOMEM, "%s fail at %ld: %s (%s)", what, at, vx_result_str(r), e.msg);
        CHECKF(f.live == 0, "%s fail at %ld: %ld blocks leaked", what, at, f.live);
        CHECK(s.model_count == 0xABABABABu); /* output untouched */
        if (vx_t_cur_failed) return;
    }
}

/* ---- Teardown's TDCZ -------------------------------------------------------------------------- */

/* SIZE s, then TDCZ declaring sizes t and the first `ncomp` cells of grid
 * (x fastest) deflated; finish false stops after a sync flush, as Teardown
 * leaves its streams (no final block, no Adler-32); junk follows the stream. */
static void tb_tdcz(vx_buf* b, const uint32_t s[3], const uint32_t t[3], uint8_t* grid, size_t ncomp, bool finish,
                    const char* junk) {
    size_t at = tb_begin(b, "SIZE");
    for (int k = 0; k < 3; k++) tb_u32(b, s[k]);
    tb_end(b, at);
    at = tb_begin(b, "TDCZ");
    for (int k = 0; k < 3; k++) tb_u32(b, t[k]);
    z_stream z;
    memset(&z, 0, sizeof z);
    REQUIRE(deflateInit(&z, 9) == Z_OK);
    uLong bound = deflateBound(&z, (uLong)ncomp) + 64;
    uint8_t* out = (uint8_t*)malloc(bound);
    z.next_in = grid;
    z.avail_in = (uInt)ncomp;
    z.next_out = out;
    z.avail_out = (uInt)bound;
    int zr = deflate(&z, finish ? Z_FINISH : Z_SYNC_FLUSH);
    CHECK(zr == (finish ? Z_STREAM_END : Z_OK) && z.avail_in == 0);
    vx_buf_append(b, out, bound - z.avail_out);
    deflateEnd(&z);
    free(out);
    if (junk) vx_buf_append(b, junk, strlen(junk));
    tb_end(b, at);
}

/* An RGBA chunk of n entries, entry e = 0xff000000 | e * 0x010203 */
static void tb_rgba(vx_buf* b, int n) {
    size_t at = tb_begin(b, "RGBA");
    for (int e = 0; e < n; e++) tb_u32(b, 0xff000000u | (uint32_t)e * 0x010203u);
    tb_end(b, at);
}

#define TD_X 5
#define TD_Y 3
#define TD_Z 4
#define TD_CELLS (TD_X * TD_Y * TD_Z)

static void td_grid(uint8_t g[TD_CELLS]) {
    for (int k = 0; k < TD_CELLS; k++) g[k] = (k * 7) % 3 ? (uint8_t)(1 + (k * 37) % 255) : 0;
}

/* Two models: an unterminated stream, and a terminated one with bytes after it. */
static void td_file(vx_buf* b, int rgba_entries) {
    static const uint32_t sz[3] = {TD_X, TD_Y, TD_Z}, one[3] = {2, 1, 1};
    uint8_t g[TD_CELLS], g2[2] = {0, 200};
    td_grid(g);
    tb_file(b, 150);
    tb_tdcz(b, sz, sz, g, TD_CELLS, false, NULL);
    tb_tdcz(b, one, one, g2, 2, true, "trailing bytes");
    if (rgba_entries >= 0) tb_rgba(b, rgba_entries);
    tb_finish(b);
}

static void test_teardown(void) {
    static const uint32_t sz[3] = {TD_X, TD_Y, TD_Z}, other[3] = {TD_X, TD_Z, TD_Y};
    uint8_t g[TD_CELLS];
    td_grid(g);
    const int entries[] = {255, 16, 256, 0};
    for (int ei = 0; ei < 4; ei++) {
        vx_buf b;
        td_file(&b, entries[ei]);
        vx_vox_scene s;
        vx_error e = {0};
        vx_result r = read_buf(&b, NULL, &s, &e);
        CHECKF(r == VX_OK, "TDCZ with %d RGBA entries: %s", entries[ei], e.msg);
        vx_buf_free(&b);
        if (r != VX_OK) continue;
        CHECK(s.model_count == 2 && s.instance_count == 1);
        /* the voxels in x-fastest order, index 0 left out */
        uint32_t n = 0;
        bool same = s.models[0].size[0] == TD_X && s.models[0].size[1] == TD_Y && s.models[0].size[2] == TD_Z;
        for (int k = 0; k < TD_CELLS && same; k++) {
            if (!g[k]) continue;
            const uint8_t* p = s.models[0].xyzi + (size_t)n++ * 4;
            same = n <= s.models[0].voxel_count && p[0] == k % TD_X && p[1] == (k / TD_X) % TD_Y &&
                   p[2] == k / (TD_X * TD_Y) && p[3] == g[k];
        }
        CHECK(same && n == s.models[0].voxel_count);
        CHECK(s.models[1].voxel_count == 1 && !memcmp(s.models[1].xyzi, (uint8_t[]){1, 0, 0, 200}, 4));
        /* entry e is colour index e + 1; the rest keep the default colours */
        bool pal = s.has_rgba && s.palette[0] == 0;
        for (int i = 1; i < 256; i++)
            pal = pal && s.palette[i] == (i <= entries[ei] ? 0xff000000u | (uint32_t)(i - 1) * 0x010203u
                                                             : vx_vox_default_palette[i]);
        CHECKF(pal, "palette of %d entries", entries[ei]);
        CHECK(vx_vox_validate(&s, NULL) == VX_OK);
        vx_vox_scene_free(&s);
    }

    vx_buf b;
    tb_file(&b, 150);
    tb_tdcz(&b, sz, sz, g, TD_CELLS - 7, false, NULL);
    tb_finish(&b);
    expect_fail(&b, VX_ERR_TRUNCATED, "TDCZ chunk at byte 44: the compressed voxels end after 53 of 60 cells",
                "TDCZ stream short of its cells");
    vx_buf_free(&b);
    tb_file(&b, 150);
    tb_tdcz(&b, sz, other, g, TD_CELLS, false, NULL);
    tb_finish(&b);
    expect_fail(&b, VX_ERR_BAD_FORMAT, "sizes 5 x 4 x 3 differ from the 5 x 3 x 4 of the SIZE chunk", "TDCZ sizes not SIZE's");
    vx_buf_free(&b);
    tb_file(&b, 150);
    tb_tdcz(&b, sz, sz, g, TD_CELLS, false, NULL);
    b.data[20 + 24 + 12 + 12] ^= 0x20; /* the zlib header's first byte */
    tb_finish(&b);
    expect_fail(&b, VX_ERR_BAD_FORMAT, "TDCZ chunk at byte 44: zlib error", "TDCZ not a zlib stream");
    vx_buf_free(&b);
    tb_file(&b, 150);
    size_t at = tb_begin(&b, "SIZE");
    for (int k = 0; k < 3; k++) tb_u32(&b, 2);
    tb_end(&b, at);
    at = tb_begin(&b, "TDCZ");
    tb_u32(&b, 2);
    tb_u32(&b, 2);
    tb_end(&b, at);
    tb_finish(&b);
    expect_fail(&b, VX_ERR_TRUNCATED, "TDCZ", "TDCZ without its sizes");
    vx_buf_free(&b);
    tb_file(&b, 150);
    at = tb_begin(&b, "TDCZ");
    tb_end(&b, at);
    tb_finish(&b);
    expect_fail(&b, VX_ERR_BAD_FORMAT, "TDCZ chunk at byte 20: voxels without a preceding SIZE", "TDCZ without SIZE");
    vx_buf_free(&b);

    /* limits: max_voxels counts TDCZ voxels; sides over 256 (max_dim raised) cannot be records */
    td_file(&b, -1);
    vx_vox_scene s;
    vx_error e = {0};
    CHECK(read_buf(&b, &(vx_vox_read_desc){.max_voxels = 20}, &s, &e) == VX_ERR_LIMIT && strstr(e.msg, "TDCZ"));
    /* allocation failures at every step, then every prefix and random flips */
    oom_loop("TDCZ", b.data, b.size, false);
    oom_loop("TDCZ persistent", b.data, b.size, true);
    uint8_t* c = (uint8_t*)malloc(b.size);
    for (size_t len = 20; len < b.size; len++) {
        memcpy(c, b.data, len);
        vx_buf_put_u32le(c + 16, (uint32_t)(len - 20));
        read_must_not_crash(c, len);
    }
    for (int it = 0; it < 3000; it++) {
        memcpy(c, b.data, b.size);
        for (int k = 1 + (int)(rng() % 3); k > 0; k--) {
            size_t p = 20 + (size_t)(rng() % (b.size - 20));
            c[p] = (rng() & 1) ? (uint8_t)rng() : (uint8_t)(c[p] ^ (1u << (rng() % 8)));
        }
        read_must_not_crash(c, b.size);
    }
    free(c);
    vx_buf_free(&b);
    static const uint32_t wide[3] = {257, 1, 1};
    uint8_t gw[257] = {1};
    tb_file(&b, 150);
    tb_tdcz(&b, wide, wide, gw, 257, false, NULL);
    tb_finish(&b);
    e.msg[0] = 0;
    CHECK(read_buf(&b, &(vx_vox_read_desc){.max_dim = 300}, &s, &e) == VX_ERR_LIMIT && strstr(e.msg, "beyond 256"));
    fprintf(stderr, "  side 257: %s\n", e.msg);
    vx_buf_free(&b);
}

static void test_oom(void) {
    static const char* files[] = {"eph_chr_knight.vox", "ogt_test_groups.vox"};
    int found = 0;
    for (int i = 0; i < 2; i++) {
        size_t n;
        uint8_t* d = load_corpus(files[i], &n);
        if (!d) continue;
        found++;
        oom_loop(files[i], d, n, false);
        oom_loop(files[i], d, n, true);
        free(d);
    }
    /* and a synthetic file with every chunk kind */
    vx_buf b;
    build_hidden(&b);
    oom_loop("synthetic hidden", b.data, b.size, false);
    vx_buf_free(&b);
    if (!found) SKIP("corpus vox/ not found");
}

int main(void) {
    RUN(test_default_palette);
    RUN(test_rotations);
    RUN(test_place_random);
    RUN(test_corpus);
    RUN(test_knight_resave);
    RUN(test_perf_monu1);
    RUN(test_empty_and_one_voxel);
    RUN(test_nested_groups);
    RUN(test_hidden);
    RUN(test_animation);
    RUN(test_pack_frames);
    RUN(test_other_chunks);
    RUN(test_bad_input);
    RUN(test_validate_and_write_errors);
    RUN(test_truncations);
    RUN(test_byte_flips);
    RUN(test_teardown);
    RUN(test_oom);
    return vx_test_finish();
}
