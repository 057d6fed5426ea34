/* tests/view/test_view.c - svo_view under Xvfb with lavapipe: a scripted
 * edit checked cell by cell against edits applied independently here, the
 * saved file reopening identically, --screenshot against svo_render, a pick
 * against the tracer's hit buffer, bad files, and mode gi with probes baked
 * here (screenshot against svo_render --mode gi, picks, bad .probes,
 * --validate's error count).
 *
 * Usage: test_view --editor: the editor's operations in-process (no window,
 *        no GPU: this part is leak-checked);
 *        test_view SVO_VIEW SVO_RENDER WORKDIR: the window tests (re-executes
 *        itself under xvfb-run -a when DISPLAY is not set). These run without
 *        leak detection: lavapipe's and the window system's modules are
 *        unloaded before exit, leaving leak stacks no suppression can name
 *        (as tests/probes does for the tools). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "convert/convert.h"
#include "convert/export.h"
#ifdef VX_VIEW_VDB
#include "convert/volume.h"
#endif
#include "formats/image.h"
#include "formats/vox.h"
#include "probes/probes.h"
#include "render/render.h"
#include "tests/test.h"
#include "tests/test_vox.h"
#include "tools/svo_view/batch.h"
#include "tools/svo_view/editor.h"
#include "tools/svo_view/settings.h"
#include "tools/svo_view/voxels.h"

static const char* g_view;
static const char* g_render;
static const char* g_dir;
static bool g_display;

/* ---- helpers --------------------------------------------------------------------------- */

static int run_cmd(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
static int run_cmd(const char* fmt, ...) {
    char cmd[8192];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(cmd, sizeof cmd, fmt, ap);
    va_end(ap);
    int st = system(cmd);
    if (st == -1 || !WIFEXITED(st)) return -1; /* a crash */
    return WEXITSTATUS(st);
}

static char* slurp(const char* path) { return vx_test_slurp(path, NULL); }

static bool load_vox(const char* path, vx_svo_scene* out) {
    vx_vox_scene vs;
    vx_error err = {0};
    if (vx_vox_read_file(NULL, path, &vs, &err)) return false;
    vx_result r = vx_conv_vox(NULL, &vs, out, NULL, &err);
    vx_vox_scene_free(&vs);
    return r == VX_OK;
}

typedef struct cell {
    int64_t p[3];
    uint32_t rgba;
} cell;

typedef struct cells {
    cell* v;
    size_t n, cap;
    /* decode context */
    const vx_svo_scene* s;
    const vx_svo_model* m;
    double xf[12];
} cells;

static bool push(cells* c, const int64_t p[3], uint32_t rgba) {
    if (c->n == c->cap) {
        size_t cap = c->cap ? 2 * c->cap : 1024;
        cell* v = realloc(c->v, cap * sizeof *v);
        if (!v) return false;
        c->v = v, c->cap = cap;
    }
    c->v[c->n].p[0] = p[0], c->v[c->n].p[1] = p[1], c->v[c->n].p[2] = p[2];
    c->v[c->n].rgba = rgba;
    c->n++;
    return true;
}

static bool cell_cb(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    cells* c = user;
    double v[3] = {x + 0.5, y + 0.5, z + 0.5};
    int64_t g[3];
    for (int r = 0; r < 3; r++)
        g[r] = (int64_t)floor(c->xf[4 * r] * v[0] + c->xf[4 * r + 1] * v[1] + c->xf[4 * r + 2] * v[2] + c->xf[4 * r + 3]);
    return push(c, g, vx_svo_attr_color(c->s, c->m, attr));
}

/* Grid cells of one instance with its own transform. */
static void instance_cells(const vx_svo_scene* s, const vx_svo_instance* in, cells* out) {
    out->s = s;
    out->m = &s->models[in->model];
    memcpy(out->xf, in->xform, sizeof out->xf);
    vx_svo_decode_model(out->m, cell_cb, out, NULL);
}

static bool visible(const vx_svo_scene* s, uint32_t i) {
    const vx_svo_instance* in = &s->instances[i];
    if (in->flags & VX_SVO_INSTANCE_HIDDEN) return false;
    return !(in->layer < s->layer_count && (s->layers[in->layer].flags & VX_SVO_LAYER_HIDDEN));
}

static void scene_cells(const vx_svo_scene* s, cells* out) {
    for (uint32_t i = 0; i < s->instance_count; i++)
        if (visible(s, i)) instance_cells(s, &s->instances[i], out);
}

static int cmp_cell(const void* x, const void* y) {
    const cell *a = x, *b = y;
    for (int k = 0; k < 3; k++)
        if (a->p[k] != b->p[k]) return a->p[k] < b->p[k] ? -1 : 1;
    return (a->rgba > b->rgba) - (a->rgba < b->rgba);
}

static size_t cells_diff(cells* a, cells* b) {
    qsort(a->v, a->n, sizeof *a->v, cmp_cell);
    qsort(b->v, b->n, sizeof *b->v, cmp_cell);
    if (a->n != b->n) return a->n > b->n ? a->n - b->n : b->n - a->n;
    size_t d = 0;
    for (size_t i = 0; i < a->n; i++) d += cmp_cell(&a->v[i], &b->v[i]) != 0;
    return d;
}

/* The editor's pivot rule (editor.h), from the model box corners. */
static void pivot_of(const vx_svo_scene* s, const vx_svo_instance* in, int axis, bool rotate, double p[3]) {
    const vx_svo_model* m = &s->models[in->model];
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int k = 0; k < 8; k++) {
        double q[3] = {(k & 1) ? m->size[0] : 0, (k & 2) ? m->size[1] : 0, (k & 4) ? m->size[2] : 0};
        for (int r = 0; r < 3; r++) {
            double v = in->xform[4 * r] * q[0] + in->xform[4 * r + 1] * q[1] + in->xform[4 * r + 2] * q[2] +
                       in->xform[4 * r + 3];
            lo[r] = fmin(lo[r], v), hi[r] = fmax(hi[r], v);
        }
    }
    for (int r = 0; r < 3; r++) p[r] = 0.5 * (lo[r] + hi[r]);
    int a = axis == 0 ? 1 : 0, b = axis == 2 ? 1 : 2;
    if (rotate && p[a] + p[b] != floor(p[a] + p[b])) p[a] -= 0.5;
}

/* Cell w under a quarter turn about z through p: centres (x, y) -> (-y, x). */
static void turn_z(int64_t w[3], const double p[3]) {
    double x = w[0] + 0.5 - p[0], y = w[1] + 0.5 - p[1];
    w[0] = (int64_t)floor(-y + p[0]);
    w[1] = (int64_t)floor(x + p[1]);
}

/* ---- in-process editor checks (leak-checked) ------------------------------------------- */

/* --batch auto's policy (tools/svo_view/batch.h): the batch keeps the added
 * latency (K - 1 frames) under the bound, vsync and unmeasured frames get
 * 1, and the answer changes at most once every SV_BATCH_HOLD frames, from
 * the median of the timed frames (one slow frame does not move it). */
static void test_batch_policy(void) {
    const double L = SV_BATCH_LATENCY_MS;
    CHECK(sv_batch_for(0.08, 0, false, 4) == 4);     /* an H200's monu1 frame */
    CHECK(sv_batch_for(L / 3.0, 0, false, 4) == 4);  /* 3 frames of delay fit exactly */
    CHECK(sv_batch_for(L / 2.5, 0, false, 4) == 3);
    CHECK(sv_batch_for(L / 1.5, 0, false, 4) == 2);
    CHECK(sv_batch_for(L * 1.01, 0, false, 4) == 1); /* a frame longer than the bound: alone */
    CHECK(sv_batch_for(40.0, 0, false, 4) == 1);     /* lavapipe */
    CHECK(sv_batch_for(40.0, 1000.0, false, 4) == 4);
    CHECK(sv_batch_for(0.08, 0, false, 2) == 2);
    CHECK(sv_batch_for(0.08, 0, true, 4) == 1);      /* vsync */
    CHECK(sv_batch_for(0.0, 0, false, 4) == 1 && sv_batch_for(-1.0, 0, false, 4) == 1 && sv_batch_for(NAN, 0, false, 4) == 1);
    /* the delay a chosen batch adds stays within the bound for every frame time */
    for (double ms = 0.01; ms < 5.0; ms *= 1.1) {
        uint32_t k = sv_batch_for(ms, 0, false, 4);
        CHECKF(k >= 1 && k <= 4 && (k - 1) * ms <= L + 1e-12 && (k == 4 || k * ms > L),
               "frame %.4f ms: batch %u", ms, k);
    }
    sv_batch b = sv_batch_make(4, 0);
    CHECK(b.cur == 1 && b.max == 4 && b.latency_ms == L);
    uint32_t changed_at = 0;
    for (uint32_t f = 1; f <= 3 * SV_BATCH_HOLD; f++) {
        sv_batch_frame(&b, f % 8 ? 0 : (f == 48 ? 50.0 : 0.08)); /* one timed frame in 8, one of them slow */
        uint32_t want = sv_batch_want(&b, false);
        if (want != b.cur && !changed_at) changed_at = f;
        sv_batch_set(&b, want);
    }
    CHECKF(changed_at == SV_BATCH_HOLD && b.cur == 4, "changed at frame %u to %u", changed_at, b.cur);
    CHECK(sv_batch_want(&b, true) == 1); /* vsync on: at once */
    sv_batch_set(&b, 1);
    uint64_t at = b.frames;
    for (uint32_t f = 0; f < SV_BATCH_HOLD - 1; f++) {
        sv_batch_frame(&b, 2.0 * L);
        CHECK(sv_batch_want(&b, false) == 1);
    }
    /* frames now slower than the bound: the median says 1 after the hold too */
    sv_batch_frame(&b, 2.0 * L);
    CHECK(b.frames - at == SV_BATCH_HOLD && sv_batch_want(&b, false) == 1);
    /* timed frames: the first, then one in SV_BATCH_TIMED_EVERY, one per SV_BATCH_TIMED_MS of short frames */
    sv_batch t = sv_batch_make(4, 0);
    uint32_t timed = 0, first = 0;
    for (uint32_t f = 0; f < 64; f++) {
        sv_batch_frame(&t, 0);
        if (sv_batch_timed(&t)) timed++, first += f == 0;
    }
    CHECKF(first == 1 && timed == 64 / SV_BATCH_TIMED_EVERY, "%u frames of 64 timed", timed);
    sv_batch_frame(&t, 0.08); /* a measured 0.08 ms frame: one timed per 4 ms = 50 frames */
    timed = 0;
    for (uint32_t f = 0; f < 1000; f++) {
        if (f) sv_batch_frame(&t, 0);
        timed += sv_batch_timed(&t);
    }
    CHECKF(timed >= 1000 / (uint32_t)(SV_BATCH_TIMED_MS / 0.08) && timed <= 1000 / (uint32_t)(SV_BATCH_TIMED_MS / 0.08) + 1,
           "%u frames of 1000 timed at 0.08 ms", timed);
    sv_batch fixed = sv_batch_make(1, 0);
    for (int f = 0; f < 200; f++) sv_batch_frame(&fixed, 0.01);
    CHECK(sv_batch_want(&fixed, false) == 1); /* max 1: never batched */
}


static void test_editor_ops(void) {
    const char* in = vx_test_corpus("vox/ogt_test_groups.vox");
    if (!in) SKIP("corpus file vox/ogt_test_groups.vox not found");
    vx_svo_scene s;
    REQUIRE(load_vox(in, &s));
    REQUIRE(s.instance_count > 2);
    vx_svo_instance orig = s.instances[1];
    ved e;
    ved_init(&e, &s);
    /* four quarter turns (where cell-exact in place) and two mirrors are the identity */
    for (int axis = 0; axis < 3; axis++) {
        int a = axis == 0 ? 1 : 0, b = axis == 2 ? 1 : 2;
        for (int t = 0; t < 4; t++) {
            REQUIRE(ved_begin(&e, NULL) == VX_OK);
            ved_rotate(&s, 0, 1, axis, 1);
        }
        double lo[3], hi[3];
        ved_instance_box(&s, 0, 1, lo, hi);
        bool same_parity = (((int64_t)(hi[a] - lo[a])) & 1) == (((int64_t)(hi[b] - lo[b])) & 1);
        if (same_parity) CHECK(!memcmp(s.instances[1].xform, orig.xform, sizeof orig.xform));
        memcpy(s.instances[1].xform, orig.xform, sizeof orig.xform);
        ved_mirror(&s, 0, 1, axis);
        ved_mirror(&s, 0, 1, axis);
        CHECK(!memcmp(s.instances[1].xform, orig.xform, sizeof orig.xform));
    }
    /* a rotation maps the instance's cells as R (w - c) + c */
    cells before = {0}, after = {0}, want = {0};
    instance_cells(&s, &s.instances[1], &before);
    double c[3];
    pivot_of(&s, &s.instances[1], 2, true, c);
    ved_rotate(&s, 0, 1, 2, 1);
    instance_cells(&s, &s.instances[1], &after);
    for (size_t i = 0; i < before.n; i++) {
        int64_t q[3] = {before.v[i].p[0], before.v[i].p[1], before.v[i].p[2]};
        turn_z(q, c);
        push(&want, q, before.v[i].rgba);
    }
    CHECK(before.n > 0);
    CHECK(cells_diff(&after, &want) == 0);
    /* undo all the way back, redo one, duplicate, delete */
    uint32_t n0 = s.instance_count;
    while (ved_undo(&e, NULL)) {}
    CHECK(!memcmp(s.instances[1].xform, orig.xform, sizeof orig.xform));
    CHECK(ved_redo(&e, NULL));
    uint32_t dup;
    REQUIRE(ved_begin(&e, NULL) == VX_OK);
    REQUIRE(ved_duplicate(&s, 1, &dup, NULL) == VX_OK);
    CHECK(dup == n0 && s.instance_count == n0 + 1 && s.instances[dup].model == s.instances[1].model);
    REQUIRE(ved_begin(&e, NULL) == VX_OK);
    ved_delete(&s, 0);
    CHECK(s.instance_count == n0);
    CHECK(ved_undo(&e, NULL) && s.instance_count == n0 + 1);
    CHECK(ved_undo(&e, NULL) && s.instance_count == n0);
    /* adding a scene with another palette keeps its colours */
    vx_svo_scene other;
    REQUIRE(load_vox(in, &other));
    other.palette[other.models[0].palette ? other.models[0].palette[0] : 1] ^= 0x00FFFFFFu;
    cells oc = {0};
    scene_cells(&other, &oc);
    uint32_t first, oi = other.instance_count, mc = s.model_count;
    REQUIRE(ved_begin(&e, NULL) == VX_OK);
    REQUIRE(ved_add_scene(&s, &other, (int32_t[3]){100, 0, 0}, &first, NULL) == VX_OK);
    cells added = {0};
    for (uint32_t i = first; i < first + oi; i++) {
        vx_svo_instance t = s.instances[i];
        t.xform[3] -= 100;
        CHECK(t.model >= mc);
        if (visible(&s, i)) instance_cells(&s, &t, &added);
    }
    CHECK(cells_diff(&added, &oc) == 0);
    vx_svo_scene_free(&other);
    free(oc.v), free(added.v);
    free(before.v), free(after.v), free(want.v);
    ved_free(&e);
    vx_svo_scene_free(&s);
}

/* ---- voxel edits and animations (in process, leak-checked) ----------------------------- */

/* The generated scene: model 0 is the cells of a 6x5x4 box with
 * (x + 2y + z) % 3 != 0, palette colour 1 + x % 4; instance 0 places it at
 * (5, 6, 7), instance 1 turned a quarter about z at (30, 0, 0); with frames,
 * frame f moves both by (2f, 0, f). */
#define GEN_X 6
#define GEN_Y 5
#define GEN_Z 4
static bool gen_cell(int64_t x, int64_t y, int64_t z) {
    return x >= 0 && y >= 0 && z >= 0 && x < GEN_X && y < GEN_Y && z < GEN_Z && (x + 2 * y + z) % 3 != 0;
}

static void make_scene(vx_svo_scene* s, uint32_t frames) {
    vx_svo_scene_init(s, NULL);
    uint64_t keys[GEN_X * GEN_Y * GEN_Z];
    uint8_t pal[GEN_X * GEN_Y * GEN_Z];
    size_t n = 0;
    for (uint32_t z = 0; z < GEN_Z; z++)
        for (uint32_t y = 0; y < GEN_Y; y++)
            for (uint32_t x = 0; x < GEN_X; x++)
                if (gen_cell(x, y, z)) keys[n] = vx_svo_morton(x, y, z), pal[n++] = (uint8_t)(1 + x % 4);
    s->models = vx_calloc(NULL, 1, sizeof *s->models);
    s->instances = vx_calloc(NULL, 2, sizeof *s->instances);
    REQUIRE(s->models && s->instances);
    s->model_count = 1, s->instance_count = 2;
    vx_svo_voxels v = {.size = {GEN_X, GEN_Y, GEN_Z}, .count = n, .keys = keys, .attrs = VX_ATTR_PALETTE, .palette = pal};
    REQUIRE(vx_svo_build_model(&(vx_svo_build_desc){0}, &v, &s->models[0], NULL, NULL) == VX_OK);
    static const double x0[12] = {1, 0, 0, 5, 0, 1, 0, 6, 0, 0, 1, 7}, x1[12] = {0, -1, 0, 30, 1, 0, 0, 0, 0, 0, 1, 0};
    memcpy(s->instances[0].xform, x0, sizeof x0);
    memcpy(s->instances[1].xform, x1, sizeof x1);
    for (uint32_t i = 0; i < 2; i++) s->instances[i].layer = UINT32_MAX, snprintf(s->instances[i].name, 64, "inst%u", i);
    s->has_palette = true;
    for (uint32_t i = 1; i < 256; i++) s->palette[i] = 0xFF000000u | (i * 0x00030507u & 0x00FFFFFFu);
    if (frames >= 2) {
        REQUIRE(vx_svo_scene_alloc_frames(s, frames, NULL) == VX_OK);
        for (uint32_t f = 1; f < frames; f++)
            for (uint32_t i = 0; i < 2; i++) {
                vx_svo_instance* in = &s->frame_instances[(size_t)(f - 1) * 2 + i];
                in->xform[3] += 2 * f, in->xform[11] += f;
            }
    }
    vx_svo_scene_update_bounds(s);
}

/* The undo history's bounds: a step limit drops the oldest steps (what is
 * left undoes to the state after the dropped ones), and a byte bound drops
 * them by the bytes the snapshots hold, keeping the newest. */
static void test_editor_undo_bounds(void) {
    vx_svo_scene s;
    make_scene(&s, 3);
    ved e;
    ved_init(&e, &s);
    e.undo_limit = 8;
    vx_svo_instance after12 = s.instances[0];
    for (int k = 0; k < 20; k++) {
        if (k == 12) after12 = s.instances[0];
        REQUIRE(ved_begin(&e, NULL) == VX_OK);
        ved_move(&s, 0, (int32_t[3]){1, 0, 0});
    }
    CHECKF(e.undo_count == 8 && e.dropped == 12, "%u steps kept, %u dropped (limit 8, 20 edits)", e.undo_count, e.dropped);
    uint32_t undone = 0;
    while (ved_undo(&e, NULL)) undone++;
    CHECK(undone == 8 && !memcmp(&s.instances[0], &after12, sizeof after12));
    while (ved_redo(&e, NULL)) {}
    CHECK(s.instances[0].xform[3] == after12.xform[3] + 8);
    /* a byte bound of three steps' snapshots keeps three */
    ved_free(&e);
    ved_init(&e, &s);
    REQUIRE(ved_begin(&e, NULL) == VX_OK);
    uint64_t one = ved_snapshot_bytes(&e.undo[0]);
    CHECK(one >= 3 * sizeof(vx_svo_instance) * 2); /* two instances in three frames */
    e.undo_bytes = 3 * one + one / 2;
    for (int k = 0; k < 10; k++) REQUIRE(ved_begin(&e, NULL) == VX_OK);
    CHECKF(e.undo_count == 3, "%u steps kept under a bound of 3.5 steps' bytes", e.undo_count);
    /* a limit past the old fixed 256 */
    ved_free(&e);
    ved_init(&e, &s);
    e.undo_limit = 1500;
    for (int k = 0; k < 1200; k++) REQUIRE(ved_begin(&e, NULL) == VX_OK);
    CHECK(e.undo_count == 1200 && e.dropped == 0);
    ved_free(&e);
    vx_svo_scene_free(&s);
}

/* The expected model after edits, brute force: a colour (palette index, 0 =
 * empty) per cell of a box with a margin, in the generated model's cells. */
#define EX_M 4
#define EX_X (GEN_X + 2 * EX_M)
#define EX_Y (GEN_Y + 2 * EX_M)
#define EX_Z (GEN_Z + 2 * EX_M)
typedef struct expect_model {
    uint32_t c[EX_Z][EX_Y][EX_X]; /* RGBA8, 0: empty */
} expect_model;

static void expect_init(expect_model* e, const vx_svo_scene* s) {
    memset(e, 0, sizeof *e);
    for (int z = 0; z < GEN_Z; z++)
        for (int y = 0; y < GEN_Y; y++)
            for (int x = 0; x < GEN_X; x++)
                if (gen_cell(x, y, z)) e->c[z + EX_M][y + EX_M][x + EX_M] = s->palette[1 + x % 4];
}

/* op 0 add, 1 remove, 2 paint; shape 0 voxel, 1 box, 2 sphere; c in generated-model cells */
static void expect_apply(expect_model* e, int op, int shape, int r, const int c[3], uint32_t colour) {
    if (shape == 0) r = 0;
    for (int dz = -r; dz <= r; dz++)
        for (int dy = -r; dy <= r; dy++)
            for (int dx = -r; dx <= r; dx++) {
                if (shape == 2 && dx * dx + dy * dy + dz * dz > r * r) continue;
                int x = c[0] + dx + EX_M, y = c[1] + dy + EX_M, z = c[2] + dz + EX_M;
                if (x < 0 || y < 0 || z < 0 || x >= EX_X || y >= EX_Y || z >= EX_Z) continue;
                uint32_t* v = &e->c[z][y][x];
                if (op == 0 && !*v) *v = colour;
                else if (op == 1) *v = 0;
                else if (op == 2 && *v) *v = colour;
            }
}

/* The expected grid cells of an instance record whose transform places
 * generated-model cell p at floor(M (p + 1/2) + t). */
static void expect_cells(const expect_model* e, const vx_svo_instance* in, cells* out) {
    for (int z = 0; z < EX_Z; z++)
        for (int y = 0; y < EX_Y; y++)
            for (int x = 0; x < EX_X; x++) {
                if (!e->c[z][y][x]) continue;
                double p[3] = {x - EX_M + 0.5, y - EX_M + 0.5, z - EX_M + 0.5};
                int64_t g[3];
                for (int r = 0; r < 3; r++)
                    g[r] = (int64_t)floor(in->xform[4 * r] * p[0] + in->xform[4 * r + 1] * p[1] +
                                          in->xform[4 * r + 2] * p[2] + in->xform[4 * r + 3]);
                push(out, g, e->c[z][y][x]);
            }
}

/* Every frame's every instance of `got` against the expected model placed by
 * `orig`'s records, instance `moved` (UINT32_MAX: none) moved by `move`. */
static size_t frames_diff(const vx_svo_scene* got, const vx_svo_scene* orig, const expect_model* e, uint32_t moved,
                          const int32_t move[3]) {
    size_t bad = 0;
    uint32_t nf = vx_svo_scene_frames(orig);
    if (vx_svo_scene_frames(got) != nf || got->instance_count != orig->instance_count) return SIZE_MAX;
    for (uint32_t f = 0; f < nf; f++)
        for (uint32_t i = 0; i < orig->instance_count; i++) {
            vx_svo_instance want_in = vx_svo_scene_frame_instances(orig, f)[i];
            for (int k = 0; k < 3 && i == moved; k++) want_in.xform[4 * k + 3] += move[k];
            cells have = {0}, want = {0};
            instance_cells(got, vx_svo_scene_frame_instances(got, f) + i, &have);
            expect_cells(e, &want_in, &want);
            size_t d = cells_diff(&have, &want);
            if (d || !want.n) fprintf(stderr, "frame %u instance %u: %zu of %zu cells differ\n", f, i, d, want.n);
            bad += d + !want.n;
            free(have.v), free(want.v);
        }
    return bad;
}

