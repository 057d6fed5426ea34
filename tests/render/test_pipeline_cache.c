/* tests/render/test_pipeline_cache.c - the device's pipeline cache
 * (render/gpu_pipeline.c, issue 18) with more variants than a scene needs:
 * a pipeline fetched before hundreds of others are created is still itself
 * (same handle, runs its own shader); frames of several scenes in both
 * layouts (plain and compact) with every GI method (probes baked on the
 * GPU, pathtrace, cones, photons), all through one device whose cache
 * already holds many pipelines (as a long session's would), give the bits
 * of the same frames rendered on a fresh device per scene and layout; and
 * frames recorded and held for a batch (render/display.h) while other
 * pipelines are created still run the pipelines they recorded. The cache
 * used to evict its oldest entry past 128 and move the others, so that the
 * pipelines held by a frame, a GI method or a recorded command buffer were
 * destroyed or became other pipelines (wrong images, validation errors).
 * The fresh devices make their pipelines from the modules as built
 * (VX_GPU_SPECIALISE=0), the shared one from modules specialised on the host
 * (render/spirv_opt.h, VX_GPU_SPECIALISE=1, lavapipe's default): the same bits
 * again, every module the frames use accepted by the specialiser.
 * On lavapipe; skips without a device. */
#define _POSIX_C_SOURCE 200809L /* setenv */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <vulkan/vulkan.h>

#include "cones/cones.h"
#include "photons/photons.h"
#include "probes/probes.h"
#include "render/display.h"
#include "render/pipeline.h"
#include "render/gpu.h" /* vx__pipeline_get, vx__pipeline_ahead, vx__dispatch */
#include "render/spirv_opt.h" /* vx__spirv_can_specialise */
#include "tests/gpu_test.h"
#include "tests/probes/probe_scenes.h"
#include "tests/render/scenes.h"
#include "tests/test.h"

#include "cache_value.comp.h" /* shaders/cache_value.comp: writes its constant 0 to out[0] */

static vx_gpu* gpu;
static const char* gpu_skip;

static int logged;
static vx_logger lg = {.func = vx_test_validation_log, .user_data = &logged};

