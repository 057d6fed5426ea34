/* tests/probes/test_probes_gpu.c - the GPU bake and GPU probe renderer
 * against independent paths: analytic box distances, the furnace, the CPU
 * bake and CPU renderer (statistically where the random streams differ),
 * determinism and sharding. Skipped without a Vulkan device. */
#include <dlfcn.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "probes/probes.h"
#include "tests/probes/probe_scenes.h"
#include "tests/test.h"
#include "tests/test_vox.h"
#include "tests/gpu_test.h"
#include "tests/fail_alloc.h"

static const double PI = 3.14159265358979323846;
static vx_gpu* gpu;
static const char* gpu_skip;

static vx_render_scene* scene_on_gpu(const vx_svo_scene* s) {
    vx_render_scene* rs = NULL;
    vx_error err = {0};
    if (vx_render_scene_create(gpu, s, &rs, &err)) fprintf(stderr, "  scene: %s\n", err.msg);
    return rs;
}

static void test_gpu_box_distances(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene s;
    box_scene(&s, 16, 5);
    vx_render_scene* rs = scene_on_gpu(&s);
    REQUIRE(rs);
    vx_probe_set ps;
    vx_error err = {0};
    vx_result r = vx_probe_bake_gpu(rs, &s, &(vx_probe_bake_desc){.grid = {1, 1, 1}, .res = 32, .spp = 1, .bounces = -1},
                                    &ps, &err);
    if (r) fprintf(stderr, "  %s\n", err.msg);
    REQUIRE(r == VX_OK);
    double worst = 0;
    int inward = 0;
    uint32_t n = ps.res;
    for (uint32_t j = 0; j < n; j++)
        for (uint32_t i = 0; i < n; i++) {
            double dir[3], nr[3];
            vx_probe_texel_dir(n, i, j, dir);
            double m = fmax(fabs(dir[0]), fmax(fabs(dir[1]), fabs(dir[2])));
            size_t b = (size_t)(j + 1) * (n + 2) + i + 1;
            worst = fmax(worst, fabs(ps.distance[b] * ps.dist_step - 7.0 / m));
            vx_probe_oct_unpack16(ps.normal[b], nr);
            inward += nr[0] * dir[0] + nr[1] * dir[1] + nr[2] * dir[2] < -0.5;
        }
    /* float traversal: within the quantisation plus one code for float rounding near a half step */
    fprintf(stderr, "  GPU: max |distance - analytic| = %.3g (quantisation %.3g, step %.3g)\n", worst,
            ps.dist_max_error, ps.dist_step);
    CHECK(worst <= ps.dist_max_error + ps.dist_step);
    /* rays through a wall's edge (both planes crossed within float rounding)
     * may report the side face: 8 of these 1024 texels on lavapipe */
    fprintf(stderr, "  GPU: %d of %u normals point inward\n", inward, n * n);
    CHECK(inward >= (int)(n * n) * 98 / 100);
    vx_probe_set_free(&ps);
    vx_render_scene_destroy(rs);
    vx_svo_scene_free(&s);
}

static void test_gpu_furnace(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene s;
    ts_scene(&s, NULL, 0, NULL, 0);
    vx_render_scene* rs = scene_on_gpu(&s);
    REQUIRE(rs);
    vx_probe_bake_desc d = {.grid = {2, 1, 1}, .bounds_set = true, .bounds_hi = {2, 1, 1}, .res = 32, .spp = 2,
                            .sky = {0.8, 0.5, 0.25}};
    vx_probe_set ps;
    vx_error err = {0};
    REQUIRE(vx_probe_bake_gpu(rs, &s, &d, &ps, &err) == VX_OK);
    double worst = 0;
    size_t ni = vx__bsq_test(VX_PROBE_IRR_RES);
    for (size_t p = 0; p < 2; p++)
        for (size_t t = 0; t < ni; t++)
            for (int c = 0; c < 3; c++)
                worst = fmax(worst, fabs(vx_probe_half_to_float(ps.irradiance[(p * ni + t) * 3 + c]) / (PI * d.sky[c]) - 1));
    fprintf(stderr, "  GPU furnace: max relative irradiance error %.3g\n", worst);
    CHECK(worst < 0.01);
    vx_probe_set_free(&ps);
    vx_render_scene_destroy(rs);
    vx_svo_scene_free(&s);
}

/* GPU vs CPU bake of the lit room; then determinism and shards on the GPU. */
static void test_gpu_vs_cpu_bake(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene s;
    room_scene(&s);
    vx_render_scene* rs = scene_on_gpu(&s);
    REQUIRE(rs);
    /* the grid's cell centres in the room's box [0,12]^3 (bounds_set: over the scene's own bounds the grid
     * reaches out of the box), on cell boundaries (below) */
    vx_probe_bake_desc d = {.grid = {2, 2, 2}, .bounds_set = true, .bounds_hi = {12, 12, 12}, .res = 16, .spp = 32,
                            .seed = 42, .threads = 2};
    vx_probe_set c, g;
    vx_error err = {0};
    REQUIRE(vx_probe_bake(&s, &d, &c, &err) == VX_OK);
    REQUIRE(vx_probe_bake_gpu(rs, &s, &d, &g, &err) == VX_OK);
    REQUIRE(c.count == g.count && c.res == g.res);
    size_t nt = vx__bsq_test(c.res) * c.count, same_hit = 0, dist_ok = 0, nrm_same = 0, texels = 0;
    double sum_c[3] = {0}, sum_g[3] = {0};
    for (size_t t = 0; t < nt; t++) {
        texels++;
        bool hc = c.distance[t] != VX_PROBE_DIST_MISS, hg = g.distance[t] != VX_PROBE_DIST_MISS;
        same_hit += hc == hg;
        dist_ok += abs((int)c.distance[t] - (int)g.distance[t]) <= 1;
        nrm_same += c.normal[t] == g.normal[t];
        for (int q = 0; q < 3; q++) {
            sum_c[q] += vx_probe_half_to_float(c.radiance[3 * t + q]);
            sum_g[q] += vx_probe_half_to_float(g.radiance[3 * t + q]);
        }
    }
    double worst_mean = 0;
    for (int q = 0; q < 3; q++) worst_mean = fmax(worst_mean, fabs(sum_g[q] / sum_c[q] - 1));
    /* irradiance maps: filtered, so nearly noise-free; compare their means per probe */
    size_t ni = vx__bsq_test(VX_PROBE_IRR_RES) * 3;
    double worst_irr = 0;
    for (uint32_t p = 0; p < c.count; p++) {
        double ec = 0, eg = 0;
        for (size_t i = 0; i < ni; i++)
            ec += vx_probe_half_to_float(c.irradiance[p * ni + i]), eg += vx_probe_half_to_float(g.irradiance[p * ni + i]);
        if (ec > 0) worst_irr = fmax(worst_irr, fabs(eg / ec - 1));
    }
    fprintf(stderr,
            "  GPU vs CPU bake: %zu texels, same hit %.4f, distance within 1 code %.4f, same normal %.4f, "
            "radiance mean rel. diff %.4f, worst probe irradiance mean rel. diff %.4f\n",
            texels, (double)same_hit / texels, (double)dist_ok / texels, (double)nrm_same / texels, worst_mean, worst_irr);
    CHECK(same_hit >= texels * 995 / 1000);
    CHECK(dist_ok >= texels * 99 / 100);
    /* The probes sit on cell boundaries here, so many texel rays meet voxel
     * edges exactly, where float and double pick different faces: 2-3% of
     * the texels on lavapipe, 4.1% on an H200 (FMA contraction). So a normal
     * may differ only where the CPU's hit point (the room's cells are unit
     * cubes at integer coordinates) lies on an edge, within the distance's
     * quantisation, and both faces must face the ray. */
    uint32_t n = c.res;
    size_t per = (size_t)(n + 2) * (n + 2), differ = 0, off_edge = 0, facing_away = 0;
    double tol = 2 * (c.dist_max_error + c.dist_step);
    for (uint32_t p = 0; p < c.count; p++)
        for (uint32_t j = 0; j < n; j++)
            for (uint32_t i = 0; i < n; i++) {
                size_t b = p * per + (size_t)(j + 1) * (n + 2) + i + 1;
                if (c.normal[b] == g.normal[b] || c.distance[b] == VX_PROBE_DIST_MISS ||
                    g.distance[b] == VX_PROBE_DIST_MISS)
                    continue;
                differ++;
                double dir[3], nc[3], ng[3];
                vx_probe_texel_dir(n, i, j, dir);
                int near = 0;
                for (int k = 0; k < 3; k++) {
                    double x = c.probes[c.first + p].pos[k] + dir[k] * c.distance[b] * c.dist_step;
                    near += fabs(x - round(x)) <= tol;
                }
                off_edge += near < 2;
                vx_probe_oct_unpack16(c.normal[b], nc);
                vx_probe_oct_unpack16(g.normal[b], ng);
                facing_away += nc[0] * dir[0] + nc[1] * dir[1] + nc[2] * dir[2] >= 0 ||
                               ng[0] * dir[0] + ng[1] * dir[1] + ng[2] * dir[2] >= 0;
            }
    fprintf(stderr, "  normals: %zu interior texels differ, %zu of them off a cell edge, %zu facing away\n", differ,
            off_edge, facing_away);
    CHECK(off_edge == 0);
    CHECK(facing_away == 0);
    CHECK(nrm_same >= texels * 90 / 100); /* the room's edges are a small share of what the probes see */
    CHECK(worst_mean < 0.03);
    CHECK(worst_irr < 0.05);

    /* same seed -> same bytes; another seed -> other noise */
    vx_probe_set g2, g3;
    REQUIRE(vx_probe_bake_gpu(rs, &s, &d, &g2, &err) == VX_OK);
    d.seed = 43;
    REQUIRE(vx_probe_bake_gpu(rs, &s, &d, &g3, &err) == VX_OK);
    d.seed = 42;
    uint8_t *a, *b, *x;
    size_t na, nb, nx;
    REQUIRE(bytes_of(&g, &a, &na) && bytes_of(&g2, &b, &nb) && bytes_of(&g3, &x, &nx));
    CHECK(na == nb && !memcmp(a, b, na));
    CHECK(na == nx && memcmp(a, x, na));
    /* shards (one resumed in two steps) merged in shuffled order == one GPU bake */
    vx_probe_set sh[3];
    uint32_t cuts[4] = {0, 3, 5, 8};
    for (int i = 0; i < 3; i++) {
        d.first = cuts[i], d.count = cuts[i + 1] - cuts[i];
        if (i == 0) {
            REQUIRE(vx_probe_place(&s, &d, &sh[0], &err) == VX_OK);
            REQUIRE(vx_probe_bake_more_gpu(rs, &s, &d, &sh[0], 1, &err) == VX_OK);
            REQUIRE(vx_probe_bake_more_gpu(rs, &s, &d, &sh[0], 3, &err) == VX_OK);
        } else {
            REQUIRE(vx_probe_bake_gpu(rs, &s, &d, &sh[i], &err) == VX_OK);
        }
    }
    const vx_probe_set* parts[3] = {&sh[1], &sh[2], &sh[0]};
    vx_probe_set m;
    REQUIRE(vx_probe_merge(parts, 3, NULL, &m, &err) == VX_OK);
    uint8_t* dm;
    size_t nm;
    REQUIRE(bytes_of(&m, &dm, &nm));
    CHECK(nm == na && !memcmp(dm, a, na));
    free(a), free(b), free(x), free(dm);
    for (int i = 0; i < 3; i++) vx_probe_set_free(&sh[i]);
    vx_probe_set_free(&m), vx_probe_set_free(&g2), vx_probe_set_free(&g3);
    vx_probe_set_free(&c), vx_probe_set_free(&g);
    vx_render_scene_destroy(rs);
    vx_svo_scene_free(&s);
}

