/* probes/probe_gpu.c - the GPU bake and the GPU probe renderer on the Vulkan
 * tracer (probes/shaders/probe.comp). The GPU path-traces the texels (or
 * pixels). A baked batch is filtered (quantised distances and normals,
 * radiance halfs, min-distance, irradiance and moment maps) on the GPU
 * (probes/shaders/probe_filter.comp), which reads back only the maps the
 * .probes file stores while it traces the next batch; with host_filter the
 * host filters it with the CPU bake's own code (vx__probe_finish), the
 * reference the GPU filtering is tested against. */
#define _POSIX_C_SOURCE 200809L /* nanosleep */
#include <math.h>
#include <pthread.h>
#include <string.h>
#include <time.h>

#include "probes/probes_internal.h"
#include "render/gpu.h"

#include "probe.comp.h"     /* shaders/probe.comp, embedded at build time */
#include "probe_pt.comp.h"  /* the same, -DPT_PRECISE: the render passes' kernel */
#include "probe_one.comp.h" /* the same, -DVX_ONE_WALK: the bake's one-walk kernel (bake_one()) */
#include "probe_out.comp.h" /* shaders/probe_out.comp */
#include "probe_filter.comp.h" /* shaders/probe_filter.comp */
#include "probe_beam.comp.h"   /* shaders/probe_beam.comp */

/* std430 block "Params" of probe.comp */
typedef struct gpu_params {
    float light[4], sun[4], sky[4];
    uint32_t a[4];    /* res|width, spp, bounces, first probe|height */
    uint32_t seed[4]; /* lo, hi, probes in this dispatch */
    uint32_t grid[4]; /* xyz, probe count */
    float origin[4];  /* xyz relative to the reference, w: dist_max */
    float spacing[4]; /* xyz, w: minimum */
    uint32_t lf[4];   /* light field: res, low res, words per probe */
    float lf_lo[4];   /* scene bounds relative to the reference, w: distance step */
    float lf_hi[4];
    uint32_t cnt[4]; /* lights, emissive voxels, pixel centres only, a light stands for emissive voxels */
    float pt[4];     /* total emitted power of the emissive voxels */
    float skyh[4];   /* sky by direction: horizon rgb, w: 0 uniform (sky), 1 gradient (sky: zenith), 2 map */
    float skyg[4];   /* ground rgb, w: map intensity */
    float skym[4];   /* map: rotation, width, height */
    uint32_t rw[4];  /* render: rows in the row table (0: all), samples per block, first block, blocks per round */
    uint32_t rk[4];  /* render: 0 trace / 1 add the blocks, 1 in a round's first dispatch */
    float smo[4];    /* the sun's depth map: origin relative to the reference, margin (vx__sun_map) */
    uint32_t smn[4]; /* its side, its instance entries */
} gpu_params;
_Static_assert(sizeof(gpu_params) == 320, "gpu_params vs probe.comp");

/* 0-16, then 17-19 the sun's depth map (render/shaders/smap_lookup.glsl) */
enum { NBIND = 20 };

enum { PMODE_BAKE = 0 };

/* probe.comp's constants after the tracer's (constant_id VX__SPEC_COUNT + i): BEAM (trace_common.glsl: the
 * bake's texel blocks' side, 0: no beam pass), MATS, PCONST (the pass, and LIGHTS << 8), and
 * trace_common.glsl's DEEP (0: the plain loop, as before) and FAR (off where no model can hold a far
 * pointer: the far bit's test on every push costs, issue 21) and COMPACT_FORM (the scene in the compact layout:
 * vx__render_scene_compact_form) */
/* SMAP (id 11, smap_lookup.glsl): the bake's sun rays clipped by the sun's depth map */
enum { SPEC_BEAM, SPEC_MATS, SPEC_PCONST, SPEC_DEEP, SPEC_FAR, SPEC_COMPACT, SPEC_SMAP, SPEC_EXTRA };

/* The bake's beam blocks (probe_beam.comp): BAKE_BEAM x BAKE_BEAM texels share a start distance for the
 * rays from their probe (res is a multiple of 16, so blocks never cross the map's axes). */
enum { BAKE_BEAM = 4 };

/* Samples per pixel in one dispatch on a CPU device (llvmpipe's loop limit,
 * probe.comp): fewer than 256 fit on the Cornell box with 2 bounces. */
enum { CPU_DEVICE_CHUNK = 32 };

/* The render's samples per block (probe.comp's render()): part of the
 * estimator, so the same for every device and split; up to one block a
 * pixel's value is its plain running sum. A round traces at most
 * RENDER_ROUND_BLOCKS blocks of every pixel, with at most RENDER_ROUND_BYTES
 * of their state: short invocations, enough of them to fill a GPU many times
 * over at any share of a 1080p image (16,384 spp at 1080p: 32 rounds of 8
 * blocks on one GPU, 16 of 16 on half the rows); the rounds never change the
 * result. */
enum { RENDER_BLOCK = 64, RENDER_ROUND_BLOCKS = 16 };
#define RENDER_ROUND_BYTES ((size_t)512 << 20)

typedef struct gctx {
    vx_gpu* g;
    const vx_allocator* alloc;
    vx__frame f;
    vx__buffer* scene[7];
    uint32_t spec[VX__SPEC_COUNT + SPEC_EXTRA]; /* the tracer's, then probe.comp's (SPEC_*) */
    uint32_t bounces; /* the bake's bounces plus one (probe.comp's BAKE_BOUNCES; 0: not a constant) */
    bool lights_code; /* probe.comp's LIGHTS: lights of binding 14 or emitters */
    bool glass_code;  /* probe.comp's GLASS (the render passes only): some record is glass that transmits */
    bool metal_code;  /* probe.comp's METAL (the render passes only): some record is metal */
    bool strat;       /* probe.comp's STRAT (the bake only): stratified first-bounce directions */
    vx_probe_bake_kernel kernel; /* the caller's choice (vx_probe_bake_desc.kernel) */
    bool use_one;     /* the bake runs bake_one() (choose_kernel) */
    vx__buffer params, emit, probes, out, maps, lf, mats, lights, ems, env;
    uint32_t light_count, em_count;
    bool voxel_lights;
    float em_power;
    const vx__buffer *maps_in, *lf_in; /* a vx_probe_gpu's maps, else maps and lf */
    vx__sun_map sun; /* the sun's depth map (the bake's sun rays), sun.map NULL: none */
} gctx;

static void ctx_free(gctx* c) {
    vx__buffer* b[] = {&c->params, &c->emit, &c->probes, &c->out, &c->maps, &c->lf, &c->mats, &c->lights, &c->ems,
                       &c->env};
    for (size_t i = 0; i < sizeof b / sizeof b[0]; i++) vx__buffer_destroy(c->g, b[i]);
}

static vx_result upload_to(vx_gpu* g, vx__buffer* b, const void* data, size_t size, const char* label, vx_error* err) {
    vx_result r = vx__buffer_create(g, size, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, label, b, err);
    if (!r && data) r = vx__buffer_upload(g, b, data, size, err);
    return r;
}
static vx_result upload_new(gctx* c, vx__buffer* b, const void* data, size_t size, const char* label, vx_error* err) {
    return upload_to(c->g, b, data, size, label, err);
}

void vx__pack_materials(const vx__light* L, const uint16_t* ids, size_t n, float* out) {
    for (size_t i = 0; i < n; i++) {
        const vx_material* mt = vx__light_material(L, ids[i]);
        float* o = out + 8 * i;
        o[0] = mt->type == VX_MATERIAL_METAL ? 1.0f : (mt->type == VX_MATERIAL_GLASS ? 2.0f : 0.0f);
        o[1] = (float)(mt->roughness * mt->roughness);
        o[2] = (float)mt->metalness, o[3] = (float)mt->specular;
        o[4] = (float)mt->ior, o[5] = (float)mt->transmission;
    }
}

/* The path tracer's tables (probe.comp bindings 13-15): materials per
 * attribute record only when some material is metal or glass, the lights
 * and the emissive voxels relative to the frame's reference point; each a
 * 16-byte placeholder when the scene has none. */
static vx_result upload_path_tracer(gctx* c, const vx__light* L, const uint16_t* ids, size_t na, vx_error* err) {
    const double* ref = c->f.ref;
    size_t nm = L->materials ? na : 0, nl = 0, ne = L->em_count;
    for (uint32_t i = 0; i < L->light_count; i++) nl += !(L->lights[i].flags & VX_LIGHT_FROM_VOXELS);
    float* m = vx_calloc(c->alloc, nm ? 8 * nm : 4, sizeof(float));
    float* l = vx_calloc(c->alloc, nl ? 20 * nl : 4, sizeof(float));
    float* e = vx_calloc(c->alloc, ne ? 20 * ne : 4, sizeof(float));
    vx_result r = VX_OK;
    if (!m || !l || !e) {
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for the path tracer's tables");
        goto done;
    }
    vx__pack_materials(L, ids, nm, m);
    for (size_t i = 0, j = 0; j < L->light_count; j++) {
        const vx_light* li = &L->lights[j];
        if (li->flags & VX_LIGHT_FROM_VOXELS) continue; /* the voxels emit themselves (pathtrace.c) */
        float* o = l + 20 * i++;
        double n[3], t[3], dl = 0, tn = 0, tl = 0;
        for (int k = 0; k < 3; k++) dl += li->direction[k] * li->direction[k];
        dl = sqrt(dl);
        for (int k = 0; k < 3; k++) n[k] = dl > 0 ? li->direction[k] / dl : 0, tn += li->tangent[k] * n[k];
        for (int k = 0; k < 3; k++) t[k] = li->tangent[k] - tn * n[k], tl += t[k] * t[k];
        tl = sqrt(tl);
        for (int k = 0; k < 3; k++) {
            o[k] = (float)(li->position[k] - ref[k]);
            o[4 + k] = (float)n[k];
            o[8 + k] = (float)(li->color[k] * li->intensity);
            o[16 + k] = tl > 0 ? (float)(t[k] / tl) : 0.0f;
        }
        o[3] = (float)li->type, o[7] = (float)li->range, o[11] = (float)li->radius;
        double ci = cos(li->inner_cone), co = cos(li->outer_cone), sc = 1.0 / fmax(0.001, ci - co);
        o[12] = (float)sc, o[13] = (float)(-co * sc), o[14] = (float)li->angular_diameter, o[15] = (float)li->size[0];
        o[19] = (float)li->size[1];
    }
    for (size_t i = 0; i < ne; i++) {
        const vx__emitter* em = &L->em[i];
        float* o = e + 20 * i;
        for (int k = 0; k < 3; k++) {
            o[k] = (float)(em->corner[k] - ref[k]);
            for (int a = 0; a < 3; a++) o[4 * (a + 1) + k] = (float)em->axis[a][k];
            o[16 + k] = (float)em->rad[k];
        }
        o[3] = (float)em->area, o[7] = (float)L->em_cdf[i];
    }
    /* binding 16: the environment map's texels (RGB floats), only for a map sky */
    const vx_sky_texels* t = &L->sky_map;
    bool map = L->sky_dir.type == VX_SKY_ENVMAP && t->rgb;
    if ((r = upload_new(c, &c->mats, m, nm ? 32 * nm : 16, "probe materials", err)) ||
        (r = upload_new(c, &c->lights, l, nl ? 80 * nl : 16, "probe lights", err)) ||
        (r = upload_new(c, &c->ems, e, ne ? 80 * ne : 16, "probe emitters", err)) ||
        (r = upload_new(c, &c->env, map ? t->rgb : NULL, map ? (size_t)t->width * t->height * 12 : 16, "probe sky map", err)))
        goto done;
    c->light_count = (uint32_t)nl, c->em_count = (uint32_t)ne, c->em_power = (float)L->em_power;
    c->voxel_lights = L->voxel_lights;
done:
    vx_free(c->alloc, m);
    vx_free(c->alloc, l);
    vx_free(c->alloc, e);
    return r;
}

