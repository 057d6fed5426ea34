/* bench/bake_diff.c - a diagnostic, not a tool: bakes one small probe set of a scene several ways on the GPU
 * and lists the texels whose bytes differ (issue 18: svo_bake --load models against --load whole on the H200).
 *
 *   bake_diff FILE.svo [--grid X,Y,Z] [--res N] [--spp N] [--device NAME] [--max N] [--kernel inline|one]
 *             [--seed-m N]
 *
 * The bakes (vx_probe_bake_gpu, the same desc each time):
 *   P   the plain layout (vx_render_scene_create_ex PLAIN), the beam pass on (the default bake)
 *   Pn  the plain layout, no beam pass (vx_probe_bake_desc.no_beam)
 *   C   the compact layout made from the whole scene (create_ex COMPACT, bricks inline)
 *   M   the compact layout built from the model reader as svo_bake --load models builds it
 *       (vx_compact_build_reader with attr_regions, bricks inline; vx_render_scene_create_compact)
 * then per pair the differing bytes of every array, and for the first --max differing interior texels of
 * P against M: the probe, the texel, its centre direction, both bakes' distance codes, normals and
 * radiance, and the double-precision CPU caster's hit of the texel's centre ray (instance, cell, t,
 * normal, colour) with the margins that decide it: the gap between the ray's entry planes at the hit
 * (an edge or corner tie) and the distance code's distance from a rounding boundary. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench/bench_load.h"
#include "probes/probes.h"
#include "render/compact.h"
#include "render/render.h"
#include "render/trace.h"
#include "svo/svo.h"

static int usage(void) {
    fprintf(stderr, "usage: bake_diff FILE.svo [--grid X,Y,Z] [--res N] [--spp N] [--device NAME] [--max N] "
                    "[--kernel inline|one] [--seed-m N]\n");
    return 2;
}

static size_t bsq(uint32_t n) { return (size_t)(n + 2) * (n + 2); }

/* differing bytes between two arrays of n elements of size es */
static size_t diff_bytes(const void* a, const void* b, size_t n, size_t es) {
    const uint8_t *x = a, *y = b;
    size_t d = 0;
    for (size_t i = 0; i < n * es; i++) d += x[i] != y[i];
    return d;
}

static void compare(const char* an, const vx_probe_set* a, const char* bn, const vx_probe_set* b) {
    size_t np = a->count;
    size_t low = (size_t)(a->low_res + 2) * (a->low_res + 2);
    size_t dr = diff_bytes(a->radiance, b->radiance, bsq(a->res) * 3 * np, 2),
           dn = diff_bytes(a->normal, b->normal, bsq(a->res) * np, 4),
           dd = diff_bytes(a->distance, b->distance, bsq(a->res) * np, 2),
           dl = diff_bytes(a->low, b->low, low * np, 2),
           di = diff_bytes(a->irradiance, b->irradiance, bsq(VX_PROBE_IRR_RES) * 3 * np, 2),
           dm = diff_bytes(a->moments, b->moments, bsq(VX_PROBE_DIST_RES) * 2 * np, 4);
    /* interior texels whose distance code, normal or radiance differ */
    size_t tdist = 0, tnrm = 0, trad = 0;
    for (size_t p = 0; p < np; p++)
        for (uint32_t j = 0; j < a->res; j++)
            for (uint32_t i = 0; i < a->res; i++) {
                size_t t = p * bsq(a->res) + (size_t)(j + 1) * (a->res + 2) + i + 1;
                tdist += a->distance[t] != b->distance[t];
                tnrm += a->normal[t] != b->normal[t];
                trad += memcmp(a->radiance + 3 * t, b->radiance + 3 * t, 6) != 0;
            }
    printf("%s vs %s: bytes differ: radiance %zu, normal %zu, distance %zu, low %zu, irradiance %zu, moments %zu "
           "(total %zu); interior texels differing: distance %zu, normal %zu, radiance %zu\n",
           an, bn, dr, dn, dd, dl, di, dm, dr + dn + dd + dl + di + dm, tdist, tnrm, trad);
}

