/* tests/render/test_render_edit.c - vx_render_scene_update_model against a
 * render scene made from scratch: a scene of two models (a palette model
 * drawn by two instances, a geometry-only one) is edited through
 * vx_svo_editor (svo/edit.h) with random boxes and balls (add, remove,
 * recolour, growth past the model's size and depth), and after each stroke
 * the GPU scene is updated with only the appended words and records; its
 * frame (instance, cell and colour of every pixel) must equal the frame of
 * a scene created from the compacted models (vx_svo_model_compact: the
 * builder's model of the same cells), which walks their octrees. Also after an undo and a redo
 * (headers restored, nothing uploaded), after a stroke made after the undo,
 * and on a scene created while the model was undone (the words it never
 * received are uploaded). The strokes append more words than the buffers'
 * headroom, so regions move and buffers grow. The same with grids asked for
 * (render_scene.c regrid: each stroke's model gets its grid made again, in
 * its place or, grown, after the others): the grid walk against the
 * reference's octree walk, ties at one t allowed. Lavapipe; skipped without
 * a Vulkan device. */
#include <dlfcn.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "render/render.h"
#include "render/testing.h"
#include "svo/edit.h"
#include "tests/test.h"
#include "tests/gpu_test.h"

static vx_gpu* gpu;
static const char* gpu_skip;

static uint64_t rng = 0x2545F4914F6CDD1Dull;
static uint32_t rnd(uint32_t n) {
    rng ^= rng << 13, rng ^= rng >> 7, rng ^= rng << 17;
    return (uint32_t)(rng % n);
}

#define W 112
#define H 84

/* A 40^3 palette model (a ball with a hole and colour bands; with small,
 * only its cells in [2, 10)^3) and a 24^3 geometry-only slab; model 0 drawn
 * twice (once turned). */