/* Binds the scene relative to f->ref and uploads the emission per attribute
 * record and the probe positions (ps may be NULL). */
static vx_result ctx_init(gctx* c, vx_render_scene* rs, const vx_svo_scene* s, const vx__frame* f,
                          const vx_probe_set* ps, const vx__light* L, vx_error* err) {
    memset(c, 0, sizeof *c);
    c->g = vx__render_scene_gpu(rs);
    c->alloc = ps ? ps->alloc : NULL;
    c->f = *f;
    vx_result r = vx__render_scene_bind(rs, f, c->scene, c->spec, err);
    if (r) return r;
    uint16_t* pal = NULL; /* material ids per record */
    size_t na = 0;
    if ((r = vx__render_scene_attr_material(rs, s, c->alloc, &pal, &na, err))) return r;
    c->spec[VX__SPEC_COUNT + SPEC_MATS] = L->materials;
    if ((r = upload_path_tracer(c, L, pal, na, err))) {
        vx_free(c->alloc, pal);
        return r;
    }
    c->lights_code = c->light_count > 0 || c->em_count > 0;
    c->glass_code = L->inst_inv != NULL; /* (the walks' instance maps: made where some glass transmits) */
    for (size_t i = 0; i < na && L->materials && !c->metal_code; i++)
        c->metal_code = vx__light_material(L, pal[i])->type == VX_MATERIAL_METAL;
    c->spec[VX__SPEC_COUNT + SPEC_DEEP] = vx__render_scene_deep(rs);
    c->spec[VX__SPEC_COUNT + SPEC_FAR] = vx__render_scene_far(rs);
    c->spec[VX__SPEC_COUNT + SPEC_COMPACT] = vx__render_scene_compact_form(rs);
    float* em = NULL; /* the emission table: one zero record where nothing emits */
    size_t ne = 0;
    r = vx_svo_material_table_emission_records(&L->mt, pal, na, c->alloc, &em, &ne, err);
    size_t np = ps ? ps->probe_count : 1;
    float* pp = vx_calloc(c->alloc, np, 4 * sizeof(float));
    if (!r && !pp) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    if (!r) {
        for (size_t i = 0; ps && i < np; i++) {
            for (int k = 0; k < 3; k++) pp[4 * i + k] = (float)(ps->probes[i].pos[k] - f->ref[k]);
            pp[4 * i + 3] = (float)ps->probes[i].state;
        }
        if (!(r = upload_new(c, &c->emit, em, (ne ? ne : 1) * 4 * sizeof(float), "probe emission", err)))
            r = upload_new(c, &c->probes, pp, np * 4 * sizeof(float), "probe positions", err);
        /* the light field maps: a placeholder unless a light field mode replaces it */
        if (!r) r = upload_new(c, &c->lf, NULL, 16, "probe light field", err);
        if (!r)
            r = vx__buffer_create(c->g, sizeof(gpu_params), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true, "probe params",
                                  &c->params, err);
        if (!r && !c->params.map) r = vx_fail(err, VX_ERR_GPU, VX_NO_OFFSET, "probe parameters are not host visible");
    }
    vx_free(c->alloc, pal);
    vx_free(c->alloc, em);
    vx_free(c->alloc, pp);
    return r;
}

static void params_common(gpu_params* p, const vx__light* L, uint64_t seed) {
    memset(p, 0, sizeof *p);
    for (int k = 0; k < 3; k++) {
        p->light[k] = (float)L->light_dir[k];
        p->sun[k] = (float)L->sun[k];
    }
    /* render/shaders/sky.glsl's parameters, packed as the pass pipeline packs them */
    float sk[16];
    vx__sky_pack(&L->sky_dir, &L->sky_map, L->sky, sk);
    memcpy(p->sky, sk, sizeof p->sky), memcpy(p->skyh, sk + 4, sizeof p->skyh);
    memcpy(p->skyg, sk + 8, sizeof p->skyg), memcpy(p->skym, sk + 12, sizeof p->skym);
    p->seed[0] = (uint32_t)seed, p->seed[1] = (uint32_t)(seed >> 32);
}

static void params_path(gpu_params* p, const gctx* c) {
    p->cnt[0] = c->light_count, p->cnt[1] = c->em_count, p->cnt[3] = c->voxel_lights;
    p->pt[0] = c->em_power;
    memcpy(p->smo, c->sun.origin, sizeof p->smo);
    p->smn[0] = c->sun.side, p->smn[1] = c->sun.insts;
}

/* Bindings 17-19: the sun's depth map, else placeholders (SMAP off). */
static void sun_bindings(gctx* c, vx__buffer** b) {
    b[0] = c->sun.map ? c->sun.map : &c->env;
    b[1] = c->sun.map ? c->sun.nodes : &c->env;
    b[2] = c->sun.map ? c->sun.insts_buf : &c->env;
}

/* ctx_sun_map makes a map (SMAP on, unless its build fails) */
static bool sun_map_wanted(const vx__light* L, bool allow) {
    float lf[3] = {(float)L->light_dir[0], (float)L->light_dir[1], (float)L->light_dir[2]};
    bool sun = L->sun[0] > 0 || L->sun[1] > 0 || L->sun[2] > 0;
    return allow && sun && fabsf(lf[0]) + fabsf(lf[1]) + fabsf(lf[2]) > 0;
}

/* The bake's sun rays clipped by the scene's sun depth map (render/gpu.h),
 * built for the light as probe.comp has it, where there is a sun: the same
 * bytes (tests/probes: cmp), fewer steps. allow false: the whole rays. */
static vx_result ctx_sun_map(gctx* c, vx_render_scene* rs, const vx__light* L, bool allow, vx_probe_bake_stats* st,
                             vx_error* err) {
    /* 4096 texels a side at most (the render's frames: 2048): a finer map decides more sun rays without a walk
     * (H200, the Cornell box's goal bake: GPU trace 0.386 s at 512, 0.336 at 1024, 0.270 at 2048) */
    memset(&c->sun, 0, sizeof c->sun);
    c->spec[VX__SPEC_COUNT + SPEC_SMAP] = 0;
    if (!sun_map_wanted(L, allow)) return VX_OK;
    float lf[3] = {(float)L->light_dir[0], (float)L->light_dir[1], (float)L->light_dir[2]};
    double t0 = vx_time_now();
    vx_result r = vx__render_scene_sun_map(rs, lf, c->f.ref, VX_PROBE_SUN_MAP_SIDE, &c->sun, err);
    if (st) {
        vx_render_shadow_map_info mi;
        vx_render_scene_shadow_map_info(rs, &mi);
        st->sun_map = vx_time_now() - t0, st->sun_map_side = c->sun.map ? c->sun.side : 0;
        st->sun_map_nodes = mi.nodes, st->sun_map_list = mi.list_seconds, st->sun_map_gpu = mi.build_gpu_seconds;
        st->sun_map_ahead = mi.ahead_seconds, st->sun_map_build = mi.build_seconds;
    }
    if (r) memset(&c->sun, 0, sizeof c->sun);
    c->spec[VX__SPEC_COUNT + SPEC_SMAP] = !r && c->sun.map;
    return r;
}

static void params_grid(gpu_params* p, const vx_probe_set* ps, const double ref[3]) {
    double smin = fmin(ps->spacing[0], fmin(ps->spacing[1], ps->spacing[2]));
    for (int k = 0; k < 3; k++) {
        p->grid[k] = ps->grid[k];
        p->origin[k] = (float)(ps->origin[k] - ref[k]);
        p->spacing[k] = (float)ps->spacing[k];
    }
    p->grid[3] = ps->probe_count;
    p->origin[3] = (float)ps->dist_max;
    p->spacing[3] = (float)smin;
}

/* Whether probe.comp's one-walk build (bake_one(): every ray at the one trace_scene call of a loop) may run
 * the bake: the scene has no lights or sampled emitters and no metal or glass (LIGHTS and MATS off; else
 * nee's light rays and the glass walks need bake()). Both give the same bytes (test_probes_gpu). */
static bool one_walk_ok(const gctx* c) {
    return c->kernel != VX_PROBE_KERNEL_INLINE && !c->lights_code && !c->spec[VX__SPEC_COUNT + SPEC_MATS];
}

/* probe.comp's pipeline for pass pmode (the bake: bake_one() where one, else bake()): its desc and key (sets
 * c->spec's PCONST). */
static uint64_t probe_desc(gctx* c, uint32_t pmode, bool one, vx_gpu_compute_pipeline_desc* pd) {
    c->spec[VX__SPEC_COUNT + SPEC_PCONST] =
        pmode | (c->lights_code ? 0x100u : 0u) | (c->strat && pmode == PMODE_BAKE ? 0x200u : 0u) |
        (c->glass_code && pmode != PMODE_BAKE ? 0x400u : 0u) | (c->metal_code && pmode != PMODE_BAKE ? 0x800u : 0u) |
        (pmode == PMODE_BAKE ? c->bounces << 16 : 0u);
    /* the bake's kernels (bake(), bake_one()) and the render passes' (PT_PRECISE: render()); every float
     * operation of each precise (probe.comp: the same bits whatever the pipeline's constants) */
    bool bake = pmode == PMODE_BAKE;
    const uint32_t* code = bake ? vx__probe_spv_arr : vx__probe_pt_spv_arr;
    size_t code_size = bake ? sizeof vx__probe_spv_arr : sizeof vx__probe_pt_spv_arr;
    one = one && bake;
    if (one) code = vx__probe_one_spv_arr, code_size = sizeof vx__probe_one_spv_arr;
    *pd = (vx_gpu_compute_pipeline_desc){.spirv = code, .spirv_size = code_size, .binding_count = NBIND,
                                         .spec_count = VX__SPEC_COUNT + SPEC_EXTRA, .label = "probe"};
    pd->bindings[0] = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    for (uint32_t i = 1; i < NBIND; i++) pd->bindings[i] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    memcpy(pd->spec, c->spec, sizeof c->spec);
    return vx__spec_key(0x9B0BE2ull + (bake ? (one ? 2 : 0) : 1), c->spec, VX__SPEC_COUNT + SPEC_EXTRA);
}

/* probe.comp's pipeline for pass pmode (created once per device and spec constants). */
static vx_result pipeline_of(gctx* c, uint32_t pmode, vx__pipeline** out, vx_error* err) {
    vx_gpu_compute_pipeline_desc pd;
    uint64_t key = probe_desc(c, pmode, c->use_one, &pd);
    return vx__pipeline_get(c->g, key, &pd, out, err);
}

/* Which bake kernel runs (c->use_one), both being made ahead (vx_probe_baker_create): bake_one() where the
 * caller asks for it, and with VX_PROBE_KERNEL_AUTO where the driver has it ready and bake() still not
 * KERNEL_GRACE seconds later. A hit of the driver's shader cache takes it 0.0001-0.003 s (H200), a compile
 * 0.3 s (bake_one()) and 0.66-0.89 s (bake()); bake() traces faster (0.254 s against 0.359 s, Cornell box),
 * so it runs wherever its compile is not the wait: on every process after a machine's first, whose bake()
 * compile, left running, the driver's cache keeps. The wait polls: it ends within 0.3 s. */