/* The CPU caster's hit of the centre ray of texel (i, j) from probe p, and its margins. */
static void cpu_hit(const vx_render_caster* c, const vx_svo_scene* s, const vx_probe_set* ps, uint32_t p, uint32_t i,
                    uint32_t j) {
    double d[3];
    vx_probe_texel_dir(ps->res, i, j, d);
    const double* o = ps->probes[p].pos;
    vx_render_ray_hit h;
    if (!vx_render_cast(c, o, d, ps->dist_max, false, &h)) {
        printf("      cpu: miss (dir %.9g %.9g %.9g)\n", d[0], d[1], d[2]);
        return;
    }
    /* the entry planes of the hit cell along each axis in the instance's grid frame: the largest is the hit's
     * face; the gap to the second says how near an edge the ray enters (0: a tie, the face decided by a rule) */
    const vx_svo_instance* in = &s->instances[h.instance];
    double gi[12];
    double tp[3] = {0};
    double wm[12];
    vx_svo_instance_world(s, in, wm);
    bool inv = vx__affine_inverse(wm, gi);
    if (inv) {
        double og[3], dg[3];
        for (int k = 0; k < 3; k++) {
            og[k] = gi[4 * k] * o[0] + gi[4 * k + 1] * o[1] + gi[4 * k + 2] * o[2] + gi[4 * k + 3];
            dg[k] = gi[4 * k] * d[0] + gi[4 * k + 1] * d[1] + gi[4 * k + 2] * d[2];
        }
        for (int k = 0; k < 3; k++) {
            double plane = dg[k] > 0 ? h.cell[k] : h.cell[k] + 1.0;
            /* grid t along dg equals world t along d (d unit, dg its image) */
            tp[k] = dg[k] != 0 ? (plane - og[k]) / dg[k] : -INFINITY;
        }
    }
    double m1 = fmax(tp[0], fmax(tp[1], tp[2]));
    double m2 = -INFINITY;
    for (int k = 0; k < 3; k++)
        if (tp[k] != m1) m2 = fmax(m2, tp[k]);
    double q = h.t / ps->dist_step;
    printf("      cpu: inst %u cell %u,%u,%u t %.9g normal %.3g,%.3g,%.3g rgba %08x palette %u; entry planes t "
           "%.9g %.9g %.9g (edge gap %.3g = %.3g of a cell); t/step %.6f (%.3g steps from a code boundary)\n",
           h.instance, h.cell[0], h.cell[1], h.cell[2], h.t, h.normal[0], h.normal[1], h.normal[2], h.rgba, h.palette,
           tp[0], tp[1], tp[2], m1 - m2, (m1 - m2) / h.cell_size, q, fabs(fabs(q - floor(q)) - 0.5));
}

static void list_texels(const char* an, const vx_probe_set* a, const char* bn, const vx_probe_set* b,
                        const vx_render_caster* c, const vx_svo_scene* s, unsigned max) {
    unsigned shown = 0;
    for (uint32_t p = 0; p < a->count && shown < max; p++)
        for (uint32_t j = 0; j < a->res && shown < max; j++)
            for (uint32_t i = 0; i < a->res && shown < max; i++) {
                size_t t = (size_t)p * bsq(a->res) + (size_t)(j + 1) * (a->res + 2) + i + 1;
                bool dd = a->distance[t] != b->distance[t], dn = a->normal[t] != b->normal[t],
                     dr = memcmp(a->radiance + 3 * t, b->radiance + 3 * t, 6) != 0;
                if (!dd && !dn && !dr) continue;
                shown++;
                double na[3], nb[3], dir[3];
                vx_probe_oct_unpack16(a->normal[t], na);
                vx_probe_oct_unpack16(b->normal[t], nb);
                vx_probe_texel_dir(a->res, i, j, dir);
                printf("  probe %u texel %u,%u dir %.6f,%.6f,%.6f:%s%s%s\n", p, i, j, dir[0], dir[1], dir[2],
                       dd ? " distance" : "", dn ? " normal" : "", dr ? " radiance" : "");
                printf("      %-3s dist %u (t %.9g) normal %.4f,%.4f,%.4f radiance %.5g %.5g %.5g\n", an,
                       a->distance[t], a->distance[t] * a->dist_step, na[0], na[1], na[2],
                       vx_probe_half_to_float(a->radiance[3 * t]), vx_probe_half_to_float(a->radiance[3 * t + 1]),
                       vx_probe_half_to_float(a->radiance[3 * t + 2]));
                printf("      %-3s dist %u (t %.9g) normal %.4f,%.4f,%.4f radiance %.5g %.5g %.5g\n", bn,
                       b->distance[t], b->distance[t] * b->dist_step, nb[0], nb[1], nb[2],
                       vx_probe_half_to_float(b->radiance[3 * t]), vx_probe_half_to_float(b->radiance[3 * t + 1]),
                       vx_probe_half_to_float(b->radiance[3 * t + 2]));
                if (c) cpu_hit(c, s, a, p, i, j);
            }
}

