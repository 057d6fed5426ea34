/* tests/render/test_render_cpu.c - the parts that need no Vulkan device: the
 * BVH builder, the CPU reference against brute force, desc checks, limits. */
#include <math.h>
#include <stdio.h>

#include "tests/test.h"
#include "tests/render/scenes.h"
#include "render/trace.h"

static void test_bvh_structure_and_speed(void) {
    enum { N = 10000 };
    double* lo = malloc(N * 3 * sizeof(double));
    double* hi = malloc(N * 3 * sizeof(double));
    REQUIRE(lo && hi);
    uint32_t seed = 7;
    for (int i = 0; i < N; i++)
        for (int k = 0; k < 3; k++) {
            double c = (ts_rng(&seed) % 100000) * 0.1, e = 1 + ts_rng(&seed) % 50;
            lo[3 * i + k] = c, hi[3 * i + k] = c + e;
        }
    vx_bvh b;
    vx_error err = {0};
    double best = 1e9;
    for (int rep = 0; rep < 3; rep++) {
        double t0 = vx_time_now();
        REQUIRE(vx_bvh_build(lo, hi, N, NULL, &b, &err) == VX_OK);
        double t = vx_time_now() - t0;
        if (t < best) best = t;
        if (rep < 2) vx_bvh_free(&b);
    }
    printf("bvh: %d instances built in %.2f ms (best of 3)\n", N, best * 1e3);
    /* every item exactly once, inside every ancestor's box */
    uint8_t* seen = calloc(N, 1);
    uint32_t* stack = malloc(b.node_count * sizeof *stack);
    uint32_t* parent = malloc(b.node_count * sizeof *parent);
    REQUIRE(seen && stack && parent);
    int sp = 0, bad = 0;
    stack[sp++] = 0;
    parent[0] = UINT32_MAX;
    while (sp) {
        uint32_t n = stack[--sp];
        const vx_bvh_node* nd = &b.nodes[n];
        if (nd->count) {
            CHECK(nd->count <= 4);
            for (uint32_t i = nd->first; i < nd->first + nd->count; i++) {
                uint32_t it = b.items[i];
                seen[it]++;
                for (uint32_t a = n; a != UINT32_MAX; a = parent[a])
                    for (int k = 0; k < 3; k++)
                        if (!(b.nodes[a].lo[k] <= lo[3 * it + k] && b.nodes[a].hi[k] >= hi[3 * it + k])) bad++;
            }
        } else {
            REQUIRE(nd->first + 1 < b.node_count);
            parent[nd->first] = parent[nd->first + 1] = n;
            stack[sp++] = nd->first;
            stack[sp++] = nd->first + 1;
        }
    }
    CHECK(bad == 0);
    for (int i = 0; i < N; i++) CHECK(seen[i] == 1);
    free(seen), free(stack), free(parent);
    vx_bvh_free(&b);
    free(lo), free(hi);
}

