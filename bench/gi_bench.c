/* bench/gi_bench.c - every GI method on one scene and camera against a
 * path-traced reference: relative MSE of the full image (direct + indirect)
 * and of the indirect light alone, render time (GPU timestamps, median of
 * --runs renders) and build time (a probe bake) where the method has one.
 * Needs only libvulkan and libc, so it runs on a GPU machine with a bare
 * loader. bench/gi_table runs it on every scene and draws the plot.
 *
 *   gi_bench [options] SCENE.{svo,vox} WxH [spacing:res:spp ...]
 *
 * The reference is the mean of two path-traced images of REF_SPP samples
 * with different seeds (999 and 1000), for the full image and for the
 * indirect light; the row "reference" gives the relMSE between the two (its
 * own noise: the mean's expected relMSE against the converged image is a
 * quarter of that). Errors are over the pixels whose reference hits the
 * scene (the sky is exact in every method). Each bake setting is baked once
 * (on the GPU, filtering on --threads CPU threads) and shared by every
 * method that reads probes.
 *
 * Method photons (photons/photons.h): spp counts progressive passes of
 * --photons N photons each (default 2^20), first radius --photon-radius R
 * (default: the scene diagonal / 100); its full image is the photon maps'
 * whole estimate (direct light too), its indirect image the gi pass's;
 * photons-fg the same with a final gather of 16 rays per pixel and pass.
 *
 * Options: --device N|NAME, --ref-spp N (1024), --runs N (5), --threads N (2),
 * --warm MS (0: off; a path-traced frame of about MS GPU ms before each timed
 * render, so that short frames are timed at a busy GPU's clocks),
 * --methods a,b,.. (all), --max-spp METHOD=N (the method's default),
 * --camera EX,EY,EZ,TX,TY,TZ [--up X,Y,Z] [--fov DEG], --light X,Y,Z
 * (towards the sun), --bounds X0,Y0,Z0,X1,Y1,Z1 (the probe grid's box),
 * --name NAME (the scene column; default: the file name), --csv FILE
 * (appends one line per row, with a header when the file is new). A row
 * whose images hold non-finite pixels says how many (its relMSE is then nan).
 * A method that fails (an error at some sample count) is reported in its
 * place in the text and on stderr, and the other methods go on.
 * Exit status: 0; 3 when some method failed (the others' rows are written);
 * 1 when the scene, the GPU or the reference failed; 2 a usage error.
 *
 * The reference's health: after its row, a line gives the share of the two
 * seeds' squared difference held by the worst pixel, and a warning when the
 * two seeds' relMSE is above REF_NOISE_WARN (the mean reference's own error,
 * a quarter of it, would then be above most methods' errors: the scene's
 * rows say nothing). On the converted DamagedHelmet that is the sun (a
 * delta light) reflected by its roughness-0 metal (GGX alpha 1e-3) at a
 * vertex after a diffuse bounce: a caustic only light sampling can find,
 * rare samples of 10^4 and more (docs/PERFORMANCE.md section 7).
 * --ref-sun-angle DEG (0: off) gives the reference and the pathtrace rows
 * the sun as a disc of that angular diameter (the real sun's is 0.53; a
 * directional vx_light of the same irradiance, which the path tracer samples
 * as a cone and weighs against BSDF sampling): no longer a delta, so a
 * near-mirror's reflection of it is found by BSDF rays too. The other
 * methods keep the delta sun; on the helmet the two suns' images differ by
 * less than the reference's noise (PERFORMANCE.md section 7).
 *
 * Adding a method: one entry in methods[]. Methods of the probe renderer
 * name their two modes; another module's method gives its own render()
 * (and a build kind if it needs a build step before rendering).
 *
 * Voxel cone tracing (cones/cones.h, issue 12): "cones" (the defaults),
 * "cones-iso" (isotropic), "cones-16" (16 cones), "cones-256" (res 256),
 * "cones-512" (res 512; only when --methods names it), "cones-half" and
 * "cones-iso-half" (diffuse cones at half resolution, depth- and
 * normal-aware upsampling), "cones-shadows" (cone soft shadows: the pass
 * list gbuffer,gi=cones, the gi image holds the direct light too, so its
 * indirect column is not the indirect light), "cones-half-4",
 * "cones-iso-half-4" (4 cones), "cones-half-step1" (steps of a whole diameter),
 * rendered through the pass pipeline (gbuffer,direct,gi=cones; the indirect
 * image is its gi image; the times are the frame's and the gi pass's GPU
 * time); a line before their rows gives the volume's build (voxelize,
 * inject, filter GPU ms) and the ratio of the mean indirect light to the
 * reference's (above 1: light leaked in). SCENE "thin-wall" is a scene made
 * here: a closed room of one-cell walls with a window towards the sun on a
 * lit ground (64 x 64 x 26 cells), where cones leak light through walls;
 * SCENE "metal-room" a rough metal floor (roughness 0.3) with two coloured
 * walls and a block, for the specular cones ("cones-nospec": the metal
 * shaded as diffuse). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench/bench_load.h"
#include "photons/photons.h"
#include "cones/cones.h"
#include "probes/probes.h"
#include "tools/common/tool.h" /* vx_tool_parse_vec */

