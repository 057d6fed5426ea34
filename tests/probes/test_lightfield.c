/* tests/probes/test_lightfield.c - rays traced through the probes' distance
 * maps (probes/lightfield.c) against the octree tracer: a probe's answer
 * (a hit at t, the sky, or "cannot tell beyond t") must agree with where the
 * octree says the ray really stops, for rays that start on surfaces (as the
 * renderer's bounce rays do), in scenes with occluders so that probes see
 * silhouettes; and light field renders against the path tracer. */
#include <math.h>
#include <stdio.h>

#include "probes/probes_internal.h"
#include "tests/probes/probe_scenes.h"
#include "tests/test.h"

static double rnd(uint32_t* s) { return (ts_rng(s) >> 8) * (1.0 / 16777216.0); }

/* A closed 16^3 box (5) with a pillar (6) and a floating slab (7) inside:
 * every probe sees depth discontinuities. */
static uint8_t pillar_cell(uint32_t x, uint32_t y, uint32_t z, uint32_t n) {
    if (!x || !y || !z || x == n - 1 || y == n - 1 || z == n - 1) return 5;
    if (x >= 6 && x < 8 && y >= 5 && y < 8) return 6;
    return (z == 9 && x >= 9 && x < 13 && y >= 3 && y < 12) ? 7 : 0;
}

static void pillar_scene(vx_svo_scene* s) {
    cells_scene(s, 16, pillar_cell);
    s->palette[5] = 0xFFC0C0C0u, s->palette[6] = 0xFF2060C0u, s->palette[7] = 0xFFC06020u;
}

static bool pillar_solid(int x, int y, int z) {
    if (x < 0 || y < 0 || z < 0 || x > 15 || y > 15 || z > 15) return false;
    return pillar_cell((uint32_t)x, (uint32_t)y, (uint32_t)z, 16) != 0;
}

/* Distance from p to the nearest solid voxel of the pillar scene (brute force). */
static double dist_to_solid(const double p[3]) {
    double best = INFINITY;
    for (int z = 0; z < 16; z++)
        for (int y = 0; y < 16; y++)
            for (int x = 0; x < 16; x++) {
                if (!pillar_solid(x, y, z)) continue;
                double c[3] = {x, y, z}, s = 0;
                for (int k = 0; k < 3; k++) {
                    double e = fmax(fmax(c[k] - p[k], p[k] - (c[k] + 1)), 0);
                    s += e * e;
                }
                best = fmin(best, s);
            }
    return sqrt(best);
}

/* How deep the ray o + t d, t in [ta, tb], goes into solid voxels: the
 * largest distance from a point on it to free space (sampled). */
static double max_penetration(const double o[3], const double d[3], double ta, double tb) {
    double worst = 0;
    for (double t = ta; t <= tb; t += 0.02) {
        double p[3] = {o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]};
        if (!pillar_solid((int)floor(p[0]), (int)floor(p[1]), (int)floor(p[2]))) continue;
        double best = INFINITY;
        for (int z = -1; z < 17; z++)
            for (int y = -1; y < 17; y++)
                for (int x = -1; x < 17; x++) {
                    if (pillar_solid(x, y, z)) continue;
                    double c[3] = {x, y, z}, s2 = 0;
                    for (int k = 0; k < 3; k++) {
                        double e = fmax(fmax(c[k] - p[k], p[k] - (c[k] + 1)), 0);
                        s2 += e * e;
                    }
                    best = fmin(best, s2);
                }
        worst = fmax(worst, sqrt(best));
    }
    return worst;
}

typedef struct agree {
    size_t rays, hits, misses, unknown, bad_hit, bad_miss, bad_unknown, early;
    size_t bounce_rays, answered; /* rays, and rays some probe answered */
    double worst_hit;
} agree;

/* Rays from surface points seen by the probes, cosine-distributed about the
 * surface normal, each walked through every enabled probe. */