/* The bake's beam (probe_beam.comp: per probe and block of 4x4 texels a
 * distance before which no ray from the probe through the block meets a
 * non-empty node; the camera and centre rays start their walk there) against
 * the walk from the probe (vx_probe_bake_desc.no_beam): the same cells, so the
 * same bytes, over one and several dispatches (spp 40: llvmpipe traces 32
 * samples a dispatch), with Russian roulette (4 bounces), no bounce, no sun, a
 * room with emitters (the lights' code) and without, and narrow beams (R=64);
 * and the estimate against the CPU bake (statistically: other random streams). */
static void test_gpu_bake_beam(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene s;
    room_scene(&s);
    vx_render_scene* rs = scene_on_gpu(&s);
    REQUIRE(rs);
    struct { uint32_t spp; int32_t bounces; bool no_sun; uint32_t res; } cfg[] = {
        {40, 0, false, 16}, {6, 4, false, 16}, {8, -1, false, 16}, {8, 2, true, 16}, {2, 0, false, 64}, {6, 0, false, 32}};
    vx_error err = {0};
    for (size_t k = 0; k < sizeof cfg / sizeof cfg[0]; k++) {
        if (k == 5) {
            /* the block plain white: no emitter, no lights' code in the kernel */
            vx_render_scene_destroy(rs);
            for (uint32_t i = 0; i < s.material_count; i++) free(s.materials[i].dict);
            free(s.materials);
            s.materials = NULL, s.material_count = 0;
            REQUIRE(rs = scene_on_gpu(&s));
        }
        /* the probes inside the room (the grid's cell centres in its box; over the scene's bounds the grid
         * reaches out of it), which sees the room's walls in most texels */
        vx_probe_bake_desc d = {.grid = {2, 2, 2}, .bounds_set = true, .bounds_hi = {12, 12, 12}, .res = cfg[k].res,
                                .spp = cfg[k].spp, .bounces = cfg[k].bounces, .no_sun = cfg[k].no_sun, .seed = 7 + k,
                                .threads = 2};
        vx_probe_set a, b;
        REQUIRE(vx_probe_bake_gpu(rs, &s, &d, &a, &err) == VX_OK);
        d.no_beam = true;
        REQUIRE(vx_probe_bake_gpu(rs, &s, &d, &b, &err) == VX_OK);
        uint8_t *x, *y;
        size_t nx, ny;
        REQUIRE(bytes_of(&a, &x, &nx) && bytes_of(&b, &y, &ny));
        size_t nt = vx__bsq_test(a.res) * a.count, hits = 0, lit = 0;
        for (size_t t = 0; t < nt; t++)
            hits += a.distance[t] != VX_PROBE_DIST_MISS, lit += vx_probe_half_to_float(a.radiance[3 * t]) > 0;
        fprintf(stderr, "  beam vs none: R=%u, spp %u, bounces %d%s: %zu of %zu texels hit, %zu lit, %s\n",
                cfg[k].res, cfg[k].spp, cfg[k].bounces, cfg[k].no_sun ? ", no sun" : "", hits, nt, lit,
                nx == ny && !memcmp(x, y, nx) ? "same bytes" : "BYTES DIFFER");
        CHECK(hits > nt / 4 && hits < nt); /* walls and floor, and the open sides' sky */
        CHECK(lit > nt / 2);
        CHECK(nx == ny && !memcmp(x, y, nx));
        if (k == 0) {
            /* the loop's estimate against the CPU bake's (double precision, own random streams) */
            vx_probe_set c;
            d.no_beam = false;
            REQUIRE(vx_probe_bake(&s, &d, &c, &err) == VX_OK);
            double sum_c[3] = {0}, sum_g[3] = {0};
            for (size_t t = 0; t < nt; t++)
                for (int q = 0; q < 3; q++) {
                    sum_c[q] += vx_probe_half_to_float(c.radiance[3 * t + q]);
                    sum_g[q] += vx_probe_half_to_float(a.radiance[3 * t + q]);
                }
            double worst = 0;
            for (int q = 0; q < 3; q++) worst = fmax(worst, fabs(sum_g[q] / sum_c[q] - 1));
            fprintf(stderr, "  beam vs CPU bake: radiance mean rel. diff %.4f\n", worst);
            CHECK(worst < 0.03);
            vx_probe_set_free(&c);
        }
        free(x), free(y);
        vx_probe_set_free(&a), vx_probe_set_free(&b);
    }
    vx_render_scene_destroy(rs);
    vx_svo_scene_free(&s);
}

/* The bake's sun rays clipped by the sun's light-space depth map (render/gpu.h
 * vx__render_scene_sun_map, probe.comp SMAP) against the whole rays
 * (vx_probe_bake_desc.no_shadow_map): the same bytes, for the room (its
 * emitter: the lights' code, nee()) and for sparse random models drawn as
 * instances turned a quarter, mirrored, turned about a skew axis and scaled,
 * on a floor, under lights along and against the axes, grazing a face and
 * diagonal; the host-filtered bake too. The sun must matter (a bake without
 * it differs) and the map must have been used (stats.sun_map_side). The GPU
 * path tracer (vx_probe_render_gpu, pathtrace and pathtrace-indirect) the
 * same: the same pixel bits with and without (base.no_shadow_map). */