/* The file bytes of s, as svo_view saves it (e: the edits' ved, NULL before any). */
static uint8_t* scene_bytes(const ved* e, const vx_svo_scene* s, size_t* n) {
    uint8_t* b = NULL;
    vx_svo_scene tmp = *s;
    if (e && vvx_file_scene(e, &tmp, NULL)) return NULL;
    vx_svo_scene_update_bounds(&tmp); /* the writer stores bounds; edits leave them stale */
    vx_result r = vx_svo_write(&tmp, NULL, &b, n, NULL);
    if (e) vvx_file_scene_free(e, &tmp);
    return r ? NULL : b;
}

/* Undoes every step of e: s saves as the n0 bytes b0 again; with redo, then redoes every step: s saves as it did
 * before the undo. */
static void check_undo_redo(ved* e, const vx_svo_scene* s, const uint8_t* b0, size_t n0, bool redo) {
    size_t n1 = 0, n2, n3;
    uint8_t* b1 = redo ? scene_bytes(e, s, &n1) : NULL;
    CHECK(!redo || b1);
    while (ved_undo(e, NULL)) {}
    uint8_t* b2 = scene_bytes(e, s, &n2);
    CHECK(b2 && n2 == n0 && !memcmp(b2, b0, n0));
    if (redo && b1) {
        while (ved_redo(e, NULL)) {}
        uint8_t* b3 = scene_bytes(e, s, &n3);
        CHECK(b3 && n3 == n1 && !memcmp(b3, b1, n1));
        vx_free(NULL, b3);
    }
    vx_free(NULL, b1), vx_free(NULL, b2);
}

/* The corpus scene with two lights and a gradient sky (lights allocated as
 * the reader does, so the editor's undo may swap them). */
static bool scene_with_lights(vx_svo_scene* s) {
    const char* in = vx_test_corpus("vox/ogt_test_groups.vox");
    if (!in || !load_vox(in, s)) return false;
    s->lights = vx_calloc(s->alloc, 2, sizeof *s->lights);
    if (!s->lights) return false;
    s->light_count = 2;
    s->lights[0] = (vx_light){.type = VX_LIGHT_POINT, .position = {4, 5, 20}, .color = {1, 0.9, 0.8}, .intensity = 300};
    s->lights[1] = (vx_light){.type = VX_LIGHT_DIRECTIONAL, .direction = {0, 0, 1}, .color = {1, 1, 1},
                              .intensity = 2};
    s->sky = (vx_sky){.type = VX_SKY_GRADIENT, .color = {0.2, 0.3, 0.6}, .horizon = {0.7, 0.7, 0.8}, .ground = {0.1, 0.1, 0.1}};
    return true;
}

/* Light edits are undo steps: edit, undo gives the scene's bytes back, redo the edit's. */
static void test_editor_lights(void) {
    vx_svo_scene s;
    if (!scene_with_lights(&s)) SKIP("corpus file vox/ogt_test_groups.vox not found");
    size_t n0, n1, n2, n3;
    uint8_t* b0 = scene_bytes(NULL, &s, &n0);
    REQUIRE(b0);
    ved e;
    ved_init(&e, &s);
    vx_error err = {0};
    REQUIRE(ved_begin(&e, &err) == VX_OK);
    s.lights[0].color[0] = 0.25, s.lights[0].intensity = 7;
    s.sky.color[2] = 0.9;
    uint8_t* b1 = scene_bytes(&e, &s, &n1);
    REQUIRE(b1);
    CHECK(n1 != n0 || memcmp(b0, b1, n0));
    CHECK(ved_undo(&e, &err));
    uint8_t* b2 = scene_bytes(&e, &s, &n2);
    CHECKF(b2 && n2 == n0 && !memcmp(b0, b2, n0), "undo of a light edit: %zu bytes, the original %zu, or other bytes", n2, n0);
    CHECK(ved_redo(&e, &err));
    uint8_t* b3 = scene_bytes(&e, &s, &n3);
    CHECKF(b3 && n3 == n1 && !memcmp(b1, b3, n1), "redo of a light edit gives other bytes");
    CHECK(s.lights[0].intensity == 7 && s.sky.color[2] == 0.9);
    vx_free(NULL, b0), vx_free(NULL, b1), vx_free(NULL, b2), vx_free(NULL, b3);
    ved_free(&e);
    vx_svo_scene_free(&s);
}

/* The palette index used by the rank-th most attribute records of the
 * scene's models (rank 0: the most used), 0 when there is none. */
static uint32_t top_palette(const vx_svo_scene* s, uint32_t rank) {
    uint32_t count[256] = {0};
    bool taken[256] = {false};
    for (uint32_t m = 0; m < s->model_count; m++)
        for (uint32_t i = 0; s->models[m].palette && i < s->models[m].attr_count; i++) count[s->models[m].palette[i]]++;
    uint32_t best = 0;
    for (uint32_t r = 0; r <= rank; r++) {
        best = 0;
        for (uint32_t k = 1; k < 256; k++)
            if (!taken[k] && count[k] > count[best]) best = k;
        taken[best] = true;
    }
    return best;
}

/* How often key occurs in a material's dictionary. */
static int key_count(const vx_svo_material* m, const char* key) {
    int n = 0;
    for (uint32_t at = 0; m && at < m->dict_size;) {
        const char* k = m->dict + at;
        size_t kl = strlen(k);
        n += !strcmp(k, key);
        at += (uint32_t)kl + 1;
        at += (uint32_t)strlen(m->dict + at) + 1;
    }
    return n;
}

static const vx_svo_material* find_material(const vx_svo_scene* s, uint32_t id) {
    for (uint32_t i = 0; i < s->material_count; i++)
        if (s->materials[i].id == id) return &s->materials[i];
    return NULL;
}

/* Material edits (ved_material_set, the properties panel's and the script's
 * `material` through sv_material_field): the resolved material (svo.h's
 * reader, an independent path) has the values set, a key set twice is
 * there once, a removed key takes its default, the file keeps them (read
 * back), undo gives the original file bytes and redo the edited ones; the
 * fields' ranges are svo.h's; the gi options parse with svo_render's
 * ranges and print as its command line. */
static void test_editor_materials(void) {
    vx_svo_scene s;
    const char* in = vx_test_corpus("vox/ogt_test_groups.vox");
    if (!in || !load_vox(in, &s)) SKIP("corpus file vox/ogt_test_groups.vox not found");
    uint32_t p = top_palette(&s, 0);
    REQUIRE(p > 0);
    size_t n0, n1, n2, n3;
    uint8_t* b0 = scene_bytes(NULL, &s, &n0);
    REQUIRE(b0);
    ved e;
    ved_init(&e, &s);
    vx_error err = {0};
    uint32_t before = s.material_count;
    bool had_p = find_material(&s, p) != NULL;
    REQUIRE(ved_begin_materials(&e, &err) == VX_OK);
    const char* keys[2];
    char values[2][SV_MATERIAL_VALUE], why[256];
    uint32_t n;
    /* through the panel's and script's field names */
    REQUIRE(sv_material_field("type", "metal", keys, values, &n, why, sizeof why));
    CHECK(n == 1 && !strcmp(keys[0], "_type") && !strcmp(values[0], "_metal"));
    REQUIRE(ved_material_set(&s, p, keys[0], values[0], &err) == VX_OK);
    REQUIRE(sv_material_field("rough", "0.25", keys, values, &n, why, sizeof why));
    REQUIRE(ved_material_set(&s, p, keys[0], values[0], &err) == VX_OK);
    REQUIRE(sv_material_field("rough", "0.5", keys, values, &n, why, sizeof why));
    REQUIRE(ved_material_set(&s, p, keys[0], values[0], &err) == VX_OK);
    /* a glass with an index (both keys) on an id the file has no material for, an emitter on another */
    uint32_t g = 201, em = 202;
    REQUIRE(!find_material(&s, g) && !find_material(&s, em));
    REQUIRE(sv_material_field("ior", "1.3", keys, values, &n, why, sizeof why));
    CHECK(n == 2 && !strcmp(keys[0], "_ri") && !strcmp(keys[1], "_ior") && !strcmp(values[1], "0.3"));
    for (uint32_t k = 0; k < n; k++) REQUIRE(ved_material_set(&s, g, keys[k], values[k], &err) == VX_OK);
    REQUIRE(ved_material_set(&s, g, "_type", "_glass", &err) == VX_OK);
    REQUIRE(ved_material_set(&s, em, "_emit", "3", &err) == VX_OK);
    REQUIRE(ved_material_set(&s, em, "_flux", "1", &err) == VX_OK);
    /* the emission's own colour (_emit_color): R,G,B, or none for the voxel's colour; bad forms refused */
    REQUIRE(sv_material_field("emit_color", "1,0.5,0", keys, values, &n, why, sizeof why));
    CHECK(n == 1 && !strcmp(keys[0], "_emit_color") && !strcmp(values[0], "1 0.5 0"));
    REQUIRE(ved_material_set(&s, em, keys[0], values[0], &err) == VX_OK);
    static const char* const bad_colors[] = {"1,2", "1,2,3,4", "-1,0,0", "nan,0,0", "inf,0,0", "1;2;3", "", "1,0,0x"};
    for (size_t i = 0; i < sizeof bad_colors / sizeof *bad_colors; i++)
        CHECKF(!sv_material_field("emit_color", bad_colors[i], keys, values, &n, why, sizeof why) &&
                   strstr(why, "emit_color"),
               "'%s' taken", bad_colors[i]);
    REQUIRE(sv_material_field("emit_color", "none", keys, values, &n, why, sizeof why));
    CHECK(!strcmp(values[0], "0 0 0"));
    CHECK(vx_svo_scene_material(&s, em).emission_color[1] == 0.5);
    CHECK(s.material_count == before + 2 + !had_p); /* new materials for the ids without one */
    vx_material mp = vx_svo_scene_material(&s, p), mg = vx_svo_scene_material(&s, g), me = vx_svo_scene_material(&s, em);
    CHECKF(mp.type == VX_MATERIAL_METAL && mp.roughness == 0.5 && mp.metalness == 1, "metal: type %d rough %g metal %g",
           (int)mp.type, mp.roughness, mp.metalness);
    CHECK(key_count(find_material(&s, p), "_rough") == 1);
    CHECKF(mg.type == VX_MATERIAL_GLASS && fabs(mg.ior - 1.3) < 1e-12 && mg.transmission == 1, "glass: ior %g", mg.ior);
    CHECKF(me.emission == 6 && me.type == VX_MATERIAL_DIFFUSE, "emitter: emission %g (3 * 2^1)", me.emission);
    /* removed: the type's default roughness */
    REQUIRE(ved_material_set(&s, p, "_rough", NULL, &err) == VX_OK);
    CHECK(key_count(find_material(&s, p), "_rough") == 0 && vx_svo_scene_material(&s, p).roughness ==
                                                                 vx_material_default(VX_MATERIAL_METAL).roughness);
    REQUIRE(ved_material_set(&s, p, "_rough", "0.5", &err) == VX_OK);
    CHECK(ved_material_set(&s, p, "", "1", &err) == VX_ERR_INVALID_ARG);
    /* bad fields and values are refused */
    CHECK(!sv_material_field("rough", "1.5", keys, values, &n, why, sizeof why));
    CHECK(!sv_material_field("ior", "0.9", keys, values, &n, why, sizeof why));
    CHECK(!sv_material_field("type", "wood", keys, values, &n, why, sizeof why));
    CHECK(!sv_material_field("shine", "1", keys, values, &n, why, sizeof why));
    CHECK(!sv_material_field("emit", "-1", keys, values, &n, why, sizeof why));
    /* the file keeps them */
    uint8_t* b1 = scene_bytes(&e, &s, &n1);
    REQUIRE(b1);
    vx_svo_scene back;
    REQUIRE(vx_svo_read(NULL, b1, n1, &back, &err) == VX_OK);
    mp = vx_svo_scene_material(&back, p), mg = vx_svo_scene_material(&back, g), me = vx_svo_scene_material(&back, em);
    CHECK(mp.type == VX_MATERIAL_METAL && mp.roughness == 0.5 && mg.type == VX_MATERIAL_GLASS &&
          fabs(mg.ior - 1.3) < 1e-12 && me.emission == 6);
    vx_svo_scene_free(&back);
    CHECK(ved_undo(&e, &err));
    uint8_t* b2 = scene_bytes(&e, &s, &n2);
    CHECKF(b2 && n2 == n0 && !memcmp(b0, b2, n0), "undo of material edits: %zu bytes, the original %zu", n2, n0);
    CHECK(s.material_count == before);
    CHECK(ved_redo(&e, &err));
    uint8_t* b3 = scene_bytes(&e, &s, &n3);
    CHECKF(b3 && n3 == n1 && !memcmp(b1, b3, n1), "redo of material edits gives other bytes");
    vx_free(NULL, b0), vx_free(NULL, b1), vx_free(NULL, b2), vx_free(NULL, b3);
    ved_free(&e);
    vx_svo_scene_free(&s);
    /* the gi options: svo_render's names and ranges */
    sv_gi_settings gs = {0};
    const char* good[][2] = {{"cone-res", "32"}, {"cones", "8"}, {"cone-aperture", "20"}, {"cone-bounces", "2"},
                             {"cone-half", "on"}, {"cone-shadows", "on"}, {"photons", "20000"}, {"radius", "0.5"},
                             {"final-gather", "2"}, {"bounces", "3"}, {"seed", "7"}, {"passes-count", "2"}};
    for (size_t i = 0; i < sizeof good / sizeof good[0]; i++)
        CHECKF(sv_gi_option(&gs, good[i][0], good[i][1], why, sizeof why), "gi %s %s: %s", good[i][0], good[i][1], why);
    CHECK(gs.cone.res == 32 && gs.cone.cones == 8 && gs.cone.aperture == 20 && gs.cone.bounces == 2 && gs.cone.half_res &&
          gs.cone.shadows && gs.photon.photons == 20000 && gs.photon.radius == 0.5 && gs.photon.final_gather == 2 &&
          gs.bounces == 3 && gs.seed == 7 && gs.spp == 2);
    const char* bad[][2] = {{"cone-res", "1"},     {"cones", "33"},         {"cone-aperture", "89"}, {"cone-bounces", "5"},
                            {"cone-half", "yes"},  {"photons", "0"},        {"radius", "-1"},        {"final-gather", "2000"},
                            {"bounces", "0"},      {"seed", "-1"},          {"spp", "0"},            {"cone-sun-angle", "30"},
                            {"fog", "1"}};
    sv_gi_settings kept = gs;
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
        CHECKF(!sv_gi_option(&gs, bad[i][0], bad[i][1], why, sizeof why), "gi %s %s accepted", bad[i][0], bad[i][1]);
    CHECK(!memcmp(&gs, &kept, sizeof gs));
    char line[320];
    sv_gi_options_format(&gs, line, sizeof line);
    CHECKF(!strcmp(line, " --bounces 3 --seed 7 --spp 2 --photons 20000 --final-gather 2 --radius 0.5 --cone-res 32 "
                         "--cones 8 --cone-aperture 20 --cone-bounces 2 --cone-half --cone-shadows"),
           "options: '%s'", line);
}

static void test_editor_voxels(void) {
    vx_svo_scene s, orig;
    make_scene(&s, 3);
    make_scene(&orig, 3);
    size_t n0;
    uint8_t* b0 = scene_bytes(NULL, &s, &n0);
    REQUIRE(b0);
    ved e;
    ved_init(&e, &s);
    expect_model ex;
    expect_init(&ex, &orig);
    /* add a box reaching below x = 0: the model grows by two cells there and its
     * instances step back, so every old cell stays where it was in the world */
    vvx_brush b = {.shape = VVX_BOX, .radius = 1, .palette = 7};
    uint64_t changed = 0;
    REQUIRE(vvx_apply(&e, 0, VVX_ADD, &b, (int64_t[3]){-1, 2, 1}, &changed, NULL) == VX_OK);
    expect_apply(&ex, 0, 1, 1, (int[3]){-1, 2, 1}, orig.palette[7]);
    CHECK(changed > 9 && s.models[0].size[0] == GEN_X + 2);
    CHECK(frames_diff(&s, &orig, &ex, UINT32_MAX, NULL) == 0);
    /* the model's cells are now two further along x: generated cell (3, 2, 2) is (5, 2, 2) */
    b = (vvx_brush){.shape = VVX_SPHERE, .radius = 1};
    REQUIRE(vvx_apply(&e, 0, VVX_REMOVE, &b, (int64_t[3]){5, 2, 2}, &changed, NULL) == VX_OK);
    expect_apply(&ex, 1, 2, 1, (int[3]){3, 2, 2}, 0);
    CHECK(frames_diff(&s, &orig, &ex, UINT32_MAX, NULL) == 0);
    b = (vvx_brush){.shape = VVX_BOX, .radius = 2, .palette = 9};
    REQUIRE(vvx_apply(&e, 0, VVX_PAINT, &b, (int64_t[3]){2, 0, 0}, &changed, NULL) == VX_OK);
    expect_apply(&ex, 2, 1, 2, (int[3]){0, 0, 0}, orig.palette[9]);
    CHECK(frames_diff(&s, &orig, &ex, UINT32_MAX, NULL) == 0);
    /* nothing there: no step */
    uint32_t steps = e.undo_count;
    b = (vvx_brush){0};
    REQUIRE(vvx_apply(&e, 0, VVX_REMOVE, &b, (int64_t[3]){100, 0, 0}, &changed, NULL) == VX_OK);
    CHECK(changed == 0 && e.undo_count == steps);
    /* undo to the start: the original bytes; redo: the edited ones */
    check_undo_redo(&e, &s, b0, n0, true);
    vx_free(NULL, b0);
    ved_free(&e);
    vx_svo_scene_free(&s);
    vx_svo_scene_free(&orig);
}

/* Instance edits of an animation keep every frame: duplicate and delete per
 * frame, a turn applied to the whole track about the chosen frame's pivot. */
static void test_editor_frames(void) {
    vx_svo_scene s, orig;
    make_scene(&s, 4);
    make_scene(&orig, 4);
    size_t n0;
    uint8_t* b0 = scene_bytes(NULL, &s, &n0);
    REQUIRE(b0);
    ved e;
    ved_init(&e, &s);
    uint32_t dup;
    REQUIRE(ved_begin(&e, NULL) == VX_OK);
    REQUIRE(ved_duplicate(&s, 1, &dup, NULL) == VX_OK);
    CHECK(dup == 2 && s.instance_count == 3 && s.frame_count == 4);
    for (uint32_t f = 0; f < 4; f++) {
        const vx_svo_instance *g = vx_svo_scene_frame_instances(&s, f), *o = vx_svo_scene_frame_instances(&orig, f);
        CHECKF(!memcmp(g, o, 2 * sizeof *g) && !memcmp(&g[2], &o[1], sizeof *g), "frame %u after duplicate", f);
    }
    REQUIRE(ved_begin(&e, NULL) == VX_OK);
    ved_delete(&s, 0);
    for (uint32_t f = 0; f < 4; f++) {
        const vx_svo_instance *g = vx_svo_scene_frame_instances(&s, f), *o = vx_svo_scene_frame_instances(&orig, f);
        CHECKF(s.instance_count == 2 && !memcmp(&g[0], &o[1], sizeof *g) && !memcmp(&g[1], &o[1], sizeof *g),
               "frame %u after delete", f);
    }
    /* a quarter turn about z with frame 2's pivot: every frame's cells turn about that point */
    double p[3];
    pivot_of(&s, vx_svo_scene_frame_instances(&s, 2) + 0, 2, true, p);
    cells before[4] = {{0}};
    for (uint32_t f = 0; f < 4; f++) instance_cells(&s, vx_svo_scene_frame_instances(&s, f) + 0, &before[f]);
    REQUIRE(ved_begin(&e, NULL) == VX_OK);
    ved_rotate(&s, 2, 0, 2, 1);
    for (uint32_t f = 0; f < 4; f++) {
        cells after = {0};
        instance_cells(&s, vx_svo_scene_frame_instances(&s, f) + 0, &after);
        for (size_t i = 0; i < before[f].n; i++) turn_z(before[f].v[i].p, p);
        CHECKF(before[f].n && cells_diff(&after, &before[f]) == 0, "frame %u after the turn", f);
        free(after.v), free(before[f].v);
    }
    REQUIRE(ved_begin(&e, NULL) == VX_OK);
    ved_hide(&s, 1, true);
    for (uint32_t f = 0; f < 4; f++) CHECK(vx_svo_scene_frame_instances(&s, f)[1].flags & VX_SVO_INSTANCE_HIDDEN);
    /* the saved file keeps every frame */
    size_t n1;
    uint8_t* b1 = scene_bytes(&e, &s, &n1);
    vx_svo_scene back;
    CHECK(b1 && vx_svo_read(NULL, b1, n1, &back, NULL) == VX_OK && back.frame_count == 4 && back.instance_count == 2);
    if (b1) vx_svo_scene_free(&back);
    check_undo_redo(&e, &s, b0, n0, false);
    vx_free(NULL, b0), vx_free(NULL, b1);
    ved_free(&e);
    vx_svo_scene_free(&s);
    vx_svo_scene_free(&orig);
}

/* Random instance and voxel edits, then undo all the way: the original file
 * bytes; redo all the way: the edited bytes. */
static void test_editor_random(void) {
    vx_svo_scene s;
    make_scene(&s, 3);
    size_t n0;
    uint8_t* b0 = scene_bytes(NULL, &s, &n0);
    REQUIRE(b0);
    ved e;
    ved_init(&e, &s);
    uint64_t rng = 0x9E3779B97F4A7C15ull;
    uint32_t edits = 0;
    for (int it = 0; it < 250; it++) {
        rng = rng * 6364136223846793005ull + 1442695040888963407ull;
        uint32_t r = (uint32_t)(rng >> 33), i = r % s.instance_count, k = (r >> 8) % 10;
        if (k <= 2) {
            vvx_brush b = {.shape = (vvx_shape)((r >> 12) % 3), .radius = (r >> 14) % 3, .palette = (uint8_t)(1 + (r >> 16) % 200)};
            const vx_svo_model* m = &s.models[s.instances[i].model];
            int64_t c[3] = {(int64_t)((r >> 4) % (m->size[0] + 2)) - 1, (int64_t)((r >> 20) % (m->size[1] + 2)) - 1,
                            (int64_t)((r >> 24) % (m->size[2] + 2)) - 1};
            uint64_t ch = 0;
            REQUIRE(vvx_apply(&e, s.instances[i].model, (vvx_op)k, &b, c, &ch, NULL) == VX_OK);
            edits += ch > 0;
            continue;
        }
        REQUIRE(ved_begin(&e, NULL) == VX_OK);
        edits++;
        if (k == 3) ved_move(&s, i, (int32_t[3]){(int32_t)(r % 7) - 3, 1, -2});
        else if (k == 4) ved_rotate(&s, (r >> 3) % 3, i, (r >> 5) % 3, (r >> 7) % 2 ? 1 : -1);
        else if (k == 5) ved_mirror(&s, (r >> 3) % 3, i, (r >> 5) % 3);
        else if (k == 6 && s.instance_count < 8) ved_duplicate(&s, i, &i, NULL);
        else if (k == 7 && s.instance_count > 1) ved_delete(&s, i);
        else if (k == 9) ved_rename(&s, i, (r >> 11) & 1 ? "renamed" : "");
        else ved_hide(&s, i, (r >> 9) & 1);
    }
    CHECK(edits > 100);
    check_undo_redo(&e, &s, b0, n0, true);
    vx_free(NULL, b0);
    ved_free(&e);
    vx_svo_scene_free(&s);
}

/* Incremental brush edits (svo/edit.h) against the reference, the model
 * decoded and built again for every edit (ved.vox_rebuild): random brushes
 * on a palette model and on an RGBA8 + normal + material + density model
 * (added cells take a neighbour's channels) give the same file bytes after
 * every edit, and the same bytes after undoing and redoing all of them. */