static void check_agreement(const vx_svo_scene* s, const vx_probe_set* ps, uint32_t nrays, agree* A) {
    vx_render_caster* c = NULL;
    vx_error err = {0};
    REQUIRE(vx_render_caster_create(s, NULL, &c, &err) == VX_OK);
    vx__light L;
    REQUIRE(vx__light_init(&L, c, s, NULL, NULL, false, NULL, false, &err) == VX_OK);
    double lo[3], hi[3];
    lo[0] = lo[1] = lo[2] = 0, hi[0] = hi[1] = hi[2] = 16;
    uint32_t seed = 7;
    for (uint32_t r = 0; r < nrays; r++) {
        /* a surface point: cast from a random probe in a random direction */
        uint32_t pi = ts_rng(&seed) % ps->probe_count;
        if (ps->probes[pi].state == VX_PROBE_DISABLED) continue;
        double d0[3], len = 0;
        for (int k = 0; k < 3; k++) d0[k] = rnd(&seed) * 2 - 1, len += d0[k] * d0[k];
        if (len < 1e-6 || len > 1) continue;
        for (int k = 0; k < 3; k++) d0[k] /= sqrt(len);
        vx_render_ray_hit h;
        if (!vx_render_cast(c, ps->probes[pi].pos, d0, INFINITY, false, &h)) continue;
        vx__surface sf;
        vx__surface_of(&L, ps->probes[pi].pos, d0, &h, &sf);
        double d[3];
        vx__cosine_dir(sf.n, rnd(&seed), rnd(&seed), d);
        vx_render_ray_hit truth;
        double t_true = vx_render_cast(c, sf.p, d, INFINITY, false, &truth) ? truth.t : INFINITY;
        double t_end = INFINITY;
        for (int k = 0; k < 3; k++) {
            if (d[k] == 0) continue;
            double a = ((d[k] > 0 ? hi[k] : lo[k]) - sf.p[k]) / d[k];
            t_end = fmin(t_end, a);
        }
        A->bounce_rays++;
        bool answered = false;
        for (uint32_t q = 0; q < ps->probe_count; q++) {
            if (ps->probes[q].state == VX_PROBE_DISABLED) continue;
            double t = 0;
            uint32_t texel = 0;
            vx__lf_status st = vx__lf_trace_probe(ps, q, sf.p, d, &t, t_end, &texel, NULL);
            A->rays++;
            /* A texel's cone has a half-angle of up to 4.25/res radians: the
             * probe knows its surfaces only to about that footprint. A hit
             * beyond the true one must not have gone deeper into a voxel than
             * that (a ray grazing an edge the probe cannot resolve), nor may
             * a miss or an "unknown from here"; a hit before the true one
             * must lie within two footprints of a voxel. */
            double X[3], pr = 0;
            for (int k = 0; k < 3; k++) {
                X[k] = sf.p[k] + t * d[k];
                pr += (X[k] - ps->probes[q].pos[k]) * (X[k] - ps->probes[q].pos[k]);
            }
            double foot = sqrt(pr) * 4.25 / ps->res;
            double tol = 2 * foot + 4 * ps->dist_step;
            bool past = isfinite(t_true) && t > t_true + 4 * ps->dist_step &&
                        max_penetration(sf.p, d, t_true, t) > foot + 4 * ps->dist_step;
            if (st != VX__LF_UNKNOWN) answered = true;
            if (st == VX__LF_HIT) {
                A->hits++;
                double e = t - t_true;
                bool wrong = past || (e < -tol && dist_to_solid(X) > tol);
                if (wrong) {
                    A->bad_hit++;
                    if (A->bad_hit <= 3)
                        fprintf(stderr, "  wrong hit: probe %u t %.3f, octree %.3f (tol %.2f)\n", q, t, t_true, tol);
                }
                if (e < -tol) A->early++;
                if (isfinite(e)) A->worst_hit = fmax(A->worst_hit, fabs(e));
            } else if (st == VX__LF_MISS) {
                A->misses++;
                if (past) A->bad_miss++;
            } else {
                A->unknown++;
                if (past) A->bad_unknown++;
            }
        }
        A->answered += answered;
    }
    vx__light_free(&L);
    vx_render_caster_destroy(c);
}

static void test_trace_agrees_with_octree(void) {
    vx_svo_scene s;
    pillar_scene(&s);
    vx_error err = {0};
    for (uint32_t res = 32; res <= 64; res *= 2) {
        vx_probe_set ps;
        /* geometry only: distances and normals do not depend on the light; the grid's cell centres in the
         * scene's box [0,16]^3 (bounds_set: over the scene's own bounds the grid reaches out of the box, and
         * the surface points below are cast from the probes) */
        vx_result r = vx_probe_bake(&s, &(vx_probe_bake_desc){.grid = {3, 3, 3}, .bounds_set = true,
                                                             .bounds_hi = {16, 16, 16}, .res = res, .spp = 1,
                                                             .bounces = -1, .threads = 2},
                                    &ps, &err);
        if (r) fprintf(stderr, "%s\n", err.msg);
        REQUIRE(r == VX_OK);
        agree A = {0};
        check_agreement(&s, &ps, 400, &A);
        fprintf(stderr,
                "  res %u: %zu probe walks: %zu hits (%zu at an edge before the octree's), %zu unknown, %zu misses; "
                "wrong: %zu hits, %zu misses, %zu unknown\n",
                res, A.rays, A.hits, A.early, A.unknown, A.misses, A.bad_hit, A.bad_miss, A.bad_unknown);
        CHECK(A.rays > 4000);
        CHECK(A.bad_hit == 0);
        CHECK(A.bad_miss == 0);
        CHECK(A.bad_unknown == 0);
        /* Every probe walks every ray (also probes that cannot see its
         * origin); some probe answers nearly every ray. */
        fprintf(stderr, "  %zu rays, %zu answered by some probe\n", A.bounce_rays, A.answered);
        CHECK(A.hits > A.rays / 3);
        CHECK(A.answered >= A.bounce_rays * 95 / 100);
        vx_probe_set_free(&ps);
    }
    vx_svo_scene_free(&s);
}

