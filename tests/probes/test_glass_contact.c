/* tests/probes/test_glass_contact.c - opaque voxels against glass, seen
 * through it: a glass slab standing on a floor (its bottom face touches the
 * floor's cells), the commonest way glass meets other voxels. A walk through
 * the glass that reaches such a face meets the opaque voxel from inside the
 * glass; before, every walk (the path tracers', the photons', the passes')
 * ended there with no light, so the floor under a glass block, and anything
 * set into glass, rendered black. Now that face is a surface: its emission
 * counts, and the path tracers bounce off it back into the glass (light
 * reaches it only through the glass: no light is sampled there, a shadow ray
 * starting in glass meets the glass). Seen from far above, a little off the
 * vertical:
 *  - emissive floor, black sky, a point light above (the passes' radiometric
 *    model): each pixel whose ray enters the slab's top and meets the floor
 *    under it sees tint x (1 - F_in) x the floor's emission, exactly (F at
 *    the entry angle, tint the glass cell's colour). The passes per pixel,
 *    the CPU and the GPU path tracers by their mean over those pixels;
 *  - a diffuse floor under the slab, walled in by an opaque rim as high as
 *    the slab (so that no light comes in through its sides), a white
 *    constant sky of radiance L, one bounce: the floor under the glass is lit
 *    by the sky through the slab's top, E = 2 pi L int_0^theta_c (1 -
 *    F(theta)) cos sin dtheta (theta_c the critical angle: the rest reflects
 *    back down, or meets the rim, and needs a second bounce), so the pixel
 *    sees F_in L (the sky in the top face) + tint x (1 - F_in) x albedo / pi
 *    x E. Both path tracers by their means (the passes do not follow light
 *    into glass: not checked);
 *  - a model placed overlapping a glass one (MagicaVoxel's water model over
 *    a riverbed): an emissive block of its own instance inside a thick
 *    uniform glass body, where the walks step over whole leaves of glass,
 *    must render as the same block set into the glass model itself (one
 *    model): the passes per pixel, both path tracers by their means (before:
 *    the block was not seen);
 *  - photons from the point light above (photon mapping): those that enter
 *    the slab's top and land on the floor under it are stored there as
 *    caustic photons, their power over a square of the floor the closed form
 *    I x the integral over the directions of the light's rays that land in
 *    it of tint x (1 - F_in) (before: none stored there).
 * Skips without a Vulkan device. */
#include <dlfcn.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "photons/photons.h"
#include "probes/probes.h"
#include "render/pipeline.h"
#include "tests/probes/closed_form.h"
#include "tests/probes/probe_scenes.h"
#include "tests/test.h"

static const double PI = 3.14159265358979323846;
static vx_gpu* gpu;

/* floor S x S at z = 0; slab x, y in [X0, X1), z in [1, 1 + T) */
enum { W = 32, H = 24, S = 48, X0 = 8, X1 = 40, T = 6 };
static const uint32_t FLOOR_RGBA = 0xFF4090D0u, TINT_RGBA = 0xFFE0F0FFu;
static const double IOR = 1.5, EMIT = 2.0;

static void contact_scene(vx_svo_scene* s, bool emissive) {
    size_t cap = (size_t)S * S + (size_t)(X1 - X0 + 2) * (X1 - X0 + 2) * T, n = 0;
    uint32_t* xyz = malloc(cap * 12);
    uint8_t* pal = malloc(cap);
    REQUIRE(xyz && pal);
    for (uint32_t y = 0; y < S; y++)
        for (uint32_t x = 0; x < S; x++) xyz[3 * n] = x, xyz[3 * n + 1] = y, xyz[3 * n + 2] = 0, pal[n++] = 1;
    for (uint32_t z = 1; z < 1 + T; z++)
        for (uint32_t y = X0 - 1; y < X1 + 1; y++)
            for (uint32_t x = X0 - 1; x < X1 + 1; x++) {
                bool wall = x < X0 || x >= X1 || y < X0 || y >= X1;
                if (wall && emissive) continue;
                xyz[3 * n] = x, xyz[3 * n + 1] = y, xyz[3 * n + 2] = z, pal[n++] = wall ? 3 : 2;
            }
    vx_svo_model m;
    uint32_t size[3] = {S, S, 1 + T};
    REQUIRE(ts_model(&m, size, xyz, pal, n) == VX_OK);
    free(xyz), free(pal);
    vx_svo_instance in = ts_inst(0, NULL, 0, 0, 0);
    ts_scene(s, &m, 1, &in, 1);
    s->palette[1] = FLOOR_RGBA, s->palette[2] = TINT_RGBA, s->palette[3] = 0xFF808080u;
    const char* glass[] = {"_type", "_glass", "_trans", "1", "_ior", "0.5", "_rough", "0"};
    add_material(s, 2, glass, 4);
    if (emissive) {
        const char* emit[] = {"_type", "_emit", "_emit", "2"};
        add_material(s, 1, emit, 2);
    }
}

