/* tests/render/test_compact.c - the compact GPU layout (render/compact.h)
 * against the model's own voxel list: vx_svo_decode_model walks the .svo tree
 * (an independent path) and gives every cell in Morton order with its
 * attribute record; the compact walk must find each cell at its rank with
 * the same colour, and find no cell the list lacks. The CPU traversal of
 * the layout (vx_compact_render_cpu) must give vx_render_cpu's instance,
 * cell, depth and colour for every pixel of several views of each scene:
 * the reference reads the decoded voxels, never the compact arrays. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "convert/convert.h"
#include "render/compact.h"
#include "tests/render/scenes.h"
#include "tests/test.h"
#include "tests/test_vox.h"
#ifdef VX_TEST_HAVE_MESH
#include "convert/mesh.h"
#endif

typedef struct walk {
    const vx_compact_scene* c;
    const vx_svo_scene* s;
    const vx_svo_model* m;
    uint32_t mi, next, bad;
    uint64_t* keys; /* Morton keys in decode order */
} walk;

static bool check_cell(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    walk* w = user;
    uint32_t idx = UINT32_MAX;
    bool ok = vx_compact_lookup(w->c, w->mi, x, y, z, &idx) && idx == w->next &&
              vx_compact_rgba(w->c, w->mi, idx) == vx_svo_attr_rgba(w->s, w->m, attr);
    if (!ok && w->bad++ < 5)
        fprintf(stderr, "  model %u cell (%u %u %u): rank %u, lookup %u, colour %08x, expected %08x\n", w->mi, x, y, z,
                w->next, idx, vx_compact_rgba(w->c, w->mi, idx), vx_svo_attr_rgba(w->s, w->m, attr));
    w->keys[w->next++] = vx_svo_morton(x, y, z);
    return true;
}

/* The cells among the sorted keys below key k. */
static uint32_t keys_below(const uint64_t* keys, uint32_t n, uint64_t k) {
    uint32_t lo = 0, hi = n;
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (keys[mid] < k) lo = mid + 1;
        else hi = mid;
    }
    return lo;
}

/* position of key in the sorted keys, or -1 */
static int64_t find_key(const uint64_t* keys, uint32_t n, uint64_t k) {
    uint32_t lo = keys_below(keys, n, k);
    return lo < n && keys[lo] == k ? (int64_t)lo : -1;
}

/* The level-3 records (vx__compact_level3_records) against the cells: field
 * o - 1 of a level-3 node's record is the cells from the node's first to its
 * octant o's first in Morton order (an aligned cube's cells are contiguous
 * there), counted in the model's decoded keys, not in the layout. */
typedef struct rec_check {
    const vx_compact_scene* c;
    const uint32_t* rec;
    uint32_t first, count, n;
    const uint64_t* keys;
    uint32_t checked, wrong;
} rec_check;
static void rec_node(rec_check* rc, uint32_t slot, uint32_t L, uint32_t x, uint32_t y, uint32_t z) {
    const uint32_t* sl = rc->c->geom + 2 * (size_t)slot;
    uint32_t leaf = sl[0] & 0xFFu, inner = (sl[0] >> 8) & ~leaf & 0xFFu;
    if (L == 3) {
        rc->checked++;
        if (slot < rc->first || slot - rc->first >= rc->count) {
            rc->wrong++;
            return;
        }
        uint64_t v = rc->rec[2 * (size_t)(slot - rc->first)] | (uint64_t)rc->rec[2 * (size_t)(slot - rc->first) + 1] << 32;
        uint64_t base = vx_svo_morton(x, y, z);
        uint32_t b0 = keys_below(rc->keys, rc->n, base), bad = 0;
        for (uint32_t o = 1; o < 8; o++)
            bad += ((v >> (9 * (o - 1))) & 0x1FFu) != keys_below(rc->keys, rc->n, base + 64ull * o) - b0;
        rc->wrong += bad != 0;
        return;
    }
    for (uint32_t o = 0, k = 0; o < 8; o++) {
        if (!((inner >> o) & 1u)) continue;
        uint32_t s = L - 1;
        rec_node(rc, vx__compact_child(rc->c, L, sl[1], k++), s, x + ((o & 1u) << s), y + (((o >> 1) & 1u) << s),
                 z + (((o >> 2) & 1u) << s));
    }
}

/* Every cell of every model, and cells around them and at random, with the
 * bricks in their blocks (kept in *keep) and in the brick dictionary. */
static void check_scene_bricks(const vx_svo_scene* s, const char* name, uint32_t block, uint32_t bricks,
                               vx_compact_scene* keep);