static void test_editor_incremental(void) {
    vx_svo_scene s[2];
    for (int k = 0; k < 2; k++) {
        make_scene(&s[k], 1);
        /* a second model with every other channel, drawn by a third instance */
        vx_svo_model* ms = vx_calloc(NULL, 2, sizeof *ms);
        vx_svo_instance* is = vx_calloc(NULL, 3, sizeof *is);
        REQUIRE(ms && is);
        ms[0] = s[k].models[0];
        memcpy(is, s[k].instances, 2 * sizeof *is);
        vx_free(NULL, s[k].models), vx_free(NULL, s[k].instances);
        s[k].models = ms, s[k].instances = is;
        uint64_t keys[9 * 7 * 5];
        uint32_t rgba[9 * 7 * 5], nrm[9 * 7 * 5];
        uint16_t mat[9 * 7 * 5];
        float den[9 * 7 * 5];
        size_t n = 0;
        for (uint32_t z = 0; z < 5; z++)
            for (uint32_t y = 0; y < 7; y++)
                for (uint32_t x = 0; x < 9; x++)
                    if ((x * y + z) % 4 != 1) {
                        keys[n] = vx_svo_morton(x, y, z), rgba[n] = 0xFF000000u | (x * 0x30u) | (y << 12);
                        nrm[n] = x % 3 * 0x1234u, mat[n] = (uint16_t)(z % 2), den[n] = 0.25f * (float)(y % 3);
                        n++;
                    }
        vx_svo_voxels v = {.size = {9, 7, 5}, .count = n, .keys = keys, .rgba = rgba, .normal = nrm, .material = mat,
                           .density = den, .attrs = VX_ATTR_RGBA8 | VX_ATTR_NORMAL | VX_ATTR_MATERIAL | VX_ATTR_DENSITY};
        REQUIRE(vx_svo_build_model(&(vx_svo_build_desc){0}, &v, &s[k].models[1], NULL, NULL) == VX_OK);
        s[k].model_count = 2;
        s[k].instances[2] = s[k].instances[0];
        s[k].instances[2].model = 1;
        s[k].instances[2].xform[3] += 40;
        s[k].instance_count = 3;
    }
    ved e[2];
    for (int k = 0; k < 2; k++) ved_init(&e[k], &s[k]);
    e[1].vox_rebuild = true;
    size_t n0;
    uint8_t* b0 = scene_bytes(NULL, &s[0], &n0);
    REQUIRE(b0);
    uint64_t rng = 0xD1B54A32D192ED03ull;
    uint32_t bad = 0, edits = 0;
    for (int it = 0; it < 120; it++) {
        rng = rng * 6364136223846793005ull + 1442695040888963407ull;
        uint32_t r = (uint32_t)(rng >> 33), model = r & 1, op = (r >> 1) % 3;
        vvx_brush b = {.shape = (vvx_shape)((r >> 3) % 3), .radius = (r >> 5) % 4, .palette = (uint8_t)(1 + (r >> 8) % 20),
                       .rgba = 0xFF000000u | (r >> 13) % 5 * 0x00402010u};
        const vx_svo_model* m = &s[0].models[model];
        /* mostly inside, sometimes past the size (growth) or below 0 (a rebuild for both) */
        int64_t c[3] = {(int64_t)((r >> 16) % (m->size[0] + 4)) - ((r >> 30) & 1 ? 1 : 0),
                        (int64_t)((r >> 20) % (m->size[1] + 2)), (int64_t)((r >> 24) % (m->size[2] + 2))};
        uint64_t ch[2] = {0, 0};
        vx_result res0 = vvx_apply(&e[0], model, (vvx_op)op, &b, c, &ch[0], NULL);
        vx_result res1 = vvx_apply(&e[1], model, (vvx_op)op, &b, c, &ch[1], NULL);
        REQUIRE(res0 == VX_OK && res1 == VX_OK);
        edits += ch[0] > 0;
        size_t na, nb;
        uint8_t* ba = scene_bytes(&e[0], &s[0], &na);
        uint8_t* bb = scene_bytes(&e[1], &s[1], &nb);
        bool same = ba && bb && na == nb && !memcmp(ba, bb, na) && ch[0] == ch[1];
        if (!same && bad++ < 3)
            fprintf(stderr, "edit %d (model %u, %s %s r%u at %lld,%lld,%lld): %llu vs %llu cells, %zu vs %zu bytes\n", it, model,
                    vvx_op_name((vvx_op)op), vvx_shape_name(b.shape), b.radius, (long long)c[0], (long long)c[1],
                    (long long)c[2], (unsigned long long)ch[0], (unsigned long long)ch[1], na, nb);
        vx_free(NULL, ba), vx_free(NULL, bb);
    }
    CHECKF(bad == 0, "%u of 120 edits differ from the rebuild", bad);
    CHECK(edits > 60);
    check_undo_redo(&e[0], &s[0], b0, n0, true);
    vx_free(NULL, b0);
    for (int k = 0; k < 2; k++) {
        ved_free(&e[k]);
        vx_svo_scene_free(&s[k]);
    }
}

/* The face brush against brute force: a terraced 10x10x6 palette model;
 * extrusions (+z on a terrace, -y and +x on sides, the +x one growing the
 * model), a push (remove), a paint limited by the radius, a face that is not
 * exposed (nothing) and one whose extrusion would reach below 0 (refused);
 * after each, every cell and palette index equals a dense grid where the
 * region is found by relaxation (cells marked until no exposed in-plane
 * neighbour of a marked one is left), and undoing all gives the original
 * bytes. */
#define FG 16
typedef struct face_grid {
    uint8_t c[FG][FG][FG]; /* [z][y][x], palette index, 0: empty */
} face_grid;

static bool fg_exposed(const face_grid* g, const int p[3], int ax, int d) {
    for (int k = 0; k < 3; k++)
        if (p[k] < 0 || p[k] >= FG) return false;
    if (!g->c[p[2]][p[1]][p[0]]) return false;
    int q[3] = {p[0], p[1], p[2]};
    q[ax] += d;
    if (q[ax] < 0 || q[ax] >= FG) return true;
    return !g->c[q[2]][q[1]][q[0]];
}

static void fg_apply(face_grid* g, int op, int face, int R, const int c[3], uint8_t pal) {
    int ax = face / 2, a1 = (ax + 1) % 3, a2 = (ax + 2) % 3, d = face & 1 ? 1 : -1;
    if (!R) R = 64;
    if (!fg_exposed(g, c, ax, d)) return;
    static uint8_t mark[FG][FG]; /* [v][u] of the plane: u along a1, v along a2 */
    memset(mark, 0, sizeof mark);
    mark[c[a2]][c[a1]] = 1;
    for (bool more = true; more;) {
        more = false;
        for (int v = 0; v < FG; v++)
            for (int u = 0; u < FG; u++) {
                if (mark[v][u] || abs(u - c[a1]) > R || abs(v - c[a2]) > R) continue;
                int p[3];
                p[ax] = c[ax], p[a1] = u, p[a2] = v;
                bool nb = (u > 0 && mark[v][u - 1]) || (u + 1 < FG && mark[v][u + 1]) || (v > 0 && mark[v - 1][u]) ||
                          (v + 1 < FG && mark[v + 1][u]);
                if (nb && fg_exposed(g, p, ax, d)) mark[v][u] = 1, more = true;
            }
    }
    face_grid before = *g;
    for (int v = 0; v < FG; v++)
        for (int u = 0; u < FG; u++) {
            if (!mark[v][u]) continue;
            int p[3];
            p[ax] = c[ax], p[a1] = u, p[a2] = v;
            uint8_t* cell = &g->c[p[2]][p[1]][p[0]];
            if (op == VVX_ADD) {
                int q[3] = {p[0], p[1], p[2]};
                q[ax] += d;
                g->c[q[2]][q[1]][q[0]] = before.c[p[2]][p[1]][p[0]];
            } else if (op == VVX_REMOVE) {
                *cell = 0;
            } else {
                *cell = pal;
            }
        }
}

static bool fg_cb(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    void** u = user;
    face_grid* g = u[0];
    const vx_svo_model* m = u[1];
    if (x < FG && y < FG && z < FG) g->c[z][y][x] = m->palette[attr];
    return true;
}

static size_t fg_diff(const vx_svo_model* m, const face_grid* want) {
    static face_grid have;
    memset(&have, 0, sizeof have);
    void* u[2] = {&have, (void*)m};
    if (vx_svo_decode_model(m, fg_cb, u, NULL) || m->voxel_count > (uint64_t)FG * FG * FG) return SIZE_MAX;
    size_t bad = 0;
    for (int z = 0; z < FG; z++)
        for (int y = 0; y < FG; y++)
            for (int x = 0; x < FG; x++) bad += have.c[z][y][x] != want->c[z][y][x];
    return bad;
}

/* The terraced 10x10x6 palette model and its grid. */
static void make_face_scene(vx_svo_scene* s, face_grid* g) {
    vx_svo_scene_init(s, NULL);
    memset(g, 0, sizeof *g);
    uint64_t keys[10 * 10 * 6];
    uint8_t pal[10 * 10 * 6];
    size_t n = 0;
    for (uint32_t z = 0; z < 6; z++)
        for (uint32_t y = 0; y < 10; y++)
            for (uint32_t x = 0; x < 10; x++)
                if (z < 3 + (x / 3 + y / 4) % 3) {
                    keys[n] = vx_svo_morton(x, y, z), pal[n] = (uint8_t)(1 + (x + y) % 3);
                    g->c[z][y][x] = pal[n++];
                }
    s->models = vx_calloc(NULL, 1, sizeof *s->models);
    s->instances = vx_calloc(NULL, 1, sizeof *s->instances);
    REQUIRE(s->models && s->instances);
    s->model_count = s->instance_count = 1;
    vx_svo_voxels v = {.size = {10, 10, 6}, .count = n, .keys = keys, .attrs = VX_ATTR_PALETTE, .palette = pal};
    REQUIRE(vx_svo_build_model(&(vx_svo_build_desc){0}, &v, &s->models[0], NULL, NULL) == VX_OK);
    s->instances[0].xform[0] = s->instances[0].xform[5] = s->instances[0].xform[10] = 1;
    s->instances[0].layer = UINT32_MAX;
    s->has_palette = true;
    for (uint32_t i = 1; i < 256; i++) s->palette[i] = 0xFF000000u | i * 0x010203u;
    vx_svo_scene_update_bounds(s);
}

static void test_editor_face(void) {
    vx_svo_scene s;
    static face_grid g;
    make_face_scene(&s, &g);
    size_t n0;
    uint8_t* b0 = scene_bytes(NULL, &s, &n0);
    REQUIRE(b0);
    ved e;
    ved_init(&e, &s);
    CHECK(fg_diff(&s.models[0], &g) == 0);
    /* op, face, radius, cell, palette; the cells changed (0: nothing to do) */
    static const struct {
        int op, face, r, c[3], pal;
        bool changes;
    } steps[] = {
        {VVX_ADD, 5, 0, {1, 1, 2}, 7, true},   /* +z on the lowest terrace: the terrace grows one layer */
        {VVX_ADD, 5, 0, {4, 1, 2}, 7, false},  /* a covered face: nothing */
        {VVX_ADD, 2, 1, {3, 4, 4}, 7, true},   /* -y side of a terrace step, radius 1 (2 of its 3 cells) */
        {VVX_ADD, 1, 0, {9, 4, 0}, 7, true},   /* +x side: the model grows to 11 */
        {VVX_REMOVE, 3, 0, {3, 9, 2}, 7, true}, /* +y side pushed in */
        {VVX_PAINT, 5, 1, {7, 1, 4}, 9, true},  /* a top, radius 1 */
        {VVX_PAINT, 5, 0, {7, 1, 4}, 9, true},  /* the rest of that region */
    };
    for (size_t i = 0; i < sizeof steps / sizeof steps[0]; i++) {
        vvx_brush b = {.shape = VVX_FACE, .radius = (uint32_t)steps[i].r, .face = (uint8_t)steps[i].face,
                       .palette = (uint8_t)steps[i].pal};
        uint64_t ch = 0;
        int64_t c[3] = {steps[i].c[0], steps[i].c[1], steps[i].c[2]};
        vx_error err = {0};
        vx_result r = vvx_apply(&e, 0, (vvx_op)steps[i].op, &b, c, &ch, &err);
        CHECKF(r == VX_OK, "face step %zu: %s", i, err.msg);
        if (r) break;
        fg_apply(&g, steps[i].op, steps[i].face, steps[i].r, steps[i].c, (uint8_t)steps[i].pal);
        size_t d = fg_diff(&s.models[0], &g);
        CHECKF(d == 0 && (ch > 0) == steps[i].changes, "face step %zu: %zu cells differ, %llu changed", i, d,
               (unsigned long long)ch);
    }
    CHECK(s.models[0].size[0] == 11);
    /* an extrusion below 0 is refused, the model unchanged */
    vvx_brush b = {.shape = VVX_FACE, .face = 0};
    uint32_t steps_before = e.undo_count;
    CHECK(vvx_apply(&e, 0, VVX_ADD, &b, (int64_t[3]){0, 3, 1}, NULL, NULL) == VX_ERR_LIMIT);
    CHECK(e.undo_count == steps_before && fg_diff(&s.models[0], &g) == 0);
    check_undo_redo(&e, &s, b0, n0, false);
    vx_free(NULL, b0);
    ved_free(&e);
    vx_svo_scene_free(&s);
}

/* ---- svo_view runs --------------------------------------------------------------------- */

static void path(char* buf, size_t n, const char* name) { snprintf(buf, n, "%s/%s", g_dir, name); }

static void test_scripted_edit(void) {
    if (!g_display) SKIP("no display (xvfb-run not found)");
    const char* in = vx_test_corpus("vox/ogt_test_groups.vox");
    if (!in) SKIP("corpus file vox/ogt_test_groups.vox not found");
    char script[1024], out_svo[1024], out_vox[1024], again[1024], log[1024], script2[1024];
    path(script, sizeof script, "edit.txt");
    path(out_svo, sizeof out_svo, "edited.svo");
    path(out_vox, sizeof out_vox, "edited.vox");
    path(again, sizeof again, "again.svo");
    path(log, sizeof log, "edit.log");
    path(script2, sizeof script2, "resave.txt");
    remove(out_svo), remove(out_vox), remove(again);
    FILE* f = fopen(script, "w");
    REQUIRE(f);
    fprintf(f,
            "# move, rotate, duplicate, delete, save\n"
            "select 1\nmove 3 -2 1\nrotate z\nduplicate\nmove 0 20 0\nmirror x\n"
            "select 0\ndelete\nundo\nredo\nsave %s\nexport %s\nquit\n",
            out_svo, out_vox);
    fclose(f);
    int rc = run_cmd("%s %s --script %s --hidden --size 96x64 > %s 2>&1", g_view, in, script, log);
    if (rc != 0) {
        char* s = slurp(log);
        fprintf(stderr, "svo_view output:\n%s\n", s ? s : "(none)");
        free(s);
    }
    REQUIRE(rc == 0);
    /* expected: the same edits applied to the cells here */
    vx_svo_scene s, got;
    REQUIRE(load_vox(in, &s));
    vx_error err = {0};
    REQUIRE(vx_svo_read_file(NULL, out_svo, &got, &err) == VX_OK);
    cells want = {0}, have = {0}, one = {0}, dup = {0};
    vx_svo_instance i1 = s.instances[1];
    for (int k = 0; k < 3; k++) i1.xform[4 * k + 3] += (int[]){3, -2, 1}[k];
    instance_cells(&s, &i1, &one);
    double c[3];
    pivot_of(&s, &i1, 2, true, c);
    for (size_t i = 0; i < one.n; i++) turn_z(one.v[i].p, c);
    /* the copy moves by (0, 20, 0), then mirrors in x about its own pivot */
    for (size_t i = 0; i < one.n; i++) push(&dup, one.v[i].p, one.v[i].rgba);
    for (size_t i = 0; i < dup.n; i++) dup.v[i].p[1] += 20;
    {
        /* pivot of the moved, rotated copy: recompute from the model box through the rotated transform */
        vx_svo_scene s2;
        REQUIRE(load_vox(in, &s2));
        s2.instances[1] = i1;
        ved_rotate(&s2, 0, 1, 2, 1);
        s2.instances[1].xform[7] += 20;
        double c2[3];
        pivot_of(&s2, &s2.instances[1], 0, false, c2);
        for (size_t i = 0; i < dup.n; i++) dup.v[i].p[0] = (int64_t)floor(-(dup.v[i].p[0] + 0.5 - c2[0]) + c2[0]);
        vx_svo_scene_free(&s2);
    }
    for (uint32_t i = 1; i < s.instance_count; i++) {
        if (!visible(&s, i)) continue;
        if (i == 1) {
            for (size_t k = 0; k < one.n; k++) push(&want, one.v[k].p, one.v[k].rgba);
        } else instance_cells(&s, &s.instances[i], &want);
    }
    if (visible(&s, 1))
        for (size_t k = 0; k < dup.n; k++) push(&want, dup.v[k].p, dup.v[k].rgba);
    scene_cells(&got, &have);
    CHECKF(got.instance_count == s.instance_count, "%u instances, expected %u", got.instance_count, s.instance_count);
    size_t d = cells_diff(&have, &want);
    CHECKF(d == 0 && want.n > 0, "%zu of %zu cells differ", d, want.n);
    /* the .vox export holds the same cells */
    vx_svo_scene vx;
    if (load_vox(out_vox, &vx)) {
        cells vc = {0};
        scene_cells(&vx, &vc);
        CHECKF(cells_diff(&vc, &have) == 0, "exported .vox differs");
        free(vc.v);
        vx_svo_scene_free(&vx);
    } else {
        CHECK(!"exported .vox does not read back");
    }
    /* the saved file reopens identically: saving it again gives the same bytes */
    f = fopen(script2, "w");
    REQUIRE(f);
    fprintf(f, "save %s\nquit\n", again);
    fclose(f);
    CHECK(run_cmd("%s %s --script %s --hidden --size 64x48 > %s 2>&1", g_view, out_svo, script2, log) == 0);
    char *a = slurp(out_svo), *b = slurp(again);
    struct stat sa, sb;
    CHECK(a && b && !stat(out_svo, &sa) && !stat(again, &sb) && sa.st_size == sb.st_size &&
          !memcmp(a, b, (size_t)sa.st_size));
    free(a), free(b);
    free(want.v), free(have.v), free(one.v), free(dup.v);
    vx_svo_scene_free(&s);
    vx_svo_scene_free(&got);
}

/* svo_view's script edits a light (two steps), undoes both and saves: the
 * file's bytes are the unedited save's; redo brings the last edit back. */
static void test_scripted_light_undo(void) {
    if (!g_display) SKIP("no display (xvfb-run not found)");
    vx_svo_scene s;
    if (!scene_with_lights(&s)) SKIP("corpus file vox/ogt_test_groups.vox not found");
    char in[1024], script[1024], plain[1024], undone[1024], redone[1024], log[1024];
    path(in, sizeof in, "lights.svo");
    path(script, sizeof script, "lights.txt");
    path(plain, sizeof plain, "lights_plain.svo");
    path(undone, sizeof undone, "lights_undone.svo");
    path(redone, sizeof redone, "lights_redone.svo");
    path(log, sizeof log, "lights.log");
    vx_error err = {0};
    REQUIRE(vx_svo_write_file(NULL, &s, in, &err) == VX_OK);
    vx_svo_scene_free(&s);
    remove(plain), remove(undone), remove(redone);
    FILE* f = fopen(script, "w");
    REQUIRE(f);
    fprintf(f, "save %s\nlight 0 color 0.1 0.2 0.3\nlight 0 intensity 42\nlight 1 intensity 0.5\nundo\nundo\nundo\n"
               "save %s\nredo\nsave %s\nquit\n", plain, undone, redone);
    fclose(f);
    int rc = run_cmd("%s %s --script %s --hidden --size 64x48 > %s 2>&1", g_view, in, script, log);
    if (rc != 0) {
        char* t = slurp(log);
        fprintf(stderr, "svo_view output:\n%s\n", t ? t : "(none)");
        free(t);
    }
    REQUIRE(rc == 0);
    char *a = slurp(plain), *b = slurp(undone);
    struct stat sa, sb;
    CHECKF(a && b && !stat(plain, &sa) && !stat(undone, &sb) && sa.st_size == sb.st_size &&
               !memcmp(a, b, (size_t)sa.st_size),
           "after undoing the light edits the saved file differs from the unedited save");
    free(a), free(b);
    vx_svo_scene got;
    REQUIRE(vx_svo_read_file(NULL, redone, &got, &err) == VX_OK);
    CHECKF(got.light_count == 2 && got.lights[0].color[0] == 0.1 && got.lights[0].color[2] == 0.3 &&
               got.lights[0].intensity == 300,
           "redo: light 0 is not the first edit's (colour %g,%g,%g, intensity %g)", got.lights[0].color[0],
           got.lights[0].color[1], got.lights[0].color[2], got.lights[0].intensity);
    vx_svo_scene_free(&got);
}

/* Palette entries the models of s use (a .svo stores only those). */
static uint32_t used_entries(const vx_svo_scene* s, uint8_t out[255]) {
    bool used[256] = {0};
    for (uint32_t m = 0; m < s->model_count; m++)
        if (s->models[m].palette)
            for (uint32_t a = 0; a < s->models[m].attr_count; a++) used[s->models[m].palette[a]] = true;
    uint32_t n = 0;
    for (int i = 1; i < 256; i++)
        if (used[i] && s->palette[i]) out[n++] = (uint8_t)i;
    return n;
}

/* A thousand random script edits (voxel add, remove and paint with every
 * brush shape, moves, turns, mirrors, duplicates, deletes, hides, renames,
 * light edits, some undone and redone on the way) with --undo-limit past
 * them, then undo to the start: the saved file has the bytes of the save
 * before the first edit; redo to the end gives the edited save's bytes. */