static void make_scene(vx_svo_scene* s, bool small) {
    vx_svo_scene_init(s, NULL);
    s->models = vx_calloc(NULL, 2, sizeof *s->models);
    s->instances = vx_calloc(NULL, 3, sizeof *s->instances);
    REQUIRE(s->models && s->instances);
    s->model_count = 2, s->instance_count = 3;
    static uint64_t keys[40 * 40 * 40];
    static uint8_t pal[40 * 40 * 40];
    size_t n = 0;
    for (uint32_t z = 0; z < 40; z++)
        for (uint32_t y = 0; y < 40; y++)
            for (uint32_t x = 0; x < 40; x++) {
                double dx = x - 19.5, dy = y - 19.5, dz = z - 19.5, r2 = dx * dx + dy * dy + dz * dz;
                bool in = !small || (x >= 2 && x < 10 && y >= 2 && y < 10 && z >= 2 && z < 10);
                if (in && r2 < 19 * 19 && !(r2 < 8 * 8 && x > 20)) keys[n] = vx_svo_morton(x, y, z), pal[n++] = (uint8_t)(1 + (z / 5) % 6);
            }
    vx_svo_voxels v = {.size = {40, 40, 40}, .count = n, .keys = keys, .attrs = VX_ATTR_PALETTE, .palette = pal};
    REQUIRE(vx_svo_build_model(&(vx_svo_build_desc){0}, &v, &s->models[0], NULL, NULL) == VX_OK);
    n = 0;
    for (uint32_t z = 0; z < 6; z++)
        for (uint32_t y = 0; y < 24; y++)
            for (uint32_t x = 0; x < 24; x++)
                if ((x ^ y) & 4) keys[n++] = vx_svo_morton(x, y, z);
    vx_svo_voxels g = {.size = {24, 24, 6}, .count = n, .keys = keys};
    REQUIRE(vx_svo_build_model(&(vx_svo_build_desc){0}, &g, &s->models[1], NULL, NULL) == VX_OK);
    static const double x0[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    static const double x1[12] = {0, -1, 0, 110, 1, 0, 0, 0, 0, 0, 1, 4};
    static const double x2[12] = {1, 0, 0, 20, 0, 1, 0, -40, 0, 0, 1, 0};
    memcpy(s->instances[0].xform, x0, sizeof x0);
    memcpy(s->instances[1].xform, x1, sizeof x1);
    memcpy(s->instances[2].xform, x2, sizeof x2);
    s->instances[0].model = s->instances[1].model = 0;
    s->instances[2].model = 1;
    for (uint32_t i = 0; i < 3; i++) s->instances[i].layer = UINT32_MAX;
    s->has_palette = true;
    for (uint32_t i = 1; i < 256; i++) s->palette[i] = 0xFF000000u | (i * 0x00294F83u & 0x00FFFFFFu);
    vx_svo_scene_update_bounds(s);
}

static vx_render_desc view(void) {
    vx_render_desc d = {.width = W, .height = H, .want_hits = true};
    d.camera = (vx_render_camera){.set = true, .eye = {-20, -75, 85}, .target = {45, 5, 15}};
    return d;
}

/* The frame of rs against the frame of a scene made from scratch from the
 * compacted models of s: pixels whose instance, cell or colour differ. */
static size_t frame_diff_ties(vx_render_scene* rs, const vx_svo_scene* s, size_t* hits, size_t* ties) {
    vx_svo_scene c = *s;
    vx_svo_model cm[2] = {0};
    c.models = cm;
    vx_error err = {0};
    size_t bad = SIZE_MAX;
    if (s->model_count > 2) return SIZE_MAX;
    for (uint32_t i = 0; i < s->model_count; i++)
        if (vx_svo_model_compact(NULL, &s->models[i], &cm[i], &err)) {
            fprintf(stderr, "compact: %s\n", err.msg);
            for (uint32_t j = 0; j < i; j++) vx_svo_model_free(NULL, &cm[j]);
            return SIZE_MAX;
        }
    vx_render_scene* ref = NULL;
    vx_render_image a = {0}, b = {0};
    vx_render_desc d = view();
    /* the reference walks the octrees on every device (a GPU builds grids by default) */
    vx_render_scene_desc rd = {.grid_budget = VX_RENDER_NO_GRID};
    if (vx_render_scene_create_ex(gpu, &c, &rd, &ref, &err) || vx_render_frame(rs, &d, &a, &err) ||
        vx_render_frame(ref, &d, &b, &err)) {
        fprintf(stderr, "frame: %s\n", err.msg);
    } else {
        bad = 0, *hits = 0;
        if (ties) *ties = 0;
        for (size_t i = 0; i < (size_t)W * H; i++) {
            const vx_render_hit *p = &a.hits[i], *q = &b.hits[i];
            *hits += p->instance != VX_RENDER_NO_HIT;
            bool same = p->instance == q->instance && (p->instance == VX_RENDER_NO_HIT || !memcmp(p->cell, q->cell, sizeof p->cell));
            same = same && !memcmp(&a.pixels[4 * i], &b.pixels[4 * i], 4 * sizeof(float));
            /* with ties: two walks (the grid's and the octree's) may round a ray's crossing apart by an ulp or two
             * where it meets two cells at one point (an edge, or the coincident faces of the two instances of
             * model 0): another cell at the same t (within 1e-5 of t: a cell is 1 unit, t 50-200 here) is a tie */
            if (!same && ties && p->instance != VX_RENDER_NO_HIT && q->instance != VX_RENDER_NO_HIT &&
                fabsf(p->t - q->t) <= 1e-5f * q->t) {
                ++*ties;
                continue;
            }
            if (!same && bad < 3)
                fprintf(stderr, "  pixel %zu,%zu: instance %d cell %u,%u,%u t %.9g vs %d %u,%u,%u t %.9g\n", i % W, i / W,
                        (int)p->instance, p->cell[0], p->cell[1], p->cell[2], p->t, (int)q->instance, q->cell[0],
                        q->cell[1], q->cell[2], q->t);
            bad += !same;
        }
    }
    vx_render_image_free(&a);
    vx_render_image_free(&b);
    vx_render_scene_destroy(ref);
    for (uint32_t i = 0; i < s->model_count; i++) vx_svo_model_free(NULL, &cm[i]);
    return bad;
}

static size_t frame_diff(vx_render_scene* rs, const vx_svo_scene* s, size_t* hits) {
    return frame_diff_ties(rs, s, hits, NULL);
}

/* frame_diff where grids (the grid walk against the reference's octree
 * walk): ties allowed, at most 2% of the hits (more count as differing
 * pixels; 20-26 pixels of 9,408 in this test's frames, most where
 * model 0's two instances have grown into each other); the most in one
 * frame kept in *most_ties. */
static size_t grid_diff(vx_render_scene* rs, const vx_svo_scene* s, size_t* hits, bool grids, size_t* most_ties) {
    size_t ties = 0, bad = frame_diff_ties(rs, s, hits, grids ? &ties : NULL);
    if (ties > *most_ties) *most_ties = ties;
    return bad == SIZE_MAX ? bad : bad + (ties > *hits / 50 ? ties : 0);
}

/* One random stroke on model mi: a box or ball of writes (set with a
 * palette colour, clear, or recolour the set cells), sometimes past the
 * model's size. */
static bool stroke(vx_svo_editor* e, const vx_svo_model* m, bool palette, int64_t grow_x, vx_svo_edit_stats* st) {
    static vx_svo_cell_write w[25 * 25 * 25];
    size_t n = 0;
    int r = 3 + (int)rnd(10), op = grow_x > 0 ? 0 : (int)rnd(3), ball = (int)rnd(2), noise = (int)rnd(4) != 0;
    int64_t c[3];
    for (int k = 0; k < 3; k++) c[k] = rnd(m->size[k]);
    if (grow_x > 0) c[0] = grow_x; /* an add centred there */
    vx_svo_cell v = {.palette = (uint8_t)(1 + rnd(9))};
    for (int dz = -r; dz <= r; dz++)
        for (int dy = -r; dy <= r; dy++)
            for (int dx = -r; dx <= r; dx++) {
                if (ball && dx * dx + dy * dy + dz * dz > r * r) continue;
                int64_t p[3] = {c[0] + dx, c[1] + dy, c[2] + dz};
                if (p[0] < 0 || p[1] < 0 || p[2] < 0) continue;
                vx_svo_cell old;
                bool set = vx_svo_editor_get(e, (uint32_t)p[0], (uint32_t)p[1], (uint32_t)p[2], &old);
                if (op == 2 && (!set || !palette)) continue; /* recolour: the set cells */
                /* half the strokes one colour, half noise (few shared blocks: many words) */
                if (noise) v.palette = (uint8_t)(1 + rnd(9));
                w[n++] = (vx_svo_cell_write){.x = (uint32_t)p[0], .y = (uint32_t)p[1], .z = (uint32_t)p[2],
                                             .set = op != 1, .value = v};
            }
    vx_error err = {0};
    vx_result res = vx_svo_editor_apply(e, w, n, st, &err);
    if (res) fprintf(stderr, "apply: %s\n", err.msg);
    return res == VX_OK;
}

/* With grids (the grid walk; asked for, as every device's default): each
 * edited model's grid is made again (render_scene.c regrid), in its place or
 * after the others as it grows, and the frames must still equal the
 * reference's, which walks the compacted models' octrees. */
static void update_model(bool grids) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene s;
    make_scene(&s, false);
    vx_error err = {0};
    vx_svo_editor *e0 = NULL, *e1 = NULL;
    REQUIRE(vx_svo_editor_create(&(vx_svo_editor_desc){0}, &s.models[0], &e0, &err) == VX_OK);
    REQUIRE(vx_svo_editor_create(&(vx_svo_editor_desc){0}, &s.models[1], &e1, &err) == VX_OK);
    vx_render_scene* rs = NULL;
    vx_render_scene_desc sd = {.grid_budget = grids ? VX_RENDER_GRID_BUDGET : VX_RENDER_NO_GRID};
    REQUIRE(vx_render_scene_create_ex(gpu, &s, &sd, &rs, &err) == VX_OK);
    CHECK(vx__render_scene_grid_models(rs) == (grids ? 2u : 0u));
    size_t most_ties = 0;
#define DIFF(r, sc, h) grid_diff((r), (sc), (h), grids, &most_ties)
    vx_render_layout_info li0 = {0};
    vx_render_scene_layout(rs, &li0);
    size_t hits = 0, bad = DIFF(rs, &s, &hits);
    CHECKF(bad == 0 && hits > (size_t)W * H / 10, "before the edits: %zu pixels differ, %zu hits", bad, hits);
    uint64_t w0 = (uint64_t)s.models[0].node_count + s.models[1].node_count, appended = 0;
    vx_svo_model_header undo_to = {0}, redo_to = {0};
    uint32_t strokes = 200;
    for (uint32_t k = 0; k < strokes; k++) {
        uint32_t mi = k % 5 == 4 ? 1 : 0;
        if (k == 80) undo_to = vx_svo_model_header_get(&s.models[0]);
        vx_svo_edit_stats st;
        /* strokes 10 and 120 add past x = size (120: past 64 cells, one level deeper) */
        int64_t gx = k == 10 ? s.models[0].size[0] + 3 : k == 120 ? 68 : 0;
        REQUIRE(stroke(mi ? e1 : e0, &s.models[mi], mi == 0, gx, &st));
        appended += st.words_added;
        REQUIRE(vx_render_scene_update_model(rs, &s, mi, st.words_from, st.records_from, &err) == VX_OK);
        /* the grids made again after every stroke (both models' grids are far under regrid's limit) */
        CHECKF(vx__render_scene_grid_models(rs) == (grids ? 2u : 0u), "stroke %u: %u models walk a grid", k,
               vx__render_scene_grid_models(rs));
        if (k % 8 == 0 || k == 10 || k >= 118) {
            bad = DIFF(rs, &s, &hits);
            CHECKF(bad == 0, "stroke %u (model %u, %llu words appended, size %u%s): %zu pixels differ", k, mi,
                   (unsigned long long)st.words_added, s.models[mi].size[0], grids ? ", grids" : "", bad);
        }
    }
    vx_render_scene_stats rst;
    vx_render_scene_get_stats(rs, &rst);
    vx_render_layout_info li = {0};
    vx_render_scene_layout(rs, &li);
    printf("%s: %u grids made again, grid bytes %llu -> %llu\n", grids ? "grids" : "octrees", rst.grids_rebuilt,
           (unsigned long long)li0.grid_bytes, (unsigned long long)li.grid_bytes);
    CHECK(rst.grids_rebuilt == (grids ? strokes : 0u));
    /* the growth past 64 cells (stroke 120) made a grid larger than its place: the buffer grew */
    CHECK(!grids || li.grid_bytes > li0.grid_bytes);
    printf("%u strokes appended %llu node words to %llu (model 0 now %u words, depth %u)\n", strokes,
           (unsigned long long)appended, (unsigned long long)w0, s.models[0].node_count, s.models[0].depth);
    CHECKF(appended > w0 / 16 + 65536, "the strokes did not exceed the headroom (%llu words)", (unsigned long long)appended);
    CHECK(s.models[0].depth == 7);
    /* undo model 0 to before stroke 80 (its size and depth too), then redo */
    redo_to = vx_svo_model_header_get(&s.models[0]);
    vx_svo_model_header_set(&s.models[0], &undo_to);
    REQUIRE(vx_render_scene_update_model(rs, &s, 0, UINT32_MAX, UINT32_MAX, &err) == VX_OK);
    bad = DIFF(rs, &s, &hits);
    CHECKF(bad == 0, "after the undo: %zu pixels differ", bad);
    /* a scene made now holds only the undone model's words; the redo brings the rest */
    vx_render_scene* rs2 = NULL;
    REQUIRE(vx_render_scene_create_ex(gpu, &s, &sd, &rs2, &err) == VX_OK);
    vx_svo_model_header_set(&s.models[0], &redo_to);
    REQUIRE(vx_render_scene_update_model(rs, &s, 0, UINT32_MAX, UINT32_MAX, &err) == VX_OK);
    REQUIRE(vx_render_scene_update_model(rs2, &s, 0, UINT32_MAX, UINT32_MAX, &err) == VX_OK);
    bad = DIFF(rs, &s, &hits);
    CHECKF(bad == 0, "after the redo: %zu pixels differ", bad);
    bad = DIFF(rs2, &s, &hits);
    CHECKF(bad == 0, "after the redo, scene made while undone: %zu pixels differ", bad);
    /* undo again and edit: the stroke's words go after every earlier append */
    vx_svo_model_header_set(&s.models[0], &undo_to);
    REQUIRE(vx_render_scene_update_model(rs, &s, 0, UINT32_MAX, UINT32_MAX, &err) == VX_OK);
    vx_svo_edit_stats st;
    REQUIRE(stroke(e0, &s.models[0], true, 0, &st));
    CHECK(st.words_from >= redo_to.node_count);
    REQUIRE(vx_render_scene_update_model(rs, &s, 0, st.words_from, st.records_from, &err) == VX_OK);
    bad = DIFF(rs, &s, &hits);
    CHECKF(bad == 0, "a stroke after the undo: %zu pixels differ", bad);
    /* bad arguments */
    CHECK(vx_render_scene_update_model(rs, &s, 2, 0, 0, &err) == VX_ERR_INVALID_ARG);
    CHECK(vx_render_scene_update_model(NULL, &s, 0, 0, 0, &err) == VX_ERR_INVALID_ARG);
    CHECK(vx_gpu_validation_errors(gpu) == 0);
#undef DIFF
    if (grids) printf("grids: at most %zu pixels of a frame at a tie\n", most_ties);
    vx_render_scene_destroy(rs);
    vx_render_scene_destroy(rs2);
    vx_svo_editor_destroy(e0);
    vx_svo_editor_destroy(e1);
    vx_svo_scene_free(&s);
}