static void test_gpu_bake_sun_map(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene scenes[2];
    room_scene(&scenes[0]);
    vx_svo_model m[2];
    REQUIRE(ts_random_model(&m[0], 12, 10, 8, 25, 5) == VX_OK);
    REQUIRE(ts_random_model(&m[1], 40, 40, 1, 100, 1) == VX_OK);
    const double quarter[9] = {0, -1, 0, 1, 0, 0, 0, 0, 1}, mirror[9] = {-1, 0, 0, 0, 1, 0, 0, 0, 1};
    /* 35 degrees about (1, 2, 3) / |.|, times 0.75 */
    double skew[9], ax[3] = {1, 2, 3}, n = sqrt(14.0), c = cos(35 * PI / 180), sn = sin(35 * PI / 180);
    for (int k = 0; k < 3; k++) ax[k] /= n;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double v = (i == j ? c : 0) + (1 - c) * ax[i] * ax[j];
            int e = 3 - i - j; /* the cross term's axis for i != j */
            if (i != j) v += ((j == (i + 1) % 3) ? -1 : 1) * sn * ax[e];
            skew[3 * i + j] = 0.75 * v;
        }
    vx_svo_instance in[5] = {ts_inst(0, NULL, 2, 3, 1), ts_inst(0, quarter, 30, 4, 1), ts_inst(0, mirror, 14, 26, 1),
                             ts_inst(0, skew, 26, 24, 3), ts_inst(1, NULL, 0, 0, 0)};
    ts_scene(&scenes[1], m, 2, in, 5);
    static const double lights[][3] = {{0.35, -0.45, 0.82}, {0, 0, 1}, {-1, 0, 0}, {1, 0.3, 1e-4}, {-0.6, 0.5, 0.2}, {0, 0, -1}};
    vx_error err = {0};
    for (int sc = 0; sc < 2; sc++) {
        vx_render_scene* rs = scene_on_gpu(&scenes[sc]);
        REQUIRE(rs);
        for (size_t li = 0; li < sizeof lights / sizeof lights[0]; li++) {
            vx_probe_bake_stats st = {0};
            vx_probe_bake_desc d = {.grid = {2, 2, 2}, .res = 16, .spp = 2, .bounces = 1, .seed = 3 + li,
                                    .threads = 2, .stats = &st, .host_filter = li == 2};
            memcpy(d.light_dir, lights[li], sizeof d.light_dir);
            vx_probe_set a, b, z;
            REQUIRE(vx_probe_bake_gpu(rs, &scenes[sc], &d, &a, &err) == VX_OK);
            uint32_t side = st.sun_map_side;
            d.no_shadow_map = true;
            REQUIRE(vx_probe_bake_gpu(rs, &scenes[sc], &d, &b, &err) == VX_OK);
            uint32_t side_off = st.sun_map_side;
            d.no_sun = true;
            REQUIRE(vx_probe_bake_gpu(rs, &scenes[sc], &d, &z, &err) == VX_OK);
            uint8_t *x, *y, *w;
            size_t nx, ny, nw;
            REQUIRE(bytes_of(&a, &x, &nx) && bytes_of(&b, &y, &ny) && bytes_of(&z, &w, &nw));
            bool same = nx == ny && !memcmp(x, y, nx);
            fprintf(stderr, "  sun map: scene %d, light %zu%s: map %u texels a side, %s\n", sc, li,
                    d.host_filter ? " (host filter)" : "", side, same ? "same bytes" : "BYTES DIFFER");
            CHECK(side >= 16 && side_off == 0);
            CHECK(same);
            CHECK(!(nw == nx && !memcmp(w, x, nx))); /* the sun's rays shape the bytes */
            if (li == 0 || li == 4) {
                /* the GPU path tracer's sun rays, under this set's light: the same pixel bits */
                vx_render_desc base = {.width = 24, .height = 18};
                vx_probe_render_stats rst = {0};
                vx_probe_render_desc rd = {.base = &base, .spp = 8, .stats = &rst,
                                           .mode = li ? VX_PROBE_RENDER_PT_INDIRECT : VX_PROBE_RENDER_PATHTRACE};
                vx_render_image ia = {0}, ib = {0};
                REQUIRE(vx_probe_render_gpu(rs, &scenes[sc], &a, &rd, &ia, &err) == VX_OK);
                uint32_t rside = rst.sun_map_side;
                base.no_shadow_map = true;
                REQUIRE(vx_probe_render_gpu(rs, &scenes[sc], &a, &rd, &ib, &err) == VX_OK);
                size_t np = (size_t)base.width * base.height * 4;
                bool psame = ia.pixels && ib.pixels && !memcmp(ia.pixels, ib.pixels, np * sizeof(float));
                fprintf(stderr, "  sun map, path tracer: scene %d, light %zu: map %u texels a side, %s\n", sc, li, rside,
                        psame ? "same pixels" : "PIXELS DIFFER");
                CHECK(rside >= 16 && rst.sun_map_side == 0);
                CHECK(psame);
                vx_render_image_free(&ia), vx_render_image_free(&ib);
            }
            free(x), free(y), free(w);
            vx_probe_set_free(&a), vx_probe_set_free(&b), vx_probe_set_free(&z);
        }
        vx_render_scene_destroy(rs);
        vx_svo_scene_free(&scenes[sc]);
    }
    CHECK(vx_gpu_validation_errors(gpu) == 0);
}

/* The bake's one-walk kernel (probe.comp bake_one(), where a scene has no lights or sampled emitters and no
 * metal or glass: every ray at one trace_scene call of a loop) against bake() (vx_probe_bake_desc.kernel
 * VX_PROBE_KERNEL_ONE_WALK, VX_PROBE_KERNEL_INLINE; the default takes the one the driver has ready first):
 * the same bytes, with the beam and without, the sun's depth map and
 * without, one to three bounces (Russian roulette from the third), a second dispatch of the same texels
 * (samples past the lavapipe chunk), on a box, on rotated, scaled and mirrored instances and in a room with
 * emissive cells; a scene with glass and metal keeps bake(). The sums must also be the sun's: with the sun
 * off the bytes differ. */
static void test_gpu_bake_one_walk(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene scenes[4];
    box_scene(&scenes[0], 16, 5);
    vx_svo_model m[2];
    REQUIRE(ts_random_model(&m[0], 12, 10, 8, 25, 5) == VX_OK);
    REQUIRE(ts_random_model(&m[1], 40, 40, 1, 100, 1) == VX_OK);
    const double quarter[9] = {0, -1, 0, 1, 0, 0, 0, 0, 1}, mirror[9] = {-1, 0, 0, 0, 1, 0, 0, 0, 1};
    const double half[9] = {0.5, 0, 0, 0, 0.5, 0, 0, 0, 0.5};
    vx_svo_instance in[4] = {ts_inst(0, NULL, 2, 3, 1), ts_inst(0, quarter, 30, 4, 1), ts_inst(0, mirror, 14, 26, 1),
                             ts_inst(1, half, 0, 0, 0)};
    ts_scene(&scenes[1], m, 2, in, 4);
    room_scene(&scenes[2]); /* emissive cells: the one-walk kernel still */
    cells_scene(&scenes[3], 12, glass_room_cell); /* glass and metal: bake() */
    scenes[3].palette[3] = 0xFF80A0C0u, scenes[3].palette[4] = 0xFFE0F0FFu, scenes[3].palette[5] = 0xFF4080E0u;
    static const char* const glass[] = {"_type", "_glass", "_ri", "1.5", "_rough", "0"};
    static const char* const metal[] = {"_type", "_metal", "_metal", "1", "_rough", "0.3"};
    add_material(&scenes[3], 4, glass, 3);
    add_material(&scenes[3], 3, metal, 3);
    static const struct {
        int32_t bounces;
        uint32_t spp;
        bool no_beam, no_shadow_map;
        double light[3];
    } cases[] = {
        {1, 3, false, false, {0.35, -0.45, 0.82}},
        {3, 6, true, true, {-0.6, 0.5, 0.2}},
        {2, 40, false, true, {1, 0.3, 1e-4}}, /* 40 spp: two dispatches on lavapipe (chunks of 32) */
    };
    vx_error err = {0};
    for (int sc = 0; sc < 4; sc++) {
        vx_render_scene* rs = scene_on_gpu(&scenes[sc]);
        REQUIRE(rs);
        for (size_t k = 0; k < (sc >= 2 ? 1 : sizeof cases / sizeof cases[0]); k++) {
            vx_probe_bake_stats sa = {0}, sb = {0}, sc0 = {0};
            vx_probe_bake_desc d = {.grid = {2, 2, 2}, .res = 16, .spp = cases[k].spp, .bounces = cases[k].bounces,
                                    .seed = 7 + k, .threads = 2, .stats = &sa, .no_beam = cases[k].no_beam,
                                    .no_shadow_map = cases[k].no_shadow_map, .kernel = VX_PROBE_KERNEL_ONE_WALK};
            memcpy(d.light_dir, cases[k].light, sizeof d.light_dir);
            vx_probe_set a, b, c, z;
            REQUIRE(vx_probe_bake_gpu(rs, &scenes[sc], &d, &a, &err) == VX_OK);
            d.kernel = VX_PROBE_KERNEL_INLINE, d.stats = &sb;
            REQUIRE(vx_probe_bake_gpu(rs, &scenes[sc], &d, &b, &err) == VX_OK);
            d.kernel = VX_PROBE_KERNEL_AUTO, d.stats = &sc0; /* either, both made by now */
            REQUIRE(vx_probe_bake_gpu(rs, &scenes[sc], &d, &c, &err) == VX_OK);
            d.stats = NULL, d.no_sun = true;
            REQUIRE(vx_probe_bake_gpu(rs, &scenes[sc], &d, &z, &err) == VX_OK);
            uint8_t *x, *y, *v, *w;
            size_t nx, ny, nv, nw;
            REQUIRE(bytes_of(&a, &x, &nx) && bytes_of(&b, &y, &ny) && bytes_of(&c, &v, &nv) && bytes_of(&z, &w, &nw));
            bool same = nx == ny && !memcmp(x, y, nx), same_auto = nv == nx && !memcmp(v, x, nx);
            fprintf(stderr, "  one walk: scene %d, case %zu: kernels %s / %s / auto %s, %s, auto's %s\n", sc, k,
                    sa.one_walk ? "one walk" : "four walks", sb.one_walk ? "one walk" : "four walks",
                    sc0.one_walk ? "one walk" : "four walks", same ? "same bytes" : "BYTES DIFFER",
                    same_auto ? "the same" : "DIFFER");
            CHECKF(sa.one_walk == (sc != 3), "scene %d: the one-walk kernel %s", sc, sa.one_walk ? "ran" : "did not run");
            CHECK(!sb.one_walk);
            /* both kernels were made (cached in the device) before the third bake: it takes bake() */
            CHECK(!sc0.one_walk);
            CHECK(same && same_auto);
            CHECK(!(nw == nx && !memcmp(w, x, nx))); /* the sun's rays shape the bytes */
            free(x), free(y), free(v), free(w);
            vx_probe_set_free(&a), vx_probe_set_free(&b), vx_probe_set_free(&c), vx_probe_set_free(&z);
        }
        vx_render_scene_destroy(rs);
        vx_svo_scene_free(&scenes[sc]);
    }
    CHECK(vx_gpu_validation_errors(gpu) == 0);
}