int main(int argc, char** argv) {
    vx_probe_bake_desc d = {.grid = {4, 4, 4}, .res = 16, .spp = 1, .bounces = 1, .threads = 4};
    const char* device = NULL;
    unsigned max = 40;
    uint64_t seed_m = 0; /* --seed-m: M baked with another seed (the listing's own check: it must find texels) */
    if (argc < 2) return usage();
    const char* path = argv[1];
    for (int i = 2; i < argc; i++) {
        const char* a = argv[i];
        if (i + 1 >= argc) return usage();
        if (!strcmp(a, "--grid")) {
            if (sscanf(argv[++i], "%u,%u,%u", &d.grid[0], &d.grid[1], &d.grid[2]) != 3) return usage();
        } else if (!strcmp(a, "--res")) d.res = (uint32_t)atoi(argv[++i]);
        else if (!strcmp(a, "--spp")) d.spp = (uint32_t)atoi(argv[++i]);
        else if (!strcmp(a, "--device")) device = argv[++i];
        else if (!strcmp(a, "--max")) max = (unsigned)atoi(argv[++i]);
        else if (!strcmp(a, "--seed-m")) seed_m = (uint64_t)atoll(argv[++i]);
        else if (!strcmp(a, "--kernel")) {
            i++;
            d.kernel = !strcmp(argv[i], "one") ? VX_PROBE_KERNEL_ONE_WALK : VX_PROBE_KERNEL_INLINE;
        } else return usage();
    }
    vx_error err = {0};
    vx_svo_scene s;
    if (bench_load(path, &s, &err)) return fprintf(stderr, "%s: %s\n", path, err.msg), 1;
    vx_gpu* gpu = NULL;
    if (vx_gpu_create(&(vx_gpu_desc){.device = device}, &gpu, &err))
        return fprintf(stderr, "GPU: %s\n", err.msg), 1;
    printf("device: %s; grid %u,%u,%u R=%u spp %u\n", vx_gpu_device_name(gpu), d.grid[0], d.grid[1], d.grid[2], d.res,
           d.spp);
    vx_render_scene *rp = NULL, *rc = NULL, *rm = NULL;
    if (vx_render_scene_create_ex(gpu, &s, &(vx_render_scene_desc){.layout = VX_RENDER_LAYOUT_PLAIN}, &rp, &err))
        return fprintf(stderr, "plain scene: %s\n", err.msg), 1;
    if (vx_render_scene_create_ex(gpu, &s,
                                  &(vx_render_scene_desc){.layout = VX_RENDER_LAYOUT_COMPACT,
                                                          .compact_bricks = VX_RENDER_BRICKS_INLINE},
                                  &rc, &err))
        return fprintf(stderr, "compact scene: %s\n", err.msg), 1;
    /* svo_bake's --load models (tools/svo_bake/main.c bake_job_models) */
    vx_svo_model_reader* rd = NULL;
    vx_compact_scene cs;
    if (vx_svo_reader_open(NULL, path, &rd, &err) ||
        vx_compact_build_reader(&(vx_compact_desc){.attr_regions = true, .bricks = VX_COMPACT_BRICKS_INLINE}, rd, &cs,
                                &err) ||
        vx_render_scene_create_compact(gpu, rd, &cs, 0, NULL, &rm, &err))
        return fprintf(stderr, "models scene: %s\n", err.msg), 1;
    vx_svo_reader_close(rd);
    vx_probe_set P, Pn, C, M;
    vx_probe_bake_desc dn = d;
    dn.no_beam = true;
    if (vx_probe_bake_gpu(rp, &s, &d, &P, &err) || vx_probe_bake_gpu(rp, &s, &dn, &Pn, &err) ||
        vx_probe_bake_gpu(rc, &s, &d, &C, &err) ||
        vx_probe_bake_gpu(rm, &s, &(vx_probe_bake_desc){.seed = seed_m ? seed_m : d.seed, .grid = {d.grid[0], d.grid[1], d.grid[2]}, .res = d.res,
                                                        .spp = d.spp, .bounces = d.bounces, .threads = d.threads, .kernel = d.kernel},
                          &M, &err))
        return fprintf(stderr, "bake: %s\n", err.msg), 1;
    compare("P", &P, "Pn", &Pn);
    compare("P", &P, "C", &C);
    compare("P", &P, "M", &M);
    compare("Pn", &Pn, "C", &C);
    compare("C", &C, "M", &M);
    vx_render_caster* caster = NULL;
    if (vx_render_caster_create(&s, NULL, &caster, &err)) fprintf(stderr, "caster: %s\n", err.msg), caster = NULL;
    printf("texels of P against M (first %u):\n", max);
    list_texels("P", &P, "M", &M, caster, &s, max);
    printf("texels of P against Pn (first %u):\n", max);
    list_texels("P", &P, "Pn", &Pn, caster, &s, max);
    vx_render_caster_destroy(caster);
    vx_probe_set_free(&P), vx_probe_set_free(&Pn), vx_probe_set_free(&C), vx_probe_set_free(&M);
    vx_render_scene_destroy(rp), vx_render_scene_destroy(rc), vx_render_scene_destroy(rm);
    vx_gpu_destroy(gpu);
    vx_svo_scene_free(&s);
    return 0;
}
