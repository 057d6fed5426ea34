/* tests/convert/test_vox_svo.c - .vox -> .svo is exact.
 *
 * Two independent paths give the voxels of a scene in world cells:
 *  (a) the .vox reader's own placement (vx_vox_place over the raw XYZI data);
 *  (b) the .svo path: convert, serialise, parse, decode each octree and
 *      apply the instance's affine transform in floating point.
 * They must agree cell for cell and colour for colour, and
 * .vox -> .svo -> .vox -> .svo must give the same voxel set again. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "convert/convert.h"
#include "tests/test.h"
#include "tests/test_vox.h"

typedef struct cell {
    int32_t x, y, z;
    uint32_t rgba;
} cell;

typedef struct cells {
    cell* v;
    size_t n, cap;
} cells;

static void push(cells* c, int32_t x, int32_t y, int32_t z, uint32_t rgba) {
    if (c->n == c->cap) {
        c->cap = c->cap ? c->cap * 2 : 1024;
        c->v = realloc(c->v, c->cap * sizeof *c->v);
    }
    c->v[c->n++] = (cell){x, y, z, rgba};
}

static int cmp_cell(const void* a, const void* b) {
    const cell *p = a, *q = b;
    if (p->x != q->x) return p->x < q->x ? -1 : 1;
    if (p->y != q->y) return p->y < q->y ? -1 : 1;
    if (p->z != q->z) return p->z < q->z ? -1 : 1;
    return p->rgba < q->rgba ? -1 : p->rgba > q->rgba;
}

/* Hidden: by its nodes (hidden), or by its own layer's flag (formats/vox.h). */
static bool vox_hidden(const vx_vox_scene* s, const vx_vox_instance* in) {
    for (uint32_t l = 0; l < s->layer_count; l++)
        if (s->layers[l].id == in->layer && s->layers[l].hidden) return true;
    return in->hidden;
}

static bool svo_hidden(const vx_svo_scene* s, const vx_svo_instance* in) {
    if (in->layer < s->layer_count && (s->layers[in->layer].flags & VX_SVO_LAYER_HIDDEN)) return true;
    return (in->flags & VX_SVO_INSTANCE_HIDDEN) != 0;
}

static void cells_from_vox(const vx_vox_scene* s, cells* out) {
    for (uint32_t i = 0; i < s->instance_count; i++) {
        const vx_vox_instance* in = &s->instances[i];
        if (vox_hidden(s, in)) continue;
        const vx_vox_model* m = &s->models[in->model];
        for (uint32_t k = 0; k < m->voxel_count; k++) {
            const uint8_t* v = m->xyzi + 4 * (size_t)k;
            uint32_t vv[3] = {v[0], v[1], v[2]};
            int32_t w[3];
            vx_vox_place(in->rot, in->t, m->size, vv, w);
            push(out, w[0], w[1], w[2], s->palette[v[3]]);
        }
    }
    qsort(out->v, out->n, sizeof *out->v, cmp_cell);
}

typedef struct dec_ctx {
    const vx_svo_scene* s;
    const vx_svo_model* m;
    const double* x;
    cells* out;
} dec_ctx;

static bool on_voxel(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    dec_ctx* c = user;
    double p[3] = {x + 0.5, y + 0.5, z + 0.5};
    int32_t g[3];
    for (int r = 0; r < 3; r++)
        g[r] = (int32_t)floor(c->x[r * 4] * p[0] + c->x[r * 4 + 1] * p[1] + c->x[r * 4 + 2] * p[2] + c->x[r * 4 + 3]);
    push(c->out, g[0], g[1], g[2], vx_svo_attr_color(c->s, c->m, attr));
    return true;
}

static bool cells_from_svo(const vx_svo_scene* s, cells* out) {
    for (uint32_t i = 0; i < s->instance_count; i++) {
        const vx_svo_instance* in = &s->instances[i];
        if (svo_hidden(s, in)) continue;
        dec_ctx c = {s, &s->models[in->model], in->xform, out};
        vx_error err = {0};
        if (vx_svo_decode_model(c.m, on_voxel, &c, &err) != VX_OK) {
            fprintf(stderr, "decode: %s\n", err.msg);
            return false;
        }
    }
    qsort(out->v, out->n, sizeof *out->v, cmp_cell);
    return true;
}

static bool same_cells(const cells* a, const cells* b, const char* what) {
    if (a->n != b->n) {
        fprintf(stderr, "  %s: %zu cells vs %zu\n", what, a->n, b->n);
        return false;
    }
    for (size_t i = 0; i < a->n; i++)
        if (cmp_cell(&a->v[i], &b->v[i])) {
            fprintf(stderr, "  %s: first difference at %zu: (%d %d %d %08x) vs (%d %d %d %08x)\n", what, i, a->v[i].x,
                    a->v[i].y, a->v[i].z, a->v[i].rgba, b->v[i].x, b->v[i].y, b->v[i].z, b->v[i].rgba);
            return false;
        }
    return true;
}

/* vox scene -> svo scene -> bytes (written with wd, NULL: the defaults) -> svo scene */
static bool through_file_w(const vx_vox_scene* vs, vx_svo_scene* out, const vx_svo_build_desc* bd, const vx_write_desc* wd) {
    vx_svo_scene s;
    vx_error err = {0};
    vx_conv_stats st;
    if (vx_conv_vox(&(vx_conv_vox_desc){.build = *bd}, vs, &s, &st, &err) != VX_OK) {
        fprintf(stderr, "  convert: %s\n", err.msg);
        return false;
    }
    uint8_t* bytes = NULL;
    size_t n = 0;
    vx_result r = vx_svo_write_ex(wd, &s, &bytes, &n, &err);
    vx_svo_scene_free(&s);
    if (r != VX_OK) {
        fprintf(stderr, "  write: %s\n", err.msg);
        return false;
    }
    r = vx_svo_read(NULL, bytes, n, out, &err);
    free(bytes);
    if (r != VX_OK) {
        fprintf(stderr, "  read back: %s\n", err.msg);
        return false;
    }
    return true;
}

static bool through_file(const vx_vox_scene* vs, vx_svo_scene* out, const vx_svo_build_desc* bd) {
    return through_file_w(vs, out, bd, NULL);
}

/* The same node words and records (docs/FORMAT.md 3). */
static bool same_models(const vx_svo_scene* x, const vx_svo_scene* y) {
    if (x->model_count != y->model_count) return false;
    for (uint32_t i = 0; i < x->model_count; i++) {
        const vx_svo_model *a = &x->models[i], *b = &y->models[i];
        if (a->node_count != b->node_count || a->attr_count != b->attr_count || a->root != b->root || a->root_attr != b->root_attr ||
            a->attrs != b->attrs || (a->node_count && memcmp(a->nodes, b->nodes, (size_t)a->node_count * 4)))
            return false;
        if ((a->attrs & VX_ATTR_PALETTE) && a->attr_count && memcmp(a->palette, b->palette, a->attr_count)) return false;
        if ((a->attrs & VX_ATTR_RGBA8) && a->attr_count && memcmp(a->rgba, b->rgba, (size_t)a->attr_count * 4)) return false;
    }
    return true;
}

/* Models some instance of vs places (what vx_conv_vox stores by default). */
static uint32_t placed_models(const vx_vox_scene* vs) {
    uint32_t n = 0;
    for (uint32_t m = 0; m < vs->model_count; m++) {
        bool used = false;
        for (uint32_t i = 0; i < vs->instance_count && !used; i++) used = vs->instances[i].model == m;
        n += used;
    }
    return n;
}