/* The bake's stratified first bounce (probe.comp STRAT, the default) against the independent one
 * (vx_probe_bake_desc.independent_bounce, main's estimator) and the CPU bake: each sample's
 * direction is still cosine-distributed, so the mean is the CPU's; a texel's samples cover the
 * hemisphere evenly, so its noise is lower. Noise: half the squared difference of two seeds' radiance,
 * summed over the texels; the independent GPU estimator's is the CPU's (other random streams). */
static double bake_noise(vx_render_scene* rs, const vx_svo_scene* s, vx_probe_bake_desc d, bool cpu, double* mean,
                         double* irr_noise) {
    vx_probe_set a, b;
    vx_error err = {0};
    d.seed = 11;
    bool ok = (cpu ? vx_probe_bake(s, &d, &a, &err) : vx_probe_bake_gpu(rs, s, &d, &a, &err)) == VX_OK;
    d.seed = 12;
    ok = ok && (cpu ? vx_probe_bake(s, &d, &b, &err) : vx_probe_bake_gpu(rs, s, &d, &b, &err)) == VX_OK;
    if (!ok) {
        fprintf(stderr, "  %s\n", err.msg);
        return -1;
    }
    double noise = 0, sum = 0;
    size_t n = vx__bsq_test(a.res) * a.count * 3;
    for (size_t i = 0; i < n; i++) {
        double x = vx_probe_half_to_float(a.radiance[i]), y = vx_probe_half_to_float(b.radiance[i]);
        noise += 0.5 * (x - y) * (x - y), sum += x + y;
    }
    *mean = sum / (2.0 * (double)n);
    /* the irradiance maps integrate every texel: there the texels' correlations count too */
    size_t ni = vx__bsq_test(VX_PROBE_IRR_RES) * 3 * a.count;
    *irr_noise = 0;
    for (size_t i = 0; i < ni; i++) {
        double x = vx_probe_half_to_float(a.irradiance[i]), y = vx_probe_half_to_float(b.irradiance[i]);
        *irr_noise += 0.5 * (x - y) * (x - y);
    }
    vx_probe_set_free(&a), vx_probe_set_free(&b);
    return noise;
}

static void test_gpu_bake_strata(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene s;
    room_scene(&s);
    vx_render_scene* rs = scene_on_gpu(&s);
    REQUIRE(rs);
    /* inside the room: the grid's cell centres in its box (over the scene's bounds it reaches out of it) */
    vx_probe_bake_desc d = {.grid = {2, 1, 1}, .bounds_set = true, .bounds_hi = {12, 12, 12}, .res = 32, .spp = 64,
                            .threads = 2};
    double m_st, m_in, m_cpu, i_st, i_in, i_cpu;
    double n_st = bake_noise(rs, &s, d, false, &m_st, &i_st);
    d.independent_bounce = true;
    double n_in = bake_noise(rs, &s, d, false, &m_in, &i_in);
    double n_cpu = bake_noise(rs, &s, d, true, &m_cpu, &i_cpu);
    REQUIRE(n_st >= 0 && n_in >= 0 && n_cpu > 0);
    fprintf(stderr,
            "  stratified / independent / CPU bake: mean %.5f / %.5f / %.5f, noise %.4g / %.4g / %.4g, "
            "irradiance noise %.4g / %.4g / %.4g\n",
            m_st, m_in, m_cpu, n_st, n_in, n_cpu, i_st, i_in, i_cpu);
    CHECK(fabs(m_st / m_cpu - 1) < 0.02);
    CHECK(fabs(m_in / m_cpu - 1) < 0.02);
    CHECK(n_in > 0.8 * n_cpu && n_in < 1.25 * n_cpu); /* the same estimator as the CPU's */
    CHECK(n_st < 0.9 * n_in);                         /* stratified: less noise */
    /* neighbouring texels share their strata's order: their noise is correlated, yet the irradiance maps that
     * sum them must not get noisier than the independent estimator's (the GPU's or the CPU's) */
    CHECK(i_st < 1.25 * fmin(i_in, i_cpu));
    /* the two estimators differ, and each is deterministic */
    vx_probe_set a, b;
    vx_error err = {0};
    d.seed = 11;
    REQUIRE(vx_probe_bake_gpu(rs, &s, &d, &a, &err) == VX_OK);
    d.independent_bounce = false;
    REQUIRE(vx_probe_bake_gpu(rs, &s, &d, &b, &err) == VX_OK);
    CHECK(memcmp(a.radiance, b.radiance, vx__bsq_test(a.res) * a.count * 6) != 0);
    vx_probe_set_free(&a), vx_probe_set_free(&b);
    vx_render_scene_destroy(rs);
    vx_svo_scene_free(&s);
}

/* Half a and b as integers on one line (sign-magnitude to ordered). */
static int half_ord(uint16_t h) { return (h & 0x8000u) ? -(int)(h & 0x7FFFu) : (int)h; }

/* The GPU filtering (probe_filter.comp) against the host's (vx__probe_finish,
 * the CPU bake's code) of the same traced radiance and distances: the same
 * device traces both bakes, so only the filtering differs. Quantised values
 * (halfs, distance codes, snorm16 normals) may differ by one step only where
 * float and double rounding straddle a tie; sums by float rounding. Then the
 * batch split: any batch size gives the same bytes. A grid with moved and
 * disabled probes, at res 16 (a 1x1 min-distance map: padding) and 32. */
