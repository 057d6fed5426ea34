/* tests/probes/test_metal_direct.c - metal seen directly in the pass
 * pipeline (render/shaders/pass_bodies.glsl direct_pixel, resolve_pixel):
 * a flat metal plate under one point light and a black sky against
 *  - the BRDF written here in double (the path tracer's lobe, probes/pathtrace.c:
 *    Lambert kd / pi plus GGX D, Smith height-correlated G2, Schlick F) for
 *    each pixel's view and light directions (a point light is a delta: the
 *    direct term is exact), merged and separate passes;
 *  - the CPU path tracer (nothing else in the scene: no indirect light);
 *  - a plate without metal: Lambert albedo / pi E, the same pixels whether
 *    or not the scene has metal elsewhere (its SPIR-V path then differs);
 *  - the sky term of a metal under a uniform sky: kd E_sky / pi plus the sky
 *    times the lobe's directional albedo, against a quadrature written here.
 * Skips without a Vulkan device. */
#include <dlfcn.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "probes/probes.h"
#include "render/pipeline.h"
#include "tests/probes/probe_scenes.h"
#include "tests/test.h"

static const double PI = 3.14159265358979323846;
static vx_gpu* gpu;

enum { W = 40, H = 30, N = 16 };
static const uint32_t PLATE_RGBA = 0xFF4090D0u; /* R 0xD0, G 0x90, B 0x40 */
static const double LIGHT_POS[3] = {6, 9, 5}, LIGHT_I = 60;

/* palette 1 in the left half, palette 2 in the right: a 16 x 16 x 1 plate, top face at z = 1 */
static uint8_t plate_cell(uint32_t x, uint32_t y, uint32_t z, uint32_t n) {
    (void)y;
    return z == 0 ? (x < n / 2 ? 1 : 2) : 0;
}

/* The plate; metal (palette 1 and 2, or 1 only) with metalness mt, roughness rough, specular sp (NULL: no metal). */
static void plate_scene(vx_svo_scene* s, const char* mt, const char* rough, const char* sp, bool both) {
    cells_scene(s, N, plate_cell);
    s->palette[1] = s->palette[2] = PLATE_RGBA;
    if (!mt) return;
    const char* kv[] = {"_type", "_metal", "_metal", mt, "_rough", rough, "_spec", sp};
    add_material(s, 1, kv, 4);
    if (both) add_material(s, 2, kv, 4);
}

static vx_render_desc camera(void) {
    vx_render_desc b = {.width = W, .height = H, .spp = 1};
    b.camera.set = true;
    b.camera.eye[0] = 8, b.camera.eye[1] = -7, b.camera.eye[2] = 12;
    b.camera.target[0] = 8, b.camera.target[1] = 8, b.camera.target[2] = 1;
    b.camera.up[2] = 1, b.camera.fov = 40;
    return b;
}

/* The pixel-centre ray of the camera above (render/render.h's pinhole: u
 * across, v up, the half height tan(fov / 2)) meeting the plate's top z = 1:
 * the point, and whether it lies on the plate 0.25 from its edges. */
static bool pixel_point(const vx_render_desc* b, uint32_t px, uint32_t py, double p[3]) {
    const double* e = b->camera.eye;
    double f[3], r[3], u[3], up[3] = {0, 0, 1};
    for (int k = 0; k < 3; k++) f[k] = b->camera.target[k] - e[k];
    double lf = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    for (int k = 0; k < 3; k++) f[k] /= lf;
    r[0] = f[1] * up[2] - f[2] * up[1], r[1] = f[2] * up[0] - f[0] * up[2], r[2] = f[0] * up[1] - f[1] * up[0];
    double lr = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    for (int k = 0; k < 3; k++) r[k] /= lr;
    u[0] = r[1] * f[2] - r[2] * f[1], u[1] = r[2] * f[0] - r[0] * f[2], u[2] = r[0] * f[1] - r[1] * f[0];
    double hh = tan(0.5 * b->camera.fov * PI / 180), hw = hh * (double)b->width / b->height;
    double su = ((px + 0.5) / b->width) * 2 - 1, sv = 1 - ((py + 0.5) / b->height) * 2, d[3];
    for (int k = 0; k < 3; k++) d[k] = f[k] + su * hw * r[k] + sv * hh * u[k];
    if (!(d[2] < 0)) return false;
    double t = (1 - e[2]) / d[2];
    for (int k = 0; k < 3; k++) p[k] = e[k] + t * d[k];
    return p[0] > 0.25 && p[0] < N - 0.25 && p[1] > 0.25 && p[1] < N - 0.25;
}