static void check_scene(const vx_svo_scene* s, const char* name, uint32_t block, vx_compact_scene* keep) {
    check_scene_bricks(s, name, block, VX_COMPACT_BRICKS_INLINE, keep);
    check_scene_bricks(s, name, block, VX_COMPACT_BRICKS_DICT, NULL);
}
static void check_scene_bricks(const vx_svo_scene* s, const char* name, uint32_t block, uint32_t bricks,
                               vx_compact_scene* keep) {
    vx_compact_desc d = vx_compact_desc_defaults();
    d.block = block;
    d.bricks = bricks;
    vx_compact_scene c;
    vx_error err = {0};
    vx_result r = vx_compact_build(&d, s, &c, &err);
    CHECKF(r == VX_OK, "%s: %s", name, err.msg);
    if (r) return;
    uint64_t voxels = 0;
    uint32_t bad_total = 0, rng = 12345;
    rec_check rc = {.c = &c};
    uint32_t* rec = NULL;
    CHECKF(vx__compact_level3_records(&c, NULL, &rec, &rc.first, &rc.count, &err) == VX_OK, "%s: %s", name, err.msg);
    rc.rec = rec;
    for (uint32_t mi = 0; mi < s->model_count; mi++) {
        const vx_svo_model* m = &s->models[mi];
        voxels += m->voxel_count;
        CHECKF(c.models[mi].voxels == m->voxel_count, "%s model %u: %u cells, the model counts %llu", name, mi,
               c.models[mi].voxels, (unsigned long long)m->voxel_count);
        walk w = {.c = &c, .s = s, .m = m, .mi = mi, .keys = malloc((m->voxel_count ? m->voxel_count : 1) * 8)};
        if (!w.keys) {
            CHECK(!"out of memory");
            break;
        }
        CHECK(vx_svo_decode_model(m, check_cell, &w, &err) == VX_OK);
        CHECKF(w.bad == 0 && w.next == m->voxel_count, "%s model %u: %u of %u cells wrong", name, mi, w.bad, w.next);
        bad_total += w.bad;
        /* empty and set cells: the neighbours of set cells, and cells anywhere in the cube */
        uint32_t side = m->depth >= 31 ? 0 : 1u << m->depth, wrong = 0;
        for (uint32_t t = 0; side && t < 20000; t++) {
            uint32_t x, y, z;
            if (w.next && (t & 1)) {
                vx_svo_demorton(w.keys[ts_rng(&rng) % w.next], &x, &y, &z);
                x += ts_rng(&rng) % 3 - 1, y += ts_rng(&rng) % 3 - 1, z += ts_rng(&rng) % 3 - 1;
            } else {
                x = ts_rng(&rng) % side, y = ts_rng(&rng) % side, z = ts_rng(&rng) % side;
            }
            uint32_t idx;
            bool in = x < side && y < side && z < side;
            int64_t at = in ? find_key(w.keys, w.next, vx_svo_morton(x, y, z)) : -1;
            bool found = vx_compact_lookup(&c, mi, x, y, z, &idx);
            if (found != (at >= 0) || (found && idx != (uint64_t)at)) wrong++;
        }
        CHECKF(wrong == 0, "%s model %u: %u sampled cells looked up wrong", name, mi, wrong);
        if (c.models[mi].root < VX_SVO_ROOT_LEAF && c.models[mi].depth >= 3 && (rec || !rc.count)) {
            rc.keys = w.keys, rc.n = w.next;
            uint32_t before = rc.wrong;
            rec_node(&rc, c.models[mi].root, c.models[mi].depth, 0, 0, 0);
            CHECKF(rc.wrong == before, "%s model %u: %u level-3 records wrong", name, mi, rc.wrong - before);
        }
        free(w.keys);
    }
    printf("  %-32s block %4u%s: %10llu voxels, geometry %.3f + attributes %.3f bytes/voxel (%llu nodes)%s\n", name,
           block, bricks ? ", dictionary" : "", (unsigned long long)voxels, voxels ? 4.0 * c.geom_words / (double)voxels : 0.0,
           voxels ? 4.0 * c.attr_words / (double)voxels : 0.0, (unsigned long long)c.stats.nodes,
           bad_total ? " WRONG" : "");
    CHECKF(rc.checked > 0 || !c.slot_count || c.brick_count == c.slot_count, "%s: no level-3 record checked", name);
    vx_free(NULL, rec);
    if (keep) *keep = c;
    else vx_compact_free(&c);
}

/* Every pixel of three views (the default framing, orthographic, a close-up
 * from inside the bounds): the CPU reference against the walk of the
 * compact layout. Returns the pixels that hit. */