static void test_update_model(void) { update_model(false); }
static void test_update_model_grids(void) { update_model(true); }

/* Writes setting every cell of the box [lo, hi) to palette entry pal into
 * w; returns their count. */
static size_t box_writes(vx_svo_cell_write* w, const uint32_t lo[3], const uint32_t hi[3], uint8_t pal) {
    size_t n = 0;
    for (uint32_t z = lo[2]; z < hi[2]; z++)
        for (uint32_t y = lo[1]; y < hi[1]; y++)
            for (uint32_t x = lo[0]; x < hi[0]; x++)
                w[n++] = (vx_svo_cell_write){.x = x, .y = y, .z = z, .set = true, .value = {.palette = pal}};
    return n;
}

/* Cells added outside a model's cells' box (inside its size): the
 * instances' boxes (the BVH's) are its cells' box, so the update must make
 * them again, or the new cells are culled. With grids, the same for the
 * grid's header (the box the walk clips to, and the cube the grid covers:
 * model 0's 8^3 cells in a 2^6 cube make the scene lay its grids over their
 * cells' cubes, GRID_CUBE). */
static void update_past_cells(bool grids) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene s;
    make_scene(&s, true);
    vx_error err = {0};
    vx_svo_editor* e0 = NULL;
    REQUIRE(vx_svo_editor_create(&(vx_svo_editor_desc){0}, &s.models[0], &e0, &err) == VX_OK);
    vx_render_scene* rs = NULL;
    vx_render_scene_desc sd = {.grid_budget = grids ? VX_RENDER_GRID_BUDGET : VX_RENDER_NO_GRID};
    REQUIRE(vx_render_scene_create_ex(gpu, &s, &sd, &rs, &err) == VX_OK);
    size_t most_ties = 0, hits0 = 0, hits = 0, bad = grid_diff(rs, &s, &hits0, grids, &most_ties);
    CHECKF(bad == 0, "before the edit: %zu pixels differ", bad);
    /* a block at the model's far corner, inside its size */
    static vx_svo_cell_write w[12 * 12 * 12];
    size_t n = box_writes(w, (const uint32_t[3]){26, 26, 26}, (const uint32_t[3]){38, 38, 38}, 3);
    vx_svo_edit_stats st;
    REQUIRE(vx_svo_editor_apply(e0, w, n, &st, &err) == VX_OK);
    CHECK(s.models[0].size[0] == 40);
    REQUIRE(vx_render_scene_update_model(rs, &s, 0, st.words_from, st.records_from, &err) == VX_OK);
    CHECK(vx__render_scene_grid_models(rs) == (grids ? 2u : 0u));
    bad = grid_diff(rs, &s, &hits, grids, &most_ties);
    CHECKF(bad == 0 && hits > hits0, "after the edit%s: %zu pixels differ, %zu hits (%zu before)", grids ? " (grids)" : "",
           bad, hits, hits0);
    CHECK(vx_gpu_validation_errors(gpu) == 0);
    vx_render_scene_destroy(rs);
    vx_svo_editor_destroy(e0);
    vx_svo_scene_free(&s);
}