static void test_scripted_random(void) {
    if (!g_display) SKIP("no display (xvfb-run not found)");
    vx_svo_scene s;
    if (!scene_with_lights(&s)) SKIP("corpus file vox/ogt_test_groups.vox not found");
    char in[1024], script[1024], plain[1024], edited[1024], undone[1024], redone[1024], log[1024];
    path(in, sizeof in, "random_in.svo");
    path(script, sizeof script, "random.txt");
    path(plain, sizeof plain, "random_plain.svo");
    path(edited, sizeof edited, "random_edited.svo");
    path(undone, sizeof undone, "random_undone.svo");
    path(redone, sizeof redone, "random_redone.svo");
    path(log, sizeof log, "random.log");
    vx_error err = {0};
    REQUIRE(vx_svo_write_file(NULL, &s, in, &err) == VX_OK);
    vx_svo_scene_free(&s);
    REQUIRE(vx_svo_read_file(NULL, in, &s, &err) == VX_OK); /* the palette as the file stores it */
    uint8_t pal[255];
    uint32_t npal = used_entries(&s, pal);
    REQUIRE(npal > 0 && s.instance_count >= 2 && s.light_count == 2);
    remove(plain), remove(edited), remove(undone), remove(redone);
    FILE* f = fopen(script, "w");
    REQUIRE(f);
    fprintf(f, "overlay off\nsave %s\n", plain);
    uint32_t model[16], count = s.instance_count > 8 ? 8 : s.instance_count;
    for (uint32_t i = 0; i < count; i++) model[i] = s.instances[i].model;
    static const char* const shapes[3] = {"voxel", "box", "sphere"};
    static const char* const ops[3] = {"add", "remove", "paint"};
    static const char axes[3] = {'x', 'y', 'z'};
    uint64_t rng = 0x2545F4914F6CDD1Dull;
    const int edits = 1000;
    for (int it = 0; it < edits; it++) {
        rng = rng * 6364136223846793005ull + 1442695040888963407ull;
        uint32_t r = (uint32_t)(rng >> 32), i = r % count, k = (r >> 4) % 12;
        const uint32_t* sz = s.models[model[i]].size;
        fprintf(f, "select %u\n", i);
        if (k <= 3) {
            fprintf(f, "brush %s %u\ncolor %u\nvoxel %s %d %d %d\n", shapes[(r >> 8) % 3], (r >> 10) % 3,
                    pal[(r >> 12) % npal], ops[k % 3], (int)((r >> 16) % (sz[0] + 2)) - 1,
                    (int)((r >> 20) % (sz[1] + 2)) - 1, (int)((r >> 24) % (sz[2] + 2)) - 1);
        } else if (k == 4) fprintf(f, "move %d %d %d\n", (int)(r >> 8) % 7 - 3, (int)(r >> 12) % 5 - 2, (int)(r >> 16) % 3 - 1);
        else if (k == 5) fprintf(f, "rotate %c %d\n", axes[(r >> 8) % 3], (r >> 10) & 1 ? 1 : -1);
        else if (k == 6) fprintf(f, "mirror %c\n", axes[(r >> 8) % 3]);
        else if (k == 7) {
            if ((r >> 8) & 1) fprintf(f, "light %u intensity %g\n", (r >> 9) & 1, 0.5 + (r >> 12) % 400);
            else fprintf(f, "light 0 color %g %g %g\n", ((r >> 12) % 11) / 10.0, ((r >> 16) % 11) / 10.0, ((r >> 20) % 11) / 10.0);
        } else if (k == 8 && count < 8) {
            fprintf(f, "duplicate\n");
            model[count++] = model[i];
        } else if (k == 8 || (k == 9 && count > 2)) {
            if (k == 8) fprintf(f, "hide\n");
            else {
                fprintf(f, "delete\n");
                for (uint32_t j = i; j + 1 < count; j++) model[j] = model[j + 1];
                count--;
            }
        } else if (k == 9) fprintf(f, "rename r%u\n", r % 1000);
        else if (k == 10) fprintf(f, "show\n");
        else fprintf(f, "light 0 position %d %d %d\n", (int)(r >> 8) % 40, (int)(r >> 14) % 40, 5 + (int)(r >> 20) % 30);
        if ((r >> 28) == 0) fprintf(f, "undo\nredo\n"); /* 1 in 16 */
    }
    fprintf(f, "save %s\n", edited);
    for (int it = 0; it < edits + 8; it++) fprintf(f, "undo\n");
    fprintf(f, "save %s\n", undone);
    for (int it = 0; it < edits + 8; it++) fprintf(f, "redo\n");
    fprintf(f, "save %s\nquit\n", redone);
    fclose(f);
    double t0 = vx_time_now();
    int rc = run_cmd("%s %s --script %s --hidden --size 64x48 --undo-limit 2000 -v > %s 2>&1", g_view, in, script, log);
    char* text = slurp(log);
    if (rc != 0) fprintf(stderr, "svo_view output:\n%s\n", text ? text : "(none)");
    REQUIRE(rc == 0 && text);
    /* -v prints each step: the edits that changed something, and as many undone */
    uint32_t undos = 0, kinds[3] = {0};
    for (const char* p = text; (p = strstr(p, "svo_view: ")); p++) {
        p += 10;
        undos += !strncmp(p, "undo (", 6);
        for (int k = 0; k < 3; k++) {
            char pre[32];
            snprintf(pre, sizeof pre, "voxel %s at", ops[k]);
            kinds[k] += !strncmp(p, pre, strlen(pre));
        }
    }
    fprintf(stderr, "  %d random script edits (%u undo steps; voxel add %u, remove %u, paint %u), undone and redone: %.1f s\n",
            edits, undos, kinds[0], kinds[1], kinds[2], vx_time_now() - t0);
    CHECKF(undos > 800 && kinds[0] > 10 && kinds[1] > 10 && kinds[2] > 10, "%u steps undone", undos);
    free(text);
    char *a = slurp(plain), *b = slurp(undone), *c = slurp(edited), *d = slurp(redone);
    struct stat sa, sb, sc, sd;
    REQUIRE(a && b && c && d && !stat(plain, &sa) && !stat(undone, &sb) && !stat(edited, &sc) && !stat(redone, &sd));
    CHECKF(sa.st_size == sb.st_size && !memcmp(a, b, (size_t)sa.st_size),
           "after undoing %d random edits the saved file differs from the unedited save (%lld vs %lld bytes)", edits,
           (long long)sb.st_size, (long long)sa.st_size);
    CHECKF(sa.st_size != sc.st_size || memcmp(a, c, (size_t)sa.st_size), "the edits changed nothing");
    CHECKF(sc.st_size == sd.st_size && !memcmp(c, d, (size_t)sc.st_size), "redoing every edit gives other bytes");
    free(a), free(b), free(c), free(d);
    /* the option is what kept them: with --undo-limit 5, ten moves do not undo to the start */
    path(script, sizeof script, "random_limit.txt");
    path(undone, sizeof undone, "random_limit.svo");
    path(log, sizeof log, "random_limit.log");
    f = fopen(script, "w");
    REQUIRE(f);
    fprintf(f, "select 0\n");
    for (int it = 0; it < 10; it++) fprintf(f, "move 1 0 0\n");
    for (int it = 0; it < 12; it++) fprintf(f, "undo\n");
    fprintf(f, "save %s\nquit\n", undone);
    fclose(f);
    CHECK(run_cmd("%s %s --script %s --hidden --size 64x48 --undo-limit 5 > %s 2>&1", g_view, in, script, log) == 0);
    vx_svo_scene got;
    if (vx_svo_read_file(NULL, undone, &got, &err) == VX_OK) {
        CHECKF(got.instances[0].xform[3] == s.instances[0].xform[3] + 5, "instance 0 at x %g after 10 moves, 5 undone "
               "(from %g)", got.instances[0].xform[3], s.instances[0].xform[3]);
        vx_svo_scene_free(&got);
    } else CHECKF(false, "%s: %s", undone, err.msg);
    vx_svo_scene_free(&s);
}

/* A tool beside svo_render (svo_info, vox2svo): the same directory. */
static void sibling_tool(char* buf, size_t n, const char* name) {
    const char* slash = strrchr(g_render, '/');
    int dir = slash ? (int)(slash - g_render) : 1;
    snprintf(buf, n, "%.*s/%s", dir, slash ? g_render : ".", name);
}

/* Model 0's cells (model coordinates) and colours. */
static void model0_cells(const vx_svo_scene* s, cells* out) {
    vx_svo_instance id = {.xform = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0}, .model = 0};
    instance_cells(s, &id, out);
}

/* A script paints, removes and adds voxels with the brushes and undoes some
 * of it on a .vox file; the same edits are applied here to the file's voxel
 * grid, written with formats/'s .vox writer and converted by vox2svo: the
 * model svo_view saves has every cell and colour of that one, and its file
 * passes svo_info --verify. */
static void test_scripted_vox_compare(void) {
    if (!g_display) SKIP("no display (xvfb-run not found)");
    const char* in = vx_test_corpus("vox/eph_chr_knight.vox");
    if (!in) SKIP("corpus file vox/eph_chr_knight.vox not found");
    char info[1024], v2s[1024];
    sibling_tool(info, sizeof info, "svo_info");
    sibling_tool(v2s, sizeof v2s, "vox2svo");
    if (access(info, X_OK) || access(v2s, X_OK)) SKIP("svo_info or vox2svo is not built beside %s", g_render);
    char script[1024], saved[1024], ref_vox[1024], ref_svo[1024], log[1024];
    path(script, sizeof script, "voxcmp.txt");
    path(saved, sizeof saved, "voxcmp_view.svo");
    path(ref_vox, sizeof ref_vox, "voxcmp_ref.vox");
    path(ref_svo, sizeof ref_svo, "voxcmp_ref.svo");
    path(log, sizeof log, "voxcmp.log");
    remove(saved), remove(ref_vox), remove(ref_svo);
    vx_vox_scene vs;
    vx_error err = {0};
    REQUIRE(vx_vox_read_file(NULL, in, &vs, &err) == VX_OK);
    REQUIRE(vs.model_count == 1 && vs.instance_count == 1);
    const uint32_t* sz = vs.models[0].size;
    size_t ncell = (size_t)sz[0] * sz[1] * sz[2];
    /* the grid, palette indices; one copy per undo step */
    enum { STEPS = 200 };
    uint8_t* grid = calloc(ncell, 1);
    uint8_t** stack = calloc(STEPS, sizeof *stack);
    REQUIRE(grid && stack);
    for (uint32_t v = 0; v < vs.models[0].voxel_count; v++) {
        const uint8_t* q = &vs.models[0].xyzi[4 * v];
        grid[((size_t)q[2] * sz[1] + q[1]) * sz[0] + q[0]] = q[3];
    }
    /* the precondition: svo_view's model cells are the .vox's voxel coordinates, colours its palette's */
    vx_svo_scene orig;
    REQUIRE(load_vox(in, &orig));
    cells co = {0}, cv = {0};
    model0_cells(&orig, &co);
    for (uint32_t v = 0; v < vs.models[0].voxel_count; v++) {
        const uint8_t* q = &vs.models[0].xyzi[4 * v];
        push(&cv, (int64_t[3]){q[0], q[1], q[2]}, vs.palette[q[3]]);
    }
    REQUIRE(cells_diff(&co, &cv) == 0 && co.n > 0);
    free(cv.v);
    uint8_t colours[255];
    uint32_t ncol = 0;
    for (int i = 1; i < 256; i++)
        if (vs.palette[i]) colours[ncol++] = (uint8_t)i;
    REQUIRE(ncol > 0);
    FILE* f = fopen(script, "w");
    REQUIRE(f);
    fprintf(f, "overlay off\nselect 0\n");
    static const char* const shapes[3] = {"voxel", "box", "sphere"};
    static const char* const ops[3] = {"add", "remove", "paint"};
    uint32_t depth = 0, changed_run = 0, undos = 0, counts[3] = {0};
    uint64_t rng = 0xD1B54A32D192ED03ull;
    for (int it = 0; it < STEPS; it++) {
        rng = rng * 6364136223846793005ull + 1442695040888963407ull;
        uint32_t r = (uint32_t)(rng >> 32);
        int op = (int)(r % 3), shape = (int)((r >> 2) % 3), R = shape ? (int)((r >> 4) % 3) : 0;
        int c[3] = {(int)((r >> 6) % sz[0]), (int)((r >> 12) % sz[1]), (int)((r >> 18) % sz[2])};
        uint8_t col = colours[(r >> 24) % ncol];
        /* remove and paint mostly at a set cell (the model is sparse) */
        for (uint32_t t = 0; op && t < 64 && !grid[((size_t)c[2] * sz[1] + c[1]) * sz[0] + c[0]]; t++) {
            rng = rng * 6364136223846793005ull + 1442695040888963407ull;
            uint64_t q = (rng >> 16) % ncell;
            c[0] = (int)(q % sz[0]), c[1] = (int)(q / sz[0] % sz[1]), c[2] = (int)(q / sz[0] / sz[1]);
        }
        /* the grid before, as the undo step */
        uint8_t* before = malloc(ncell);
        REQUIRE(before);
        memcpy(before, grid, ncell);
        bool changed = false;
        for (int dz = -R; dz <= R; dz++)
            for (int dy = -R; dy <= R; dy++)
                for (int dx = -R; dx <= R; dx++) {
                    if (shape == 2 && dx * dx + dy * dy + dz * dz > R * R) continue;
                    int x = c[0] + dx, y = c[1] + dy, z = c[2] + dz;
                    if (x < 0 || y < 0 || z < 0 || x >= (int)sz[0] || y >= (int)sz[1] || z >= (int)sz[2]) continue;
                    uint8_t* g = &grid[((size_t)z * sz[1] + y) * sz[0] + x];
                    uint8_t nv = op == 0 ? (*g ? *g : col) : op == 1 ? 0 : (*g ? col : 0);
                    changed |= nv != *g;
                    *g = nv;
                }
        /* cells outside the model's box would grow it: only centres whose brush stays inside */
        bool inside = c[0] - R >= 0 && c[1] - R >= 0 && c[2] - R >= 0 && c[0] + R < (int)sz[0] &&
                      c[1] + R < (int)sz[1] && c[2] + R < (int)sz[2];
        if (!inside || !changed) {
            memcpy(grid, before, ncell);
            free(before);
            continue;
        }
        fprintf(f, "brush %s %d\ncolor %u\nvoxel %s %d %d %d\n", shapes[shape], R, col, ops[op], c[0], c[1], c[2]);
        counts[op]++;
        stack[depth++] = before;
        changed_run++;
        /* undo the last one or two (every step here changed the model, so svo_view has as many) */
        uint32_t k = (r >> 28) % 8 == 0 ? 2 : (r >> 28) % 8 == 1 ? 1 : 0;
        if (k > changed_run) k = changed_run;
        for (uint32_t u = 0; u < k; u++) {
            fprintf(f, "undo\n");
            memcpy(grid, stack[--depth], ncell);
            free(stack[depth]);
            undos++;
        }
        if (k) changed_run = 0;
    }
    fprintf(f, "save %s\nquit\n", saved);
    fclose(f);
    CHECKF(counts[0] > 5 && counts[1] > 5 && counts[2] > 5 && undos > 5, "add %u, remove %u, paint %u, undo %u",
           counts[0], counts[1], counts[2], undos);
    /* the reference: the grid written as the model of the same .vox scene */
    uint32_t nv = 0;
    for (size_t i = 0; i < ncell; i++) nv += grid[i] != 0;
    uint8_t* xyzi = vx_alloc(vs.alloc, (size_t)(nv ? nv : 1) * 4);
    REQUIRE(xyzi);
    uint32_t k = 0;
    for (uint32_t z = 0; z < sz[2]; z++)
        for (uint32_t y = 0; y < sz[1]; y++)
            for (uint32_t x = 0; x < sz[0]; x++) {
                uint8_t g = grid[((size_t)z * sz[1] + y) * sz[0] + x];
                if (!g) continue;
                xyzi[4 * k] = (uint8_t)x, xyzi[4 * k + 1] = (uint8_t)y, xyzi[4 * k + 2] = (uint8_t)z, xyzi[4 * k + 3] = g;
                k++;
            }
    vx_free(vs.alloc, vs.models[0].xyzi);
    vs.models[0].xyzi = xyzi;
    vs.models[0].voxel_count = nv;
    REQUIRE(vx_vox_write_file(NULL, &vs, ref_vox, &err) == VX_OK);
    REQUIRE(run_cmd("%s %s %s > %s 2>&1", v2s, ref_vox, ref_svo, log) == 0);
    int rc = run_cmd("%s %s --script %s --hidden --size 64x48 > %s 2>&1", g_view, in, script, log);
    if (rc != 0) {
        char* text = slurp(log);
        fprintf(stderr, "svo_view output:\n%s\n", text ? text : "(none)");
        free(text);
    }
    REQUIRE(rc == 0);
    vx_svo_scene got, want;
    REQUIRE(vx_svo_read_file(NULL, saved, &got, &err) == VX_OK);
    REQUIRE(vx_svo_read_file(NULL, ref_svo, &want, &err) == VX_OK);
    cells cg = {0}, cw = {0};
    REQUIRE(got.model_count == 1 && want.model_count == 1);
    CHECKF(!memcmp(got.models[0].size, want.models[0].size, sizeof got.models[0].size), "size %ux%ux%u, vox2svo's %ux%ux%u",
           got.models[0].size[0], got.models[0].size[1], got.models[0].size[2], want.models[0].size[0],
           want.models[0].size[1], want.models[0].size[2]);
    model0_cells(&got, &cg);
    model0_cells(&want, &cw);
    size_t d = cells_diff(&cg, &cw);
    CHECKF(d == 0 && cw.n == nv, "%zu of %zu cells (cell or colour) differ from the edited .vox converted (%u voxels)",
           d, cw.n, nv);
    CHECKF(cells_diff(&co, &cw) != 0, "the edits left the model as it was");
    fprintf(stderr, "  %u adds, %u removes, %u paints, %u undone: %zu cells, equal to the edited .vox's\n", counts[0],
            counts[1], counts[2], undos, cg.n);
    CHECK(run_cmd("%s %s --verify > %s 2>&1", info, saved, log) == 0);
    free(co.v), free(cg.v), free(cw.v);
    vx_svo_scene_free(&got), vx_svo_scene_free(&want), vx_svo_scene_free(&orig);
    while (depth) free(stack[--depth]);
    free(stack), free(grid);
    vx_vox_scene_free(&vs);
}

/* Fraction of pixels in columns [x0, x1) that differ by more than 1/255 in some channel. */
static double image_diff_cols(const char* pa, const char* pb, uint32_t x0, uint32_t x1) {
    uint32_t w1, h1, c1, w2, h2, c2;
    void *p1 = NULL, *p2 = NULL;
    if (vx_image_read(pa, VX_IMAGE_U8, 0, &w1, &h1, &c1, &p1, NULL) ||
        vx_image_read(pb, VX_IMAGE_U8, 0, &w2, &h2, &c2, &p2, NULL) || w1 != w2 || h1 != h2 || c1 != c2 || x1 > w1) {
        vx_free(NULL, p1);
        vx_free(NULL, p2);
        return 2;
    }
    size_t bad = 0, n = 0;
    const uint8_t *a = p1, *b = p2;
    for (uint32_t y = 0; y < h1; y++)
        for (uint32_t x = x0; x < x1; x++, n++) {
            size_t i = (size_t)y * w1 + x;
            bool diff = false;
            for (uint32_t k = 0; k < c1; k++) diff |= abs((int)a[i * c1 + k] - (int)b[i * c1 + k]) > 1;
            bad += diff;
        }
    vx_free(NULL, p1);
    vx_free(NULL, p2);
    return n ? (double)bad / (double)n : 2;
}

/* A script paints, removes and adds voxels with brushes, undoes and redoes,
 * steps the animation and moves an instance: the saved file keeps every
 * frame and equals the same edits applied to the cells here, brute force.
 * The displayed frame (grab) holds the panels; between them it is the
 * tracer's image (screenshot). */
static void test_scripted_voxels(void) {
    if (!g_display) SKIP("no display (xvfb-run not found)");
    vx_svo_scene orig;
    make_scene(&orig, 3);
    char in[1024], script[1024], out[1024], log[1024], grab[1024], shot[1024];
    path(in, sizeof in, "gen_anim.svo");
    path(script, sizeof script, "voxels.txt");
    path(out, sizeof out, "voxels_out.svo");
    path(log, sizeof log, "voxels.log");
    path(grab, sizeof grab, "voxels_grab.png");
    path(shot, sizeof shot, "voxels_shot.png");
    remove(out);
    REQUIRE(vx_svo_write_file(NULL, &orig, in, NULL) == VX_OK);
    FILE* f = fopen(script, "w");
    REQUIRE(f);
    fprintf(f,
            /* palette entries 1-4 are in the file (a .svo stores the used ones): colour 2 is
             * one, #102030 fills an empty entry (and is stored with the cells that use it) */
            "overlay off\nselect 1\nbrush box 1\ncolor 2\nvoxel add -1 2 1\n"   /* grows the model by two cells below x = 0 */
            "brush sphere 1\nvoxel remove 5 2 2\n"                 /* generated cell (3, 2, 2) */
            "brush box 2\ncolor #102030\nvoxel paint 2 0 0\n"      /* generated (0, 0, 0) */
            "brush voxel\ncolor 3\nvoxel add 9 0 0\nundo\nredo\nundo\n"
            "anim step 2\nmove 0 3 0\nrename walker\nselect none\ngrab %s\nscreenshot %s\nsave %s\nquit\n",
            grab, shot, out);
    fclose(f);
    int rc = run_cmd("%s %s --script %s --hidden --size 800x480 > %s 2>&1", g_view, in, script, log);
    char* text = slurp(log);
    CHECKF(rc == 0 && text && strstr(text, "frame 2 of 3"), "status %d: %s", rc, text ? text : "(none)");
    free(text);
    vx_svo_scene got;
    vx_error err = {0};
    if (rc == 0 && vx_svo_read_file(NULL, out, &got, &err) == VX_OK) {
        expect_model ex;
        expect_init(&ex, &orig);
        expect_apply(&ex, 0, 1, 1, (int[3]){-1, 2, 1}, orig.palette[2]);
        expect_apply(&ex, 1, 2, 1, (int[3]){3, 2, 2}, 0);
        expect_apply(&ex, 2, 1, 2, (int[3]){0, 0, 0}, 0xFF302010u);
        CHECK(got.frame_count == 3);
        CHECK(frames_diff(&got, &orig, &ex, 1, (int32_t[3]){0, 3, 0}) == 0);
        for (uint32_t fr = 0; fr < 3 && got.instance_count == 2; fr++)
            CHECK(!strcmp(vx_svo_scene_frame_instances(&got, fr)[1].name, "walker"));
        vx_svo_scene_free(&got);
    } else {
        CHECKF(false, "%s: %s", out, err.msg);
    }
    double panels = image_diff_cols(grab, shot, 0, 280), view = image_diff_cols(grab, shot, 310, 460);
#if VX_VIEW_PANELS
    CHECKF(panels > 0.5 && view == 0, "panel columns differ %.3f, view %.3f", panels, view);
#else
    CHECKF(view == 0, "view columns differ %.3f", view);
    (void)panels;
#endif
    vx_svo_scene_free(&orig);
}

/* The face brush through script commands (`brush face R`, `voxel OP X Y Z
 * FACE`): the saved model equals the brute-force grid after the same steps. */
static void test_scripted_face(void) {
    if (!g_display) SKIP("no display (xvfb-run not found)");
    vx_svo_scene s;
    static face_grid g;
    make_face_scene(&s, &g);
    char in[1024], script[1024], out[1024], log[1024];
    path(in, sizeof in, "face.svo");
    path(script, sizeof script, "face.txt");
    path(out, sizeof out, "face_out.svo");
    path(log, sizeof log, "face.log");
    remove(out);
    REQUIRE(vx_svo_write_file(NULL, &s, in, NULL) == VX_OK);
    FILE* f = fopen(script, "w");
    REQUIRE(f);
    fprintf(f, "select 0\nbrush face\nvoxel add 1 1 2 +z\nvoxel add 9 4 0 +x\nbrush face 1\ncolor 3\n"
               "voxel paint 7 1 4 +z\nbrush face 0\nvoxel remove 3 9 2 +y\nvoxel add 2 2 3 +z\nundo\nsave %s\nquit\n",
            out);
    fclose(f);
    int rc = run_cmd("%s %s --script %s --hidden --size 320x240 > %s 2>&1", g_view, in, script, log);
    char* text = slurp(log);
    CHECKF(rc == 0, "status %d: %s", rc, text ? text : "(none)");
    free(text);
    fg_apply(&g, VVX_ADD, 5, 0, (int[3]){1, 1, 2}, 0);
    fg_apply(&g, VVX_ADD, 1, 0, (int[3]){9, 4, 0}, 0);
    fg_apply(&g, VVX_PAINT, 5, 1, (int[3]){7, 1, 4}, 3);
    fg_apply(&g, VVX_REMOVE, 3, 0, (int[3]){3, 9, 2}, 0);
    vx_svo_scene got;
    vx_error err = {0};
    if (rc == 0 && vx_svo_read_file(NULL, out, &got, &err) == VX_OK) {
        CHECK(got.model_count == 1 && got.models[0].size[0] == 11);
        CHECK(got.model_count == 1 && fg_diff(&got.models[0], &g) == 0);
        vx_svo_scene_free(&got);
    } else {
        CHECKF(false, "%s: %s", out, err.msg);
    }
    vx_svo_scene_free(&s);
}

/* Fraction of pixels that differ by more than 1/255 in some channel. */
static double image_diff(const char* pa, const char* pb) {
    uint32_t w1, h1, c1, w2, h2, c2;
    void *p1 = NULL, *p2 = NULL;
    vx_error err = {0};
    if (vx_image_read(pa, VX_IMAGE_U8, 0, &w1, &h1, &c1, &p1, &err) ||
        vx_image_read(pb, VX_IMAGE_U8, 0, &w2, &h2, &c2, &p2, &err) || w1 != w2 || h1 != h2 || c1 != c2) {
        vx_free(NULL, p1);
        vx_free(NULL, p2);
        return 2;
    }
    size_t n = (size_t)w1 * h1, bad = 0;
    const uint8_t *a = p1, *b = p2;
    for (size_t i = 0; i < n; i++) {
        bool diff = false;
        for (uint32_t k = 0; k < c1; k++) diff |= abs((int)a[i * c1 + k] - (int)b[i * c1 + k]) > 1;
        bad += diff;
    }
    vx_free(NULL, p1);
    vx_free(NULL, p2);
    return (double)bad / (double)n;
}

/* The file's lights reach gi=pathtrace, gi=cones and gi=photons in the
 * viewer (as in svo_render: the frame refuses a gi method made without its
 * lights), and a light edit and its undo remake the method: the frames
 * differ after the edit and come back after the undo (the photons too: the
 * same seed gives the same image). */
static void test_scripted_lights_gi(void) {
    if (!g_display) SKIP("no display (xvfb-run not found)");
    vx_svo_scene s;
    if (!scene_with_lights(&s)) SKIP("corpus file vox/ogt_test_groups.vox not found");
    char in[1024], script[1024], log[1024], shot[3][1024];
    path(in, sizeof in, "lights_gi.svo");
    path(script, sizeof script, "lights_gi.txt");
    path(log, sizeof log, "lights_gi.log");
    vx_error err = {0};
    REQUIRE(vx_svo_write_file(NULL, &s, in, &err) == VX_OK);
    vx_svo_scene_free(&s);
    const char* methods[3] = {"pathtrace", "cones", "photons"};
    for (int m = 0; m < 3; m++) {
        for (int k = 0; k < 3; k++) {
            char name[64];
            snprintf(name, sizeof name, "lights_gi_%s_%d.png", methods[m], k);
            path(shot[k], sizeof shot[k], name);
            remove(shot[k]);
        }
        FILE* f = fopen(script, "w");
        REQUIRE(f);
        fprintf(f, "passes gbuffer,direct,gi=%s\nscreenshot %s\nlight 1 intensity 0.2\nscreenshot %s\nundo\n"
                   "screenshot %s\nquit\n", methods[m], shot[0], shot[1], shot[2]);
        fclose(f);
        int rc = run_cmd("%s %s --script %s --hidden --size 64x48 > %s 2>&1", g_view, in, script, log);
        char* t = slurp(log);
        bool refused = t && strstr(t, "not made with the frame's lights");
        if (rc != 0 || refused) fprintf(stderr, "svo_view output:\n%s\n", t ? t : "(none)");
        free(t);
        CHECKF(rc == 0 && !refused, "gi=%s with the file's lights: rc %d%s", methods[m], rc, refused ? ", refused" : "");
        double d01 = image_diff(shot[0], shot[1]), d02 = image_diff(shot[0], shot[2]);
        fprintf(stderr, "  gi=%s: %.1f%% of pixels change with the light, %.1f%% after its undo\n", methods[m], d01 * 100,
                d02 * 100);
        CHECKF(d01 > 0.003 && d01 <= 1, "gi=%s: the light edit changes %.3f of the pixels (the scene covers a few %%)", methods[m], d01);
        CHECKF(d02 <= 0.01, "gi=%s: after the undo %.3f of the pixels differ", methods[m], d02);
    }
}

