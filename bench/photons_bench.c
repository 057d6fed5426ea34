/* bench/photons_bench.c - photon mapping (photons/photons.h) on its own
 * scenes: GPU time of one pass split into tracing, the grids' build and the
 * gather per photon count, and the progressive estimate's error against
 * the path tracer's against time, next to the path tracer's own.
 *
 *   photons_bench [options] cornell|caustic|FILE.{vox,svo}
 *
 * cornell: the seed's scene in voxels (64^3: white floor, ceiling and back,
 * red and green side walls, open front, a glass and a metal sphere, a
 * 12 x 12 emissive ceiling panel); caustic: a glass sphere (IOR 1.5) over a
 * white floor under a 16 x 16 emissive panel. Both are MagicaVoxel scenes
 * with MATL records (--write DIR writes them as .vox for the other tools)
 * lit by their emissive voxels alone (no sun, a black sky: photons are not
 * spent on the outside), the path tracer with the same light. A FILE is lit
 * as gi_bench lights it (the bake defaults: sun and sky).
 *
 * Rows: "pass" per --photons count (median of --runs passes: trace, build
 * and gather ms, stored photons, build ms per million stored); "photons"
 * per progressive pass count 1, 4, 16, ... --max-passes (GPU ms, relMSE of
 * the indirect light against the reference); "pathtrace" per spp 1, 4, ...
 * --max-spp. The reference is the path tracer at --ref-spp (its noise: the
 * relMSE between two seeds, printed). Needs only libvulkan and libc.
 *
 * Options: --device N|NAME, --size WxH (320x240), --photons N[,N...]
 * (1000000), --radius R[,R...] (photons.h's default; each radius its
 * rows), --alpha A (photons.h's default), --runs N (3),
 * --max-passes N (16), --max-spp N (256), --ref-spp N (1024),
 * --step F (4: the factor between rows of the error curves),
 * --workgroup N[:B][,...] (the trace's workgroup sizes and batches,
 * vx_photon_desc's, timed in "pass" rows; the first is used for the
 * curves; 0: the defaults), --target E (0.01: each curve's
 * crossing of relMSE E, interpolated log-log between its rows, with and
 * without the reference's own noise, and the ratio of the times),
 * --final-gather N (also rows "photons+fg N": a final gather of N rays per
 * pixel and pass, up to 16 passes), --write DIR, --view EX,EY,EZ,TX,TY,TZ,FOV
 * (the generated scenes' camera: eye, target, vertical field of view in
 * degrees; world units, the scene's 64^3 centred on the origin).
 *
 * The reference's noise: its two halves (seeds apart) differ by a relMSE
 * of 2 v (v: one half's), their mean's own is v / 2 = apart / 4; an
 * estimate's relMSE against the mean is its own plus about that, so the
 * rows also give "corrected" = relMSE - apart / 4. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench/bench_load.h"
#include "bench/bench_stats.h"
#include "formats/vox.h"
#include "photons/photons.h"

enum { N = 64 };

typedef uint8_t (*cell_fn)(int x, int y, int z);

static bool in_sphere(int x, int y, int z, double cx, double cy, double cz, double r) {
    double dx = x + 0.5 - cx, dy = y + 0.5 - cy, dz = z + 0.5 - cz;
    return dx * dx + dy * dy + dz * dz <= r * r;
}
/* palette: 1 white, 2 red, 3 green, 4 emissive, 5 glass, 6 metal */
static uint8_t cornell_cell(int x, int y, int z) {
    if (z == N - 2 && x >= 26 && x < 38 && y >= 26 && y < 38) return 4;
    if (x == 0) return 2;
    if (x == N - 1) return 3;
    if (z == 0 || z == N - 1 || y == N - 1) return 1;
    if (in_sphere(x, y, z, 21, 40, 13, 12)) return 5;
    if (in_sphere(x, y, z, 43, 26, 13, 12)) return 6;
    return 0;
}
static uint8_t caustic_cell(int x, int y, int z) {
    if (z == 0) return 1;
    if (z == N - 4 && x >= 24 && x < 40 && y >= 24 && y < 40) return 4;
    return in_sphere(x, y, z, 32, 32, 22, 14) ? 5 : 0;
}