/* Axis-parallel rays, rays with -0 components, and rays through the probe's
 * own coordinate planes and centre: the walk must still agree. */
static void test_trace_special_rays(void) {
    vx_svo_scene s;
    box_scene(&s, 16, 5);
    vx_error err = {0};
    vx_probe_set ps;
    REQUIRE(vx_probe_bake(&s, &(vx_probe_bake_desc){.grid = {1, 1, 1}, .res = 32, .spp = 1, .bounces = -1}, &ps,
                          &err) == VX_OK);
    const double* P = ps.probes[0].pos; /* (8, 8, 8) */
    struct {
        double o[3], d[3], t_true;
    } cases[] = {
        {{8, 8, 8}, {1, 0, 0}, 7},         /* from the centre along an axis */
        {{8, 8, 8}, {-0.0, -1, -0.0}, 7},  /* -0 components */
        {{3, 8, 8}, {1, 0, 0}, 12},        /* through the probe's centre */
        {{3, 5, 8}, {1, 0, 0}, 12},        /* in the probe's z plane */
        {{3, 5, 8}, {0, 0, -1}, 7},        /* along the plane's normal */
        {{2, 2, 2}, {0.57735026918962573, 0.57735026918962573, 0.57735026918962573}, 13 * 1.7320508075688772},
        {{4, 12, 8}, {0.70710678118654752, -0.70710678118654752, 0}, 11 * 1.4142135623730951}, /* through edges */
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        double t = 0;
        uint32_t texel = 0;
        vx__lf_status st = vx__lf_trace_probe(&ps, 0, cases[i].o, cases[i].d, &t, 100, &texel, NULL);
        double tol = 0.5 + 15 * 8.0 / ps.res;
        bool ok = st == VX__LF_HIT ? fabs(t - cases[i].t_true) <= tol : (st == VX__LF_UNKNOWN && t <= cases[i].t_true);
        if (!ok) fprintf(stderr, "  case %zu: status %d t %.4f (expected hit at %.4f)\n", i, st, t, cases[i].t_true);
        CHECK(ok);
        /* a closed convex box seen from inside: every such ray is answered */
        CHECK(st == VX__LF_HIT);
    }
    (void)P;
    vx_probe_set_free(&ps);
    vx_svo_scene_free(&s);
}

/* The light field bounce converges to the path tracer's: with many rays
 * per pixel its error is far below probe GI's on the room scene. */
