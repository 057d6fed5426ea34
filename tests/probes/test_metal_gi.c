/* tests/probes/test_metal_gi.c - metal's specular lobe in the probe modes
 * (probes/render_gi.c render_pixel, probes/shaders/probe.comp render()). An
 * open room: a floor, a red wall lit by the sun (no sky) and, facing it, a
 * metal mirror in the shade (the sun is behind it). The camera looks at the
 * mirror, whose centre reflects the red wall. Before, the probe modes shaded
 * metal's indirect light as diffuse (albedo / pi times the probes'
 * irradiance): the mirror showed a dull average of the room, not the wall.
 * Now the specular lobe casts a ray and shades the surface it meets, so the
 * mirror's pixels must give the path tracer's mean (the ground truth) within
 * the probes' error, in gi and lightfield on the CPU and the GPU and in the
 * pass pipeline's gi=probes frame, and differ from the diffuse shading of the
 * same surface (the old value: the scene with the mirror's record diffuse,
 * the same probes). A rough metal (roughness 0.6) blurs the wall with the
 * floor: the same checks with a wider tolerance. */
#include <dlfcn.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tests/probes/probe_scenes.h"
#include "tests/test.h"

static vx_gpu* gpu;

enum { N = 16, W = 40, H = 30 };
/* the floor z = 0 (3), the wall x = 0 (4), the mirror x = 15, y 2..13, z 1..12 (6) */
static uint8_t mirror_cell(uint32_t x, uint32_t y, uint32_t z, uint32_t n) {
    (void)n;
    if (x == N - 1 && y >= 2 && y <= 13 && z >= 1 && z <= 12) return 6;
    if (z == 0) return 3;
    if (x == 0) return 4;
    return 0;
}

/* The red wall metal too (test_lobe_meets_metal). */
static bool wall_metal;

/* The room with the mirror's record: metal of roughness `rough`, or (rough NULL) diffuse. */
static void mirror_scene(vx_svo_scene* s, const char* rough) {
    cells_scene(s, N, mirror_cell);
    s->palette[3] = 0xFF909090u, s->palette[4] = 0xFF2020D0u, s->palette[6] = 0xFFE0E0E0u;
    const char* const metal[] = {"_type", "_metal", "_metal", "1", "_rough", rough ? rough : "0"};
    const char* const diffuse[] = {"_type", "_diffuse"};
    if (rough) add_material(s, 6, metal, 3);
    else add_material(s, 6, diffuse, 1);
    const char* const wall[] = {"_type", "_metal", "_metal", "1", "_rough", "0.3"};
    if (wall_metal) add_material(s, 4, wall, 3);
}

static vx_render_desc view(void) {
    static const double eye[3] = {5, 8, 8}, at[3] = {15, 8, 7};
    return ps_view(W, H, eye, at);
}

/* The mean of the central 12 x 10 pixels (all on the mirror, seeing the wall's reflection). */
static void centre_mean(const vx_render_image* im, double m[3]) { ps_centre_mean(im, m); }

/* The bake's light: the sun from +x and above (it lights the wall's face and the floor, not the mirror's),
 * no sky; one bounce. */
static vx_probe_bake_desc bake_desc(void) {
    vx_probe_bake_desc bd = {.grid = {4, 4, 4}, .res = 32, .spp = 64, .bounces = 1, .seed = 5, .black_sky = true};
    double l[3] = {1, 0.3, 2}, len = sqrt(1 + 0.09 + 4);
    for (int k = 0; k < 3; k++) bd.light_dir[k] = l[k] / len, bd.sun[k] = 3;
    return bd;
}

typedef struct ctx {
    vx_svo_scene s, diffuse;
    vx_render_scene *rs, *rs_diffuse;
    vx_probe_set ps;
    double pt[3]; /* the path tracer's mean */
} ctx;

/* bounces: the path tracer's (0: the set's + 1, as the probe modes' light) */
static bool ctx_make(ctx* c, const char* rough, uint32_t bounces) {
    memset(c, 0, sizeof *c);
    mirror_scene(&c->s, rough);
    mirror_scene(&c->diffuse, NULL);
    vx_error err = {0};
    vx_probe_bake_desc bd = bake_desc();
    if (vx_render_scene_create(gpu, &c->s, &c->rs, &err) || vx_render_scene_create(gpu, &c->diffuse, &c->rs_diffuse, &err) ||
        vx_probe_bake_gpu(c->rs, &c->s, &bd, &c->ps, &err)) {
        fprintf(stderr, "  set-up: %s\n", err.msg);
        return false;
    }
    /* the reference: the path tracer with the probes' light (the set's sun, no sky) and bounces */
    vx_render_desc base = view();
    vx_probe_render_desc rd = {.base = &base, .mode = VX_PROBE_RENDER_PATHTRACE, .spp = 256, .seed = 11,
                               .pixel_centre = true, .bounces = bounces};
    vx_render_image im = {0};
    if (vx_probe_render_gpu(c->rs, &c->s, &c->ps, &rd, &im, &err)) {
        fprintf(stderr, "  path tracer: %s\n", err.msg);
        return false;
    }
    centre_mean(&im, c->pt);
    vx_render_image_free(&im);
    return true;
}