static void add_matl(vx_vox_scene* s, uint32_t id, const char* const* kv, int n) {
    size_t size = 0, at = 0;
    for (int i = 0; i < 2 * n; i++) size += strlen(kv[i]) + 1;
    vx_vox_material* m = &s->materials[s->material_count++];
    m->id = id, m->dict_size = (uint32_t)size, m->dict = malloc(size);
    for (int i = 0; i < 2 * n; i++) {
        memcpy(m->dict + at, kv[i], strlen(kv[i]) + 1);
        at += strlen(kv[i]) + 1;
    }
}

static int make_scene(const char* name, vx_vox_scene* s) {
    cell_fn cell = !strcmp(name, "cornell") ? cornell_cell : (!strcmp(name, "caustic") ? caustic_cell : NULL);
    if (!cell) return 1;
    memset(s, 0, sizeof *s);
    s->version = 200;
    s->model_count = 1, s->models = calloc(1, sizeof *s->models);
    s->instance_count = 1, s->instances = calloc(1, sizeof *s->instances);
    s->instances[0].rot[0] = s->instances[0].rot[4] = s->instances[0].rot[8] = 1;
    s->instances[0].t[0] = s->instances[0].t[1] = s->instances[0].t[2] = N / 2; /* .vox centres models */
    s->instances[0].layer = -1;
    vx_vox_model* m = &s->models[0];
    m->size[0] = m->size[1] = m->size[2] = N;
    m->xyzi = malloc((size_t)N * N * N * 4);
    for (int z = 0; z < N; z++)
        for (int y = 0; y < N; y++)
            for (int x = 0; x < N; x++) {
                uint8_t c = cell(x, y, z);
                if (!c) continue;
                uint8_t* v = m->xyzi + 4 * (size_t)m->voxel_count++;
                v[0] = (uint8_t)x, v[1] = (uint8_t)y, v[2] = (uint8_t)z, v[3] = c;
            }
    s->has_rgba = true;
    for (int i = 0; i < 256; i++) s->palette[i] = 0xFFBFBFBFu;
    s->palette[2] = 0xFF2020C0u, s->palette[3] = 0xFF20C020u, s->palette[4] = 0xFFFFFFFFu;
    s->palette[5] = 0xFFFFFFFFu, s->palette[6] = 0xFFC0C0C0u;
    s->materials = calloc(3, sizeof *s->materials);
    const char* emit[] = {"_type", "_emit", "_emit", "4", "_flux", "2"};
    const char* glass[] = {"_type", "_glass", "_ri", "1.5", "_rough", "0"};
    const char* metal[] = {"_type", "_metal", "_metal", "1", "_rough", "0.15"};
    add_matl(s, 4, emit, 3);
    add_matl(s, 5, glass, 3);
    add_matl(s, 6, metal, 3);
    s->frame_count = 1;
    return 0;
}

static double rel_mse(const vx_render_image* a, const vx_render_image* ref) {
    double se = 0, r2 = 0;
    for (size_t i = 0; i < (size_t)ref->width * ref->height; i++) {
        if (ref->pixels[4 * i + 3] == 0) continue;
        for (int c = 0; c < 3; c++) {
            double d = (double)a->pixels[4 * i + c] - ref->pixels[4 * i + c];
            se += d * d, r2 += (double)ref->pixels[4 * i + c] * ref->pixels[4 * i + c];
        }
    }
    return r2 > 0 ? se / r2 : 0;
}

/* The error's parts (where the photons' error comes from, issue 13's cornell
 * plateau): relMSE after an 8 x 8 box filter of both images (noise falls by
 * about 64 there, a bias stays), and the ratio of the images' sums (a bias
 * of the light as a whole: emission, power). */