static uint64_t check_trace_bricks(const vx_svo_scene* s, const char* name, uint32_t w, uint32_t h, uint32_t bricks);
static uint64_t check_trace(const vx_svo_scene* s, const char* name, uint32_t w, uint32_t h) {
    uint64_t hits = check_trace_bricks(s, name, w, h, VX_COMPACT_BRICKS_INLINE);
    CHECK(check_trace_bricks(s, name, w, h, VX_COMPACT_BRICKS_DICT) == hits);
    return hits;
}
static uint64_t check_trace_bricks(const vx_svo_scene* s, const char* name, uint32_t w, uint32_t h, uint32_t bricks) {
    vx_compact_scene c;
    vx_error err = {0};
    if (vx_compact_build(&(vx_compact_desc){.bricks = bricks}, s, &c, &err) != VX_OK) {
        CHECKF(0, "%s: %s", name, err.msg);
        return 0;
    }
    double lo[3], hi[3];
    vx_svo_scene_world_bounds(s, lo, hi);
    uint64_t hits_total = 0;
    for (int view = 0; view < 3; view++) {
        vx_render_desc d = {.width = w, .height = h, .mode = VX_RENDER_ALBEDO, .want_hits = true};
        if (view == 1) d.camera.ortho = true;
        if (view == 2) {
            d.camera.set = true;
            d.camera.fov = 70;
            for (int k = 0; k < 3; k++) {
                double mid = 0.5 * (lo[k] + hi[k]), ext = hi[k] - lo[k];
                d.camera.target[k] = mid - 0.05 * ext;
                d.camera.eye[k] = mid + (k == 1 ? -0.3 : 0.2) * ext;
            }
        }
        vx_render_image ref = {0}, got = {0};
        vx_result r1 = vx_render_cpu(s, &d, NULL, &ref, &err);
        CHECKF(r1 == VX_OK, "%s view %d: reference: %s", name, view, err.msg);
        vx_result r2 = r1 ? r1 : vx_compact_render_cpu(&c, s, &d, NULL, &got, &err);
        CHECKF(r2 == VX_OK, "%s view %d: compact: %s", name, view, err.msg);
        if (!r1 && !r2) {
            uint32_t wrong = 0, hits = 0;
            for (size_t i = 0; i < (size_t)w * h; i++) {
                const vx_render_hit *a = &ref.hits[i], *b = &got.hits[i];
                bool same = a->instance == b->instance && !memcmp(&ref.pixels[4 * i], &got.pixels[4 * i], 16);
                if (a->instance != VX_RENDER_NO_HIT) {
                    hits++;
                    same = same && !memcmp(a->cell, b->cell, sizeof a->cell) && a->t == b->t && a->flags == b->flags;
                }
                if (!same && wrong++ < 3)
                    fprintf(stderr, "  %s view %d pixel %zu: reference instance %u cell (%u %u %u) t %.9g colour %.4f %.4f %.4f;"
                            " compact %u (%u %u %u) t %.9g colour %.4f %.4f %.4f\n", name, view, i, a->instance,
                            a->cell[0], a->cell[1], a->cell[2], a->t, ref.pixels[4 * i], ref.pixels[4 * i + 1],
                            ref.pixels[4 * i + 2], b->instance, b->cell[0], b->cell[1], b->cell[2], b->t,
                            got.pixels[4 * i], got.pixels[4 * i + 1], got.pixels[4 * i + 2]);
            }
            CHECKF(wrong == 0, "%s view %d: %u of %u pixels differ", name, view, wrong, w * h);
            hits_total += hits;
            printf("  %-32s view %d: %ux%u, %u pixels hit, %u differ\n", name, view, w, h, hits, wrong);
        }
        vx_render_image_free(&ref);
        vx_render_image_free(&got);
    }
    vx_compact_free(&c);
    return hits_total;
}

/* A model from cells and per-cell RGBA (level tiles optional). */
static vx_result rgba_model(vx_svo_model* m, uint32_t side, const uint64_t* keys, const uint8_t* level,
                            const uint32_t* rgba, size_t n) {
    vx_svo_voxels v = {.size = {side, side, side}, .count = n, .keys = keys, .level = level, .attrs = VX_ATTR_RGBA8,
                       .rgba = rgba};
    vx_error err = {0};
    return vx_svo_build_model(NULL, &v, m, NULL, &err);
}


/* The geometry built on several threads (each model apart, then merged in
 * model order, or level by level on all threads) must be the one-thread
 * build's bytes: models, geometry, attributes and the counts, with and
 * without the brick dictionary. */