static void test_gpu_filter_vs_host(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene s;
    room_scene(&s);
    vx_render_scene* rs = scene_on_gpu(&s);
    REQUIRE(rs);
    vx_error err = {0};
    for (uint32_t res = 16; res <= 32; res += 16) {
        /* probes one apart from (5.8, 6, 1.5), in the emissive block [5,7]x[5,7]x[0,3] with all of its
         * half cell (disabled); (6.8, 6, 1.5) in it too, but with free space within half a cell (moved) */
        vx_probe_bake_desc d = {.grid = {3, 3, 3}, .bounds_set = true, .bounds_lo = {5.3, 5.5, 1.0},
                                .bounds_hi = {8.3, 8.5, 4.0}, .res = res, .spp = 8, .seed = 11, .threads = 2};
        vx_probe_set h, g;
        vx_probe_bake_stats st = {0};
        d.host_filter = true;
        REQUIRE(vx_probe_bake_gpu(rs, &s, &d, &h, &err) == VX_OK);
        d.host_filter = false, d.stats = &st;
        REQUIRE(vx_probe_bake_gpu(rs, &s, &d, &g, &err) == VX_OK);
        d.stats = NULL;
        uint32_t states[3] = {0};
        for (uint32_t p = 0; p < g.probe_count; p++) states[g.probes[p].state]++;
        REQUIRE(states[VX_PROBE_DISABLED] >= 1 && states[VX_PROBE_MOVED] >= 1 && states[VX_PROBE_OK] >= 1);
        size_t nb = vx__bsq_test(res), lr = res / 16, nl = vx__bsq_test((uint32_t)lr);
        size_t ni = vx__bsq_test(VX_PROBE_IRR_RES) * 3, nm = vx__bsq_test(VX_PROBE_DIST_RES) * 2;
        size_t n = g.count, rad_diff = 0, rad_far = 0, nrm_diff = 0, nrm_far = 0, dist_diff = 0, dist_far = 0;
        size_t low_bad = 0, low_far = 0, zero_bad = 0;
        double irr_worst = 0, mom_worst = 0;
        for (size_t p = 0; p < n; p++) {
            bool off = g.probes[p].state == VX_PROBE_DISABLED;
            for (size_t t = 0; t < nb; t++) {
                for (int q = 0; q < 3; q++) {
                    int a = half_ord(g.radiance[(p * nb + t) * 3 + q]), b = half_ord(h.radiance[(p * nb + t) * 3 + q]);
                    rad_diff += a != b, rad_far += abs(a - b) > 1;
                    zero_bad += off && a != 0;
                }
                uint32_t a = g.normal[p * nb + t], b = h.normal[p * nb + t];
                int du = (int16_t)(a & 0xFFFF) - (int16_t)(b & 0xFFFF), dv = (int16_t)(a >> 16) - (int16_t)(b >> 16);
                nrm_diff += a != b, nrm_far += abs(du) > 1 || abs(dv) > 1;
                int dd = (int)g.distance[p * nb + t] - (int)h.distance[p * nb + t];
                dist_diff += dd != 0, dist_far += abs(dd) > 1;
                zero_bad += off && (a || g.distance[p * nb + t]);
            }
            /* the min-distance map is exactly the minimum of the GPU's own codes */
            const uint16_t* dg = g.distance + p * nb;
            for (size_t lj = 0; lj < lr; lj++)
                for (size_t li = 0; li < lr; li++) {
                    uint16_t m = 0xFFFF;
                    for (size_t j = lj * 16; j < lj * 16 + 16; j++)
                        for (size_t i = li * 16; i < li * 16 + 16; i++) m = m < dg[(j + 1) * (res + 2) + i + 1] ? m : dg[(j + 1) * (res + 2) + i + 1];
                    low_bad += !off && g.low[p * nl + (lj + 1) * (lr + 2) + li + 1] != m;
                }
            for (size_t b = 0; b < nl; b++) {
                uint32_t si, sj;
                vx_probe_border_src((uint32_t)lr, (uint32_t)(b % (lr + 2)), (uint32_t)(b / (lr + 2)), &si, &sj);
                low_bad += g.low[p * nl + b] != g.low[p * nl + (sj + 1) * (lr + 2) + si + 1];
                low_far += abs((int)g.low[p * nl + b] - (int)h.low[p * nl + b]) > 1;
                zero_bad += off && g.low[p * nl + b];
            }
            for (size_t i = 0; i < ni; i++) {
                float a = vx_probe_half_to_float(g.irradiance[p * ni + i]), b = vx_probe_half_to_float(h.irradiance[p * ni + i]);
                /* one half step (2^-10 relative at most) plus float sums */
                irr_worst = fmax(irr_worst, fabs(a - b) / (fmax(fabs(a), fabs(b)) * 0x1p-10 + 1e-30));
                zero_bad += off && a != 0;
            }
            for (size_t i = 0; i < nm; i++) {
                double a = g.moments[p * nm + i], b = h.moments[p * nm + i];
                mom_worst = fmax(mom_worst, fabs(a - b) / (fmax(fabs(a), fabs(b)) + 1e-30));
                zero_bad += off && a != 0;
            }
        }
        size_t vals = n * nb;
        fprintf(stderr,
                "  res %u, %u probes (%u moved, %u disabled): GPU vs host filtering: radiance halfs %zu of %zu differ "
                "(%zu by more than one step), normals %zu (%zu by more than one code), distances %zu (%zu), min map %zu "
                "inconsistent, %zu more than one code off; irradiance worst %.3g half steps, moments worst relative "
                "%.3g; GPU busy %.0f%%\n",
                res, g.probe_count, states[VX_PROBE_MOVED], states[VX_PROBE_DISABLED], rad_diff, 3 * vals, rad_far,
                nrm_diff, nrm_far, dist_diff, dist_far, low_bad, low_far, irr_worst, mom_worst, 100 * st.busy);
        CHECK(rad_far == 0 && rad_diff <= 3 * vals / 1000);
        CHECK(nrm_far == 0 && nrm_diff <= vals / 1000);
        CHECK(dist_far == 0 && dist_diff <= vals / 1000);
        CHECK(low_bad == 0 && low_far == 0);
        CHECK(zero_bad == 0);
        CHECK(irr_worst <= 1.0);
        CHECK(mom_worst <= 1e-5);
        /* the GPU filtering downloads the file's maps only (plus a 16-byte flag block per batch) */
        size_t file_block = nb * 12 + nl * 2 + ni * 2 + nm * 4;
        CHECK(st.batches >= 1 && st.bytes_down <= (uint64_t)n * (file_block + 2) + 16 * st.batches);

        /* any batch split: the same bytes */
        uint8_t *a, *b;
        size_t na, nbytes;
        REQUIRE(bytes_of(&g, &a, &na));
        uint32_t batches[5] = {1, 4, 8, 12, 27}; /* 8, 12: full batches, a short one, the last quarter batch */
        for (int k = 0; k < 5; k++) {
            vx_probe_set x;
            d.batch = batches[k];
            REQUIRE(vx_probe_bake_gpu(rs, &s, &d, &x, &err) == VX_OK);
            REQUIRE(bytes_of(&x, &b, &nbytes));
            CHECKF(nbytes == na && !memcmp(a, b, na), "res %u, batches of %u probes: other bytes", res, batches[k]);
            free(b);
            vx_probe_set_free(&x);
        }
        free(a);
        vx_probe_set_free(&h), vx_probe_set_free(&g);
    }
    vx_render_scene_destroy(rs);
    vx_svo_scene_free(&s);
}

/* One baker for many ranges (svo_bake's MPI batches, its single process):
 * ranges of views on one placement, baked out of order through one
 * vx_probe_baker, give the bytes of one vx_probe_bake_gpu call; a set of
 * another placement is refused. */
static void test_gpu_baker_ranges(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene s;
    room_scene(&s);
    vx_render_scene* rs = scene_on_gpu(&s);
    REQUIRE(rs);
    vx_error err = {0};
    vx_probe_bake_desc d = {.grid = {3, 3, 2}, .res = 16, .spp = 4, .seed = 5, .batch = 3};
    vx_probe_set one, placed;
    REQUIRE(vx_probe_bake_gpu(rs, &s, &d, &one, &err) == VX_OK);
    REQUIRE(vx_probe_place(&s, &d, &placed, &err) == VX_OK);
    vx_probe_baker* b = NULL;
    REQUIRE(vx_probe_baker_create(rs, &s, &d, &placed, &b, &err) == VX_OK);
    /* ranges [11, 18), [0, 4), [4, 11), the last in two runs (a resumed view) */
    uint32_t from[3] = {11, 0, 4}, to[3] = {18, 4, 11};
    vx_probe_set v[3];
    vx_probe_bake_stats st = {0};
    for (int i = 0; i < 3; i++) {
        v[i] = placed;
        v[i].first = from[i], v[i].count = 0;
        v[i].radiance = NULL, v[i].normal = NULL, v[i].distance = NULL, v[i].low = NULL, v[i].irradiance = NULL,
        v[i].moments = NULL;
        if (i == 2) {
            vx_probe_bake_desc d1 = d;
            d1.stats = &st;
            REQUIRE(vx_probe_baker_run(b, &d1, &v[i], from[i] + 2, &err) == VX_OK);
            CHECK(v[i].count == 2 && st.batches == 1 && st.setup == 0); /* the set-up was the first run's */
        }
        REQUIRE(vx_probe_baker_run(b, &d, &v[i], to[i], &err) == VX_OK);
        CHECK(v[i].count == to[i] - from[i]);
    }
    /* another placement's set (its own probes array) is refused */
    vx_probe_set other;
    REQUIRE(vx_probe_place(&s, &d, &other, &err) == VX_OK);
    CHECK(vx_probe_baker_run(b, &d, &other, 2, &err) == VX_ERR_INVALID_ARG);
    vx_probe_baker_destroy(b);
    /* the views share placed's probes: merge copies of them */
    vx_probe_set parts[3];
    const vx_probe_set* pp[3];
    uint8_t *want, *got, *pd;
    size_t nwant, ngot, pn;
    for (int i = 0; i < 3; i++) {
        REQUIRE(bytes_of(&v[i], &pd, &pn));
        REQUIRE(vx_probe_read(NULL, pd, pn, &parts[i], &err) == VX_OK);
        free(pd);
        pp[i] = &parts[i];
    }
    vx_probe_set m;
    REQUIRE(vx_probe_merge(pp, 3, NULL, &m, &err) == VX_OK);
    REQUIRE(bytes_of(&one, &want, &nwant) && bytes_of(&m, &got, &ngot));
    CHECKF(ngot == nwant && !memcmp(got, want, nwant), "ranges through one baker: other bytes than one bake");
    free(want), free(got);
    for (int i = 0; i < 3; i++) {
        vx_probe_set_free(&parts[i]);
        vx_free(NULL, v[i].radiance), vx_free(NULL, v[i].normal), vx_free(NULL, v[i].distance);
        vx_free(NULL, v[i].low), vx_free(NULL, v[i].irradiance), vx_free(NULL, v[i].moments);
    }
    vx_probe_set_free(&m), vx_probe_set_free(&one), vx_probe_set_free(&placed), vx_probe_set_free(&other);
    vx_render_scene_destroy(rs);
    vx_svo_scene_free(&s);
}