/* What a method needs built before it renders, per setting. */
typedef enum build_kind {
    BUILD_NONE = 0, /* nothing: one row set, setting "-" */
    BUILD_PROBES    /* a probe bake per spacing:res:spp setting on the command line */
} build_kind;

/* What is built for one setting (shared by the methods of that build kind). */
typedef struct built {
    const char* setting;
    vx_probe_set ps;
    bool has_ps;
    vx_probe_gpu* pg; /* the probe renderer, with ps or without probes */
    double seconds;   /* build wall time (0: none) */
} built;

typedef struct gi_method gi_method;
struct gi_method {
    const char* name;
    build_kind build;
    unsigned max_spp; /* rows at 1, 4, 16, ... max_spp samples (or rays) per pixel */
    vx_probe_render_mode full, indirect;
    /* NULL: the probe renderer in mode full or indirect */
    vx_result (*render)(const gi_method* m, const built* b, bool indirect, unsigned spp, vx_render_image* out,
                        vx_error* err);
    bool on_request; /* only when --methods names it */
};

static vx_result photon_render(const gi_method* m, const built* b, bool indirect, unsigned spp, vx_render_image* out,
                               vx_error* err);
static vx_result cone_render(const gi_method* m, const built* b, bool indirect, unsigned spp, vx_render_image* out,
                             vx_error* err);

static const gi_method methods[] = {
    {"pathtrace", BUILD_NONE, 256, VX_PROBE_RENDER_PATHTRACE, VX_PROBE_RENDER_PT_INDIRECT, NULL, false},
    {"probes", BUILD_PROBES, 16, VX_PROBE_RENDER_GI, VX_PROBE_RENDER_INDIRECT, NULL, false},
    {"lightfield", BUILD_PROBES, 256, VX_PROBE_RENDER_LIGHTFIELD, VX_PROBE_RENDER_LF_INDIRECT, NULL, false},
    /* spp: progressive photon passes (--photons N each); full: every photon, direct light too */
    {"photons", BUILD_NONE, 16, 0, 0, photon_render, false},
    {"photons-fg", BUILD_NONE, 16, 0, 0, photon_render, false}, /* the same with a final gather of 16 rays */
    {"cones", BUILD_NONE, 1, 0, 0, cone_render, false},
    {"cones-iso", BUILD_NONE, 1, 0, 0, cone_render, false},
    {"cones-16", BUILD_NONE, 1, 0, 0, cone_render, false},
    {"cones-256", BUILD_NONE, 1, 0, 0, cone_render, false},
    {"cones-512", BUILD_NONE, 1, 0, 0, cone_render, true}, /* 13 GB of GPU memory */
    {"cones-half", BUILD_NONE, 1, 0, 0, cone_render, false},
    {"cones-iso-half", BUILD_NONE, 1, 0, 0, cone_render, false},
    {"cones-shadows", BUILD_NONE, 1, 0, 0, cone_render, false},
    {"cones-half-4", BUILD_NONE, 1, 0, 0, cone_render, false},
    {"cones-half-step1", BUILD_NONE, 1, 0, 0, cone_render, false},
    {"cones-iso-half-4", BUILD_NONE, 1, 0, 0, cone_render, false},
    {"cones-nospec", BUILD_NONE, 1, 0, 0, cone_render, false},
};
#define METHOD_COUNT (sizeof methods / sizeof methods[0])

static vx_render_desc base;      /* size, camera, sun direction */
static vx_light ref_sun;         /* --ref-sun-angle: the reference's sun as a disc */
static uint32_t ref_sun_count;   /* 1 with --ref-sun-angle, else 0 (the delta sun) */
static vx_gpu* gpu;
static vx_render_scene* rs;
static vx_svo_scene scene;
static unsigned runs = 5, threads = 2;
static double warm_ms;           /* --warm MS: a path-traced frame of about MS GPU ms before each timed render */
static double pt_ms_per_spp;     /* the indirect reference's GPU ms per sample, sizes that frame */
static built* warm_with;         /* the path tracer without probes */

static vx_photon_desc photon_desc; /* --photons N, --photon-radius R */
static vx_photon_gi* photon_gi[2]; /* photons, photons-fg */

static vx_result photon_render(const gi_method* m, const built* b, bool indirect, unsigned spp, vx_render_image* out,
                               vx_error* err) {
    (void)b;
    int k = strcmp(m->name, "photons") != 0;
    vx_result r = VX_OK;
    if (!photon_gi[k]) {
        vx_gi_method gm;
        vx_photon_desc d = photon_desc;
        d.final_gather = k ? 16 : 0;
        memcpy(d.light_dir, base.light_dir, sizeof d.light_dir); /* the path tracer's sun */
        if ((r = vx_photon_gi_create(rs, &scene, NULL, &d, &gm, &photon_gi[k], err))) return r;
    }
    return vx_photon_render(photon_gi[k], &base, spp, !indirect, out, err);
}