static vx_render_desc camera(void) {
    vx_render_desc b = {.width = W, .height = H, .spp = 1};
    b.camera.set = true;
    b.camera.eye[0] = 24 + 9, b.camera.eye[1] = 24 + 15, b.camera.eye[2] = 1 + T + 900.0;
    b.camera.target[0] = 24, b.camera.target[1] = 24, b.camera.target[2] = 1;
    b.camera.up[1] = 1, b.camera.fov = 1.6;
    return b;
}

static vx_light point_light(void) {
    vx_light L = {.type = VX_LIGHT_POINT, .color = {1, 1, 1}, .intensity = 60, .range = 1000};
    L.position[0] = 24, L.position[1] = 24, L.position[2] = 40;
    return L;
}

/* The pass pipeline's frame (gbuffer,direct), the point light, a black sky. */
static bool frame(const vx_svo_scene* s, vx_render_image* out) {
    vx_light L = point_light();
    vx_render_desc base = camera();
    return ps_pass_frame(gpu, s, &base, &L, 1, out);
}

/* The path tracer (GPU with gpu_rs, else CPU) at pixel centres: `bounces`
 * diffuse bounces, sky radiance `sky`, the point light where lit. */
static bool pathtrace(const vx_svo_scene* s, vx_render_scene* gpu_rs, uint32_t spp, uint32_t bounces, double sky_l,
                      bool lit, vx_render_image* out) {
    vx_light L = point_light();
    vx_render_desc base = camera();
    return ps_pathtrace(s, gpu_rs, &base, spp, bounces, sky_l, lit ? &L : NULL, lit ? 1 : 0, out);
}

static bool inside(double v, double lo, double hi, double margin) { return v > lo + margin && v < hi - margin; }

/* Pixel (px, py)'s centre ray: whether it enters the slab's top 0.5 inside
 * its sides and, refracted, meets the floor under the slab 2 + T cells
 * inside them (so that the sky-lit floor's cone of exits stays on the top
 * face); then its entry factor tint x (1 - F_in) per channel and F_in. */
static bool pixel_factor(uint32_t px, uint32_t py, double f[3], double* fr) {
    vx_render_desc b = camera();
    const double* e = b.camera.eye;
    double d[3];
    cf_pixel_ray(&b, px, py, d);
    if (!(d[2] < 0)) return false;
    double top = 1 + (double)T, t0 = (top - e[2]) / d[2], a[3];
    for (int k = 0; k < 3; k++) a[k] = e[k] + t0 * d[k];
    if (!inside(a[0], X0, X1, 0.5) || !inside(a[1], X0, X1, 0.5)) return false;
    double c = -d[2], ei = 1 / IOR, k2 = 1 - ei * ei * (1 - c * c), n[3] = {0, 0, 1}, di[3];
    for (int k = 0; k < 3; k++) di[k] = ei * d[k] + (ei * c - sqrt(k2)) * n[k];
    double t1 = (1 - a[2]) / di[2], q[3];
    for (int k = 0; k < 3; k++) q[k] = a[k] + t1 * di[k];
    if (!inside(q[0], X0, X1, 2 + T) || !inside(q[1], X0, X1, 2 + T)) return false;
    *fr = cf_fresnel(c, IOR);
    for (int k = 0; k < 3; k++) f[k] = (1 - *fr) * ((TINT_RGBA >> (8 * k)) & 255) / 255.0;
    return true;
}

