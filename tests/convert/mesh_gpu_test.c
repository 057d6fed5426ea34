/* tests/convert/mesh_gpu_test.c - the GPU voxelizer (convert/mesh_gpu.h)
 * against the CPU one: the same .svo bytes (cells, colours, normals,
 * materials, regions and octrees) and the same cell lists, on every corpus
 * mesh at 32 and 64 cells and at 128 in regions of 64 (whole and in 3 shares), and on generated
 * meshes made to hit the hard cases: degenerate triangles (points,
 * segments, slivers), vertices and faces exactly on cell boundaries,
 * axis-aligned faces on the grid's bounds, textures with every wrap mode
 * and uv far outside [0, 1], vertex colours, special materials. The GPU
 * path's octree builders take the tuples interned on the GPU. Split into
 * shares (vox2svo --gpu under mpirun), the GPU path gives the same file.
 * Runs on whatever device vx_gpu_create picks (lavapipe here); skipped
 * without a device or without shaderFloat64. */
#include <dlfcn.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "convert/mesh_gpu.h"
#include "render/render.h"
#include "tests/test.h"
#include "tests/gpu_test.h"
#include "tests/convert/mesh_tex_gltf.h"

static vx_gpu* gpu;
static vx_conv_mesh_gpu* mg;
static const char* gpu_skip;

/* CPU and GPU conversions of mesh, written; 1 when the bytes are equal. */
static int same_svo(const vx_gltf_mesh* mesh, uint32_t res, uint32_t region, bool normals, const char* what) {
    vx_conv_mesh_desc d = {.res = res, .region = region, .normals = normals};
    vx_svo_scene a, b;
    vx_error err = {0};
    vx_result r = vx_conv_mesh(&d, mesh, &a, NULL, &err);
    if (r) {
        fprintf(stderr, "  %s res %u: CPU: %s\n", what, res, err.msg);
        return 0;
    }
    d.backend = vx_conv_mesh_gpu_backend(mg);
    r = vx_conv_mesh(&d, mesh, &b, NULL, &err);
    if (r) {
        fprintf(stderr, "  %s res %u: GPU: %s\n", what, res, err.msg);
        vx_svo_scene_free(&a);
        return 0;
    }
    uint8_t *da = NULL, *db = NULL;
    size_t na = 0, nb = 0;
    int ok = vx_svo_write(&a, NULL, &da, &na, &err) == VX_OK && vx_svo_write(&b, NULL, &db, &nb, &err) == VX_OK &&
             na == nb && memcmp(da, db, na) == 0;
    /* the scene's bounds (the GPU path's from the cells' boxes, the CPU path's from a pass over each model) */
    if (ok && (memcmp(a.bounds_min, b.bounds_min, sizeof a.bounds_min) || memcmp(a.bounds_max, b.bounds_max, sizeof a.bounds_max))) {
        fprintf(stderr, "  %s res %u region %u: bounds (%g %g %g)-(%g %g %g), the CPU path's (%g %g %g)-(%g %g %g)\n", what, res,
                region, b.bounds_min[0], b.bounds_min[1], b.bounds_min[2], b.bounds_max[0], b.bounds_max[1], b.bounds_max[2],
                a.bounds_min[0], a.bounds_min[1], a.bounds_min[2], a.bounds_max[0], a.bounds_max[1], a.bounds_max[2]);
        ok = 0;
    }
    vx_conv_mesh_gpu_stats st;
    vx_conv_mesh_gpu_last_stats(mg, &st);
    /* the builders got the tuples interned on the GPU (vx__svo_build_interned,
     * which rejects equal tuples under two ids; one id for two tuples would
     * change the bytes): at least one per region, at most one per cell */
    bool attrs = a.model_count && a.models[0].attrs;
    if (ok && attrs && !(st.tuples >= a.model_count && st.tuples <= st.cells)) {
        fprintf(stderr, "  %s res %u region %u: %llu tuples interned for %u models, %llu cells\n", what, res, region,
                (unsigned long long)st.tuples, a.model_count, (unsigned long long)st.cells);
        ok = 0;
    }
    if (!ok) fprintf(stderr, "  %s res %u region %u: .svo differs (%zu vs %zu bytes)\n", what, res, region, na, nb);
    else fprintf(stderr, "  %s res %u region %u: %llu cells from %llu pieces, %llu tuples, %llu nodes built on the GPU, equal\n",
                 what, res, region, (unsigned long long)st.cells, (unsigned long long)st.records, (unsigned long long)st.tuples,
                 (unsigned long long)st.nodes);
    /* the trees were built on the GPU (no fallback to the CPU builders) */
    if (ok && attrs && st.build_fallback) {
        fprintf(stderr, "  %s res %u region %u: the GPU build fell back to the CPU builders\n", what, res, region);
        ok = 0;
    }
    /* and the block layout (attribute runs, blocks) was done on the GPU too */
    if (ok && attrs && !st.build_fallback && st.nodes && (!st.run_records || !st.laid_words)) {
        fprintf(stderr, "  %s res %u region %u: the attribute runs or blocks were not laid out on the GPU\n", what, res, region);
        ok = 0;
    }
    /* and the records' attributes filled there (a little-endian host: the
     * material halves are the model's array) */
    const uint16_t one = 1;
    if (ok && attrs && st.laid_words && *(const uint8_t*)&one == 1 && st.filled_records != st.run_records) {
        fprintf(stderr, "  %s res %u region %u: %llu of %llu records filled on the GPU\n", what, res, region,
                (unsigned long long)st.filled_records, (unsigned long long)st.run_records);
        ok = 0;
    }
    /* and each region's node pool is the CPU builder's, node for node (and
     * with them the GPU's attribute runs and node words the builder's
     * layout's): the
     * builders build their own too and fail at the first node that differs */
    if (ok && attrs) {
        vx_svo_scene c;
        vx_conv_mesh_gpu_set_build(mg, VX_CONV_MESH_GPU_BUILD_CHECK);
        r = vx_conv_mesh(&d, mesh, &c, NULL, &err);
        vx_conv_mesh_gpu_set_build(mg, VX_CONV_MESH_GPU_BUILD_GPU);
        if (r) {
            fprintf(stderr, "  %s res %u region %u: GPU pools against the CPU builders': %s\n", what, res, region, err.msg);
            ok = 0;
        } else {
            vx_svo_scene_free(&c);
        }
    }
    free(da);
    free(db);
    vx_svo_scene_free(&a);
    vx_svo_scene_free(&b);
    return ok;
}