static vx_result probe_render(const gi_method* m, const built* b, bool indirect, unsigned spp, vx_render_image* out,
                              vx_error* err) {
    vx_probe_render_desc d = {.base = &base, .mode = indirect ? m->indirect : m->full, .spp = spp, .seed = 7};
    if (m->full == VX_PROBE_RENDER_PATHTRACE) d.lights = &ref_sun, d.light_count = ref_sun_count; /* as the reference */
    return vx_probe_gpu_render(b->pg, &d, out, err);
}

static int cmp_double(const void* a, const void* b) {
    double x = *(const double*)a, y = *(const double*)b;
    return (x > y) - (x < y);
}

/* A GPU left idle between short frames (each render reads its image back)
 * runs them at lower clocks: on an H100, 16- and 64-sample frames timed
 * 1.4 ms per sample where 1- and 256-sample frames took 0.44. With --warm,
 * a path-traced frame of about warm_ms GPU ms runs just before each timed
 * render, so short frames are timed at the clocks of a busy GPU. */
static vx_result warm_up(vx_error* err) {
    if (warm_ms <= 0 || pt_ms_per_spp <= 0) return VX_OK;
    double spp = ceil(warm_ms / pt_ms_per_spp);
    vx_probe_render_desc d = {.base = &base, .mode = VX_PROBE_RENDER_PT_INDIRECT, .seed = 5};
    d.spp = spp > 1e6 ? 1000000 : (uint32_t)spp;
    vx_render_image img = {0};
    vx_result r = vx_probe_gpu_render(warm_with->pg, &d, &img, err);
    vx_render_image_free(&img);
    return r;
}

/* ---- voxel cone tracing through the pass pipeline ---------------------------------- */

static vx_frame_renderer* cone_fr;
static vx_cone_gi* cone_gi;
static const gi_method* cone_for; /* the method cone_gi was built for */
static vx_gi_method cone_gm;

static vx_result cone_render(const gi_method* m, const built* b, bool indirect, unsigned spp, vx_render_image* out,
                             vx_error* err) {
    (void)b;
    vx_result r = VX_OK;
    if (!cone_fr && (r = vx_frame_renderer_create(rs, &scene, &cone_fr, err))) return r;
    if (cone_for != m) {
        vx_cone_gi_destroy(cone_gi);
        cone_gi = NULL, cone_for = NULL;
        vx_cone_desc d = {0};
        memcpy(d.light_dir, base.light_dir, sizeof d.light_dir);
        d.isotropic = !strncmp(m->name, "cones-iso", 9);
        d.half_res = strstr(m->name, "-half") != NULL;
        d.shadows = !strcmp(m->name, "cones-shadows");
        if (!strcmp(m->name, "cones-16")) d.cones = 16;
        if (strstr(m->name, "-half-4")) d.cones = 4;
        if (strstr(m->name, "-step1")) d.step = 1;
        d.no_specular = !strcmp(m->name, "cones-nospec");
        if (!strcmp(m->name, "cones-256")) d.res = 256;
        if (!strcmp(m->name, "cones-512")) d.res = 512;
        if ((r = vx_cone_gi_create(rs, &scene, &d, &cone_gm, &cone_gi, err))) return r;
        /* again, timed alone: the first build includes the pipelines' creation */
        if ((r = vx_cone_gi_voxelize(cone_gi, err))) return r;
        cone_for = m;
        vx_cone_info ci;
        vx_cone_gi_info(cone_gi, &ci);
        /* relighting (a light change: inject, then filter the occupied voxels): the median of 5 */
        double relight[5];
        for (int k = 0; k < 5; k++) {
            vx_cone_desc ld = {0};
            memcpy(ld.light_dir, base.light_dir, sizeof ld.light_dir);
            if ((r = vx_cone_gi_inject(cone_gi, &ld, &cone_gm, err))) return r;
            vx_cone_info li;
            vx_cone_gi_info(cone_gi, &li);
            relight[k] = li.inject_ms + li.filter_ms;
        }
        for (int a = 0; a < 5; a++)
            for (int b = a + 1; b < 5; b++)
                if (relight[b] < relight[a]) {
                    double t = relight[a];
                    relight[a] = relight[b], relight[b] = t;
                }
        vx_cone_gi_info(cone_gi, &ci);
        printf("%s: volume %ux%ux%u (%u levels, %u entries a voxel), %u voxels with geometry, %u occupied above, %.1f MB; "
               "GPU ms: voxelize %.3f, inject %.3f, filter %.3f; relight median of 5 %.3f%s\n", m->name, ci.dims[0][0],
               ci.dims[0][1], ci.dims[0][2], ci.levels, ci.entries, ci.surface_voxels, ci.occupied_voxels, ci.bytes / 1e6,
               ci.voxelize_ms, ci.inject_ms, ci.filter_ms, relight[2], ci.specular ? "; specular cones" : "");
    }
    vx_pass_list L;
    if ((r = vx_pass_list_parse(cone_gm.includes_direct ? "gbuffer,gi=cones" : "gbuffer,direct,gi=cones", &L, err))) return r;
    vx_frame_desc fd = vx_frame_desc_defaults();
    fd.base = base;
    fd.base.spp = spp;
    fd.passes = &L;
    fd.gi = &cone_gm;
    fd.show = indirect ? VX_SHOW_GI : VX_SHOW_FINAL;
    memcpy(fd.sky, cone_gm.sky, sizeof fd.sky);
    vx_frame_result res;
    if ((r = vx_frame_render(cone_fr, &fd, &res, err))) return r;
    double ms = res.frame_ms;
    for (uint32_t t = 0; indirect && t < res.timing_count; t++)
        if (!strcmp(res.timings[t].name, "gi")) ms = res.timings[t].ms;
    *out = res.image;
    out->gpu_seconds = ms * 1e-3;
    return VX_OK;
}