static void check_scene(const char* name, const vx_vox_scene* vs) {
    cells a = {0}, b = {0}, c = {0}, d = {0};
    cells_from_vox(vs, &a);
    static const vx_svo_build_desc modes[] = {{0}, {.no_collapse = true}, {.no_dag = true}, {.no_collapse = true, .no_dag = true}};
    for (unsigned mode = 0; mode < 4; mode++) {
        vx_svo_scene s;
        REQUIRE(through_file(vs, &s, &modes[mode]));
        CHECK(s.model_count == placed_models(vs)); /* instancing kept: no copies; unused models left out */
        b.n = 0;
        CHECK(cells_from_svo(&s, &b));
        CHECKF(same_cells(&a, &b, name), "%s: reader placement != decoded svo (mode %u)", name, mode);
        /* every model in the chunked form (format version 3): the same words,
         * records and cells */
        {
            vx_svo_scene sc;
            REQUIRE(through_file_w(vs, &sc, &modes[mode], &(vx_write_desc){.svo_chunk_words = 1}));
            CHECKF(same_models(&s, &sc), "%s: chunked form read back other words or records (mode %u)", name, mode);
            c.n = 0;
            CHECK(cells_from_svo(&sc, &c));
            CHECKF(same_cells(&a, &c, name), "%s: reader placement != decoded chunked svo (mode %u)", name, mode);
            vx_svo_scene_free(&sc);
        }

        if (mode == 0) {
            /* svo -> vox -> svo: the same voxel set again */
            vx_vox_scene v2;
            vx_error err = {0};
            vx_result r = vx_conv_svo_to_vox(&s, NULL, &v2, &err);
            CHECKF(r == VX_OK, "%s: svo -> vox: %s", name, err.msg);
            if (r == VX_OK) {
                uint8_t* bytes = NULL;
                size_t n = 0;
                r = vx_vox_write(&v2, NULL, &bytes, &n, &err);
                CHECKF(r == VX_OK, "%s: vox write: %s", name, err.msg);
                vx_vox_scene v3;
                if (r == VX_OK) {
                    r = vx_vox_read(NULL, bytes, n, &v3, &err);
                    CHECKF(r == VX_OK, "%s: vox re-read: %s", name, err.msg);
                    free(bytes);
                }
                if (r == VX_OK) {
                    c.n = 0;
                    cells_from_vox(&v3, &c);
                    CHECKF(same_cells(&a, &c, name), "%s: .vox -> .svo -> .vox changed the voxels", name);
                    vx_svo_scene s3;
                    if (through_file(&v3, &s3, &modes[0])) {
                        d.n = 0;
                        CHECK(cells_from_svo(&s3, &d));
                        CHECKF(same_cells(&a, &d, name), "%s: .vox -> .svo -> .vox -> .svo changed the voxels", name);
                        vx_svo_scene_free(&s3);
                    } else {
                        CHECK(!"second conversion failed");
                    }
                    vx_vox_scene_free(&v3);
                }
                vx_vox_scene_free(&v2);
            }
        }
        vx_svo_scene_free(&s);
    }
    fprintf(stderr, "  %s: %zu cells agree\n", name, a.n);
    free(a.v);
    free(b.v);
    free(c.v);
    free(d.v);
}

static const char* corpus[] = {
    "eph_chr_knight.vox", "eph_dragon.vox", "eph_teapot.vox", "eph_menger.vox", "eph_monu1.vox",
    "ogt_test_groups.vox", "ogt_test_multiple_model_scene.vox", "ogt_doom.vox", "ogt_chr_knight.vox",
};

static void test_corpus(void) {
    int found = 0;
    for (size_t i = 0; i < sizeof corpus / sizeof corpus[0]; i++) {
        char rel[256];
        snprintf(rel, sizeof rel, "vox/%s", corpus[i]);
        const char* path = vx_test_corpus(rel);
        if (!path) continue;
        found++;
        vx_vox_scene vs;
        vx_error err = {0};
        vx_result r = vx_vox_read_file(NULL, path, &vs, &err);
        CHECKF(r == VX_OK, "%s: %s", corpus[i], err.msg);
        if (r != VX_OK) continue;
        check_scene(corpus[i], &vs);
        vx_vox_scene_free(&vs);
    }
    if (!found) SKIP("corpus not found (../shared/corpus/vox); set VX_CORPUS_DIR");
}

static void test_keep_hidden(void) {
    const char* path = vx_test_corpus("vox/ogt_test_groups.vox");
    if (!path) SKIP("corpus not found");
    vx_vox_scene vs;
    vx_error err = {0};
    REQUIRE(vx_vox_read_file(&(vx_vox_read_desc){.keep_hidden = true}, path, &vs, &err) == VX_OK);
    check_scene("ogt_test_groups.vox (keep hidden)", &vs);
    vx_vox_scene_free(&vs);
}

/* A scene written by the project's own writer: 5 models of different
 * sizes and colours, model 2 placed twice (one mirrored), model 4 only by
 * an instance on a hidden layer, models 0, 1 and 3 by nothing (like the
 * other frames of an animation). Colours 10 + m, a MATL record for each. */