enum { KERNEL_POLL_NS = 250000 };
#define KERNEL_GRACE 0.02
static void choose_kernel(gctx* c) {
    c->use_one = false;
    if (!one_walk_ok(c)) return;
    if (c->kernel == VX_PROBE_KERNEL_ONE_WALK) {
        c->use_one = true;
        return;
    }
    vx_gpu_compute_pipeline_desc pd;
    uint64_t kb = probe_desc(c, PMODE_BAKE, false, &pd), kn = probe_desc(c, PMODE_BAKE, true, &pd);
    double t_one = -1;
    for (;;) {
        int b = vx__pipeline_state(c->g, kb), n = vx__pipeline_state(c->g, kn);
        /* bake() ready, or nothing to race (not made ahead: another sun map than predicted) */
        if (b != VX__PIPE_PENDING || n == VX__PIPE_NONE) return;
        if (n == VX__PIPE_READY) {
            double now = vx_time_now();
            if (t_one < 0) t_one = now;
            else if (now - t_one >= KERNEL_GRACE) {
                c->use_one = true;
                return;
            }
        }
        nanosleep(&(struct timespec){0, KERNEL_POLL_NS}, NULL);
    }
}

static vx_result run(gctx* c, uint32_t pmode, uint32_t gx, uint32_t gy, double* seconds, vx_error* err) {
    vx__pipeline* p;
    vx_result r = pipeline_of(c, pmode, &p, err);
    if (r) return r;
    vx__dispatch_desc dd = {.pipeline = p, .buffer_count = NBIND, .groups = {gx, gy, 1}, .label = "probe"};
    for (int i = 0; i < 7; i++) dd.buffers[i] = c->scene[i];
    dd.buffers[7] = &c->params, dd.buffers[8] = &c->emit, dd.buffers[9] = &c->probes, dd.buffers[10] = &c->out;
    dd.buffers[11] = (vx__buffer*)(c->maps_in ? c->maps_in : &c->maps);
    dd.buffers[12] = (vx__buffer*)(c->lf_in ? c->lf_in : &c->lf);
    dd.buffers[13] = &c->mats, dd.buffers[14] = &c->lights, dd.buffers[15] = &c->ems, dd.buffers[16] = &c->env;
    sun_bindings(c, &dd.buffers[17]);
    return vx__dispatch(c->g, &dd, seconds, err);
}

/* Runs pass pmode (bake or render in probe.comp) over samples 0..spp-1 in as
 * many dispatches as the device needs: llvmpipe ends every loop of a SIMD
 * group after 65535 iterations in all, silently (see probe.comp); each
 * dispatch checks that, and one the limit cut is repeated with half the
 * samples. The result does not depend on the split: every texel or pixel adds
 * its samples to its running sum in sample order, whatever the dispatches.
 * c->out starts with the flags. */
/* chunk_io: the samples per dispatch to start with (0: the device's), and
 * on return the chunk that worked; resume: a bake whose state is written
 * already (the GPU-filtered bake's batch after its own dispatches). */
static vx_result run_samples_ex(gctx* c, uint32_t pmode, uint32_t gx, uint32_t gy, uint32_t spp, uint32_t* chunk_io,
                                bool resume, double* seconds, vx_error* err) {
    gpu_params* p = c->params.map;
    uint32_t chunk = chunk_io && *chunk_io ? *chunk_io : (vx_gpu_is_cpu(c->g) ? CPU_DEVICE_CHUNK : spp);
    p->lf[3] = 2; /* loops_intact() */
    if (seconds) *seconds = 0;
    for (uint32_t runs = 0;; runs++) {
        if (chunk_io) *chunk_io = chunk;
        /* each dispatch either advances every unfinished texel or pixel or halves the chunk */
        if (runs > spp + 32)
            return vx_fail(err, VX_ERR_GPU, VX_NO_OFFSET, "probe pass: samples still missing after %u dispatches", runs);
        /* the first dispatch writes the texels' or the blocks' state */
        if (pmode == PMODE_BAKE) p->lf[0] = runs == 0 && !resume;
        else p->rk[1] = runs == 0;
        p->seed[3] = chunk < spp ? chunk : spp;
        float flags[4] = {0};
        double t = 0;
        vx_result r = vx__buffer_upload(c->g, &c->out, flags, sizeof flags, err);
        if (r || (r = run(c, pmode, gx, gy, &t, err)) ||
            (r = vx__buffer_download(c->g, &c->out, flags, sizeof flags, err)))
            return r;
        if (seconds) *seconds += t;
        if (flags[0] != 0) {
            if (chunk == 1)
                return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "one sample exceeds the loop limit of %s",
                               vx_gpu_device_name(c->g));
            chunk /= 2;
        }
        if (flags[1] == 0) return VX_OK;
    }
}

static vx_result run_samples(gctx* c, uint32_t pmode, uint32_t gx, uint32_t gy, uint32_t spp, double* seconds,
                             vx_error* err) {
    return run_samples_ex(c, pmode, gx, gy, spp, NULL, false, seconds, err);
}

/* ---- bake --------------------------------------------------------------------------- */

typedef struct fjob {
    vx_probe_set* ps;
    const vx__tables* T;
    const float* raw; /* per slot res^2 * 12 floats (probe.comp's Out after the flags) */
    uint32_t spp;
    uint32_t first_slot, count, next;
    bool failed;
    pthread_mutex_t mu;
} fjob;

static void finish_one(fjob* J, uint32_t i, double* L, double* D) {
    vx_probe_set* ps = J->ps;
    uint32_t k = J->first_slot + i, n = ps->res;
    if (ps->probes[ps->first + k].state == VX_PROBE_DISABLED) return; /* stays zero, as the CPU bake */
    size_t nt = (size_t)n * n, nb = n + 2;
    uint16_t* dist = ps->distance + vx__bsq(n) * k;
    uint32_t* nrm = ps->normal + vx__bsq(n) * k;
    const float* o = J->raw + (size_t)i * nt * 12;
    for (size_t t = 0; t < nt; t++) {
        const float* v = o + 12 * t;
        size_t b = (t / n + 1) * nb + t % n + 1;
        for (int q = 0; q < 3; q++) L[3 * t + q] = v[q] / (float)J->spp;
        if (v[3] >= 0 && v[7] > 0) {
            double nn[3] = {v[4], v[5], v[6]};
            dist[b] = vx__dist_code(ps, v[3]);
            nrm[b] = vx_probe_oct_pack16(nn);
            D[t] = dist[b] * ps->dist_step;
        } else {
            dist[b] = VX_PROBE_DIST_MISS;
            nrm[b] = 0;
            D[t] = ps->dist_max;
        }
    }
    vx__probe_finish(ps, J->T, k, L, D);
}

static void* fworker(void* arg) {
    fjob* J = arg;
    size_t nt = (size_t)J->ps->res * J->ps->res;
    double* L = vx_alloc(J->ps->alloc, nt * 4 * sizeof(double));
    pthread_mutex_lock(&J->mu);
    if (!L) J->failed = true;
    while (!J->failed && J->next < J->count) {
        uint32_t i = J->next++;
        pthread_mutex_unlock(&J->mu);
        finish_one(J, i, L, L + 3 * nt);
        pthread_mutex_lock(&J->mu);
    }
    pthread_mutex_unlock(&J->mu);
    vx_free(J->ps->alloc, L);
    return NULL;
}

static bool finish_batch(vx_probe_set* ps, const vx__tables* T, const float* raw, uint32_t first_slot, uint32_t count,
                         uint32_t threads) {
    fjob J = {.ps = ps, .T = T, .raw = raw, .spp = ps->spp ? ps->spp : 1, .first_slot = first_slot, .count = count};
    pthread_mutex_init(&J.mu, NULL);
    vx_run_threads(threads < count ? threads : (count ? count : 1), fworker, &J);
    pthread_mutex_destroy(&J.mu);
    return !J.failed;
}

/* ---- the bake with the filtering on the GPU ----------------------------------------- */

/* Push constants of probe_filter.comp */
typedef struct fpush {
    uint32_t stage, res, spp, first, count, per, low, small, o_nrm, o_dist, o_low, o_irr, o_mom;
    float step_hi, step_lo, dist_max;
} fpush;

/* Words of one probe's maps as probe_filter.comp packs them (the .probes
 * file's block, each map padded to whole words). */
typedef struct flayout {
    size_t nb, lb;                                    /* bordered texels: full and low-resolution maps */
    uint32_t o_nrm, o_dist, o_low, o_irr, o_mom, per; /* word offsets; per: words per probe */
    uint32_t small;                                   /* Small floats per probe */
} flayout;

static flayout layout_of(const vx_probe_set* ps) {
    flayout l;
    l.nb = vx__bsq(ps->res), l.lb = vx__bsq(ps->low_res);
    l.o_nrm = (uint32_t)(l.nb * 3 / 2); /* res even: (res+2)^2 even */
    l.o_dist = l.o_nrm + (uint32_t)l.nb;
    l.o_low = l.o_dist + (uint32_t)(l.nb / 2);
    l.o_irr = l.o_low + (uint32_t)((l.lb + 1) / 2);
    l.o_mom = l.o_irr + (uint32_t)(vx__bsq(VX_PROBE_IRR_RES) * 3 / 2);
    l.per = l.o_mom + (uint32_t)(vx__bsq(VX_PROBE_DIST_RES) * 2);
    l.small = 3 * VX_PROBE_IRR_RES * VX_PROBE_IRR_RES + 2 * VX_PROBE_DIST_RES * VX_PROBE_DIST_RES +
              ps->low_res * ps->low_res;
    return l;
}

/* One batch in flight: its own parameters, trace output, filter scratch,
 * packed maps and host-visible copy, so the next batch runs while the host
 * stores this one. */
typedef struct bslot {
    vx__buffer params, out, texl, small, packed, back, beam;
    VkCommandBuffer cmd;
    VkFence fence;
    VkDescriptorSet trace_set, filter_set, beam_set;
    uint32_t at, cnt;
    uint32_t cap; /* probes its buffers hold */
    bool made;    /* slot_init done */
} bslot;

typedef struct gbake {
    gctx* c;
    vx_probe_set* ps;
    vx__pipeline *trace, *filter, *beam; /* beam: NULL without the beam pass */
    vx__buffer tables;
    VkCommandPool pool;
    VkDescriptorPool dpool;
    VkQueryPool queries; /* 4 per slot: start, traced, filtered, copied */
    bslot slot[2];
    flayout lay;
    uint32_t batch, chunk, nt, res;
    uint32_t first; /* probes of the first slot's buffers at first (the first batch; 0: batch) */
    uint64_t ts_first, ts_last; /* the run's first batch's start and the last waited batch's end (ticks) */
    double pipes;   /* seconds gbake_init spent making the filter and beam pipelines */
    double slots_s; /* seconds gbake_init spent making the two slots' buffers and sets */
} gbake;

/* A slot's buffers (made by slot_buffers), for the places that destroy or hand them on. */
enum { SLOT_BUFFERS = 7 };
static void slot_buffer_list(bslot* s, vx__buffer* b[SLOT_BUFFERS]) {
    b[0] = &s->params, b[1] = &s->out, b[2] = &s->texl, b[3] = &s->small, b[4] = &s->packed, b[5] = &s->back,
    b[6] = &s->beam;
}