/* Mean over the reference's hit pixels of a's RGB over the reference's. */
static double mean_ratio(const vx_render_image* a, const vx_render_image* ref) {
    double sa = 0, sr = 0;
    for (size_t i = 0; i < (size_t)ref->width * ref->height; i++)
        if (ref->pixels[4 * i + 3] != 0)
            for (int c = 0; c < 3; c++) sa += a->pixels[4 * i + c], sr += ref->pixels[4 * i + c];
    return sr > 0 ? sa / sr : 0;
}

/* The generated scenes' common end: the cells (Morton keys, palette indices;
 * both freed here) as the scene's one model under one identity instance.
 * `ok` false (an allocation of the caller's failed) builds nothing. */
static int single_model_scene(vx_svo_scene* s, uint32_t sx, uint32_t sy, uint32_t sz, uint64_t* keys, uint8_t* pal,
                              size_t n, bool ok, vx_error* err) {
    s->models = calloc(1, sizeof *s->models);
    s->instances = calloc(1, sizeof *s->instances);
    vx_svo_voxels v = {.size = {sx, sy, sz}, .count = n, .keys = keys, .attrs = VX_ATTR_PALETTE, .palette = pal};
    vx_result r = ok && s->models && s->instances ? vx_svo_build_model(NULL, &v, s->models, NULL, err) : VX_ERR_NOMEM;
    free(keys);
    free(pal);
    if (r) return 1;
    s->model_count = 1, s->instance_count = 1;
    s->instances[0].layer = UINT32_MAX;
    for (int k = 0; k < 3; k++) s->instances[0].xform[4 * k + k] = 1;
    vx_svo_scene_update_bounds(s);
    return 0;
}

/* The thin-wall scene: a lit ground, a closed room of one-cell walls and
 * roof (x, y in [16, 48), z in [1, 25)) with a 8 x 8 window in its -y wall
 * (towards the default sun), world units = cells. */
static int thin_wall_scene(vx_svo_scene* s, vx_error* err) {
    size_t cap = 64 * 64 * 26, n = 0;
    uint64_t* keys = malloc(cap * sizeof *keys);
    uint8_t* pal = malloc(cap);
    if (!keys || !pal) return free(keys), free(pal), 1;
    for (uint32_t z = 0; z < 26; z++)
        for (uint32_t y = 0; y < 64; y++)
            for (uint32_t x = 0; x < 64; x++) {
                bool in = x >= 16 && x < 48 && y >= 16 && y < 48 && z >= 1 && z < 26;
                bool wall = in && (x == 16 || x == 47 || y == 16 || y == 47 || z == 25);
                bool window = y == 16 && x >= 28 && x < 36 && z >= 8 && z < 16;
                if (z == 0 || (wall && !window)) {
                    keys[n] = vx_svo_morton(x, y, z);
                    pal[n++] = z == 0 ? 1 : (x == 47 ? 3 : 2);
                }
            }
    vx_svo_scene_init(s, NULL);
    s->has_palette = true;
    s->palette[1] = 0xFF6080A0u, s->palette[2] = 0xFFD0D0D0u, s->palette[3] = 0xFF3040C0u;
    return single_model_scene(s, 64, 64, 26, keys, pal, n, true, err);
}

/* The metal-room scene: a rough metal floor (roughness 0.3, 64 x 64 cells),
 * a red and a blue wall, a white block in the middle; world units = cells. */