static void error_parts(const vx_render_image* a, const vx_render_image* ref, double* filtered, double* ratio) {
    enum { B = 8 };
    double se = 0, r2 = 0, sa = 0, sr = 0;
    for (uint32_t ty = 0; ty + B <= ref->height; ty += B)
        for (uint32_t tx = 0; tx + B <= ref->width; tx += B) {
            double ma[3] = {0}, mr[3] = {0};
            for (uint32_t y = ty; y < ty + B; y++)
                for (uint32_t x = tx; x < tx + B; x++) {
                    size_t i = (size_t)y * ref->width + x;
                    for (int c = 0; c < 3; c++) ma[c] += a->pixels[4 * i + c], mr[c] += ref->pixels[4 * i + c];
                }
            for (int c = 0; c < 3; c++) {
                se += (ma[c] - mr[c]) * (ma[c] - mr[c]), r2 += mr[c] * mr[c];
                sa += ma[c], sr += mr[c];
            }
        }
    *filtered = r2 > 0 ? se / r2 : 0;
    *ratio = sr > 0 ? sa / sr : 0;
}

/* The tiles (the image cut into 16 x 9) that hold the largest shares of the
 * squared error, with their mean ratio to the reference: where the error sits. */
static void error_tiles(const char* what, const vx_render_image* a, const vx_render_image* ref) {
    enum { TX = 16, TY = 9, T = TX * TY };
    double se[T] = {0}, sa[T] = {0}, sr[T] = {0}, tot = 0;
    for (uint32_t y = 0; y < ref->height; y++)
        for (uint32_t x = 0; x < ref->width; x++) {
            size_t i = (size_t)y * ref->width + x;
            int t = (int)(y * TY / ref->height) * TX + (int)(x * TX / ref->width);
            for (int c = 0; c < 3; c++) {
                double d = (double)a->pixels[4 * i + c] - ref->pixels[4 * i + c];
                se[t] += d * d, tot += d * d, sa[t] += a->pixels[4 * i + c], sr[t] += ref->pixels[4 * i + c];
            }
        }
    printf("%s: the squared error's largest tiles of 16 x 9 (column, row: share, mean / reference's):", what);
    for (int k = 0; k < 6; k++) {
        int best = 0;
        for (int t = 1; t < T; t++)
            if (se[t] > se[best]) best = t;
        printf(" (%d,%d: %.3f, %.3f)", best % TX, best / TX, tot > 0 ? se[best] / tot : 0.0,
               sr[best] > 0 ? sa[best] / sr[best] : 0.0);
        se[best] = -1;
    }
    printf("\n");
}

/* Where a curve (times t, errors e, n rows, in order) first reaches target:
 * log-log interpolation between the rows around it; -1 when it never does. */
static double crossing(const double* t, const double* e, int n, double target) {
    for (int i = 0; i < n; i++) {
        if (!(e[i] <= target)) continue;
        if (i == 0 || !(e[i - 1] > 0) || !(e[i] > 0) || !(t[i - 1] > 0)) return t[i];
        double f = (log(target) - log(e[i - 1])) / (log(e[i]) - log(e[i - 1]));
        return exp(log(t[i - 1]) + f * (log(t[i]) - log(t[i - 1])));
    }
    return -1;
}

static void print_crossing(const char* name, const char* what, const double* t, const double* e, const double* ec, int n,
                           double target, double* out, double* outc) {
    *out = crossing(t, e, n, target), *outc = crossing(t, ec, n, target);
    printf("%s: %s reaches relMSE %g at %s%.4g ms (corrected for the reference's noise: %s%.4g ms)\n", name, what,
           target, *out < 0 ? "never, > " : "", *out < 0 ? t[n - 1] : *out, *outc < 0 ? "never, > " : "",
           *outc < 0 ? t[n - 1] : *outc);
}