/* A grid over its cells' cube (render/grid.h vx__grid_cube; GRID_CUBE) made
 * again: a 2^8 model whose cells are an 8^3 block at 40 (its grid over a 2^3
 * cube at 40, where the model's cube would take a 32^3 root), then a block
 * added at (60, 20, 10): the cube is now 2^6 from (40, 16, 8). Its frames
 * against the octree walk's after each step, the new block's hits seen. */
static void test_update_grid_cube(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene s;
    vx_svo_scene_init(&s, NULL);
    s.models = vx_calloc(NULL, 1, sizeof *s.models);
    s.instances = vx_calloc(NULL, 1, sizeof *s.instances);
    REQUIRE(s.models && s.instances);
    s.model_count = 1, s.instance_count = 1;
    uint64_t keys[512];
    uint8_t pal[512];
    size_t n = 0;
    for (uint32_t z = 40; z < 48; z++)
        for (uint32_t y = 40; y < 48; y++)
            for (uint32_t x = 40; x < 48; x++) keys[n] = vx_svo_morton(x, y, z), pal[n++] = (uint8_t)(1 + (x + y + z) % 5);
    vx_svo_voxels v = {.size = {256, 256, 256}, .count = n, .keys = keys, .attrs = VX_ATTR_PALETTE, .palette = pal};
    REQUIRE(vx_svo_build_model(&(vx_svo_build_desc){0}, &v, &s.models[0], NULL, NULL) == VX_OK);
    static const double x0[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    memcpy(s.instances[0].xform, x0, sizeof x0);
    s.instances[0].layer = UINT32_MAX;
    s.has_palette = true;
    for (uint32_t i = 1; i < 256; i++) s.palette[i] = 0xFF000000u | (i * 0x00294F83u & 0x00FFFFFFu);
    vx_svo_scene_update_bounds(&s);
    vx_error err = {0};
    vx_render_scene* rs = NULL;
    vx_render_scene_desc sd = {.grid_budget = VX_RENDER_GRID_BUDGET};
    REQUIRE(vx_render_scene_create_ex(gpu, &s, &sd, &rs, &err) == VX_OK);
    vx_render_layout_info li = {0};
    vx_render_scene_layout(rs, &li);
    CHECKF(li.grid_models == 1 && li.grid_cubes == 1, "%u grids, %u over their cells' cubes", li.grid_models, li.grid_cubes);
    size_t most_ties = 0, hits0 = 0, hits = 0, bad = grid_diff(rs, &s, &hits0, true, &most_ties);
    CHECKF(bad == 0 && hits0 > 0, "before the edit: %zu pixels differ, %zu hits", bad, hits0);
    vx_svo_editor* e = NULL;
    REQUIRE(vx_svo_editor_create(&(vx_svo_editor_desc){0}, &s.models[0], &e, &err) == VX_OK);
    static vx_svo_cell_write w[6 * 6 * 6];
    n = box_writes(w, (const uint32_t[3]){60, 20, 10}, (const uint32_t[3]){66, 26, 16}, 7);
    vx_svo_edit_stats st;
    REQUIRE(vx_svo_editor_apply(e, w, n, &st, &err) == VX_OK);
    REQUIRE(vx_render_scene_update_model(rs, &s, 0, st.words_from, st.records_from, &err) == VX_OK);
    CHECK(vx__render_scene_grid_models(rs) == 1);
    bad = grid_diff(rs, &s, &hits, true, &most_ties);
    CHECKF(bad == 0 && hits > hits0, "after the edit: %zu pixels differ, %zu hits (%zu before)", bad, hits, hits0);
    CHECK(vx_gpu_validation_errors(gpu) == 0);
    vx_render_scene_destroy(rs);
    vx_svo_editor_destroy(e);
    vx_svo_scene_free(&s);
}

static void test_update_past_cells(void) { update_past_cells(false); }
static void test_update_past_cells_grids(void) { update_past_cells(true); }

/* The node buffer holds the descriptors a model's walk reaches in the GPU
 * form (render_scene.c, issue 21: the low byte the inner mask), the other
 * words as the model has them. A scene made while model 0's root is its
 * octant-0 child (one level less, its other subtrees unreachable, so never
 * turned) and updated with the whole model's header and nothing appended
 * (a redo that reaches words no earlier root reached) must turn and upload
 * those words below words_from; and a descriptor that points outside its
 * model's words is refused at the upload, not traced. */
static void test_update_gpu_form(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene s;
    make_scene(&s, false);
    vx_svo_model* m = &s.models[0];
    vx_svo_model_header whole = vx_svo_model_header_get(m), part = whole;
    /* the root's octant-0 child: its children's block's first inner descriptor */
    uint32_t rd = m->nodes[m->root];
    uint32_t inner = vx_svo_desc_valid(rd) & ~vx_svo_desc_leaf(rd);
    REQUIRE(m->depth == 6 && (inner & 1u) && !vx_svo_desc_far(rd));
    part.root = m->root - vx_svo_desc_ptr(rd);
    part.depth = m->depth - 1;
    for (int k = 0; k < 3; k++) part.size[k] = 32;
    REQUIRE(m->attrs); /* the child's coarse record: octant 0's attribute of the root's block */
    uint32_t ablk = m->root - vx_svo_desc_ptr(rd) + (uint32_t)__builtin_popcount(inner);
    part.root_attr = m->nodes[ablk];
    part.voxel_count = 0; /* make_scene's cells in [0, 32)^3 */
    for (uint32_t z = 0; z < 32; z++)
        for (uint32_t y = 0; y < 32; y++)
            for (uint32_t x = 0; x < 32; x++) {
                double dx = x - 19.5, dy = y - 19.5, dz = z - 19.5, r2 = dx * dx + dy * dy + dz * dz;
                part.voxel_count += r2 < 19 * 19 && !(r2 < 8 * 8 && x > 20);
            }
    vx_svo_model_header_set(m, &part);
    vx_svo_scene_update_bounds(&s);
    vx_error err = {0};
    vx_render_scene* rs = NULL;
    REQUIRE(vx_render_scene_create(gpu, &s, &rs, &err) == VX_OK);
    size_t hits = 0, hits0 = 0, bad = frame_diff(rs, &s, &hits0);
    CHECKF(bad == 0 && hits0 > 0, "octant 0 as the root: %zu pixels differ, %zu hits", bad, hits0);
    vx_svo_model_header_set(m, &whole);
    vx_svo_scene_update_bounds(&s);
    REQUIRE(vx_render_scene_update_model(rs, &s, 0, m->node_count, m->attr_count, &err) == VX_OK);
    bad = frame_diff(rs, &s, &hits);
    CHECKF(bad == 0 && hits > hits0, "the whole model after the update: %zu pixels differ, %zu hits (%zu before)", bad,
           hits, hits0);
    CHECK(vx_gpu_validation_errors(gpu) == 0);
    vx_render_scene_destroy(rs);
    /* a root whose children's block would start before word 0 */
    uint32_t saved = m->nodes[m->root];
    m->nodes[m->root] = vx_svo_desc_make(m->root + 1, false, vx_svo_desc_valid(saved), vx_svo_desc_leaf(saved));
    rs = NULL;
    vx_render_scene_desc sd = {.grid_budget = VX_RENDER_NO_GRID}; /* the octrees' GPU form (a GPU builds grids) */
    vx_result r = vx_render_scene_create_ex(gpu, &s, &sd, &rs, &err);
    CHECKF(r == VX_ERR_BAD_FORMAT && strstr(err.msg, "model 0") && !rs, "bad pointer: result %d, %s", (int)r, err.msg);
    vx_render_scene_destroy(rs);
    m->nodes[m->root] = saved;
    vx_svo_scene_free(&s);
}

int main(void) {
    /* as in test_render_gpu.c: pinned driver and layer keep their frames
     * symbolised for tests/render/lsan.supp */
    gpu_skip = vx_test_gpu_open((vx_gpu_desc){0}, true, &gpu);
    RUN(test_update_model);
    RUN(test_update_model_grids);
    RUN(test_update_past_cells);
    RUN(test_update_past_cells_grids);
    RUN(test_update_grid_cube);
    RUN(test_update_gpu_form);
    if (gpu) vx_gpu_destroy(gpu);
    return vx_test_finish();
}