static void ctx_free(ctx* c) {
    vx_probe_set_free(&c->ps);
    vx_render_scene_destroy(c->rs);
    vx_render_scene_destroy(c->rs_diffuse);
    vx_svo_scene_free(&c->s);
    vx_svo_scene_free(&c->diffuse);
}

/* A probe mode's centre mean of scene s (CPU, or GPU with rs), the set's probes. */
static bool mode_mean_spp(const ctx* c, const vx_svo_scene* s, vx_render_scene* rs, vx_probe_render_mode mode,
                          uint32_t spp, double m[3]) {
    vx_render_desc base = view();
    vx_probe_render_desc rd = {.base = &base, .mode = mode, .spp = spp, .seed = 7, .threads = 2,
                               .pixel_centre = true};
    vx_render_image im = {0};
    vx_error err = {0};
    vx_result r = rs ? vx_probe_render_gpu(rs, s, &c->ps, &rd, &im, &err) : vx_probe_render(s, &c->ps, &rd, &im, &err);
    if (r) {
        fprintf(stderr, "  %s: %s\n", vx_probe_render_mode_name(mode), err.msg);
        return false;
    }
    centre_mean(&im, m);
    vx_render_image_free(&im);
    return true;
}

/* The same at 64 samples. */
static bool mode_mean(const ctx* c, const vx_svo_scene* s, vx_render_scene* rs, vx_probe_render_mode mode, double m[3]) {
    return mode_mean_spp(c, s, rs, mode, 64, m);
}

/* The pass pipeline's "gbuffer,direct,gi=METHOD" frame's centre mean (the set's light). */
static bool pass_mean(const ctx* c, const char* method, double m[3]) {
    vx_error err = {0};
    vx_frame_renderer* fr = NULL;
    vx_probe_gi* pg = NULL;
    vx_gi_method gm;
    vx_pass_list L;
    char list[64];
    snprintf(list, sizeof list, "gbuffer,direct,gi=%s", method);
    vx_probe_render_desc prd = {.spp = 1, .seed = 3};
    bool ok = false;
    if (vx_frame_renderer_create(c->rs, &c->s, &fr, &err) ||
        vx_probe_gi_create(c->rs, &c->s, &c->ps, method, &prd, &gm, &pg, &err) || vx_pass_list_parse(list, &L, &err))
        goto done;
    vx_frame_desc d = vx_frame_desc_defaults();
    d.base = view();
    d.base.spp = 32;
    d.passes = &L;
    d.gi = &gm;
    vx_frame_result res;
    if (vx_frame_render(fr, &d, &res, &err)) goto done;
    centre_mean(&res.image, m);
    vx_render_image_free(&res.image);
    ok = true;
done:
    if (!ok) fprintf(stderr, "  gi=%s: %s\n", method, err.msg);
    vx_probe_gi_destroy(pg);
    vx_frame_renderer_destroy(fr);
    return ok;
}

static double rel(const double a[3], const double b[3], int k) { return fabs(a[k] / b[k] - 1); }

/* Every probe mode's mirror (CPU, GPU, the pass pipeline) against the path tracer within tol (per channel,
 * relative), the diffuse shading of the same pixels off it by more than far[mode] in some channel (0: not
 * checked); and the CPU and the GPU within cg of each other (different random numbers: their noise). */