static double lambda(double a2, double z) {
    double z2 = z * z;
    return z2 >= 1 ? 0 : 0.5 * (-1 + sqrt(1 + a2 * (1 - z2) / z2));
}

/* The radiance a plate point p (normal +z) reflects to the eye from the
 * point light: f(wo, wi) E, E = I cos / d^2 times glTF's window of range R;
 * metal: kd / pi + F D G2 / (4 cos_o cos_i), else albedo / pi. The light's
 * direction and distance from p raised by dz (the pipeline's shading point
 * lies about 1e-3 cell above the surface, where its shadow ray starts). */
static void expected(const vx_render_desc* b, const double p[3], double dz, double mt, double rough, double sp,
                     bool metal, double range, double out[3]) {
    double alb[3] = {(PLATE_RGBA & 255) / 255.0, ((PLATE_RGBA >> 8) & 255) / 255.0, ((PLATE_RGBA >> 16) & 255) / 255.0};
    double wi[3], wo[3], di = 0, dd = 0;
    for (int k = 0; k < 3; k++) wi[k] = LIGHT_POS[k] - p[k] - (k == 2 ? dz : 0), wo[k] = b->camera.eye[k] - p[k];
    for (int k = 0; k < 3; k++) di += wi[k] * wi[k], dd += wo[k] * wo[k];
    double dist = sqrt(di);
    for (int k = 0; k < 3; k++) wi[k] /= dist, wo[k] /= sqrt(dd);
    double q = (dist / range) * (dist / range), win = (1 - q * q) * (1 - q * q);
    double E = LIGHT_I * wi[2] / di * win;
    if (!metal) {
        for (int k = 0; k < 3; k++) out[k] = alb[k] / PI * E;
        return;
    }
    double alpha = fmax(rough * rough, 1e-3), a2 = alpha * alpha, f0d = 0.08 * sp;
    double h[3] = {wo[0] + wi[0], wo[1] + wi[1], wo[2] + wi[2]}, lh = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
    for (int k = 0; k < 3; k++) h[k] /= lh;
    double c = h[2] * h[2] * (a2 - 1) + 1, D = a2 / (PI * c * c);
    double G2 = 1 / (1 + lambda(a2, wo[2]) + lambda(a2, wi[2]));
    double s5 = pow(1 - fmax(0, wi[0] * h[0] + wi[1] * h[1] + wi[2] * h[2]), 5);
    for (int k = 0; k < 3; k++) {
        double kd = (1 - mt) * (1 - f0d) * alb[k], f0 = (1 - mt) * f0d + mt * alb[k];
        out[k] = (kd / PI + (f0 + (1 - f0) * s5) * D * G2 / (4 * wo[2] * wi[2])) * E;
    }
}

static vx_light point_light(void) {
    vx_light L = {.type = VX_LIGHT_POINT, .color = {1, 1, 1}, .intensity = LIGHT_I, .range = 1000};
    memcpy(L.position, LIGHT_POS, sizeof L.position);
    return L;
}

/* The pass pipeline's frame of s with list `passes`, the point light, a sky of radiance sky. */
static bool frame(const vx_svo_scene* s, const char* passes, bool separate, double sky, vx_render_image* out) {
    vx_error err = {0};
    vx_render_scene* rs = NULL;
    vx_frame_renderer* fr = NULL;
    vx_pass_list list;
    vx_light L = point_light();
    vx_result r = vx_pass_list_parse(passes, &list, &err);
    if (!r) r = vx_render_scene_create(gpu, s, &rs, &err);
    if (!r) r = vx_frame_renderer_create(rs, s, &fr, &err);
    vx_frame_result res = {0};
    if (!r) {
        vx_frame_desc fd = vx_frame_desc_defaults();
        fd.base = camera();
        fd.passes = &list;
        fd.lights = &L, fd.light_count = 1;
        fd.sky[0] = fd.sky[1] = fd.sky[2] = sky;
        fd.separate_passes = separate;
        r = vx_frame_render(fr, &fd, &res, &err);
    }
    if (r) fprintf(stderr, "  frame: %s\n", err.msg);
    vx_frame_renderer_destroy(fr);
    vx_render_scene_destroy(rs);
    *out = res.image;
    return r == VX_OK;
}