/* The GPU path split into `shares` shares (vx_conv_mesh_share, as vox2svo
 * under mpirun): each share's regions are the CPU share's, and the parts of
 * all shares assembled give the one-process CPU file; 1 when so. */
static int same_shares(const vx_gltf_mesh* mesh, uint32_t res, uint32_t region, uint32_t shares, const char* what) {
    vx_conv_mesh_desc d = {.res = res, .region = region}, dg = d;
    dg.backend = vx_conv_mesh_gpu_backend(mg);
    vx_error err = {0};
    vx_svo_scene a, b;
    if (vx_conv_mesh(&d, mesh, &a, NULL, &err)) return fprintf(stderr, "  %s: CPU: %s\n", what, err.msg), 0;
    vx_conv_mesh_part* all = NULL;
    size_t total = 0;
    int ok = 1;
    for (uint32_t sh = 0; sh < shares && ok; sh++) {
        vx_conv_mesh_part *gp = NULL, *cp = NULL;
        size_t gn = 0, cn = 0;
        if (vx_conv_mesh_share(&dg, mesh, sh, shares, &gp, &gn, NULL, &err) ||
            vx_conv_mesh_share(&d, mesh, sh, shares, &cp, &cn, NULL, &err)) {
            fprintf(stderr, "  %s share %u of %u: %s\n", what, sh, shares, err.msg);
            ok = 0;
        }
        ok = ok && gn == cn;
        for (size_t i = 0; ok && i < gn; i++) ok = gp[i].index == cp[i].index;
        /* each GPU part's box (from the cells on the GPU) is its model's, as a pass over the model finds it */
        for (size_t i = 0; ok && i < gn; i++) {
            vx_svo_instance inst;
            memset(&inst, 0, sizeof inst);
            inst.xform[0] = inst.xform[5] = inst.xform[10] = 1.0;
            inst.layer = UINT32_MAX;
            vx_svo_scene one;
            vx_svo_scene_init(&one, NULL);
            one.models = &gp[i].model, one.model_count = 1, one.instances = &inst, one.instance_count = 1;
            vx_svo_scene_update_bounds(&one);
            bool same = gp[i].has_box;
            for (int k = 0; k < 3; k++)
                same = same && one.bounds_min[k] == gp[i].box_min[k] && one.bounds_max[k] == gp[i].box_max[k];
            if (!same) {
                fprintf(stderr, "  %s share %u part %zu: box %u %u %u - %u %u %u (known %d), the model's %g %g %g - %g %g %g\n", what,
                        sh, i, gp[i].box_min[0], gp[i].box_min[1], gp[i].box_min[2], gp[i].box_max[0], gp[i].box_max[1],
                        gp[i].box_max[2], gp[i].has_box, one.bounds_min[0], one.bounds_min[1], one.bounds_min[2], one.bounds_max[0],
                        one.bounds_max[1], one.bounds_max[2]);
                ok = 0;
            }
        }
        if (!ok) fprintf(stderr, "  %s share %u of %u: %zu regions, the CPU's %zu\n", what, sh, shares, gn, cn);
        vx_conv_mesh_part* t = ok ? (vx_conv_mesh_part*)realloc(all, (total + gn + 1) * sizeof *all) : NULL;
        if (t) {
            all = t;
            if (gn) memcpy(all + total, gp, gn * sizeof *gp); /* a share may have no region (gp NULL) */
            total += gn;
            free(gp); /* the models moved into all */
        } else {
            ok = 0;
            vx_conv_mesh_parts_free(NULL, gp, gn);
        }
        vx_conv_mesh_parts_free(NULL, cp, cn);
    }
    if (ok && vx_conv_mesh_assemble(&dg, mesh, all, total, &b, NULL, &err)) {
        fprintf(stderr, "  %s: assemble: %s\n", what, err.msg);
        ok = 0;
    }
    vx_conv_mesh_parts_free(NULL, all, total);
    uint8_t *da = NULL, *db = NULL;
    size_t na = 0, nb = 0;
    if (ok) {
        ok = vx_svo_write(&a, NULL, &da, &na, &err) == VX_OK && vx_svo_write(&b, NULL, &db, &nb, &err) == VX_OK && na == nb &&
             memcmp(da, db, na) == 0;
        fprintf(stderr, "  %s res %u region %u over %u shares (%u models): %s\n", what, res, region, shares, b.model_count,
                ok ? "equal" : "DIFFERENT");
        vx_svo_scene_free(&b);
    }
    free(da);
    free(db);
    vx_svo_scene_free(&a);
    return ok;
}