/* Brute force: nearest voxel box along the ray over every filled cell. */
static void test_cpu_vs_brute_force(void) {
    vx_svo_model m;
    REQUIRE(ts_random_model(&m, 7, 6, 5, 30, 1234) == VX_OK);
    /* collect the cells back through the decoder */
    typedef struct { uint32_t n; uint32_t c[7 * 6 * 5][3]; } cells_t;
    static cells_t cells;
    cells.n = 0;
    bool cb(void* u, uint32_t x, uint32_t y, uint32_t z, uint32_t a);
    vx_svo_instance in = ts_inst(0, (const double[9]){0, -1, 0, 1, 0, 0, 0, 0, 1}, 10, 3, -2);
    vx_svo_scene s;
    ts_scene(&s, &m, 1, &in, 1);
    struct ctx { cells_t* c; } ctx = {&cells};
    (void)ctx;
    vx_error err = {0};
    REQUIRE(vx_svo_decode_model(&s.models[0], cb, &cells, &err) == VX_OK);
    REQUIRE(cells.n > 10);
    vx_render_desc d = {.width = 40, .height = 30, .mode = VX_RENDER_DEPTH, .want_hits = true};
    d.camera.set = true;
    double eye[3] = {15.5, -3.25, 8.1}, tg[3] = {7, 6.5, 0.5};
    memcpy(d.camera.eye, eye, sizeof eye);
    memcpy(d.camera.target, tg, sizeof tg);
    vx_render_image img;
    REQUIRE(vx_render_cpu(&s, &d, NULL, &img, &err) == VX_OK);
    /* rebuild the same rays from the depth image: the hit point must lie on
     * the hit cell's box, and no cell box may be entered earlier */
    int checked = 0, wrong = 0, hits = 0;
    double w[12], inv[12];
    memcpy(w, s.instances[0].xform, sizeof w);
    /* invert the rotation (orthonormal) */
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) inv[4 * r + c] = w[4 * c + r];
    for (int r = 0; r < 3; r++) inv[4 * r + 3] = -(inv[4 * r] * w[3] + inv[4 * r + 1] * w[7] + inv[4 * r + 2] * w[11]);
    double fwd[3] = {tg[0] - eye[0], tg[1] - eye[1], tg[2] - eye[2]};
    double fl = sqrt(fwd[0] * fwd[0] + fwd[1] * fwd[1] + fwd[2] * fwd[2]);
    for (int k = 0; k < 3; k++) fwd[k] /= fl;
    double up[3] = {0, 0, 1}, right[3] = {fwd[1] * up[2] - fwd[2] * up[1], fwd[2] * up[0] - fwd[0] * up[2],
                                          fwd[0] * up[1] - fwd[1] * up[0]};
    double rl = sqrt(right[0] * right[0] + right[1] * right[1] + right[2] * right[2]);
    for (int k = 0; k < 3; k++) right[k] /= rl;
    double upv[3] = {right[1] * fwd[2] - right[2] * fwd[1], right[2] * fwd[0] - right[0] * fwd[2],
                     right[0] * fwd[1] - right[1] * fwd[0]};
    double th = tan(22.5 * 3.14159265358979323846 / 180), aspect = 40.0 / 30.0;
    for (uint32_t py = 0; py < 30; py++)
        for (uint32_t px = 0; px < 40; px++) {
            double u = ((px + 0.5) / 40) * 2 - 1, v = 1 - ((py + 0.5) / 30) * 2;
            double dw[3], dl = 0;
            for (int k = 0; k < 3; k++) dw[k] = fwd[k] + u * right[k] * th * aspect + v * upv[k] * th, dl += dw[k] * dw[k];
            dl = sqrt(dl);
            for (int k = 0; k < 3; k++) dw[k] /= dl;
            double om[3], dm[3];
            for (int r = 0; r < 3; r++) {
                om[r] = inv[4 * r] * eye[0] + inv[4 * r + 1] * eye[1] + inv[4 * r + 2] * eye[2] + inv[4 * r + 3];
                dm[r] = inv[4 * r] * dw[0] + inv[4 * r + 1] * dw[1] + inv[4 * r + 2] * dw[2];
            }
            double best = INFINITY;
            int bi = -1;
            for (uint32_t i = 0; i < cells.n; i++) {
                double t0 = 0, t1 = INFINITY;
                for (int k = 0; k < 3; k++) {
                    double a = (cells.c[i][k] - om[k]) / dm[k], b = (cells.c[i][k] + 1 - om[k]) / dm[k];
                    t0 = fmax(t0, fmin(a, b)), t1 = fmin(t1, fmax(a, b));
                }
                if (t0 < t1 && t0 < best) best = t0, bi = (int)i;
            }
            const vx_render_hit* h = &img.hits[py * 40 + px];
            checked++;
            if (bi < 0) {
                if (h->instance != VX_RENDER_NO_HIT) wrong++;
                continue;
            }
            hits++;
            bool same = h->instance == 0 && h->cell[0] == cells.c[bi][0] && h->cell[1] == cells.c[bi][1] &&
                        h->cell[2] == cells.c[bi][2];
            if (!same || fabs(h->t - best) > 1e-4 * best) {
                wrong++;
                fprintf(stderr, "  pixel %u,%u: brute force cell %u,%u,%u t=%g, cpu %u,%u,%u t=%g\n", px, py,
                        cells.c[bi][0], cells.c[bi][1], cells.c[bi][2], best, h->cell[0], h->cell[1], h->cell[2], h->t);
            }
        }
    printf("cpu vs brute force: %d pixels, %d hits, %d wrong\n", checked, hits, wrong);
    CHECK(hits > 100);
    CHECK(wrong == 0);
    vx_render_image_free(&img);
    vx_svo_scene_free(&s);
}

