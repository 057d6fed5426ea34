/* bench/emissive_bench.c - emissive voxels as the direct pass's lights
 * (issue 11): one light per voxel or one per cluster, against the path
 * tracer. docs/PERFORMANCE.md section 11, "Emissive voxels".
 *
 *   emissive_bench [--device N|NAME] [--size WxH] [--spp N] [--ref-spp N] [--blocks 1,2,8,...]
 *
 * The scene, generated here: a room corner (floor, two walls) lit only by
 * emissive voxels of a MagicaVoxel `_emit` material: a neon tube along the
 * back wall (35 cells), a lamp of 3x3x3 cells on a post, a wall panel of
 * 10x6 cells, three single-cell pilot lights on the floor, and a block that
 * casts shadows from the lamp and the tube. Black sky, no sun.
 *
 * Each row turns the emissive voxels into lights with vx_svo_emissive_lights
 * at one cluster cut (`block` cells per side: 1 makes one light per voxel)
 * and renders the pass pipeline "gbuffer,direct,gi=pathtrace" with them:
 * the direct pass shades the first surface with those lights (the strongest
 * shadow_lights per pixel shadowed), the gi pass adds the path-traced light
 * after the first bounce (the same in every row). The reference is the path
 * tracer, which samples the emissive voxels themselves (pixel centres, as
 * the G-buffer), the mean of two images of --ref-spp with different seeds;
 * the row "reference" gives their relMSE against each other (the noise
 * floor). relMSE: sum of squared differences over the sum of the squared
 * reference, over the pixels whose reference hits the scene (gi_bench's).
 * Needs only libvulkan and libc. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench/bench_stats.h"
#include "probes/probes.h"
#include "render/pipeline.h"
#include "render/render.h"

enum { N = 48, LAMP = 9 /* the emissive palette index */ };
static uint8_t grid[N][N][N]; /* [z][y][x]: palette index, 0 empty */

static void fill(int x0, int y0, int z0, int x1, int y1, int z1, uint8_t c) {
    for (int z = z0; z <= z1; z++)
        for (int y = y0; y <= y1; y++)
            for (int x = x0; x <= x1; x++) grid[z][y][x] = c;
}

static int make_scene(vx_svo_scene* s, vx_error* err) {
    fill(0, 0, 0, N - 1, N - 1, 0, 1);         /* floor */
    fill(0, N - 1, 1, N - 1, N - 1, 30, 2);    /* back wall */
    fill(0, 0, 1, 0, N - 2, 30, 3);            /* left wall */
    fill(6, N - 3, 20, 40, N - 3, 20, LAMP);      /* neon tube, one cell off the back wall */
    fill(13, 13, 1, 13, 13, 5, 4);             /* lamp post */
    fill(12, 12, 6, 14, 14, 8, LAMP);             /* lamp */
    fill(2, 20, 10, 2, 29, 15, LAMP);             /* wall panel, one cell off the left wall */
    fill(30, 10, 1, 30, 10, 1, LAMP), fill(36, 20, 1, 36, 20, 1, LAMP), fill(24, 30, 1, 24, 30, 1, LAMP); /* pilots */
    fill(18, 20, 1, 23, 27, 9, 4);             /* a block between the lamp, the tube and the floor */
    size_t n = 0;
    for (int z = 0; z < N; z++)
        for (int y = 0; y < N; y++)
            for (int x = 0; x < N; x++) n += grid[z][y][x] != 0;
    uint64_t* keys = malloc(n * sizeof *keys);
    uint8_t* pal = malloc(n);
    if (!keys || !pal) return 1;
    n = 0;
    for (int z = 0; z < N; z++)
        for (int y = 0; y < N; y++)
            for (int x = 0; x < N; x++)
                if (grid[z][y][x]) keys[n] = vx_svo_morton((uint32_t)x, (uint32_t)y, (uint32_t)z), pal[n++] = grid[z][y][x];
    vx_svo_voxels v = {.size = {N, N, N}, .count = n, .keys = keys, .attrs = VX_ATTR_PALETTE, .palette = pal};
    vx_svo_scene_init(s, NULL);
    s->models = calloc(1, sizeof *s->models);
    s->instances = calloc(1, sizeof *s->instances);
    static const char dict[] = "_type\0_emit\0_emit\0" "1\0_flux\0" "2";
    s->materials = calloc(1, sizeof *s->materials);
    char* d = malloc(sizeof dict);
    if (!s->models || !s->instances || !s->materials || !d) return 1;
    memcpy(d, dict, sizeof dict);
    s->materials[0] = (vx_svo_material){.id = LAMP, .dict = d, .dict_size = sizeof dict};
    s->material_count = 1;
    if (vx_svo_build_model(NULL, &v, &s->models[0], NULL, err)) return 1;
    free(keys);
    free(pal);
    s->model_count = 1;
    s->instance_count = 1;
    s->instances[0].xform[0] = s->instances[0].xform[5] = s->instances[0].xform[10] = 1;
    s->instances[0].layer = UINT32_MAX;
    s->has_palette = true;
    s->palette[1] = 0xFF909090u, s->palette[2] = 0xFF7080A0u, s->palette[3] = 0xFFA08070u, s->palette[4] = 0xFF606060u;
    s->palette[LAMP] = 0xFF80D0FFu; /* warm white (ABGR) */
    vx_svo_scene_update_bounds(s);
    return 0;
}