static void test_lightfield_vs_pathtrace(void) {
    vx_svo_scene s;
    room_scene(&s);
    vx_probe_set ps;
    vx_error err = {0};
    REQUIRE(vx_probe_bake(&s, &(vx_probe_bake_desc){.spacing = 3, .res = 32, .spp = 16, .threads = 2}, &ps, &err) ==
            VX_OK);
    vx_render_desc base = {.width = 32, .height = 24};
    vx_render_image lf = {0}, pt = {0}, gi = {0};
    vx_probe_render_stats st = {0};
    REQUIRE(vx_probe_render(&s, &ps,
                            &(vx_probe_render_desc){.base = &base, .mode = VX_PROBE_RENDER_LF_INDIRECT, .spp = 64,
                                                    .threads = 2, .stats = &st},
                            &lf, &err) == VX_OK);
    REQUIRE(vx_probe_render(&s, &ps, &(vx_probe_render_desc){.base = &base, .mode = VX_PROBE_RENDER_INDIRECT}, &gi,
                            &err) == VX_OK);
    REQUIRE(vx_probe_render(&s, &ps,
                            &(vx_probe_render_desc){.base = &base, .mode = VX_PROBE_RENDER_PT_INDIRECT, .spp = 256,
                                                    .threads = 2},
                            &pt, &err) == VX_OK);
    double se_lf = 0, se_gi = 0, ref = 0;
    for (size_t i = 0; i < (size_t)32 * 24; i++) {
        if (pt.pixels[4 * i + 3] == 0) continue;
        for (int c = 0; c < 3; c++) {
            double b = pt.pixels[4 * i + c];
            se_lf += (lf.pixels[4 * i + c] - b) * (lf.pixels[4 * i + c] - b);
            se_gi += (gi.pixels[4 * i + c] - b) * (gi.pixels[4 * i + c] - b);
            ref += b * b;
        }
    }
    double rel_lf = sqrt(se_lf / ref), rel_gi = sqrt(se_gi / ref);
    fprintf(stderr,
            "  relative RMSE vs path tracing (256 spp): light field (64 rays) %.3f, probe gi %.3f; "
            "%llu rays, %.1f%% answered by probes, %.1f%% octree\n",
            rel_lf, rel_gi, (unsigned long long)st.rays, 100.0 * (st.hits + st.misses) / (st.rays ? st.rays : 1),
            100.0 * st.fallbacks / (st.rays ? st.rays : 1));
    CHECK(st.rays > 0 && st.hits + st.misses + st.fallbacks == st.rays);
    CHECK(st.fallbacks < st.rays / 2);
    CHECK(rel_lf < 0.15);
    CHECK(rel_lf < rel_gi);
    /* the full modes add the same direct light, emission and sky to their
     * indirect parts (same seed and spp: the same camera rays) */
    vx_render_image full = {0}, pt_full = {0}, pt_ind = {0};
    vx_probe_render_desc fd = {.base = &base, .mode = VX_PROBE_RENDER_LIGHTFIELD, .spp = 64, .threads = 1};
    REQUIRE(vx_probe_render(&s, &ps, &fd, &full, &err) == VX_OK);
    fd.mode = VX_PROBE_RENDER_PATHTRACE, fd.threads = 2;
    REQUIRE(vx_probe_render(&s, &ps, &fd, &pt_full, &err) == VX_OK);
    fd.mode = VX_PROBE_RENDER_PT_INDIRECT;
    REQUIRE(vx_probe_render(&s, &ps, &fd, &pt_ind, &err) == VX_OK);
    double worst = 0, direct_sum = 0;
    for (size_t i = 0; i < (size_t)32 * 24; i++)
        for (int c = 0; c < 3; c++) {
            double a = full.pixels[4 * i + c] - lf.pixels[4 * i + c];
            double b = pt_full.pixels[4 * i + c] - pt_ind.pixels[4 * i + c];
            worst = fmax(worst, fabs(a - b));
            direct_sum += b;
            if (c == 0) CHECK(lf.pixels[4 * i + 3] == pt_ind.pixels[4 * i + 3]); /* same camera rays */
        }
    CHECK(worst < 1e-4);
    CHECK(direct_sum > 1);
    vx_render_image_free(&full), vx_render_image_free(&pt_full), vx_render_image_free(&pt_ind);
    vx_render_image_free(&lf), vx_render_image_free(&gi), vx_render_image_free(&pt);
    vx_probe_set_free(&ps);
    vx_svo_scene_free(&s);
}

/* A probe set read from a file may hold extreme (finite) values: the walk
 * must end and answer something, never loop or read outside the maps. */
static void test_extreme_values(void) {
    vx_svo_scene s;
    box_scene(&s, 16, 5);
    vx_error err = {0};
    vx_probe_set ps;
    REQUIRE(vx_probe_bake(&s, &(vx_probe_bake_desc){.grid = {1, 1, 1}, .res = 16, .spp = 1, .bounces = -1}, &ps,
                          &err) == VX_OK);
    const double far[3] = {1e300, -1e300, 1e-300};
    double steps[3] = {1e300, 1e-300, ps.dist_step};
    uint32_t seed = 3;
    for (int k = 0; k < 3; k++) {
        ps.dist_step = steps[k];
        for (int i = 0; i < 200; i++) {
            double o[3], d[3], len = 0;
            for (int a = 0; a < 3; a++) {
                o[a] = (i % 3 == 0) ? far[(a + i) % 3] : rnd(&seed) * 16;
                d[a] = rnd(&seed) * 2 - 1, len += d[a] * d[a];
            }
            if (len < 1e-6) continue;
            for (int a = 0; a < 3; a++) d[a] /= sqrt(len);
            double t = 0;
            uint32_t texel = 0;
            vx__lf_status st = vx__lf_trace_probe(&ps, 0, o, d, &t, i % 2 ? 1e300 : 40, &texel, NULL);
            CHECK(st == VX__LF_HIT || st == VX__LF_MISS || st == VX__LF_UNKNOWN);
            if (st == VX__LF_HIT) CHECK(texel < (ps.res + 2) * (ps.res + 2));
        }
    }
    vx_probe_set_free(&ps);
    vx_svo_scene_free(&s);
}

int main(void) {
    (void)ts_random_model;
    RUN(test_trace_agrees_with_octree);
    RUN(test_trace_special_rays);
    RUN(test_extreme_values);
    RUN(test_lightfield_vs_pathtrace);
    return vx_test_finish();
}