static void check_threads(const vx_svo_scene* s, const char* name) {
    for (uint32_t bricks = VX_COMPACT_BRICKS_INLINE; bricks <= VX_COMPACT_BRICKS_DICT; bricks++) {
        vx_error err = {0};
        vx_compact_scene one;
        vx_compact_desc d = {.bricks = bricks, .threads = 1};
        REQUIRE(vx_compact_build(&d, s, &one, &err) == VX_OK);
        CHECKF(one.stats.geom_threads == 1, "%s: %u threads asked 1", name, one.stats.geom_threads);
        static const uint32_t counts[] = {2, 3, 7, 2, 3, 7};
        for (int t = 0; t < 6; t++) {
            vx_compact_scene c;
            d.threads = counts[t];
            d.merge = t < 3 ? VX_COMPACT_MERGE_ORDERED : VX_COMPACT_MERGE_ALL;
            REQUIRE(vx_compact_build(&d, s, &c, &err) == VX_OK);
            uint32_t want = counts[t] < s->model_count ? counts[t] : s->model_count;
            CHECKF(c.stats.geom_threads == want, "%s: geometry on %u threads, asked %u", name, c.stats.geom_threads,
                   want);
            CHECKF(c.model_count == one.model_count &&
                       !memcmp(c.models, one.models, (size_t)one.model_count * sizeof *one.models),
                   "%s, %u threads, bricks %u: models differ", name, counts[t], bricks);
            CHECKF(c.slot_count == one.slot_count && c.brick_count == one.brick_count &&
                       c.geom_words == one.geom_words &&
                       (!one.geom_words || !memcmp(c.geom, one.geom, (size_t)one.geom_words * 4)),
                   "%s, %u threads, bricks %u: geometry differs (%u / %u words)", name, counts[t], bricks,
                   c.geom_words, one.geom_words);
            CHECKF(c.attr_words == one.attr_words &&
                       (!one.attr_words || !memcmp(c.attr, one.attr, (size_t)one.attr_words * 4)),
                   "%s, %u threads: attributes differ", name, counts[t]);
            CHECKF(c.stats.nodes == one.stats.nodes && c.stats.bricks == one.stats.bricks &&
                       !memcmp(c.stats.level_slots, one.stats.level_slots, sizeof one.stats.level_slots) &&
                       !memcmp(c.stats.level_blocks, one.stats.level_blocks, sizeof one.stats.level_blocks),
                   "%s, %u threads: counts differ", name, counts[t]);
            vx_compact_free(&c);
        }
        vx_compact_free(&one);
    }
}

/* The attributes left in per-model regions (vx_compact_desc.attr_regions)
 * are the one array's words at each model's base, and joined they are the
 * one array. */
static void check_regions(const vx_svo_scene* s, const char* name) {
    vx_error err = {0};
    vx_compact_scene one, c;
    REQUIRE(vx_compact_build(NULL, s, &one, &err) == VX_OK);
    REQUIRE(vx_compact_build(&(vx_compact_desc){.attr_regions = true}, s, &c, &err) == VX_OK);
    CHECKF(!c.attr && c.attr_region && c.attr_words == one.attr_words && one.attr_words,
           "%s: regions: %u words, %u in one array", name, c.attr_words, one.attr_words);
    uint32_t bad = 0, with = 0;
    for (uint32_t i = 0; c.attr_region && i < c.model_count; i++) {
        const vx_compact_model* m = &c.models[i];
        CHECK(!memcmp(m, &one.models[i], sizeof *m));
        if (!c.attr_region[i]) {
            bad += m->attr_words != 0;
            continue;
        }
        with++;
        bad += memcmp(c.attr_region[i], one.attr + m->attr_base, (size_t)m->attr_words * 4) != 0;
    }
    CHECKF(!bad && with > 1, "%s: %u of %u regions differ", name, bad, with);
    REQUIRE(vx_compact_join_attrs(&c, &err) == VX_OK);
    CHECKF(!c.attr_region && c.attr && !memcmp(c.attr, one.attr, (size_t)one.attr_words * 4), "%s: joined differs", name);
    REQUIRE(vx_compact_join_attrs(&c, &err) == VX_OK); /* nothing left to join */
    vx_compact_free(&c);
    vx_compact_free(&one);
}