/* "gpu:K" (render.h; what svo_bake and svo_render under mpirun pass for
 * local rank K): the (K mod G)-th GPU as vx_gpu_list_devices lists them, the
 * default pick where there is no GPU (lavapipe only); bad forms refused. */
typedef struct dev_list {
    char gpus[8][256];
    unsigned n;
} dev_list;
static void dev_fn(void* user, uint32_t index, const char* name, const char* type) {
    (void)index;
    dev_list* l = user;
    if (strcmp(type, "cpu") && strcmp(type, "other") && l->n < 8) snprintf(l->gpus[l->n++], 256, "%s", name);
}
static void test_gpu_device_choice(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_error err = {0};
    dev_list l = {.n = 0};
    REQUIRE(vx_gpu_list_devices(dev_fn, &l, &err) == VX_OK);
    vx_gpu* def = NULL;
    REQUIRE(vx_gpu_create(NULL, &def, &err) == VX_OK);
    for (unsigned k = 0; k < 5; k++) {
        char want[16];
        snprintf(want, sizeof want, "gpu:%u", k);
        vx_gpu* g = NULL;
        REQUIRE(vx_gpu_create(&(vx_gpu_desc){.device = want}, &g, &err) == VX_OK);
        const char* expect = l.n ? l.gpus[k % l.n] : vx_gpu_device_name(def);
        CHECKF(!strcmp(vx_gpu_device_name(g), expect), "%s opened %s, not %s", want, vx_gpu_device_name(g), expect);
        vx_gpu_destroy(g);
    }
    const char* bad[] = {"gpu:", "gpu:x", "gpu:-1", "gpu:1x"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        vx_gpu* g = NULL;
        CHECKF(vx_gpu_create(&(vx_gpu_desc){.device = bad[i]}, &g, &err) == VX_ERR_INVALID_ARG && !g, "'%s' accepted",
               bad[i]);
    }
    vx_gpu_destroy(def);
}

/* GPU gi vs CPU gi per pixel (same probes); GPU vs CPU path tracer by image statistics. */
/* A GPU (g) and a CPU (c) Monte Carlo image with different random streams
 * estimate the same image: equal means, and a difference no larger than
 * between two CPU images of different seeds (c, c2). */
static void same_estimate(const char* what, const vx_render_image* c, const vx_render_image* g,
                          const vx_render_image* c2) {
    double mc = 0, mg = 0, se_g = 0, se_c = 0;
    size_t n = (size_t)c->width * c->height * 4;
    for (size_t i = 0; i < n; i++) {
        if (i % 4 == 3) continue;
        mc += c->pixels[i], mg += g->pixels[i];
        se_g += (c->pixels[i] - g->pixels[i]) * (c->pixels[i] - g->pixels[i]);
        se_c += (c->pixels[i] - c2->pixels[i]) * (c->pixels[i] - c2->pixels[i]);
    }
    fprintf(stderr, "  %s: mean GPU/CPU %.4f, RMSE GPU-CPU %.4f vs CPU-CPU (other seed) %.4f\n", what, mg / mc,
            sqrt(se_g / n), sqrt(se_c / n));
    CHECK(mc > 0);
    CHECK(fabs(mg / mc - 1) < 0.03);
    CHECK(sqrt(se_g / n) < 1.25 * sqrt(se_c / n));
}

static void test_gpu_render(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene s;
    room_scene(&s);
    vx_render_scene* rs = scene_on_gpu(&s);
    REQUIRE(rs);
    vx_probe_set ps;
    vx_error err = {0};
    REQUIRE(vx_probe_bake(&s, &(vx_probe_bake_desc){.spacing = 3, .res = 16, .spp = 8, .threads = 2}, &ps, &err) ==
            VX_OK);
    vx_render_desc base = {.width = 32, .height = 24};
    const vx_probe_render_mode modes[2] = {VX_PROBE_RENDER_GI, VX_PROBE_RENDER_INDIRECT};
    for (int mi = 0; mi < 2; mi++) {
        vx_render_image c = {0}, g = {0};
        vx_probe_render_desc rd = {.base = &base, .mode = modes[mi]};
        REQUIRE(vx_probe_render(&s, &ps, &rd, &c, &err) == VX_OK);
        vx_result r = vx_probe_render_gpu(rs, &s, &ps, &rd, &g, &err);
        if (r) fprintf(stderr, "  %s\n", err.msg);
        REQUIRE(r == VX_OK);
        size_t n = (size_t)32 * 24, close = 0, hits = 0;
        double worst = 0;
        for (size_t i = 0; i < n; i++) {
            double e = 0, mag = 0;
            for (int q = 0; q < 4; q++) {
                e = fmax(e, fabs(c.pixels[4 * i + q] - g.pixels[4 * i + q]));
                mag = fmax(mag, fabs(c.pixels[4 * i + q]));
            }
            hits += c.pixels[4 * i + 3] != 0;
            /* float vs double: tiny; a shadow or probe-cell boundary through a pixel centre may flip */
            bool ok = e <= 1e-3 + 1e-3 * mag;
            close += ok;
            if (ok) worst = fmax(worst, e);
        }
        fprintf(stderr, "  %s GPU vs CPU: %zu/%zu pixels within 1e-3 (+1e-3 relative), worst of those %.2g; %zu hits\n",
                vx_probe_render_mode_name(modes[mi]), close, n, worst, hits);
        CHECK(hits > 200);
        CHECK(close >= n * 98 / 100);
        vx_render_image_free(&c), vx_render_image_free(&g);
    }
    /* path tracer: both estimate the same image; mean and per-pixel RMSE within the noise */
    vx_render_image c = {0}, g = {0};
    vx_probe_render_desc rd = {.base = &base, .mode = VX_PROBE_RENDER_PATHTRACE, .spp = 32, .threads = 2};
    REQUIRE(vx_probe_render(&s, &ps, &rd, &c, &err) == VX_OK);
    REQUIRE(vx_probe_render_gpu(rs, &s, &ps, &rd, &g, &err) == VX_OK);
    /* a second CPU image with another seed measures the noise alone */
    vx_render_image c2 = {0};
    rd.seed = 77;
    REQUIRE(vx_probe_render(&s, &ps, &rd, &c2, &err) == VX_OK);
    same_estimate("pathtrace 32 spp", &c, &g, &c2);
    vx_render_image_free(&c), vx_render_image_free(&g), vx_render_image_free(&c2);
    vx_probe_set_free(&ps);
    vx_render_scene_destroy(rs);
    vx_svo_scene_free(&s);
}

/* Issue 10: lavapipe ends every loop of an 8-invocation SIMD group once its
 * loops have run 65535 iterations in all, silently (probe.comp), so a pixel
 * or texel that looped over all its samples in one dispatch kept a partial
 * sum divided by spp: runs of 8 at a fraction of their value (half at 512 spp
 * on the Cornell box). These compare the GPU with the CPU at 1024 samples by
 * runs of 8 consecutive values (the SIMD groups): the worst run's GPU-CPU
 * difference in standard deviations, the variance from two CPU estimates of
 * different seeds (c, c2), n values of 3 channels, n a multiple of 8. */