/* The worst relative error of the frame's plate pixels (x < xmax) against
 * expected(): the distance from the values for a shading point on the
 * surface and 2e-3 above it, over the expected value. */
static double worst_error(const vx_render_image* im, double mt, double rough, double sp, bool metal, double xmax,
                          size_t* count, double* peak) {
    vx_render_desc b = camera();
    double worst = 0;
    *count = 0, *peak = 0;
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            double p[3], e[3], e1[3];
            if (!pixel_point(&b, x, y, p) || p[0] > xmax) continue;
            expected(&b, p, 0, mt, rough, sp, metal, 1000, e);
            expected(&b, p, 2e-3, mt, rough, sp, metal, 1000, e1);
            const float* g = im->pixels + 4 * ((size_t)y * W + x);
            for (int k = 0; k < 3; k++) {
                double lo = fmin(e[k], e1[k]), hi = fmax(e[k], e1[k]);
                double err = (g[k] < lo ? lo - g[k] : g[k] > hi ? g[k] - hi : 0) / (fabs(e[k]) + 1e-4);
                if (err > worst) worst = err;
                if (e[k] > *peak) *peak = e[k];
            }
            (*count)++;
        }
    return worst;
}

/* Metalness 1 and 0.5 (and a sharper lobe), roughness 0.4: every plate pixel
 * against the BRDF in double, merged and separate passes. */
static void test_metal_plate_analytic(void) {
    if (!gpu) SKIP("no Vulkan device");
    static const struct {
        const char *mt, *rough, *sp;
    } cases[] = {{"1", "0.4", "0.5"}, {"0.5", "0.4", "0.7"}, {"1", "0.15", "0.5"}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        vx_svo_scene s;
        plate_scene(&s, cases[c].mt, cases[c].rough, cases[c].sp, true);
        for (int sep = 0; sep < 2; sep++) {
            vx_render_image im = {0};
            REQUIRE(frame(&s, "gbuffer,direct", sep, 0, &im));
            size_t n;
            double peak;
            double e = worst_error(&im, atof(cases[c].mt), atof(cases[c].rough), atof(cases[c].sp), true, N, &n, &peak);
            fprintf(stderr, "  metal %s rough %s sp %s (%s): %zu pixels, peak %.4f, worst relative error %.2e\n",
                    cases[c].mt, cases[c].rough, cases[c].sp, sep ? "separate" : "merged", n, peak, e);
            CHECK(n > 400);
            CHECKF(e < 1e-3, "worst relative error %.2e", e);
            vx_render_image_free(&im);
        }
        vx_svo_scene_free(&s);
    }
}

/* The same plate against the CPU path tracer (pixel centres; the point
 * light by next-event estimation, nothing to bounce from: its estimate is
 * f E at every sample), and the direct image's documented content. */
static void test_metal_plate_vs_pathtracer(void) {
    if (!gpu) SKIP("no Vulkan device");
    vx_svo_scene s;
    plate_scene(&s, "0.5", "0.4", "0.5", true);
    vx_render_image im = {0};
    REQUIRE(frame(&s, "gbuffer,direct", false, 0, &im));
    double sky[3] = {0, 0, 0};
    vx_probe_set ps = light_only(0, sky, 2);
    vx_light L = point_light();
    vx_render_desc base = camera();
    vx_probe_render_desc rd = {.base = &base, .mode = VX_PROBE_RENDER_PATHTRACE, .spp = 4, .bounces = 2, .seed = 5,
                               .lights = &L, .light_count = 1, .pixel_centre = true};
    vx_render_image ref = {0};
    vx_error err = {0};
    vx_result r = vx_probe_render(&s, &ps, &rd, &ref, &err);
    if (r) fprintf(stderr, "  path tracer: %s\n", err.msg);
    REQUIRE(r == VX_OK);
    double worst = 0, sum = 0, sum_ref = 0;
    size_t n = 0;
    for (size_t i = 0; i < (size_t)W * H; i++) {
        if (im.pixels[4 * i + 3] <= 0) continue; /* a miss */
        for (int k = 0; k < 3; k++) {
            double a = im.pixels[4 * i + k], b = ref.pixels[4 * i + k];
            sum += a, sum_ref += b;
            if (b > 1e-3) worst = fmax(worst, fabs(a - b) / b);
        }
        n++;
    }
    fprintf(stderr, "  against the CPU path tracer: %zu pixels, mean ratio %.5f, worst relative %.2e\n", n,
            sum / sum_ref, worst);
    CHECK(n > 600);
    CHECKF(fabs(sum / sum_ref - 1) < 2e-3, "mean ratio %.5f", sum / sum_ref);
    CHECKF(worst < 5e-3, "worst relative %.2e", worst);
    vx_render_image_free(&ref), vx_render_image_free(&im);
    vx_svo_scene_free(&s);
}