typedef struct cell {
    uint32_t x, y, z, rgba;
} cell;
static int cell_cmp(const void* pa, const void* pb) {
    const cell *a = (const cell*)pa, *b = (const cell*)pb;
    if (a->z != b->z) return a->z < b->z ? -1 : 1;
    if (a->y != b->y) return a->y < b->y ? -1 : 1;
    if (a->x != b->x) return a->x < b->x ? -1 : 1;
    return 0;
}
static cell* cells_of(const vx_conv_mesh_desc* d, const vx_gltf_mesh* mesh, size_t* n) {
    uint32_t *xyz = NULL, *rgba = NULL;
    vx_error err = {0};
    if (vx_conv_mesh_cells(d, mesh, NULL, &xyz, &rgba, n, &err)) {
        fprintf(stderr, "  cells: %s\n", err.msg);
        return NULL;
    }
    cell* c = (cell*)malloc((*n ? *n : 1) * sizeof *c);
    for (size_t i = 0; i < *n; i++) c[i] = (cell){xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2], rgba ? rgba[i] : 0};
    qsort(c, *n, sizeof *c, cell_cmp);
    free(xyz);
    free(rgba);
    return c;
}

/* The flat cell lists: how many cells or colours differ (0: equal). */
static size_t cell_diffs(const vx_gltf_mesh* mesh, uint32_t res, const char* what) {
    vx_conv_mesh_desc d = {.res = res};
    size_t na = 0, nb = 0, diff = 0;
    cell* a = cells_of(&d, mesh, &na);
    d.backend = vx_conv_mesh_gpu_backend(mg);
    cell* b = cells_of(&d, mesh, &nb);
    if (!a || !b) diff = 1;
    else if (na != nb) diff = na > nb ? na - nb : nb - na;
    else
        for (size_t i = 0; i < na; i++) {
            if (cell_cmp(&a[i], &b[i]) || a[i].rgba != b[i].rgba) {
                if (diff < 3)
                    fprintf(stderr, "  %s res %u: cell %u %u %u rgba %08x, GPU %u %u %u rgba %08x\n", what, res, a[i].x,
                            a[i].y, a[i].z, a[i].rgba, b[i].x, b[i].y, b[i].z, b[i].rgba);
                diff++;
            }
        }
    if (diff) fprintf(stderr, "  %s res %u: %zu vs %zu cells, %zu differ\n", what, res, na, nb, diff);
    free(a);
    free(b);
    return diff;
}

static const char* corpus_meshes[] = {
    "gltf/aleph_Box.glb", "gltf/tinygltf_box01.glb", "gltf/julian_Duck.glb", "gltf/rtxgi_cornell.glb",
    "gltf/rtxgi_furnace.glb", "gltf/rtxgi_two-rooms.glb", "gltf/rtxgi_tunnel.glb", "gltf/khronos_DamagedHelmet.glb",
    "gltf/khronos_Avocado_glTF/Avocado.gltf", "gltf/aleph_white-claw-can.glb", "gltf/mjurczyk_shuttle.glb",
    "gltf/tinygltf_Cube/Cube.gltf", "gltf/tinygltf_CubeImageUriSpaces/CubeImageUriSpaces.gltf"};