static vx_result unused_scene(bool keep_hidden, vx_vox_scene* out) {
    vx_vox_scene s;
    memset(&s, 0, sizeof s);
    s.version = 150;
    s.model_count = 5;
    s.models = calloc(5, sizeof *s.models);
    s.instances = calloc(3, sizeof *s.instances);
    s.layers = calloc(2, sizeof *s.layers);
    s.materials = calloc(5, sizeof *s.materials);
    if (!s.models || !s.instances || !s.layers || !s.materials) return VX_ERR_NOMEM;
    for (uint32_t m = 0; m < 5; m++) {
        vx_vox_model* vm = &s.models[m];
        uint32_t n = 3 + m;
        vm->size[0] = n;
        vm->size[1] = n + 1;
        vm->size[2] = 2 * n;
        vm->xyzi = malloc(4 * (size_t)n * n);
        if (!vm->xyzi) return VX_ERR_NOMEM;
        for (uint32_t y = 0; y < n; y++) /* a diagonal wall: x == z / 2 */
            for (uint32_t x = 0; x < n; x++) {
                uint8_t* v = vm->xyzi + 4 * (size_t)vm->voxel_count++;
                v[0] = (uint8_t)x;
                v[1] = (uint8_t)y;
                v[2] = (uint8_t)(2 * x + (y & 1));
                v[3] = (uint8_t)(10 + m);
            }
        static const char dict[] = "_type\0_metal\0";
        s.materials[m].id = 10 + m;
        s.materials[m].dict_size = sizeof dict - 1; /* the literal's own NUL is not part of it */
        s.materials[m].dict = malloc(sizeof dict);
        if (!s.materials[m].dict) return VX_ERR_NOMEM;
        memcpy(s.materials[m].dict, dict, sizeof dict);
    }
    s.material_count = 5;
    memcpy(s.palette, vx_vox_default_palette, sizeof s.palette);
    s.layer_count = 2;
    s.layers[0] = (vx_vox_layer){.id = 0, .name = "shown"};
    s.layers[1] = (vx_vox_layer){.id = 1, .hidden = true, .name = "hidden"};
    static const int32_t id[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, mirror[9] = {-1, 0, 0, 0, 0, 1, 0, 1, 0};
    s.instances[0] = (vx_vox_instance){.model = 2, .layer = 0, .t = {5, -3, 7}, .name = "placed"};
    memcpy(s.instances[0].rot, id, sizeof id);
    s.instances[1] = (vx_vox_instance){.model = 2, .layer = 0, .t = {-20, 4, 0}, .name = "placed, mirrored"};
    memcpy(s.instances[1].rot, mirror, sizeof mirror);
    s.instances[2] = (vx_vox_instance){.model = 4, .layer = 1, .t = {0, 30, 0}, .name = "on the hidden layer"};
    memcpy(s.instances[2].rot, id, sizeof id);
    s.instance_count = 3;
    uint8_t* bytes = NULL;
    size_t n = 0;
    vx_error err = {0};
    vx_result r = vx_vox_write(&s, NULL, &bytes, &n, &err);
    vx_vox_scene_free(&s);
    if (!r) r = vx_vox_read(&(vx_vox_read_desc){.keep_hidden = keep_hidden}, bytes, n, out, &err);
    free(bytes);
    if (r) fprintf(stderr, "  unused_scene: %s\n", err.msg);
    return r;
}

/* Unused models are left out by default (renumbered, the same voxels),
 * kept with keep_unused; the statistics count them either way. */
static void test_unused_models(void) {
    vx_vox_scene vs;
    REQUIRE(unused_scene(false, &vs) == VX_OK);
    REQUIRE(vs.model_count == 5 && vs.instance_count == 2); /* the hidden layer's instance is not read */
    cells want = {0};
    cells_from_vox(&vs, &want);
    CHECK(want.n == 2 * 5 * 5);
    size_t bytes[2] = {0, 0};
    for (int keep = 0; keep < 2; keep++) {
        vx_svo_scene s;
        vx_conv_stats st;
        vx_error err = {0};
        REQUIRE(vx_conv_vox(&(vx_conv_vox_desc){.keep_unused = keep}, &vs, &s, &st, &err) == VX_OK);
        CHECKF(st.models_unused == 4, "keep %d: %u unused", keep, st.models_unused);
        CHECKF(s.model_count == (keep ? 5u : 1u) && st.models == s.model_count, "keep %d: %u models", keep, s.model_count);
        for (uint32_t i = 0; i < s.instance_count; i++) CHECK(s.instances[i].model == (keep ? 2u : 0u));
        /* the materials of the stored models' colours */
        CHECKF(s.material_count == (keep ? 5u : 1u) && s.materials[0].id == (keep ? 10u : 12u), "%u materials, first id %u",
               s.material_count, s.material_count ? s.materials[0].id : 0);
        cells got = {0};
        CHECK(cells_from_svo(&s, &got));
        CHECKF(same_cells(&want, &got, "unused models"), "keep %d: voxels differ", keep);
        free(got.v);
        uint8_t* data = NULL;
        REQUIRE(vx_svo_write(&s, NULL, &data, &bytes[keep], &err) == VX_OK);
        free(data);
        vx_svo_scene_free(&s);
    }
    CHECKF(bytes[0] < bytes[1], "%zu bytes without the unused models, %zu with", bytes[0], bytes[1]);
    vx_vox_scene_free(&vs);
    free(want.v);
    /* keep_hidden: the hidden instance places model 4, which is then stored
     * (as model 1, after model 2 as model 0) */
    REQUIRE(unused_scene(true, &vs) == VX_OK);
    REQUIRE(vs.instance_count == 3);
    vx_svo_scene s;
    vx_conv_stats st;
    REQUIRE(vx_conv_vox(NULL, &vs, &s, &st, NULL) == VX_OK);
    CHECK(st.models_unused == 3 && s.model_count == 2);
    uint32_t hidden = 0;
    for (uint32_t i = 0; i < s.instance_count; i++) {
        bool h = svo_hidden(&s, &s.instances[i]); /* its layer's flag (the instance's own is clear) */
        hidden += h;
        CHECK(s.instances[i].model == (h ? 1u : 0u));
    }
    CHECK(hidden == 1);
    CHECK(s.material_count == 2);
    check_scene("unused models (keep hidden)", &vs);
    vx_svo_scene_free(&s);
    vx_vox_scene_free(&vs);
}

static void put32(uint8_t** p, uint32_t v) {
    for (int i = 0; i < 4; i++) *(*p)++ = (uint8_t)(v >> (8 * i));
}

/* A legacy animation (.vox 150 without a scene graph, PACK of 8 frames,
 * frame f a 4^3 cube of varied colours shifted by f cells). */
enum { FRAMES = 8, N = 4 * 4 * 4 };
static uint8_t pack_file[8 + 12 + 16 + FRAMES * (24 + 16 + 4 * N)];
static bool make_pack(void) {
    uint8_t* file = pack_file;
    uint8_t* p = file;
    memcpy(p, "VOX ", 4);
    p += 4;
    put32(&p, 150);
    memcpy(p, "MAIN", 4);
    p += 4;
    put32(&p, 0);
    put32(&p, (uint32_t)(sizeof pack_file - 20));
    memcpy(p, "PACK", 4);
    p += 4;
    put32(&p, 4);
    put32(&p, 0);
    put32(&p, FRAMES);
    for (uint32_t f = 0; f < FRAMES; f++) {
        memcpy(p, "SIZE", 4);
        p += 4;
        put32(&p, 12);
        put32(&p, 0);
        put32(&p, 4 + f);
        put32(&p, 4);
        put32(&p, 4);
        memcpy(p, "XYZI", 4);
        p += 4;
        put32(&p, 4 + 4 * N);
        put32(&p, 0);
        put32(&p, N);
        for (uint32_t i = 0; i < N; i++) {
            *p++ = (uint8_t)(f + (i & 3));
            *p++ = (uint8_t)((i >> 2) & 3);
            *p++ = (uint8_t)(i >> 4);
            *p++ = (uint8_t)(1 + (i * 37 + f * 11) % 200); /* varied colours: no collapse */
        }
    }
    return p == file + sizeof pack_file;
}

/* With --frame, only the chosen frame's model is placed, and stored;
 * keep_unused stores all 8 (about 8 times the bytes). */
static void test_unused_animation_frames(void) {
    REQUIRE(make_pack());
    const uint8_t* file = pack_file;
    const size_t file_size = sizeof pack_file;
    for (uint32_t frame = 0; frame < FRAMES; frame += 5) {
        vx_vox_scene vs;
        vx_error err = {0};
        vx_result r = vx_vox_read(&(vx_vox_read_desc){.frame = frame}, file, file_size, &vs, &err);
        CHECKF(r == VX_OK, "%s", err.msg);
        if (r) return;
        REQUIRE(vs.model_count == FRAMES && vs.instance_count == 1 && vs.instances[0].model == frame);
        size_t bytes[2] = {0, 0};
        for (int keep = 0; keep < 2; keep++) {
            vx_svo_scene s;
            vx_conv_stats st;
            REQUIRE(vx_conv_vox(&(vx_conv_vox_desc){.keep_unused = keep}, &vs, &s, &st, &err) == VX_OK);
            CHECK(st.models_unused == FRAMES - 1);
            CHECK(s.model_count == (keep ? FRAMES : 1u) && s.instances[0].model == (keep ? frame : 0u));
            CHECK(s.models[s.instances[0].model].size[0] >= 4 + frame);
            uint8_t* data = NULL;
            REQUIRE(vx_svo_write(&s, NULL, &data, &bytes[keep], &err) == VX_OK);
            free(data);
            vx_svo_scene_free(&s);
        }
        fprintf(stderr, "  frame %u: %zu bytes, %zu with the 7 unused frames\n", frame, bytes[0], bytes[1]);
        CHECKF(bytes[0] * 3 < bytes[1], "%zu vs %zu bytes", bytes[0], bytes[1]); /* the header and palette are shared */
        check_scene("legacy animation", &vs);
        vx_vox_scene_free(&vs);
    }
}

/* ---- animations: every frame equals an independent per-frame flattening ------------ */

/* Cells of svo frame f (through the library's frame view). */
static bool cells_of_frame(const vx_svo_scene* s, uint32_t f, cells* out) {
    vx_svo_scene v;
    return vx_svo_scene_frame(s, f, &v) && cells_from_svo(&v, out);
}

/* Frame f read from the file by the reader's single-frame path (--frame f),
 * placed voxel by voxel, and the same frame converted alone (vox2svo
 * --frame f): both must equal frame f of the all-frames file (anim). */
static void check_frame(const char* what, const uint8_t* file, size_t size, const vx_svo_scene* anim, uint32_t f) {
    vx_vox_scene one;
    vx_error err = {0};
    vx_result r = vx_vox_read(&(vx_vox_read_desc){.frame = f}, file, size, &one, &err);
    CHECKF(r == VX_OK, "%s frame %u: %s", what, f, err.msg);
    if (r) return;
    cells want = {0}, got = {0}, single = {0};
    cells_from_vox(&one, &want);
    vx_svo_scene s1;
    CHECK(cells_of_frame(anim, f, &got));
    CHECKF(same_cells(&want, &got, what), "frame %u of the all-frames file", f);
    if (through_file(&one, &s1, &(vx_svo_build_desc){0})) {
        CHECK(cells_from_svo(&s1, &single) && vx_svo_scene_frames(&s1) == 1);
        CHECKF(same_cells(&single, &got, what), "--frame %u vs frame %u of the all-frames file", f, f);
        vx_svo_scene_free(&s1);
    }
    CHECK(want.n > 0);
    free(want.v), free(got.v), free(single.v);
    vx_vox_scene_free(&one);
}

/* A PACK model sequence: one instance whose model is the frame number. */
static void test_pack_all_frames(void) {
    REQUIRE(make_pack());
    vx_vox_scene vs;
    vx_error err = {0};
    REQUIRE(vx_vox_read(&(vx_vox_read_desc){.all_frames = true}, pack_file, sizeof pack_file, &vs, &err) == VX_OK);
    CHECK(vs.frame_count == FRAMES && vs.frame_instances && vs.instance_count == 1 && vs.instances[0].model == 0);
    vx_svo_scene s;
    REQUIRE(through_file(&vs, &s, &(vx_svo_build_desc){0}));
    CHECK(vx_svo_scene_frames(&s) == FRAMES && s.model_count == FRAMES && s.instance_count == 1);
    for (uint32_t f = 0; f < FRAMES; f++) check_frame("PACK", pack_file, sizeof pack_file, &s, f);
    /* without all_frames the reader still reports the animation's length */
    vx_vox_scene one;
    REQUIRE(vx_vox_read(&(vx_vox_read_desc){.frame = 3}, pack_file, sizeof pack_file, &one, &err) == VX_OK);
    CHECK(one.frame_count == FRAMES && !one.frame_instances);
    vx_vox_scene_free(&one);
    vx_svo_scene_free(&s);
    vx_vox_scene_free(&vs);
}

/* A keyframed scene graph written by our writer (nTRN _f frames, nSHP model
 * keys): 3 models, 3 shapes over 7 frames; shape 0 moves every frame, shape
 * 1 turns and switches models, shape 2 stands still, frame 6 repeats 5. */
static void test_keyframed_all_frames(void) {
    enum { F = 7, I = 3 };
    static const uint8_t rots[4] = {0x04, 0x11, 0x28, 0x06}; /* identity, two turns, a mirror */
    vx_vox_scene g = {0};
    g.version = 150;
    g.model_count = 3;
    g.models = calloc(3, sizeof *g.models);
    uint32_t sizes[3][3] = {{5, 4, 3}, {6, 6, 2}, {3, 7, 4}};
    for (uint32_t m = 0; m < 3; m++) {
        vx_vox_model* vm = &g.models[m];
        memcpy(vm->size, sizes[m], sizeof vm->size);
        vm->xyzi = malloc(4u * 200);
        for (uint32_t x = 0; x < vm->size[0]; x++)
            for (uint32_t y = 0; y < vm->size[1]; y++)
                for (uint32_t z = 0; z < vm->size[2]; z++)
                    if ((x * 7 + y * 3 + z * 5 + m) % 3) {
                        uint8_t* v = vm->xyzi + 4 * (size_t)vm->voxel_count++;
                        v[0] = (uint8_t)x, v[1] = (uint8_t)y, v[2] = (uint8_t)z, v[3] = (uint8_t)(1 + (x + 9 * y + 31 * z + 50 * m) % 250);
                    }
    }
    memcpy(g.palette, vx_vox_default_palette, sizeof g.palette);
    g.layer_count = 1;
    g.layers = calloc(1, sizeof *g.layers);
    g.layers[0].id = 5;
    snprintf(g.layers[0].name, sizeof g.layers[0].name, "actors");
    g.instance_count = I;
    g.instances = calloc(I, sizeof *g.instances);
    g.frame_count = F;
    g.frame_instances = calloc((size_t)F * I, sizeof *g.frame_instances);
    for (uint32_t f = 0; f < F; f++)
        for (uint32_t i = 0; i < I; i++) {
            vx_vox_instance* in = &g.frame_instances[f * I + i];
            uint32_t ff = f == 6 ? 5 : f;
            in->model = i == 1 ? (ff >= 3 && ff < 5 ? 2 : 1) : i == 2 ? 0 : 0;
            REQUIRE(vx_vox_rot_from_byte(i == 1 ? rots[ff % 4] : 0x04, in->rot));
            in->t[0] = (int32_t)(i * 20 + (i == 0 ? ff : 0));
            in->t[1] = (int32_t)(i == 0 ? 2 * ff : 0);
            in->t[2] = (int32_t)(i == 0 ? -(int32_t)ff : 3);
            in->layer = i == 2 ? -1 : 5;
            snprintf(in->name, sizeof in->name, "shape%u", i);
        }
    memcpy(g.instances, g.frame_instances, I * sizeof *g.instances);
    uint8_t* file = NULL;
    size_t size = 0;
    vx_error err = {0};
    vx_result wr = vx_vox_write(&g, NULL, &file, &size, &err);
    CHECKF(wr == VX_OK, "%s", err.msg);
    if (wr) return;
    vx_vox_scene vs;
    REQUIRE(vx_vox_read(&(vx_vox_read_desc){.all_frames = true}, file, size, &vs, &err) == VX_OK);
    CHECK(vs.frame_count == F && vs.instance_count == I);
    /* the reader's frames are the generated ones */
    for (uint32_t k = 0; k < F * I; k++) {
        const vx_vox_instance *a = &g.frame_instances[k], *b = &vs.frame_instances[k];
        CHECKF(a->model == b->model && !memcmp(a->rot, b->rot, sizeof a->rot) && !memcmp(a->t, b->t, sizeof a->t) &&
                   a->layer == b->layer && !strcmp(a->name, b->name),
               "frame %u instance %u", k / I, k % I);
    }
    vx_svo_scene s;
    REQUIRE(through_file(&vs, &s, &(vx_svo_build_desc){0}));
    CHECK(vx_svo_scene_frames(&s) == F && s.model_count == 3 && s.instance_count == I);
    for (uint32_t f = 0; f < F; f++) {
        check_frame("keyframed", file, size, &s, f);
        /* and the generated frame placed directly */
        vx_vox_scene gf = g;
        gf.instances = g.frame_instances + (size_t)f * I;
        cells want = {0}, got = {0};
        cells_from_vox(&gf, &want);
        CHECK(cells_of_frame(&s, f, &got));
        CHECKF(same_cells(&want, &got, "keyframed"), "generated frame %u", f);
        free(want.v), free(got.v);
    }
    vx_svo_scene_free(&s);
    vx_vox_scene_free(&vs);
    free(file);
    /* one name per shape: a frame that renames it cannot be written */
    snprintf(g.frame_instances[2 * I + 1].name, sizeof g.frame_instances[0].name, "other");
    CHECK(vx_vox_write(&g, NULL, &file, &size, &err) == VX_ERR_UNSUPPORTED && strstr(err.msg, "frame 2 instance 1"));
    g.alloc = NULL;
    vx_vox_scene_free(&g);
}

/* A scene of a palette model and an RGBA8 model (svo_view's add of a .vox
 * with another palette makes one) exports to .vox: palette models keep
 * their entries, RGBA8 colours take one of the same colour or a free one;
 * it was refused ("scene mixes palette and RGBA colours"). */
static void test_mixed_colours_export(void) {
    vx_svo_scene s;
    vx_svo_scene_init(&s, NULL);
    s.models = calloc(2, sizeof *s.models);
    s.instances = calloc(2, sizeof *s.instances);
    REQUIRE(s.models && s.instances);
    s.model_count = 2, s.instance_count = 2;
    uint64_t keys[8];
    uint8_t pal[8];
    uint32_t rgba[8];
    for (uint32_t k = 0; k < 8; k++) keys[k] = vx_svo_morton(k & 1, (k >> 1) & 1, k >> 2);
    for (uint32_t k = 0; k < 8; k++) pal[k] = (uint8_t)(1 + k % 3);  /* entries 1, 2, 3 */
    s.has_palette = true;
    for (uint32_t i = 1; i < 256; i++) s.palette[i] = 0xFF000000u | (i * 0x010203u);
    for (uint32_t k = 0; k < 8; k++) rgba[k] = k < 2 ? s.palette[2] : 0xFF000000u | (0x405060u + k); /* entry 2's colour, 6 new */
    vx_svo_voxels pv = {.size = {2, 2, 2}, .count = 8, .keys = keys, .attrs = VX_ATTR_PALETTE, .palette = pal};
    vx_svo_voxels rv = {.size = {2, 2, 2}, .count = 8, .keys = keys, .attrs = VX_ATTR_RGBA8, .rgba = rgba};
    REQUIRE(vx_svo_build_model(&(vx_svo_build_desc){0}, &pv, &s.models[0], NULL, NULL) == VX_OK);
    REQUIRE(vx_svo_build_model(&(vx_svo_build_desc){0}, &rv, &s.models[1], NULL, NULL) == VX_OK);
    static const double x0[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0}, x1[12] = {0, -1, 0, 10, 1, 0, 0, 0, 0, 0, 1, 0};
    memcpy(s.instances[0].xform, x0, sizeof x0);
    memcpy(s.instances[1].xform, x1, sizeof x1);
    s.instances[0].layer = s.instances[1].layer = UINT32_MAX;
    s.instances[1].model = 1;
    cells want = {0}, got = {0};
    CHECK(cells_from_svo(&s, &want));
    vx_vox_scene v;
    vx_error err = {0};
    vx_result r = vx_conv_svo_to_vox(&s, NULL, &v, &err);
    CHECKF(r == VX_OK, "export: %s", err.msg);
    if (r == VX_OK) {
        cells_from_vox(&v, &got);
        CHECK(same_cells(&want, &got, "mixed colours"));
        uint32_t used = 0;
        for (uint32_t i = 1; i < 256; i++) used += v.palette[i] != s.palette[i];
        CHECKF(used == 6, "%u entries given new colours, expected 6", used);
        vx_vox_scene_free(&v);
    }
    free(want.v), free(got.v);
    vx_svo_scene_free(&s);
}

/* ---- models over 256 cells a side: split into pieces ------------------------------------- */

/* A model of size sx x sy x sz: its cells where a plane of each axis's
 * "marks" (both ends, the 256 tile boundaries either side, a few between)
 * meets a line of another, and a scatter; cells only at or past `from` on
 * every axis. Palette entries (rgba false) or RGBA8 colours by place. */
static void split_model(vx_svo_model* out, uint32_t sx, uint32_t sy, uint32_t sz, uint32_t from, bool rgba) {
    const uint32_t S[3] = {sx, sy, sz};
    uint32_t marks[3][24], nm[3] = {0, 0, 0};
    for (int d = 0; d < 3; d++) {
        const uint32_t cand[] = {0, 1, 2, 7, 127, 128, 255, 256, 257, 300, 511, 512, 513, 600, 699,
                                 S[d] / 2, S[d] - 2, S[d] - 1};
        for (size_t k = 0; k < sizeof cand / sizeof cand[0]; k++) {
            uint32_t c = cand[k];
            bool dup = c >= S[d] || c < from;
            for (uint32_t j = 0; j < nm[d] && !dup; j++) dup = marks[d][j] == c;
            if (!dup) marks[d][nm[d]++] = c;
        }
    }
    size_t cap = 1 << 16, n = 0;
    uint64_t* keys = malloc(cap * sizeof *keys);
    uint8_t* pal = malloc(cap);
    uint32_t* col = malloc(cap * sizeof *col);
    REQUIRE(keys && pal && col);
#define ADD(X, Y, Z)                                                                                   \
    do {                                                                                               \
        uint32_t x_ = (X), y_ = (Y), z_ = (Z);                                                         \
        if (n < cap && x_ >= from && y_ >= from && z_ >= from && x_ < sx && y_ < sy && z_ < sz) {      \
            keys[n] = vx_svo_morton(x_, y_, z_);                                                       \
            pal[n] = (uint8_t)(1 + (x_ * 7 + y_ * 13 + z_ * 3) % 200);                                 \
            col[n++] = 0xFF000000u | (uint32_t)(((x_ * 5 + z_) % 9) * 0x1C) | (uint32_t)((y_ % 7) * 0x20) << 8; \
        }                                                                                              \
    } while (0)
    /* lines along x at marked (y, z), along y at marked (x, z), along z at marked (x, y) */
    for (uint32_t a = 0; a < nm[1]; a++)
        for (uint32_t b = 0; b < nm[2]; b++)
            for (uint32_t x = from; x < sx; x += 3) ADD(x, marks[1][a], marks[2][b]);
    for (uint32_t a = 0; a < nm[0]; a++)
        for (uint32_t b = 0; b < nm[2]; b++)
            for (uint32_t y = from; y < sy; y += 5) ADD(marks[0][a], y, marks[2][b]);
    for (uint32_t a = 0; a < nm[0]; a++)
        for (uint32_t b = 0; b < nm[1]; b++)
            for (uint32_t z = from; z < sz; z += 2) ADD(marks[0][a], marks[1][b], z);
    uint32_t h = sx * 2654435761u ^ sy * 40503u ^ sz;
    for (int k = 0; k < 2000; k++) {
        h = h * 1664525u + 1013904223u;
        uint32_t x = from + (h >> 8) % (sx - from);
        h = h * 1664525u + 1013904223u;
        uint32_t y = from + (h >> 8) % (sy - from);
        h = h * 1664525u + 1013904223u;
        ADD(x, y, from + (h >> 8) % (sz - from));
    }
#undef ADD
    REQUIRE(n < cap);
    vx_svo_voxels in = {.size = {sx, sy, sz}, .count = n, .keys = keys, .attrs = rgba ? VX_ATTR_RGBA8 : VX_ATTR_PALETTE};
    if (rgba) in.rgba = col;
    else in.palette = pal;
    REQUIRE(vx_svo_build_model(&(vx_svo_build_desc){0}, &in, out, NULL, NULL) == VX_OK);
    free(keys), free(pal), free(col);
}

/* A scene of the given models (a palette on every entry) and no instances. */
static void split_scene(vx_svo_scene* s, uint32_t models, uint32_t instances) {
    vx_svo_scene_init(s, NULL);
    s->models = calloc(models, sizeof *s->models);
    s->instances = calloc(instances, sizeof *s->instances);
    REQUIRE(s->models && s->instances);
    s->model_count = models, s->instance_count = instances;
    s->has_palette = true;
    for (uint32_t i = 1; i < 256; i++) s->palette[i] = 0xFF000000u | (i * 0x0103F1u);
    for (uint32_t i = 0; i < instances; i++) s->instances[i].layer = UINT32_MAX;
}

/* Instance i: model m, the signed permutation rows (+-1-based column) and translation. */
static void place(vx_svo_scene* s, uint32_t i, uint32_t m, const int rows[3], const double t[3]) {
    vx_svo_instance* in = &s->instances[i];
    memset(in->xform, 0, sizeof in->xform);
    for (int r = 0; r < 3; r++) {
        int c = abs(rows[r]) - 1;
        in->xform[r * 4 + c] = rows[r] < 0 ? -1.0 : 1.0;
        in->xform[r * 4 + 3] = t[r];
    }
    in->model = m;
}

/* Every instance's cells (hidden ones too) in frame f, each colour mixed
 * with its instance's name, layer and hidden flag. */
static bool tagged_cells(const vx_svo_scene* s, uint32_t f, cells* out) {
    vx_svo_scene view;
    if (!vx_svo_scene_frame(s, f, &view)) return false;
    for (uint32_t i = 0; i < view.instance_count; i++) {
        const vx_svo_instance* in = &view.instances[i];
        size_t from = out->n;
        dec_ctx c = {&view, &view.models[in->model], in->xform, out};
        if (vx_svo_decode_model(c.m, on_voxel, &c, NULL) != VX_OK) return false;
        uint32_t tag = in->layer * 0x9E3779B1u ^ (in->flags & VX_SVO_INSTANCE_HIDDEN) * 0x85EBCA6Bu;
        for (const char* p = in->name; *p; p++) tag = tag * 31u + (uint8_t)*p;
        for (size_t k = from; k < out->n; k++) out->v[k].rgba ^= tag;
    }
    qsort(out->v, out->n, sizeof *out->v, cmp_cell);
    return true;
}

/* svo -> vox -> bytes -> vox (every frame, hidden kept) -> svo: every frame's
 * cells, colours, names, layers and hidden flags as before; the visible
 * cells through the .vox reader's own placement too. want_models: the .vox
 * models the export makes (pieces shared by the instances of one model),
 * want_groups its groups. */
static void check_split(const char* name, const vx_svo_scene* s, uint32_t want_models, uint32_t want_groups) {
    vx_vox_scene v, back;
    vx_error err = {0};
    vx_result r = vx_conv_svo_to_vox(s, NULL, &v, &err);
    CHECKF(r == VX_OK, "%s: export: %s", name, err.msg);
    if (r != VX_OK) return;
    CHECKF(v.model_count == want_models && v.group_count == want_groups, "%s: %u models, %u groups (expected %u, %u)", name,
           v.model_count, v.group_count, want_models, want_groups);
    for (uint32_t m = 0; m < v.model_count; m++)
        CHECKF(v.models[m].size[0] <= 256 && v.models[m].size[1] <= 256 && v.models[m].size[2] <= 256 && v.models[m].voxel_count,
               "%s: model %u is %ux%ux%u, %u voxels", name, m, v.models[m].size[0], v.models[m].size[1], v.models[m].size[2],
               v.models[m].voxel_count);
    uint8_t* bytes = NULL;
    size_t n = 0;
    r = vx_vox_write(&v, NULL, &bytes, &n, &err);
    vx_vox_scene_free(&v);
    CHECKF(r == VX_OK, "%s: write: %s", name, err.msg);
    if (r != VX_OK) return;
    r = vx_vox_read(&(vx_vox_read_desc){.all_frames = true, .keep_hidden = true}, bytes, n, &back, &err);
    free(bytes);
    CHECKF(r == VX_OK, "%s: read back: %s", name, err.msg);
    if (r != VX_OK) return;
    vx_svo_scene s2;
    r = vx_conv_vox(NULL, &back, &s2, NULL, &err);
    CHECKF(r == VX_OK, "%s: convert back: %s", name, err.msg);
    uint32_t frames = vx_svo_scene_frames(s);
    if (r == VX_OK) {
        CHECKF(vx_svo_scene_frames(&s2) == frames, "%s: %u frames, expected %u", name, vx_svo_scene_frames(&s2), frames);
        CHECKF(s2.model_count == want_models, "%s: %u models back, expected %u", name, s2.model_count, want_models);
        for (uint32_t f = 0; f < frames; f++) {
            cells a = {0}, b = {0};
            CHECK(tagged_cells(s, f, &a) && tagged_cells(&s2, f, &b));
            char what[128];
            snprintf(what, sizeof what, "%s frame %u", name, f);
            CHECKF(a.n > 0 && same_cells(&a, &b, what), "%s: cells, colours, names, layers or hidden flags changed", what);
            free(a.v), free(b.v);
        }
        /* the reader's placement of the visible cells (frame 0) */
        cells a = {0}, b = {0};
        CHECK(cells_from_svo(s, &a));
        cells_from_vox(&back, &b);
        CHECKF(same_cells(&a, &b, name), "%s: visible cells by the .vox reader's placement differ", name);
        fprintf(stderr, "  %s: %zu visible cells agree, %u models, %u frames\n", name, a.n, want_models, frames);
        free(a.v), free(b.v);
        vx_svo_scene_free(&s2);
    }
    vx_vox_scene_free(&back);
}

/* svo_info --to-vox and the editor's export refused a model over 256 cells a
 * side ("model 0 is 300x40x700: .vox models are at most 256 cells per side").
 * It is now split into 256^3 pieces, one .vox model each under a group per
 * instance; read back, every cell is where it was. */
/* A split case's model: size, cells only at or past `from` (split_model),
 * RGBA8 or palette colours; empty: no cells at all. */
typedef struct split_spec {
    uint32_t size[3], from;
    bool rgba, empty;
} split_spec;

/* A split case's instance: model, signed permutation rows, translation, name (NULL: none). */
typedef struct split_inst {
    uint32_t model;
    const int* rows;
    double t[3];
    const char* name;
} split_inst;

/* The scene of a split case: its models and instances (split_scene,
 * split_model, place), for check_split after any further changes. */
static void split_build(vx_svo_scene* s, const split_spec* models, uint32_t nm, const split_inst* inst, uint32_t ni) {
    split_scene(s, nm, ni);
    for (uint32_t m = 0; m < nm; m++) {
        const split_spec* sp = &models[m];
        if (sp->empty) {
            vx_svo_voxels none = {.size = {sp->size[0], sp->size[1], sp->size[2]}};
            REQUIRE(vx_svo_build_model(&(vx_svo_build_desc){0}, &none, &s->models[m], NULL, NULL) == VX_OK);
        } else {
            split_model(&s->models[m], sp->size[0], sp->size[1], sp->size[2], sp->from, sp->rgba);
        }
    }
    for (uint32_t i = 0; i < ni; i++) {
        place(s, i, inst[i].model, inst[i].rows, inst[i].t);
        if (inst[i].name) snprintf(s->instances[i].name, sizeof s->instances[i].name, "%s", inst[i].name);
    }
}

/* svo_info --to-vox and the editor's export refused a model over 256 cells a
 * side ("model 0 is 300x40x700: .vox models are at most 256 cells per side").
 * It is now split into 256^3 pieces, one .vox model each under a group per
 * instance; read back, every cell is where it was. */
static void test_split_export(void) {
    static const int ID[3] = {1, 2, 3}, TURN[3] = {-2, 3, 1} /* a rotation */, MIRROR[3] = {3, -1, -2} /* turned and mirrored */;
    vx_svo_scene s;
    /* 300x40x700: 2 x 1 x 3 tiles, all holding cells */
    split_build(&s, (split_spec[]){{.size = {300, 40, 700}}}, 1, (split_inst[]){{0, ID, {-150, 7, -350}, "castle"}}, 1);
    check_split("300x40x700", &s, 6, 1);
    vx_svo_scene_free(&s);
    /* 256 a side is one model as before (no group); 257 is two pieces */
    split_build(&s, (split_spec[]){{.size = {256, 256, 256}}, {.size = {257, 5, 3}}}, 2,
                (split_inst[]){{0, ID, {0, 0, 0}, NULL}, {1, ID, {10, 300, -4}, NULL}}, 2);
    check_split("256 and 257", &s, 3, 1);
    vx_svo_scene_free(&s);
    {
        /* odd sizes (the pivot rounds down), turned and mirrored instances of
         * one big model, a second instance sharing its pieces, RGBA8 colours,
         * a layer, a hidden instance, a small model beside them */
        split_build(&s, (split_spec[]){{.size = {513, 301, 259}, .from = 0, .rgba = true}, {.size = {9, 7, 5}}}, 2,
                    (split_inst[]){{0, TURN, {3, -1000, 17}, NULL},
                                   {0, MIRROR, {-9, 4, 2001}, "mirrored"},
                                   {1, MIRROR, {1, 2, 3}, NULL},
                                   {0, ID, {700, 0, 0}, "plain"}},
                    4);
        s.layers = calloc(2, sizeof *s.layers);
        REQUIRE(s.layers);
        s.layer_count = 2;
        snprintf(s.layers[1].name, sizeof s.layers[1].name, "walls");
        s.instances[0].layer = 1;
        s.instances[1].flags = VX_SVO_INSTANCE_HIDDEN;
        /* 3 x 2 x 2 tiles: 12 pieces, shared by three instances, and the small model */
        check_split("513x301x259 turned, mirrored, shared", &s, 13, 3);
        vx_svo_scene_free(&s);
    }
    /* cells only in the far corner: the empty pieces are left out */
    split_build(&s, (split_spec[]){{.size = {600, 601, 599}, .from = 520}}, 1, (split_inst[]){{0, MIRROR, {-5, 5, 0.0}, NULL}}, 1);
    check_split("far corner", &s, 1, 1);
    vx_svo_scene_free(&s);
    {
        /* an animated instance of a big model (moving, turning), one of a
         * small model, one hidden all along */
        split_build(&s, (split_spec[]){{.size = {270, 531, 33}}, {.size = {4, 4, 4}}}, 2,
                    (split_inst[]){{0, ID, {0, 0, 0}, "mover"}, {1, ID, {-20, 0, 0}, NULL}, {0, TURN, {0, 0, 900}, NULL}}, 3);
        s.instances[2].flags = VX_SVO_INSTANCE_HIDDEN;
        REQUIRE(vx_svo_scene_alloc_frames(&s, 4, NULL) == VX_OK);
        for (uint32_t f = 1; f < 4; f++) {
            vx_svo_instance* fi = (vx_svo_instance*)vx_svo_scene_frame_instances(&s, f);
            vx_svo_instance keep = fi[0];
            place(&s, 0, 0, f == 2 ? MIRROR : TURN, (double[3]){f * 11.0, -3.0 * f, f == 3 ? 0 : 5});
            fi[0] = s.instances[0];
            memcpy(fi[0].name, keep.name, sizeof fi[0].name);
            s.instances[0] = keep;
            fi[1].xform[3] += f;
        }
        /* 2 x 3 x 1 tiles */
        check_split("animated 270x531x33", &s, 7, 2);
        /* a frame that shows another model in place of a split one: refused, named */
        vx_svo_instance* f2 = (vx_svo_instance*)vx_svo_scene_frame_instances(&s, 2);
        f2[0].model = 1;
        vx_vox_scene v;
        vx_error err = {0};
        CHECK(vx_conv_svo_to_vox(&s, NULL, &v, &err) == VX_ERR_UNSUPPORTED);
        CHECKF(strstr(err.msg, "frame 2 instance 0") && strstr(err.msg, "270x531x33"), "message: %s", err.msg);
        vx_svo_scene_free(&s);
    }
    /* an empty model over 256: no pieces, its instance an empty group */
    split_build(&s, (split_spec[]){{.size = {400, 2, 2}, .empty = true}, {.size = {3, 3, 3}}}, 2,
                (split_inst[]){{0, ID, {0, 0, 0}, NULL}, {1, ID, {0, 0, 0}, NULL}}, 2);
    check_split("empty 400x2x2", &s, 1, 1);
    vx_svo_scene_free(&s);
    {
        /* the writer checks a scene's groups: index in range, a rotation */
        uint8_t xyzi[4] = {0, 0, 0, 1};
        vx_vox_model m = {.size = {1, 1, 1}, .voxel_count = 1, .xyzi = xyzi};
        vx_vox_instance in = {.rot = {1, 0, 0, 0, 1, 0, 0, 0, 1}, .layer = -1, .group = 2};
        vx_vox_group g = {.rot = {1, 0, 0, 0, 1, 0, 0, 0, 1}, .layer = -1};
        vx_vox_scene v = {.model_count = 1, .models = &m, .instance_count = 1, .instances = &in, .group_count = 1, .groups = &g};
        vx_error err = {0};
        CHECK(vx_vox_validate(&v, &err) == VX_ERR_INVALID_ARG && strstr(err.msg, "group 2 out of range"));
        in.group = 1;
        CHECK(vx_vox_validate(&v, &err) == VX_OK);
        g.rot[4] = 0;
        CHECK(vx_vox_validate(&v, &err) == VX_ERR_INVALID_ARG && strstr(err.msg, "group 0: rotation"));
    }
}

/* ---- more than 255 colours: refused, or quantized on request ---------------------------------- */

/* A scene of an RGBA8 model of side n, cell (x, y, z) coloured (x, y, z) *
 * step (n^3 colours), a palette model on entries 1..3, and a geometry-only model. */
static void colour_scene(vx_svo_scene* s, uint32_t n, uint32_t step, bool palette_model) {
    split_scene(s, 3, 3);
    uint64_t* keys = malloc((size_t)n * n * n * sizeof *keys);
    uint32_t* rgba = malloc((size_t)n * n * n * sizeof *rgba);
    REQUIRE(keys && rgba);
    size_t k = 0;
    for (uint32_t z = 0; z < n; z++)
        for (uint32_t y = 0; y < n; y++)
            for (uint32_t x = 0; x < n; x++, k++)
                keys[k] = vx_svo_morton(x, y, z), rgba[k] = 0xFF000000u | (z * step) << 16 | (y * step) << 8 | x * step;
    vx_svo_voxels v = {.size = {n, n, n}, .count = k, .keys = keys, .attrs = VX_ATTR_RGBA8, .rgba = rgba};
    REQUIRE(vx_svo_build_model(&(vx_svo_build_desc){0}, &v, &s->models[0], NULL, NULL) == VX_OK);
    uint8_t pal[3] = {1, 2, 3};
    vx_svo_voxels pv = {.size = {3, 1, 1}, .count = palette_model ? 3 : 0, .keys = keys, .attrs = palette_model ? VX_ATTR_PALETTE : 0,
                        .palette = palette_model ? pal : NULL};
    REQUIRE(vx_svo_build_model(&(vx_svo_build_desc){0}, &pv, &s->models[1], NULL, NULL) == VX_OK);
    vx_svo_voxels gv = {.size = {2, 1, 1}, .count = 2, .keys = keys};
    REQUIRE(vx_svo_build_model(&(vx_svo_build_desc){0}, &gv, &s->models[2], NULL, NULL) == VX_OK);
    free(keys), free(rgba);
    for (uint32_t i = 0; i < 256; i++) s->palette[i] = vx_vox_default_palette[i];
    s->has_palette = true;
    s->palette[1] = 0xFFFFFFFFu;
    place(s, 0, 0, (int[3]){1, 2, 3}, (double[3]){0, 0, 0});
    place(s, 1, 1, (int[3]){1, 2, 3}, (double[3]){0, 0, -5});
    place(s, 2, 2, (int[3]){1, 2, 3}, (double[3]){0, 0, -9});
}

/* Export (quantize as asked), write, read back: the cells' colours, and the bytes written. */
static vx_result export_colours(const vx_svo_scene* s, bool quantize, vx_conv_vox_export_stats* st, cells* out, uint8_t** bytes,
                                size_t* n, uint32_t pal[256], vx_error* err) {
    vx_vox_scene v, back;
    vx_result r = vx_conv_svo_to_vox_ex(&(vx_conv_vox_export_desc){.quantize = quantize}, s, &v, st, err);
    if (r != VX_OK) return r;
    r = vx_vox_write(&v, NULL, bytes, n, err);
    vx_vox_scene_free(&v);
    if (r != VX_OK) return r;
    r = vx_vox_read(NULL, *bytes, *n, &back, err);
    if (r != VX_OK) return r;
    cells_from_vox(&back, out);
    memcpy(pal, back.palette, 256 * sizeof *pal);
    vx_vox_scene_free(&back);
    return VX_OK;
}

static void test_quantize_export(void) {
    /* 16^3 colours a step of 17 apart, 3 palette entries, white: refused by default, naming the count */
    vx_svo_scene s;
    colour_scene(&s, 16, 17, true);
    cells want = {0}, got = {0}, again = {0};
    CHECK(cells_from_svo(&s, &want));
    vx_vox_scene v;
    vx_error err = {0};
    CHECK(vx_conv_svo_to_vox(&s, NULL, &v, &err) == VX_ERR_UNSUPPORTED);
    /* white and entries 2, 3 (ffffcc, ffff99) lie on the lattice: 4096 in all */
    CHECKF(strstr(err.msg, "4096 distinct colours") && strstr(err.msg, "quantize"), "message: %s", err.msg);
    /* quantized: each cell's colour the nearest of the palette made, the
     * palette model's entries and white kept, the error as reported */
    vx_conv_vox_export_stats st, st2;
    uint8_t *b1 = NULL, *b2 = NULL;
    size_t n1 = 0, n2 = 0;
    uint32_t pal[256], pal2[256];
    REQUIRE(export_colours(&s, true, &st, &got, &b1, &n1, pal, &err) == VX_OK);
    CHECKF(st.quantized && st.colors == 4096, "stats: quantized %d, %u colours", st.quantized, st.colors);
    REQUIRE(got.n == want.n);
    double max = 0, sum = 0;
    size_t rgba_cells = 0, not_nearest = 0, moved = 0;
    for (size_t i = 0; i < want.n; i++) {
        const cell *a = &want.v[i], *b = &got.v[i];
        if (a->x != b->x || a->y != b->y || a->z != b->z) moved++;
        if (a->z < 0) { /* the palette and geometry models: exact */
            CHECKF(a->rgba == b->rgba, "(%d %d %d): %08x became %08x", a->x, a->y, a->z, a->rgba, b->rgba);
            continue;
        }
        double d = vx_test_rgba_dist(a->rgba, b->rgba), best = INFINITY;
        for (int e = 1; e < 256; e++) best = fmin(best, vx_test_rgba_dist(a->rgba, pal[e]));
        not_nearest += d != best;
        max = fmax(max, d), sum += d, rgba_cells++;
    }
    CHECKF(moved == 0 && not_nearest == 0, "%zu cells moved, %zu not at their nearest entry", moved, not_nearest);
    CHECKF(fabs(max - st.max_error) < 1e-9 && fabs(sum / (double)rgba_cells - st.mean_error) < 1e-9,
           "error max %.3f mean %.3f, reported %.3f %.3f", max, sum / (double)rgba_cells, st.max_error, st.mean_error);
    /* 252 boxes over a 16^3 lattice: none of more than 4 x 4 x 2 points (halves of the 8 x 4 x 4
     * boxes after 7 cuts a colour), so a point lies at most 1.5 x 1.5 x 0.5 steps of 17 from its
     * box's mean, plus the mean's rounding (half a unit a channel): 38.2; the mean below 1.5 steps */
    CHECKF(st.max_error <= 17 * sqrt(1.5 * 1.5 + 1.5 * 1.5 + 0.5 * 0.5) + 0.5 * sqrt(3) && st.mean_error < 1.5 * 17,
           "error max %.2f mean %.2f", st.max_error, st.mean_error);
    fprintf(stderr, "  4096 colours: error max %.2f, mean %.2f\n", st.max_error, st.mean_error);
    /* deterministic: the same bytes again */
    REQUIRE(export_colours(&s, true, &st2, &again, &b2, &n2, pal2, &err) == VX_OK);
    CHECK(n1 == n2 && !memcmp(b1, b2, n1));
    free(b1), free(b2), free(want.v), free(got.v), free(again.v);
    vx_svo_scene_free(&s);

    /* 6^3 = 216 colours + entries 1 (white, the geometry's too), 2, 3: 219, exact, quantize or not;
     * 7^3: 346, quantized */
    for (uint32_t side = 6; side <= 7; side++) {
        colour_scene(&s, side, 40, true);
        cells w = {0}, g = {0};
        CHECK(cells_from_svo(&s, &w));
        b1 = NULL;
        vx_result r = export_colours(&s, true, &st, &g, &b1, &n1, pal, &err);
        CHECKF(r == VX_OK, "side %u: %s", side, err.msg);
        if (side == 6) CHECKF(!st.quantized && same_cells(&w, &g, "216 colours"), "216 colours not exact");
        else CHECKF(st.quantized && st.colors == 346 && st.max_error > 0, "346 colours: quantized %d, %u", st.quantized, st.colors);
        free(b1), free(w.v), free(g.v);
        vx_svo_scene_free(&s);
    }
    /* without the palette model (an empty one): the geometry-only cells stay white (entry 1);
     * RGBA8 colours took entry 1 first, so those cells took colour (0, 0, 0) */
    colour_scene(&s, 6, 40, false);
    cells w = {0}, g = {0};
    CHECK(cells_from_svo(&s, &w));
    b1 = NULL;
    CHECK(export_colours(&s, false, &st, &g, &b1, &n1, pal, &err) == VX_OK);
    CHECK(same_cells(&w, &g, "geometry beside RGBA8"));
    free(b1), free(w.v), free(g.v);
    vx_svo_scene_free(&s);
}

int main(void) {
    RUN(test_corpus);
    RUN(test_keep_hidden);
    RUN(test_unused_models);
    RUN(test_unused_animation_frames);
    RUN(test_pack_all_frames);
    RUN(test_keyframed_all_frames);
    RUN(test_mixed_colours_export);
    RUN(test_split_export);
    RUN(test_quantize_export);
    return vx_test_finish();
}