/* No metal: albedo / pi E (what the pipeline always gave); and a diffuse
 * half next to a metal half shows the same pixels as without the metal. */
static void test_diffuse_plate_unchanged(void) {
    if (!gpu) SKIP("no Vulkan device");
    vx_svo_scene s, m;
    plate_scene(&s, NULL, NULL, NULL, false);
    plate_scene(&m, "1", "0.4", "0.5", false); /* palette 1 (x < 8) metal, 2 diffuse */
    vx_render_image a = {0}, b = {0};
    REQUIRE(frame(&s, "gbuffer,direct", false, 0.3, &a));
    REQUIRE(frame(&m, "gbuffer,direct", false, 0.3, &b));
    size_t n, same = 0, right = 0, differ = 0;
    double peak, apart = 0; /* the diffuse half's largest relative difference */
    /* the sky term adds albedo * 0.3: subtract it for the closed form */
    vx_render_image c = {0};
    REQUIRE(frame(&s, "gbuffer,direct", false, 0, &c));
    double e = worst_error(&c, 0, 0, 0, false, N, &n, &peak);
    fprintf(stderr, "  diffuse plate: %zu pixels, worst relative error against albedo / pi E %.2e\n", n, e);
    CHECK(n > 400);
    CHECKF(e < 1e-3, "worst relative error %.2e", e);
    vx_render_desc cam = camera();
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            double p[3];
            if (!pixel_point(&cam, x, y, p)) continue;
            size_t i = 4 * ((size_t)y * W + x);
            bool eq = !memcmp(a.pixels + i, b.pixels + i, 4 * sizeof(float));
            if (p[0] > 8.25) { /* diffuse in both */
                same += eq, right++;
                for (int k = 0; k < 3; k++) {
                    double u = a.pixels[i + k], v = b.pixels[i + k];
                    if (u > 0) apart = fmax(apart, fabs(u - v) / u);
                }
            }
            else if (p[0] < 7.75) differ += !eq;   /* metal in m */
        }
    fprintf(stderr,
            "  diffuse half beside metal: %zu of %zu pixels equal bit for bit, at most %.2e apart; metal half: %zu "
            "differ\n",
            same, right, apart, differ);
    /* The scene with metal runs the kernels specialised with METAL: the same
     * expressions for a diffuse pixel, but a driver may schedule and contract
     * them differently (lavapipe gives the same bits; the H200 251 of 394
     * pixels, the rest a float rounding apart), so the check is the rounding */
    CHECK(right > 100);
    CHECKF(apart < 1e-5, "the diffuse half %.2e apart", apart);
    CHECK(differ > 100);
    vx_render_image_free(&a), vx_render_image_free(&b), vx_render_image_free(&c);
    vx_svo_scene_free(&s), vx_svo_scene_free(&m);
}

/* Directional albedo (A, B) of the GGX lobe for a view at cos mu, F = f0 A + B
 * (Schlick), by a midpoint quadrature over the normals in the variables that
 * make D cos uniform (tan^2 = a^2 x / (1 - x)); test_pathtrace.c's furnace
 * integrand with the Fresnel split. */