bool cb(void* u, uint32_t x, uint32_t y, uint32_t z, uint32_t a) {
    (void)a;
    struct { uint32_t n; uint32_t c[7 * 6 * 5][3]; }* c = u;
    c->c[c->n][0] = x, c->c[c->n][1] = y, c->c[c->n][2] = z;
    c->n++;
    return true;
}

static void test_desc_validation(void) {
    vx_error err = {0};
    CHECK(vx_render_desc_validate(&(vx_render_desc){0}, &err) == VX_OK);
    CHECK(vx_render_desc_validate(&(vx_render_desc){.width = 20000}, &err) == VX_ERR_INVALID_ARG);
    CHECK(vx_render_desc_validate(&(vx_render_desc){.mode = VX_RENDER_MODE_NUM}, &err) == VX_ERR_INVALID_ARG);
    vx_render_desc d = {0};
    d.camera.set = true; /* eye == target */
    CHECK(vx_render_desc_validate(&d, &err) == VX_ERR_INVALID_ARG);
    d.camera.set = false;
    d.camera.fov = NAN;
    CHECK(vx_render_desc_validate(&d, &err) == VX_ERR_INVALID_ARG);
    vx_render_mode m;
    CHECK(vx_render_mode_parse("iterations", &m) && m == VX_RENDER_ITERATIONS);
    CHECK(!vx_render_mode_parse("colour", &m));
}

static void test_too_deep_refused(void) {
    vx_svo_model m;
    memset(&m, 0, sizeof m);
    m.size[0] = m.size[1] = m.size[2] = 1u << 21;
    m.depth = 22;
    m.root = VX_SVO_ROOT_LEAF;
    m.voxel_count = 1;
    vx_svo_instance in = ts_inst(0, NULL, 0, 0, 0);
    vx_svo_scene s;
    ts_scene(&s, &m, 1, &in, 1);
    vx_render_image img;
    vx_error err = {0};
    CHECK(vx_render_cpu(&s, &(vx_render_desc){.width = 8, .height = 8}, NULL, &img, &err) == VX_ERR_UNSUPPORTED);
    printf("refused: %s\n", err.msg);
    CHECK(strstr(err.msg, "22") && strstr(err.msg, "21"));
    vx_svo_scene_free(&s);
}

/* A whole model that is one collapsed leaf, seen from outside and inside. */
static void test_cpu_root_leaf(void) {
    uint32_t xyz[8 * 3], n = 0;
    for (uint32_t z = 0; z < 2; z++)
        for (uint32_t y = 0; y < 2; y++)
            for (uint32_t x = 0; x < 2; x++) xyz[3 * n] = x, xyz[3 * n + 1] = y, xyz[3 * n + 2] = z, n++;
    vx_svo_model m;
    REQUIRE(ts_model(&m, (uint32_t[3]){2, 2, 2}, xyz, NULL, n) == VX_OK);
    CHECK(m.root == VX_SVO_ROOT_LEAF);
    vx_svo_instance in = ts_inst(0, NULL, 0, 0, 0);
    vx_svo_scene s;
    ts_scene(&s, &m, 1, &in, 1);
    vx_render_desc d = {.width = 8, .height = 8, .mode = VX_RENDER_DEPTH, .want_hits = true};
    d.camera.set = true, d.camera.ortho = true, d.camera.ortho_height = 1;
    double e[3] = {1.25, 1.25, 10}, t[3] = {1.25, 1.25, 0};
    memcpy(d.camera.eye, e, sizeof e), memcpy(d.camera.target, t, sizeof t);
    d.camera.up[1] = 1;
    vx_render_image img;
    vx_error err = {0};
    REQUIRE(vx_render_cpu(&s, &d, NULL, &img, &err) == VX_OK);
    for (int i = 0; i < 64; i++) {
        CHECK(img.hits[i].instance == 0);
        CHECK(fabs(img.hits[i].t - 8.0) < 1e-6);
        CHECK(img.hits[i].cell[2] == 1);
    }
    vx_render_image_free(&img);
    vx_svo_scene_free(&s);
}