static int metal_room_scene(vx_svo_scene* s, vx_error* err) {
    size_t cap = 64 * 64 * 33, n = 0;
    uint64_t* keys = malloc(cap * sizeof *keys);
    uint8_t* pal = malloc(cap);
    if (!keys || !pal) return free(keys), free(pal), 1;
    for (uint32_t z = 0; z < 33; z++)
        for (uint32_t y = 0; y < 64; y++)
            for (uint32_t x = 0; x < 64; x++) {
                uint8_t c = z == 0 ? 1 : x == 0 ? 2 : y == 63 ? 3 : (x >= 28 && x < 36 && y >= 28 && y < 36 && z <= 8) ? 4 : 0;
                if (c) keys[n] = vx_svo_morton(x, y, z), pal[n++] = c;
            }
    vx_svo_scene_init(s, NULL);
    s->has_palette = true;
    s->palette[1] = 0xFFB0C0D0u, s->palette[2] = 0xFF3030D0u, s->palette[3] = 0xFFD06030u, s->palette[4] = 0xFFE0E0E0u;
    static const char dict[] = "_type\0_metal\0_rough\0" "0.3";
    s->materials = calloc(1, sizeof *s->materials);
    if (s->materials && (s->materials[0].dict = malloc(sizeof dict))) {
        memcpy(s->materials[0].dict, dict, sizeof dict);
        s->materials[0].id = 1, s->materials[0].dict_size = sizeof dict;
        s->material_count = 1;
    }
    return single_model_scene(s, 64, 64, 33, keys, pal, n, s->material_count == 1, err);
}

/* Renders `runs` times; *out is the first image with the median GPU time. */
static vx_result render_median(const gi_method* m, const built* b, bool indirect, unsigned spp, vx_render_image* out,
                               vx_error* err) {
    double t[64];
    unsigned n = runs < 64 ? runs : 64;
    for (unsigned i = 0; i < n; i++) {
        vx_render_image img = {0};
        vx_result r = warm_up(err);
        if (!r) r = (m->render ? m->render : probe_render)(m, b, indirect, spp, &img, err);
        if (r) {
            if (i) vx_render_image_free(out);
            return r;
        }
        t[i] = img.gpu_seconds;
        if (i) vx_render_image_free(&img);
        else *out = img;
    }
    qsort(t, n, sizeof t[0], cmp_double);
    out->gpu_seconds = n % 2 ? t[n / 2] : 0.5 * (t[n / 2 - 1] + t[n / 2]);
    return VX_OK;
}

/* Sum of squared errors over the reference's hit pixels (RGB) divided by
 * the sum of the squared reference values there. */
static double rel_mse(const vx_render_image* a, const vx_render_image* ref) {
    double se = 0, rs2 = 0;
    for (size_t i = 0; i < (size_t)ref->width * ref->height; i++) {
        if (ref->pixels[4 * i + 3] == 0) continue;
        for (int c = 0; c < 3; c++) {
            double d = (double)a->pixels[4 * i + c] - ref->pixels[4 * i + c];
            se += d * d, rs2 += (double)ref->pixels[4 * i + c] * ref->pixels[4 * i + c];
        }
    }
    return rs2 > 0 ? se / rs2 : 0;
}

/* The share of the squared difference between a and b (RGB, over b's hit
 * pixels) that its worst pixel holds: near 1, a firefly in one image. */
static double worst_pixel_share(const vx_render_image* a, const vx_render_image* b) {
    double se = 0, worst = 0;
    for (size_t i = 0; i < (size_t)b->width * b->height; i++) {
        if (b->pixels[4 * i + 3] == 0) continue;
        double e = 0;
        for (int c = 0; c < 3; c++) {
            double d = (double)a->pixels[4 * i + c] - b->pixels[4 * i + c];
            e += d * d;
        }
        se += e, worst = fmax(worst, e);
    }
    return se > 0 ? worst / se : 0;
}

/* Pixels with a non-finite channel (a method's failure: the row says so). */
static size_t nonfinite(const vx_render_image* a) {
    size_t n = 0;
    for (size_t i = 0; i < (size_t)a->width * a->height; i++)
        n += !isfinite(a->pixels[4 * i]) || !isfinite(a->pixels[4 * i + 1]) || !isfinite(a->pixels[4 * i + 2]);
    return n;
}

/* Above this relMSE between the reference's two seeds, gi_bench warns: the
 * mean reference's expected error (a quarter of it) would pass 0.025, more
 * than the error of most rows of section 7's tables. */
#define REF_NOISE_WARN 0.1

static FILE* csv;
static const char* scene_name;

static void row(const char* method, const char* setting, unsigned probes, unsigned spp, double build_s, double full_s,
                double ind_s, double rel_full, double rel_ind, size_t bad) {
    char pr[16] = "-", bs[24] = "-";
    if (probes) snprintf(pr, sizeof pr, "%u", probes);
    if (build_s > 0) snprintf(bs, sizeof bs, "%.3f", build_s);
    printf("| %s | %s | %s | %s | %u | %s | %.4g | %.4g | %.4g | %.4g |", scene_name, method, setting, pr, spp, bs,
           full_s * 1e3, ind_s * 1e3, rel_full, rel_ind);
    printf(bad ? " %zu pixels not finite\n" : "\n", bad);
    if (csv) {
        fprintf(csv, "%s,%s,%s,%u,%u,%.6g,%.6g,%.6g,%.6g,%.6g,%u,%u,\"%s\",%zu\n", scene_name, method, setting, probes,
                spp, build_s, full_s * 1e3, ind_s * 1e3, rel_full, rel_ind, base.width, base.height,
                vx_gpu_device_name(gpu), bad);
        fflush(csv);
    }
}