/* The viewer's gi=photons (--passes, as the script command and key 9 set
 * it) renders what svo_render --passes renders with the same list: the same
 * photons and seed, bitwise reproducible; and the photons' light shows (the
 * image differs from the one without gi). */
static void test_photons_view(void) {
    if (!g_display) SKIP("no display (xvfb-run not found)");
    const char* in = vx_test_corpus("vox/ogt_test_groups.vox");
    if (!in) SKIP("corpus file vox/ogt_test_groups.vox not found");
    if (access(g_render, X_OK)) SKIP("svo_render is not built (%s)", g_render);
    char svo[1024], a[1024], b[1024], c[1024], log[1024];
    path(svo, sizeof svo, "photons.svo");
    path(a, sizeof a, "view_photons.png");
    path(b, sizeof b, "render_photons.png");
    path(c, sizeof c, "view_nogi.png");
    path(log, sizeof log, "photons.log");
    vx_svo_scene s;
    REQUIRE(load_vox(in, &s));
    REQUIRE(vx_svo_write_file(NULL, &s, svo, NULL) == VX_OK);
    vx_svo_scene_free(&s);
    const char* with = "gbuffer,direct,gi=photons,tonemap";
    int rc = run_cmd("%s %s --screenshot %s --size 96x72 --hidden --passes %s > %s 2>&1", g_view, svo, a, with, log);
    CHECKF(rc == 0, "svo_view --passes %s: rc %d", with, rc);
    rc = run_cmd("%s %s %s --size 96x72 --passes %s > %s 2>&1", g_render, svo, b, with, log);
    CHECKF(rc == 0, "svo_render --passes %s: rc %d", with, rc);
    rc = run_cmd("%s %s --screenshot %s --size 96x72 --hidden --passes gbuffer,direct,tonemap > %s 2>&1", g_view, svo, c,
                 log);
    CHECKF(rc == 0, "svo_view without gi: rc %d", rc);
    double d = image_diff(a, b), g = image_diff(a, c);
    fprintf(stderr, "  gi=photons: %.3f%% of pixels differ from svo_render's, %.1f%% from the image without gi\n",
            d * 100, g * 100);
    CHECKF(d <= 0.001, "gi=photons: %.4f of the pixels differ from svo_render's", d);
    CHECKF(g > 0.05 && g <= 1, "gi=photons changes %.3f of the pixels", g);
}

/* The properties panel's material edits and the render panel's GI settings,
 * as script commands (`material ID FIELD VALUE`, `gi OPTION VALUE`): the
 * frame after them equals svo_render of the saved scene with the same
 * options (its default camera, as the viewer's), differs from the frame
 * before them, and undoing the material edits gives the file's bytes and
 * frame back. Cases: metal, glass and an emitter under gi=pathtrace with
 * --bounces and --seed; gi=cones with --cone-res, --cones, --cone-bounces,
 * --cone-half; cone shadows (no direct pass, as svo_render drops it);
 * gi=photons with --photons, --radius and --spp. */
static void test_scripted_materials_gi(void) {
    if (!g_display) SKIP("no display (xvfb-run not found)");
    vx_svo_scene s;
    if (!scene_with_lights(&s)) SKIP("corpus file vox/ogt_test_groups.vox not found");
    if (access(g_render, X_OK)) SKIP("svo_render is not built (%s)", g_render);
    uint32_t p = top_palette(&s, 0), q = top_palette(&s, 1), r = top_palette(&s, 2); /* the three most used colours */
    REQUIRE(p && q && r);
    char in[1024], script[1024], log[1024], saved0[1024], saved[1024], undone[1024];
    path(in, sizeof in, "mat_in.svo");
    path(script, sizeof script, "mat.txt");
    path(log, sizeof log, "mat.log");
    path(saved0, sizeof saved0, "mat_saved0.svo");
    path(saved, sizeof saved, "mat_saved.svo");
    path(undone, sizeof undone, "mat_undone.svo");
    vx_error err = {0};
    REQUIRE(vx_svo_write_file(NULL, &s, in, &err) == VX_OK);
    vx_svo_scene_free(&s);
    static const struct {
        const char* name;
        const char* passes;
        const char* view;   /* script lines after the first screenshot */
        const char* render; /* svo_render's options */
        bool materials;
    } c[] = {
        {"pathtrace", "gbuffer,direct,gi=pathtrace", "gi bounces 3\ngi seed 7\n", "--bounces 3 --seed 7", true},
        {"cones", "gbuffer,direct,gi=cones", "gi cone-res 24\ngi cones 8\ngi cone-bounces 2\ngi cone-half on\n",
         "--cone-res 24 --cones 8 --cone-bounces 2 --cone-half", false},
        {"cone_shadows", "gbuffer,direct,gi=cones", "gi cone-res 24\ngi cone-shadows on\n", "--cone-res 24 --cone-shadows",
         false},
        {"photons", "gbuffer,direct,gi=photons", "gi photons 30000\ngi radius 0.75\ngi spp 2\n",
         "--photons 30000 --radius 0.75 --spp 2", false},
    };
    for (size_t k = 0; k < sizeof c / sizeof c[0]; k++) {
        char s0[1024], s1[1024], s2[1024], rr[1024], name[96];
        snprintf(name, sizeof name, "mat_%s_0.png", c[k].name), path(s0, sizeof s0, name);
        snprintf(name, sizeof name, "mat_%s_1.png", c[k].name), path(s1, sizeof s1, name);
        snprintf(name, sizeof name, "mat_%s_2.png", c[k].name), path(s2, sizeof s2, name);
        snprintf(name, sizeof name, "mat_%s_render.png", c[k].name), path(rr, sizeof rr, name);
        remove(s0), remove(s1), remove(s2), remove(rr), remove(saved), remove(undone), remove(saved0);
        FILE* f = fopen(script, "w");
        REQUIRE(f);
        /* with material edits the settings come first: the frames before and after differ by the materials */
        if (c[k].materials) fprintf(f, "passes %s\n%ssave %s\nscreenshot %s\n", c[k].passes, c[k].view, saved0, s0);
        else fprintf(f, "passes %s\nsave %s\nscreenshot %s\n%s", c[k].passes, saved0, s0, c[k].view);
        if (c[k].materials)
            fprintf(f, "material %u type metal\nmaterial %u rough 0.2\nmaterial %u type glass\nmaterial %u ior 1.3\n"
                       "material %u type emit\nmaterial %u emit 2\nmaterial %u flux 1\n",
                    p, p, q, q, r, r, r);
        fprintf(f, "screenshot %s\nsave %s\n", s1, saved);
        if (c[k].materials) fprintf(f, "undo\nundo\nundo\nundo\nundo\nundo\nundo\nscreenshot %s\nsave %s\n", s2, undone);
        fprintf(f, "quit\n");
        fclose(f);
        int rc = run_cmd("%s %s --script %s --hidden --size 80x60 > %s 2>&1", g_view, in, script, log);
        char* t = slurp(log);
        CHECKF(rc == 0, "%s: svo_view status %d: %s", c[k].name, rc, t ? t : "(none)");
        free(t);
        rc = run_cmd("%s %s %s --size 80x60 --passes %s %s > %s 2>&1", g_render, saved, rr, c[k].passes, c[k].render, log);
        t = slurp(log);
        CHECKF(rc == 0, "%s: svo_render status %d: %s", c[k].name, rc, t ? t : "(none)");
        free(t);
        double d = image_diff(s1, rr), ch = image_diff(s0, s1);
        fprintf(stderr, "  %s: the frame after the edits differs from svo_render's in %.3f%% of pixels, from the frame "
                        "before in %.1f%%\n", c[k].name, d * 100, ch * 100);
        CHECKF(d == 0, "%s: %.4f of the pixels differ from svo_render %s", c[k].name, d, c[k].render);
        CHECKF(ch > 0.01 && ch <= 1, "%s: the edits change %.4f of the pixels", c[k].name, ch);
        if (!c[k].materials) continue;
        /* the saved file has the materials; undoing them gives the file's bytes and the first frame */
        vx_svo_scene got;
        if (vx_svo_read_file(NULL, saved, &got, &err) == VX_OK) {
            vx_material mp = vx_svo_scene_material(&got, p), mq = vx_svo_scene_material(&got, q),
                        mr = vx_svo_scene_material(&got, r);
            CHECKF(mp.type == VX_MATERIAL_METAL && fabs(mp.roughness - 0.2) < 1e-12 && mq.type == VX_MATERIAL_GLASS &&
                       fabs(mq.ior - 1.3) < 1e-12 && mr.type == VX_MATERIAL_EMIT && mr.emission == 4,
                   "saved materials: %d %g, %d %g, %d %g", (int)mp.type, mp.roughness, (int)mq.type, mq.ior, (int)mr.type,
                   mr.emission);
            vx_svo_scene_free(&got);
        } else {
            CHECKF(false, "%s: %s", saved, err.msg);
        }
        char* x0 = slurp(saved0);
        char* x2 = slurp(undone);
        struct stat st0, st2;
        CHECKF(x0 && x2 && !stat(saved0, &st0) && !stat(undone, &st2) && st0.st_size == st2.st_size &&
                   !memcmp(x0, x2, (size_t)st0.st_size),
               "%s: the save after the undos differs from the save before the edits", c[k].name);
        free(x0), free(x2);
        CHECKF(image_diff(s0, s2) == 0, "%s: the frame after the undos differs from the first", c[k].name);
    }
}

/* The new panel sections driven as a user drives them: clicks on the
 * widgets (`ui click LABEL`: at the widget as the panels laid it out; the
 * script fails when a widget is missing), Ctrl+click and typing into
 * fields, the combo lists opened and an item clicked. The material section
 * (id slider, type combo, roughness field) and the render panel (GI method
 * combo, GI settings: a checkbox and a slider) change the scene as the
 * script commands `material` and `gi` do: the saved file has the same
 * bytes as the one saved after those commands, and the frame equals
 * svo_render of the saved scene with the same options. */
static void test_ui_panels(void) {
    if (!g_display) SKIP("no display (xvfb-run not found)");
#if !VX_VIEW_PANELS
    SKIP("svo_view was built without panels (no Dear ImGui)");
#endif
    vx_svo_scene s;
    if (!scene_with_lights(&s)) SKIP("corpus file vox/ogt_test_groups.vox not found");
    if (access(g_render, X_OK)) SKIP("svo_render is not built (%s)", g_render);
    uint32_t p = top_palette(&s, 0);
    REQUIRE(p);
    char in[1024], script[1024], log[1024], saved_ui[1024], saved_cmd[1024], shot0[1024], shot[1024], rr[1024];
    path(in, sizeof in, "ui_in.svo");
    path(script, sizeof script, "ui.txt");
    path(log, sizeof log, "ui.log");
    path(saved_ui, sizeof saved_ui, "ui_saved.svo");
    path(saved_cmd, sizeof saved_cmd, "ui_saved_cmd.svo");
    path(shot0, sizeof shot0, "ui_shot0.png");
    path(shot, sizeof shot, "ui_shot.png");
    path(rr, sizeof rr, "ui_render.png");
    vx_error err = {0};
    REQUIRE(vx_svo_write_file(NULL, &s, in, &err) == VX_OK);
    vx_svo_scene_free(&s);
    remove(saved_ui), remove(saved_cmd), remove(shot0), remove(shot), remove(rr);
    const char* render_opts = "--passes gbuffer,direct,gi=cones --cone-res 24 --cone-shadows";
    for (int m = 0; m < 2; m++) {
        FILE* f = fopen(script, "w");
        REQUIRE(f);
        if (m == 0) { /* through the widgets */
            fprintf(f, "screenshot %s\nui click Material\nui ctrl-click id (palette index / material)\nui type %u\nui key enter\n"
                       "ui click type\nui click metal\nui ctrl-click roughness\nui type 0.2\nui key enter\n"
                       "ui click GI method\nui click cones\nui click GI settings\nui click cone shadows (no direct pass)\n"
                       "ui ctrl-click volume res\nui type 24\nui key enter\nsave %s\nscreenshot %s\nquit\n",
                    shot0, p, saved_ui, shot);
        } else { /* the same edits as script commands */
            fprintf(f, "material %u type metal\nmaterial %u rough 0.2\npasses gbuffer,direct,gi=cones\ngi cone-shadows on\n"
                       "gi cone-res 24\nsave %s\nquit\n", p, p, saved_cmd);
        }
        fclose(f);
        int rc = run_cmd("%s %s --script %s --hidden --size 640x640 -v > %s 2>&1", g_view, in, script, log);
        char* t = slurp(log);
        CHECKF(rc == 0, "%s: svo_view status %d: %s", m ? "commands" : "clicks", rc, t ? t : "(none)");
        free(t);
    }
    /* the clicks made the commands' edits: the same file, byte for byte, and the material is in it */
    char* a = slurp(saved_ui);
    char* b = slurp(saved_cmd);
    struct stat sa, sb;
    bool same = a && b && !stat(saved_ui, &sa) && !stat(saved_cmd, &sb) && sa.st_size == sb.st_size &&
                !memcmp(a, b, (size_t)sa.st_size);
    fprintf(stderr, "  the file saved after the clicks %s the file saved after the commands\n", same ? "equals" : "DIFFERS from");
    CHECK(same);
    free(a), free(b);
    vx_svo_scene got;
    if (vx_svo_read_file(NULL, saved_ui, &got, &err) == VX_OK) {
        vx_material mp = vx_svo_scene_material(&got, p);
        CHECKF(mp.type == VX_MATERIAL_METAL && fabs(mp.roughness - 0.2) < 1e-12, "material %u: type %d roughness %g", p,
               (int)mp.type, mp.roughness);
        vx_svo_scene_free(&got);
    } else {
        CHECKF(false, "%s: %s", saved_ui, err.msg);
    }
    /* the frame after the clicks: svo_render's with the GI settings the clicks chose */
    int rc = run_cmd("%s %s %s --size 640x640 %s > %s 2>&1", g_render, saved_ui, rr, render_opts, log);
    char* t = slurp(log);
    CHECKF(rc == 0, "svo_render status %d: %s", rc, t ? t : "(none)");
    free(t);
    double d = image_diff(shot, rr), ch = image_diff(shot0, shot);
    fprintf(stderr, "  after the clicks the frame differs from svo_render %s in %.3f%% of pixels, from the frame before "
                    "in %.1f%%\n", render_opts, d * 100, ch * 100);
    CHECKF(d == 0, "%.4f of the pixels differ from svo_render %s", d, render_opts);
    CHECKF(ch > 0.01, "the clicks changed %.4f of the pixels", ch);
}

static void test_screenshot_matches_svo_render(void) {
    if (!g_display) SKIP("no display (xvfb-run not found)");
    const char* in = vx_test_corpus("vox/ogt_test_groups.vox");
    if (!in) SKIP("corpus file vox/ogt_test_groups.vox not found");
    if (access(g_render, X_OK)) SKIP("svo_render is not built (%s)", g_render);
    char svo[1024], a[1024], b[1024], log[1024];
    path(svo, sizeof svo, "groups.svo");
    path(log, sizeof log, "shot.log");
    vx_svo_scene s;
    REQUIRE(load_vox(in, &s));
    REQUIRE(vx_svo_write_file(NULL, &s, svo, NULL) == VX_OK);
    vx_svo_scene_free(&s);
    const char* modes[] = {"color", "instance"};
    for (int m = 0; m < 2; m++) {
        path(a, sizeof a, m ? "view_instance.png" : "view_color.png");
        path(b, sizeof b, m ? "render_instance.png" : "render_color.png");
        int rc = run_cmd("%s %s --screenshot %s --size 200x150 --hidden --mode %s > /dev/null 2>&1", g_view, in, a,
                         modes[m]);
        REQUIRE(rc == 0);
        rc = run_cmd("%s %s %s --size 200x150 --mode %s > /dev/null 2>&1", g_render, svo, b, modes[m]);
        REQUIRE(rc == 0);
        double d = image_diff(a, b);
        CHECKF(d <= 0.01, "mode %s: %.2f%% of pixels differ", modes[m], d * 100);
        fprintf(stderr, "  mode %s: %.3f%% of pixels differ from svo_render\n", modes[m], d * 100);
    }
}

/* The numbers of svo_view's `stats` line after `prefix`. */
static bool parse_stats(const char* text, int which, unsigned long long v[5]) {
    const char* p = text;
    for (int i = 0; i <= which; i++) {
        p = strstr(p, "stats: render scenes made ");
        if (!p) return false;
        if (i < which) p++;
    }
    return sscanf(p, "stats: render scenes made %llu, node words uploaded %llu, records uploaded %llu; this scene: "
                     "%*u words, %*u model updates, %llu instance table rebuilds (%llu in place)", &v[0], &v[1], &v[2],
                  &v[3], &v[4]) == 5;
}

/* Instance edits (moves, quarter turns, mirrors, a duplicate, a hide) keep
 * the GPU scene: the frames after them equal svo_render of the saved scene
 * with the same camera (colour and instance modes), no render scene is made
 * again and no node word or colour record is uploaded (svo_view's `stats`:
 * vx_render_scene_get_stats), while the instance tables were rebuilt, those
 * that keep the number of instances in place (no wait for the device). With
 * --present gpu the frames between the edits are frames in flight. */
static void test_scripted_instances_gpu(void) {
    if (!g_display) SKIP("no display (xvfb-run not found)");
    const char* src = vx_test_corpus("vox/ogt_test_groups.vox");
    if (!src) SKIP("corpus file vox/ogt_test_groups.vox not found");
    if (access(g_render, X_OK)) SKIP("svo_render is not built (%s)", g_render);
    char in[1024], script[1024], saved[1024], log[1024], va[1024], vb[1024], ra[1024], rb[1024], vd[1024];
    path(in, sizeof in, "inst_in.svo");
    path(vd, sizeof vd, "inst_view_default.png");
    path(script, sizeof script, "inst.txt");
    path(saved, sizeof saved, "inst_saved.svo");
    path(log, sizeof log, "inst.log");
    path(va, sizeof va, "inst_view_color.png");
    path(vb, sizeof vb, "inst_view_instance.png");
    path(ra, sizeof ra, "inst_render_color.png");
    path(rb, sizeof rb, "inst_render_instance.png");
    vx_svo_scene s;
    REQUIRE(load_vox(src, &s));
    REQUIRE(vx_svo_write_file(NULL, &s, in, NULL) == VX_OK);
    REQUIRE(s.instance_count >= 3);
    double lo[3], hi[3], c[3], r = 0;
    vx_svo_scene_world_bounds(&s, lo, hi);
    for (int k = 0; k < 3; k++) c[k] = 0.5 * (lo[k] + hi[k]), r = fmax(r, hi[k] - lo[k]);
    double eye[3] = {c[0] + 0.9 * r, c[1] - 1.3 * r, c[2] + 0.8 * r};
    vx_svo_scene_free(&s);
    FILE* f = fopen(script, "w");
    REQUIRE(f);
    fprintf(f,
            "overlay off\npanels off\ncamera %.6f %.6f %.6f %.6f %.6f %.6f\nstats\n"
            "select 1\nmove 3 -2 1\nrotate z\nmirror x\nselect 2\nrotate y -1\nmove 0 4 2\nduplicate\nmove 60 0 25\n"
            "select 0\nhide\nundo\nmirror y\nstats\nmode color\nscreenshot %s\nmode instance\nscreenshot %s\nstats\n"
            "camera default\nscreenshot %s\nsave %s\nquit\n",
            eye[0], eye[1], eye[2], c[0], c[1], c[2], va, vb, vd, saved);
    fclose(f);
    int rc = run_cmd("%s %s --script %s --hidden --size 160x120 --present gpu > %s 2>&1", g_view, in, script, log);
    char* text = slurp(log);
    if (rc) fprintf(stderr, "svo_view output:\n%s\n", text ? text : "(none)");
    REQUIRE(rc == 0 && text);
    unsigned long long s0[5], s1[5], s2[5];
    REQUIRE(parse_stats(text, 0, s0) && parse_stats(text, 1, s1) && parse_stats(text, 2, s2));
    /* moves, turns and mirrors keep the count (in place); the duplicate, the hide and its undo do not */
    CHECKF(s1[4] >= s0[4] + 7 && s1[3] - s0[3] >= s1[4] - s0[4] + 3, "in place %llu of %llu rebuilds", s1[4] - s0[4],
           s1[3] - s0[3]);
    CHECKF(s1[0] == s0[0] && s2[0] == s0[0], "render scenes made %llu, then %llu, %llu", s0[0], s1[0], s2[0]);
    CHECKF(s1[1] == s0[1] && s1[2] == s0[2] && s2[1] == s0[1], "node words uploaded %llu, after the instance edits %llu",
           s0[1], s1[1]);
    CHECKF(s1[3] >= s0[3] + 10, "instance tables rebuilt %llu times for 10 edits and an undo", s1[3] - s0[3]);
    CHECK(s0[1] > 0); /* the scene's own upload at creation is counted */
    free(text);
    const char* modes[2] = {"color", "instance"};
    for (int m = 0; m < 2; m++) {
        rc = run_cmd("%s %s %s --size 160x120 --camera %.6f,%.6f,%.6f,%.6f,%.6f,%.6f --mode %s > %s 2>&1", g_render,
                     saved, m ? rb : ra, eye[0], eye[1], eye[2], c[0], c[1], c[2], modes[m], log);
        REQUIRE(rc == 0);
        double d = image_diff(m ? vb : va, m ? rb : ra);
        fprintf(stderr, "  after instance edits, mode %s: %.3f%% of pixels differ from svo_render of the saved file\n",
                modes[m], d * 100);
        CHECKF(d <= 0.002, "mode %s: %.2f%% of pixels differ", modes[m], d * 100);
    }
    /* the default framing follows the moved instances, as svo_render frames the saved file */
    rc = run_cmd("%s %s %s --size 160x120 --mode instance > %s 2>&1", g_render, saved, ra, log);
    double dd = rc ? 2 : image_diff(vd, ra);
    CHECKF(dd <= 0.002, "default camera: %.2f%% of pixels differ", dd * 100);
    /* and the edits show: the unedited file's frame differs */
    rc = run_cmd("%s %s %s --size 160x120 --camera %.6f,%.6f,%.6f,%.6f,%.6f,%.6f --mode color > %s 2>&1", g_render, in,
                 rb, eye[0], eye[1], eye[2], c[0], c[1], c[2], log);
    CHECK(rc == 0 && image_diff(va, rb) > 0.01);
    /* light edits with a move, on a scene with lights: the colour frame equals svo_render of the save
     * (which lights it with the file's lights, as the viewer's passes do) */
    vx_svo_scene ls;
    REQUIRE(scene_with_lights(&ls));
    REQUIRE(vx_svo_write_file(NULL, &ls, in, NULL) == VX_OK);
    vx_svo_scene_free(&ls);
    f = fopen(script, "w");
    REQUIRE(f);
    fprintf(f,
            "overlay off\npanels off\ncamera %.6f %.6f %.6f %.6f %.6f %.6f\nlight 0 color 0.2 0.9 0.3\n"
            "light 0 position %.3f %.3f %.3f\nlight 1 intensity 0.7\nselect 1\nmove 2 3 0\nstats\nscreenshot %s\n"
            "save %s\nquit\n",
            eye[0], eye[1], eye[2], c[0], c[1], c[2], c[0] + 5, c[1] - 8, c[2] + 12, va, saved);
    fclose(f);
    rc = run_cmd("%s %s --script %s --hidden --size 160x120 > %s 2>&1", g_view, in, script, log);
    text = slurp(log);
    if (rc) fprintf(stderr, "svo_view output:\n%s\n", text ? text : "(none)");
    REQUIRE(rc == 0 && text);
    CHECKF(parse_stats(text, 0, s0) && s0[0] == 1, "render scenes made after light edits and a move: %llu", s0[0]);
    free(text);
    rc = run_cmd("%s %s %s --size 160x120 --camera %.6f,%.6f,%.6f,%.6f,%.6f,%.6f --mode color > %s 2>&1", g_render,
                 saved, ra, eye[0], eye[1], eye[2], c[0], c[1], c[2], log);
    REQUIRE(rc == 0);
    double dl = image_diff(va, ra);
    fprintf(stderr, "  after light edits and a move: %.3f%% of pixels differ from svo_render of the saved file\n", dl * 100);
    CHECKF(dl <= 0.002, "light edits: %.2f%% of pixels differ", dl * 100);
    rc = run_cmd("%s %s %s --size 160x120 --camera %.6f,%.6f,%.6f,%.6f,%.6f,%.6f --mode color > %s 2>&1", g_render, in,
                 rb, eye[0], eye[1], eye[2], c[0], c[1], c[2], log);
    CHECK(rc == 0 && image_diff(va, rb) > 0.01); /* the edits show */
}