/* vx_render_camera_default states the default framing: a frame with the
 * camera it gives for the scene's bounds is the default frame, hit for hit and
 * bit for bit (perspective at two fovs, orthographic with and without a
 * height, another up), and a wider box moves the eye back (what svo_render
 * gives an animation's frame: the camera of all its frames). */
static void test_default_camera(void) {
    uint32_t xyz[4 * 3] = {0, 0, 0, 5, 1, 2, 2, 6, 1, 7, 7, 7};
    vx_svo_model m;
    REQUIRE(ts_model(&m, (uint32_t[3]){8, 8, 8}, xyz, NULL, 4) == VX_OK);
    vx_svo_instance in = ts_inst(0, NULL, 3, -2, 1);
    vx_svo_scene s;
    ts_scene(&s, &m, 1, &in, 1);
    double lo[3], hi[3];
    vx_svo_scene_world_bounds(&s, lo, hi);
    for (int v = 0; v < 5; v++) {
        vx_render_desc d = {.width = 48, .height = 36, .mode = VX_RENDER_DEPTH, .want_hits = true};
        if (v == 1) d.camera.fov = 30;
        if (v == 2 || v == 3) d.camera.ortho = true;
        if (v == 3) d.camera.ortho_height = 5;
        if (v == 4) d.camera.up[1] = 1;
        vx_render_desc e = d;
        vx_render_camera_default(lo, hi, &d, &e.camera);
        CHECK(e.camera.set && e.camera.fov == d.camera.fov && e.camera.up[1] == d.camera.up[1]);
        CHECK(v != 3 || e.camera.ortho_height == 5);
        if (v != 3) { /* the framing holds the whole box, and not loosely: its corners project inside [-1, 1]^2, one
                         past half of it (independent of the formulas: a camera too near or too far fails) */
            double up[3] = {e.camera.up[0], e.camera.up[1], e.camera.up[2]}, fw[3], rt[3], uv[3], n = 0;
            if (up[0] == 0 && up[1] == 0 && up[2] == 0) up[2] = 1;
            for (int k = 0; k < 3; k++) fw[k] = e.camera.target[k] - e.camera.eye[k], n += fw[k] * fw[k];
            for (int k = 0; k < 3; k++) fw[k] /= sqrt(n);
            rt[0] = fw[1] * up[2] - fw[2] * up[1], rt[1] = fw[2] * up[0] - fw[0] * up[2], rt[2] = fw[0] * up[1] - fw[1] * up[0];
            n = sqrt(rt[0] * rt[0] + rt[1] * rt[1] + rt[2] * rt[2]);
            for (int k = 0; k < 3; k++) rt[k] /= n;
            uv[0] = rt[1] * fw[2] - rt[2] * fw[1], uv[1] = rt[2] * fw[0] - rt[0] * fw[2], uv[2] = rt[0] * fw[1] - rt[1] * fw[0];
            double th = tan(0.5 * (d.camera.fov > 0 ? d.camera.fov : 45) * 3.14159265358979323846 / 180), most = 0;
            for (int c = 0; c < 8; c++) {
                double q[3] = {(c & 1) ? hi[0] : lo[0], (c & 2) ? hi[1] : lo[1], (c & 4) ? hi[2] : lo[2]}, x = 0, y = 0, z = 0;
                for (int k = 0; k < 3; k++) {
                    double r = q[k] - e.camera.eye[k];
                    x += r * rt[k], y += r * uv[k], z += r * fw[k];
                }
                double sx = d.camera.ortho ? x / (0.5 * e.camera.ortho_height) / (48.0 / 36) : x / (z * th) / (48.0 / 36);
                double sy = d.camera.ortho ? y / (0.5 * e.camera.ortho_height) : y / (z * th);
                CHECKF(z > 0 && fabs(sx) <= 1 && fabs(sy) <= 1, "variant %d corner %d at %g %g (z %g)", v, c, sx, sy, z);
                most = fmax(most, fmax(fabs(sx), fabs(sy)));
            }
            CHECKF(most > 0.5, "variant %d: the box fills at most %g of the view", v, most);
        }
        vx_render_image a, b;
        vx_error err = {0};
        REQUIRE(vx_render_cpu(&s, &d, NULL, &a, &err) == VX_OK);
        REQUIRE(vx_render_cpu(&s, &e, NULL, &b, &err) == VX_OK);
        uint32_t hit = 0, differ = 0;
        for (uint32_t i = 0; i < 48 * 36; i++) {
            hit += a.hits[i].instance != VX_RENDER_NO_HIT;
            differ += a.hits[i].instance != b.hits[i].instance || memcmp(&a.hits[i].t, &b.hits[i].t, sizeof a.hits[i].t) ||
                      memcmp(a.hits[i].cell, b.hits[i].cell, sizeof a.hits[i].cell);
        }
        CHECKF(hit > 20 && differ == 0, "variant %d: %u hits, %u differ", v, hit, differ);
        vx_render_image_free(&a), vx_render_image_free(&b);
        /* a box twice as wide around the same centre: the eye twice as far */
        double lo2[3], hi2[3];
        for (int k = 0; k < 3; k++) {
            double c = 0.5 * (lo[k] + hi[k]), h = hi[k] - lo[k];
            lo2[k] = c - h, hi2[k] = c + h;
        }
        vx_render_camera f;
        vx_render_camera_default(lo2, hi2, &d, &f);
        double d1 = 0, d2 = 0;
        for (int k = 0; k < 3; k++) {
            d1 += (e.camera.eye[k] - e.camera.target[k]) * (e.camera.eye[k] - e.camera.target[k]);
            d2 += (f.eye[k] - f.target[k]) * (f.eye[k] - f.target[k]);
            CHECK(fabs(f.target[k] - e.camera.target[k]) < 1e-12);
        }
        CHECKF(fabs(sqrt(d2) - 2 * sqrt(d1)) < 1e-9 * sqrt(d2), "variant %d: %g against %g", v, sqrt(d2), sqrt(d1));
    }
    vx_svo_scene_free(&s);
}