static double worst_run_sigma(const double* c, const double* g, const double* c2, size_t n, double* ratio) {
    double worst = 0;
    *ratio = 1;
    for (size_t r0 = 0; r0 + 8 <= n; r0 += 8) {
        double sc = 0, sg = 0, var = 0;
        for (size_t i = 3 * r0; i < 3 * (r0 + 8); i++) {
            sc += c[i], sg += g[i];
            var += 0.5 * (c[i] - c2[i]) * (c[i] - c2[i]); /* one estimate's variance */
        }
        /* a difference of two estimates: twice that; a floor for noise-free runs (sky) */
        double z = fabs(sg - sc) / sqrt(2 * var + 1e-6 * sc * sc + 1e-12);
        if (z > worst) worst = z, *ratio = sc > 0 ? sg / sc : 1;
    }
    return worst;
}

static void rgb_of(const vx_render_image* im, double* out) {
    for (size_t i = 0; i < (size_t)im->width * im->height; i++)
        for (int q = 0; q < 3; q++) out[3 * i + q] = im->pixels[4 * i + q];
}

/* The path tracer: same estimate (mean, RMSE against the CPU's own noise),
 * every run of 8 pixels along a row within 8 sigma (the variance estimate
 * is rough; a cut run is off by over 100), the same bytes twice. */
static void test_gpu_pathtrace_high_spp(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene s;
    room_scene(&s);
    vx_render_scene* rs = scene_on_gpu(&s);
    REQUIRE(rs);
    enum { W = 16, H = 12, SPP = 1024 };
    vx_render_desc base = {.width = W, .height = H};
    vx_probe_render_desc rd = {.base = &base, .mode = VX_PROBE_RENDER_PATHTRACE, .spp = SPP, .seed = 1, .threads = 2};
    vx_render_image c = {0}, g = {0}, g2 = {0}, c2 = {0};
    vx_error err = {0};
    REQUIRE(vx_probe_render(&s, NULL, &rd, &c, &err) == VX_OK);
    vx_result r = vx_probe_render_gpu(rs, &s, NULL, &rd, &g, &err);
    if (r) fprintf(stderr, "  %s\n", err.msg);
    REQUIRE(r == VX_OK);
    REQUIRE(vx_probe_render_gpu(rs, &s, NULL, &rd, &g2, &err) == VX_OK);
    CHECK(!memcmp(g.pixels, g2.pixels, (size_t)W * H * 16));
    rd.seed = 77;
    REQUIRE(vx_probe_render(&s, NULL, &rd, &c2, &err) == VX_OK);
    same_estimate("pathtrace 1024 spp", &c, &g, &c2);
    double vc[W * H * 3], vg[W * H * 3], vc2[W * H * 3], ratio;
    rgb_of(&c, vc), rgb_of(&g, vg), rgb_of(&c2, vc2);
    double z = worst_run_sigma(vc, vg, vc2, W * H, &ratio);
    fprintf(stderr, "  pathtrace %d spp, runs of 8 pixels: worst |GPU-CPU| %.2f sigma (GPU/CPU %.4f)\n", SPP, z, ratio);
    CHECK(z < 8);
    vx_render_image_free(&c), vx_render_image_free(&g), vx_render_image_free(&g2), vx_render_image_free(&c2);
    vx_render_scene_destroy(rs);
    vx_svo_scene_free(&s);
}

/* The bake: radiance texels (runs of 8 along a map row) and the mean. */
static void test_gpu_bake_high_spp(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene s;
    room_scene(&s);
    vx_render_scene* rs = scene_on_gpu(&s);
    REQUIRE(rs);
    enum { N = 16 };
    vx_probe_bake_desc d = {.grid = {1, 1, 1}, .res = N, .spp = 1024, .seed = 3, .threads = 2};
    vx_probe_set c, g, c2;
    vx_error err = {0};
    REQUIRE(vx_probe_bake(&s, &d, &c, &err) == VX_OK);
    vx_result r = vx_probe_bake_gpu(rs, &s, &d, &g, &err);
    if (r) fprintf(stderr, "  %s\n", err.msg);
    REQUIRE(r == VX_OK);
    d.seed = 4;
    REQUIRE(vx_probe_bake(&s, &d, &c2, &err) == VX_OK);
    double vc[N * N * 3], vg[N * N * 3], vc2[N * N * 3], mc = 0, mg = 0, ratio;
    for (size_t t = 0; t < N * N; t++)
        for (int q = 0; q < 3; q++) {
            size_t b = 3 * ((t / N + 1) * (N + 2) + t % N + 1) + q; /* interior texel t of the bordered map */
            vc[3 * t + q] = vx_probe_half_to_float(c.radiance[b]);
            vg[3 * t + q] = vx_probe_half_to_float(g.radiance[b]);
            vc2[3 * t + q] = vx_probe_half_to_float(c2.radiance[b]);
            mc += vc[3 * t + q], mg += vg[3 * t + q];
        }
    double z = worst_run_sigma(vc, vg, vc2, N * N, &ratio);
    fprintf(stderr, "  bake 1024 spp: mean GPU/CPU %.4f; runs of 8 texels: worst |GPU-CPU| %.2f sigma (GPU/CPU %.4f)\n",
            mg / mc, z, ratio);
    CHECK(mc > 0 && fabs(mg / mc - 1) < 0.02);
    CHECK(z < 8);
    vx_probe_set_free(&c), vx_probe_set_free(&g), vx_probe_set_free(&c2);
    vx_render_scene_destroy(rs);
    vx_svo_scene_free(&s);
}

/* The light field walk on the GPU (float) estimates the same image as the
 * CPU's (double): random streams differ, so compare against the CPU's own
 * noise (a second seed). */
static void test_gpu_lightfield(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene s;
    room_scene(&s);
    vx_render_scene* rs = scene_on_gpu(&s);
    REQUIRE(rs);
    vx_probe_set ps;
    vx_error err = {0};
    REQUIRE(vx_probe_bake(&s, &(vx_probe_bake_desc){.spacing = 3, .res = 32, .spp = 8, .threads = 2}, &ps, &err) ==
            VX_OK);
    vx_render_desc base = {.width = 32, .height = 24};
    const vx_probe_render_mode modes[2] = {VX_PROBE_RENDER_LIGHTFIELD, VX_PROBE_RENDER_LF_INDIRECT};
    for (int mi = 0; mi < 2; mi++) {
        vx_render_image c = {0}, g = {0}, c2 = {0};
        vx_probe_render_desc rd = {.base = &base, .mode = modes[mi], .spp = 32, .threads = 2};
        REQUIRE(vx_probe_render(&s, &ps, &rd, &c, &err) == VX_OK);
        vx_result r = vx_probe_render_gpu(rs, &s, &ps, &rd, &g, &err);
        if (r) fprintf(stderr, "  %s\n", err.msg);
        REQUIRE(r == VX_OK);
        rd.seed = 77;
        REQUIRE(vx_probe_render(&s, &ps, &rd, &c2, &err) == VX_OK);
        same_estimate(vx_probe_render_mode_name(modes[mi]), &c, &g, &c2);
        vx_render_image_free(&c), vx_render_image_free(&g), vx_render_image_free(&c2);
    }
    /* maps kept on the GPU across frames and modes give the same images as
     * one-off renders, byte for byte */
    vx_probe_gpu* pg = NULL;
    REQUIRE(vx_probe_gpu_create(rs, &s, &ps, &pg, &err) == VX_OK);
    const vx_probe_render_mode seq[4] = {VX_PROBE_RENDER_GI, VX_PROBE_RENDER_LIGHTFIELD, VX_PROBE_RENDER_GI,
                                         VX_PROBE_RENDER_PATHTRACE};
    for (int i = 0; i < 4; i++) {
        vx_render_image a = {0}, b = {0};
        vx_probe_render_desc rd = {.base = &base, .mode = seq[i], .spp = 4};
        REQUIRE(vx_probe_gpu_render(pg, &rd, &a, &err) == VX_OK);
        REQUIRE(vx_probe_render_gpu(rs, &s, &ps, &rd, &b, &err) == VX_OK);
        CHECK(!memcmp(a.pixels, b.pixels, (size_t)32 * 24 * 16));
        vx_render_image_free(&a), vx_render_image_free(&b);
    }
    vx_probe_gpu_destroy(pg);
    /* a shard renders the path tracer (its light) but not the probe modes */
    vx_probe_set part;
    REQUIRE(vx_probe_bake(&s, &(vx_probe_bake_desc){.spacing = 3, .res = 16, .spp = 1, .count = 2}, &part, &err) ==
            VX_OK);
    REQUIRE(vx_probe_gpu_create(rs, &s, &part, &pg, &err) == VX_OK);
    vx_render_image a = {0};
    CHECK(vx_probe_gpu_render(pg, &(vx_probe_render_desc){.base = &base, .mode = VX_PROBE_RENDER_LIGHTFIELD}, &a,
                              &err) == VX_ERR_INVALID_ARG);
    CHECK(vx_probe_gpu_render(pg, &(vx_probe_render_desc){.base = &base, .mode = VX_PROBE_RENDER_PATHTRACE, .spp = 1},
                              &a, &err) == VX_OK);
    vx_render_image_free(&a);
    vx_probe_gpu_destroy(pg);
    vx_probe_set_free(&part);
    vx_probe_set_free(&ps);
    vx_render_scene_destroy(rs);
    vx_svo_scene_free(&s);
}