static void test_generated(void) {
    /* palette models: sparse, half full, nearly full (collapsed cubes) */
    vx_svo_model pm[3];
    REQUIRE(ts_random_model(&pm[0], 37, 20, 9, 5, 1) == VX_OK);
    REQUIRE(ts_random_model(&pm[1], 24, 24, 24, 50, 2) == VX_OK);
    REQUIRE(ts_random_model(&pm[2], 16, 16, 16, 99, 3) == VX_OK);
    /* RGBA: smooth colours (few per block), noise (raw blocks), tiles of one colour (full cubes) */
    size_t n = 0, cap = 64 * 64 * 64;
    uint64_t* keys = malloc(cap * 8);
    uint32_t* rgba = malloc(cap * 4);
    uint8_t* level = calloc(cap, 1);
    REQUIRE(keys && rgba && level);
    uint32_t seed = 7;
    vx_svo_model rm[3];
    for (uint32_t z = 0; z < 64; z++)
        for (uint32_t y = 0; y < 64; y++)
            for (uint32_t x = 0; x < 64; x++)
                if ((x - 32) * (x - 32) + (y - 32) * (y - 32) + (z - 32) * (z - 32) < 900 && ts_rng(&seed) % 4) {
                    keys[n] = vx_svo_morton(x, y, z);
                    /* coarse bands (block palettes), gradients (deltas), shading (decorrelated deltas) */
                    uint32_t lum = (x * 3 + y * 2 + z) & 0xFFu;
                    rgba[n++] = x < 32   ? 0xFF000000u | (x / 8) | ((y / 4) << 8) | ((z / 16) << 16)
                                : x < 48 ? 0xFF000000u | (x * 3) | ((y * 3) << 8) | ((z * 3) << 16)
                                         : 0xFF000000u | lum | (((lum + 5) & 0xFFu) << 8) | (((lum - 7) & 0xFFu) << 16);
                }
    REQUIRE(rgba_model(&rm[0], 64, keys, NULL, rgba, n) == VX_OK);
    for (size_t i = 0; i < n; i++) rgba[i] = ts_rng(&seed);
    REQUIRE(rgba_model(&rm[1], 64, keys, NULL, rgba, n) == VX_OK);
    n = 0;
    for (uint32_t z = 0; z < 64; z += 8)
        for (uint32_t y = 0; y < 64; y += 8)
            for (uint32_t x = 0; x < 64; x += 8)
                if (ts_rng(&seed) % 3 == 0) {
                    keys[n] = vx_svo_morton(x, y, z);
                    level[n] = ts_rng(&seed) % 2 ? 3 : 2;
                    rgba[n++] = 0xFF000000u | (ts_rng(&seed) % 3);
                }
    REQUIRE(rgba_model(&rm[2], 64, keys, level, rgba, n) == VX_OK);
    free(keys), free(rgba), free(level);
    vx_svo_model all[6] = {pm[0], pm[1], pm[2], rm[0], rm[1], rm[2]};
    vx_svo_instance in[6];
    for (uint32_t i = 0; i < 6; i++) in[i] = ts_inst(i, NULL, 70.0 * i, 0, 0);
    vx_svo_scene s;
    ts_scene(&s, all, 6, in, 6);
    static const uint32_t blocks[] = {8, 64, 1024, 0};
    for (int b = 0; b < 4; b++) check_scene(&s, "generated", blocks[b], NULL);
    CHECK(check_trace(&s, "generated", 160, 90) > 160 * 90 / 4);
    check_threads(&s, "generated");
    check_regions(&s, "generated");
    /* every block code appears: raw (noise), uniform (tiles), deltas (gradients), palettes */
    vx_compact_scene c;
    check_scene(&s, "generated", 64, &c);
    CHECK(c.stats.raw > 0 && c.stats.uniform > 0 && c.stats.shared > 0 && c.stats.delta > 0 &&
          c.stats.blocks > c.stats.raw + c.stats.uniform + c.stats.delta);
    vx_compact_free(&c);
    vx_svo_scene_free(&s);
}

/* Two copies of one shape in octants 0 and 7 of a 32^3 model: with one
 * colour the .svo DAG shares them; with different colours it cannot, but the
 * compact geometry must, and the two models' geometry must be one DAG. */
static void test_colour_sharing(void) {
    size_t n = 0;
    uint32_t* xyz = malloc(2 * 16 * 16 * 16 * 12);
    uint8_t* same = malloc(2 * 16 * 16 * 16);
    uint8_t* diff = malloc(2 * 16 * 16 * 16);
    REQUIRE(xyz && same && diff);
    uint32_t seed = 5;
    for (uint32_t z = 0; z < 16; z++)
        for (uint32_t y = 0; y < 16; y++)
            for (uint32_t x = 0; x < 16; x++)
                if (ts_rng(&seed) % 3 == 0)
                    for (uint32_t copy = 0; copy < 2; copy++) {
                        xyz[3 * n] = x + 16 * copy, xyz[3 * n + 1] = y + 16 * copy, xyz[3 * n + 2] = z + 16 * copy;
                        same[n] = 9;
                        diff[n++] = (uint8_t)(copy ? 1 + ts_rng(&seed) % 255 : 9);
                    }
    vx_svo_model m[2];
    uint32_t size[3] = {32, 32, 32};
    REQUIRE(ts_model(&m[0], size, xyz, same, n) == VX_OK);
    REQUIRE(ts_model(&m[1], size, xyz, diff, n) == VX_OK);
    free(xyz), free(same), free(diff);
    CHECKF(m[1].node_count > m[0].node_count + m[0].node_count / 4, ".svo words: %u with one colour, %u with two",
           m[0].node_count, m[1].node_count);
    vx_svo_instance in[2] = {ts_inst(0, NULL, 0, 0, 0), ts_inst(1, NULL, 40, 0, 0)};
    vx_svo_scene s, s1;
    ts_scene(&s, m, 2, in, 2);
    vx_compact_scene c, c1;
    check_scene(&s, "colour sharing", 64, &c);
    REQUIRE(c.model_count == 2);
    CHECK(c.models[0].root == c.models[1].root);
    /* the root's two children are one node: equal slots, so one block below */
    const uint32_t* root = c.geom + 2 * (size_t)c.models[1].root;
    CHECK(root[0] == 0x8100u);
    const uint32_t* kids = c.geom + 2 * (size_t)root[1];
    CHECK((kids[0] & 0xFFFFu) == (kids[2] & 0xFFFFu) && kids[1] == kids[3]);
    /* level-4 slots carry the cells of their block up to them: the second child has twice the first's */
    CHECK(kids[0] >> 16 != 0 && kids[2] >> 16 == 2 * (kids[0] >> 16));
    /* the second model adds no geometry to the first */
    vx_svo_model only = s.models[0];
    ts_scene(&s1, &only, 1, in, 1);
    check_scene(&s1, "colour sharing, one model", 64, &c1);
    CHECK(c1.geom_words == c.geom_words);
    /* one colour: one group of one header and one payload */
    CHECK(c1.stats.uniform_groups == 1 && c1.attr_words == 3);
    s1.models[0] = (vx_svo_model){0}; /* owned by s */
    vx_svo_scene_free(&s1);
    check_threads(&s, "colour sharing");
    vx_compact_free(&c);
    vx_compact_free(&c1);
    vx_svo_scene_free(&s);
}