/* Largest channel difference and the pixels differing by more than tol in
 * the box [x0, x1) x [y0, y1) of two images (-1: unreadable or sizes differ). */
static int image_box_diff(const char* pa, const char* pb, uint32_t x0, uint32_t x1, uint32_t y0, uint32_t y1, int tol,
                          size_t* over) {
    uint32_t w1, h1, c1, w2, h2, c2;
    void *p1 = NULL, *p2 = NULL;
    int m = -1;
    *over = 0;
    if (!vx_image_read(pa, VX_IMAGE_U8, 0, &w1, &h1, &c1, &p1, NULL) &&
        !vx_image_read(pb, VX_IMAGE_U8, 0, &w2, &h2, &c2, &p2, NULL) && w1 == w2 && h1 == h2 && c1 == c2 && x1 <= w1 &&
        y1 <= h1) {
        const uint8_t *a = p1, *b = p2;
        m = 0;
        for (uint32_t y = y0; y < y1; y++)
            for (uint32_t x = x0; x < x1; x++) {
                int d = 0;
                for (uint32_t k = 0; k < c1; k++) {
                    size_t i = ((size_t)y * w1 + x) * c1 + k;
                    int e = abs((int)a[i] - (int)b[i]);
                    d = e > d ? e : d;
                }
                m = d > m ? d : m;
                *over += d > tol;
            }
    }
    vx_free(NULL, p1);
    vx_free(NULL, p2);
    return m;
}

/* --present gpu (the colour passes' image converted, overlaid and copied to
 * the swapchain on the GPU, lavapipe included when asked) against --present
 * host (read back, converted and drawn on the CPU): the displayed frame
 * (grab reads the GPU path's bytes back) is the same between the panels,
 * byte for byte, and within rounding on the panels (premultiplied overlay
 * against blending each primitive into the frame); -v names the path. */
static void test_gpu_present(void) {
    if (!g_display) SKIP("no display (xvfb-run not found)");
    /* usage errors: status 2, nothing opened */
    CHECK(run_cmd("%s x.svo --present fast > /dev/null 2>&1", g_view) == 2);
    CHECK(run_cmd("%s x.svo --undo-limit 0 > /dev/null 2>&1", g_view) == 2);
    CHECK(run_cmd("%s x.svo --undo-memory lots > /dev/null 2>&1", g_view) == 2);
    const char* in = vx_test_corpus("vox/ogt_test_groups.vox");
    if (!in) SKIP("corpus file vox/ogt_test_groups.vox not found");
    char script[1024], ga[1024], gb[1024], log[1024];
    path(log, sizeof log, "present.log");
    const char* modes[2] = {"gpu", "host"};
    for (int m = 0; m < 2; m++) {
        path(script, sizeof script, m ? "present_host.txt" : "present_gpu.txt");
        path(m ? gb : ga, sizeof ga, m ? "present_host.png" : "present_gpu.png");
        FILE* f = fopen(script, "w");
        REQUIRE(f);
        fprintf(f, "select 1\ngrab %s\nquit\n", m ? gb : ga);
        fclose(f);
        int rc = run_cmd("%s %s --script %s --hidden --size 800x480 --present %s -v > %s 2>&1", g_view, in, script,
                         modes[m], log);
        char* text = slurp(log);
        CHECKF(rc == 0 && text && strstr(text, m ? "present: host readback" : "present: GPU:") &&
                   strstr(text, m ? "the displayed frame)" : "read back from the GPU path"),
               "--present %s: status %d: %s", modes[m], rc, text ? text : "(none)");
        free(text);
    }
    size_t over = 0;
    int view = image_box_diff(ga, gb, 310, 460, 0, 480, 0, &over);
    CHECKF(view == 0, "between the panels the GPU path differs from the host path by up to %d", view);
#if VX_VIEW_PANELS
    /* the outliner (no timings in it): the same within the overlay's rounding */
    int panel = image_box_diff(ga, gb, 0, 280, 0, 200, 2, &over);
    fprintf(stderr, "  GPU present path: view columns equal; outliner largest difference %d, %zu of 56000 pixels past 2\n",
            panel, over);
    CHECKF(panel >= 0 && panel <= 2 && over == 0, "outliner: %zu pixels differ by more than 2 (largest %d)", over, panel);
#endif
}

/* The validation layer can be asked for: installed, and not turned off for the
 * loader (scripts/test.sh turns it off in the sanitizer run: the release run
 * checks the same calls). */
static bool validation_layer(void) {
    if (access("/usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json", R_OK)) return false;
    const char* off = getenv("VK_LOADER_LAYERS_DISABLE");
    return !(off && (strstr(off, "validation") || strstr(off, "~all~") || strstr(off, "~explicit~")));
}

/* --batch K (frames in flight submitted K at a time, presented in order
 * after their submission), against --batch 1 on the same script (instance
 * edits, an undo, frames between them, three grabs): no validation error;
 * every frame recorded in flight is submitted and presented exactly once,
 * in the order recorded, none left queued (svo_view -v counts them from
 * the display's submissions and the presenter's presents); --batch 1 makes
 * one vkQueueSubmit a frame, --batch 3 fewer, at most three frames each; and
 * each grab (the displayed frame after the held frames went out) equals
 * --batch 1's byte for byte between the panels: a frame shows the scene it
 * was recorded with. */
static void test_batch_present(void) {
    if (!g_display) SKIP("no display (xvfb-run not found)");
    CHECK(run_cmd("%s x.svo --batch 9 > /dev/null 2>&1", g_view) == 2);
    const char* in = vx_test_corpus("vox/ogt_test_groups.vox");
    if (!in) SKIP("corpus file vox/ogt_test_groups.vox not found");
    CHECK(run_cmd("%s x.svo --batch-latency 0 > /dev/null 2>&1", g_view) == 2);
    char script[1024], g[3][3][1024], log[1024];
    path(log, sizeof log, "batch.log");
    /* 0: --batch auto, which on lavapipe's long frames batches only with a loose latency bound: 10 s here, so
     * that it goes from 1 to 4 a submission once enough frames were timed (tools/svo_view/batch.h: 4 needs frames
     * of at most a third of the bound; with 1000 ms the frames of a loaded 2-core machine, over 333 ms, gave 3) */
    const int batch[3] = {1, 3, 0};
    const char* validate = validation_layer() ? "--validate" : "";
    unsigned long long rec[3] = {0, 0, 0};
    for (int m = 0; m < 3; m++) {
        char name[64];
        snprintf(name, sizeof name, "batch%d.txt", batch[m]);
        path(script, sizeof script, name);
        for (int k = 0; k < 3; k++) {
            snprintf(name, sizeof name, "batch%d_%d.png", batch[m], k);
            path(g[m][k], sizeof g[m][k], name);
            remove(g[m][k]);
        }
        FILE* f = fopen(script, "w");
        REQUIRE(f);
        /* auto: SV_BATCH_HOLD frames and more before the edits, so that the batch has changed by then */
        fprintf(f, "wait %d\nselect 1\nmove 2 0 1\nwait 4\ngrab %s\nrotate z\nwait 7\nundo\nwait 2\ngrab %s\nselect 2\n"
                   "move 0 3 0\nwait 5\ngrab %s\nwait 3\nquit\n", batch[m] ? 5 : SV_BATCH_HOLD + 16, g[m][0], g[m][1], g[m][2]);
        fclose(f);
        char opt[64];
        if (batch[m]) snprintf(opt, sizeof opt, "--batch %d", batch[m]);
        else snprintf(opt, sizeof opt, "--batch-latency 10000");
        int rc = run_cmd("%s %s --script %s --hidden --size 800x480 --present gpu %s %s -v > %s 2>&1", g_view, in,
                         script, opt, validate, log);
        char* text = slurp(log);
        char want[64];
        if (batch[m]) snprintf(want, sizeof want, "%d a submission", batch[m]);
        else snprintf(want, sizeof want, "4 frames a submission from frame "); /* the switch, printed with -v */
        CHECKF(rc == 0 && text && strstr(text, want) && (!*validate || strstr(text, " 0 Vulkan validation errors")),
               "--batch %d: status %d: %s", batch[m], rc, text ? text : "(none)");
        const char* at = text ? strstr(text, "frames in flight: ") : NULL;
        unsigned long long sub = 0, calls = 0, pres = 0, ooo = 0;
        unsigned queued = 0;
        int got = at ? sscanf(at, "frames in flight: %llu recorded, %llu submitted in %llu vkQueueSubmit calls, %llu "
                                  "presented (%llu out of order, %u still queued)",
                              &rec[m], &sub, &calls, &pres, &ooo, &queued)
                     : 0;
        fprintf(stderr, "  --batch %s: %llu frames recorded in flight, %llu submitted in %llu calls, %llu presented, %llu "
                        "out of order, %u queued\n", batch[m] ? (batch[m] == 1 ? "1" : "3") : "auto", rec[m], sub, calls, pres,
                ooo, queued);
        CHECKF(got == 6, "--batch %d: no frame counts in the output", batch[m]);
        CHECKF(rec[m] >= 20 && sub == rec[m] && pres == rec[m] && ooo == 0 && queued == 0,
               "--batch %d: %llu recorded, %llu submitted, %llu presented, %llu out of order, %u queued", batch[m], rec[m],
               sub, pres, ooo, queued);
        if (batch[m] == 1) CHECKF(calls == rec[m], "--batch 1: %llu submissions for %llu frames", calls, rec[m]);
        else if (batch[m]) CHECKF(calls < rec[m] && calls * (unsigned long long)batch[m] >= rec[m],
                                  "--batch %d: %llu submissions for %llu frames", batch[m], calls, rec[m]);
        else { /* auto: one a submission up to the switch, then 4 */
            const char* sw = text ? strstr(text, want) : NULL;
            unsigned long long from = 0;
            CHECKF(sw && sscanf(sw + strlen(want), "%llu", &from) == 1 && from >= SV_BATCH_HOLD / 2 && from < rec[m],
                   "--batch auto: no switch to 4 a submission, or at frame %llu of %llu", from, rec[m]);
            CHECKF(calls < rec[m] && calls >= from + (rec[m] - from) / 4, "--batch auto: %llu submissions for %llu frames "
                   "(4 a submission from frame %llu)", calls, rec[m], from);
        }
        free(text);
    }
    /* between the panels (their statistics differ from run to run), as in test_gpu_present */
    for (int m = 1; m < 3; m++)
        for (int k = 0; k < 3; k++) {
            size_t over = 0;
            int d = image_box_diff(g[0][k], g[m][k], 310, 460, 0, 480, 0, &over);
            fprintf(stderr, "  --batch %s against --batch 1, grab %d: between the panels the frames differ by up to %d (%zu "
                            "pixels)\n", batch[m] ? "3" : "auto", k, d, over);
            CHECKF(d == 0, "grab %d: the frames differ by up to %d in %zu pixels", k, d, over);
        }
    /* the grabs show the edits: the first and the last differ (two moves), the second is after an undo */
    size_t over = 0;
    CHECKF(image_box_diff(g[0][0], g[0][2], 310, 460, 0, 480, 0, &over) > 0, "the move before the last grab shows no change");
}

/* The probe panel: a script bakes probes in steps between frames (probes
 * bake), shows the grid and one probe's maps, saves the set: the file has
 * the bytes of svo_bake's one-run bake with the same options (the GPU bake
 * does not depend on its batches); the grab shows the panel (the probe's
 * radiance map is in it, texel by texel) and the grid markers (the grab with
 * the grid off is the tracer's image between the panels). */
static void test_probe_panel(void) {
    if (!g_display) SKIP("no display (xvfb-run not found)");
#if !VX_VIEW_PANELS
    SKIP("svo_view has no panels in this build");
#endif
    const char* src = vx_test_corpus("vox/ogt_test_groups.vox");
    if (!src) SKIP("corpus file vox/ogt_test_groups.vox not found");
    char bake[1024];
    sibling_tool(bake, sizeof bake, "svo_bake");
    if (access(bake, X_OK)) SKIP("svo_bake is not built beside %s", g_render);
    char in[1024], script[1024], log[1024], ga[1024], gc[1024], shot[1024], pv[1024], pb[1024];
    path(in, sizeof in, "probe_in.svo");
    path(script, sizeof script, "probe.txt");
    path(log, sizeof log, "probe.log");
    path(ga, sizeof ga, "probe_grab.png");
    path(gc, sizeof gc, "probe_grab_nogrid.png");
    path(shot, sizeof shot, "probe_shot.png");
    path(pv, sizeof pv, "probe_view.probes");
    path(pb, sizeof pb, "probe_bake.probes");
    remove(pv), remove(pb);
    vx_svo_scene s;
    REQUIRE(load_vox(src, &s));
    REQUIRE(vx_svo_write_file(NULL, &s, in, NULL) == VX_OK);
    vx_svo_scene_free(&s);
    FILE* f = fopen(script, "w");
    REQUIRE(f);
    fprintf(f, "probes grid on\nprobes bake 16 4 3 3 3\nprobes show 13\ngrab %s\nscreenshot %s\nprobes save %s\n"
               "probes grid off\ngrab %s\nquit\n", ga, shot, pv, gc);
    fclose(f);
    int rc = run_cmd("%s %s --script %s --hidden --size 900x640 -v > %s 2>&1", g_view, in, script, log);
    char* text = slurp(log);
    CHECKF(rc == 0 && text && strstr(text, "baked 27 probes"), "status %d: %s", rc, text ? text : "(none)");
    free(text);
    REQUIRE(rc == 0);
    REQUIRE(run_cmd("%s %s %s --res 16 --spp 4 --grid 3,3,3 -q > %s 2>&1", bake, in, pb, log) == 0);
    char *a = slurp(pv), *b = slurp(pb);
    struct stat sa, sb;
    CHECKF(a && b && !stat(pv, &sa) && !stat(pb, &sb) && sa.st_size == sb.st_size && !memcmp(a, b, (size_t)sa.st_size),
           "the viewer's stepped bake differs from svo_bake's");
    free(a), free(b);
    /* the grid: markers between the panels, nothing there without them */
    size_t over = 0;
    int m = image_box_diff(ga, gc, 305, 565, 0, 640, 0, &over);
    CHECKF(m > 0 && over >= 27, "grid on/off: %zu pixels differ between the panels", over);
    m = image_box_diff(gc, shot, 305, 565, 0, 640, 0, &over);
    CHECKF(m == 0, "without the grid the view differs from the tracer's image by up to %d", m);
    /* probe 13's radiance map in the grab: 18 x 18 texels, 4 pixels each, as the panel tonemaps them */
    vx_probe_set ps;
    vx_error err = {0};
    REQUIRE(vx_probe_read_file(NULL, pv, &ps, &err) == VX_OK);
    REQUIRE(ps.res == 16 && ps.probe_count == 27);
    uint32_t want[18 * 18];
    for (uint32_t t = 0; t < 18 * 18; t++) {
        uint32_t v = 0;
        for (int j = 0; j < 3; j++) {
            float x = vx_probe_half_to_float(ps.radiance[(13 * 18 * 18 + t) * 3 + j]);
            x = x > 0 ? x / (1 + x) : 0;
            x = sqrtf(x);
            v |= (uint32_t)lrintf((x > 1 ? 1 : x) * 255) << (8 * j);
        }
        want[t] = v;
    }
    vx_probe_set_free(&ps);
    uint32_t w, h, c;
    void* px = NULL;
    REQUIRE(vx_image_read(ga, VX_IMAGE_U8, 0, &w, &h, &c, &px, NULL) == VX_OK && c >= 3);
    const uint8_t* g = px;
    bool found = false;
    for (uint32_t y = 300; y + 72 <= h && !found; y++)
        for (uint32_t x = 560; x + 72 <= w && !found; x++) {
            bool ok = true;
            for (uint32_t t = 0; t < 18 * 18 && ok; t++) {
                const uint8_t* q = g + ((size_t)(y + (t / 18) * 4 + 2) * w + x + (t % 18) * 4 + 2) * c;
                for (int j = 0; j < 3 && ok; j++) ok = abs((int)q[j] - (int)((want[t] >> (8 * j)) & 255)) <= 1;
            }
            found = ok;
        }
    CHECKF(found, "probe 13's radiance map is not in the probe panel of %s", ga);
    vx_free(NULL, px);
}

static void test_pick_matches_hits(void) {
    if (!g_display) SKIP("no display (xvfb-run not found)");
    const char* in = vx_test_corpus("vox/ogt_test_groups.vox");
    if (!in) SKIP("corpus file vox/ogt_test_groups.vox not found");
    vx_svo_scene s;
    REQUIRE(load_vox(in, &s));
    vx_gpu* gpu = NULL;
    vx_render_scene* rs = NULL;
    vx_render_image img = {0};
    vx_error err = {0};
    /* the reference render needs no window: without DISPLAY the driver
     * loads no window-system code (whose leaks could not be suppressed) */
    char display[256];
    snprintf(display, sizeof display, "%s", getenv("DISPLAY") ? getenv("DISPLAY") : "");
    unsetenv("DISPLAY");
    vx_result gr = vx_gpu_create(NULL, &gpu, &err);
    if (gr) setenv("DISPLAY", display, 1);
    if (gr) {
        vx_svo_scene_free(&s);
        SKIP("no Vulkan device: %s", err.msg);
    }
    const uint32_t W = 120, H = 90;
    bool ok = !vx_render_scene_create(gpu, &s, &rs, &err) &&
              !vx_render_frame(rs, &(vx_render_desc){.width = W, .height = H, .want_hits = true}, &img, &err);
    CHECKF(ok, "%s", err.msg);
    /* the hit pixel with the most hit neighbours, away from silhouettes */
    uint32_t bx = 0, by = 0, best = 0, want = VX_RENDER_NO_HIT;
    for (uint32_t y = 2; ok && y + 2 < H; y++)
        for (uint32_t x = 2; x + 2 < W; x++) {
            uint32_t id = img.hits[y * W + x].instance, same = 0;
            if (id == VX_RENDER_NO_HIT) continue;
            for (int dy = -2; dy <= 2; dy++)
                for (int dx = -2; dx <= 2; dx++) same += img.hits[(y + dy) * W + (x + dx)].instance == id;
            if (same > best) best = same, bx = x, by = y, want = id;
        }
    vx_render_image_free(&img);
    vx_render_scene_destroy(rs);
    vx_gpu_destroy(gpu);
    setenv("DISPLAY", display, 1);
    vx_svo_scene_free(&s);
    REQUIRE(ok && want != VX_RENDER_NO_HIT);
    char script[1024], log[1024];
    path(script, sizeof script, "pick.txt");
    path(log, sizeof log, "pick.log");
    FILE* f = fopen(script, "w");
    REQUIRE(f);
    fprintf(f, "pick %u %u\nquit\n", bx, by);
    fclose(f);
    char size[32];
    snprintf(size, sizeof size, "%ux%u", W, H);
    char full[4096];
    snprintf(full, sizeof full, "%s %s --script %s --hidden --size %s > %s 2>&1", g_view, in, script, size, log);
    int st = system(full);
    CHECK(st != -1 && WIFEXITED(st) && WEXITSTATUS(st) == 0);
    char* out = slurp(log);
    char expect[128];
    snprintf(expect, sizeof expect, "pick %u %u: instance %u", bx, by, want);
    CHECKF(out && strstr(out, expect), "expected '%s' in:\n%s", expect, out ? out : "(none)");
    free(out);
}

static void test_bad_files(void) {
    if (!g_display) SKIP("no display (xvfb-run not found)");
    const char* in = vx_test_corpus("vox/ogt_test_groups.vox");
    if (!in) SKIP("corpus file vox/ogt_test_groups.vox not found");
    char bad_svo[1024], bad_vox[1024], script[1024], log[1024], shot[1024];
    path(bad_svo, sizeof bad_svo, "bad.svo");
    path(bad_vox, sizeof bad_vox, "bad.vox");
    path(script, sizeof script, "bad.txt");
    path(log, sizeof log, "bad.log");
    path(shot, sizeof shot, "after_bad.png");
    FILE* f = fopen(bad_svo, "wb");
    REQUIRE(f);
    fwrite("VXSVO\0\0\0garbage-not-a-scene", 1, 28, f);
    fclose(f);
    /* a .vox whose XYZI chunk claims more voxels than there are bytes */
    f = fopen(bad_vox, "wb");
    REQUIRE(f);
    const uint8_t vox[] = {'V', 'O', 'X', ' ', 150, 0, 0, 0, 'M', 'A', 'I', 'N', 0, 0, 0, 0, 40, 0, 0, 0,
                           'S', 'I', 'Z', 'E', 12,  0, 0, 0, 0,   0,   0,   0,   2, 0, 0, 0, 2, 0, 0, 0,
                           2,   0,   0,   0,   'X', 'Y', 'Z', 'I', 8, 0, 0, 0, 0, 0, 0, 0, 255, 255, 0, 0};
    fwrite(vox, 1, sizeof vox, f);
    fclose(f);
    /* on the command line: a clean error and status 1 */
    int rc = run_cmd("%s %s --screenshot %s --hidden > %s 2>&1", g_view, bad_svo, shot, log);
    CHECKF(rc == 1, "status %d", rc);
    char* out = slurp(log);
    CHECKF(out && strstr(out, "bad.svo"), "message: %s", out ? out : "(none)");
    free(out);
    /* from the editor: a message, the scene stays, the run goes on */
    remove(shot);
    f = fopen(script, "w");
    REQUIRE(f);
    fprintf(f, "open %s\nadd %s\nadd %s/does-not-exist.vox\nscreenshot %s\nquit\n", bad_svo, bad_vox, g_dir, shot);
    fclose(f);
    rc = run_cmd("%s %s --script %s --hidden --size 64x48 > %s 2>&1", g_view, in, script, log);
    CHECKF(rc == 0, "status %d", rc);
    out = slurp(log);
    CHECKF(out && strstr(out, "bad.svo:") && strstr(out, "bad.vox:") && strstr(out, "does-not-exist.vox"),
           "messages: %s", out ? out : "(none)");
    free(out);
    CHECK(access(shot, R_OK) == 0);
    /* usage errors exit 2 */
    CHECK(run_cmd("%s %s --size 0x5 > /dev/null 2>&1", g_view, in) == 2);
    CHECK(run_cmd("%s > /dev/null 2>&1", g_view) == 2);
    CHECK(run_cmd("%s --help > /dev/null", g_view) == 0);
}

/* How many times `needle` occurs in `hay`. */
static int count_str(const char* hay, const char* needle) {
    int n = 0;
    for (const char* p = hay ? strstr(hay, needle) : NULL; p; p = strstr(p + 1, needle)) n++;
    return n;
}

/* A script's save or export that cannot write its file ends the run with
 * status 1 (it went on and ended 0, the file missing), as a layer, model or
 * instance that does not exist does (`layer N` and `setlayer`/`setmodel` ended
 * 0 where `select N` ended 1); each message names the file once (the
 * library's message names it already: it was printed twice). A file that
 * does not open still leaves the run going (test_bad_files). */