static void slot_buffers_destroy(vx_gpu* g, bslot* s) {
    vx__buffer* b[SLOT_BUFFERS];
    slot_buffer_list(s, b);
    for (int k = 0; k < SLOT_BUFFERS; k++) vx__buffer_destroy(g, b[k]);
}

static void gbake_free(gbake* B) {
    vx_gpu* g = B->c->g;
    for (int i = 0; i < 2; i++) {
        bslot* s = &B->slot[i];
        slot_buffers_destroy(g, s);
        if (s->fence) vkDestroyFence(g->device, s->fence, NULL);
    }
    vx__buffer_destroy(g, &B->tables);
    if (B->queries) vkDestroyQueryPool(g->device, B->queries, NULL);
    if (B->dpool) vkDestroyDescriptorPool(g->device, B->dpool, NULL);
    if (B->pool) vkDestroyCommandPool(g->device, B->pool, NULL); /* frees the command buffers */
}

/* The buffers of a slot whose last batch is stored, released on a thread while the GPU runs the bake's last
 * batch: their memory (about 0.19 GB at 128 probes of R=128) no longer waits for the teardown after the loop.
 * The command buffer, fence and descriptor sets stay: the pools go with the baker. */
typedef struct slot_release {
    vx_gpu* g;
    vx__buffer b[SLOT_BUFFERS];
} slot_release;

static void* slot_release_main(void* arg) {
    slot_release* a = arg;
    for (int k = 0; k < SLOT_BUFFERS; k++) vx__buffer_destroy(a->g, &a->b[k]);
    return NULL;
}

static void write_set(vx_gpu* g, VkDescriptorSet set, const vx__pipeline* p, vx__buffer* const* bufs, uint32_t n) {
    VkDescriptorBufferInfo info[VX_GPU_MAX_BINDINGS];
    VkWriteDescriptorSet w[VX_GPU_MAX_BINDINGS];
    for (uint32_t i = 0; i < n; i++) {
        info[i] = (VkDescriptorBufferInfo){.buffer = bufs[i]->buf, .range = VK_WHOLE_SIZE};
        w[i] = (VkWriteDescriptorSet){.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, .dstSet = set, .dstBinding = i,
                                      .descriptorCount = 1, .descriptorType = p->bindings[i], .pBufferInfo = &info[i]};
    }
    vkUpdateDescriptorSets(g->device, n, w, 0, NULL);
}

/* Slot i's buffers, command buffer, fence and descriptor sets. The second slot is made after the first
 * batch is submitted (bake_gpu_filtered), while the GPU traces: 0.01 s of the 0.023 s the two took on an H200
 * (Cornell box, batches of 128 probes at R=128) off the time before the first batch. */
static void slot_write_sets(gbake* B, bslot* s);

/* Slot s's buffers for cap probes (the sets written to them where the slot is made). */
static vx_result slot_buffers(gbake* B, bslot* s, uint32_t cap, vx_error* err) {
    gctx* c = B->c;
    vx_gpu* g = c->g;
    const flayout* L = &B->lay;
    uint64_t nt = B->nt, batch = cap;
    uint32_t beam = c->spec[VX__SPEC_COUNT + SPEC_BEAM], nblk = beam ? (B->res / beam) * (B->res / beam) : 1;
    vx_result r;
    s->cap = cap;
    if ((r = vx__buffer_create(g, sizeof(gpu_params), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true, "bake params",
                               &s->params, err)) ||
        (r = vx__buffer_create(g, 16 + batch * nt * 48, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, "probe texels",
                               &s->out, err)) ||
        (r = vx__buffer_create(g, batch * nt * 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, "bake filter texels",
                               &s->texl, err)) ||
        (r = vx__buffer_create(g, (VkDeviceSize)batch * L->small * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false,
                               "bake filter sums", &s->small, err)) ||
        (r = vx__buffer_create(g, (VkDeviceSize)batch * L->per * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false,
                               "bake maps", &s->packed, err)) ||
        (r = vx__buffer_create(g, 16 + (VkDeviceSize)batch * L->per * 4, 0, true, "bake readback", &s->back, err)) ||
        (r = vx__buffer_create(g, (VkDeviceSize)batch * nblk * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false,
                               "bake beam", &s->beam, err)))
        return r;
    if (!s->params.map || !s->back.map)
        return vx_fail(err, VX_ERR_GPU, VX_NO_OFFSET, "no host-visible memory for the bake's parameters and results");
    if (s->made) slot_write_sets(B, s);
    return VX_OK;
}

/* Slot i's buffers for cap probes, command buffer, fence and descriptor sets. */
static vx_result slot_init(gbake* B, int i, uint32_t cap, vx_error* err) {
    vx_gpu* g = B->c->g;
    double ts = vx_time_now();
    bslot* s = &B->slot[i];
    vx_result r = slot_buffers(B, s, cap, err);
    if (r) return r;
    VkCommandBufferAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
                                      .commandPool = B->pool, .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
                                      .commandBufferCount = 1};
    VX__VK(vkAllocateCommandBuffers(g->device, &ai, &s->cmd), "vkAllocateCommandBuffers");
    VkFenceCreateInfo fi = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VX__VK(vkCreateFence(g->device, &fi, NULL, &s->fence), "vkCreateFence");
    VkDescriptorSetLayout dsl[3] = {B->trace->dsl, B->filter->dsl, B->beam ? B->beam->dsl : VK_NULL_HANDLE};
    VkDescriptorSet sets[3];
    VkDescriptorSetAllocateInfo si = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO,
                                      .descriptorPool = B->dpool, .descriptorSetCount = B->beam ? 3 : 2,
                                      .pSetLayouts = dsl};
    VX__VK(vkAllocateDescriptorSets(g->device, &si, sets), "vkAllocateDescriptorSets");
    s->trace_set = sets[0], s->filter_set = sets[1], s->beam_set = B->beam ? sets[2] : VK_NULL_HANDLE;
    slot_write_sets(B, s);
    s->made = true;
    B->slots_s += vx_time_now() - ts;
    return VX_OK;
}

static void slot_write_sets(gbake* B, bslot* s) {
    gctx* c = B->c;
    vx_gpu* g = c->g;
    vx__buffer* tb[NBIND];
    for (int k = 0; k < 7; k++) tb[k] = c->scene[k];
    tb[7] = &s->params, tb[8] = &c->emit, tb[9] = &c->probes, tb[10] = &s->out, tb[11] = B->beam ? &s->beam : &c->maps;
    tb[12] = &c->lf, tb[13] = &c->mats, tb[14] = &c->lights, tb[15] = &c->ems, tb[16] = &c->env;
    sun_bindings(c, &tb[17]);
    write_set(g, s->trace_set, B->trace, tb, NBIND);
    vx__buffer* fb[6] = {&c->probes, &s->out, &B->tables, &s->texl, &s->small, &s->packed};
    write_set(g, s->filter_set, B->filter, fb, 6);
    if (B->beam) {
        vx__buffer* bb[11];
        for (int k = 0; k < 7; k++) bb[k] = c->scene[k];
        bb[7] = bb[8] = bb[9] = &c->probes, bb[10] = &s->beam; /* 7, 8: unused */
        write_set(g, s->beam_set, B->beam, bb, 11);
    }
}

/* Slot s's buffers again for cap probes (its last batch done and stored): the small first slot grown
 * while the GPU runs the next batch. */
static vx_result slot_grow(gbake* B, bslot* s, uint32_t cap, vx_error* err) {
    double ts = vx_time_now();
    slot_buffers_destroy(B->c->g, s);
    vx_result r = slot_buffers(B, s, cap, err);
    B->slots_s += vx_time_now() - ts;
    return r;
}

/* probe_filter.comp's pipeline: its desc and key */
static uint64_t filter_desc(vx_gpu_compute_pipeline_desc* fd) {
    *fd = (vx_gpu_compute_pipeline_desc){.spirv = vx__probe_filter_spv_arr, .spirv_size = sizeof vx__probe_filter_spv_arr,
                                         .binding_count = 6, .push_constant_size = sizeof(fpush), .label = "probe filter"};
    for (int i = 0; i < 6; i++) fd->bindings[i] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    return 0x9B0BF1u;
}

/* probe_beam.comp's pipeline: the scene (0-6; 7 and 8 unused), the probes (9), the start distances (10) */
static uint64_t beam_desc(const gctx* c, vx_gpu_compute_pipeline_desc* bd) {
    *bd = (vx_gpu_compute_pipeline_desc){.spirv = vx__probe_beam_spv_arr, .spirv_size = sizeof vx__probe_beam_spv_arr,
                                         .binding_count = 11, .spec_count = VX__SPEC_COUNT + SPEC_EXTRA,
                                         .push_constant_size = 16, .label = "probe beam"};
    bd->bindings[0] = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    for (uint32_t i = 1; i < 11; i++) bd->bindings[i] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    memcpy(bd->spec, c->spec, sizeof c->spec);
    return vx__spec_key(0x9B0BEAull, c->spec, VX__SPEC_COUNT + SPEC_EXTRA);
}

static vx_result gbake_init(gbake* B, gctx* c, const vx_probe_set* ps, uint32_t batch, uint32_t first,
                            vx_error* err) {
    vx_gpu* g = c->g;
    B->c = c, B->ps = NULL /* the run's */, B->batch = batch, B->first = first, B->lay = layout_of(ps);
    B->nt = ps->res * ps->res, B->res = ps->res;
    vx_result r = pipeline_of(c, PMODE_BAKE, &B->trace, err);
    if (r) return r;
    double tp = vx_time_now();
    vx_gpu_compute_pipeline_desc fd;
    if ((r = vx__pipeline_get(g, filter_desc(&fd), &fd, &B->filter, err))) return r;
    if (c->spec[VX__SPEC_COUNT + SPEC_BEAM]) {
        vx_gpu_compute_pipeline_desc bd;
        if ((r = vx__pipeline_get(g, beam_desc(c, &bd), &bd, &B->beam, err))) return r;
    }
    B->pipes = vx_time_now() - tp;
    /* texel directions and solid angles, then the irradiance and moment texel directions (double -> float) */
    vx__tables T;
    size_t nrow = B->nt + VX_PROBE_IRR_RES * VX_PROBE_IRR_RES + VX_PROBE_DIST_RES * VX_PROBE_DIST_RES;
    float* tab = vx_calloc(ps->alloc, nrow, 4 * sizeof(float));
    bool ok = vx__tables_make(&T, ps->res, ps->alloc) && tab;
    if (ok) {
        for (size_t t = 0; t < B->nt; t++) {
            for (int k = 0; k < 3; k++) tab[4 * t + k] = (float)T.dir[3 * t + k];
            tab[4 * t + 3] = (float)T.omega[t];
        }
        for (size_t q = 0; q < VX_PROBE_IRR_RES * VX_PROBE_IRR_RES; q++)
            for (int k = 0; k < 3; k++) tab[4 * (B->nt + q) + k] = (float)T.irr_dir[q][k];
        for (size_t q = 0; q < VX_PROBE_DIST_RES * VX_PROBE_DIST_RES; q++)
            for (int k = 0; k < 3; k++)
                tab[4 * (B->nt + VX_PROBE_IRR_RES * VX_PROBE_IRR_RES + q) + k] = (float)T.mom_dir[q][k];
    }
    vx__tables_free(&T);
    if (!ok) {
        vx_free(ps->alloc, tab);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for the filter tables at res %u", ps->res);
    }
    r = upload_to(g, &B->tables, tab, nrow * 4 * sizeof(float), "probe filter tables", err);
    vx_free(ps->alloc, tab);
    if (r) return r;
    VkCommandPoolCreateInfo cpi = {.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
                                   .flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT,
                                   .queueFamilyIndex = g->queue_family};
    VX__VK(vkCreateCommandPool(g->device, &cpi, NULL, &B->pool), "vkCreateCommandPool");
    VkDescriptorPoolSize sizes[2] = {{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 6 * VX_GPU_MAX_BINDINGS},
                                     {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 6}};
    VkDescriptorPoolCreateInfo dpi = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO, .maxSets = 6,
                                      .poolSizeCount = 2, .pPoolSizes = sizes};
    VX__VK(vkCreateDescriptorPool(g->device, &dpi, NULL, &B->dpool), "vkCreateDescriptorPool");
    if (g->has_timestamps) {
        VkQueryPoolCreateInfo qi = {.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO,
                                    .queryType = VK_QUERY_TYPE_TIMESTAMP, .queryCount = 8};
        VX__VK(vkCreateQueryPool(g->device, &qi, NULL, &B->queries), "vkCreateQueryPool");
    }
    return slot_init(B, 0, B->first && B->first < batch ? B->first : batch, err);
}