static void check_metal(const char* rough, double tol, const double far[2], double cg) {
    if (!gpu) SKIP("no Vulkan device");
    ctx c;
    REQUIRE(ctx_make(&c, rough, 0));
    fprintf(stderr, "  roughness %s: path tracer %.4f %.4f %.4f\n", rough, c.pt[0], c.pt[1], c.pt[2]);
    for (int k = 0; k < 3; k++) CHECKF(c.pt[k] > 0.005, "the mirror shows light (channel %d: %g)", k, c.pt[k]);
    CHECKF(c.pt[0] > 2 * c.pt[1], "the mirror shows the red wall (%g against %g)", c.pt[0], c.pt[1]);
    static const vx_probe_render_mode modes[] = {VX_PROBE_RENDER_GI, VX_PROBE_RENDER_LIGHTFIELD};
    for (size_t i = 0; i < sizeof modes / sizeof modes[0]; i++) {
        const char* name = vx_probe_render_mode_name(modes[i]);
        double cpu[3], gp[3], old[3];
        REQUIRE(mode_mean(&c, &c.s, NULL, modes[i], cpu));
        REQUIRE(mode_mean(&c, &c.s, c.rs, modes[i], gp));
        REQUIRE(mode_mean(&c, &c.diffuse, c.rs_diffuse, modes[i], old));
        fprintf(stderr, "  %-10s CPU %.4f %.4f %.4f, GPU %.4f %.4f %.4f, shaded diffuse %.4f %.4f %.4f\n", name, cpu[0],
                cpu[1], cpu[2], gp[0], gp[1], gp[2], old[0], old[1], old[2]);
        for (int k = 0; k < 3; k++) {
            CHECKF(rel(cpu, c.pt, k) < tol, "%s CPU channel %d: %.4f against the path tracer's %.4f", name, k, cpu[k],
                   c.pt[k]);
            CHECKF(rel(gp, c.pt, k) < tol, "%s GPU channel %d: %.4f against the path tracer's %.4f", name, k, gp[k],
                   c.pt[k]);
            CHECKF(rel(gp, cpu, k) < cg, "%s channel %d: GPU %.4f against CPU %.4f", name, k, gp[k], cpu[k]);
        }
        /* the old shading is off in the red channel (the wall) or in the others (the room's average) */
        double off = 0;
        for (int k = 0; k < 3; k++) off = fmax(off, rel(old, c.pt, k));
        if (far[i] > 0)
            CHECKF(off > far[i], "%s: the diffuse shading is within %.3f of the path tracer (%.3f)", name, far[i], off);
    }
    /* the indirect modes, CPU against GPU (the pass pipeline's gi=probes and gi=lightfield kernels) */
    static const vx_probe_render_mode ind[] = {VX_PROBE_RENDER_INDIRECT, VX_PROBE_RENDER_LF_INDIRECT};
    for (size_t i = 0; i < sizeof ind / sizeof ind[0]; i++) {
        double cpu[3], gp[3];
        REQUIRE(mode_mean(&c, &c.s, NULL, ind[i], cpu));
        REQUIRE(mode_mean(&c, &c.s, c.rs, ind[i], gp));
        fprintf(stderr, "  %-19s CPU %.4f %.4f %.4f, GPU %.4f %.4f %.4f\n", vx_probe_render_mode_name(ind[i]), cpu[0],
                cpu[1], cpu[2], gp[0], gp[1], gp[2]);
        for (int k = 0; k < 3; k++)
            CHECKF(rel(gp, cpu, k) < cg, "%s channel %d: GPU %.4f against CPU %.4f", vx_probe_render_mode_name(ind[i]), k,
                   gp[k], cpu[k]);
    }
    /* the pass pipeline: its direct pass (the metal's own lights: the sun does not reach its face) and the
     * gi pass (the lobes' light), nothing counted twice */
    static const char* const methods[] = {"probes", "lightfield"};
    for (size_t i = 0; i < sizeof methods / sizeof methods[0]; i++) {
        double p[3];
        REQUIRE(pass_mean(&c, methods[i], p));
        fprintf(stderr, "  passes gi=%-10s %.4f %.4f %.4f\n", methods[i], p[0], p[1], p[2]);
        for (int k = 0; k < 3; k++)
            CHECKF(rel(p, c.pt, k) < tol, "passes gi=%s channel %d: %.4f against the path tracer's %.4f", methods[i], k,
                   p[k], c.pt[k]);
    }
    ctx_free(&c);
}

/* The tolerances: the wall's own indirect light through the probes (gi: its green and blue, which are
 * mostly indirect, 7% under the path tracer's; lightfield: its one-bounce estimate 7% over in red) and the
 * modes' noise at their sample counts. The diffuse shading was 43% under in red and 63% over in green and
 * blue (gi; lightfield: 61% under in red). The rough lobe's mean lies nearer the room's average, and the
 * light field's diffuse estimate of it is within 17% of the path tracer: only gi's (40% over) is checked. */
static void test_polished_mirror(void) { check_metal("0.05", 0.10, (const double[2]){0.35, 0.35}, 0.04); }
static void test_rough_metal(void) { check_metal("0.6", 0.13, (const double[2]){0.25, 0}, 0.08); }