static void test_corpus(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    int found = 0;
    for (size_t i = 0; i < sizeof corpus_meshes / sizeof corpus_meshes[0]; i++) {
        const char* p = vx_test_corpus(corpus_meshes[i]);
        if (!p) {
            fprintf(stderr, "  %s: not in the corpus, skipped\n", corpus_meshes[i]);
            continue;
        }
        vx_gltf_mesh m;
        vx_error err = {0};
        if (vx_conv_mesh_read(NULL, p, &m, &err)) {
            fprintf(stderr, "  %s: %s (the CPU path refuses it too: skipped)\n", corpus_meshes[i], err.msg);
            continue;
        }
        found++;
        /* whole at 32 and 64; 128 in regions of 64 (below) is the same voxelizer at 128 with the regions' seams:
         * the whole file at 128 as well was a third of this test's 359 s in Release on 2 cores (lavapipe's
         * float64 emulation; docs/TESTING.md, stop 59) */
        static const uint32_t res[] = {32, 64};
        for (size_t k = 0; k < 2; k++) {
            CHECKF(same_svo(&m, res[k], 0, true, corpus_meshes[i]), "%s at %u", corpus_meshes[i], res[k]);
            /* DamagedHelmet samples its metallic-roughness and emissive
             * textures per cell: on the GPU, not handed to the CPU */
            if (strstr(corpus_meshes[i], "DamagedHelmet")) {
                vx_conv_mesh_gpu_stats st;
                vx_conv_mesh_gpu_last_stats(mg, &st);
                CHECKF(st.sampled_materials == 1 && st.cells > 0, "%s at %u: materials not sampled on the GPU", corpus_meshes[i],
                       res[k]);
            }
            /* the .svo bytes cover the cells; the lists say where they differ */
            if (res[k] == 64) CHECKF(cell_diffs(&m, res[k], corpus_meshes[i]) == 0, "%s at %u", corpus_meshes[i], res[k]);
        }
        CHECKF(same_svo(&m, 128, 64, false, corpus_meshes[i]), "%s at 128 in regions of 64", corpus_meshes[i]);
        CHECKF(same_shares(&m, 128, 64, 3, corpus_meshes[i]), "%s at 128 in regions of 64, 3 shares", corpus_meshes[i]);
        vx_gltf_mesh_free(&m);
    }
    if (!found) SKIP("no corpus meshes (../shared/corpus or VX_CORPUS_DIR)");
}

/* desc.solid on the GPU path (the GPU voxelizes the surface, the CPU
 * voxelizer's own code votes and fills each brick from those cells): the
 * file is the CPU path's byte for byte; *interior gets the cells the fill
 * added (the CPU path's voxels less the GPU's surface cells). 1 when equal. */
static int same_solid(const vx_gltf_mesh* mesh, uint32_t res, uint32_t region, bool normals, const char* what,
                      uint64_t* interior) {
    vx_conv_mesh_desc d = {.res = res, .region = region, .normals = normals, .solid = true};
    vx_svo_scene a, b;
    vx_conv_stats cs = {0};
    vx_error err = {0};
    if (vx_conv_mesh(&d, mesh, &a, &cs, &err)) {
        fprintf(stderr, "  %s res %u solid: CPU: %s\n", what, res, err.msg);
        return 0;
    }
    d.backend = vx_conv_mesh_gpu_backend(mg);
    if (vx_conv_mesh(&d, mesh, &b, NULL, &err)) {
        fprintf(stderr, "  %s res %u solid: GPU: %s\n", what, res, err.msg);
        vx_svo_scene_free(&a);
        return 0;
    }
    vx_conv_mesh_gpu_stats st;
    vx_conv_mesh_gpu_last_stats(mg, &st);
    uint8_t *da = NULL, *db = NULL;
    size_t na = 0, nb = 0;
    int ok = vx_svo_write(&a, NULL, &da, &na, &err) == VX_OK && vx_svo_write(&b, NULL, &db, &nb, &err) == VX_OK &&
             na == nb && memcmp(da, db, na) == 0;
    /* the surface came from the GPU: its pieces, no more cells than the solid has */
    if (ok && (st.records == 0 || st.cells > cs.build.voxels)) {
        fprintf(stderr, "  %s res %u solid: %llu pieces, %llu surface cells for %llu voxels\n", what, res,
                (unsigned long long)st.records, (unsigned long long)st.cells, (unsigned long long)cs.build.voxels);
        ok = 0;
    }
    *interior = cs.build.voxels - (st.cells < cs.build.voxels ? st.cells : cs.build.voxels);
    fprintf(stderr, "  %s res %u region %u solid: %llu surface cells from the GPU, %llu interior, %s\n", what, res, region,
            (unsigned long long)st.cells, (unsigned long long)*interior, ok ? "equal" : "DIFFERENT");
    free(da);
    free(db);
    vx_svo_scene_free(&a);
    vx_svo_scene_free(&b);
    return ok;
}