static void test_script_failures(void) {
    if (!g_display) SKIP("no display (xvfb-run not found)");
    char in[1024], script[1024], log[1024], ok[1024], bad[1024];
    path(in, sizeof in, "fail_in.svo");
    path(script, sizeof script, "fail.txt");
    path(log, sizeof log, "fail.log");
    path(ok, sizeof ok, "fail_ok.svo");
    vx_svo_scene s;
    make_scene(&s, 1);
    REQUIRE(vx_svo_write_file(NULL, &s, in, NULL) == VX_OK);
    vx_svo_scene_free(&s);
    /* the file that does not open goes on: the layer after it ends the run */
    static const char* const cmds[] = {"save %s/no-such-dir/x.svo", "export %s/no-such-dir/x.vox",
                                       "open %s/no-such-dir/x.svo\nlayer 3 hide", "select 0\nsetmodel 5"};
    for (int k = 0; k < 4; k++) {
        remove(ok);
        FILE* f = fopen(script, "w");
        REQUIRE(f);
        snprintf(bad, sizeof bad, "%s/no-such-dir/x.%s:", g_dir, k == 1 ? "vox" : "svo");
        fprintf(f, cmds[k], g_dir);
        fprintf(f, "\nsave %s\nquit\n", ok);
        fclose(f);
        int rc = run_cmd("%s %s --script %s --hidden --size 64x48 > %s 2>&1", g_view, in, script, log);
        char* out = slurp(log);
        CHECKF(rc == 1, "'%s': status %d: %s", cmds[k], rc, out ? out : "(none)");
        CHECKF(access(ok, R_OK) != 0, "'%s': the script went on", cmds[k]);
        if (k < 3) CHECKF(count_str(out, bad) == 1, "'%s': the file named %d times: %s", cmds[k], count_str(out, bad),
                          out ? out : "(none)");
        free(out);
    }
}

/* The colour of grid cell g among c's cells (0: no such cell). */
static uint32_t cell_colour(const cells* c, int64_t x, int64_t y, int64_t z) {
    for (size_t i = 0; i < c->n; i++)
        if (c->v[i].p[0] == x && c->v[i].p[1] == y && c->v[i].p[2] == z) return c->v[i].rgba;
    return 0;
}

/* A new brush colour (`color #RRGGBB`) on a .vox opened as it is: its
 * palette has all 255 entries set (MagicaVoxel writes them so) though the
 * cells use a few, and the brush refused every colour not in it ("the palette
 * is full"). It now takes an entry no cell used when the file was opened;
 * one a brush took stays its own: a colour given after an undo does not take
 * the undone paint's entry, so its redo keeps the colour. */
static void test_script_new_colour(void) {
    if (!g_display) SKIP("no display (xvfb-run not found)");
    char in[1024], script[1024], log[1024], out[1024];
    path(in, sizeof in, "colour_in.vox");
    path(script, sizeof script, "colour.txt");
    path(log, sizeof log, "colour.log");
    path(out, sizeof out, "colour_out.svo");
    vx_svo_scene s;
    make_scene(&s, 1); /* entries 1..255 set, the cells use 1..4 */
    vx_vox_scene vs;
    REQUIRE(vx_conv_svo_to_vox(&s, NULL, &vs, NULL) == VX_OK);
    REQUIRE(vx_vox_write_file(NULL, &vs, in, NULL) == VX_OK);
    vx_vox_scene_free(&vs);
    vx_svo_scene_free(&s);
    FILE* f = fopen(script, "w");
    REQUIRE(f);
    fprintf(f, "select 0\ncolor #123457\nvoxel paint 1 0 0\nundo\ncolor #654321\nredo\nvoxel paint 2 0 0\n"
               "save %s\nquit\n", out);
    fclose(f);
    remove(out);
    int rc = run_cmd("%s %s --script %s --hidden --size 64x48 > %s 2>&1", g_view, in, script, log);
    char* text = slurp(log);
    CHECKF(rc == 0, "status %d: %s", rc, text ? text : "(none)");
    free(text);
    vx_svo_scene got;
    if (rc != 0 || vx_svo_read_file(NULL, out, &got, NULL) != VX_OK) return;
    cells c = {0};
    instance_cells(&got, &got.instances[0], &c); /* instance 0: model cell + (5, 6, 7) */
    uint32_t p = cell_colour(&c, 6, 6, 7), q = cell_colour(&c, 7, 6, 7);
    CHECKF(p == 0xFF573412u, "the redone paint: colour %08x, expected ff573412 (#123457)", p);
    CHECKF(q == 0xFF214365u, "the second paint: colour %08x, expected ff214365 (#654321)", q);
    free(c.v);
    vx_svo_scene_free(&got);
}

/* A headless script run's files under the work folder: NAME_in.EXT (the
 * scene opened), NAME.txt (the script), NAME.log (its output), NAME_out.svo
 * and NAME_out.vox (what it saves and exports; removed first). */
typedef struct script_files {
    char in[1024], script[1024], log[1024], out[1024], ex[1024];
} script_files;

static void script_files_init(script_files* f, const char* name, const char* in_ext) {
    snprintf(f->in, sizeof f->in, "%s/%s_in.%s", g_dir, name, in_ext);
    snprintf(f->script, sizeof f->script, "%s/%s.txt", g_dir, name);
    snprintf(f->log, sizeof f->log, "%s/%s.log", g_dir, name);
    snprintf(f->out, sizeof f->out, "%s/%s_out.svo", g_dir, name);
    snprintf(f->ex, sizeof f->ex, "%s/%s_out.vox", g_dir, name);
    remove(f->out), remove(f->ex);
}

/* Writes the script (fmt and its arguments) and runs svo_view on f->in with
 * it, hidden at 64x48, then opts (a later --size wins); the status, and in
 * *text (when not NULL; free it) the run's output. */
static int run_script(const script_files* f, const char* opts, char** text, const char* fmt, ...)
    __attribute__((format(printf, 4, 5)));
static int run_script(const script_files* f, const char* opts, char** text, const char* fmt, ...) {
    FILE* sf = fopen(f->script, "w");
    if (text) *text = NULL;
    if (!sf) return -1;
    va_list ap;
    va_start(ap, fmt);
    vfprintf(sf, fmt, ap);
    va_end(ap);
    fclose(sf);
    int rc = run_cmd("%s %s --script %s --hidden --size 64x48 %s > %s 2>&1", g_view, f->in, f->script, opts, f->log);
    if (text) *text = slurp(f->log);
    return rc;
}

/* A shape on a layer the .vox hides (opened with --keep-hidden): `layer N
 * show` shows it, and the .vox export hides the layer, not its transform.
 * The reader gave such a shape hidden = true besides its layer's flag, so
 * the shown layer left it hidden and the export wrote _hidden on its
 * transform too. */
static void test_script_hidden_layer(void) {
    if (!g_display) SKIP("no display (xvfb-run not found)");
    script_files fs;
    script_files_init(&fs, "layer", "vox");
    vx_svo_scene s;
    make_scene(&s, 1);
    vx_vox_scene vs;
    REQUIRE(vx_conv_svo_to_vox(&s, NULL, &vs, NULL) == VX_OK);
    vx_svo_scene_free(&s);
    vx_vox_layer* l = vx_calloc(vs.alloc, 1, sizeof *l);
    REQUIRE(l && vs.instance_count == 2);
    *l = (vx_vox_layer){.id = 0, .hidden = true, .name = "off"};
    vs.layers = l, vs.layer_count = 1;
    vs.instances[1].layer = 0, vs.instances[1].hidden = false;
    REQUIRE(vx_vox_write_file(NULL, &vs, fs.in, NULL) == VX_OK);
    vx_vox_scene_free(&vs);
    int rc = run_script(&fs, "--keep-hidden", NULL, "export %s\nlayer 0 show\nsave %s\nquit\n", fs.ex, fs.out);
    REQUIRE(rc == 0);
    vx_svo_scene got;
    REQUIRE(vx_svo_read_file(NULL, fs.out, &got, NULL) == VX_OK);
    CHECKF(got.instance_count == 2 && visible(&got, 0) && visible(&got, 1), "the shown layer's shape %s",
           got.instance_count == 2 && !visible(&got, 1) ? "stays hidden" : "is missing");
    vx_svo_scene_free(&got);
    /* the export: "_hidden" once, the layer's */
    struct stat st;
    char* b = slurp(fs.ex);
    int n = 0;
    for (off_t i = 0; b && !stat(fs.ex, &st) && i + 7 <= st.st_size; i++) n += !memcmp(b + i, "_hidden", 7);
    CHECKF(n == 1, "the export holds _hidden %d times", n);
    free(b);
}

/* A model grown past 256 cells a side by the brush exports to .vox: it was
 * refused ("model 0 is 363x5x4: .vox models are at most 256 cells per
 * side"); it is now split into pieces of at most 256^3, each instance a
 * group of them (instance 1 turned), and the export reads back to the cells
 * of the save. */
static void test_script_export_split(void) {
    if (!g_display) SKIP("no display (xvfb-run not found)");
    script_files fs;
    script_files_init(&fs, "split", "svo");
    vx_svo_scene s;
    make_scene(&s, 1); /* two instances of one 6x5x4 model, the second turned */
    REQUIRE(vx_svo_write_file(NULL, &s, fs.in, NULL) == VX_OK);
    vx_svo_scene_free(&s);
    char* text;
    int rc = run_script(&fs, "", &text, "select 0\nbrush box 1\ncolor 2\nvoxel add 300 2 1\nvoxel add -60 2 2\nexport %s\nsave %s\nquit\n",
                        fs.ex, fs.out);
    CHECKF(rc == 0, "status %d: %s", rc, text ? text : "(none)");
    free(text);
    vx_svo_scene got, back;
    if (rc != 0 || vx_svo_read_file(NULL, fs.out, &got, NULL) != VX_OK) return;
    CHECKF(got.model_count == 1 && got.models[0].size[0] > 256, "the saved model is %ux%ux%u", got.models[0].size[0],
           got.models[0].size[1], got.models[0].size[2]);
    vx_vox_scene vs;
    REQUIRE(vx_vox_read_file(NULL, fs.ex, &vs, NULL) == VX_OK);
    /* two pieces along x, shared by the two instances' groups */
    CHECKF(vs.model_count == 2 && vs.instance_count == 4, "%u models, %u shapes", vs.model_count, vs.instance_count);
    vx_vox_scene_free(&vs);
    REQUIRE(load_vox(fs.ex, &back));
    cells a = {0}, b = {0};
    scene_cells(&got, &a);
    scene_cells(&back, &b);
    size_t d = cells_diff(&a, &b);
    CHECKF(d == 0 && a.n > 0, "%zu of %zu cells differ", d, a.n);
    for (uint32_t i = 0; i < back.instance_count; i++)
        CHECKF(!strcmp(back.instances[i].name, i < 2 ? "inst0" : "inst1"), "piece %u named '%s'", i, back.instances[i].name);
    free(a.v), free(b.v);
    vx_svo_scene_free(&got);
    vx_svo_scene_free(&back);
}

/* The script's `sky SPEC` (svo_render --sky's text; alone it prints the
 * sky): a gradient set, saved, read back; a map given from the current
 * folder stored from the scene file's folder (as vox2svo --sky); undo and
 * redo restore the sky before and after; a bad text ends the run naming
 * what is wrong. Before, svo_view had no way to set the sky. */
static void test_script_sky(void) {
    if (!g_display) SKIP("no display (xvfb-run not found)");
    script_files fs;
    script_files_init(&fs, "sky", "svo");
    vx_svo_scene s;
    make_scene(&s, 1); /* no sky: the default */
    vx_error err = {0};
    REQUIRE(vx_svo_write_file(NULL, &s, fs.in, &err) == VX_OK);
    vx_svo_scene_free(&s);
    /* the map from the current folder: g_dir below it (ctest's) or relative, else absolute (stored as given) */
    char cwd[1024], map[1200], grad[1100], mapped[1100], undone[1100];
    REQUIRE(getcwd(cwd, sizeof cwd));
    size_t cl = strlen(cwd);
    bool below = !strncmp(g_dir, cwd, cl) && g_dir[cl] == '/', rel = below || g_dir[0] != '/';
    snprintf(map, sizeof map, "%s/env/sky.exr", below ? g_dir + cl + 1 : g_dir);
    snprintf(grad, sizeof grad, "%s/sky_grad.svo", g_dir);
    snprintf(mapped, sizeof mapped, "%s/sky_map.svo", g_dir);
    snprintf(undone, sizeof undone, "%s/sky_undone.svo", g_dir);
    remove(grad), remove(mapped), remove(undone);
    const char* g = "gradient:0.2,0.3,0.6:0.7,0.7,0.8:0.1,0.1,0";
    char* text;
    int rc = run_script(&fs, "", &text,
                        "sky\nsky %s\nsky\nsave %s\nsky map:%s:2:90\nsky\nsave %s\nundo\nsky\nsave %s\nundo\nsky\n"
                        "redo\nredo\nsky\nquit\n",
                        g, grad, map, mapped, undone);
    CHECKF(rc == 0, "svo_view: %s", text ? text : "(no output)");
    /* what `sky` printed, in order: default, the gradient, the map (from here), then after the undos the
     * gradient and the default, after the redos the map */
    char want[6][1400];
    snprintf(want[0], sizeof want[0], "sky default\n");
    snprintf(want[1], sizeof want[1], "sky %s\n", g);
    snprintf(want[2], sizeof want[2], "sky map:%s:2:90\n", map);
    snprintf(want[3], sizeof want[3], "sky %s\n", g);
    snprintf(want[4], sizeof want[4], "sky default\n");
    snprintf(want[5], sizeof want[5], "sky map:%s:2:90\n", map);
    const char* at = text ? text : "";
    for (int i = 0; i < 6 && at; i++) {
        const char* f = strstr(at, want[i]);
        CHECKF(f, "`sky` %d printed no '%.*s' in:\n%s", i, (int)strlen(want[i]) - 1, want[i], text ? text : "");
        at = f ? f + strlen(want[i]) : NULL;
    }
    free(text);
    vx_svo_scene got;
    if (vx_svo_read_file(NULL, grad, &got, &err) == VX_OK) {
        vx_sky k = {.type = VX_SKY_GRADIENT, .color = {0.2, 0.3, 0.6}, .horizon = {0.7, 0.7, 0.8}, .ground = {0.1, 0.1, 0}};
        CHECKF(!memcmp(&got.sky, &k, sizeof k), "the saved gradient: type %d, zenith %g %g %g", (int)got.sky.type,
               got.sky.color[0], got.sky.color[1], got.sky.color[2]);
        vx_svo_scene_free(&got);
    } else {
        CHECKF(false, "%s: %s", grad, err.msg);
    }
    if (vx_svo_read_file(NULL, mapped, &got, &err) == VX_OK) {
        /* stored from the file's folder (g_dir): "env/sky.exr" either way */
        CHECKF(got.sky.type == VX_SKY_ENVMAP && !strcmp(got.sky.path, rel ? "env/sky.exr" : map) &&
                   got.sky.intensity == 2 && fabs(got.sky.rotation - 3.14159265358979323846 / 2) < 1e-15,
               "the saved map: type %d, path '%s', intensity %g, rotation %g", (int)got.sky.type, got.sky.path,
               got.sky.intensity, got.sky.rotation);
        vx_svo_scene_free(&got);
    } else {
        CHECKF(false, "%s: %s", mapped, err.msg);
    }
    /* the undone save is the gradient's, byte for byte */
    char *a = slurp(grad), *b = slurp(undone);
    struct stat sa, sb;
    CHECKF(a && b && !stat(grad, &sa) && !stat(undone, &sb) && sa.st_size == sb.st_size && !memcmp(a, b, (size_t)sa.st_size),
           "after undoing the map the saved file differs from the gradient's save");
    free(a), free(b);
#if VX_VIEW_PANELS
    /* the properties panel's Sky section: its type combo sets a gradient through the same setter (undo restores);
     * `wait 2`: the item's release reaches the panels in the frames after the script goes on */
    remove(fs.out);
    rc = run_script(&fs, "--size 640x640", &text,
                    "ui click Sky\nui click sky type\nui click gradient\nwait 2\nsave %s\nundo\nsky\nquit\n", fs.out);
    CHECKF(rc == 0 && text && strstr(text, "sky default\n"), "the panel's sky, undone: status %d: %s", rc,
           text ? text : "(no output)");
    free(text);
    if (vx_svo_read_file(NULL, fs.out, &got, &err) == VX_OK) {
        vx_sky k = {.type = VX_SKY_GRADIENT, .color = {0.5, 0.6, 0.8}, .horizon = {0.9, 0.9, 1}, .ground = {0.2, 0.2, 0.2}};
        CHECKF(!memcmp(&got.sky, &k, sizeof k), "the panel's gradient: type %d, zenith %g %g %g", (int)got.sky.type,
               got.sky.color[0], got.sky.color[1], got.sky.color[2]);
        vx_svo_scene_free(&got);
    } else {
        CHECKF(false, "%s: %s", fs.out, err.msg);
    }
#endif
    /* a bad text: the run fails, saying what is wrong, and saves nothing after it */
    remove(fs.out);
    rc = run_script(&fs, "", &text, "sky gradient:1,1,1\nsave %s\nquit\n", fs.out);
    CHECKF(rc != 0 && text && strstr(text, "bad sky 'gradient:1,1,1'") && strstr(text, "gradient:ZR") && access(fs.out, F_OK),
           "a bad sky: status %d: %s", rc, text ? text : "(no output)");
    free(text);
}

/* The frame uses the sky set (frame.c file_sky): after `sky R,G,B` the
 * passes' frame (lights: the radiometric model, the sky the background)
 * equals svo_render's of the saved file, and differs from the frame before. */
static void test_script_sky_frame(void) {
    if (!g_display) SKIP("no display (xvfb-run not found)");
    if (access(g_render, X_OK)) SKIP("svo_render is not built (%s)", g_render);
    vx_svo_scene s;
    if (!scene_with_lights(&s)) SKIP("corpus file vox/ogt_test_groups.vox not found");
    script_files fs;
    script_files_init(&fs, "skyframe", "svo");
    vx_error err = {0};
    REQUIRE(vx_svo_write_file(NULL, &s, fs.in, &err) == VX_OK);
    vx_svo_scene_free(&s);
    char shot0[1024], shot[1024], rr[1100];
    path(shot0, sizeof shot0, "skyframe0.png");
    path(shot, sizeof shot, "skyframe1.png");
    snprintf(rr, sizeof rr, "%s/skyframe_render.png", g_dir);
    remove(shot0), remove(shot), remove(rr);
    char* text;
    int rc = run_script(&fs, "--size 96x72", &text,
                        "passes gbuffer,direct\nscreenshot %s\nsky 0.9,0.2,0.1\nsave %s\nscreenshot %s\nquit\n", shot0,
                        fs.out, shot);
    CHECKF(rc == 0, "svo_view: %s", text ? text : "(no output)");
    free(text);
    if (rc) return;
    rc = run_cmd("%s %s %s --size 96x72 --passes gbuffer,direct > %s 2>&1", g_render, fs.out, rr, fs.log);
    CHECKF(rc == 0, "svo_render status %d", rc);
    double d = image_diff(shot, rr), ch = image_diff(shot0, shot);
    fprintf(stderr, "  after `sky` the frame differs from svo_render's in %.3f%% of pixels, from the frame before in %.1f%%\n",
            d * 100, ch * 100);
    CHECKF(d == 0, "%.4f of the pixels differ from svo_render of the saved file", d);
    CHECKF(ch > 0.05, "the sky changed %.4f of the pixels", ch);
}

/* `export FILE.glb` and `export FILE.vdb` (convert/export.h through the
 * editor): after an edit, the .glb is the library's export of the scene the
 * script then saves, byte for byte (its metal record and its light too), and
 * the .vdb read back (the OpenVDB import) holds the saved scene's cells. */
/* A map sky's relative path follows a save to another folder (stop 74): the
 * saved file names the same image from its own folder (vx_sky_rebase); before,
 * the path's text was copied and named a file that is not there. */
static void test_script_save_sky_map(void) {
    if (!g_display) SKIP("no display (xvfb-run not found)");
    script_files fs;
    script_files_init(&fs, "skymap", "svo");
    vx_svo_scene s;
    make_scene(&s, 1);
    s.sky.type = VX_SKY_ENVMAP, s.sky.intensity = 2;
    snprintf(s.sky.path, sizeof s.sky.path, "env/sky.exr");
    vx_error err = {0};
    REQUIRE(vx_svo_write_file(NULL, &s, fs.in, &err) == VX_OK);
    vx_svo_scene_free(&s);
    char deep[1024], out[1100];
    snprintf(deep, sizeof deep, "%s/skymap_deep", g_dir);
    mkdir(deep, 0755);
    snprintf(out, sizeof out, "%s/m.svo", deep);
    remove(out);
    char* text;
    int rc = run_script(&fs, "", &text, "save %s\nquit\n", out);
    CHECKF(rc == 0, "svo_view: %s", text ? text : "(no output)");
    free(text);
    vx_svo_scene got;
    REQUIRE(vx_svo_read_file(NULL, out, &got, &err) == VX_OK);
    CHECKF(got.sky.type == VX_SKY_ENVMAP && !strcmp(got.sky.path, "../env/sky.exr") && got.sky.intensity == 2,
           "the saved sky's path '%s'", got.sky.path);
    vx_svo_scene_free(&got);
}

static void test_script_export_glb_vdb(void) {
    if (!g_display) SKIP("no display (xvfb-run not found)");
    script_files fs;
    script_files_init(&fs, "glbvdb", "svo");
    enum { N = 6 };
    uint64_t keys[N * N * N];
    uint8_t pal[N * N * N];
    uint32_t n = 0;
    for (uint32_t k = 0; k < N * N * N; k++) {
        uint32_t x = k % N, y = k / N % N, z = k / (N * N);
        if ((x + y + z) % 3 == 0) continue;
        keys[n] = vx_svo_morton(x, y, z), pal[n++] = (uint8_t)(1 + (x + 2 * y + 3 * z) % 4);
    }
    vx_svo_scene s;
    vx_svo_scene_init(&s, NULL);
    s.models = vx_calloc(NULL, 1, sizeof *s.models);
    s.instances = vx_calloc(NULL, 2, sizeof *s.instances);
    s.materials = vx_calloc(NULL, 1, sizeof *s.materials);
    s.lights = vx_calloc(NULL, 1, sizeof *s.lights);
    REQUIRE(s.models && s.instances && s.materials && s.lights);
    s.model_count = 1, s.instance_count = 2;
    s.has_palette = true;
    for (int i = 1; i < 256; i++) s.palette[i] = 0xFF000000u | (uint32_t)(i * 0x3F1F0F);
    vx_svo_voxels v = {.size = {N, N, N}, .count = n, .keys = keys, .attrs = VX_ATTR_PALETTE, .palette = pal};
    REQUIRE(vx_svo_build_model(&(vx_svo_build_desc){0}, &v, &s.models[0], NULL, NULL) == VX_OK);
    for (int i = 0; i < 2; i++) {
        s.instances[i].xform[0] = s.instances[i].xform[5] = s.instances[i].xform[10] = 1;
        s.instances[i].xform[3] = 8.0 * i;
        s.instances[i].layer = UINT32_MAX;
    }
    static const char metal[] = "_type\0_metal\0_rough\0" "0.3";
    s.materials[0] = (vx_svo_material){.id = 2, .dict_size = sizeof metal, .dict = vx_calloc(NULL, 1, sizeof metal)};
    REQUIRE(s.materials[0].dict);
    memcpy(s.materials[0].dict, metal, sizeof metal);
    s.material_count = 1;
    s.lights[0] = (vx_light){.type = VX_LIGHT_POINT, .position = {7, 3, 12}, .color = {1, 0.9, 0.8}, .intensity = 40};
    s.light_count = 1;
    REQUIRE(vx_svo_write_file(NULL, &s, fs.in, NULL) == VX_OK);
    vx_svo_scene_free(&s);
    char glb[1100], vdb[1100], again[1100];
    snprintf(glb, sizeof glb, "%s/glbvdb_out.glb", g_dir);
    snprintf(vdb, sizeof vdb, "%s/glbvdb_out.vdb", g_dir);
    snprintf(again, sizeof again, "%s/glbvdb_again.glb", g_dir);
    remove(glb), remove(vdb);
    char* text;
    int rc = run_script(&fs, "", &text, "select 1\nmove 0 3 0\nexport %s\nexport %s\nsave %s\nquit\n", glb, vdb, fs.out);
    CHECKF(rc == 0 && text && strstr(text, glb) && strstr(text, vdb), "status %d: %s", rc, text ? text : "(none)");
    free(text);
    vx_svo_scene saved;
    if (rc != 0 || vx_svo_read_file(NULL, fs.out, &saved, NULL) != VX_OK) return;
    vx_error err = {0};
    vx_result r = vx_conv_svo_to_glb_file(NULL, &saved, again, NULL, &err);
    if (r == VX_ERR_UNSUPPORTED) {
        fprintf(stderr, "  %s: the .glb comparison skipped\n", err.msg);
    } else {
        size_t na = 0, nb = 0;
        char *a = vx_test_slurp(glb, &na), *b = vx_test_slurp(again, &nb);
        CHECKF(r == VX_OK && a && b, "reading the .glb files: %s", err.msg);
        CHECKF(a && b && na == nb && !memcmp(a, b, na) && na > 1000,
               "export FILE.glb: %zu bytes, the library's export of the saved scene %zu", na, nb);
        CHECKF(a && strstr(a + 20, "KHR_lights_punctual") && strstr(a + 20, "\"metallicFactor\""),
               "the .glb's JSON holds the light and the metal material");
        free(a), free(b);
    }
#ifdef VX_VIEW_VDB
    vx_svo_scene back;
    r = vx_conv_vdb_file(&(vx_conv_vdb_desc){.color_grid = "color"}, vdb, &back, NULL, &err);
    CHECKF(r == VX_OK, "the .vdb read back: %s", err.msg);
    if (r == VX_OK) {
        cells ca = {0}, cb = {0};
        scene_cells(&saved, &ca);
        scene_cells(&back, &cb);
        CHECKF(ca.n == 2 * n && cells_diff(&ca, &cb) == 0, "export FILE.vdb: %zu cells back of the saved %zu", cb.n,
               ca.n);
        free(ca.v), free(cb.v);
        vx_svo_scene_free(&back);
    }
#endif
    vx_svo_scene_free(&saved);
}