static void barrier(VkCommandBuffer cmd, VkPipelineStageFlags src, VkAccessFlags sa, VkPipelineStageFlags dst,
                    VkAccessFlags da) {
    VkMemoryBarrier mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER, .srcAccessMask = sa, .dstAccessMask = da};
    vkCmdPipelineBarrier(cmd, src, dst, 0, 1, &mb, 0, NULL, 0, NULL);
}

#define CS VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT
#define XF VK_PIPELINE_STAGE_TRANSFER_BIT
#define SW VK_ACCESS_SHADER_WRITE_BIT
#define SR VK_ACCESS_SHADER_READ_BIT
#define TW VK_ACCESS_TRANSFER_WRITE_BIT

/* Records and submits batch s->at .. +cnt: `traces` path-tracing dispatches
 * of `chunk` samples (0: only the filtering, after run_samples_ex finished
 * the samples), the three filter stages and the copy of the flags and maps
 * into host-visible memory. Does not wait. */
static vx_result gbake_submit(gbake* B, bslot* s, uint32_t traces, vx_error* err) {
    vx_gpu* g = B->c->g;
    const vx_probe_set* ps = B->ps;
    const flayout* L = &B->lay;
    VkCommandBuffer cmd = s->cmd;
    uint32_t qi = (uint32_t)(s - B->slot) * 4;
    VX__VK(vkResetCommandBuffer(cmd, 0), "vkResetCommandBuffer");
    VkCommandBufferBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
                                   .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};
    VX__VK(vkBeginCommandBuffer(cmd, &bi), "vkBeginCommandBuffer");
    if (B->queries) {
        vkCmdResetQueryPool(cmd, B->queries, qi, 4);
        vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, B->queries, qi);
    }
    VkDeviceSize raw = 16 + (VkDeviceSize)s->cnt * B->nt * 48;
    if (B->beam && traces) {
        /* the texel blocks' start distances, read by every trace dispatch */
        uint32_t blk = B->c->spec[VX__SPEC_COUNT + SPEC_BEAM], nb = ps->res / blk;
        uint32_t pc[4] = {ps->res, blk, s->at, s->cnt};
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, B->beam->pipe);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, B->beam->layout, 0, 1, &s->beam_set, 0, NULL);
        vkCmdPushConstants(cmd, B->beam->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof pc, pc);
        vkCmdDispatch(cmd, (nb * nb + 7) / 8, (s->cnt + 7) / 8, 1);
        barrier(cmd, CS, SW, CS, SR);
    }
    for (uint32_t k = 0; k < traces; k++) {
        /* a zero state (no samples yet) before the first; fresh flags before each */
        vkCmdFillBuffer(cmd, s->out.buf, 0, k == 0 ? raw : 16, 0);
        barrier(cmd, XF, TW, CS, SR | SW);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, B->trace->pipe);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, B->trace->layout, 0, 1, &s->trace_set, 0, NULL);
        vkCmdDispatch(cmd, (B->nt + 63) / 64, s->cnt, 1);
        barrier(cmd, CS, SW, CS | XF, SR | SW | TW);
    }
    if (B->queries) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, B->queries, qi + 1);
    double step = ps->dist_step;
    fpush pc = {.res = ps->res, .spp = ps->spp ? ps->spp : 1, .first = s->at, .count = s->cnt, .per = L->per,
                .low = ps->low_res, .small = L->small, .o_nrm = L->o_nrm, .o_dist = L->o_dist, .o_low = L->o_low,
                .o_irr = L->o_irr, .o_mom = L->o_mom, .step_hi = (float)step, .dist_max = (float)ps->dist_max};
    pc.step_lo = (float)(step - (double)pc.step_hi);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, B->filter->pipe);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, B->filter->layout, 0, 1, &s->filter_set, 0, NULL);
    uint32_t groups[3][2] = {{(uint32_t)((L->nb / 2 + 255) / 256), s->cnt},
                             {VX_PROBE_IRR_RES * VX_PROBE_IRR_RES + VX_PROBE_DIST_RES * VX_PROBE_DIST_RES +
                                  ps->low_res * ps->low_res,
                              s->cnt},
                             {1, s->cnt}};
    for (uint32_t st = 0; st < 3; st++) {
        pc.stage = st;
        vkCmdPushConstants(cmd, B->filter->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof pc, &pc);
        vkCmdDispatch(cmd, groups[st][0], groups[st][1], 1);
        barrier(cmd, CS, SW, CS | XF, SR | VK_ACCESS_TRANSFER_READ_BIT);
    }
    if (B->queries) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, B->queries, qi + 2);
    VkBufferCopy cp[2] = {{.size = 16}, {.dstOffset = 16, .size = (VkDeviceSize)s->cnt * L->per * 4}};
    vkCmdCopyBuffer(cmd, s->out.buf, s->back.buf, 1, &cp[0]);
    vkCmdCopyBuffer(cmd, s->packed.buf, s->back.buf, 1, &cp[1]);
    barrier(cmd, XF, TW, VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
    if (B->queries) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, B->queries, qi + 3);
    VX__VK(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
    VX__VK(vkResetFences(g->device, 1, &s->fence), "vkResetFences");
    VkSubmitInfo si = {.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO, .commandBufferCount = 1, .pCommandBuffers = &cmd};
    VX__VK(vkQueueSubmit(g->queue, 1, &si, s->fence), "vkQueueSubmit");
    return VX_OK;
}