static void test_solid(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    int found = 0;
    uint64_t all = 0;
    for (size_t i = 0; i < sizeof corpus_meshes / sizeof corpus_meshes[0]; i++) {
        const char* p = vx_test_corpus(corpus_meshes[i]);
        if (!p) continue;
        vx_gltf_mesh m;
        vx_error err = {0};
        if (vx_conv_mesh_read(NULL, p, &m, &err)) continue;
        found++;
        uint64_t in32 = 0, in64 = 0;
        CHECKF(same_solid(&m, 32, 0, false, corpus_meshes[i], &in32), "%s at 32, solid", corpus_meshes[i]);
        CHECKF(same_solid(&m, 64, 0, true, corpus_meshes[i], &in64), "%s at 64 with normals, solid", corpus_meshes[i]);
        all += in32 + in64;
        /* closed meshes: the fill adds cells; regions (and bricks) with no surface cell in them (the box's inside) */
        if (strstr(corpus_meshes[i], "aleph_Box") || strstr(corpus_meshes[i], "julian_Duck")) {
            CHECKF(in64 > 0, "%s at 64: no interior cells", corpus_meshes[i]);
            uint64_t in = 0;
            CHECKF(same_solid(&m, 256, 64, false, corpus_meshes[i], &in), "%s at 256 in regions of 64, solid", corpus_meshes[i]);
            CHECKF(in > in64, "%s at 256: %llu interior cells", corpus_meshes[i], (unsigned long long)in);
        }
        vx_gltf_mesh_free(&m);
    }
    if (!found) SKIP("no corpus meshes (../shared/corpus or VX_CORPUS_DIR)");
    CHECK(all > 0);
}

/* ---- generated meshes -------------------------------------------------------------- */

typedef struct gen {
    vx_gltf_mesh m;
    size_t cap;
} gen;

static uint64_t rng = 0x9E3779B97F4A7C15ull;
static double frand(void) {
    rng ^= rng << 13, rng ^= rng >> 7, rng ^= rng << 17;
    return (double)(rng >> 11) / 9007199254740992.0;
}

static void tri(gen* g, const float v[9], uint32_t mat) {
    if (g->m.tri_count == g->cap) {
        g->cap = g->cap ? 2 * g->cap : 64;
        g->m.pos = realloc(g->m.pos, g->cap * 36);
        g->m.uv = realloc(g->m.uv, g->cap * 24);
        g->m.color = realloc(g->m.color, g->cap * 48);
        g->m.material = realloc(g->m.material, g->cap * 4);
    }
    size_t t = g->m.tri_count++;
    memcpy(g->m.pos + 9 * t, v, 36);
    for (int k = 0; k < 6; k++) g->m.uv[6 * t + k] = (float)(frand() * 6 - 3); /* every wrap, far outside [0, 1] */
    for (int k = 0; k < 12; k++) g->m.color[12 * t + k] = (float)frand();
    g->m.material[t] = mat;
}

static void gen_free(gen* g) {
    free(g->m.pos), free(g->m.uv), free(g->m.color), free(g->m.material), free(g->m.materials);
    for (uint32_t i = 0; i < g->m.image_count; i++) free(g->m.images[i].rgba);
    free(g->m.images);
    memset(g, 0, sizeof *g);
}

/* Materials: 0 textured (repeat), 1 textured clamp / mirror, 2 metallic
 * (a MATL record), 3 plain; two small random images. */
static void gen_materials(gen* g) {
    g->m.image_count = 2;
    g->m.images = calloc(2, sizeof *g->m.images);
    for (int i = 0; i < 2; i++) {
        vx_gltf_image* im = &g->m.images[i];
        im->width = 5 + 3 * i;
        im->height = 7 - 2 * i;
        im->rgba = malloc((size_t)im->width * im->height * 4);
        for (size_t k = 0; k < (size_t)im->width * im->height * 4; k++) im->rgba[k] = (uint8_t)(frand() * 256);
    }
    g->m.material_count = 4;
    g->m.materials = calloc(4, sizeof *g->m.materials);
    for (int i = 0; i < 4; i++) {
        vx_gltf_material* mt = &g->m.materials[i];
        for (int k = 0; k < 4; k++) mt->base_color[k] = (float)(0.3 + 0.7 * frand());
        mt->image = i < 2 ? i : -1;
        mt->wrap_s = i == 0 ? VX_GLTF_WRAP_REPEAT : VX_GLTF_WRAP_CLAMP;
        mt->wrap_t = i == 0 ? VX_GLTF_WRAP_REPEAT : VX_GLTF_WRAP_MIRROR;
        mt->roughness = 0.5f;
        mt->ior = 1.5f;
        mt->metallic = i == 2 ? 1.0f : 0.0f;
    }
}

static void check_gen(gen* g, const char* what) {
    static const uint32_t res[] = {16, 32, 64, 100};
    for (size_t k = 0; k < 4; k++) {
        CHECKF(same_svo(&g->m, res[k], 0, true, what), "%s at %u", what, res[k]);
        CHECKF(cell_diffs(&g->m, res[k], what) == 0, "%s at %u", what, res[k]);
    }
}

/* Vertices on a lattice of 1/8 of the box: at res 16, 32, 64 every vertex is
 * a cell corner or lies on cell faces; axis-aligned faces, the box's own
 * faces on the grid bounds, degenerate triangles (repeated vertices,
 * collinear points) among them. */