/* The mirror's lobe meets a metal: the red wall made a rough metal (0.3) too, lit by the sun. The two face each
 * other: a hall of mirrors, where the light goes on for many bounces between them, so the reference is the path
 * tracer at 10 bounces (converged: 6 gave 0.1623 in red, 10 0.1643; at its default 2, the set's + 1, 0.0585, when
 * each metal event spent a bounce; now that the path tracer's first VX__METAL_CHAIN metal events spend none, the
 * default gives 0.98x of 10: test_reference_follows_metal).
 * The probe modes follow the chain of metal events (each metal's own lobe) up to VX__METAL_CHAIN (4), then
 * shade the surface reached whole; they come out darker than the converged paths (the light past the chain is
 * dropped): gi 0.131, lightfield 0.117 (0.80x, 0.71x; 256 samples, CPU and GPU alike). History: with one metal
 * event (stop 73: the met metal shaded by its own BRDF and kd, no second lobe) 0.013 (0.08x) in gi and
 * lightfield; before that (the met metal shaded as a diffuse surface, its whole colour lit by the sun) gi 0.381,
 * lightfield 0.448, and the demo island's statue, whose lobe mostly meets the statue, 5-10x (docs/TESTING.md,
 * stops 73 and 74). Checked: every probe mode's every channel between 0.6 and 1.15 of the path tracer's (the
 * one-event code fails it), CPU and GPU within 8% (256 samples: at 64 the light field's noise alone reached 10%
 * between them). */
static void test_lobe_meets_metal(void) {
    if (!gpu) SKIP("no Vulkan device");
    wall_metal = true;
    ctx c;
    bool made = ctx_make(&c, "0.05", 10);
    wall_metal = false;
    REQUIRE(made);
    fprintf(stderr, "  a metal wall in the mirror: path tracer (10 bounces) %.4f %.4f %.4f\n", c.pt[0], c.pt[1], c.pt[2]);
    CHECKF(c.pt[0] > 0.005, "the mirror shows light (%g)", c.pt[0]);
    static const vx_probe_render_mode modes[] = {VX_PROBE_RENDER_GI, VX_PROBE_RENDER_LIGHTFIELD};
    for (size_t i = 0; i < sizeof modes / sizeof modes[0]; i++) {
        const char* name = vx_probe_render_mode_name(modes[i]);
        double cpu[3], gp[3];
        REQUIRE(mode_mean_spp(&c, &c.s, NULL, modes[i], 256, cpu));
        REQUIRE(mode_mean_spp(&c, &c.s, c.rs, modes[i], 256, gp));
        fprintf(stderr, "  %-10s CPU %.4f %.4f %.4f, GPU %.4f %.4f %.4f\n", name, cpu[0], cpu[1], cpu[2], gp[0], gp[1],
                gp[2]);
        for (int k = 0; k < 3; k++) {
            CHECKF(cpu[k] > 0.6 * c.pt[k] && cpu[k] < 1.15 * c.pt[k],
                   "%s CPU channel %d %.4f against the path tracer's %.4f", name, k, cpu[k], c.pt[k]);
            CHECKF(gp[k] > 0.6 * c.pt[k] && gp[k] < 1.15 * c.pt[k],
                   "%s GPU channel %d %.4f against the path tracer's %.4f", name, k, gp[k], c.pt[k]);
            CHECKF(rel(gp, cpu, k) < 0.08, "%s channel %d: GPU %.4f against CPU %.4f", name, k, gp[k], cpu[k]);
        }
    }
    /* the indirect modes (the pass pipeline's gi=probes and gi=lightfield kernels), CPU against GPU */
    static const vx_probe_render_mode ind[] = {VX_PROBE_RENDER_INDIRECT, VX_PROBE_RENDER_LF_INDIRECT};
    for (size_t i = 0; i < sizeof ind / sizeof ind[0]; i++) {
        double cpu[3], gp[3];
        REQUIRE(mode_mean_spp(&c, &c.s, NULL, ind[i], 256, cpu));
        REQUIRE(mode_mean_spp(&c, &c.s, c.rs, ind[i], 256, gp));
        fprintf(stderr, "  %-19s CPU %.4f %.4f %.4f, GPU %.4f %.4f %.4f\n", vx_probe_render_mode_name(ind[i]), cpu[0],
                cpu[1], cpu[2], gp[0], gp[1], gp[2]);
        for (int k = 0; k < 3; k++)
            CHECKF(rel(gp, cpu, k) < 0.08, "%s channel %d: GPU %.4f against CPU %.4f", vx_probe_render_mode_name(ind[i]), k,
                   gp[k], cpu[k]);
    }
    ctx_free(&c);
}