/* The screen cull's rectangle (vx__frame_rect, which trace.comp traces; the
 * rest misses unseen): every pixel that the CPU reference sees hit lies inside
 * it, for cameras near, far, inside the scene, looking away, perspective and
 * orthographic; a camera looking away gets nothing, one inside everything; and
 * from outside, the rectangle of a box whose corners are filled cells lies
 * within a few pixels of the hits (it culls). */
static void test_screen_rect(void) {
    enum { W = 96, H = 72 };
    /* scene 0: one box of filled cells (its corners on the silhouette); scene 1:
     * two rotated instances of a random model and the box */
    uint32_t sz[3] = {6, 5, 4}, xyz[6 * 5 * 4 * 3], n = 0;
    for (uint32_t z = 0; z < sz[2]; z++)
        for (uint32_t y = 0; y < sz[1]; y++)
            for (uint32_t x = 0; x < sz[0]; x++) xyz[3 * n] = x, xyz[3 * n + 1] = y, xyz[3 * n + 2] = z, n++;
    vx_svo_model box[1], two[2];
    REQUIRE(ts_model(&box[0], sz, xyz, NULL, n) == VX_OK);
    REQUIRE(ts_model(&two[0], sz, xyz, NULL, n) == VX_OK);
    REQUIRE(ts_random_model(&two[1], 7, 6, 5, 30, 99) == VX_OK);
    vx_svo_instance ib = ts_inst(0, NULL, 2, -1, 0.5);
    const double c = cos(0.7), sn = sin(0.7);
    vx_svo_instance it[3] = {ts_inst(0, NULL, 2, -1, 0.5), ts_inst(1, (const double[9]){c, -sn, 0, sn, c, 0, 0, 0, 1}, 9, 4, -2),
                             ts_inst(1, (const double[9]){1, 0, 0, 0, 0, -1, 0, 1, 0}, -6, 2, 3)};
    vx_svo_scene sc[2];
    ts_scene(&sc[0], box, 1, &ib, 1);
    ts_scene(&sc[1], two, 2, it, 3);
    uint32_t seed = 4242;
    int culled = 0, far_views = 0, tight_checked = 0;
    for (int si = 0; si < 2; si++) {
        double lo[3], hi[3], ctr[3], rad = 0;
        vx_svo_scene_world_bounds(&sc[si], lo, hi);
        for (int k = 0; k < 3; k++) ctr[k] = 0.5 * (lo[k] + hi[k]), rad += 0.25 * (hi[k] - lo[k]) * (hi[k] - lo[k]);
        rad = sqrt(rad);
        for (int view = 0; view < 60; view++) {
            /* 0-2: inside, near, far (perspective); 3: far orthographic; 4: away */
            int kind = view % 5;
            double dist = rad * (kind == 0 ? 0.2 : kind == 1 ? 1.6 : 4 + ts_rng(&seed) % 5);
            double dir[3], dl = 0;
            for (int k = 0; k < 3; k++) dir[k] = (double)(ts_rng(&seed) % 2001) - 1000, dl += dir[k] * dir[k];
            dl = sqrt(dl);
            vx_render_desc d = {.width = W, .height = H, .mode = VX_RENDER_DEPTH, .want_hits = true};
            d.camera.set = true;
            d.camera.fov = 30 + ts_rng(&seed) % 60;
            d.camera.ortho = kind == 3;
            d.camera.ortho_height = 2.5 * rad;
            for (int k = 0; k < 3; k++) {
                d.camera.eye[k] = ctr[k] + dir[k] / dl * dist;
                /* the target off the centre by up to half the radius: boxes cut by the image's edges */
                double off = ((double)(ts_rng(&seed) % 1001) / 1000 - 0.5) * rad;
                d.camera.target[k] = kind == 4 ? 2 * d.camera.eye[k] - ctr[k] : ctr[k] + off;
            }
            vx__frame f;
            vx_error err = {0};
            REQUIRE(vx__frame_setup(lo, hi, &d, &f, &err) == VX_OK);
            uint32_t r[4];
            vx__frame_rect(&f, lo, hi, r);
            CHECK(r[0] <= r[2] && r[1] <= r[3] && r[2] <= W && r[3] <= H);
            vx_render_image img;
            REQUIRE(vx_render_cpu(&sc[si], &d, NULL, &img, &err) == VX_OK);
            int out = 0, hits = 0;
            uint32_t hx0 = W, hy0 = H, hx1 = 0, hy1 = 0;
            for (uint32_t y = 0; y < H; y++)
                for (uint32_t x = 0; x < W; x++) {
                    if (img.hits[y * W + x].instance == VX_RENDER_NO_HIT) continue;
                    hits++;
                    if (x < r[0] || x >= r[2] || y < r[1] || y >= r[3]) out++;
                    hx0 = x < hx0 ? x : hx0, hy0 = y < hy0 ? y : hy0;
                    hx1 = x + 1 > hx1 ? x + 1 : hx1, hy1 = y + 1 > hy1 ? y + 1 : hy1;
                }
            CHECK(out == 0);
            if (out) printf("screen rect: scene %d view %d: %d of %d hits outside [%u,%u)x[%u,%u)\n", si, view, out, hits,
                            r[0], r[2], r[1], r[3]);
            bool full = r[0] == 0 && r[1] == 0 && r[2] == W && r[3] == H;
            if (kind == 0) CHECK(full);
            if (kind == 4) CHECK(r[0] == 0 && r[1] == 0 && r[2] == 0 && r[3] == 0 && hits == 0);
            if (kind >= 2 && kind <= 3) {
                far_views++;
                culled += !full;
                /* the box's corners are filled: its rectangle is the hits' within the margin
                 * (2 pixels) and the pixel grid (a corner's nearest centre inside) */
                if (si == 0 && hits) {
                    tight_checked++;
                    CHECK(r[0] == 0 || r[0] + 5 >= hx0);
                    CHECK(r[1] == 0 || r[1] + 5 >= hy0);
                    CHECK(r[2] == W || r[2] <= hx1 + 5);
                    CHECK(r[3] == H || r[3] <= hy1 + 5);
                }
            }
            vx_render_image_free(&img);
        }
    }
    printf("screen rect: %d of %d far views culled, %d checked for tightness\n", culled, far_views, tight_checked);
    CHECK(culled * 2 > far_views);
    CHECK(tight_checked >= 20);
    vx_svo_scene_free(&sc[0]);
    vx_svo_scene_free(&sc[1]);
}