static int usage(void) {
    fprintf(stderr, "usage: photons_bench [--device N|NAME] [--size WxH] [--photons N[,N..]] [--radius R[,R..]] [--runs N]\n"
                    "                     [--max-passes N] [--max-spp N] [--ref-spp N] [--step F] [--workgroup N[:B],..]\n"
                    "                     [--alpha A] [--target E] [--final-gather N] [--write DIR]\n"
                    "                     [--view EX,EY,EZ,TX,TY,TZ,FOV]\n"
                    "                     cornell|caustic|FILE.{vox,svo}\n");
    return 2;
}

/* FNV-1a over the image's bytes: two builds' images compared bit for bit in a log (the photon sums are
 * exact, so a change to how they are made must leave this unchanged) */
static uint64_t image_bits(const vx_render_image* im) {
    const unsigned char* b = (const unsigned char*)im->pixels;
    uint64_t h = UINT64_C(14695981039346656037);
    for (size_t i = 0; i < (size_t)im->width * im->height * 16; i++) h = (h ^ b[i]) * UINT64_C(1099511628211);
    return h;
}

int main(int argc, char** argv) {
    const char *device = NULL, *counts = "1000000", *write_dir = NULL, *groups = "0";
    vx_render_desc base = {.width = 320, .height = 240};
    const char* radii = "0";
    double alpha = 0, target = 0.01, view[7] = {0};
    unsigned step = 4, runs = 3, max_passes = 16, max_spp = 256, ref_spp = 1024, fg = 0;
    int i = 1;
    for (; i < argc && !strncmp(argv[i], "--", 2); i++) {
        const char* o = argv[i];
        if (i + 1 >= argc) return usage();
        const char* v = argv[++i];
        if (!strcmp(o, "--device")) device = v;
        else if (!strcmp(o, "--size")) {
            if (sscanf(v, "%ux%u", &base.width, &base.height) != 2) return usage();
        } else if (!strcmp(o, "--photons")) counts = v;
        else if (!strcmp(o, "--radius")) radii = v;
        else if (!strcmp(o, "--alpha")) alpha = atof(v);
        else if (!strcmp(o, "--runs")) runs = (unsigned)atoi(v);
        else if (!strcmp(o, "--max-passes")) max_passes = (unsigned)atoi(v);
        else if (!strcmp(o, "--max-spp")) max_spp = (unsigned)atoi(v);
        else if (!strcmp(o, "--ref-spp")) ref_spp = (unsigned)atoi(v);
        else if (!strcmp(o, "--write")) write_dir = v;
        else if (!strcmp(o, "--final-gather")) fg = (unsigned)atoi(v);
        else if (!strcmp(o, "--step")) step = (unsigned)atoi(v);
        else if (!strcmp(o, "--workgroup")) groups = v;
        else if (!strcmp(o, "--view")) {
            if (sscanf(v, "%lf,%lf,%lf,%lf,%lf,%lf,%lf", &view[0], &view[1], &view[2], &view[3], &view[4], &view[5],
                       &view[6]) != 7)
                return usage();
        }
        else if (!strcmp(o, "--target")) target = atof(v);
        else return usage();
    }
    if (i + 1 != argc || !runs || !ref_spp || step < 2 || !(target > 0)) return usage();
    const char* name = argv[i];
    vx_error err = {0};
    vx_svo_scene scene;
    bool own = false;
    vx_vox_scene vs;
    if (!make_scene(name, &vs)) {
        own = true;
        if (write_dir) {
            char path[1024];
            snprintf(path, sizeof path, "%s/%s.vox", write_dir, name);
            if (vx_vox_write_file(NULL, &vs, path, &err)) return fprintf(stderr, "%s: %s\n", path, err.msg), 1;
        }
        vx_result r = vx_conv_vox(NULL, &vs, &scene, NULL, &err);
        vx_vox_scene_free(&vs);
        if (r) return fprintf(stderr, "%s: %s\n", name, err.msg), 1;
        base.camera.set = true, base.camera.fov = 40, base.camera.up[2] = 1;
        double cornell[6] = {0, -88, 0, 0, 0, -2}, caustic[6] = {0, -62, 58, 0, 0, -28};
        const double* c = !strcmp(name, "cornell") ? cornell : caustic;
        memcpy(base.camera.eye, c, 24), memcpy(base.camera.target, c + 3, 24);
        if (view[6] > 0) memcpy(base.camera.eye, view, 24), memcpy(base.camera.target, view + 3, 24), base.camera.fov = view[6];
    } else if (bench_load(name, &scene, &err)) {
        return fprintf(stderr, "%s: %s\n", name, err.msg), 1;
    }
    vx_gpu* gpu;
    vx_render_scene* rs;
    if (vx_gpu_create(&(vx_gpu_desc){.device = device}, &gpu, &err) || vx_render_scene_create(gpu, &scene, &rs, &err))
        return fprintf(stderr, "GPU: %s\n", err.msg), 1;
    /* the generated scenes: their emissive voxels only (a set of no probes carries sun and sky) */
    vx_probe_set dark = {.light_dir = {0, 0, 1}, .bounces = 7};
    const vx_probe_set* light = own ? &dark : NULL;
    printf("device: %s; %s at %ux%u\n", vx_gpu_device_name(gpu), name, base.width, base.height);
    printf("| scene | row | photons or spp | passes | stored | trace ms | build ms | build ms / M stored | "
           "gather ms | total ms | relMSE indirect |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");

    /* the reference: two seeds of the path tracer's indirect light */
    vx_probe_gpu* pg;
    vx_render_image ref[2] = {{0}};
    if (vx_probe_gpu_create(rs, &scene, light, &pg, &err)) return fprintf(stderr, "GPU: %s\n", err.msg), 1;
    for (int k = 0; k < 2; k++) {
        vx_probe_render_desc d = {.base = &base, .mode = VX_PROBE_RENDER_PT_INDIRECT, .spp = ref_spp,
                                  .seed = 999 + (uint64_t)k, .pixel_centre = true};
        if (vx_probe_gpu_render(pg, &d, &ref[k], &err)) return fprintf(stderr, "reference: %s\n", err.msg), 1;
    }
    double noise = rel_mse(&ref[1], &ref[0]), mean_noise = noise / 4;
    for (size_t p = 0; p < (size_t)base.width * base.height * 4; p++)
        ref[0].pixels[p] = 0.5f * (ref[0].pixels[p] + ref[1].pixels[p]);
    printf("| %s | reference | 2 x %u | - | - | - | - | - | - | %.4g | %.4g (halves apart; the mean's own: %.4g) |\n",
           name, ref_spp, (ref[0].gpu_seconds + ref[1].gpu_seconds) * 1e3, noise, mean_noise);
    /* the path tracer at the pixel centres, as the photons' gather */
    enum { ROWS = 40 };
    double ct[ROWS], ce[ROWS], cc[ROWS], pt_at = -1, pt_atc = -1;
    int rows = 0;
    for (unsigned spp = 1; spp <= max_spp && rows < ROWS; spp *= step) {
        vx_render_image im = {0};
        vx_probe_render_desc d = {.base = &base, .mode = VX_PROBE_RENDER_PT_INDIRECT, .spp = spp, .seed = 5,
                                  .pixel_centre = true};
        if (vx_probe_gpu_render(pg, &d, &im, &err)) return fprintf(stderr, "pathtrace: %s\n", err.msg), 1;
        ct[rows] = im.gpu_seconds * 1e3, ce[rows] = rel_mse(&im, &ref[0]), cc[rows] = ce[rows] - mean_noise;
        double fe, ratio;
        error_parts(&im, &ref[0], &fe, &ratio);
        printf("| %s | pathtrace | %u | - | - | - | - | - | - | %.4g | %.4g (corrected %.4g; 8x8 %.4g; mean %.4f) |\n",
               name, spp, ct[rows], ce[rows], cc[rows], fe, ratio);
        if (spp * step > max_spp) error_tiles("pathtrace", &im, &ref[0]);
        fflush(stdout);
        rows++;
        vx_render_image_free(&im);
    }
    print_crossing(name, "pathtrace", ct, ce, cc, rows, target, &pt_at, &pt_atc);
    for (const char* c = counts; c && *c;) {
        uint32_t photons = (uint32_t)strtoul(c, NULL, 10);
        c = strchr(c, ',');
        if (c) c++;
        for (const char* rl = radii; rl && *rl;) {
            double radius = atof(rl);
            rl = strchr(rl, ',');
            if (rl) rl++;
            vx_gi_method gm;
            vx_photon_gi* ph;
            vx_photon_desc pd = {.photons = photons, .radius = radius, .alpha = alpha, .light_dir = {0, 0, 1}};
            vx_photon_stats st = {0};
            /* one pass, timed runs times, per workgroup size of the trace (the first one's object stays for the curves) */
            ph = NULL;
            for (const char* w = groups; w && *w;) {
                char* e;
                pd.workgroup = (uint32_t)strtoul(w, &e, 10);
                pd.batch = *e == ':' ? (uint32_t)strtoul(e + 1, NULL, 10) : 0;
                w = strchr(w, ',');
                if (w) w++;
                if (ph) vx_photon_gi_destroy(ph);
                if (vx_photon_gi_create(rs, &scene, light, &pd, &gm, &ph, &err))
                    return fprintf(stderr, "photons: %s\n", err.msg), 1;
                double t[7][64];
                unsigned n = runs < 64 ? runs : 64;
                for (unsigned k = 0; k < n; k++) {
                    vx_render_image im = {0};
                    if (vx_photon_render(ph, &base, 1, false, &im, &err)) return fprintf(stderr, "photons: %s\n", err.msg), 1;
                    vx_render_image_free(&im);
                    vx_photon_last_stats(ph, &st);
                    t[0][k] = st.trace_ms, t[1][k] = st.build_ms, t[2][k] = st.gather_ms;
                    t[3][k] = st.paths_ms, t[4][k] = st.density_ms, t[5][k] = st.wall_ms;
                    t[6][k] = st.trace_ms + st.build_ms + st.gather_ms;
                }
                double tr = bench_median(t[0], n), bu = bench_median(t[1], n), ga = bench_median(t[2], n);
                vx_photon_desc D = vx_photon_desc_defaults();
                char bt[16];
                snprintf(bt, sizeof bt, pd.batch ? "%u" : "auto", pd.batch);
                printf("| %s | pass wg %u batch %s | %u | 1 | %llu | %.3f | %.3f | %.3f | %.3f | %.3f (trace + build %.3f) | - |\n",
                       name, pd.workgroup ? pd.workgroup : D.workgroup, bt, photons, (unsigned long long)st.stored, tr, bu,
                       st.stored ? bu / (st.stored * 1e-6) : 0.0, ga, tr + bu + ga, tr + bu);
                double lo = t[6][0], least[5];
                for (unsigned k = 1; k < n; k++) lo = fmin(lo, t[6][k]);
                /* each step's least over the runs: what a shared GPU (other work in some runs) leaves readable */
                for (int j = 0; j < 5; j++) {
                    least[j] = t[j][0];
                    for (unsigned k = 1; k < n; k++) least[j] = fmin(least[j], t[j][k]);
                }
                printf("%s: the gather's steps: camera paths %.3f ms%s, density %.3f ms; the pass on the host (submissions, "
                       "waits, downloads) %.3f ms (medians); GPU ms per pass (the steps' sum in each run): median %.3f, "
                       "least %.3f\n",
                       name, bench_median(t[3], n), st.fused ? " (run beside the trace: in its ms)" : "",
                       bench_median(t[4], n), bench_median(t[5], n), bench_median(t[6], n), lo);
                printf("%s: each step's least over the %u runs: trace %.3f, grid %.3f, gather %.3f (camera paths %.3f, "
                       "density %.3f) ms\n",
                       name, n, least[0], least[1], least[2], least[3], least[4]);
                fflush(stdout);
                if (w && *w) continue;
                /* the curves with the first size */
                if (groups != w && strchr(groups, ',')) {
                    char* e;
                    pd.workgroup = (uint32_t)strtoul(groups, &e, 10);
                    pd.batch = *e == ':' ? (uint32_t)strtoul(e + 1, NULL, 10) : 0;
                    vx_photon_gi_destroy(ph);
                    if (vx_photon_gi_create(rs, &scene, light, &pd, &gm, &ph, &err))
                        return fprintf(stderr, "photons: %s\n", err.msg), 1;
                }
                break;
            }
            rows = 0;
            for (unsigned passes = 1; passes <= max_passes && rows < ROWS; passes *= step) {
                vx_render_image im = {0};
                if (vx_photon_render(ph, &base, passes, false, &im, &err)) return fprintf(stderr, "photons: %s\n", err.msg), 1;
                vx_photon_last_stats(ph, &st);
                ct[rows] = im.gpu_seconds * 1e3, ce[rows] = rel_mse(&im, &ref[0]), cc[rows] = ce[rows] - mean_noise;
                double fe, ratio;
                error_parts(&im, &ref[0], &fe, &ratio);
                printf("| %s | photons r %.4g | %u | %u | %llu | - | - | - | - | %.4g | %.4g (corrected %.4g; 8x8 %.4g; mean %.4f; "
                       "bits %016llx) |\n",
                       name, st.radius, photons, passes, (unsigned long long)st.stored, ct[rows], ce[rows], cc[rows], fe, ratio,
                       (unsigned long long)image_bits(&im));
                if (passes * step > max_passes) error_tiles("photons", &im, &ref[0]);
                fflush(stdout);
                rows++;
                vx_render_image_free(&im);
            }
            double at, atc;
            char what[64];
            snprintf(what, sizeof what, "photons %u per pass", photons);
            print_crossing(name, what, ct, ce, cc, rows, target, &at, &atc);
            if (at > 0 && pt_at > 0) printf("%s: %s / pathtrace time at relMSE %g: %.4g\n", name, what, target, at / pt_at);
            if (atc > 0 && pt_atc > 0)
                printf("%s: %s / pathtrace time at relMSE %g (corrected): %.4g\n", name, what, target, atc / pt_atc);
            vx_photon_gi_destroy(ph);
            if (!fg) continue;
            pd.final_gather = fg;
            if (vx_photon_gi_create(rs, &scene, light, &pd, &gm, &ph, &err)) return fprintf(stderr, "photons: %s\n", err.msg), 1;
            for (unsigned passes = 1; passes <= max_passes && passes <= 16; passes *= step) {
                vx_render_image im = {0};
                if (vx_photon_render(ph, &base, passes, false, &im, &err)) return fprintf(stderr, "photons: %s\n", err.msg), 1;
                vx_photon_last_stats(ph, &st);
                double fe, ratio;
                error_parts(&im, &ref[0], &fe, &ratio);
                printf("| %s | photons+fg %u | %u | %u | %llu | - | - | - | %.3f | %.4g | %.4g (8x8 %.4g; mean %.4f) |\n", name,
                       fg, photons, passes, (unsigned long long)st.stored, st.gather_ms, im.gpu_seconds * 1e3,
                       rel_mse(&im, &ref[0]), fe, ratio);
                fflush(stdout);
                vx_render_image_free(&im);
            }
            vx_photon_gi_destroy(ph);
        }
    }
    vx_render_image_free(&ref[0]);
    vx_render_image_free(&ref[1]);
    vx_probe_gpu_destroy(pg);
    vx_render_scene_destroy(rs);
    vx_gpu_destroy(gpu);
    vx_svo_scene_free(&scene);
    return 0;
}