/* The path tracer's own mean of the mirror's centre (GPU, or the CPU reference with cpu), bounces as ctx_make. */
static bool pt_mean(const ctx* c, uint32_t bounces, bool cpu, uint32_t spp, uint64_t seed, double m[3]) {
    vx_render_desc base = view();
    vx_probe_render_desc rd = {.base = &base, .mode = VX_PROBE_RENDER_PATHTRACE, .spp = spp, .seed = seed,
                               .threads = 2, .pixel_centre = true, .bounces = bounces};
    vx_render_image im = {0};
    vx_error err = {0};
    vx_result r = cpu ? vx_probe_render(&c->s, &c->ps, &rd, &im, &err) : vx_probe_render_gpu(c->rs, &c->s, &c->ps, &rd, &im, &err);
    if (r) {
        fprintf(stderr, "  path tracer (%s): %s\n", cpu ? "CPU" : "GPU", err.msg);
        return false;
    }
    centre_mean(&im, m);
    vx_render_image_free(&im);
    return true;
}

/* The GI table's reference (bench/gi_bench.c: the path tracer at its default bounces, the set's + 1, 2 here) on
 * the mirror facing a metal wall. A metal event (the specular lobe of a metal record, whatever its roughness)
 * spends no bounce, up to VX__METAL_CHAIN of them a path, as the probe modes' chain of metal events does not
 * (probes/pathtrace.c vx__path, probe.comp path()), so the default reference follows the hall of mirrors as far as
 * the methods it judges and comes within a few percent of the converged transport (10 bounces). Before, each
 * metal event spent a bounce and the default reference gave 0.0585 in red against 0.1643 (0.36x): the table's
 * reference was silently low on such scenes. Each device against itself at 10 bounces with the same seed (the
 * same paths up to where the shorter stops: what differs is the light past the cut, not the noise, which between
 * seeds reaches 4% here at 256 samples: the near-mirror's sun highlights): every channel within 3% (the old rule
 * fails it by 64%); and the two devices at the default bounces within 5% (1024 samples each). */
static void test_reference_follows_metal(void) {
    if (!gpu) SKIP("no Vulkan device");
    wall_metal = true;
    ctx c;
    bool made = ctx_make(&c, "0.05", 2);
    wall_metal = false;
    REQUIRE(made);
    double g2[3], g10[3], c2[3], c10[3], g[3], cp[3];
    REQUIRE(pt_mean(&c, 0, false, 256, 11, g2) && pt_mean(&c, 10, false, 256, 11, g10));
    REQUIRE(pt_mean(&c, 0, true, 256, 11, c2) && pt_mean(&c, 10, true, 256, 11, c10));
    REQUIRE(pt_mean(&c, 0, false, 1024, 17, g) && pt_mean(&c, 0, true, 1024, 17, cp));
    fprintf(stderr, "  path tracer, default (2) and 10 bounces: GPU %.4f %.4f %.4f and %.4f %.4f %.4f, CPU %.4f %.4f "
            "%.4f and %.4f %.4f %.4f\n", g2[0], g2[1], g2[2], g10[0], g10[1], g10[2], c2[0], c2[1], c2[2], c10[0],
            c10[1], c10[2]);
    fprintf(stderr, "  default bounces, 1024 samples: GPU %.4f %.4f %.4f, CPU %.4f %.4f %.4f\n", g[0], g[1], g[2], cp[0],
            cp[1], cp[2]);
    for (int k = 0; k < 3; k++) {
        CHECKF(rel(g2, g10, k) < 0.03, "GPU channel %d: default bounces %.4f against 10 bounces %.4f", k, g2[k], g10[k]);
        CHECKF(rel(c2, c10, k) < 0.03, "CPU channel %d: default bounces %.4f against 10 bounces %.4f", k, c2[k], c10[k]);
        CHECKF(rel(g, cp, k) < 0.05, "channel %d: GPU %.4f against CPU %.4f", k, g[k], cp[k]);
    }
    ctx_free(&c);
}

int main(void) {
    (void)ts_random_model, (void)room_scene, (void)box_scene, (void)glass_room_cell;
    dlopen("libvulkan_lvp.so", RTLD_NOW | RTLD_NODELETE); /* see test_probes_gpu.c */
    vx_error err = {0};
    if (vx_gpu_create(&(vx_gpu_desc){0}, &gpu, &err)) {
        fprintf(stderr, "no Vulkan device (%s): GPU comparisons skipped\n", err.msg);
        gpu = NULL;
    }
    RUN(test_polished_mirror);
    RUN(test_rough_metal);
    RUN(test_lobe_meets_metal);
    RUN(test_reference_follows_metal);
    if (gpu) vx_gpu_destroy(gpu);
    return vx_test_finish();
}