/* The automatic block size: blocks of 64 for a textured model, of 512 for
 * 8^3 tiles of one colour each (a header per 64 cells would be 8 per tile). */
/* The seams of the geometry's fields (render/compact.h), reached by
 * construction (ts_seam_model): every 4^3 brick of a 32^3 model lacks one
 * cell (at a place that varies), so each level-3 node has 8 bricks of 63 cells (its last
 * index word counts 504 cells, 503 stored in 9 bits), each level-4 node 4,032
 * cells, and the root's block of level-4 slots carries 32,256 in bits 16..31
 * of the last one's word 0. Every cell's rank and colour, the CPU walk's
 * pixels, and the brick limit: at the scene's distinct bricks it builds, one
 * fewer is refused. */
static void test_brick_seams(void) {
    vx_svo_model m;
    REQUIRE(ts_seam_model(&m) == VX_OK);
    REQUIRE(m.voxel_count == 32768 - 512);
    vx_svo_instance in = ts_inst(0, NULL, 0, 0, 0);
    vx_svo_scene s;
    ts_scene(&s, &m, 1, &in, 1);
    vx_compact_scene c, ci;
    check_scene(&s, "brick seams", 64, &ci);
    vx_error err = {0};
    REQUIRE(vx_compact_build(&(vx_compact_desc){.bricks = VX_COMPACT_BRICKS_DICT}, &s, &c, &err) == VX_OK);
    REQUIRE(c.models[0].depth == 5 && c.brick_dict && !ci.brick_dict && ci.brick_count == 0);
    /* the dictionary saves: 8 brick children a level-3 node, most of them repeated */
    CHECKF(c.geom_words < ci.geom_words, "geometry words: %u with the dictionary, %u without", c.geom_words,
           ci.geom_words);
    /* the largest counts the fields hold: 9 bits of the index words, 16 of word 0 at level 4 */
    uint32_t n5 = (uint32_t)c.stats.offset_words, first_index = 2 * c.slot_count + n5, most_bricks = 0, most_rank = 0;
    for (uint32_t i = 0; i < c.stats.brick_refs; i++) {
        uint32_t w = c.geom[first_index + i];
        CHECK((w & (VX_COMPACT_MAX_BRICKS - 1u)) < c.brick_count);
        if (w >> VX_COMPACT_BRICK_BITS > most_bricks) most_bricks = w >> VX_COMPACT_BRICK_BITS;
    }
    uint32_t indexed = 0;
    for (uint32_t sl = c.brick_count + n5; sl < c.slot_count; sl++) {
        uint32_t w0 = c.geom[2 * (size_t)sl];
        /* the level-3 nodes carry VX_COMPACT_INDEXED above their rank (a level-4 rank here stays under 2^15) */
        bool level3 = (w0 & 0xFFFFu) == 0xFF00u && (w0 & VX_COMPACT_INDEXED);
        indexed += level3;
        uint32_t rank = (w0 >> 16) & (level3 ? 0x7FFFu : 0xFFFFu);
        if (rank > most_rank) most_rank = rank;
    }
    CHECKF(indexed == c.stats.level_slots[3] && indexed > 0, "%u level-3 slots flagged VX_COMPACT_INDEXED of %llu",
           indexed, (unsigned long long)c.stats.level_slots[3]);
    CHECKF(most_bricks == 8 * 63 - 1, "index words: most cells %u, expected %u", most_bricks + 1, 8 * 63);
    CHECKF(most_rank == 8 * 8 * 8 * 63, "level 3-4 ranks: most %u, expected %u", most_rank, 8 * 8 * 8 * 63);
    CHECKF(c.brick_count <= 64 && c.stats.bricks == c.brick_count, "%u distinct bricks (at most 64 holes)",
           c.brick_count);
    CHECK(check_trace(&s, "brick seams", 64, 48) > 0);
    /* the brick limit, at the scene's own count and one below it */
    vx_compact_desc d = vx_compact_desc_defaults();
    vx_compact_scene c2;
    d.bricks = VX_COMPACT_BRICKS_DICT;
    d.max_bricks = c.brick_count;
    CHECK(vx_compact_build(&d, &s, &c2, &err) == VX_OK && c2.geom_words == c.geom_words);
    vx_compact_free(&c2);
    d.max_bricks = c.brick_count - 1;
    CHECK(vx_compact_build(&d, &s, &c2, &err) == VX_ERR_LIMIT && strstr(err.msg, "distinct bricks"));
    vx_compact_free(&c);
    vx_compact_free(&ci);
    vx_svo_scene_free(&s);
}