static int usage(void) {
    fprintf(stderr,
            "usage: gi_bench [--device N|NAME] [--ref-spp N] [--runs N] [--warm MS] [--threads N] [--methods a,b]\n"
            "                [--max-spp METHOD=N] [--camera EX,EY,EZ,TX,TY,TZ] [--up X,Y,Z] [--fov DEG]\n"
            "                [--light X,Y,Z] [--bounds X0,Y0,Z0,X1,Y1,Z1] [--name NAME] [--csv FILE]\n"
            "                [--photons N] [--photon-radius R] [--ref-sun-angle DEG]\n"
            "                SCENE.{svo,vox} WxH [spacing:res:spp[:i] ...]  (:i: independent first bounce)\n"
            "methods:");
    for (size_t k = 0; k < METHOD_COUNT; k++) fprintf(stderr, " %s (max spp %u)", methods[k].name, methods[k].max_spp);
    fprintf(stderr, "\n");
    return 2;
}

/* Renders every row of method m with what b holds. */
static int method_rows(const gi_method* m, const unsigned* max_spp, const built* b, const vx_render_image* ref_full,
                       const vx_render_image* ref_ind) {
    for (unsigned spp = 1; spp <= max_spp[m - methods]; spp *= 4) {
        vx_render_image full = {0}, ind = {0};
        vx_error err = {0};
        if (render_median(m, b, false, spp, &full, &err) || render_median(m, b, true, spp, &ind, &err)) {
            vx_render_image_free(&full);
            /* in the table's text too: a method's failure leaves its rows out, not the table's others */
            fprintf(stderr, "%s: %s %s %u spp: %s\n", scene_name, m->name, b->setting, spp, err.msg);
            printf("%s: %s %s failed at %u spp (its rows from there left out): %s\n", scene_name, m->name, b->setting,
                   spp, err.msg);
            return 1;
        }
        size_t bad[2] = {nonfinite(&full), nonfinite(&ind)};
        if (bad[0] || bad[1])
            fprintf(stderr, "%s: %s %s %u spp: %zu (full) and %zu (indirect) pixels not finite\n", scene_name, m->name,
                    b->setting, spp, bad[0], bad[1]);
        if (m->render == cone_render)
            printf("%s: mean indirect light / the reference's: %.3f\n", m->name, mean_ratio(&ind, ref_ind));
        row(m->name, b->setting, b->has_ps ? b->ps.probe_count : 0, spp, b->seconds, full.gpu_seconds, ind.gpu_seconds,
            rel_mse(&full, ref_full), rel_mse(&ind, ref_ind), bad[0] + bad[1]);
        vx_render_image_free(&full);
        vx_render_image_free(&ind);
    }
    return 0;
}