/* Irradiance on a surface under glass of index IOR from a constant sky of
 * radiance 1 through a horizontal face: the directions inside the glass
 * within the critical angle leave it with 1 - F (midpoint rule, 20000
 * steps). */
static double sky_through_glass(void) {
    double tc = asin(1 / IOR), sum = 0;
    int n = 20000;
    for (int i = 0; i < n; i++) {
        double th = (i + 0.5) * tc / n;
        sum += (1 - cf_fresnel(cos(th), 1 / IOR)) * cos(th) * sin(th);
    }
    return 2 * PI * sum * tc / n;
}

/* Means over the pixels pixel_factor accepts: want (closed form: the entry
 * factor times scale, plus F_in times the sky) and the images'. */
static size_t means(const vx_render_image* const* ims, int count, double scale[3], double sky, double* want,
                    double* got) {
    size_t n = 0;
    *want = 0;
    for (int i = 0; i < count; i++) got[i] = 0;
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            double f[3], fr;
            if (!pixel_factor(x, y, f, &fr)) continue;
            size_t at = 4 * ((size_t)y * W + x);
            for (int k = 0; k < 3; k++) {
                *want += f[k] * scale[k] + fr * sky;
                for (int i = 0; i < count; i++) got[i] += ims[i]->pixels[at + k];
            }
            n++;
        }
    return n;
}

/* The emissive floor under the slab, seen through it. */
static void test_emissive_floor_under_glass(void) {
    if (!gpu) SKIP("no Vulkan device");
    vx_svo_scene s;
    contact_scene(&s, true);
    vx_render_image im = {0}, cpu = {0}, gpt = {0};
    REQUIRE(frame(&s, &im));
    REQUIRE(pathtrace(&s, NULL, 64, 0, 0, true, &cpu));
    vx_error err = {0};
    vx_render_scene* rs = NULL;
    REQUIRE(vx_render_scene_create(gpu, &s, &rs, &err) == VX_OK);
    REQUIRE(pathtrace(&s, rs, 64, 0, 0, true, &gpt));
    vx_render_scene_destroy(rs);
    double le[3], worst = 0;
    for (int k = 0; k < 3; k++) le[k] = EMIT * ((FLOOR_RGBA >> (8 * k)) & 255) / 255.0;
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            double f[3], fr;
            if (!pixel_factor(x, y, f, &fr)) continue;
            for (int k = 0; k < 3; k++)
                worst = fmax(worst, fabs(im.pixels[4 * ((size_t)y * W + x) + k] - f[k] * le[k]) / (f[k] * le[k]));
        }
    const vx_render_image* ims[2] = {&cpu, &gpt};
    double want, got[2];
    size_t n = means(ims, 2, le, 0, &want, got);
    fprintf(stderr, "  %zu pixels onto the floor under the glass: passes' worst relative error %.2e; mean ratio to the "
            "closed form: CPU path tracer %.4f, GPU path tracer %.4f\n", n, worst, got[0] / want, got[1] / want);
    CHECK(n > 200);
    CHECKF(worst < 5e-3, "passes: worst relative error %.2e", worst);
    CHECKF(fabs(got[0] / want - 1) < 0.02, "CPU path tracer: mean ratio %.4f", got[0] / want);
    CHECKF(fabs(got[1] / want - 1) < 0.02, "GPU path tracer: mean ratio %.4f", got[1] / want);
    vx_render_image_free(&im), vx_render_image_free(&cpu), vx_render_image_free(&gpt);
    vx_svo_scene_free(&s);
}