/* More than 255 colours: the viewer's .vox export refused them and named
 * svo_info --to-vox --quantize as the only way; `export FILE quantize` and
 * the Export panel's checkbox now map them to a 255-entry palette (as
 * svo_info --quantize) with a warning giving the count and the error. An
 * 8^3 RGBA8 cube, cell (x, y, z) coloured (32x, 32y, 32z): 512 colours.
 * Without quantize: refused (status 1, no file), naming the count and the
 * viewer's option. With it: every saved cell at its place in the export,
 * each colour's error its distance to the nearest palette entry in use, the
 * largest as the warning says and within the median cut's bound; the
 * panel's checkbox and button write the same bytes. */
static void test_script_export_quantize(void) {
    if (!g_display) SKIP("no display (xvfb-run not found)");
    script_files fs;
    script_files_init(&fs, "quant", "svo");
    enum { N = 8, STEP = 32 };
    uint64_t keys[N * N * N];
    uint32_t rgba[N * N * N];
    for (uint32_t k = 0; k < N * N * N; k++) {
        uint32_t x = k % N, y = k / N % N, z = k / (N * N);
        keys[k] = vx_svo_morton(x, y, z), rgba[k] = 0xFF000000u | (z * STEP) << 16 | (y * STEP) << 8 | x * STEP;
    }
    vx_svo_scene s;
    vx_svo_scene_init(&s, NULL);
    s.models = vx_calloc(NULL, 1, sizeof *s.models);
    s.instances = vx_calloc(NULL, 1, sizeof *s.instances);
    REQUIRE(s.models && s.instances);
    s.model_count = 1, s.instance_count = 1;
    vx_svo_voxels v = {.size = {N, N, N}, .count = N * N * N, .keys = keys, .attrs = VX_ATTR_RGBA8, .rgba = rgba};
    REQUIRE(vx_svo_build_model(&(vx_svo_build_desc){0}, &v, &s.models[0], NULL, NULL) == VX_OK);
    s.instances[0].xform[0] = s.instances[0].xform[5] = s.instances[0].xform[10] = 1;
    s.instances[0].layer = UINT32_MAX;
    REQUIRE(vx_svo_write_file(NULL, &s, fs.in, NULL) == VX_OK);
    vx_svo_scene_free(&s);
    /* refused without quantize: the run ends 1 (as a failed export does), no file */
    char* text;
    int rc = run_script(&fs, "", &text, "export %s\nsave %s\nquit\n", fs.ex, fs.out);
    CHECKF(rc == 1 && access(fs.ex, F_OK) != 0, "without quantize: status %d, the file %s", rc,
           access(fs.ex, F_OK) ? "absent" : "written");
    CHECKF(text && strstr(text, fs.ex) && strstr(text, "512 distinct colours") && strstr(text, "export FILE.vox quantize") &&
               !strstr(text, "svo_info"),
           "the refusal: %s", text ? text : "(none)");
    free(text);
    /* quantized, with a warning */
    rc = run_script(&fs, "", &text, "export %s quantize\nsave %s\nquit\n", fs.ex, fs.out);
    const char* w = text ? strstr(text, "512 distinct colours quantized to a 255-entry palette") : NULL;
    double wmax = -1, wmean = -1;
    CHECKF(rc == 0 && w && sscanf(strstr(w, "max "), "max %lf, mean %lf", &wmax, &wmean) == 2, "status %d: %s", rc,
           text ? text : "(none)");
    free(text);
    vx_svo_scene got, back;
    vx_vox_scene vs;
    if (rc != 0 || vx_svo_read_file(NULL, fs.out, &got, NULL) != VX_OK) return;
    REQUIRE(vx_vox_read_file(NULL, fs.ex, &vs, NULL) == VX_OK);
    REQUIRE(load_vox(fs.ex, &back));
    cells a = {0}, b = {0};
    scene_cells(&got, &a);
    scene_cells(&back, &b);
    qsort(a.v, a.n, sizeof *a.v, cmp_cell);
    qsort(b.v, b.n, sizeof *b.v, cmp_cell);
    size_t moved = a.n != b.n ? SIZE_MAX : 0, not_nearest = 0;
    double max = 0, sum = 0;
    for (size_t i = 0; moved != SIZE_MAX && i < a.n; i++) {
        if (memcmp(a.v[i].p, b.v[i].p, sizeof a.v[i].p)) moved++;
        double d = vx_test_rgba_dist(a.v[i].rgba, b.v[i].rgba), best = INFINITY;
        for (uint32_t e = 1; e < 256; e++) { /* the entries the export's cells use */
            bool used = false;
            for (uint32_t m = 0; m < vs.model_count && !used; m++)
                for (uint32_t k = 0; k < vs.models[m].voxel_count && !used; k++) used = vs.models[m].xyzi[4 * (size_t)k + 3] == e;
            if (used) best = fmin(best, vx_test_rgba_dist(a.v[i].rgba, vs.palette[e]));
        }
        not_nearest += d != best;
        max = fmax(max, d), sum += d;
    }
    CHECKF(a.n == N * N * N && moved == 0, "%zu saved cells, %zu exported; %zu moved", a.n, b.n, moved);
    CHECKF(not_nearest == 0, "%zu cells not at their nearest entry", not_nearest);
    double mean = a.n ? sum / (double)a.n : 0;
    /* 255 boxes over the 8^3 lattice, halved along the widest side: none
     * larger than 2 x 2 x 2 points, so a colour lies at most sqrt(3) half
     * steps from its box's mean, plus the mean's rounding (half a unit a channel) */
    double bound = STEP / 2.0 * sqrt(3) + 0.5 * sqrt(3);
    fprintf(stderr, "  512 colours quantized: error max %.2f, mean %.2f (warning: %.2f, %.2f; bound %.2f)\n", max, mean, wmax,
            wmean, bound);
    CHECKF(fabs(max - wmax) <= 0.005 && fabs(mean - wmean) <= 0.005, "error max %.3f mean %.3f, the warning says %.2f %.2f", max,
           mean, wmax, wmean);
    CHECKF(max > 0 && max <= bound, "error max %.2f, bound %.2f", max, bound);
    free(a.v), free(b.v);
    vx_vox_scene_free(&vs);
    vx_svo_scene_free(&back);
    vx_svo_scene_free(&got);
#if VX_VIEW_PANELS
    /* the Export panel: the checkbox, then the button (Ctrl+E's file, FILE.edited.vox) */
    char edited[1024];
    path(edited, sizeof edited, "quant_in.edited.vox");
    remove(edited);
    rc = run_script(&fs, "--size 640x640", &text, "panels on\nui click Export\nui click quantize colours (over 255)\n"
                                    "ui click export .vox (Ctrl+E)\nwait 2\nquit\n");
    char *e1 = slurp(edited), *e2 = slurp(fs.ex);
    struct stat s1, s2;
    bool same = e1 && e2 && !stat(edited, &s1) && !stat(fs.ex, &s2) && s1.st_size == s2.st_size &&
                !memcmp(e1, e2, (size_t)s1.st_size);
    CHECKF(rc == 0 && same, "the panel's export (status %d) %s the script's: %s", rc, e1 ? "differs from" : "did not write",
           text ? text : "(none)");
    free(e1), free(e2), free(text);
#endif
}

/* ---- mode gi ------------------------------------------------------------------------------ */

/* A pixel whose 5x5 neighbourhood differs from the background (pixel 0,0)
 * in every pixel: a hit well inside an object. */
static bool object_pixel(const char* png, uint32_t* ox, uint32_t* oy) {
    uint32_t w, h, c;
    void* px = NULL;
    if (vx_image_read(png, VX_IMAGE_U8, 0, &w, &h, &c, &px, NULL)) return false;
    const uint8_t* p = px;
    bool found = false;
    for (uint32_t y = 2; !found && y + 2 < h; y++)
        for (uint32_t x = 2; !found && x + 2 < w; x++) {
            bool all = true;
            for (int dy = -2; all && dy <= 2; dy++)
                for (int dx = -2; all && dx <= 2; dx++)
                    all = memcmp(p + ((size_t)(y + dy) * w + (x + dx)) * c, p, c) != 0;
            if (all) *ox = x, *oy = y, found = true;
        }
    vx_free(NULL, px);
    return found;
}

static void test_gi_mode(void) {
    if (!g_display) SKIP("no display (xvfb-run not found)");
    const char* in = vx_test_corpus("vox/ogt_test_groups.vox");
    if (!in) SKIP("corpus file vox/ogt_test_groups.vox not found");
    if (access(g_render, X_OK)) SKIP("svo_render is not built (%s)", g_render);
    char svo[1024], probes[1024], bad[1024], shard[1024], a[1024], b[1024], c[1024], s2[1024], log[1024];
    char script[1024];
    path(svo, sizeof svo, "gi.svo");
    path(probes, sizeof probes, "gi.probes");
    path(bad, sizeof bad, "bad.probes");
    path(shard, sizeof shard, "shard.probes");
    path(a, sizeof a, "view_gi.png");
    path(b, sizeof b, "render_gi.png");
    path(c, sizeof c, "view_gi_color.png");
    path(s2, sizeof s2, "view_gi_script.png");
    path(log, sizeof log, "gi.log");
    path(script, sizeof script, "gi.txt");
    /* a tiny bake through the probes API (CPU): what svo_bake --grid 2,2,2 --res 16 --spp 4 --cpu writes */
    vx_svo_scene s;
    REQUIRE(load_vox(in, &s));
    REQUIRE(vx_svo_write_file(NULL, &s, svo, NULL) == VX_OK);
    vx_probe_bake_desc bd = {.grid = {2, 2, 2}, .res = 16, .spp = 4, .seed = 1};
    vx_probe_set ps, part;
    vx_error err = {0};
    REQUIRE(vx_probe_bake(&s, &bd, &ps, &err) == VX_OK);
    REQUIRE(vx_probe_write_file(NULL, &ps, probes, &err) == VX_OK);
    bd.first = 0, bd.count = 4; /* half the grid: a shard, which the viewer must refuse */
    REQUIRE(vx_probe_bake(&s, &bd, &part, &err) == VX_OK);
    REQUIRE(vx_probe_write_file(NULL, &part, shard, &err) == VX_OK);
    vx_probe_set_free(&part);
    /* a truncated copy */
    uint8_t* bytes = NULL;
    size_t size = 0;
    REQUIRE(vx_probe_write(&ps, NULL, &bytes, &size, &err) == VX_OK);
    FILE* f = fopen(bad, "wb");
    REQUIRE(f);
    fwrite(bytes, 1, size / 2, f);
    fclose(f);
    vx_free(NULL, bytes);
    vx_probe_set_free(&ps);
    vx_svo_scene_free(&s);

    /* --screenshot in mode gi equals svo_render --mode gi */
    int rc = run_cmd("%s %s --probes %s --mode gi --screenshot %s --size 200x150 --hidden > /dev/null 2>&1", g_view, svo,
                     probes, a);
    REQUIRE(rc == 0);
    rc = run_cmd("%s %s %s --probes %s --mode gi --size 200x150 > /dev/null 2>&1", g_render, svo, b, probes);
    REQUIRE(rc == 0);
    double d = image_diff(a, b);
    CHECKF(d <= 0.01, "mode gi: %.2f%% of pixels differ from svo_render", d * 100);
    fprintf(stderr, "  mode gi: %.3f%% of pixels differ from svo_render\n", d * 100);
    /* mode lightfield too: the same GPU walk, seed and default rays per pixel */
    rc = run_cmd("%s %s --probes %s --mode lightfield --screenshot %s --size 200x150 --hidden > /dev/null 2>&1", g_view,
                 svo, probes, a);
    REQUIRE(rc == 0);
    rc = run_cmd("%s %s %s --probes %s --mode lightfield --size 200x150 > /dev/null 2>&1", g_render, svo, b, probes);
    REQUIRE(rc == 0);
    d = image_diff(a, b);
    CHECKF(d <= 0.01, "mode lightfield: %.2f%% of pixels differ from svo_render", d * 100);
    fprintf(stderr, "  mode lightfield: %.3f%% of pixels differ from svo_render\n", d * 100);
    rc = run_cmd("%s %s %s --probes %s --mode gi --size 200x150 > /dev/null 2>&1", g_render, svo, b, probes);
    REQUIRE(rc == 0);
    /* and it is not the colour mode (probes loaded, mode colour: nothing of gi) */
    rc = run_cmd("%s %s --probes %s --screenshot %s --size 200x150 --hidden > /dev/null 2>&1", g_view, svo, probes, c);
    REQUIRE(rc == 0);
    d = image_diff(a, c);
    CHECKF(d > 0.5, "mode gi differs from mode color in only %.2f%% of pixels", d * 100);

    /* a script: gi refused without probes and with bad ones (messages, the run goes on), then
     * loaded; a pick in mode gi finds what the colour mode's pick finds */
    uint32_t px = 0, py = 0;
    REQUIRE(object_pixel(b, &px, &py));
    char pick[64];
    snprintf(pick, sizeof pick, "pick %u %u", px, py);
    f = fopen(script, "w");
    REQUIRE(f);
    fprintf(f, "mode gi\nprobes %s\nprobes %s\nmode gi\n%s\nprobes %s\nmode gi\n%s\nscreenshot %s\nmode color\n%s\n"
               "open %s\nmode lightfield\nquit\n",
            bad, shard, pick, probes, pick, s2, pick, svo);
    fclose(f);
    rc = run_cmd("%s %s --script %s --hidden --size 200x150 > %s 2>&1", g_view, svo, script, log);
    char* out = slurp(log);
    CHECKF(rc == 0, "status %d: %s", rc, out ? out : "(none)");
    /* opening a scene unloads the probes of the previous one */
    const char* need[] = {"mode gi needs light field probes", "bad.probes:", "shard.probes: a shard", "2x2x2 grid",
                          "probes of the previous scene unloaded", "mode lightfield needs light field probes"};
    for (int i = 0; i < 6; i++) CHECKF(out && strstr(out, need[i]), "expected '%s' in:\n%s", need[i], out ? out : "(none)");
    /* three picks of one pixel (colour, gi, colour again) name one instance */
    uint32_t hits[3], nh = 0;
    for (const char* q = out; q && (q = strstr(q, pick)) && nh < 3; q += strlen(pick)) {
        unsigned id;
        if (sscanf(q + strlen(pick), ": instance %u", &id) == 1) hits[nh] = id;
        else hits[nh] = VX_RENDER_NO_HIT;
        nh++;
    }
    CHECKF(nh == 3 && hits[0] != VX_RENDER_NO_HIT && hits[0] == hits[1] && hits[1] == hits[2],
           "picks at %u,%u: %s", px, py, out ? out : "(none)");
    free(out);
    d = image_diff(s2, b);
    CHECKF(d <= 0.01, "scripted mode gi: %.2f%% of pixels differ from svo_render", d * 100);

    /* on the command line: usage error without probes, status 1 naming a bad file */
    CHECK(run_cmd("%s %s --mode gi --screenshot %s --hidden > /dev/null 2>&1", g_view, svo, a) == 2);
    rc = run_cmd("%s %s --probes %s --mode gi --screenshot %s --hidden > %s 2>&1", g_view, svo, bad, a, log);
    CHECKF(rc == 1, "status %d", rc);
    out = slurp(log);
    CHECKF(out && strstr(out, "bad.probes"), "message: %s", out ? out : "(none)");
    free(out);
    /* a misspelt gi method: named as unknown with the methods listed (not sent to the probes' gi) */
    rc = run_cmd("%s %s --passes gbuffer,direct,gi=cone --screenshot %s --hidden > %s 2>&1", g_view, svo, a, log);
    CHECKF(rc == 2, "status %d", rc);
    out = slurp(log);
    CHECKF(out && strstr(out, "unknown gi method 'cone' (probes, lightfield, pathtrace, photons, cones)"), "message: %s",
           out ? out : "(none)");
    free(out);

    /* --validate counts the layer's errors and prints the count */
    if (!validation_layer()) {
        fprintf(stderr, "  --validate: skipped (VK_LAYER_KHRONOS_validation is not installed or turned off)\n");
        return;
    }
    rc = run_cmd("%s %s --probes %s --mode gi --screenshot %s --size 64x48 --hidden --validate > %s 2>&1", g_view, svo,
                 probes, a, log);
    out = slurp(log);
    CHECKF(rc == 0 && out && strstr(out, "0 Vulkan validation errors"), "status %d: %s", rc, out ? out : "(none)");
    free(out);
}

/* The line of `text` that starts with `prefix` (after "svo_view: "), parsed by fmt. */
static int scan_line(const char* text, const char* prefix, const char* fmt, long long* v) {
    const char* p = text;
    while (p && (p = strstr(p, prefix))) {
        int n = sscanf(p, fmt, &v[0], &v[1], &v[2], &v[3], &v[4], &v[5]);
        if (n == 6) return n;
        p++;
    }
    return 0;
}

/* A click in voxel mode adds the cell in front of the face the pixel's ray
 * enters: picking the same pixel afterwards hits the new cell (the tracer's
 * own hit buffer), which was empty and is a face neighbour of the cell hit
 * before; removing it there gives the first hit back. */
static void test_vclick(void) {
    if (!g_display) SKIP("no display (xvfb-run not found)");
    vx_svo_scene s;
    make_scene(&s, 1);
    char in[1024], shot[1024], script[1024], log[1024];
    path(in, sizeof in, "gen_still.svo");
    path(shot, sizeof shot, "vclick_shot.png");
    path(script, sizeof script, "vclick.txt");
    path(log, sizeof log, "vclick.log");
    REQUIRE(vx_svo_write_file(NULL, &s, in, NULL) == VX_OK);
    REQUIRE(run_cmd("%s %s --screenshot %s --size 160x120 --hidden > %s 2>&1", g_view, in, shot, log) == 0);
    uint32_t bx, by;
    REQUIRE(object_pixel(shot, &bx, &by));
    FILE* f = fopen(script, "w");
    REQUIRE(f);
    fprintf(f, "pick %u %u\nvclick add %u %u\npick %u %u\nvclick remove %u %u\npick %u %u\nquit\n", bx, by, bx, by, bx, by,
            bx, by, bx, by);
    fclose(f);
    int rc = run_cmd("%s %s --script %s --hidden --size 160x120 > %s 2>&1", g_view, in, script, log);
    char* out = slurp(log);
    REQUIRE(out);
    CHECKF(rc == 0, "status %d: %s", rc, out);
    /* the three picks and the two edits, in order */
    long long p0[6], add[6], p1[6], rem[6], p2[6];
    const char* q[5];
    q[0] = strstr(out, "pick ");
    q[1] = q[0] ? strstr(q[0], "voxel add at") : NULL;
    q[2] = q[1] ? strstr(q[1], "pick ") : NULL;
    q[3] = q[2] ? strstr(q[2], "voxel remove at") : NULL;
    q[4] = q[3] ? strstr(q[3], "pick ") : NULL;
    bool ok = q[4] && scan_line(q[0], "pick ", "pick %lld %lld: instance %lld cell %lld %lld %lld", p0) &&
              scan_line(q[1], "voxel add", "voxel add at %lld %lld: instance %lld cell %lld %lld %lld", add) &&
              scan_line(q[2], "pick ", "pick %lld %lld: instance %lld cell %lld %lld %lld", p1) &&
              scan_line(q[3], "voxel remove", "voxel remove at %lld %lld: instance %lld cell %lld %lld %lld", rem) &&
              scan_line(q[4], "pick ", "pick %lld %lld: instance %lld cell %lld %lld %lld", p2);
    CHECKF(ok, "picks and edits not found in:\n%s", out);
    if (ok) {
        /* the target: empty before, a face neighbour of the first hit */
        long long d = llabs(add[3] - p0[3]) + llabs(add[4] - p0[4]) + llabs(add[5] - p0[5]);
        CHECKF(d == 1 && !gen_cell(add[3], add[4], add[5]) && gen_cell(p0[3], p0[4], p0[5]),
               "hit %lld %lld %lld, added %lld %lld %lld", p0[3], p0[4], p0[5], add[3], add[4], add[5]);
        /* cells below 0 shifted the model's cells by the overhang */
        long long sh[3];
        for (int k = 0; k < 3; k++) sh[k] = add[3 + k] < 0 ? -add[3 + k] : 0;
        CHECKF(p1[2] == p0[2] && p1[3] == add[3] + sh[0] && p1[4] == add[4] + sh[1] && p1[5] == add[5] + sh[2],
               "after the add the pixel hits %lld %lld %lld, expected the new cell", p1[3], p1[4], p1[5]);
        CHECK(rem[3] == p1[3] && rem[4] == p1[4] && rem[5] == p1[5]);
        CHECKF(p2[3] == p0[3] + sh[0] && p2[4] == p0[4] + sh[1] && p2[5] == p0[5] + sh[2],
               "after the remove the pixel hits %lld %lld %lld", p2[3], p2[4], p2[5]);
    }
    free(out);
    vx_svo_scene_free(&s);
}

int main(int argc, char** argv) {
    if (argc == 2 && !strcmp(argv[1], "--editor")) { /* the leak-checked part: no window, no driver */
        RUN(test_editor_ops);
        RUN(test_editor_voxels);
        RUN(test_editor_lights);
        RUN(test_editor_materials);
        RUN(test_editor_frames);
        RUN(test_editor_random);
        RUN(test_editor_incremental);
        RUN(test_editor_face);
        RUN(test_editor_undo_bounds);
        RUN(test_batch_policy);
        return vx_test_finish();
    }
    if (argc < 4) {
        fprintf(stderr, "usage: test_view SVO_VIEW SVO_RENDER WORKDIR\n");
        return 2;
    }
    g_view = argv[1], g_render = argv[2], g_dir = argv[3];
    mkdir(g_dir, 0755);
    if (!getenv("DISPLAY") && !getenv("VX_TEST_VIEW_XVFB")) {
        if (system("command -v xvfb-run > /dev/null 2>&1") == 0) {
            setenv("VX_TEST_VIEW_XVFB", "1", 1);
            char* args[8] = {"xvfb-run", "-a", argv[0], argv[1], argv[2], argv[3], argc >= 5 ? argv[4] : NULL, NULL};
            execvp("xvfb-run", args);
        }
    }
    g_display = getenv("DISPLAY") != NULL;
    if (argc >= 5 && !strcmp(argv[4], "script")) { /* the long script tests, a ctest of their own */
        RUN(test_scripted_random);
        RUN(test_scripted_vox_compare);
        RUN(test_scripted_instances_gpu);
        RUN(test_gpu_present);
        RUN(test_batch_present);
        RUN(test_probe_panel);
        return vx_test_finish();
    }
    if (argc >= 5 && !strcmp(argv[4], "gi")) { /* svo_view's GI frames against svo_render's, a ctest of their own */
        RUN(test_scripted_lights_gi);
        RUN(test_photons_view);
        RUN(test_scripted_materials_gi);
        RUN(test_gi_mode);
        return vx_test_finish();
    }
    RUN(test_scripted_edit);
    RUN(test_scripted_light_undo);
    RUN(test_ui_panels);
    RUN(test_scripted_voxels);
    RUN(test_scripted_face);
    RUN(test_vclick);
    RUN(test_screenshot_matches_svo_render);
    RUN(test_pick_matches_hits);
    RUN(test_bad_files);
    RUN(test_script_failures);
    RUN(test_script_new_colour);
    RUN(test_script_hidden_layer);
    RUN(test_script_export_split);
    RUN(test_script_save_sky_map);
    RUN(test_script_sky);
    RUN(test_script_sky_frame);
    RUN(test_script_export_quantize);
    RUN(test_script_export_glb_vdb);
    return vx_test_finish();
}