/* The light field walk read outside a probe's maps where a coarse DDA step
 * landed one cell past the map's edge: NaN halves on lavapipe (3 pixels of
 * this frame), other probes' radiance on NVIDIA. eph_monu1, probes 32 apart
 * at R=32, 16 rays per pixel: every pixel finite, in both light field modes. */
static void test_gpu_lightfield_finite(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene s;
    vx_test_vox st = vx_test_vox_scene("eph_monu1.vox", &s);
    if (st == VX_TEST_VOX_ABSENT) SKIP("corpus eph_monu1.vox not available");
    REQUIRE(st == VX_TEST_VOX_OK);
    vx_error err = {0};
    vx_render_scene* rs = scene_on_gpu(&s);
    REQUIRE(rs);
    vx_probe_set ps;
    vx_probe_bake_desc bd = {.spacing = 32, .res = 32, .spp = 2};
    REQUIRE(vx_probe_bake_gpu(rs, &s, &bd, &ps, &err) == VX_OK);
    vx_render_desc base = {.width = 160, .height = 120};
    vx_probe_render_mode modes[2] = {VX_PROBE_RENDER_LIGHTFIELD, VX_PROBE_RENDER_LF_INDIRECT};
    for (int m = 0; m < 2; m++) {
        vx_probe_render_desc d = {.base = &base, .mode = modes[m], .spp = 16};
        vx_render_image img = {0};
        CHECK(vx_probe_render_gpu(rs, &s, &ps, &d, &img, &err) == VX_OK);
        size_t bad = 0;
        for (size_t i = 0; img.pixels && i < (size_t)160 * 120 * 4; i++) bad += !isfinite(img.pixels[i]);
        CHECKF(bad == 0, "%s: %zu non-finite values", vx_probe_render_mode_name(modes[m]), bad);
        vx_render_image_free(&img);
    }
    vx_probe_set_free(&ps);
    vx_render_scene_destroy(rs);
    vx_svo_scene_free(&s);
}

/* The probe GI methods as the pass pipeline's gi pass: the gi image the
 * pipeline shows is the probe renderer's indirect image (which it writes
 * into the pipeline's buffer on the GPU), and direct + gi is the full mode. */
static void test_gi_pass_equals_renderer(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene s;
    room_scene(&s);
    vx_render_scene* rs = scene_on_gpu(&s);
    REQUIRE(rs);
    vx_error err = {0};
    vx_frame_renderer* fr = NULL;
    REQUIRE(vx_frame_renderer_create(rs, &s, &fr, &err) == VX_OK);
    vx_probe_render_desc pd = {.spp = 8, .bounces = 2, .seed = 7};
    vx_gi_method gm;
    vx_probe_gi* pgi = NULL;
    REQUIRE(vx_probe_gi_create(rs, &s, NULL, "pathtrace", &pd, &gm, &pgi, &err) == VX_OK);
    vx_pass_list L;
    REQUIRE(vx_pass_list_parse("gbuffer,direct,gi=pathtrace", &L, &err) == VX_OK);
    vx_frame_desc fd = vx_frame_desc_defaults();
    fd.base.width = 24, fd.base.height = 16;
    fd.passes = &L;
    fd.gi = &gm;
    fd.show = VX_SHOW_GI;
    vx_frame_result res;
    REQUIRE(vx_frame_render(fr, &fd, &res, &err) == VX_OK);
    vx_render_desc base = fd.base;
    base.light_dir[0] = gm.light_dir[0], base.light_dir[1] = gm.light_dir[1], base.light_dir[2] = gm.light_dir[2];
    vx_probe_render_desc rd = pd;
    rd.base = &base;
    rd.mode = VX_PROBE_RENDER_PT_INDIRECT;
    rd.pixel_centre = true; /* the gi pass traces the G-buffer's pixel-centre rays */
    vx_render_image ref = {0};
    CHECK(vx_probe_render_gpu(rs, &s, NULL, &rd, &ref, &err) == VX_OK);
    double worst = 0;
    size_t n = (size_t)24 * 16, lit = 0;
    for (size_t i = 0; ref.pixels && i < n; i++)
        for (int k = 0; k < 3; k++) {
            double a = res.image.pixels[4 * i + k], b = ref.pixels[4 * i + k];
            if (fabs(a - b) / fmax(fabs(b), 1e-6) > worst && getenv("VX_DEBUG"))
                fprintf(stderr, "  px %zu ch %d: pipeline %g renderer %g\n", i, k, a, b);
            worst = fmax(worst, fabs(a - b) / fmax(fabs(b), 1e-6));
            lit += b > 0;
        }
    printf("  gi pass vs probe renderer: worst relative difference %.2e over %zu lit values\n", worst, lit);
    CHECK(lit > 50);
    CHECK(worst < 1e-5); /* the same shader and samples; only the division may round differently */
    vx_render_image_free(&ref);
    vx_render_image_free(&res.image);
    vx_probe_gi_destroy(pgi);
    vx_frame_renderer_destroy(fr);
    vx_render_scene_destroy(rs);
    vx_svo_scene_free(&s);
}

/* The GPU bake with its allocations failing one by one (the k-th, then every one after it): each run
 * returns an error and leaves nothing allocated; none crashes (a failed baker left the bake's pointer to it
 * unset, which it then freed), and the run with no failure bakes the same bytes as the plain allocator. */
static void test_gpu_bake_allocation_failures(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene s;
    room_scene(&s);
    vx_render_scene* rs = scene_on_gpu(&s);
    REQUIRE(rs);
    vx_probe_bake_desc d = {.grid = {2, 2, 2}, .res = 16, .spp = 1, .bounces = 1, .seed = 3};
    vx_error err = {0};
    vx_probe_set want;
    vx_result r0 = vx_probe_bake_gpu(rs, &s, &d, &want, &err);
    if (r0) fprintf(stderr, "  bake: %s\n", err.msg);
    REQUIRE(r0 == VX_OK);
    uint8_t *wb = NULL, *gb = NULL;
    size_t wn = 0, gn = 0;
    REQUIRE(bytes_of(&want, &wb, &wn));
    bool done = false;
    long k = 1;
    for (; k < 400 && !done; k++) {
        tfail f = {.fail_at = k, .persistent = true};
        vx_allocator a = {.alloc = tfail_alloc, .free = tfail_free, .user_data = &f};
        d.alloc = &a;
        vx_probe_set ps;
        vx_result r = vx_probe_bake_gpu(rs, &s, &d, &ps, &err);
        if (r == VX_OK) {
            CHECKF(!f.failed, "allocation %ld failed and the bake went on as if not", k);
            done = true;
            if (bytes_of(&ps, &gb, &gn)) CHECK(gn == wn && !memcmp(gb, wb, wn));
            vx_probe_set_free(&ps);
        }
        CHECKF(f.live == 0, "allocation %ld failing: %ld blocks left", k, f.live);
    }
    fprintf(stderr, "  %ld allocation failures, each an error; then baked\n", k - 2);
    CHECK(done);
    vx_free(NULL, wb), vx_free(NULL, gb);
    vx_probe_set_free(&want);
    vx_render_scene_destroy(rs);
    vx_svo_scene_free(&s);
}

int main(void) {
    (void)ts_random_model;
    gpu_skip = vx_test_gpu_open((vx_gpu_desc){0}, false, &gpu);
    RUN(test_gpu_box_distances);
    RUN(test_gpu_furnace);
    RUN(test_gpu_vs_cpu_bake);
    RUN(test_gpu_bake_beam);
    RUN(test_gpu_bake_sun_map);
    RUN(test_gpu_bake_one_walk);
    RUN(test_gpu_bake_strata);
    RUN(test_gpu_filter_vs_host);
    RUN(test_gpu_baker_ranges);
    RUN(test_gpu_device_choice);
    RUN(test_gpu_render);
    RUN(test_gpu_pathtrace_high_spp);
    RUN(test_gpu_bake_high_spp);
    RUN(test_gpu_lightfield);
    RUN(test_gpu_lightfield_finite);
    RUN(test_gi_pass_equals_renderer);
    RUN(test_gpu_bake_allocation_failures);
    vx_gpu_destroy(gpu);
    return vx_test_finish();
}