/* Whether instance item lies in the BVH subtree of node n. */
static bool bvh_subtree_has(const vx_bvh* b, uint32_t n, uint32_t item) {
    const vx_bvh_node* nd = &b->nodes[n];
    if (nd->count) {
        for (uint32_t k = 0; k < nd->count; k++)
            if (b->items[nd->first + k] == item) return true;
        return false;
    }
    return bvh_subtree_has(b, nd->first, item) || bvh_subtree_has(b, nd->first + 1, item);
}

/* vx__frame_tiles (trace.comp's BVH start per screen tile) is conservative:
 * the instance of every pixel that the CPU reference sees hit lies in the
 * subtree of its tile's start node (never a tile marked none), for cameras
 * among the instances (boxes that cross the eye's plane: vx__frame_rect's
 * cut), near and far, perspective and orthographic; and it culls: far views
 * start tiles below the root and mark tiles none. The instances are boxes of
 * filled cells (hits reach their boxes' silhouettes). */
static void test_screen_tiles(void) {
    enum { W = 96, H = 72, NI = 24 };
    uint32_t sa[3] = {3, 2, 2}, sb[3] = {2, 2, 3}, xa[3 * 12], xb[3 * 12], na = 0, nb = 0;
    for (uint32_t z = 0; z < 3; z++)
        for (uint32_t y = 0; y < 2; y++)
            for (uint32_t x = 0; x < 3; x++) {
                if (x < sa[0] && z < sa[2]) xa[3 * na] = x, xa[3 * na + 1] = y, xa[3 * na + 2] = z, na++;
                if (x < sb[0] && z < sb[2]) xb[3 * nb] = x, xb[3 * nb + 1] = y, xb[3 * nb + 2] = z, nb++;
            }
    vx_svo_model m[2];
    REQUIRE(ts_model(&m[0], sa, xa, NULL, na) == VX_OK);
    REQUIRE(ts_model(&m[1], sb, xb, NULL, nb) == VX_OK);
    static const double rot[9] = {0, -1, 0, 1, 0, 0, 0, 0, 1};
    vx_svo_instance in[NI];
    for (uint32_t i = 0; i < NI; i++)
        in[i] = ts_inst(i % 2, i % 3 == 0 ? rot : NULL, 5.0 * (i % 4), 6.0 * ((i / 4) % 3), 7.0 * (i / 12));
    vx_svo_scene sc;
    ts_scene(&sc, m, 2, in, NI);
    double blo[3 * NI], bhi[3 * NI], lo[3], hi[3], ctr[3], rad = 0;
    for (uint32_t i = 0; i < NI; i++) vx_svo_instance_world_box(&sc, &sc.instances[i], &blo[3 * i], &bhi[3 * i]);
    vx_bvh bvh;
    vx_error err = {0};
    REQUIRE(vx_bvh_build(blo, bhi, NI, NULL, &bvh, &err) == VX_OK);
    vx_svo_scene_world_bounds(&sc, lo, hi);
    for (int k = 0; k < 3; k++) ctr[k] = 0.5 * (lo[k] + hi[k]), rad += 0.25 * (hi[k] - lo[k]) * (hi[k] - lo[k]);
    rad = sqrt(rad);
    uint32_t seed = 777;
    int deeper = 0, none = 0, inside_deeper = 0, checked = 0;
    for (int view = 0; view < 200; view++) {
        /* 0-1: among the instances, 2: near, 3: far, 4: far orthographic */
        int kind = view % 5;
        vx_render_desc d = {.width = W, .height = H, .mode = VX_RENDER_DEPTH, .want_hits = true};
        d.camera.set = true;
        d.camera.fov = 30 + ts_rng(&seed) % 60;
        d.camera.ortho = kind == 4;
        d.camera.ortho_height = 2.5 * rad;
        double dir[3], dl = 0;
        for (int k = 0; k < 3; k++) dir[k] = (double)(ts_rng(&seed) % 2001) - 1000, dl += dir[k] * dir[k];
        dl = sqrt(dl);
        for (int k = 0; k < 3; k++) {
            double u = (double)(ts_rng(&seed) % 1001) / 1000;
            if (kind <= 1) {
                d.camera.eye[k] = lo[k] + u * (hi[k] - lo[k]);
                d.camera.target[k] = d.camera.eye[k] + dir[k] / dl;
            } else {
                double dist = rad * (kind == 2 ? 1.6 : 4 + ts_rng(&seed) % 5);
                d.camera.eye[k] = ctr[k] + dir[k] / dl * dist;
                d.camera.target[k] = ctr[k] + (u - 0.5) * rad;
            }
        }
        vx__frame f;
        REQUIRE(vx__frame_setup(lo, hi, &d, &f, &err) == VX_OK);
        uint16_t tiles[VX__TILES_X * VX__TILES_X];
        uint32_t shift = 0, nx = 0;
        vx__frame_tiles(&f, &bvh, tiles, &shift, &nx);
        CHECK(nx <= VX__TILES_X && ((H + (1u << shift) - 1) >> shift) <= VX__TILES_X);
        vx_render_image img;
        REQUIRE(vx_render_cpu(&sc, &d, NULL, &img, &err) == VX_OK);
        int bad = 0;
        for (uint32_t y = 0; y < H; y++)
            for (uint32_t x = 0; x < W; x++) {
                uint32_t t = tiles[(y >> shift) * nx + (x >> shift)];
                if (t != 0 && t != VX__TILE_NONE) {
                    deeper++;
                    inside_deeper += kind <= 1;
                }
                none += t == VX__TILE_NONE && kind >= 3;
                uint32_t id = img.hits[y * W + x].instance;
                if (id == VX_RENDER_NO_HIT) continue;
                checked++;
                if (t == VX__TILE_NONE || !bvh_subtree_has(&bvh, t, id)) bad++;
            }
        CHECK(bad == 0);
        if (bad) printf("screen tiles: view %d (kind %d): %d hit pixels outside their tile's start node\n", view, kind, bad);
        vx_render_image_free(&img);
    }
    printf("screen tiles: %d hit pixels checked; pixels below the root %d (%d from inside), none %d\n", checked, deeper,
           inside_deeper, none);
    CHECK(checked > 10000);
    CHECK(deeper > W * H * 10);
    CHECK(inside_deeper > W * H);
    CHECK(none > W * H);
    vx_bvh_free(&bvh);
    vx_svo_scene_free(&sc);
}

int main(void) {
    RUN(test_bvh_structure_and_speed);
    RUN(test_cpu_vs_brute_force);
    RUN(test_desc_validation);
    RUN(test_too_deep_refused);
    RUN(test_cpu_root_leaf);
    RUN(test_default_camera);
    RUN(test_screen_rect);
    RUN(test_screen_tiles);
    return vx_test_finish();
}