static void test_auto_block(void) {
    uint64_t keys[512];
    uint8_t level[512];
    uint32_t rgba[512], seed = 3;
    for (uint32_t i = 0; i < 512; i++) {
        uint32_t x, y, z;
        vx_svo_demorton(i, &x, &y, &z);
        keys[i] = vx_svo_morton(8 * x, 8 * y, 8 * z);
        level[i] = 3;
        rgba[i] = 0xFF000000u | i;
    }
    vx_svo_model m[2];
    REQUIRE(rgba_model(&m[0], 64, keys, level, rgba, 512) == VX_OK);
    for (uint32_t i = 0; i < 512; i++) {
        keys[i] = vx_svo_morton(ts_rng(&seed) % 64, ts_rng(&seed) % 64, i % 64);
        rgba[i] = ts_rng(&seed);
    }
    REQUIRE(rgba_model(&m[1], 64, keys, NULL, rgba, 512) == VX_OK);
    vx_svo_instance in[2] = {ts_inst(0, NULL, 0, 0, 0), ts_inst(1, NULL, 70, 0, 0)};
    vx_svo_scene s;
    ts_scene(&s, m, 2, in, 2);
    vx_compact_scene c, c64;
    check_scene(&s, "tiles and noise, automatic", 0, &c);
    check_scene(&s, "tiles and noise, 64", VX_COMPACT_BLOCK, &c64);
    CHECK(c.models[0].block == VX_COMPACT_BLOCK_UNIFORM && c.models[1].block == VX_COMPACT_BLOCK);
    CHECK(c.models[0].attr_words < c64.models[0].attr_words && c.models[1].attr_words == c64.models[1].attr_words);
    vx_compact_free(&c);
    vx_compact_free(&c64);
    vx_svo_scene_free(&s);
}

/* Empty models, a model that is one full cube, bad options. */
static void test_edges(void) {
    uint32_t xyz[3 * 64], k = 0;
    for (uint32_t z = 0; z < 4; z++)
        for (uint32_t y = 0; y < 4; y++)
            for (uint32_t x = 0; x < 4; x++) xyz[3 * k] = x, xyz[3 * k + 1] = y, xyz[3 * k + 2] = z, k++;
    uint8_t pal[64];
    memset(pal, 3, sizeof pal);
    vx_svo_model m[2];
    uint32_t size[3] = {4, 4, 4};
    REQUIRE(ts_model(&m[0], size, xyz, pal, 64) == VX_OK);
    REQUIRE(ts_model(&m[1], size, xyz, pal, 0) == VX_OK);
    CHECK(m[0].root == VX_SVO_ROOT_LEAF && m[1].root == VX_SVO_ROOT_EMPTY);
    vx_svo_instance in[1] = {ts_inst(0, NULL, 0, 0, 0)};
    vx_svo_scene s;
    ts_scene(&s, m, 2, in, 1);
    vx_compact_scene c;
    check_scene(&s, "full cube and empty model", 8, &c);
    CHECK(c.geom_words == 0 && c.models[0].voxels == 64 && c.models[1].voxels == 0);
    uint32_t idx;
    CHECK(!vx_compact_lookup(&c, 1, 0, 0, 0, &idx) && !vx_compact_lookup(&c, 0, 4, 0, 0, &idx) &&
          !vx_compact_lookup(&c, 2, 0, 0, 0, &idx));
    CHECK(vx_compact_rgba(&c, 0, 64) == 0xFFFFFFFFu && vx_compact_rgba(&c, 0, 63) == s.palette[3]);
    vx_compact_free(&c);
    vx_compact_desc d = {.block = 12};
    vx_error err = {0};
    CHECK(vx_compact_build(&d, &s, &c, &err) == VX_ERR_INVALID_ARG && strstr(err.msg, "12"));
    d.block = 2048;
    CHECK(vx_compact_build(&d, &s, &c, &err) == VX_ERR_INVALID_ARG);
    vx_svo_scene_free(&s);
}