static void test_lattice(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    gen g;
    memset(&g, 0, sizeof g);
    gen_materials(&g);
    /* the bounding box: two opposite corners, as faces on the bounds */
    float box[][9] = {{0, 0, 0, 8, 0, 0, 8, 8, 0}, {0, 0, 8, 8, 8, 8, 0, 8, 8}, {0, 0, 0, 0, 8, 0, 0, 8, 8},
                      {8, 0, 0, 8, 8, 8, 8, 0, 8}};
    for (size_t i = 0; i < 4; i++) tri(&g, box[i], (uint32_t)i % 4);
    for (int i = 0; i < 300; i++) {
        float v[9];
        for (int k = 0; k < 9; k++) v[k] = (float)floor(frand() * 9);
        int kind = i % 6;
        if (kind == 1) memcpy(v + 3, v, 12), memcpy(v + 6, v, 12);              /* a point */
        if (kind == 2) memcpy(v + 6, v + 3, 12);                                /* a segment */
        if (kind == 3) for (int k = 0; k < 3; k++) v[6 + k] = 2 * v[3 + k] - v[k]; /* collinear */
        if (kind == 4) v[2] = v[5] = v[8];                                      /* axis-aligned */
        if (kind == 5) for (int k = 0; k < 9; k++) v[k] = (float)(floor(frand() * 17) / 2); /* half cells */
        if (kind == 3) {
            bool in = true;
            for (int k = 6; k < 9; k++) in = in && v[k] >= 0 && v[k] <= 8;
            if (!in) continue;
        }
        tri(&g, v, i % 5 == 4 ? UINT32_MAX : (uint32_t)(i % 4));
    }
    check_gen(&g, "lattice");
    gen_free(&g);
}

/* Random triangles of every size and slivers, textured, coloured. */
static void test_random(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    gen g;
    memset(&g, 0, sizeof g);
    gen_materials(&g);
    for (int i = 0; i < 400; i++) {
        float v[9], c[3];
        double s = i % 3 == 0 ? 0.02 : i % 3 == 1 ? 0.2 : 1.0;
        for (int k = 0; k < 3; k++) c[k] = (float)(frand() * 10 - 5);
        for (int k = 0; k < 9; k++) v[k] = c[k % 3] + (float)((frand() - 0.5) * s * 10);
        if (i % 7 == 0) for (int k = 0; k < 3; k++) v[6 + k] = v[k] + (v[3 + k] - v[k]) * 0.5f + 1e-4f; /* sliver */
        tri(&g, v, (uint32_t)(i % 4));
    }
    check_gen(&g, "random");
    /* one colour (no vertex colours, one untextured material): every record
     * and every representative is the same tuple, so the root's
     * representative is among the records (its first record found there,
     * not appended after them as above) */
    float* col = g.m.color;
    g.m.color = NULL;
    for (size_t t = 0; t < g.m.tri_count; t++) g.m.material[t] = 3;
    CHECK(same_svo(&g.m, 48, 0, false, "random, one colour"));
    g.m.color = col;
    /* no colour source at all: a geometry-only model */
    free(g.m.color), g.m.color = NULL;
    free(g.m.material), g.m.material = NULL;
    g.m.material_count = 0;
    CHECK(same_svo(&g.m, 48, 0, false, "random, geometry only"));
    gen_free(&g);
}

static void test_refusals(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 1};
    vx_gltf_mesh m;
    memset(&m, 0, sizeof m);
    m.tri_count = 1;
    m.pos = v;
    vx_svo_scene s;
    vx_error err = {0};
    vx_conv_mesh_desc d = {.res = 16, .backend = vx_conv_mesh_gpu_backend(mg)};
    vx_conv_mesh_part* parts = NULL;
    size_t n = 0;
    CHECK(vx_conv_mesh_share(&d, &m, 2, 2, &parts, &n, NULL, &err) == VX_ERR_INVALID_ARG && parts == NULL);
    v[4] = NAN;
    CHECK(vx_conv_mesh(&d, &m, &s, NULL, &err) == VX_ERR_BAD_FORMAT);
}

/* The GPU build's hash tables with collisions forced (vx_conv_mesh_gpu_set_hash):
 * every probe starting in one of 8 slots, the result stays on the GPU (long
 * probe chains, the node pools and runs checked against the CPU builders');
 * the structural hash cut to 4 bits, the GPU's check finds the distinct
 * subtrees that hash alike and the CPU builders build. The file is the CPU
 * path's either way. */