static void lobe_albedo(double alpha, double mu, double* A, double* B) {
    double a2 = alpha * alpha, wo[3] = {sqrt(1 - mu * mu), 0, mu};
    enum { NX = 400, NP = 120 };
    double sa = 0, sb = 0;
    for (int i = 0; i < NX; i++) {
        double x = (i + 0.5) / NX, t2 = a2 * x / (1 - x), ct = 1 / sqrt(1 + t2), st = sqrt(1 - ct * ct);
        for (int j = 0; j < NP; j++) {
            double ph = 2 * PI * (j + 0.5) / NP, m[3] = {st * cos(ph), st * sin(ph), ct};
            double om = wo[0] * m[0] + wo[1] * m[1] + wo[2] * m[2];
            if (om <= 0) continue;
            double wiz = 2 * om * m[2] - wo[2];
            if (wiz <= 0) continue;
            double w = 1 / (1 + lambda(a2, mu) + lambda(a2, wiz)) * om / (mu * ct), s5 = pow(1 - om, 5);
            sa += (1 - s5) * w, sb += s5 * w;
        }
    }
    *A = sa / (NX * NP), *B = sb / (NX * NP);
}

/* A metal under a uniform sky of radiance Ls (no occluder, no ao pass): the
 * sky term kd Ls + Ls (f0 A + B) (the Lambert lobe's, and the specular lobe's
 * directional albedo: exact for a uniform sky), as the difference of frames
 * with and without the sky. On main the term was albedo Ls. */
static void test_metal_sky_term(void) {
    if (!gpu) SKIP("no Vulkan device");
    vx_svo_scene s;
    plate_scene(&s, "0.5", "0.4", "0.5", true);
    const double Ls = 0.3, mt = 0.5, rough = 0.4, sp = 0.5;
    vx_render_image a = {0}, b = {0};
    REQUIRE(frame(&s, "gbuffer,direct", false, Ls, &a));
    REQUIRE(frame(&s, "gbuffer,direct", false, 0, &b));
    vx_render_desc cam = camera();
    double alb[3] = {(PLATE_RGBA & 255) / 255.0, ((PLATE_RGBA >> 8) & 255) / 255.0, ((PLATE_RGBA >> 16) & 255) / 255.0};
    double worst = 0, alpha = fmax(rough * rough, 1e-3);
    size_t n = 0;
    for (uint32_t y = 0; y < H; y += 3)
        for (uint32_t x = 0; x < W; x += 3) {
            double p[3], wo[3], l = 0, A, B;
            if (!pixel_point(&cam, x, y, p)) continue;
            for (int k = 0; k < 3; k++) wo[k] = cam.camera.eye[k] - p[k], l += wo[k] * wo[k];
            lobe_albedo(alpha, wo[2] / sqrt(l), &A, &B);
            size_t i = 4 * ((size_t)y * W + x);
            for (int k = 0; k < 3; k++) {
                double kd = (1 - mt) * (1 - 0.08 * sp) * alb[k], f0 = (1 - mt) * 0.08 * sp + mt * alb[k];
                double want = Ls * (kd + f0 * A + B), got = (double)a.pixels[i + k] - b.pixels[i + k];
                worst = fmax(worst, fabs(got - want) / want);
            }
            n++;
        }
    fprintf(stderr, "  metal sky term: %zu pixels, worst relative error %.2e\n", n, worst);
    CHECK(n > 40);
    CHECKF(worst < 0.01, "worst relative error %.2e", worst);
    vx_render_image_free(&a), vx_render_image_free(&b);
    vx_svo_scene_free(&s);
}

int main(void) {
    (void)ts_random_model, (void)room_scene, (void)box_scene;
    dlopen("libvulkan_lvp.so", RTLD_NOW | RTLD_NODELETE); /* see test_probes_gpu.c */
    vx_error err = {0};
    if (vx_gpu_create(&(vx_gpu_desc){0}, &gpu, &err)) {
        fprintf(stderr, "no Vulkan device (%s): GPU comparisons skipped\n", err.msg);
        gpu = NULL;
    }
    RUN(test_metal_plate_analytic);
    RUN(test_metal_plate_vs_pathtracer);
    RUN(test_diffuse_plate_unchanged);
    RUN(test_metal_sky_term);
    if (gpu) vx_gpu_destroy(gpu);
    return vx_test_finish();
}