/* A model of more than 2^22 cells in large full cubes (the reference then
 * walks the collapsed leaves instead of decoding every cell) beside a
 * rotated instance and a shifted one of a palette model. */
static void test_trace_large(void) {
    uint64_t keys[16];
    uint8_t level[16];
    uint32_t rgba[16], n = 0, seed = 11;
    for (uint32_t i = 0; i < 8; i++) {
        uint32_t x, y, z;
        vx_svo_demorton(i, &x, &y, &z);
        if (i == 3 || i == 6) continue;
        keys[n] = vx_svo_morton(128 * x, 128 * y, 128 * z), level[n] = 7, rgba[n++] = 0xFF000000u | ts_rng(&seed);
    }
    keys[n] = vx_svo_morton(300, 40, 260), level[n] = 0, rgba[n++] = 0xFF0000FFu;
    keys[n] = vx_svo_morton(264, 8, 16), level[n] = 3, rgba[n++] = 0xFF00FF00u;
    vx_svo_model m[2];
    REQUIRE(rgba_model(&m[0], 512, keys, level, rgba, n) == VX_OK);
    REQUIRE(m[0].voxel_count > (1u << 22));
    REQUIRE(ts_random_model(&m[1], 40, 33, 21, 35, 9) == VX_OK);
    static const double rot[9] = {0.36, -0.48, 0.8, 0.8, 0.6, 0, -0.48, 0.64, 0.6};
    vx_svo_instance in[3] = {ts_inst(0, NULL, 0, 0, 0), ts_inst(1, rot, 100, 300, 310), ts_inst(1, NULL, -60, 20, 50)};
    vx_svo_scene s;
    ts_scene(&s, m, 2, in, 3);
    CHECK(check_trace(&s, "large cubes, rotated instance", 120, 90) > 120 * 90 / 4);
    vx_svo_scene_free(&s);
}

static void test_corpus(void) {
    static const char* files[] = {"eph_chr_knight.vox", "eph_dragon.vox", "eph_menger.vox",
                                  "eph_monu1.vox", "eph_teapot.vox", "ogt_chr_knight.vox",
                                  "ogt_doom.vox", "ogt_test_groups.vox", "ogt_test_multiple_model_scene.vox"};
    int done = 0;
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
        vx_svo_scene s;
        vx_test_vox st = vx_test_vox_scene(files[i], &s);
        if (st == VX_TEST_VOX_ABSENT) continue;
        done++; /* found: a file that fails to load fails the test, not skips it */
        CHECKF(st == VX_TEST_VOX_OK, "%s: not loaded", files[i]);
        if (st != VX_TEST_VOX_OK) continue;
        check_scene(&s, files[i], 0, NULL);
        if (s.model_count > 1) check_threads(&s, files[i]);
        CHECKF(check_trace(&s, files[i], 96, 72) > 96 * 72 / 20, "%s: too few pixels hit", files[i]);
        vx_svo_scene_free(&s);
    }
    if (!done) SKIP("no corpus .vox files");
}

/* An RGBA scene from a textured mesh (exact colours, not a palette). */
static void test_corpus_mesh(void) {
#ifdef VX_TEST_HAVE_MESH
    const char* path = vx_test_corpus("gltf/khronos_DamagedHelmet.glb");
    if (!path) SKIP("no DamagedHelmet.glb");
    vx_svo_scene s;
    vx_error err = {0};
    vx_conv_mesh_desc d = {.res = 128};
    REQUIRE(vx_conv_mesh_file(&d, path, &s, NULL, &err) == VX_OK);
    check_scene(&s, "DamagedHelmet at 128", 0, NULL);
    CHECK(check_trace(&s, "DamagedHelmet at 128", 128, 96) > 128 * 96 / 10);
    vx_svo_scene_free(&s);
    /* regions of 64: many models whose surfaces share blocks across models */
    d = (vx_conv_mesh_desc){.res = 384, .region = 64};
    REQUIRE(vx_conv_mesh_file(&d, path, &s, NULL, &err) == VX_OK);
    CHECKF(s.model_count > 20, "DamagedHelmet at 384 in regions of 64: %u models", s.model_count);
    check_threads(&s, "DamagedHelmet at 384, regions of 64");
    check_regions(&s, "DamagedHelmet at 384, regions of 64");
    vx_svo_scene_free(&s);
#else
    SKIP("built without the mesh converter");
#endif
}

int main(void) {
    RUN(test_generated);
    RUN(test_colour_sharing);
    RUN(test_brick_seams);
    RUN(test_auto_block);
    RUN(test_edges);
    RUN(test_trace_large);
    RUN(test_corpus);
    RUN(test_corpus_mesh);
    return vx_test_finish();
}