int main(int argc, char** argv) {
    const char *device = NULL, *method_list = NULL, *csv_path = NULL;
    unsigned ref_spp = 1024, max_spp[METHOD_COUNT];
    bool bounds_set = false;
    double bounds[6] = {0};
    for (size_t k = 0; k < METHOD_COUNT; k++) max_spp[k] = methods[k].max_spp;
    int i = 1;
    for (; i < argc && argv[i][0] == '-' && argv[i][1] == '-'; i++) {
        const char* o = argv[i];
        if (i + 1 >= argc) return usage();
        const char* v = argv[++i];
        if (!strcmp(o, "--device")) device = v;
        else if (!strcmp(o, "--ref-spp")) ref_spp = (unsigned)atoi(v);
        else if (!strcmp(o, "--runs")) runs = (unsigned)atoi(v);
        else if (!strcmp(o, "--warm")) warm_ms = atof(v);
        else if (!strcmp(o, "--threads")) threads = (unsigned)atoi(v);
        else if (!strcmp(o, "--methods")) method_list = v;
        else if (!strcmp(o, "--name")) scene_name = v;
        else if (!strcmp(o, "--csv")) csv_path = v;
        else if (!strcmp(o, "--photons")) photon_desc.photons = (uint32_t)atoi(v);
        else if (!strcmp(o, "--photon-radius")) photon_desc.radius = atof(v);
        else if (!strcmp(o, "--ref-sun-angle")) {
            ref_sun.angular_diameter = atof(v) * 3.14159265358979323846 / 180;
            if (!(ref_sun.angular_diameter >= 0 && ref_sun.angular_diameter < 3)) return usage();
        }
        else if (!strcmp(o, "--max-spp")) {
            const char* eq = strchr(v, '=');
            size_t k = 0;
            while (eq && k < METHOD_COUNT &&
                   !(strlen(methods[k].name) == (size_t)(eq - v) && !strncmp(methods[k].name, v, (size_t)(eq - v))))
                k++;
            if (!eq || k == METHOD_COUNT) return usage();
            max_spp[k] = (unsigned)atoi(eq + 1);
        } else if (!strcmp(o, "--camera")) {
            double c[6];
            if (!vx_tool_parse_vec(v, c, 6)) return usage();
            base.camera.set = true;
            memcpy(base.camera.eye, c, 24), memcpy(base.camera.target, c + 3, 24);
        } else if (!strcmp(o, "--up")) {
            if (!vx_tool_parse_vec(v, base.camera.up, 3)) return usage();
        } else if (!strcmp(o, "--fov")) {
            if (!vx_tool_parse_vec(v, &base.camera.fov, 1)) return usage();
        } else if (!strcmp(o, "--light")) {
            if (!vx_tool_parse_vec(v, base.light_dir, 3)) return usage();
        } else if (!strcmp(o, "--bounds")) {
            if (!vx_tool_parse_vec(v, bounds, 6)) return usage();
            bounds_set = true;
        } else return usage();
    }
    if (argc - i < 2 || !runs || !ref_spp || !threads) return usage();
    const char* path = argv[i];
    if (sscanf(argv[i + 1], "%ux%u", &base.width, &base.height) != 2) return usage();
    int first_setting = i + 2;
    if (!scene_name) {
        const char* slash = strrchr(path, '/');
        scene_name = slash ? slash + 1 : path;
    }
    bool use[METHOD_COUNT];
    for (size_t k = 0; k < METHOD_COUNT; k++) {
        use[k] = !method_list && !methods[k].on_request;
        if (method_list) {
            size_t n = strlen(methods[k].name);
            for (const char* p = method_list; (p = strstr(p, methods[k].name)); p += n)
                if ((p == method_list || p[-1] == ',') && (p[n] == ',' || !p[n])) use[k] = true;
        }
    }

    vx_error err = {0};
    if (!strcmp(path, "thin-wall")    ? thin_wall_scene(&scene, &err)
        : !strcmp(path, "metal-room") ? metal_room_scene(&scene, &err)
                                      : bench_load(path, &scene, &err))
        return fprintf(stderr, "%s: %s\n", path, err.msg), 1;
    if (vx_gpu_create(&(vx_gpu_desc){.device = device}, &gpu, &err) ||
        vx_render_scene_create(gpu, &scene, &rs, &err)) {
        fprintf(stderr, "GPU: %s\n", err.msg);
        return 1;
    }
    if (csv_path) {
        csv = fopen(csv_path, "a");
        if (!csv) return fprintf(stderr, "%s: cannot open\n", csv_path), 1;
        if (ftell(csv) == 0)
            fprintf(csv, "scene,method,setting,probes,spp,build_s,full_ms,indirect_ms,relmse_full,relmse_indirect,"
                         "width,height,device,nonfinite\n");
    }
    printf("device: %s; %s at %ux%u, reference %u spp x 2 seeds, median of %u renders, warm-up %g ms\n",
           vx_gpu_device_name(gpu), scene_name, base.width, base.height, ref_spp, runs, warm_ms);
    printf("| scene | method | setting | probes | spp | build s | full ms | indirect ms | relMSE full | "
           "relMSE indirect |\n|---|---|---|---:|---:|---:|---:|---:|---:|---:|\n");
    int rc = 0;
    built none = {.setting = "-"};
    if (vx_probe_gpu_create(rs, &scene, NULL, &none.pg, &err)) return fprintf(stderr, "GPU: %s\n", err.msg), 1;

    if (ref_sun.angular_diameter > 0) { /* the probes' sun (direction, irradiance) as a disc */
        const vx_probe_bake_desc D = vx_probe_bake_desc_defaults();
        bool dir_set = base.light_dir[0] || base.light_dir[1] || base.light_dir[2];
        ref_sun.type = VX_LIGHT_DIRECTIONAL;
        memcpy(ref_sun.direction, dir_set ? base.light_dir : D.light_dir, sizeof ref_sun.direction);
        memcpy(ref_sun.color, D.sun, sizeof ref_sun.color);
        ref_sun.intensity = 1;
        ref_sun_count = 1;
    }
    /* the reference: two seeds each for the full image and the indirect light */
    vx_render_image ref[2][2] = {{{0}}}; /* [indirect][seed] */
    double ref_s[2] = {0};
    for (int ind = 0; ind < 2 && !rc; ind++)
        for (int k = 0; k < 2 && !rc; k++) {
            vx_probe_render_desc d = {.base = &base,
                                      .mode = ind ? VX_PROBE_RENDER_PT_INDIRECT : VX_PROBE_RENDER_PATHTRACE,
                                      .spp = ref_spp,
                                      .seed = 999 + (uint64_t)k,
                                      .lights = &ref_sun,
                                      .light_count = ref_sun_count};
            if (vx_probe_gpu_render(none.pg, &d, &ref[ind][k], &err)) {
                fprintf(stderr, "%s: reference: %s\n", scene_name, err.msg);
                rc = 1;
            }
            ref_s[ind] += ref[ind][k].gpu_seconds / 2;
        }
    if (rc) return rc;
    double noise[2], worst_share[2];
    for (int ind = 0; ind < 2; ind++) {
        noise[ind] = rel_mse(&ref[ind][0], &ref[ind][1]);
        worst_share[ind] = worst_pixel_share(&ref[ind][0], &ref[ind][1]);
        float* a = ref[ind][0].pixels;
        const float* b = ref[ind][1].pixels;
        for (size_t p = 0; p < (size_t)base.width * base.height * 4; p++) a[p] = 0.5f * (a[p] + b[p]);
        vx_render_image_free(&ref[ind][1]);
    }
    char ref_setting[64];
    if (ref_sun_count)
        snprintf(ref_setting, sizeof ref_setting, "seed 999 vs 1000; sun %.2f deg",
                 ref_sun.angular_diameter * 180 / 3.14159265358979323846);
    else snprintf(ref_setting, sizeof ref_setting, "seed 999 vs 1000");
    row("reference", ref_setting, 0, ref_spp, 0, ref_s[0], ref_s[1], noise[0], noise[1],
        nonfinite(&ref[0][0]) + nonfinite(&ref[1][0]));
    for (int ind = 0; ind < 2; ind++) {
        printf("%s: reference %s: the worst pixel holds %.0f%% of the two seeds' squared difference\n", scene_name,
               ind ? "indirect" : "full", 100 * worst_share[ind]);
        if (noise[ind] > REF_NOISE_WARN) {
            printf("%s: WARNING: the %s reference's two seeds differ by relMSE %.3g (above %g): its own error is "
                   "above most methods', so this scene's %s column says nothing\n", scene_name,
                   ind ? "indirect" : "full", noise[ind], REF_NOISE_WARN, ind ? "indirect" : "full");
            fprintf(stderr, "%s: warning: the %s reference is noisy (seeds' relMSE %.3g)\n", scene_name,
                    ind ? "indirect" : "full", noise[ind]);
        }
    }
    pt_ms_per_spp = ref_s[1] * 1e3 / ref_spp;
    warm_with = &none;

    /* A method that fails (e.g. photons-fg at lavapipe's loop limit on the helmet) is reported and the others go
     * on; the exit status says some failed (3), so a script can go on to the next scene and still know. */
    unsigned failed = 0;
    for (size_t k = 0; k < METHOD_COUNT && !rc; k++)
        if (use[k] && methods[k].build == BUILD_NONE)
            failed += method_rows(&methods[k], max_spp, &none, &ref[0][0], &ref[1][0]);
    for (int s = first_setting; s < argc && !rc; s++) {
        bool needed = false;
        for (size_t k = 0; k < METHOD_COUNT; k++) needed |= use[k] && methods[k].build == BUILD_PROBES;
        if (!needed) break;
        double sp;
        unsigned res, spp;
        char tail = 0;
        /* a setting ending in ":i" bakes with the independent first bounce (the estimator before the
         * stratified one, vx_probe_bake_desc.independent_bounce), to compare both against one reference */
        int nf = sscanf(argv[s], "%lf:%u:%u:%c", &sp, &res, &spp, &tail);
        if (nf < 3 || (nf == 4 && tail != 'i')) {
            rc = usage();
            break;
        }
        built b = {.setting = argv[s], .has_ps = true};
        vx_probe_bake_desc bd = {.spacing = sp, .res = res, .spp = spp, .threads = threads, .bounds_set = bounds_set,
                                 .independent_bounce = nf == 4};
        memcpy(bd.bounds_lo, bounds, 24), memcpy(bd.bounds_hi, bounds + 3, 24);
        memcpy(bd.light_dir, base.light_dir, 24);
        double t0 = vx_time_now();
        if (vx_probe_bake_gpu(rs, &scene, &bd, &b.ps, &err)) {
            fprintf(stderr, "%s: bake %s: %s\n", scene_name, argv[s], err.msg);
            rc = 1;
            break;
        }
        b.seconds = vx_time_now() - t0;
        if (vx_probe_gpu_create(rs, &scene, &b.ps, &b.pg, &err)) {
            fprintf(stderr, "GPU: %s\n", err.msg);
            rc = 1;
        }
        for (size_t k = 0; k < METHOD_COUNT && !rc; k++)
            if (use[k] && methods[k].build == BUILD_PROBES)
                failed += method_rows(&methods[k], max_spp, &b, &ref[0][0], &ref[1][0]);
        vx_probe_gpu_destroy(b.pg);
        vx_probe_set_free(&b.ps);
    }
    vx_render_image_free(&ref[0][0]);
    vx_render_image_free(&ref[1][0]);
    vx_probe_gpu_destroy(none.pg);
    vx_photon_gi_destroy(photon_gi[0]);
    vx_photon_gi_destroy(photon_gi[1]);
    vx_cone_gi_destroy(cone_gi);
    vx_frame_renderer_destroy(cone_fr);
    if (csv) fclose(csv);
    vx_render_scene_destroy(rs);
    vx_gpu_destroy(gpu);
    vx_svo_scene_free(&scene);
    if (!rc && failed) fprintf(stderr, "%s: %u method setting(s) failed (above)\n", scene_name, failed);
    return rc ? rc : failed ? 3 : 0;
}