/* A diffuse floor under the slab, lit by a white sky through the glass. */
static void test_floor_lit_through_glass(void) {
    if (!gpu) SKIP("no Vulkan device");
    vx_svo_scene s;
    contact_scene(&s, false);
    vx_render_image cpu = {0}, gpt = {0};
    REQUIRE(pathtrace(&s, NULL, 128, 1, 1, false, &cpu));
    vx_error err = {0};
    vx_render_scene* rs = NULL;
    REQUIRE(vx_render_scene_create(gpu, &s, &rs, &err) == VX_OK);
    REQUIRE(pathtrace(&s, rs, 128, 1, 1, false, &gpt));
    vx_render_scene_destroy(rs);
    double e = sky_through_glass(), scale[3];
    for (int k = 0; k < 3; k++) scale[k] = ((FLOOR_RGBA >> (8 * k)) & 255) / 255.0 / PI * e;
    const vx_render_image* ims[2] = {&cpu, &gpt};
    double want, got[2];
    size_t n = means(ims, 2, scale, 1, &want, got);
    fprintf(stderr, "  %zu pixels onto the floor under the glass, irradiance through the glass %.4f (the open sky's "
            "%.4f): mean ratio to the closed form: CPU path tracer %.4f, GPU path tracer %.4f\n", n, e, PI,
            got[0] / want, got[1] / want);
    CHECK(n > 200);
    CHECKF(fabs(got[0] / want - 1) < 0.03, "CPU path tracer: mean ratio %.4f", got[0] / want);
    CHECKF(fabs(got[1] / want - 1) < 0.03, "GPU path tracer: mean ratio %.4f", got[1] / want);
    vx_render_image_free(&cpu), vx_render_image_free(&gpt);
    vx_svo_scene_free(&s);
}

/* The overlap scenes: a floor (palette 1) at z = 0 and a glass body
 * (palette 2) x, y in [8, 40), z in [8, 24), whose 8^3 leaves are uniform;
 * an emissive block (palette 4) at [18, 22) x [18, 22) x [17, 20), inside
 * the leaf [16, 24)^3: its own model and instance over the glass (overlap),
 * or the glass model's own cells there (the twin). */
static void overlap_scene(vx_svo_scene* s, bool twin) {
    size_t cap = (size_t)S * S + 32 * 32 * 16 + 64, n = 0, nb = 0;
    uint32_t *xyz = malloc(cap * 12), bxyz[48 * 3];
    uint8_t *pal = malloc(cap), bpal[48];
    REQUIRE(xyz && pal);
    for (uint32_t y = 0; y < S; y++)
        for (uint32_t x = 0; x < S; x++) xyz[3 * n] = x, xyz[3 * n + 1] = y, xyz[3 * n + 2] = 0, pal[n++] = 1;
    for (uint32_t z = 8; z < 24; z++)
        for (uint32_t y = 8; y < 40; y++)
            for (uint32_t x = 8; x < 40; x++) {
                bool block = x >= 18 && x < 22 && y >= 18 && y < 22 && z >= 17 && z < 20;
                xyz[3 * n] = x, xyz[3 * n + 1] = y, xyz[3 * n + 2] = z, pal[n++] = block && twin ? 4 : 2;
                if (block) bxyz[3 * nb] = x - 18, bxyz[3 * nb + 1] = y - 18, bxyz[3 * nb + 2] = z - 17, bpal[nb++] = 4;
            }
    vx_svo_model m[2];
    uint32_t size[3] = {S, S, 24}, bsize[3] = {4, 4, 3};
    REQUIRE(ts_model(&m[0], size, xyz, pal, n) == VX_OK);
    if (!twin) REQUIRE(ts_model(&m[1], bsize, bxyz, bpal, nb) == VX_OK);
    free(xyz), free(pal);
    vx_svo_instance in[2] = {ts_inst(0, NULL, 0, 0, 0), ts_inst(1, NULL, 18, 18, 17)};
    ts_scene(s, m, twin ? 1 : 2, in, twin ? 1 : 2);
    s->palette[1] = FLOOR_RGBA, s->palette[2] = TINT_RGBA, s->palette[4] = 0xFF2040F0u;
    const char* glass[] = {"_type", "_glass", "_trans", "1", "_ior", "0.5", "_rough", "0"};
    const char* emit[] = {"_type", "_emit", "_emit", "3"};
    add_material(s, 2, glass, 4);
    add_material(s, 4, emit, 2);
}