/* relMSE over the pixels whose reference hits the scene and, with skip,
 * whose flag is 0. */
static double rel_mse(const vx_render_image* a, const vx_render_image* ref, const uint8_t* skip) {
    double se = 0, rs2 = 0;
    for (size_t i = 0; i < (size_t)ref->width * ref->height; i++) {
        if (ref->pixels[4 * i + 3] == 0 || (skip && skip[i])) continue;
        for (int c = 0; c < 3; c++) {
            double d = (double)a->pixels[4 * i + c] - ref->pixels[4 * i + c];
            se += d * d, rs2 += (double)ref->pixels[4 * i + c] * ref->pixels[4 * i + c];
        }
    }
    return rs2 > 0 ? se / rs2 : 0;
}

/* Mean over the pixels and channels where the reference hits the scene. */
static double mean_hit(const vx_render_image* a, const vx_render_image* ref) {
    double m = 0;
    size_t n = 0;
    for (size_t i = 0; i < (size_t)ref->width * ref->height; i++)
        if (ref->pixels[4 * i + 3] != 0) m += (double)a->pixels[4 * i] + a->pixels[4 * i + 1] + a->pixels[4 * i + 2], n += 3;
    return n ? m / (double)n : 0;
}

static void die(const char* what, const vx_error* e) {
    fprintf(stderr, "emissive_bench: %s: %s\n", what, e->msg);
    exit(1);
}