/* The cheap pipeline that writes `value`. */
static vx_gpu_compute_pipeline_desc value_desc(uint32_t value) {
    return (vx_gpu_compute_pipeline_desc){.spirv = vx_test_cache_value_spv,
                                          .spirv_size = sizeof vx_test_cache_value_spv,
                                          .binding_count = 1,
                                          .bindings = {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
                                          .spec_count = 1,
                                          .spec = {value},
                                          .label = "cache value"};
}

/* The same, cached under `key`. */
static vx_result value_pipeline(vx_gpu* g, uint64_t key, uint32_t value, vx__pipeline** out, vx_error* err) {
    vx_gpu_compute_pipeline_desc d = value_desc(value);
    return vx__pipeline_get(g, key, &d, out, err);
}

enum { FILL_KEY = 0xCAC4E000u };

/* n pipelines of distinct keys from `first` (values 1000 + index). */
static bool fill_cache(vx_gpu* g, uint32_t first, uint32_t n) {
    vx_error err = {0};
    for (uint32_t i = first; i < first + n; i++) {
        vx__pipeline* p;
        if (value_pipeline(g, FILL_KEY + i, 1000 + i, &p, &err)) {
            fprintf(stderr, "  filler %u: %s\n", i, err.msg);
            return false;
        }
    }
    return true;
}

/* What p writes (UINT32_MAX on failure). */
static uint32_t run_value(vx_gpu* g, vx__pipeline* p, vx__buffer* out) {
    vx_error err = {0};
    uint32_t v = UINT32_MAX;
    if (vx__buffer_upload(g, out, &v, 4, &err) ||
        vx__dispatch(g, &(vx__dispatch_desc){.pipeline = p, .buffer_count = 1, .buffers = {out}, .groups = {1, 1, 1}},
                     NULL, &err) ||
        vx__buffer_download(g, out, &v, 4, &err)) {
        fprintf(stderr, "  dispatch: %s\n", err.msg);
        return UINT32_MAX;
    }
    return v;
}

/* A pipeline held while 300 others are created: the same entry, handle and shader. */
static void test_held_pipeline(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_gpu* g = NULL;
    REQUIRE(!vx_test_gpu_open((vx_gpu_desc){.logger = &lg}, true, &g));
    vx_error err = {0};
    vx__buffer out = {0};
    vx__pipeline *a = NULL, *b = NULL;
    REQUIRE(vx__buffer_create(g, 256, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, "out", &out, &err) == VX_OK);
    REQUIRE(value_pipeline(g, 0xA11CEu, 111, &a, &err) == VX_OK);
    CHECK(run_value(g, a, &out) == 111);
    VkPipeline handle = a->pipe;
    uint32_t before = g->pipeline_count;
    CHECK(fill_cache(g, 0, 300));
    CHECKF(g->pipeline_count == before + 300, "%u pipelines cached, %u expected", g->pipeline_count, before + 300);
    CHECKF(a->key == 0xA11CEu && a->pipe == handle, "the held entry now has key %llx", (unsigned long long)a->key);
    uint32_t got = run_value(g, a, &out);
    CHECKF(got == 111, "the held pipeline wrote %u, not 111", got);
    /* a lookup finds the same entry and creates nothing */
    REQUIRE(value_pipeline(g, 0xA11CEu, 111, &b, &err) == VX_OK);
    CHECK(b == a && g->pipeline_count == before + 300);
    /* and a filler made early is itself too */
    REQUIRE(value_pipeline(g, FILL_KEY + 5, 1005, &b, &err) == VX_OK);
    CHECK(run_value(g, b, &out) == 1005 && g->pipeline_count == before + 300);
    CHECKF(vx_gpu_validation_errors(g) == 0, "%u validation errors", vx_gpu_validation_errors(g));
    vx__buffer_destroy(g, &out);
    vx_gpu_destroy(g);
}

/* Pipelines made ahead on threads of their own (vx__pipeline_ahead, the probe bake's kernels while its sun map
 * is built): the get of each key takes its own pipeline (it writes its own constant) in any order, into the
 * cache (counted once, found again by a later get); another ahead of a key pending or made starts nothing;
 * those never asked for go with the device (LeakSanitizer in the ASan build, no validation error). */
static void test_ahead(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_gpu* g = NULL;
    REQUIRE(!vx_test_gpu_open((vx_gpu_desc){.logger = &lg}, true, &g));
    vx_error err = {0};
    vx__buffer out = {0};
    REQUIRE(vx__buffer_create(g, 256, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, "out", &out, &err) == VX_OK);
    enum { N = 6, EXTRA = 2 };
    const uint64_t key = 0xAEAD000u;
    uint32_t before = g->pipeline_count;
    for (uint32_t i = 0; i < N + EXTRA; i++) {
        vx_gpu_compute_pipeline_desc d = value_desc(3000 + i);
        CHECKF(vx__pipeline_ahead(g, key + i, &d), "ahead %u not started", i);
    }
    vx_gpu_compute_pipeline_desc d0 = value_desc(3000);
    CHECK(!vx__pipeline_ahead(g, key, &d0)); /* pending */
    CHECK(g->pipeline_count == before);      /* nothing in the cache before its get */
    vx__pipeline* p[N] = {0};
    for (uint32_t k = N; k-- > 0;) { /* taken in another order than made */
        REQUIRE(value_pipeline(g, key + k, 3000 + k, &p[k], &err) == VX_OK);
        uint32_t got = run_value(g, p[k], &out);
        CHECKF(got == 3000 + k, "pipeline %u made ahead wrote %u", k, got);
    }
    CHECKF(g->pipeline_count == before + N, "%u pipelines cached, %u expected", g->pipeline_count, before + N);
    CHECK(!vx__pipeline_ahead(g, key + 1, &d0)); /* made */
    vx__pipeline* again = NULL;
    REQUIRE(value_pipeline(g, key + 2, 3002, &again, &err) == VX_OK);
    CHECK(again == p[2] && g->pipeline_count == before + N);
    /* a key never made ahead is made by its get as before, beside the pending ones */
    REQUIRE(value_pipeline(g, key + 100, 3100, &again, &err) == VX_OK);
    CHECK(run_value(g, again, &out) == 3100);
    CHECK(g->pending != NULL); /* the EXTRA never asked for: vx_gpu_destroy joins and destroys them */
    CHECKF(vx_gpu_validation_errors(g) == 0, "%u validation errors", vx_gpu_validation_errors(g));
    vx__buffer_destroy(g, &out);
    vx_gpu_destroy(g);
}

/* ---- frames of many scenes, both layouts and the GI methods through one device ---- */

enum { GI_NONE, GI_PROBES, GI_PATHTRACE, GI_CONES, GI_PHOTONS };
typedef struct job {
    const char* list;
    int gi;
    uint32_t spp;
    bool merged; /* passes merged where they can be (the frame kernel) */
} job;
/* each method's frame comes after the others made their pipelines; probes twice */
static const job jobs[] = {
    {"gbuffer,direct", GI_NONE, 1, true},
    {"gbuffer,direct,gi=probes", GI_PROBES, 1, false},
    {"gbuffer,direct,ao,aa,tonemap", GI_NONE, 2, false},
    {"gbuffer,direct,gi=cones", GI_CONES, 1, false},
    {"gbuffer,direct,gi=photons", GI_PHOTONS, 1, false},
    {"gbuffer,direct,gi=pathtrace", GI_PATHTRACE, 1, false},
    {"gbuffer,direct,ao", GI_NONE, 1, false},
    {"gbuffer,direct,gi=probes", GI_PROBES, 1, false},
};
enum { NJOBS = sizeof jobs / sizeof jobs[0], W = 32, H = 24 };

/* The jobs' images of scene s in `layout` on device g (pixels NULL where a frame failed). */
static bool frames_of(vx_gpu* g, const vx_svo_scene* s, vx_render_layout layout, vx_render_image img[NJOBS]) {
    vx_error err = {0};
    memset(img, 0, NJOBS * sizeof *img);
    vx_render_scene* rs = NULL;
    vx_frame_renderer* fr = NULL;
    vx_render_scene_desc rd = {.layout = layout, .memory_budget = 1ull << 40}; /* the whole compact layout */
    vx_probe_set ps = {0};
    vx_gi_method gm[5];
    vx_probe_gi *pg = NULL, *pt = NULL;
    vx_cone_gi* cg = NULL;
    vx_photon_gi* ph = NULL;
    bool ok = false;
    if (vx_render_scene_create_ex(g, s, &rd, &rs, &err) || vx_frame_renderer_create(rs, s, &fr, &err)) goto done;
    /* every method made before any frame: each holds its state while the others make theirs */
    vx_probe_bake_desc bd = {.grid = {2, 2, 2}, .res = 16, .spp = 1, .bounces = 1, .seed = 5};
    vx_probe_render_desc prd = {.spp = 1, .bounces = 1, .seed = 3};
    if (vx_probe_bake_gpu(rs, s, &bd, &ps, &err) ||
        vx_probe_gi_create(rs, s, &ps, "probes", &prd, &gm[GI_PROBES], &pg, &err) ||
        vx_probe_gi_create(rs, s, &ps, "pathtrace", &prd, &gm[GI_PATHTRACE], &pt, &err) ||
        vx_cone_gi_create(rs, s, &(vx_cone_desc){.res = 16}, &gm[GI_CONES], &cg, &err) ||
        vx_photon_gi_create(rs, s, NULL, &(vx_photon_desc){.photons = 1 << 12, .seed = 9}, &gm[GI_PHOTONS], &ph,
                            &err))
        goto done;
    for (int k = 0; k < NJOBS; k++) {
        vx_pass_list L;
        if (vx_pass_list_parse(jobs[k].list, &L, &err)) goto done;
        vx_frame_desc d = vx_frame_desc_defaults();
        d.base.width = W, d.base.height = H, d.base.spp = jobs[k].spp;
        d.passes = &L;
        d.gi = jobs[k].gi ? &gm[jobs[k].gi] : NULL;
        d.separate_passes = !jobs[k].merged;
        vx_frame_result res;
        if (vx_frame_render(fr, &d, &res, &err)) goto done;
        img[k] = res.image;
    }
    ok = true;
done:
    if (!ok) fprintf(stderr, "  %s layout: %s\n", vx_render_layout_name(layout), err.msg);
    vx_photon_gi_destroy(ph);
    vx_cone_gi_destroy(cg);
    vx_probe_gi_destroy(pt);
    vx_probe_gi_destroy(pg);
    vx_probe_set_free(&ps);
    vx_frame_renderer_destroy(fr);
    vx_render_scene_destroy(rs);
    return ok;
}

static void free_images(vx_render_image img[NJOBS]) {
    for (int k = 0; k < NJOBS; k++) vx_render_image_free(&img[k]);
}

static void make_scenes(vx_svo_scene s[2]) {
    /* palette models, one rotated instance */
    vx_svo_model m[2];
    memset(m, 0, sizeof m);
    CHECK(ts_random_model(&m[0], 20, 12, 9, 40, 1) == VX_OK);
    CHECK(ts_random_model(&m[1], 10, 10, 10, 60, 2) == VX_OK);
    static const double rot[9] = {0.36, -0.48, 0.8, 0.8, 0.6, 0, -0.48, 0.64, 0.6};
    vx_svo_instance in[3] = {ts_inst(0, NULL, 0, 0, 0), ts_inst(1, rot, 24, 3, 0), ts_inst(1, NULL, -12, 8, 4)};
    ts_scene(&s[0], m, 2, in, 3);
    /* a room with materials (emissive, glass, metal) */
    (void)box_scene, (void)room_scene; /* probe_scenes.h's other scenes */
    glass_room_scene(&s[1]);
}

/* The scenes and layouts drawn: each pair's variants compiled twice (on
 * its fresh device and on the shared one), so two of the four: both
 * scenes and both layouts on the shared device. The room's compact pair as
 * well made it 303 s in Release with a cold shader cache, almost all of it
 * lavapipe compiling (stop 59, docs/TESTING.md). */
static const struct {
    int scene;
    vx_render_layout layout;
} pairs[] = {{1, VX_RENDER_LAYOUT_PLAIN}, {0, VX_RENDER_LAYOUT_COMPACT}};
enum { NPAIRS = sizeof pairs / sizeof pairs[0] };

/* The shared device's pipelines ("gpu.pipeline" lines): how many were specialised on the host, how many the
 * specialiser refused (made from the module as built); validation messages counted as lg's. */
typedef struct host_log {
    int validation, specialised, refused;
    char first_refusal[256];
} host_log;

static void host_cb(void* user, vx_log_level level, const char* id, const char* msg) {
    host_log* h = user;
    vx_test_validation_log(&h->validation, level, id, msg);
    if (strcmp(id, "gpu.pipeline") != 0) return;
    if (strstr(msg, "; specialised on the host in ")) h->specialised++;
    if (strstr(msg, "; not specialised on the host")) {
        if (!h->refused++) snprintf(h->first_refusal, sizeof h->first_refusal, "%s", msg);
    }
}

static void test_frames_one_device(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    bool host = vx__spirv_can_specialise();
    static const char* const names[] = {"generated", "room"};
    vx_svo_scene s[2];
    make_scenes(s);
    /* the references: a fresh device per scene and layout (about 30 pipelines each) */
    /* their pixels (an image is freed before its device: its allocator is the device's) */
    static float want[NPAIRS][NJOBS][4 * W * H];
    static bool have[NPAIRS][NJOBS];
    for (int i = 0; i < NPAIRS; i++) {
        const char* name = names[pairs[i].scene];
        const char* layout = vx_render_layout_name(pairs[i].layout);
        vx_gpu* g = NULL;
        setenv("VX_GPU_SPECIALISE", "0", 1); /* the modules as built, constants given to the driver */
        REQUIRE(!vx_test_gpu_open((vx_gpu_desc){.logger = &lg}, true, &g));
        unsetenv("VX_GPU_SPECIALISE");
        CHECK(!g->specialise);
        vx_render_image img[NJOBS];
        CHECKF(frames_of(g, &s[pairs[i].scene], pairs[i].layout, img), "%s %s: fresh device", name, layout);
        for (int k = 0; k < NJOBS; k++)
            if ((have[i][k] = img[k].pixels && img[k].width == W && img[k].height == H))
                memcpy(want[i][k], img[k].pixels, sizeof want[i][k]);
        free_images(img);
        printf("  %-10s %-8s fresh device: %u pipelines\n", name, layout, g->pipeline_count);
        CHECKF(vx_gpu_validation_errors(g) == 0, "%u validation errors", vx_gpu_validation_errors(g));
        vx_gpu_destroy(g);
    }
    /* one device for all, its cache holding 100 pipelines already, its modules specialised on the host */
    vx_gpu* g = NULL;
    host_log hl = {0};
    vx_logger hlg = {.func = host_cb, .user_data = &hl};
    setenv("VX_GPU_SPECIALISE", "1", 1);
    REQUIRE(!vx_test_gpu_open((vx_gpu_desc){.logger = &hlg}, true, &g));
    unsetenv("VX_GPU_SPECIALISE");
    CHECK(g->specialise == host);
    CHECK(fill_cache(g, 0, 100));
    for (int i = 0; i < NPAIRS; i++) {
        const char* name = names[pairs[i].scene];
        const char* layout = vx_render_layout_name(pairs[i].layout);
        vx_render_image got[NJOBS];
        CHECKF(frames_of(g, &s[pairs[i].scene], pairs[i].layout, got), "%s %s: shared device", name, layout);
        for (int k = 0; k < NJOBS; k++) {
            const float* a = want[i][k];
            const vx_render_image* b = &got[k];
            if (!have[i][k] || !b->pixels) continue;
            size_t n = (size_t)W * H, hits = 0, diff = 0;
            bool same_size = b->width == W && b->height == H;
            for (size_t q = 0; q < n; q++) hits += a[4 * q + 3] > 0;
            for (size_t q = 0; q < 4 * n; q++) diff += !same_size || memcmp(&a[q], &b->pixels[q], 4) != 0;
            printf("  %-10s %-8s %-30s %zu hit, %zu floats differ (%u pipelines)\n", name, layout, jobs[k].list, hits,
                   diff, g->pipeline_count);
            CHECKF(diff == 0, "%s %s '%s': %zu floats differ from a fresh device's frame", name, layout, jobs[k].list,
                   diff);
            CHECKF(hits > 0, "%s %s '%s': nothing hit", name, layout, jobs[k].list);
        }
        free_images(got);
    }
    CHECKF(vx_gpu_validation_errors(g) == 0, "%u validation errors", vx_gpu_validation_errors(g));
    printf("  shared device: %u pipelines, %d specialised on the host, %d refused by the specialiser\n",
           g->pipeline_count, hl.specialised, hl.refused);
    if (host) {
        CHECKF(hl.refused == 0, "the specialiser refused a module: %s", hl.first_refusal);
        CHECKF(hl.specialised >= (int)g->pipeline_count, "%d of %u pipelines specialised on the host", hl.specialised,
               g->pipeline_count);
    }
    vx_gpu_destroy(g);
    vx_svo_scene_free(&s[0]);
    vx_svo_scene_free(&s[1]);
}

/* ---- a frame makes the pipelines it dispatches, no others ---- */

/* The labels of the pipelines a device made ("gpu.pipeline" log lines: "LABEL (N bytes of SPIR-V, ...) made in"),
 * the validation layer's messages counted as lg's. */
typedef struct made_log {
    int validation;
    char labels[4096];
} made_log;

static void made_cb(void* user, vx_log_level level, const char* id, const char* msg) {
    made_log* m = user;
    vx_test_validation_log(&m->validation, level, id, msg);
    const char* e = strstr(msg, " (");
    size_t n = strlen(m->labels), k = e ? (size_t)(e - msg) : 0;
    if (!strcmp(id, "gpu.pipeline") && k && n + k + 2 < sizeof m->labels)
        memcpy(m->labels + n, msg, k), memcpy(m->labels + n + k, ";", 2);
}

/* One frame of list on fr (merged unless separate): the labels of the pipelines it made, into made (";"-ended);
 * false on a failure. */
static bool frame_made(vx_frame_renderer* fr, made_log* m, const char* list, bool separate, char* made, size_t cap) {
    vx_error err = {0};
    vx_pass_list L;
    vx_frame_desc d = vx_frame_desc_defaults();
    d.base.width = W, d.base.height = H;
    d.passes = &L;
    d.separate_passes = separate;
    m->labels[0] = 0;
    vx_frame_result res;
    if (vx_pass_list_parse(list, &L, &err) || vx_frame_render(fr, &d, &res, &err)) {
        fprintf(stderr, "  '%s': %s\n", list, err.msg);
        return false;
    }
    vx_render_image_free(&res.image);
    snprintf(made, cap, "%s", m->labels);
    printf("  %-20s %-8s made: %s\n", list, separate ? "separate" : "merged", made[0] ? made : "(none)");
    return true;
}

/* A merged frame (gbuffer, direct, ao and resolve in one frame kernel) dispatches that kernel alone: it makes the
 * frame kernel and the G-buffer's pipeline (whose layout its descriptor set takes), not the direct, AO and
 * resolve kernels, which only separate passes run. On lavapipe the direct kernel's compile was half of a default
 * svo_render's 3.7 s. A fresh device, so that its cache holds none of them before; its log names what it made. */
static void test_pipelines_per_frame(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene s[2];
    make_scenes(s);
    static made_log m;
    vx_logger ml = {.func = made_cb, .user_data = &m};
    vx_gpu* g = NULL;
    REQUIRE(!vx_test_gpu_open((vx_gpu_desc){.logger = &ml}, true, &g));
    vx_error err = {0};
    vx_render_scene* rs = NULL;
    vx_frame_renderer* fr = NULL;
    char a[4096], b[4096], c[4096], e[4096];
    if (vx_render_scene_create(g, &s[0], &rs, &err) || vx_frame_renderer_create(rs, &s[0], &fr, &err)) {
        CHECKF(false, "frame renderer: %s", err.msg);
    } else if (!frame_made(fr, &m, "gbuffer,direct", false, a, sizeof a) ||
               !frame_made(fr, &m, "gbuffer,direct,ao", false, b, sizeof b) ||
               !frame_made(fr, &m, "gbuffer,direct", true, c, sizeof c) ||
               !frame_made(fr, &m, "gbuffer,direct,ao", true, e, sizeof e)) {
        CHECKF(false, "%s", "a frame failed");
    } else {
        static const char* const pass_kernels[] = {"direct;", "ao;", "resolve;"};
        for (int k = 0; k < 3; k++) {
            CHECKF(!strstr(a, pass_kernels[k]) && !strstr(b, pass_kernels[k]),
                   "a merged frame made the %.*s kernel, which it does not run", (int)strlen(pass_kernels[k]) - 1,
                   pass_kernels[k]);
        }
        CHECKF(strstr(a, "frame;") && strstr(a, "gbuffer;"), "the merged frame made '%s'", a);
        CHECKF(strstr(b, "frame;"), "the merged frame with ao made '%s' (its own frame kernel)", b);
        /* the separate passes then make their kernels: what the merged frames did not */
        CHECKF(strstr(c, "direct;") && strstr(c, "resolve;"), "the separate passes made '%s'", c);
        CHECKF(strstr(e, "ao;"), "the separate passes with ao made '%s'", e);
    }
    CHECKF(m.validation == 0 && vx_gpu_validation_errors(g) == 0, "%u validation errors",
           vx_gpu_validation_errors(g));
    vx_frame_renderer_destroy(fr);
    vx_render_scene_destroy(rs);
    vx_gpu_destroy(g);
    vx_svo_scene_free(&s[0]);
    vx_svo_scene_free(&s[1]);
}

/* ---- frames recorded and held while other pipelines are created ---- */

/* Records frame d into a display frame that copies it into image img, and submits it (held for the batch). */
static bool record_frame(vx_display* disp, vx_frame_renderer* fr, const vx_frame_desc* d, uint64_t img) {
    vx_error err = {0};
    uint32_t slot;
    void* cmd;
    vx_frame_result res;
    uint64_t buf = 0;
    vx_display_desc dd = {.fr = fr, .width = W, .height = H};
    if (vx_display_frame_begin(disp, &slot, &cmd, &err)) goto fail;
    if (vx_frame_record(fr, d, cmd, slot, &res, &err)) {
        vx_display_frame_cancel(disp);
        goto fail;
    }
    if (vx_display_record(disp, cmd, &dd, &buf, &err)) {
        vx_frame_record_cancel(fr);
        vx_display_frame_cancel(disp);
        goto fail;
    }
    vx_display_copy_to_image(cmd, buf, W, H, img, W, H, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    if (vx_display_frame_submit(disp, 0, 0, &err)) goto fail;
    return true;
fail:
    fprintf(stderr, "  record: %s\n", err.msg);
    return false;
}

static void test_held_frames(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_gpu* g = NULL;
    REQUIRE(!vx_test_gpu_open((vx_gpu_desc){.logger = &lg}, true, &g));
    vx_svo_scene s[2];
    make_scenes(s);
    vx_error err = {0};
    vx_render_scene* rs = NULL;
    vx_frame_renderer* fr = NULL;
    vx_display* disp = NULL;
    uint64_t img[2] = {0, 0};
    bool ok = vx_render_scene_create(g, &s[0], &rs, &err) == VX_OK && vx_frame_renderer_create(rs, &s[0], &fr, &err) == VX_OK &&
              vx_display_create(g, &disp, &err) == VX_OK && vx_display_image_create(disp, W, H, &img[0], &err) == VX_OK &&
              vx_display_image_create(disp, W, H, &img[1], &err) == VX_OK &&
              vx_display_set_queue(disp, 2, 2, false, &err) == VX_OK;
    CHECKF(ok, "set-up: %s", err.msg);
    static const char* const lists[2] = {"gbuffer,direct,ao,aa,tonemap", "gbuffer,direct"};
    vx_pass_list L[2];
    vx_frame_desc d[2];
    for (int k = 0; ok && k < 2; k++) {
        REQUIRE(vx_pass_list_parse(lists[k], &L[k], &err) == VX_OK);
        d[k] = vx_frame_desc_defaults();
        d[k].base.width = W, d[k].base.height = H, d[k].base.spp = 2 - (uint32_t)k;
        d[k].passes = &L[k];
        d[k].no_readback = true;
    }
    /* frame 0 recorded and held (batches of 2); 300 pipelines made; frame 1 recorded: both submitted */
    if (ok) ok = record_frame(disp, fr, &d[0], img[0]);
    if (ok) CHECK(fill_cache(g, 0, 300));
    if (ok) ok = record_frame(disp, fr, &d[1], img[1]);
    if (ok) ok = vx_display_wait(disp, &err) == VX_OK;
    CHECKF(ok, "frames in flight: %s", err.msg);
    /* each against the same frame rendered and converted with a wait */
    uint8_t got[W * H * 4], want[W * H * 4];
    for (int k = 0; ok && k < 2; k++) {
        vx_frame_result res;
        vx_display_desc dd = {.fr = fr, .width = W, .height = H};
        REQUIRE(vx_frame_render(fr, &d[k], &res, &err) == VX_OK);
        vx_render_image_free(&res.image);
        REQUIRE(vx_display_run(disp, &dd, want, NULL, &err) == VX_OK);
        REQUIRE(vx_display_image_read(disp, img[k], W, H, got, &err) == VX_OK);
        size_t bad = 0, lit = 0;
        for (size_t q = 0; q < sizeof got; q++) bad += got[q] != want[q];
        for (size_t q = 0; q < (size_t)W * H; q++) lit += want[4 * q] != want[4 * q + 1];
        printf("  held frame %d ('%s'): %zu of %zu bytes differ from the waited frame\n", k, lists[k], bad, sizeof got);
        CHECKF(bad == 0, "held frame %d: %zu bytes differ", k, bad);
        CHECKF(lit > 0, "frame %d: a flat image", k);
    }
    CHECKF(vx_gpu_validation_errors(g) == 0, "%u validation errors", vx_gpu_validation_errors(g));
    for (int k = 0; k < 2; k++)
        if (img[k]) vx_display_image_destroy(disp, img[k]);
    vx_display_destroy(disp);
    vx_frame_renderer_destroy(fr);
    vx_render_scene_destroy(rs);
    vx_gpu_destroy(g);
    vx_svo_scene_free(&s[0]);
    vx_svo_scene_free(&s[1]);
}

int main(void) {
    gpu_skip = vx_test_gpu_open((vx_gpu_desc){.logger = &lg}, true, &gpu);
    RUN(test_held_pipeline);
    RUN(test_ahead);
    RUN(test_held_frames);
    RUN(test_frames_one_device);
    RUN(test_pipelines_per_frame);
    vx_gpu_destroy(gpu);
    return vx_test_finish();
}