static vx_result gbake_wait(gbake* B, bslot* s, vx_probe_bake_stats* st, uint64_t ts[4], vx_error* err) {
    vx_gpu* g = B->c->g;
    double t = vx_time_now();
    VX__VK(vkWaitForFences(g->device, 1, &s->fence, VK_TRUE, UINT64_C(600) * 1000000000u), "vkWaitForFences");
    st->wait += vx_time_now() - t;
    if (B->queries) {
        VX__VK(vkGetQueryPoolResults(g->device, B->queries, (uint32_t)(s - B->slot) * 4, 4, 4 * sizeof(uint64_t), ts,
                                     sizeof(uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
               "vkGetQueryPoolResults");
        double per = g->props.limits.timestampPeriod * 1e-9;
        st->gpu_trace += (double)(ts[1] - ts[0]) * per;
        st->gpu_filter += (double)(ts[2] - ts[1]) * per;
        st->gpu_copy += (double)(ts[3] - ts[2]) * per;
        /* each batch's GPU intervals for -v ("probe.batch"): where the GPU waited between batches */
        if (!B->ts_first) B->ts_first = ts[0], B->ts_last = ts[0];
        vx_log(g->logger, VX_LOG_INFO, "probe.batch",
               "probes %u..%u: GPU from %.4f s: trace %.4f s, filter %.4f s, copy %.4f s; idle %.4f s before", s->at,
               s->at + s->cnt, (double)(ts[0] - B->ts_first) * per, (double)(ts[1] - ts[0]) * per,
               (double)(ts[2] - ts[1]) * per, (double)(ts[3] - ts[2]) * per,
               ts[0] > B->ts_last ? (double)(ts[0] - B->ts_last) * per : 0.0);
        B->ts_last = ts[3];
    }
    return VX_OK;
}

/* Stores a finished batch's maps into ps (what the file stores, word-padded). */
static void gbake_store(gbake* B, const bslot* s) {
    vx_probe_set* ps = B->ps;
    const flayout* L = &B->lay;
    size_t ni = vx__bsq(VX_PROBE_IRR_RES) * 3, nm = vx__bsq(VX_PROBE_DIST_RES) * 2;
    const uint32_t* w = (const uint32_t*)s->back.map + 4;
    for (uint32_t i = 0; i < s->cnt; i++, w += L->per) {
        size_t k = s->at - ps->first + i;
        memcpy(ps->radiance + L->nb * 3 * k, w, L->nb * 3 * 2);
        memcpy(ps->normal + L->nb * k, w + L->o_nrm, L->nb * 4);
        memcpy(ps->distance + L->nb * k, w + L->o_dist, L->nb * 2);
        memcpy(ps->low + L->lb * k, w + L->o_low, L->lb * 2);
        memcpy(ps->irradiance + ni * k, w + L->o_irr, ni * 2);
        memcpy(ps->moments + nm * k, w + L->o_mom, nm * 4);
    }
}

/* Batches of B->batch probes through two slots: while the host stores batch
 * i - 1, the GPU traces and filters batch i. */
static vx_result bake_gpu_filtered(gbake* Bp, vx_probe_set* ps, const vx__light* L, const vx__frame* f,
                                   uint32_t begin, uint32_t end, const vx_progress* progress, vx_probe_bake_stats* st,
                                   vx_error* err) {
    gbake B = *Bp; /* copied back at the end: the chunk a CPU device needs */
    gctx* c = B.c;
    B.ps = ps;
    uint32_t batch = B.batch;
    vx_result r = VX_OK;
    /* full batches, then the last quarter batch on its own: what is left after the GPU's last batch (the
     * host storing its maps, the caller writing them) is short */
    uint32_t n = end - begin, tail = batch >= 8 && n > batch ? batch / 4 : 0;
    /* a first batch as small as the first slot (its buffers made before the first batch, the full slot's
     * later beside the GPU), at most a quarter batch */
    uint32_t head = B.slot[0].cap < batch && tail && B.slot[0].cap <= batch / 4 ? B.slot[0].cap : 0;
    uint32_t body = n - tail - head;
    uint32_t spp = ps->spp ? ps->spp : 1, nbody = (body + batch - 1) / batch;
    uint32_t nbatch = (head ? 1 : 0) + nbody + (tail ? 1 : 0), done = 0;
    uint64_t (*ts)[4] = vx_calloc(ps->alloc, nbatch, sizeof *ts);
    if (!ts) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    double t1 = vx_time_now();
    uint32_t submitted = 0;
    B.ts_first = 0;
    /* the run that bakes the set's last probes (usually the baker's last; a later run of another range makes the
     * released slot again) */
    bool early = end == ps->probe_count && nbatch >= 2;
    slot_release rel = {.g = c->g};
    pthread_t rel_thread;
    bool released = false;
    for (uint32_t i = 0; !r && i <= nbatch; i++) {
        if (i < nbatch) {
            bslot* s = &B.slot[i % 2];
            s->at = begin + done;
            if (head && i == 0) s->cnt = head;
            else if (tail && i == nbatch - 1) s->cnt = tail;
            else s->cnt = n - tail - done < batch ? n - tail - done : batch;
            done += s->cnt;
            if (s->cap < s->cnt && (r = slot_grow(&B, s, batch, err))) break;
            gpu_params* p = s->params.map;
            params_common(p, L, ps->seed);
            params_path(p, c);
            params_grid(p, ps, f->ref);
            p->a[0] = ps->res, p->a[1] = spp, p->a[2] = ps->bounces, p->a[3] = s->at;
            p->seed[2] = s->cnt, p->seed[3] = B.chunk < spp ? B.chunk : spp;
            p->lf[0] = 0, p->lf[3] = 2; /* the state zeroed by a fill; loops_intact() */
            if ((r = gbake_submit(&B, s, (spp + B.chunk - 1) / B.chunk, err))) break;
            submitted = i + 1;
            if (i == 0 && nbatch > 1 && !B.slot[1].made && (r = slot_init(&B, 1, batch, err))) break;
        }
        if (i == 0) continue;
        bslot* s = &B.slot[(i - 1) % 2];
        if ((r = gbake_wait(&B, s, st, ts[i - 1], err))) break;
        if (i == 1 && B.queries)
            st->first_latency = vx_time_now() - t1 - (double)(ts[0][3] - ts[0][0]) * c->g->props.limits.timestampPeriod * 1e-9;
        double t_got = vx_time_now();
        const float* flags = s->back.map;
        if (flags[1] != 0) {
            /* samples left (llvmpipe's loop guard fired): finish them with
             * smaller chunks, then filter again (the results do not depend on
             * the split; checked by recording too few dispatches on purpose:
             * the same bytes). The batch's timestamps then cover the second
             * filtering only. */
            vkQueueWaitIdle(c->g->queue); /* batch i, if any, done: it keeps its own flags */
            vx__buffer keep_out = c->out, keep_params = c->params;
            c->out = s->out, c->params = s->params;
            if (B.beam) c->maps_in = &s->beam; /* the batch's start distances, from its submission */
            double sec = 0;
            r = run_samples_ex(c, PMODE_BAKE, (B.nt + 63) / 64, s->cnt, spp, &B.chunk, true, &sec, err);
            c->out = keep_out, c->params = keep_params, c->maps_in = NULL;
            st->gpu_trace += sec;
            if (r || (r = gbake_submit(&B, s, 0, err)) || (r = gbake_wait(&B, s, st, ts[i - 1], err))) break;
        }
        double td = vx_time_now();
        gbake_store(&B, s);
        st->download += vx_time_now() - td;
        if (early && i == nbatch - 1) {
            /* the slot of the last batch but one: stored, never submitted again */
            vx__buffer* b[SLOT_BUFFERS];
            slot_buffer_list(s, b);
            for (int k = 0; k < SLOT_BUFFERS; k++) rel.b[k] = *b[k];
            if (pthread_create(&rel_thread, NULL, slot_release_main, &rel) == 0) {
                released = true;
                for (int k = 0; k < SLOT_BUFFERS; k++) memset(b[k], 0, sizeof *b[k]);
                s->cap = 0; /* made again where a later run (another range of the set) uses it */
            }
        }
        st->bytes_down += 16 + (uint64_t)s->cnt * B.lay.per * 4;
        st->batches++;
        if (!vx_progress_report(progress, "bake", s->at + s->cnt - begin, end - begin)) {
            r = vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "cancelled");
            break;
        }
        if (i == nbatch) st->tail = vx_time_now() - t_got;
    }
    /* nothing of ours may still run when the buffers go */
    if (r && submitted) vkQueueWaitIdle(c->g->queue);
    if (released) pthread_join(rel_thread, NULL);
    st->loop += vx_time_now() - t1;
    /* busy: the union of the batches' GPU intervals over the loop's wall time */
    if (!r && B.queries && st->loop > 0) {
        double busy = 0, per = c->g->props.limits.timestampPeriod * 1e-9;
        uint64_t last = 0;
        for (uint32_t i = 0; i < nbatch; i++) {
            uint64_t a = ts[i][0] > last ? ts[i][0] : last;
            if (ts[i][3] > a) busy += (double)(ts[i][3] - a) * per;
            if (ts[i][3] > last) last = ts[i][3];
        }
        st->busy = busy / st->loop;
    }
    vx_free(ps->alloc, ts);
    /* the second slot, made here; either one's buffers released here */
    Bp->chunk = B.chunk, Bp->slot[0] = B.slot[0], Bp->slot[1] = B.slot[1], Bp->slots_s = B.slots_s;
    return r;
}

/* Probes per batch: about 2^seg_log2 path segments and at most `cap` bytes of trace output. */
static uint32_t batch_of(const vx_probe_set* ps, uint32_t seg_log2, uint64_t cap, uint32_t want, uint32_t n) {
    uint64_t nt = (uint64_t)ps->res * ps->res;
    uint64_t per_probe = nt * ps->spp * (ps->bounces + 1);
    uint64_t batch = want ? want : (UINT64_C(1) << seg_log2) / (per_probe ? per_probe : 1);
    uint64_t most = cap / (nt * 48);
    if (batch > most) batch = most;
    if (batch < 1) batch = 1;
    if (batch > n) batch = n;
    return (uint32_t)batch;
}

/* The frame block of a bake: float coordinates relative to the scene's centre. */
static vx_result bake_frame(const vx_svo_scene* scene, vx__frame* f, vx_error* err) {
    double lo[3], hi[3];
    vx_svo_scene_world_bounds(scene, lo, hi);
    vx_result r = vx__frame_setup(lo, hi, &(vx_render_desc){.width = 1, .height = 1}, f, err);
    if (!r) r = vx__gpu_float_range(lo, hi, err);
    for (int k = 0; k < 3; k++) f->ref[k] = 0.5 * (lo[k] + hi[k]);
    return r;
}

/* A GPU bake kept across calls (probes.h): the context, the filter tables,
 * the pipelines and the two batch slots are made once. */
struct vx_probe_baker {
    vx__light L;
    vx__frame f;
    gctx c;
    gbake B;
    bool light, ctx, slots;
    const vx_allocator* alloc;
    /* what a run's set must share with the set the baker was made for */
    uint32_t res, spp, bounces, probe_count;
    uint64_t seed;
    const vx_probe* probes;
    double setup, setup_ctx, setup_pipes; /* seconds vx_probe_baker_create took (the first run's stats) */
    double sun_map;                       /* of setup_ctx: the sun's depth map */
    uint32_t sun_map_side, sun_map_nodes;
    double sun_map_list, sun_map_gpu, sun_map_ahead, sun_map_build;
    bool setup_reported;
};

void vx_probe_baker_destroy(vx_probe_baker* b) {
    if (!b) return;
    if (b->slots) gbake_free(&b->B);
    if (b->ctx) ctx_free(&b->c);
    if (b->light) vx__light_free(&b->L);
    vx_free(b->alloc, b);
}

vx_result vx_probe_baker_create(vx_render_scene* rs, const vx_svo_scene* scene, const vx_probe_bake_desc* desc,
                                const vx_probe_set* ps, vx_probe_baker** out, vx_error* err) {
    if (!rs || !scene || !ps || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    *out = NULL;
    double t0 = vx_time_now();
    vx_probe_bake_desc d = desc ? *desc : (vx_probe_bake_desc){0};
    vx_probe_baker* b = vx_calloc(ps->alloc, 1, sizeof *b);
    if (!b) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    b->alloc = ps->alloc;
    b->res = ps->res, b->spp = ps->spp, b->bounces = ps->bounces, b->probe_count = ps->probe_count;
    b->seed = ps->seed, b->probes = ps->probes;
    vx_result r = vx__probe_set_light(&b->L, NULL, scene, ps, err);
    b->light = !r;
    if (!r) r = bake_frame(scene, &b->f, err);
    vx__pipeline* pipe;
    if (!r) {
        r = ctx_init(&b->c, rs, scene, &b->f, ps, &b->L, err);
        b->ctx = true; /* ctx_free is safe on a partly made context */
    }
    /* the beam pass for the rays from the probes (H200, Cornell box, 512 probes at R=128, 64 spp, with
     * probe.comp's 8x4 texel tiles: GPU trace 0.544 -> 0.493 s; the camera rays alone 0.136 -> 0.091 s) */
    /* (either layout: probe_beam.comp walks the compact one's slots where the scene is in it) */
    if (!r && !d.no_beam) b->c.spec[VX__SPEC_COUNT + SPEC_BEAM] = BAKE_BEAM;
    if (!r) b->c.strat = !d.independent_bounce, b->c.kernel = d.kernel;
    /* the bounces a constant of the bake's kernel (PCONST bits 16-23) */
    if (!r && ps->bounces < 255) b->c.bounces = ps->bounces + 1;
    /* The bake's kernel (both, where bake_one() may run: choose_kernel), the filter and the beam pass made
     * ahead on threads of their own, beside each other and beside the sun map (its kernel, its nodes' upload
     * and build) and the filter tables: on a machine whose shader cache is empty each is a compile of the
     * driver's, in turn they added up. The kernel's SMAP as the map will be; where its build fails,
     * pipeline_of makes the kernel without it (and the one made ahead goes with the device). */
    if (!r) {
        gctx* c = &b->c;
        vx_gpu_compute_pipeline_desc pd;
        c->spec[VX__SPEC_COUNT + SPEC_SMAP] = sun_map_wanted(&b->L, !d.no_shadow_map);
        bool one = one_walk_ok(c);
        if (!one || d.kernel != VX_PROBE_KERNEL_ONE_WALK)
            vx__pipeline_ahead(c->g, probe_desc(c, PMODE_BAKE, false, &pd), &pd);
        if (one) vx__pipeline_ahead(c->g, probe_desc(c, PMODE_BAKE, true, &pd), &pd);
        vx__pipeline_ahead(c->g, filter_desc(&pd), &pd);
        if (c->spec[VX__SPEC_COUNT + SPEC_BEAM]) vx__pipeline_ahead(c->g, beam_desc(c, &pd), &pd);
    }
    if (!r) {
        vx_probe_bake_stats sm = {0};
        r = ctx_sun_map(&b->c, rs, &b->L, !d.no_shadow_map, &sm, err);
        b->sun_map = sm.sun_map, b->sun_map_side = sm.sun_map_side, b->sun_map_nodes = sm.sun_map_nodes;
        b->sun_map_list = sm.sun_map_list, b->sun_map_gpu = sm.sun_map_gpu, b->sun_map_ahead = sm.sun_map_ahead;
        b->sun_map_build = sm.sun_map_build;
    }
    b->setup_ctx = vx_time_now() - t0;
    double tp = vx_time_now();
    if (!r) choose_kernel(&b->c);
    if (!r) r = pipeline_of(&b->c, PMODE_BAKE, &pipe, err);
    b->setup_pipes = vx_time_now() - tp;
    if (!r) r = vx__buffer_create(b->c.g, 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, "probe maps", &b->c.maps, err);
    if (!r) {
        /* the trace output stays on the GPU: larger batches, fewer partly filled last waves
         * (H100, Cornell box, 512 probes at R=128, 64 spp: 0.689 s of tracing in batches of 32
         * probes, 0.650 s of 64, 0.626 s of 128 (2^28 segments), 0.614 s of 256) */
        uint32_t batch = batch_of(ps, 28, UINT64_C(1) << 28, d.batch, ps->probe_count);
        b->slots = true; /* gbake_free is safe on partly made slots */
        uint32_t first = ps->probe_count > batch && batch >= 8 ? batch / 4 : 0;
        r = gbake_init(&b->B, &b->c, ps, batch, first, err);
        b->B.chunk = vx_gpu_is_cpu(b->c.g) ? CPU_DEVICE_CHUNK : (ps->spp ? ps->spp : 1);
    }
    if (r) {
        vx_probe_baker_destroy(b);
        return r;
    }
    b->setup = vx_time_now() - t0;
    *out = b;
    return VX_OK;
}

vx_result vx_probe_baker_run(vx_probe_baker* b, const vx_probe_bake_desc* desc, vx_probe_set* ps, uint32_t end,
                             vx_error* err) {
    if (!b || !ps) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    if (ps->res != b->res || ps->spp != b->spp || ps->bounces != b->bounces || ps->probe_count != b->probe_count ||
        ps->seed != b->seed || ps->probes != b->probes)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "probe set of another bake than the baker's");
    uint32_t begin;
    vx_result r = vx__probe_bake_begin(ps, end, &begin, err);
    if (r || end == begin) return r;
    vx_probe_bake_desc d = desc ? *desc : (vx_probe_bake_desc){0};
    vx_probe_bake_stats st = {0};
    if (!b->setup_reported) {
        st.setup = b->setup, st.setup_ctx = b->setup_ctx, st.setup_pipes = b->setup_pipes + b->B.pipes;
        st.setup_slots = b->B.slots_s;
        st.sun_map = b->sun_map, st.sun_map_list = b->sun_map_list, st.sun_map_gpu = b->sun_map_gpu;
        st.sun_map_ahead = b->sun_map_ahead, st.sun_map_build = b->sun_map_build;
        b->setup_reported = true;
    }
    st.sun_map_side = b->sun_map_side, st.sun_map_nodes = b->sun_map_nodes;
    st.one_walk = b->c.use_one;
    double tg = vx_time_now();
    /* every byte of the range's maps comes from gbake_store before ps->count covers it */
    if (!vx__probe_grow(ps, end - ps->first, false))
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u probes at res %u", end - ps->first, ps->res);
    st.grow = vx_time_now() - tg;
    if ((r = bake_gpu_filtered(&b->B, ps, &b->L, &b->f, begin, end, &d.progress, &st, err))) return r;
    ps->count = end - ps->first;
    if (d.stats) *d.stats = st;
    return VX_OK;
}

vx_result vx_probe_bake_more_gpu(vx_render_scene* rs, const vx_svo_scene* scene, const vx_probe_bake_desc* desc,
                                 vx_probe_set* ps, uint32_t end, vx_error* err) {
    if (!rs || !scene || !ps) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    vx_probe_bake_desc d = desc ? *desc : (vx_probe_bake_desc){0};
    uint32_t begin;
    vx_result r = vx__probe_bake_begin(ps, end, &begin, err);
    if (r || end == begin) return r;
    if (!d.host_filter) {
        vx_probe_baker* b = NULL; /* (a failed create leaves it NULL) */
        r = vx_probe_baker_create(rs, scene, &d, ps, &b, err);
        if (!r) r = vx_probe_baker_run(b, &d, ps, end, err);
        vx_probe_baker_destroy(b);
        return r;
    }
    vx_probe_bake_stats st = {0};
    double t0 = vx_time_now();
    vx__light L;
    vx__frame f;
    r = vx__probe_set_light(&L, NULL, scene, ps, err);
    if (!r) r = bake_frame(scene, &f, err);
    if (r) {
        vx__light_free(&L);
        return r;
    }
    gctx c;
    vx__tables T = {0};
    float* raw = NULL;
    vx__pipeline* pipe;
    if ((r = ctx_init(&c, rs, scene, &f, ps, &L, err))) goto done;
    c.strat = !d.independent_bounce; /* the same estimator as the GPU filtering's */
    c.kernel = d.kernel;
    c.use_one = d.kernel == VX_PROBE_KERNEL_ONE_WALK && one_walk_ok(&c); /* nothing made ahead here */
    st.one_walk = c.use_one;
    if ((r = ctx_sun_map(&c, rs, &L, !d.no_shadow_map, &st, err))) goto done;
    if ((r = pipeline_of(&c, PMODE_BAKE, &pipe, err))) goto done;
    if (!vx__probe_grow(ps, end - ps->first, true)) {
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u probes at res %u", end - ps->first, ps->res);
        goto done;
    }
    if ((r = vx__buffer_create(c.g, 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, "probe maps", &c.maps, err)))
        goto done;
    uint64_t nt = (uint64_t)ps->res * ps->res;
    /* a batch: about 2^26 path segments and at most 384 MiB of output (48 bytes a texel) */
    uint32_t batch = batch_of(ps, 26, UINT64_C(3) << 27, d.batch, end - begin);
    if (!vx__tables_make(&T, ps->res, ps->alloc) || !(raw = vx_alloc(ps->alloc, (size_t)(16 + batch * nt * 48)))) {
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u probes at res %u", end - ps->first, ps->res);
        goto done;
    }
    if ((r = vx__buffer_create(c.g, 16 + batch * nt * 48, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, "probe texels",
                               &c.out, err)))
        goto done;
    double t1 = vx_time_now();
    st.setup = t1 - t0;
    for (uint32_t at = begin; at < end;) {
        uint32_t cnt = (uint32_t)(end - at < batch ? end - at : batch);
        gpu_params* p = c.params.map;
        params_common(p, &L, ps->seed);
        params_path(p, &c);
        params_grid(p, ps, f.ref);
        p->a[0] = ps->res, p->a[1] = ps->spp, p->a[2] = ps->bounces, p->a[3] = at;
        p->seed[2] = cnt;
        double sec = 0;
        if ((r = run_samples(&c, PMODE_BAKE, (uint32_t)((nt + 63) / 64), cnt, ps->spp ? ps->spp : 1, &sec, err)))
            goto done;
        st.gpu_trace += sec;
        double ta = vx_time_now();
        if ((r = vx__buffer_download(c.g, &c.out, raw, 16 + (VkDeviceSize)cnt * nt * 48, err))) goto done;
        double tb = vx_time_now();
        if (!finish_batch(ps, &T, raw + 4, at - ps->first, cnt, d.threads)) {
            r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
            goto done;
        }
        st.download += tb - ta, st.host_filter += vx_time_now() - tb;
        st.bytes_down += 16 + (uint64_t)cnt * nt * 48;
        st.batches++;
        at += cnt;
        if (!vx_progress_report(&d.progress, "bake", at - begin, end - begin)) {
            r = vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "cancelled");
            goto done;
        }
    }
    ps->count = end - ps->first;
    st.loop = vx_time_now() - t1;
    st.busy = st.loop > 0 ? (st.gpu_trace + st.gpu_filter + st.gpu_copy) / st.loop : 0;
    if (d.stats) *d.stats = st;
done:
    vx_free(ps->alloc, raw);
    vx__tables_free(&T);
    ctx_free(&c);
    vx__light_free(&L);
    return r;
}