static void test_collisions(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    gen g = {0};
    gen_materials(&g);
    for (int i = 0; i < 60; i++) {
        float v[9];
        for (int k = 0; k < 9; k++) v[k] = (float)(frand() * 2.0 - 1.0);
        tri(&g, v, (uint32_t)i % 3u);
    }
    static const struct {
        vx_conv_mesh_gpu_hash hash;
        const char* what;
        uint32_t fallback;
    } cases[] = {{VX_CONV_MESH_GPU_HASH_FEW_SLOTS, "random, probes from 8 slots", 0},
                 {VX_CONV_MESH_GPU_HASH_FEW_LABELS, "random, structural hash of 4 bits", 1}};
    for (size_t c = 0; c < 2; c++) {
        vx_conv_mesh_gpu_set_hash(mg, cases[c].hash);
        vx_conv_mesh_gpu_stats st;
        if (cases[c].fallback) {
            /* same_svo asserts the GPU built: here the file alone, and the fallback */
            vx_conv_mesh_desc d = {.res = 48};
            vx_svo_scene a, b;
            vx_error err = {0};
            CHECK(vx_conv_mesh(&d, &g.m, &a, NULL, &err) == VX_OK);
            d.backend = vx_conv_mesh_gpu_backend(mg);
            CHECKF(vx_conv_mesh(&d, &g.m, &b, NULL, &err) == VX_OK, "%s: %s", cases[c].what, err.msg);
            vx_conv_mesh_gpu_last_stats(mg, &st);
            uint8_t *da = NULL, *db = NULL;
            size_t na = 0, nb = 0;
            CHECK(vx_svo_write(&a, NULL, &da, &na, &err) == VX_OK && vx_svo_write(&b, NULL, &db, &nb, &err) == VX_OK);
            CHECKF(na == nb && na && memcmp(da, db, na) == 0, "%s: the file differs from the CPU path's", cases[c].what);
            CHECKF(st.build_fallback == 1, "%s: no fallback to the CPU builders (%llu nodes)", cases[c].what,
                   (unsigned long long)st.nodes);
            fprintf(stderr, "  %s: the GPU's check found the collisions, the CPU built: equal\n", cases[c].what);
            free(da);
            free(db);
            vx_svo_scene_free(&a);
            vx_svo_scene_free(&b);
        } else {
            CHECKF(same_svo(&g.m, 48, 0, true, cases[c].what), "%s", cases[c].what);
            vx_conv_mesh_gpu_last_stats(mg, &st);
            CHECKF(st.nodes > 100 && st.run_records > 0, "%s: %llu nodes, %llu run records", cases[c].what,
                   (unsigned long long)st.nodes, (unsigned long long)st.run_records);
        }
    }
    vx_conv_mesh_gpu_set_hash(mg, VX_CONV_MESH_GPU_HASH_FULL);
    /* the blocks left to the CPU (the path taken when the GPU's layout does not settle): the same file */
    {
        vx_conv_mesh_desc d = {.res = 48};
        vx_svo_scene a, b;
        vx_error err = {0};
        vx_conv_mesh_gpu_stats st;
        CHECK(vx_conv_mesh(&d, &g.m, &a, NULL, &err) == VX_OK);
        d.backend = vx_conv_mesh_gpu_backend(mg);
        vx_conv_mesh_gpu_set_build(mg, VX_CONV_MESH_GPU_BUILD_GPU_POOLS);
        CHECKF(vx_conv_mesh(&d, &g.m, &b, NULL, &err) == VX_OK, "gpu pools: %s", err.msg);
        vx_conv_mesh_gpu_set_build(mg, VX_CONV_MESH_GPU_BUILD_GPU);
        vx_conv_mesh_gpu_last_stats(mg, &st);
        uint8_t *da = NULL, *db = NULL;
        size_t na = 0, nb = 0;
        CHECK(vx_svo_write(&a, NULL, &da, &na, &err) == VX_OK && vx_svo_write(&b, NULL, &db, &nb, &err) == VX_OK);
        CHECKF(na == nb && na && memcmp(da, db, na) == 0, "gpu pools: the file differs from the CPU path's");
        CHECKF(st.run_records > 0 && st.laid_words == 0 && !st.build_fallback, "gpu pools: %llu records, %llu words laid out",
               (unsigned long long)st.run_records, (unsigned long long)st.laid_words);
        free(da);
        free(db);
        vx_svo_scene_free(&a);
        vx_svo_scene_free(&b);
    }
    gen_free(&g);
}

/* Materials that sample their metallic-roughness and emissive textures per
 * cell (tests/convert/mesh_tex_gltf.h): the GPU samples them (its stats say
 * so) and gives the CPU path's file, in one process and over shares; uniform
 * textures (folded into the factors, not sampled) give the same ids without
 * sampling. */