int main(int argc, char** argv) {
    const char* device = NULL;
    uint32_t w = 160, h = 120, spp = 256, ref_spp = 1024, blocks[8] = {1, 2, 4, 8, 16}, nb = 5;
    for (int a = 1; a < argc; a++) {
        if (!strcmp(argv[a], "--device") && a + 1 < argc) device = argv[++a];
        else if (!strcmp(argv[a], "--size") && a + 1 < argc && sscanf(argv[a + 1], "%ux%u", &w, &h) == 2) a++;
        else if (!strcmp(argv[a], "--spp") && a + 1 < argc) spp = (uint32_t)atoi(argv[++a]);
        else if (!strcmp(argv[a], "--ref-spp") && a + 1 < argc) ref_spp = (uint32_t)atoi(argv[++a]);
        else if (!strcmp(argv[a], "--blocks") && a + 1 < argc) {
            nb = 0;
            for (char* t = strtok(argv[++a], ","); t && nb < 8; t = strtok(NULL, ",")) blocks[nb++] = (uint32_t)atoi(t);
        } else {
            fprintf(stderr, "usage: emissive_bench [--device N|NAME] [--size WxH (160x120)] [--spp N (256)] "
                            "[--ref-spp N (1024)] [--blocks 1,2,4,8,16]\n");
            return 2;
        }
    }
    vx_error err = {0};
    vx_svo_scene s;
    if (make_scene(&s, &err)) die("scene", &err);
    vx_gpu* gpu = NULL;
    if (vx_gpu_create(&(vx_gpu_desc){.device = device}, &gpu, &err)) die("GPU", &err);
    vx_render_scene* rs = NULL;
    vx_frame_renderer* fr = NULL;
    if (vx_render_scene_create(gpu, &s, &rs, &err) || vx_frame_renderer_create(rs, &s, &fr, &err)) die("scene upload", &err);
    vx_probe_set light = {0}; /* black sky, no sun: the emissive voxels are the only light */
    light.light_dir[2] = 1, light.bounces = 2; /* bounces 3 */
    vx_frame_desc fd = vx_frame_desc_defaults();
    fd.base.width = w, fd.base.height = h;
    fd.base.camera.set = true;
    const double eye[3] = {44, -14, 26}, target[3] = {18, 26, 6};
    memcpy(fd.base.camera.eye, eye, sizeof eye), memcpy(fd.base.camera.target, target, sizeof target);
    fd.base.camera.up[2] = 1;
    /* the pixels that show an emissive voxel (its attribute record's palette
     * index is the lamps'), for the relMSE of the light on the other surfaces */
    vx_pass_list list;
    if (vx_pass_list_parse("gbuffer", &list, &err)) die("passes", &err);
    fd.passes = &list;
    fd.show = VX_SHOW_MATERIAL;
    vx_frame_result mat = {0};
    if (vx_frame_render(fr, &fd, &mat, &err)) die("material ids", &err);
    uint8_t* lamp = calloc((size_t)w * h, 1);
    if (!lamp) return 1;
    size_t lamps = 0;
    for (size_t i = 0; i < (size_t)w * h; i++) {
        float r = mat.image.pixels[4 * i];
        lamp[i] = r >= 0 && r < s.models[0].attr_count && s.models[0].palette[(uint32_t)r] == LAMP;
        lamps += lamp[i];
    }
    vx_render_image_free(&mat.image);
    fd.show = VX_SHOW_FINAL;
    /* the reference: the path tracer alone, emissive voxels sampled as emitters */
    vx_render_desc base = fd.base;
    vx_probe_render_desc rd = {.base = &base, .mode = VX_PROBE_RENDER_PATHTRACE, .spp = ref_spp, .seed = 999,
                               .pixel_centre = true};
    vx_render_image ref = {0}, ref2 = {0};
    if (vx_probe_render_gpu(rs, &s, &light, &rd, &ref, &err)) die("reference", &err);
    rd.seed = 1000;
    if (vx_probe_render_gpu(rs, &s, &light, &rd, &ref2, &err)) die("reference", &err);
    double noise = rel_mse(&ref2, &ref, NULL), noise_rest = rel_mse(&ref2, &ref, lamp);
    for (size_t i = 0; i < (size_t)w * h * 4; i++) ref.pixels[i] = 0.5f * (ref.pixels[i] + ref2.pixels[i]);
    printf("emissive voxels as lights: %ux%u, gi=pathtrace %u spp, reference 2 x %u spp (%.1f s on the GPU)\n\n", w, h, spp,
           ref_spp, ref.gpu_seconds + ref2.gpu_seconds);
    printf("%zu pixels show an emissive voxel\n\n", lamps);
    printf("| lights | block | shadowed per pixel | direct ms | mean / reference | relMSE | relMSE without the lamps' pixels |\n"
           "|---|---:|---:|---:|---:|---:|---:|\n");
    printf("| reference (path tracer, seed 999 vs 1000) | | | | %.4f | %.5f | %.5f |\n",
           mean_hit(&ref2, &ref) / mean_hit(&ref, &ref), noise, noise_rest);
    if (vx_pass_list_parse("gbuffer,direct,gi=pathtrace", &list, &err)) die("passes", &err);
    const int32_t shadows[2] = {0, VX_SHADOW_LIGHTS_MAX};
    for (uint32_t b = 0; b < nb; b++) {
        vx_light* L = NULL;
        uint32_t n = 0;
        vx_svo_emissive_desc ed = vx_svo_emissive_desc_defaults();
        ed.block = blocks[b];
        if (vx_svo_emissive_lights(&s, &ed, &L, &n, &err)) die("emissive lights", &err);
        vx_probe_render_desc pd = {.spp = spp, .seed = 7, .lights = L, .light_count = n};
        vx_gi_method gm;
        vx_probe_gi* pgi = NULL;
        if (vx_probe_gi_create(rs, &s, &light, "pathtrace", &pd, &gm, &pgi, &err)) die("gi", &err);
        fd.gi = &gm;
        fd.lights = L, fd.light_count = n;
        for (int k = 0; k < 2; k++) {
            fd.shadow_lights = shadows[k];
            vx_frame_result res = {0};
            if (vx_frame_render(fr, &fd, &res, &err)) die("frame", &err);
            double direct = 0;
            for (uint32_t t = 0; t < res.timing_count; t++)
                if (strstr(res.timings[t].name, "direct")) direct += res.timings[t].ms;
            printf("| %s%u | %u | %d | %.3f | %.4f | %.5f | %.5f |\n", blocks[b] == 1 ? "per voxel: " : "per cluster: ", n,
                   blocks[b], shadows[k] ? shadows[k] : VX_SHADOW_LIGHTS_DEFAULT, direct,
                   mean_hit(&res.image, &ref) / mean_hit(&ref, &ref), rel_mse(&res.image, &ref, NULL),
                   rel_mse(&res.image, &ref, lamp));
            fflush(stdout);
            vx_render_image_free(&res.image);
        }
        vx_probe_gi_destroy(pgi);
        vx_free(NULL, L);
    }
    free(lamp);
    vx_render_image_free(&ref), vx_render_image_free(&ref2);
    vx_frame_renderer_destroy(fr);
    vx_render_scene_destroy(rs);
    vx_gpu_destroy(gpu);
    vx_svo_scene_free(&s);
    return 0;
}