static vx_result bake_range_gpu(void* device, const vx_svo_scene* scene, const vx_probe_bake_desc* desc,
                                vx_probe_set* ps, uint32_t end, vx_error* err) {
    return vx_probe_bake_more_gpu(device, scene, desc, ps, end, err);
}

vx_result vx_probe_bake_gpu(vx_render_scene* rs, const vx_svo_scene* scene, const vx_probe_bake_desc* desc,
                            vx_probe_set* out, vx_error* err) {
    if (!rs || !scene || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    return vx__probe_bake_placed(scene, desc, bake_range_gpu, rs, out, err);
}

/* ---- rendering ------------------------------------------------------------------------ */

/* The probe maps on the GPU, kept between frames (irradiance and moments at
 * once, the light field maps at the first light field frame). */
struct vx_probe_gpu {
    vx_render_scene* rs;
    const vx_svo_scene* scene;
    const vx_probe_set* ps; /* NULL: path tracer only (a part of a set: its light only) */
    bool complete;          /* ps holds every probe: the probe modes can use it */
    vx_gpu* g;
    vx__buffer maps, lf;
    bool maps_ready;   /* irradiance and moments uploaded (at the first gi or light field frame) */
    uint32_t lf_words; /* 0 until the light field maps are uploaded */
};

/* Packs the maps the light field walk reads (layout: LfMaps in probe.comp). */
static vx_result upload_lightfield(vx_probe_gpu* pg, vx_error* err) {
    const vx_probe_set* ps = pg->ps;
    size_t nb = vx__bsq(ps->res), lb = vx__bsq(ps->low_res);
    size_t dw = (nb + 1) / 2, lw = (lb + 1) / 2, nw = nb, rw = (nb * 3 + 1) / 2, per = dw + lw + nw + rw;
    if (per > UINT32_MAX / 4 || ps->probe_count > SIZE_MAX / 4 / per)
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "%u probes at %u: too large for the GPU", ps->probe_count,
                       ps->res);
    size_t total = per * ps->probe_count;
    uint32_t* w = vx_calloc(ps->alloc, total, 4);
    if (!w) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for the light field (%zu bytes)", total * 4);
    for (size_t k = 0; k < ps->probe_count; k++) {
        uint32_t* b = w + per * k;
        uint16_t* d16 = (uint16_t*)b; /* little-endian halves, as the shader reads them */
        memcpy(d16, ps->distance + nb * k, nb * 2);
        memcpy((uint16_t*)(b + dw), ps->low + lb * k, lb * 2);
        memcpy(b + dw + lw, ps->normal + nb * k, nb * 4);
        memcpy((uint16_t*)(b + dw + lw + nw), ps->radiance + nb * 3 * k, nb * 3 * 2);
    }
    vx_result r = upload_to(pg->g, &pg->lf, w, total * 4, "probe light field", err);
    vx_free(ps->alloc, w);
    if (!r) pg->lf_words = (uint32_t)per;
    return r;
}

/* Irradiance (as floats) then moments, every probe (layout: Maps in probe.comp). */
static vx_result upload_maps(vx_probe_gpu* pg, vx_error* err) {
    const vx_probe_set* ps = pg->ps;
    size_t ni = vx__bsq(VX_PROBE_IRR_RES) * 3, nm = vx__bsq(VX_PROBE_DIST_RES) * 2;
    size_t nmaps = (ni + nm) * ps->probe_count;
    float* maps = vx_alloc(ps->alloc, nmaps * sizeof(float));
    if (!maps) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u probes' maps", ps->probe_count);
    for (size_t i = 0; i < ni * ps->probe_count; i++) maps[i] = vx_probe_half_to_float(ps->irradiance[i]);
    memcpy(maps + ni * ps->probe_count, ps->moments, nm * ps->probe_count * sizeof(float));
    vx__buffer_destroy(pg->g, &pg->maps);
    vx_result r = upload_to(pg->g, &pg->maps, maps, nmaps * sizeof(float), "probe maps", err);
    vx_free(ps->alloc, maps);
    if (r) upload_to(pg->g, &pg->maps, NULL, 16, "probe maps", NULL); /* keep a valid placeholder */
    else pg->maps_ready = true;
    return r;
}