static void test_textured_materials(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    uint8_t mr[4 * TEXG_N * TEXG_N], em[4 * TEXG_N * TEXG_N];
    texg_split(mr, em);
    for (int uniform = 0; uniform < 2; uniform++) {
        if (uniform)
            for (int i = 0; i < TEXG_N * TEXG_N; i++) mr[4 * i + 1] = 40, mr[4 * i + 2] = 200, em[4 * i] = 90, em[4 * i + 1] = 30;
        vx_gltf_mesh m;
        vx_error err = {0};
        vx_result r = texg_read(kTexgSplitMat, mr, em, &m, &err);
        CHECKF(r == VX_OK, "%s", err.msg);
        if (r) continue;
        vx_conv_mesh_desc d = {.res = 16}, dg = d;
        dg.backend = vx_conv_mesh_gpu_backend(mg);
        vx_svo_scene a, b;
        REQUIRE(vx_conv_mesh(&d, &m, &a, NULL, &err) == VX_OK);
        REQUIRE(vx_conv_mesh(&dg, &m, &b, NULL, &err) == VX_OK);
        vx_conv_mesh_gpu_stats st;
        vx_conv_mesh_gpu_last_stats(mg, &st);
        CHECKF(st.sampled_materials == (uniform ? 0u : 1u), "%s textures: sampled_materials %u", uniform ? "uniform" : "split",
               st.sampled_materials);
        CHECKF(st.cells > 0, "%s textures: no cells voxelized on the GPU", uniform ? "uniform" : "split");
        uint8_t *da = NULL, *db = NULL;
        size_t na = 0, nb = 0;
        CHECK(vx_svo_write(&a, NULL, &da, &na, &err) == VX_OK && vx_svo_write(&b, NULL, &db, &nb, &err) == VX_OK);
        CHECKF(na == nb && na && memcmp(da, db, na) == 0, "%s textures: the GPU file differs from the CPU's",
               uniform ? "uniform" : "split");
        CHECKF(a.material_count >= (uniform ? 1u : 4u), "%u records", a.material_count);
        fprintf(stderr, "  %s textures: %u records, %zu bytes, equal: %d\n", uniform ? "uniform" : "split", a.material_count, na,
                na == nb && memcmp(da, db, na) == 0);
        free(da);
        free(db);
        vx_svo_scene_free(&a);
        vx_svo_scene_free(&b);
        /* over two shares (the GPU's own boxes: where the GPU voxelizes) */
        CHECK(same_shares(&m, 16, 0, 2, uniform ? "uniform textures" : "split textures"));
        /* with normals at 32, the trees built on the GPU (same_svo's checks) */
        if (!uniform) CHECK(same_svo(&m, 32, 0, true, "split textures"));
        vx_gltf_mesh_free(&m);
    }
    /* an emission sampled per channel (mesh_scene_test's test_emissive_hue): every channel of a white factor
     * (the block 6^3), then only R and G of (1 0.5 0) (6^2): the ids and records are the CPU path's */
    static const struct {
        const char* mat;
        uint8_t full[3];
        const char* what;
    } hues[] = {{TEXG_HUE_MAT("1,1,1"), {0, 0, 255}, "emissive hues, factor 1 1 1"},
                {TEXG_HUE_MAT("1,0.5,0"), {255, 255, 255}, "emissive hues, factor 1 0.5 0"}};
    for (size_t h = 0; h < sizeof hues / sizeof hues[0]; h++) {
        memset(mr, 255, sizeof mr);
        texg_hue(hues[h].full, em);
        vx_gltf_mesh m;
        vx_error err = {0};
        vx_result r = texg_read(hues[h].mat, mr, em, &m, &err);
        CHECKF(r == VX_OK, "%s", err.msg);
        if (r) continue;
        vx_svo_scene a;
        REQUIRE(vx_conv_mesh(&(vx_conv_mesh_desc){.res = 16}, &m, &a, NULL, &err) == VX_OK);
        uint32_t emitting = 0;
        for (uint32_t k = 0; k < a.material_count; k++) emitting += vx_svo_material_resolve(&a.materials[k]).emission > 0;
        CHECKF(emitting >= 4, "%s: %u emitting records", hues[h].what, emitting);
        vx_svo_scene_free(&a);
        CHECK(same_svo(&m, 16, 0, false, hues[h].what));
        vx_conv_mesh_gpu_stats st;
        vx_conv_mesh_gpu_last_stats(mg, &st);
        CHECKF(st.sampled_materials == 1, "%s: sampled_materials %u", hues[h].what, st.sampled_materials);
        CHECK(same_svo(&m, 48, 0, true, hues[h].what));
        CHECK(same_shares(&m, 32, 0, 2, hues[h].what));
        vx_gltf_mesh_free(&m);
    }
}

int main(void) {
    vx_error err = {0};
    static char why[256];
    if ((gpu_skip = vx_test_gpu_open((vx_gpu_desc){0}, false, &gpu))) {
    } else if (vx_conv_mesh_gpu_create(gpu, NULL, &mg, &err)) {
        /* only a device without float64 is a reason to skip */
        if (err.code != VX_ERR_UNSUPPORTED) {
            fprintf(stderr, "vx_conv_mesh_gpu_create: %s\n", err.msg);
            return 1;
        }
        snprintf(why, sizeof why, "%s", err.msg);
        gpu_skip = why;
    }
    RUN(test_refusals);
    RUN(test_textured_materials);
    RUN(test_lattice);
    RUN(test_random);
    RUN(test_collisions);
    RUN(test_solid);
    RUN(test_corpus);
    vx_conv_mesh_gpu_destroy(mg);
    if (gpu) vx_gpu_destroy(gpu);
    return vx_test_finish();
}