/* A model overlapping the glass renders as the same voxels set into the
 * glass model. */
static void test_overlapping_instance(void) {
    if (!gpu) SKIP("no Vulkan device");
    vx_svo_scene ov, tw;
    overlap_scene(&ov, false);
    overlap_scene(&tw, true);
    fprintf(stderr, "  glass model: %u octree nodes for %llu cells\n", ov.models[0].node_count,
            (unsigned long long)ov.models[0].voxel_count);
    vx_render_image im[2] = {{0}}, cpu[2] = {{0}}, gpt[2] = {{0}};
    const vx_svo_scene* sc[2] = {&ov, &tw};
    for (int i = 0; i < 2; i++) {
        REQUIRE(frame(sc[i], &im[i]));
        REQUIRE(pathtrace(sc[i], NULL, 64, 0, 0, true, &cpu[i]));
        vx_error err = {0};
        vx_render_scene* rs = NULL;
        REQUIRE(vx_render_scene_create(gpu, sc[i], &rs, &err) == VX_OK);
        REQUIRE(pathtrace(sc[i], rs, 64, 0, 0, true, &gpt[i]));
        vx_render_scene_destroy(rs);
    }
    /* the pixels that see the block (bright red in the twin's passes: palette 4 is R 0xF0), and every pixel */
    double worst = 0, sum[3][2] = {{0}};
    size_t block = 0;
    for (size_t p = 0; p < (size_t)W * H; p++) {
        const float* a = im[0].pixels + 4 * p;
        const float* b = im[1].pixels + 4 * p;
        bool sees = b[0] > 1.0f;
        block += sees;
        for (int k = 0; k < 3; k++) {
            worst = fmax(worst, fabs(a[k] - b[k]) / fmax(fabs(b[k]), 1e-3));
            if (!sees) continue;
            sum[0][0] += cpu[0].pixels[4 * p + k], sum[0][1] += cpu[1].pixels[4 * p + k];
            sum[1][0] += gpt[0].pixels[4 * p + k], sum[1][1] += gpt[1].pixels[4 * p + k];
            sum[2][0] += a[k], sum[2][1] += b[k];
        }
    }
    fprintf(stderr, "  %zu pixels see the block: passes' worst relative difference to the twin %.2e (their block "
            "pixels' sum %.4g and %.4g); path tracers overlap / twin: CPU %.4f, GPU %.4f\n", block, worst, sum[2][0],
            sum[2][1], sum[0][0] / sum[0][1], sum[1][0] / sum[1][1]);
    CHECK(block >= 9);
    CHECKF(worst < 1e-3, "passes: worst relative difference %.2e", worst);
    CHECKF(fabs(sum[0][0] / sum[0][1] - 1) < 0.03, "CPU path tracer: %.4f", sum[0][0] / sum[0][1]);
    CHECKF(fabs(sum[1][0] / sum[1][1] - 1) < 0.03, "GPU path tracer: %.4f", sum[1][0] / sum[1][1]);
    for (int i = 0; i < 2; i++)
        vx_render_image_free(&im[i]), vx_render_image_free(&cpu[i]), vx_render_image_free(&gpt[i]);
    vx_svo_scene_free(&ov);
    vx_svo_scene_free(&tw);
}

/* Photons from the point light through the slab onto the floor under it:
 * the caustic power stored on the square [X0 + 4, X1 - 4)^2 of the floor's
 * top against I x sum over the light's directions (a fine grid over the
 * slab's top, each direction's solid angle) that refract into the square of
 * tint x (1 - F_in) x the light's range window. */
