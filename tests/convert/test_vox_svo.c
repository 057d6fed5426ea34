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

static void cells_from_vox(const vx_vox_scene* s, cells* out) {
    for (uint32_t i = 0; i < s->instance_count; i++) {
        const vx_vox_instance* in = &s->instances[i];
        if (in->hidden) continue;
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
        if (in->flags & VX_SVO_INSTANCE_HIDDEN) continue;
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

/* vox scene -> svo scene -> bytes -> svo scene */
static bool through_file(const vx_vox_scene* vs, vx_svo_scene* out, const vx_svo_build_desc* bd) {
    vx_svo_scene s;
    vx_error err = {0};
    vx_conv_stats st;
    if (vx_conv_vox(&(vx_conv_vox_desc){.build = *bd}, vs, &s, &st, &err) != VX_OK) {
        fprintf(stderr, "  convert: %s\n", err.msg);
        return false;
    }
    uint8_t* bytes = NULL;
    size_t n = 0;
    vx_result r = vx_svo_write(&s, NULL, &bytes, &n, &err);
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

static void check_scene(const char* name, const vx_vox_scene* vs) {
    cells a = {0}, b = {0}, c = {0}, d = {0};
    cells_from_vox(vs, &a);
    static const vx_svo_build_desc modes[] = {{0}, {.no_collapse = true}, {.no_dag = true}, {.no_collapse = true, .no_dag = true}};
    for (unsigned mode = 0; mode < 4; mode++) {
        vx_svo_scene s;
        REQUIRE(through_file(vs, &s, &modes[mode]));
        CHECK(s.model_count == vs->model_count); /* instancing kept: no copies */
        b.n = 0;
        CHECK(cells_from_svo(&s, &b));
        CHECKF(same_cells(&a, &b, name), "%s: reader placement != decoded svo (mode %u)", name, mode);

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

int main(void) {
    RUN(test_corpus);
    RUN(test_keep_hidden);
    return vx_test_finish();
}