vx_result vx_probe_gpu_create(vx_render_scene* rs, const vx_svo_scene* s, const vx_probe_set* ps, vx_probe_gpu** out,
                              vx_error* err) {
    if (!rs || !s || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    *out = NULL;
    const vx_allocator* a = ps ? ps->alloc : NULL;
    vx_probe_gpu* pg = vx_calloc(a, 1, sizeof *pg);
    if (!pg) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    *pg = (vx_probe_gpu){.rs = rs, .scene = s, .ps = ps, .g = vx__render_scene_gpu(rs),
                         .complete = ps && ps->first == 0 && ps->count == ps->probe_count};
    /* placeholders until a frame needs the maps */
    vx_result r = upload_to(pg->g, &pg->maps, NULL, 16, "probe maps", err);
    if (!r) r = upload_to(pg->g, &pg->lf, NULL, 16, "probe light field", err);
    if (r) {
        vx_probe_gpu_destroy(pg);
        return r;
    }
    *out = pg;
    return VX_OK;
}

void vx_probe_gpu_destroy(vx_probe_gpu* pg) {
    if (!pg) return;
    vx__buffer_destroy(pg->g, &pg->maps);
    vx__buffer_destroy(pg->g, &pg->lf);
    vx_free(pg->ps ? pg->ps->alloc : NULL, pg);
}

/* Divides the accumulation into dst (probe_out.comp), on the GPU. */
static vx_result resolve_into(vx_gpu* g, vx__buffer* src, vx__buffer* dst, size_t npx, uint32_t spp, double* sec,
                              vx_error* err) {
    vx_gpu_compute_pipeline_desc pd = {.spirv = vx__probe_out_spv_arr, .spirv_size = sizeof vx__probe_out_spv_arr,
                                       .binding_count = 2, .push_constant_size = 12, .label = "probe out"};
    pd.bindings[0] = pd.bindings[1] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    vx__pipeline* p;
    vx_result r = vx__pipeline_get(g, 0x9B0BE0u, &pd, &p, err);
    if (r) return r;
    uint64_t groups = (npx + 63) / 64;
    uint32_t gx = groups < 4096 ? (uint32_t)groups : 4096, gy = (uint32_t)((groups + gx - 1) / gx);
    uint32_t pc[3] = {(uint32_t)npx, spp, gx * 64};
    vx__dispatch_desc dd = {.pipeline = p, .buffer_count = 2, .buffers = {src, dst}, .groups = {gx, gy, 1},
                            .push = pc, .push_size = sizeof pc, .label = "probe out"};
    return vx__dispatch(g, &dd, sec, err);
}

static vx_result render_with(vx_probe_gpu* pg, vx__prender* pr, vx_render_image* out, vx__buffer* dst,
                             double* dst_seconds, vx_error* err) {
    const vx_svo_scene* s = pg->scene;
    const vx_probe_set* ps = pg->ps;
    vx__prender P = *pr; /* a copy: the light's arrays stay the caller's */
    vx_result r = VX_OK;
    const vx_probe_render_desc d = P.d;
    const vx__frame f = P.f;
    const double *lo = P.lo, *hi = P.hi;
    bool lf = P.lightfield, need_probes = P.uses_probes;
    uint32_t spp = P.spp, bounces = P.bounces;
    if (need_probes && !pg->maps_ready && (r = upload_maps(pg, err))) return r;
    if (lf && !pg->lf_words) {
        vx__buffer_destroy(pg->g, &pg->lf);
        if ((r = upload_lightfield(pg, err))) {
            upload_to(pg->g, &pg->lf, NULL, 16, "probe light field", NULL); /* keep a valid placeholder */
            return r;
        }
    }
    if (spp > UINT32_C(1) << 24) /* sample counts are exact floats on the GPU */
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "%u samples per pixel: at most 2^24 on the GPU", spp);
    gctx c;
    float* acc = NULL;
    if ((r = ctx_init(&c, pg->rs, s, &f, need_probes ? ps : NULL, &P.L, err))) goto done;
    c.maps_in = &pg->maps, c.lf_in = &pg->lf;
    /* the path tracer's sun rays (path() in probe.comp) ended by the sun's depth map, as the bake's; not for
     * the pass pipeline's gi (dst): its frame may hold the map of its own light already */
    if (!dst && (d.mode == VX_PROBE_RENDER_PATHTRACE || d.mode == VX_PROBE_RENDER_PT_INDIRECT)) {
        vx_probe_bake_stats sm = {0};
        if ((r = ctx_sun_map(&c, pg->rs, &P.L, !(d.base && d.base->no_shadow_map), &sm, err))) goto done;
        if (d.stats) d.stats->sun_map_side = sm.sun_map_side;
    }
    /* the rows traced: every row, or those d.rows lists, compacted (a row
     * table in the buffer), so a rank of mpirun svo_render dispatches only
     * its own pixels */
    uint32_t nrows = vx__prender_rows(&d, f.height), table = d.rows && nrows < f.height ? nrows : 0;
    if (table && dst) {
        r = vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "a row subset cannot be rendered into a GPU buffer");
        goto done;
    }
    size_t npx = (size_t)f.width * nrows, head = 1 + (table + 3) / 4;
    uint32_t nblk = (spp + RENDER_BLOCK - 1) / RENDER_BLOCK;
    size_t per_round = npx ? RENDER_ROUND_BYTES / (npx * 32) : 1;
    if (per_round < 1) per_round = 1;
    if (per_round > RENDER_ROUND_BLOCKS) per_round = RENDER_ROUND_BLOCKS;
    if (per_round > nblk) per_round = nblk;
    if (npx * per_round >= (size_t)1 << 30) {
        r = vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "a %ux%u image is too large for the GPU renderer", f.width,
                    f.height);
        goto done;
    }
    /* flags, row table, per pixel the running sum and the samples done, the per_round's blocks (probe.comp) */
    size_t nout = (head + 2 * npx + 2 * npx * per_round) * 16, nres = (head + 2 * npx) * 16;
    acc = vx_calloc(NULL, head + 2 * npx, 16);
    if (!acc) {
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for a %ux%u image", f.width, f.height);
        goto done;
    }
    for (uint32_t y = 0, k = 0; table && y < f.height; y++)
        if (d.rows[y]) acc[4 + k++] = (float)y; /* exact: rows < 2^24 */
    if ((r = vx__buffer_create(c.g, nout, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, "probe pixels", &c.out, err)) ||
        (r = vx__buffer_upload(c.g, &c.out, acc, head * 16, err)))
        goto done;
    gpu_params* p = c.params.map;
    params_common(p, &P.L, d.seed);
    params_path(p, &c);
    if (need_probes) params_grid(p, ps, f.ref);
    if (lf) {
        p->lf[0] = ps->res, p->lf[1] = ps->low_res, p->lf[2] = pg->lf_words;
        for (int k = 0; k < 3; k++) p->lf_lo[k] = (float)(lo[k] - f.ref[k]), p->lf_hi[k] = (float)(hi[k] - f.ref[k]);
        p->lf_lo[3] = (float)ps->dist_step;
    }
    p->a[0] = f.width, p->a[1] = spp, p->a[2] = bounces, p->a[3] = f.height;
    p->cnt[2] = d.pixel_centre;
    p->rw[0] = table, p->rw[1] = RENDER_BLOCK, p->rw[3] = (uint32_t)per_round;
    double sec = 0;
    uint32_t chunk = 0;
    /* each per_round: its blocks of every pixel traced, then added in block order */
    for (uint32_t b = 0; npx && b < nblk; b += (uint32_t)per_round) {
        uint32_t nb = nblk - b < per_round ? nblk - b : (uint32_t)per_round;
        uint64_t groups = (npx * nb + 63) / 64;
        uint32_t gx = groups < 4096 ? (uint32_t)groups : 4096, gy = (uint32_t)((groups + gx - 1) / gx);
        double t = 0;
        p->rw[2] = b, p->rk[0] = 0;
        if ((r = run_samples_ex(&c, (uint32_t)d.mode + 1, gx, gy, spp, &chunk, false, &t, err))) goto done;
        sec += t;
        groups = (npx + 63) / 64;
        gx = groups < 4096 ? (uint32_t)groups : 4096, gy = (uint32_t)((groups + gx - 1) / gx);
        p->rk[0] = 1;
        float flags[4] = {0};
        if ((r = run(&c, (uint32_t)d.mode + 1, gx, gy, &t, err)) ||
            (r = vx__buffer_download(c.g, &c.out, flags, sizeof flags, err)))
            goto done;
        sec += t;
        if (flags[0] != 0) { /* the loop guard fired while adding a few blocks: not seen on any device */
            r = vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "adding the sample blocks exceeds the loop limit of %s",
                        vx_gpu_device_name(c.g));
            goto done;
        }
    }
    if (dst) {
        /* stays on the GPU: the pixels divided into the caller's buffer */
        double t = 0;
        if (dst->size < npx * 16) {
            r = vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "a buffer of %llu bytes holds less than a %ux%u image",
                        (unsigned long long)dst->size, f.width, f.height);
            goto done;
        }
        if ((r = resolve_into(c.g, &c.out, dst, npx, spp, &t, err))) goto done;
        *dst_seconds = sec + t;
        goto done;
    }
    if (npx && (r = vx__buffer_download(c.g, &c.out, acc, nres, err))) goto done;
    size_t full = (size_t)f.width * f.height;
    vx_render_image img = {.width = f.width, .height = f.height, .mode = VX_RENDER_COLOR};
    img.pixels = vx_calloc(NULL, full ? full : 1, 16);
    if (!img.pixels) {
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for a %ux%u image", f.width, f.height);
        goto done;
    }
    const float* px = acc + 4 * head;
    for (size_t i = 0; i < npx; i++) {
        size_t row = table ? (size_t)acc[4 + i / f.width] : i / f.width, o = row * f.width + i % f.width;
        for (int k = 0; k < 4; k++) img.pixels[4 * o + k] = px[4 * (2 * i) + k] / (float)spp;
    }
    img.gpu_seconds = sec;
    img.rays = (uint64_t)f.width * nrows * spp;
    *out = img;
done:
    vx_free(NULL, acc);
    ctx_free(&c);
    return r;
}

static vx_result render(vx_probe_gpu* pg, const vx_probe_render_desc* desc, vx_render_image* out, vx__buffer* dst,
                        double* dst_seconds, vx_error* err) {
    vx__prender P;
    vx_result r = vx__prender_setup(pg->scene, pg->ps, pg->complete, desc, &P, err);
    if (r) return r;
    r = vx__gpu_float_range(P.lo, P.hi, err);
    if (!r) r = render_with(pg, &P, out, dst, dst_seconds, err);
    vx__prender_free(&P);
    return r;
}

vx_result vx_probe_gpu_render(vx_probe_gpu* pg, const vx_probe_render_desc* desc, vx_render_image* out,
                              vx_error* err) {
    if (!pg || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    return render(pg, desc, out, NULL, NULL, err);
}

vx_result vx_probe_gpu_render_into(vx_probe_gpu* pg, const vx_probe_render_desc* desc, void* buffer,
                                   double* gpu_seconds, vx_error* err) {
    if (!pg || !buffer || !gpu_seconds) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    return render(pg, desc, NULL, buffer, gpu_seconds, err);
}

vx_result vx_probe_render_gpu(vx_render_scene* rs, const vx_svo_scene* s, const vx_probe_set* ps,
                              const vx_probe_render_desc* desc, vx_render_image* out, vx_error* err) {
    if (!rs || !s || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    vx_probe_gpu* pg;
    vx_result r = vx_probe_gpu_create(rs, s, ps, &pg, err);
    if (r) return r;
    r = vx_probe_gpu_render(pg, desc, out, err);
    vx_probe_gpu_destroy(pg);
    return r;
}