static void test_photons_through_glass(void) {
    if (!gpu) SKIP("no Vulkan device");
    vx_svo_scene s;
    contact_scene(&s, false);
    double black[3] = {0, 0, 0};
    vx_probe_set light = light_only(0, black, 1);
    vx_light L = point_light();
    vx_photon_desc d = {.photons = 200000, .bounces = 1, .capacity = 2000000, .lights = &L, .light_count = 1};
    vx_error err = {0};
    vx_render_scene* rs = NULL;
    vx_photon_gi* pg = NULL;
    vx_gi_method gm;
    REQUIRE(vx_render_scene_create(gpu, &s, &rs, &err) == VX_OK);
    REQUIRE(vx_photon_gi_create(rs, &s, &light, &d, &gm, &pg, &err) == VX_OK);
    vx_render_desc base = {.width = 4, .height = 4};
    vx_render_image im = {0};
    REQUIRE(vx_photon_render(pg, &base, 1, false, &im, &err) == VX_OK);
    vx_photon_record* ph = NULL;
    size_t n = 0;
    REQUIRE(vx_photon_stored(pg, &ph, &n, &err) == VX_OK);
    double lo = X0 + 4, hi = X1 - 4, got[3] = {0, 0, 0};
    size_t under = 0;
    for (size_t i = 0; i < n; i++) {
        const double* p = ph[i].position;
        if (!(ph[i].flags & VX_PHOTON_CAUSTIC) || fabs(p[2] - 1) > 0.01 || p[0] < lo || p[0] >= hi || p[1] < lo ||
            p[1] >= hi)
            continue;
        for (int k = 0; k < 3; k++) got[k] += ph[i].power[k];
        under++;
    }
    /* the closed form: rays from the light to points of the top (z = 1 + T) on a fine grid */
    const double* e = L.position;
    double want = 0, top = 1 + (double)T, step = 1.0 / 64;
    for (double y = X0; y < X1; y += step)
        for (double x = X0; x < X1; x += step) {
            double a[3] = {x + step / 2, y + step / 2, top}, v[3] = {a[0] - e[0], a[1] - e[1], a[2] - e[2]};
            double d2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2], dist = sqrt(d2), dv[3] = {v[0] / dist, v[1] / dist, v[2] / dist};
            double c = -dv[2], ei = 1 / IOR, k2 = 1 - ei * ei * (1 - c * c), di[3];
            for (int k = 0; k < 3; k++) di[k] = ei * dv[k] + (ei * c - sqrt(k2)) * (k == 2 ? 1 : 0);
            double t1 = (1 - top) / di[2], q[2] = {a[0] + t1 * di[0], a[1] + t1 * di[1]};
            if (q[0] < lo || q[0] >= hi || q[1] < lo || q[1] >= hi) continue;
            double qq = (dist / L.range) * (dist / L.range), win = (1 - qq * qq) * (1 - qq * qq);
            want += L.intensity * (1 - cf_fresnel(c, IOR)) * win * c / d2 * step * step; /* dOmega = cos dA / d^2 */
        }
    fprintf(stderr, "  %zu caustic photons on the floor under the glass of %zu stored: power", under, n);
    for (int k = 0; k < 3; k++) {
        double tint = ((TINT_RGBA >> (8 * k)) & 255) / 255.0;
        fprintf(stderr, " %.4g (%.4g)", got[k], want * tint);
        CHECKF(fabs(got[k] / (want * tint) - 1) < 0.03, "channel %d: %.5g against %.5g", k, got[k], want * tint);
    }
    fprintf(stderr, "\n");
    CHECK(under > 5000);
    vx_free(NULL, ph);
    vx_render_image_free(&im);
    vx_photon_gi_destroy(pg);
    vx_render_scene_destroy(rs);
    vx_svo_scene_free(&s);
}

int main(void) {
    (void)ts_random_model, (void)room_scene, (void)box_scene, (void)cells_scene;
    dlopen("libvulkan_lvp.so", RTLD_NOW | RTLD_NODELETE); /* see test_probes_gpu.c */
    vx_error err = {0};
    if (vx_gpu_create(&(vx_gpu_desc){0}, &gpu, &err)) {
        fprintf(stderr, "no Vulkan device (%s): GPU comparisons skipped\n", err.msg);
        gpu = NULL;
    }
    RUN(test_emissive_floor_under_glass);
    RUN(test_floor_lit_through_glass);
    RUN(test_overlapping_instance);
    RUN(test_photons_through_glass);
    if (gpu) vx_gpu_destroy(gpu);
    return vx_test_finish();
}
