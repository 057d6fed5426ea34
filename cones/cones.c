/* cones/cones.c - voxel cone tracing (cones/cones.h): the radiance volume's
 * buffers and the dispatches of voxelize.comp, inject.comp, filter.comp and
 * cone.comp (cones/shaders/), which all include the tracer's shaders for the
 * scene bindings, the traversal and the lights (light_eval). */
#include <math.h>
#include <string.h>

#include "cones/cones.h"
#include "probes/probes.h" /* the probe bake's light: the defaults of every GI method */
#include "render/gpu.h"

#include "cone.comp.h"
#include "filter.comp.h"
#include "inject.comp.h"
#include "voxelize.comp.h"

/* std430 of ConeP in cone_common.glsl */
typedef struct cone_params {
    float origin[4];
    uint32_t info[4];
    float cone[4];
    uint32_t ctl[4];
    float spec[4];
    uint32_t dims[VX_CONE_LEVELS_MAX][4];
    float dirs[VX_CONE_CONES_MAX][4];
    float atlas[4];                      /* xyz: 1 / the atlas's size, w: its z stride per entry */
    uint32_t atl[VX_CONE_LEVELS_MAX][4]; /* each level's corner in the atlas */
} cone_params;

/* passes_common.glsl's push block */
typedef struct push_block {
    float f0[4], f1[4], f2[4];
    uint32_t u0[4], u1[4];
    float f3[4];
    uint32_t u2[4];
} push_block;

/* bindings of passes_common.glsl the cone shaders give other uses: 7 the
 * half-resolution samples (cone.comp), 15 the materials (cone_common.glsl
 * cmat), 17 the occupancy bits and 18 the lists of occupied voxels per level
 * (filter.comp) */
enum { NBIND = 26, BIND_HALF = 7, BIND_GI = 12, BIND_EMIT = 14, BIND_MAT = 15, BIND_LIGHTS = 16, BIND_FLAGS = 17,
       BIND_LLIST = 18, BIND_SKY = 19, BIND_VOL, BIND_REC, BIND_PARAMS, BIND_LIST, BIND_TEX, BIND_IMG };
_Static_assert(NBIND <= VX_GPU_MAX_BINDINGS, "cone shaders use 26 bindings");
enum { B_VOL, B_REC, B_PARAMS, B_LIST, B_EMIT, B_LIGHTS, B_SKY, B_DUMMY, B_MAT, B_HALF, B_FLAGS, B_LLIST, B_FLIGHTS, B_ATLAS,
       B_COUNT };
/* cone_common.glsl CONE_SPEC bits above the entries */
enum { FEAT_SPEC = 16, FEAT_SHADOWS = 32 };
#define ENV_N 32     /* the environment BRDF table's side (cone_common.glsl) */
#define LLIST_HEAD 16 /* llist[l]: voxels listed at level l; the lists from LLIST_HEAD */
#define SPEC_TAN_PER_ALPHA 2.0 /* the specular cone: tan(half angle) = 2 alpha, at most SPEC_TAN_MAX */
#define SPEC_TAN_MAX 1.0
typedef enum { SH_VOXELIZE, SH_INJECT, SH_FILTER, SH_CONE } shader_id;
#define REC_VEC4 5 /* vec4 per listed voxel and side (cone_common.glsl) */
#define LIGHT_FLOATS 24

struct vx_cone_gi {
    vx_render_scene* rs;
    const vx_svo_scene* scene;
    vx_gpu* g;
    vx_cone_desc d;
    vx__buffer b[B_COUNT];
    float* emit_attr;
    size_t emit_count;
    vx_cone_info info;
    double lo[3], hi[3]; /* the scene's world bounds (the frame's) */
    double light_dir[3], sun[3], sky[3];
    vx_sky sky_dir; /* gradient or map: the sky by direction (b[B_SKY]); else VX_SKY_DEFAULT */
    vx_sky_texels sky_map;
    cone_params P;
    uint64_t level0;
    uint32_t features;     /* FEAT_* the scene and options ask for */
    /* cone.comp's and voxelize.comp's LIGHTS constant (pass_bodies.glsl) where some record is glass that
     * transmits: the glass lobe through pass_bodies.glsl glass_lobe (its walk, the surface behind lit by the
     * direct pass's rules, the cones' light there), glass as 1 - transmission of a hit in the volume; 0
     * without glass */
    uint32_t glass_lights;
    uint32_t mat_records;  /* attribute records with a material entry (SPEC) */
    uint32_t llist_off[VX_CONE_LEVELS_MAX], llist_n[VX_CONE_LEVELS_MAX]; /* occupied voxels per level (>= 1) */
    bool sparse;           /* the lists are built: relighting filters only occupied voxels */
    double lights_ref[3];  /* the frame reference b[B_FLIGHTS] was packed for (SHADOWS) */
    bool lights_packed;
    const vx_allocator* alloc;
};

vx_cone_desc vx_cone_desc_defaults(void) {
    vx_probe_bake_desc b = vx_probe_bake_desc_defaults();
    vx_cone_desc d = {.res = 128, .samples = 2, .cones = 6, .offset = 1.5, .step = 0.5, .bounces = 1, .sun_angle = 0.53};
    memcpy(d.light_dir, b.light_dir, sizeof d.light_dir);
    memcpy(d.sun, b.sun, sizeof d.sun);
    memcpy(d.sky, b.sky, sizeof d.sky);
    d.aperture = acos(1.0 - 1.0 / d.cones) * 180 / 3.14159265358979323846;
    return d;
}

static bool zero3(const double v[3]) { return !v[0] && !v[1] && !v[2]; }

/* The desc with its zeros resolved; the light into cg. */
static vx_result resolve(vx_cone_gi* cg, const vx_cone_desc* in, vx_error* err) {
    vx_cone_desc D = vx_cone_desc_defaults(), d = in ? *in : (vx_cone_desc){0};
    if (!d.res) d.res = D.res;
    if (!d.samples) d.samples = D.samples;
    if (!d.cones) d.cones = D.cones;
    if (d.offset == 0) d.offset = D.offset;
    if (d.step == 0) d.step = D.step;
    if (!d.bounces) d.bounces = D.bounces;
    if (d.res < 2 || d.res > VX_CONE_RES_MAX)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "cone volume res %u: 2 to %u", d.res, VX_CONE_RES_MAX);
    if (d.samples > 8) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "%u samples per face side: at most 8", d.samples);
    if (d.cones > VX_CONE_CONES_MAX)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "%u cones: at most %u", d.cones, VX_CONE_CONES_MAX);
    if (d.bounces > 4) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "%u bounces: at most 4", d.bounces);
    if (!(d.aperture >= 0 && d.aperture < 89) || !(d.offset > 0 && d.offset < 64) || !(d.step >= 0.05 && d.step <= 4) ||
        !(d.ao_distance >= 0 && d.ao_distance < INFINITY))
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                       "cone aperture %g (0 to 89 degrees), offset %g (above 0, below 64 voxels), step %g (0.05 to 4 "
                       "diameters), AO distance %g (0 or more)", d.aperture, d.offset, d.step, d.ao_distance);
    if (!d.aperture) {
        /* each cone an equal share of the hemisphere: 2 pi (1 - cos) = 2 pi / n */
        double a = acos(1.0 - 1.0 / d.cones) * 180 / 3.14159265358979323846;
        d.aperture = a < 75 ? a : 75;
    }
    if (d.sun_angle == 0) d.sun_angle = D.sun_angle;
    if (!(d.sun_angle > 0 && d.sun_angle < 30))
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "sun angle %g: above 0, below 30 degrees", d.sun_angle);
    if (d.light_count && !d.lights) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "%u lights but no array", d.light_count);
    for (uint32_t i = 0; i < d.light_count; i++) {
        vx_result r = vx_light_validate(&d.lights[i], i, err);
        if (r) return r;
    }
    double ld[3];
    memcpy(ld, zero3(d.light_dir) ? D.light_dir : d.light_dir, sizeof ld);
    double l = sqrt(ld[0] * ld[0] + ld[1] * ld[1] + ld[2] * ld[2]);
    if (!(l > 0) || !isfinite(l)) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "the sun's direction is not a direction");
    for (int k = 0; k < 3; k++)
        if (!(d.sun[k] >= 0 && d.sun[k] < INFINITY && d.sky[k] >= 0 && d.sky[k] < INFINITY))
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "sun %g and sky %g: finite, 0 or more", d.sun[k], d.sky[k]);
    /* the frame's lights replace the sun, as in the pass pipeline's other
     * methods and the path tracer (probes/render_gi.c): else a frame lit by
     * lamps alone got the default sun too, in the volume and the direct pass */
    bool sun_off = d.no_sun || d.light_count;
    for (int k = 0; k < 3; k++) {
        cg->light_dir[k] = ld[k] / l;
        cg->sun[k] = sun_off ? 0 : (zero3(d.sun) ? D.sun[k] : d.sun[k]);
        cg->sky[k] = d.black_sky ? 0 : (zero3(d.sky) ? D.sky[k] : d.sky[k]);
    }
    /* the sky by direction: a constant one is the uniform sky */
    if (d.sky_dir && !d.black_sky) {
        vx_result r = vx_sky_validate(d.sky_dir, err);
        if (r) return r;
        const vx_sky* k = d.sky_dir;
        const vx_sky_texels* t = d.sky_map;
        if (k->type == VX_SKY_ENVMAP && (!t || !t->rgb || !t->width || !t->height || t->width > 65536 || t->height > 65536))
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "sky: the environment map '%s' has no texels", k->path);
        if (k->type == VX_SKY_CONSTANT) memcpy(cg->sky, k->color, sizeof cg->sky);
        if (k->type == VX_SKY_GRADIENT || k->type == VX_SKY_ENVMAP)
            cg->sky_dir = *k, cg->sky_map = k->type == VX_SKY_ENVMAP ? *t : (vx_sky_texels){0};
    }
    d.sky_dir = NULL, d.sky_map = NULL; /* kept above */
    cg->d = d;
    return VX_OK;
}

/* The cone set around +z: directions cosine-distributed over the hemisphere
 * (a Fibonacci spiral in the unit disc lifted to it, the first along +z),
 * equal weights. */
static void cone_set(cone_params* P, uint32_t n, double aperture_deg) {
    const double golden = 2.39996322972865332;
    for (uint32_t k = 0; k < n; k++) {
        double u = n == 1 ? 0 : (k + 0.5) / n, r = sqrt(u), phi = k * golden;
        P->dirs[k][0] = (float)(r * cos(phi));
        P->dirs[k][1] = (float)(r * sin(phi));
        P->dirs[k][2] = (float)sqrt(1 - u);
        P->dirs[k][3] = (float)(1.0 / n);
    }
    P->ctl[0] = n;
    P->cone[0] = (float)tan(aperture_deg * 3.14159265358979323846 / 180);
}

static vx_result dispatch(vx_cone_gi* cg, shader_id sh, uint32_t stage, const vx__frame* f, uint32_t gx, uint32_t gy,
                          const push_block* pc, vx__buffer* out, double* sec, vx_error* err) {
    vx__buffer* scene[7];
    uint32_t spec[VX__SPEC_COUNT];
    vx_result r = vx__render_scene_bind(cg->rs, f, scene, spec, err);
    if (r) return r;
    /* the volume's corner relative to this frame's reference */
    cone_params* P = cg->b[B_PARAMS].map;
    *P = cg->P;
    for (int k = 0; k < 3; k++) P->origin[k] = (float)(cg->info.origin[k] - f->ref[k]);
    static const char* const labels[] = {"cone voxelize", "cone inject", "cone filter", "cone trace"};
    vx_gpu_compute_pipeline_desc pd = {.binding_count = NBIND,
                                       .spec_count = VX__SPEC_TRACE_IDS,
                                       .push_constant_size = sizeof(push_block),
                                       .label = labels[sh]};
    switch (sh) {
    case SH_VOXELIZE: pd.spirv = vx__cone_voxelize_spv_arr, pd.spirv_size = sizeof vx__cone_voxelize_spv_arr; break;
    case SH_INJECT: pd.spirv = vx__cone_inject_spv_arr, pd.spirv_size = sizeof vx__cone_inject_spv_arr; break;
    case SH_FILTER: pd.spirv = vx__cone_filter_spv_arr, pd.spirv_size = sizeof vx__cone_filter_spv_arr; break;
    default: pd.spirv = vx__cone_trace_spv_arr, pd.spirv_size = sizeof vx__cone_trace_spv_arr; break;
    }
    pd.bindings[0] = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    for (uint32_t i = 1; i < NBIND; i++) pd.bindings[i] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    pd.bindings[BIND_TEX] = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    pd.bindings[BIND_IMG] = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
    memcpy(pd.spec, spec, sizeof spec);
    pd.spec[5] = stage;
    pd.spec[6] = cg->info.entries | (sh == SH_CONE ? cg->features : 0);
    pd.spec[7] = sh == SH_CONE || sh == SH_VOXELIZE ? cg->glass_lights : 0; /* pass_bodies.glsl LIGHTS */
    vx__render_scene_trace_ids(cg->rs, pd.spec);
    uint64_t key = vx__spec_key(0xC0E5000ull + (uint64_t)sh, pd.spec, VX__SPEC_TRACE_IDS);
    vx__pipeline* p;
    if ((r = vx__pipeline_get(cg->g, key, &pd, &p, err))) return r;
    vx__dispatch_desc dd = {.pipeline = p, .buffer_count = NBIND, .groups = {gx, gy, 1}, .push = pc,
                            .push_size = sizeof *pc, .label = labels[sh]};
    for (int i = 0; i < 7; i++) dd.buffers[i] = scene[i];
    for (int i = 7; i < NBIND; i++) dd.buffers[i] = &cg->b[B_DUMMY];
    dd.buffers[BIND_GI] = out ? out : &cg->b[B_DUMMY];
    dd.buffers[BIND_EMIT] = &cg->b[B_EMIT];
    /* (no lights buffer before the first frame's: voxelize and filter run before it) */
    dd.buffers[BIND_LIGHTS] = cg->b[B_LIGHTS].buf ? &cg->b[B_LIGHTS] : &cg->b[B_DUMMY];
    dd.buffers[BIND_SKY] = &cg->b[B_SKY];
    dd.buffers[BIND_VOL] = &cg->b[B_VOL];
    dd.buffers[BIND_REC] = &cg->b[B_REC];
    dd.buffers[BIND_PARAMS] = &cg->b[B_PARAMS];
    dd.buffers[BIND_LIST] = &cg->b[B_LIST];
    dd.buffers[BIND_TEX] = dd.buffers[BIND_IMG] = &cg->b[B_ATLAS];
    if (cg->b[B_MAT].buf) dd.buffers[BIND_MAT] = &cg->b[B_MAT];
    if (cg->b[B_HALF].buf) dd.buffers[BIND_HALF] = &cg->b[B_HALF];
    if (cg->b[B_FLAGS].buf) dd.buffers[BIND_FLAGS] = &cg->b[B_FLAGS];
    if (cg->b[B_LLIST].buf) dd.buffers[BIND_LLIST] = &cg->b[B_LLIST];
    if (sh == SH_CONE && cg->b[B_FLIGHTS].buf) dd.buffers[BIND_LIGHTS] = &cg->b[B_FLIGHTS];
    double s = 0;
    if ((r = vx__dispatch(cg->g, &dd, &s, err))) return r;
    if (sec) *sec += s;
    return VX_OK;
}

/* One invocation per item, 64 a group, the groups as a 2D grid. */
static vx_result dispatch_n(vx_cone_gi* cg, shader_id sh, uint32_t stage, const vx__frame* f, uint64_t n,
                            const push_block* pc, double* sec, vx_error* err) {
    if (!n) return VX_OK;
    uint64_t groups = (n + 63) / 64;
    uint32_t gx = groups < 4096 ? (uint32_t)groups : 4096, gy = (uint32_t)((groups + gx - 1) / gx);
    return dispatch(cg, sh, stage, f, gx, gy, pc, NULL, sec, err);
}

/* The frame the volume's steps bind: any camera (the shaders work relative
 * to its reference), the sun's direction. */
static vx_result light_frame(vx_cone_gi* cg, vx__frame* f, vx_error* err) {
    vx_render_desc rd = {.width = 1, .height = 1};
    memcpy(rd.light_dir, cg->light_dir, sizeof rd.light_dir);
    return vx__frame_setup(cg->lo, cg->hi, &rd, f, err);
}

/* Every level from the one below: over every voxel (dense: after a
 * voxelization, which also clears what no longer holds geometry), or only
 * over the voxels with geometry below them (the lists of mark_occupied: a
 * light change leaves every other voxel empty, as the dense pass left it). */
static vx_result filter_levels(vx_cone_gi* cg, const vx__frame* f, bool dense, double* sec, vx_error* err) {
    vx_result r = VX_OK;
    for (uint32_t l = 1; l < cg->info.levels && !r; l++) {
        push_block pc = {.u2 = {l, cg->llist_off[l]}};
        const uint32_t* d = cg->info.dims[l];
        if (dense || !cg->sparse) r = dispatch_n(cg, SH_FILTER, 0, f, (uint64_t)d[0] * d[1] * d[2], &pc, sec, err);
        else r = dispatch_n(cg, SH_FILTER, 1, f, cg->llist_n[l], &pc, sec, err);
    }
    return r;
}

/* The lists of occupied voxels per level above 0 (filter.comp STAGE 2): the
 * parents of the voxels listed one level below, each once (an occupancy bit
 * per voxel). A level's list holds at most as many voxels as the level, and
 * as the level-0 list (n0): the lists take at most an eighth of the dense
 * levels above 0, 4 bytes a voxel. */
static vx_result mark_occupied(vx_cone_gi* cg, const vx__frame* f, double* sec, vx_error* err) {
    vx_cone_info* I = &cg->info;
    uint64_t n0 = I->surface_voxels, at = LLIST_HEAD, total = 0;
    for (uint32_t l = 0; l < I->levels; l++) {
        uint64_t v = (uint64_t)I->dims[l][0] * I->dims[l][1] * I->dims[l][2];
        total += v;
        cg->llist_off[l] = (uint32_t)at;
        cg->llist_n[l] = 0;
        if (l) at += v < n0 ? v : n0;
    }
    cg->sparse = false;
    vx_result r = vx__buffer_ensure(cg->g, &cg->b[B_LLIST], at * 4, "cone level lists", err);
    uint64_t words = (total + 31) / 32;
    if (!r) r = vx__buffer_ensure(cg->g, &cg->b[B_FLAGS], words * 4, "cone occupancy", err);
    uint32_t* zero = r ? NULL : vx_calloc(cg->alloc, words > LLIST_HEAD ? words : LLIST_HEAD, 4);
    if (!r && !zero) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for the cone occupancy bits");
    if (!r) r = vx__buffer_upload(cg->g, &cg->b[B_FLAGS], zero, words * 4, err);
    if (!r) r = vx__buffer_upload(cg->g, &cg->b[B_LLIST], zero, LLIST_HEAD * 4, err);
    vx_free(cg->alloc, zero);
    /* level l's list from level l - 1's (at most as many parents as children) */
    uint64_t below = n0;
    for (uint32_t l = 1; l < I->levels && !r; l++) {
        push_block pc = {.u2 = {l, cg->llist_off[l], cg->llist_off[l - 1]}};
        r = dispatch_n(cg, SH_FILTER, 2, f, below, &pc, sec, err);
        uint64_t v = (uint64_t)I->dims[l][0] * I->dims[l][1] * I->dims[l][2];
        below = v < below ? v : below;
    }
    uint32_t head[LLIST_HEAD];
    if (!r) r = vx__buffer_download(cg->g, &cg->b[B_LLIST], head, sizeof head, err);
    for (uint32_t l = 1; l < I->levels && !r; l++) {
        uint64_t v = (uint64_t)I->dims[l][0] * I->dims[l][1] * I->dims[l][2];
        if (head[l] > v || head[l] > n0)
            return vx_fail(err, VX_ERR_GPU, VX_NO_OFFSET, "level %u lists %u occupied voxels of %llu", l, head[l],
                           (unsigned long long)v);
        cg->llist_n[l] = head[l];
    }
    if (!r) cg->sparse = true;
    for (uint32_t l = 1; l < I->levels && !r; l++) I->occupied_voxels += cg->llist_n[l];
    return r;
}

static vx_result upload_lights(vx_cone_gi* cg, const vx__frame* f, vx_error* err) {
    uint32_t n = cg->d.light_count;
    float* gl = vx_calloc(cg->alloc, n ? n : 1, LIGHT_FLOATS * sizeof(float));
    if (!gl) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u lights", n);
    for (uint32_t i = 0; i < n; i++) vx__light_pack(&cg->d.lights[i], f->ref, 3.14159265358979323846 / 1024, gl + LIGHT_FLOATS * i);
    vx__buffer_destroy(cg->g, &cg->b[B_LIGHTS]);
    size_t bytes = (size_t)(n ? n : 1) * LIGHT_FLOATS * sizeof(float);
    vx_result r = vx__buffer_create(cg->g, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, "cone lights", &cg->b[B_LIGHTS], err);
    if (!r) r = vx__buffer_upload(cg->g, &cg->b[B_LIGHTS], gl, bytes, err);
    vx_free(cg->alloc, gl);
    return r;
}

/* inject (+ bounces) and filter, with the light in cg */
static vx_result inject(vx_cone_gi* cg, vx_error* err) {
    vx__frame f;
    vx_result r = light_frame(cg, &f, err);
    if (!r) r = upload_lights(cg, &f, err);
    if (r) return r;
    cg->lights_packed = false; /* the gi pass's copy (cone shadows) too */
    push_block pc = {0};
    for (int k = 0; k < 3; k++) pc.f1[k] = (float)cg->sun[k], pc.f2[k] = (float)cg->sky[k];
    pc.f2[3] = cg->sky_dir.type != VX_SKY_DEFAULT; /* the sky by direction (binding 19) */
    pc.u1[2] = cg->d.light_count;
    double ti = 0, tf = 0;
    uint32_t n = cg->info.surface_voxels;
    cg->P.ctl[2] = 0;
    r = dispatch_n(cg, SH_INJECT, 0, &f, n, &pc, &ti, err);
    if (!r) r = filter_levels(cg, &f, false, &tf, err);
    for (uint32_t b = 1; b < cg->d.bounces && !r; b++) {
        /* each visible surface gathers the last volume's light, then all are injected again */
        r = dispatch_n(cg, SH_INJECT, 1, &f, n, &pc, &ti, err);
        cg->P.ctl[2] = 1;
        if (!r) r = dispatch_n(cg, SH_INJECT, 0, &f, n, &pc, &ti, err);
        if (!r) r = filter_levels(cg, &f, false, &tf, err);
    }
    cg->info.inject_ms = ti * 1e3, cg->info.filter_ms = tf * 1e3;
    return r;
}

vx_result vx_cone_gi_voxelize(vx_cone_gi* cg, vx_error* err) {
    if (!cg) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    vx__frame f;
    vx_result r = light_frame(cg, &f, err);
    uint32_t zero = 0;
    if (!r) r = vx__buffer_upload(cg->g, &cg->b[B_LIST], &zero, sizeof zero, err);
    if (r) return r;
    push_block pc = {0};
    double t = 0;
    if ((r = dispatch_n(cg, SH_VOXELIZE, 0, &f, cg->level0, &pc, &t, err))) return r;
    uint32_t n = 0;
    if ((r = vx__buffer_download(cg->g, &cg->b[B_LIST], &n, sizeof n, err))) return r;
    if (n > cg->level0) return vx_fail(err, VX_ERR_GPU, VX_NO_OFFSET, "the voxelizer listed %u of %llu voxels", n, (unsigned long long)cg->level0);
    cg->info.surface_voxels = n;
    cg->info.occupied_voxels = 0;
    VkDeviceSize rec = (VkDeviceSize)(n ? n : 1) * 6 * REC_VEC4 * 16;
    if ((r = vx__buffer_ensure(cg->g, &cg->b[B_REC], rec, "cone surfaces", err))) return r;
    if ((r = dispatch_n(cg, SH_VOXELIZE, 1, &f, n, &pc, &t, err))) return r;
    /* every level's opacity (and no light) over the dense pyramid, then the
     * occupied voxels' lists that relighting filters */
    if ((r = filter_levels(cg, &f, true, &t, err))) return r;
    if ((r = mark_occupied(cg, &f, &t, err))) return r;
    cg->info.voxelize_ms = t * 1e3;
    cg->info.bytes = 0;
    for (int i = 0; i < B_COUNT; i++)
        if (i != B_HALF) cg->info.bytes += cg->b[i].size;
    return inject(cg, err);
}

static void fill_method(vx_cone_gi* cg, vx_gi_method* m);

vx_result vx_cone_gi_inject(vx_cone_gi* cg, const vx_cone_desc* desc, vx_gi_method* method, vx_error* err) {
    if (!cg) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    /* only the light changes: the geometry options stay as built */
    vx_cone_desc d = cg->d;
    vx_cone_desc in = desc ? *desc : (vx_cone_desc){0};
    memcpy(d.light_dir, in.light_dir, sizeof d.light_dir);
    memcpy(d.sun, in.sun, sizeof d.sun);
    memcpy(d.sky, in.sky, sizeof d.sky);
    d.no_sun = in.no_sun, d.black_sky = in.black_sky;
    d.lights = in.lights, d.light_count = in.light_count;
    vx_cone_desc keep = cg->d;
    double kl[3], ks[3], kk[3];
    memcpy(kl, cg->light_dir, sizeof kl), memcpy(ks, cg->sun, sizeof ks), memcpy(kk, cg->sky, sizeof kk);
    vx_result r = resolve(cg, &d, err);
    if (r) {
        cg->d = keep;
        memcpy(cg->light_dir, kl, sizeof kl), memcpy(cg->sun, ks, sizeof ks), memcpy(cg->sky, kk, sizeof kk);
        return r;
    }
    r = inject(cg, err);
    if (!r && method) fill_method(cg, method);
    return r;
}

static vx_result gi_render(void* user, const vx_gi_io* io, double* gpu_seconds, vx_error* err) {
    vx_cone_gi* cg = user;
    vx__frame f;
    vx_result r = vx__frame_setup(cg->lo, cg->hi, io->frame, &f, err);
    if (r) return r;
    if (((vx__buffer*)io->out)->size < (VkDeviceSize)f.width * f.height * 16)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "the gi buffer holds less than a %ux%u image", f.width, f.height);
    push_block pc = {.u0 = {io->sample}};
    for (int k = 0; k < 3; k++) pc.f2[k] = (float)cg->sky[k];
    pc.f2[3] = cg->sky_dir.type != VX_SKY_DEFAULT;
    if (cg->d.shadows) {
        /* the direct light: the sun, and the lights packed for this frame's reference */
        for (int k = 0; k < 3; k++) pc.f1[k] = (float)cg->sun[k];
        pc.u1[2] = cg->d.light_count;
        if (cg->d.light_count && (!cg->lights_packed || memcmp(cg->lights_ref, f.ref, sizeof f.ref))) {
            vx__buffer keep = cg->b[B_LIGHTS];
            cg->b[B_LIGHTS] = (vx__buffer){0};
            r = upload_lights(cg, &f, err);
            vx__buffer_destroy(cg->g, &cg->b[B_FLIGHTS]);
            cg->b[B_FLIGHTS] = cg->b[B_LIGHTS], cg->b[B_LIGHTS] = keep;
            if (r) return r;
            memcpy(cg->lights_ref, f.ref, sizeof f.ref);
            cg->lights_packed = true;
        }
    }
    *gpu_seconds = 0;
    if (!cg->d.half_res) return dispatch(cg, SH_CONE, 0, &f, (f.width + 7) / 8, (f.height + 7) / 8, &pc, io->out, gpu_seconds, err);
    uint32_t hw = (f.width + 1) / 2, hh = (f.height + 1) / 2;
    if ((r = vx__buffer_ensure(cg->g, &cg->b[B_HALF], (VkDeviceSize)hw * hh * 32, "cone half resolution", err))) return r;
    if ((r = dispatch(cg, SH_CONE, 1, &f, (hw + 7) / 8, (hh + 7) / 8, &pc, io->out, gpu_seconds, err))) return r;
    return dispatch(cg, SH_CONE, 2, &f, (f.width + 7) / 8, (f.height + 7) / 8, &pc, io->out, gpu_seconds, err);
}

static void fill_method(vx_cone_gi* cg, vx_gi_method* m) {
    *m = (vx_gi_method){.name = "cones", .user = cg, .render = gi_render, .emit_attr = cg->emit_attr,
                        .emit_count = cg->emit_count, .lights = cg->d.lights, .light_count = cg->d.light_count,
                        .includes_direct = cg->d.shadows};
    for (int k = 0; k < 3; k++) m->light_dir[k] = cg->light_dir[k], m->sun[k] = cg->sun[k], m->sky[k] = cg->sky[k];
    if (cg->sky_dir.type != VX_SKY_DEFAULT) m->sky_dir = &cg->sky_dir, m->sky_map = &cg->sky_map;
}

/* Level sizes: level 0 covers the bounds with a voxel of margin on each
 * side (cones that leave it see the sky), each next level halves (ceil). */
static vx_result layout_volume(vx_cone_gi* cg, vx_error* err) {
    vx_cone_info* I = &cg->info;
    double ext = 0;
    for (int k = 0; k < 3; k++) ext = fmax(ext, cg->hi[k] - cg->lo[k]);
    if (!(ext > 0) || !isfinite(ext)) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "the scene is empty: nothing to trace cones through");
    double s = ext / cg->d.res;
    I->voxel = s;
    uint64_t total = 0;
    for (int k = 0; k < 3; k++) {
        double n = ceil((cg->hi[k] - cg->lo[k]) / s - 1e-9);
        I->dims[0][k] = (uint32_t)(n < 1 ? 1 : n) + 2;
        I->origin[k] = cg->lo[k] - s;
    }
    I->levels = 0;
    for (;;) {
        const uint32_t* d = I->dims[I->levels];
        cg->P.dims[I->levels][0] = d[0], cg->P.dims[I->levels][1] = d[1], cg->P.dims[I->levels][2] = d[2];
        cg->P.dims[I->levels][3] = (uint32_t)total;
        total += (uint64_t)d[0] * d[1] * d[2];
        I->levels++;
        if ((d[0] == 1 && d[1] == 1 && d[2] == 1) || I->levels == VX_CONE_LEVELS_MAX) break;
        for (int k = 0; k < 3; k++) I->dims[I->levels][k] = (d[k] + 1) / 2;
    }
    I->entries = cg->d.isotropic ? 1 : 6;
    cg->level0 = (uint64_t)I->dims[0][0] * I->dims[0][1] * I->dims[0][2];
    if (total * I->entries >= (UINT64_C(1) << 31))
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "a cone volume of %llu voxels is too large", (unsigned long long)total);
    cg->P.info[0] = I->levels, cg->P.info[1] = I->entries, cg->P.info[2] = cg->d.samples;
    cg->P.origin[3] = (float)s;
    cg->P.cone[1] = (float)cg->d.offset, cg->P.cone[2] = (float)cg->d.step, cg->P.cone[3] = (float)(cg->d.ao_distance / s);
    cg->P.ctl[1] = cg->d.output == VX_CONE_OUTPUT_AO;
    cg->P.spec[0] = (float)(1 - cos(cg->d.sun_angle * 0.5 * 3.14159265358979323846 / 180));
    cg->P.spec[1] = (float)SPEC_TAN_PER_ALPHA, cg->P.spec[2] = (float)SPEC_TAN_MAX;
    if (cg->d.shadows) cg->features |= FEAT_SHADOWS;
    cone_set(&cg->P, cg->d.cones, cg->d.aperture);
    /* the volume is an atlas (a 3D image), which the cones sample with the
     * hardware's trilinear filter: level 0 at (1, 1, 1), the others beside it
     * in x, stacked in y, every level with a zero voxel on each side (what a
     * read outside a level sees: the shaders clamp reads to half a voxel
     * beyond it); the entries stacked in z. Not a buffer: a storage buffer's
     * range stops at 4 GB (maxStorageBufferRange) and res 512 anisotropic
     * needs 9 GB (the buffer's upper part read as zero there) */
    uint32_t ax[3] = {I->dims[0][0] + 2, I->dims[0][1] + 2, 0}, y = 1;
    for (uint32_t l = 0; l < I->levels; l++) {
        uint32_t* a = cg->P.atl[l];
        a[0] = l ? I->dims[0][0] + 2 : 1, a[1] = l ? y : 1, a[2] = 1;
        if (l) {
            y += I->dims[l][1] + 1;
            if (a[0] + I->dims[l][0] + 1 > ax[0]) ax[0] = a[0] + I->dims[l][0] + 1;
            if (y > ax[1]) ax[1] = y;
        }
    }
    uint32_t zs = I->dims[0][2] + 2;
    ax[2] = zs * I->entries;
    for (int k = 0; k < 3; k++) cg->P.atlas[k] = 1.0f / (float)ax[k];
    cg->P.atlas[3] = (float)zs;
    vx_result r = vx__image3d_create(cg->g, ax, "cone atlas", &cg->b[B_ATLAS], err);
    if (!r) r = vx__buffer_create(cg->g, 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, "cone level copy", &cg->b[B_VOL], err);
    if (!r) r = vx__buffer_create(cg->g, (cg->level0 + 1) * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, "cone list", &cg->b[B_LIST], err);
    if (!r) r = vx__buffer_create(cg->g, sizeof(cone_params), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true, "cone params", &cg->b[B_PARAMS], err);
    if (!r && !cg->b[B_PARAMS].map) r = vx_fail(err, VX_ERR_GPU, VX_NO_OFFSET, "cone parameters are not host visible");
    if (!r) r = vx__buffer_create(cg->g, 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, "cone dummy", &cg->b[B_DUMMY], err);
    if (!r) r = vx__buffer_create(cg->g, 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, "cone surfaces", &cg->b[B_REC], err);
    if (!r && cg->sky_dir.type != VX_SKY_DEFAULT) r = vx__sky_buffer(cg->g, &cg->sky_dir, &cg->sky_map, cg->sky, &cg->b[B_SKY], err);
    else if (!r) r = vx__buffer_create(cg->g, 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, "cone sky", &cg->b[B_SKY], err);
    return r;
}

/* Per attribute record its material for the specular cones (cone_common.glsl
 * cmat: kind 1 metal, roughness, metalness, specular weight) and the glass
 * lobe (kind 2, roughness, ior, transmission: render/pipeline.c's records,
 * which pass_bodies.glsl reads), then the environment BRDF table; only when
 * some record is metal (the specular cones) or glass that transmits. */
static vx_result materials(vx_cone_gi* cg, const vx_svo_material_table* t, const uint16_t* ids, size_t n,
                           vx_error* err) {
    const vx_material diffuse = vx_material_default(VX_MATERIAL_DIFFUSE);
    bool metal = false, glass = false;
    for (size_t i = 0; t->specular && i < n && !(metal && glass); i++) {
        const vx_material* mt = vx_svo_material_table_find(t, ids[i]);
        metal |= mt && mt->type == VX_MATERIAL_METAL && !cg->d.no_specular;
        glass |= mt && mt->type == VX_MATERIAL_GLASS && mt->transmission > 0;
    }
    if (!metal && !glass) return VX_OK;
    if (n > UINT32_MAX - ENV_N * ENV_N) return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "%zu attribute records", n);
    size_t count = n + ENV_N * ENV_N;
    float* m = vx_calloc(cg->alloc, count, 4 * sizeof(float));
    if (!m) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %zu material records", n);
    for (size_t i = 0; i < n; i++) {
        const vx_material* f = vx_svo_material_table_find(t, ids[i]);
        vx_material mt = f ? *f : diffuse;
        float* o = m + 4 * i;
        if (mt.type == VX_MATERIAL_GLASS && mt.transmission > 0) {
            o[0] = 2.0f, o[1] = (float)mt.roughness, o[2] = (float)mt.ior, o[3] = (float)mt.transmission;
            continue;
        }
        o[0] = mt.type == VX_MATERIAL_METAL && metal ? 1.0f : 0.0f;
        o[1] = (float)mt.roughness, o[2] = (float)mt.metalness, o[3] = (float)mt.specular;
    }
    vx_ggx_albedo_table(ENV_N, m + 4 * n); /* render/pipeline.h */
    vx_result r = vx__buffer_create(cg->g, count * 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, "cone materials",
                                    &cg->b[B_MAT], err);
    if (!r) r = vx__buffer_upload(cg->g, &cg->b[B_MAT], m, count * 16, err);
    vx_free(cg->alloc, m);
    if (r) return r;
    cg->P.ctl[3] = (uint32_t)n;
    if (metal) cg->features |= FEAT_SPEC, cg->info.specular = true;
    /* glass: pass_bodies.glsl's LIGHTS bits 10 (glass) and 2-7 (the lights with a shadow ray, the direct
     * pass's default), bit 8 where records emit (its emission table is the cones' binding 14) */
    if (glass)
        cg->glass_lights = 1u << 10 | (uint32_t)VX_SHADOW_LIGHTS_DEFAULT << 2 | (cg->emit_count ? 1u << 8 : 0u);
    return VX_OK;
}

/* The emission's terms per attribute record (the scene's materials, vx_material_emitted_terms), and the
 * materials of the specular cones. */
static vx_result emission(vx_cone_gi* cg, vx_error* err) {
    uint16_t* pal = NULL; /* material ids per record */
    size_t n = 0;
    vx_svo_material_table t = {0};
    vx_result r = vx__render_scene_attr_material(cg->rs, cg->scene, cg->alloc, &pal, &n, err);
    if (!r) r = vx_svo_material_table_make(cg->scene, cg->alloc, &t, err);
    if (r) {
        vx_free(cg->alloc, pal);
        return r;
    }
    r = vx_svo_material_table_emission_records(&t, pal, n, cg->alloc, &cg->emit_attr, &cg->emit_count, err);
    if (!r) r = materials(cg, &t, pal, n, err);
    vx_free(cg->alloc, pal);
    vx_svo_material_table_free(&t);
    size_t ne = cg->emit_count ? cg->emit_count : 1; /* one zero record where nothing emits */
    if (!r) r = vx__buffer_create(cg->g, ne * 4 * sizeof(float), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, "cone emission",
                          &cg->b[B_EMIT], err);
    if (!r) r = vx__buffer_upload(cg->g, &cg->b[B_EMIT], cg->emit_attr, ne * 4 * sizeof(float), err);
    return r;
}

vx_result vx_cone_gi_create(vx_render_scene* rs, const vx_svo_scene* scene, const vx_cone_desc* desc,
                            vx_gi_method* method, vx_cone_gi** out, vx_error* err) {
    if (!rs || !scene || !method || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    *out = NULL;
    vx_cone_gi* cg = vx_calloc(scene->alloc, 1, sizeof *cg);
    if (!cg) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    cg->alloc = scene->alloc, cg->rs = rs, cg->scene = scene, cg->g = vx__render_scene_gpu(rs);
    vx_svo_scene_world_bounds(scene, cg->lo, cg->hi);
    vx_result r = resolve(cg, desc, err);
    if (!r) r = layout_volume(cg, err);
    if (!r) r = emission(cg, err);
    if (!r) r = vx_cone_gi_voxelize(cg, err);
    if (r) {
        vx_cone_gi_destroy(cg);
        return r;
    }
    fill_method(cg, method);
    *out = cg;
    return VX_OK;
}

void vx_cone_gi_destroy(vx_cone_gi* cg) {
    if (!cg) return;
    for (int i = 0; i < B_COUNT; i++) vx__buffer_destroy(cg->g, &cg->b[i]);
    vx_free(cg->alloc, cg->emit_attr);
    vx_free(cg->alloc, cg);
}

void vx_cone_gi_info(const vx_cone_gi* cg, vx_cone_info* out) {
    if (cg && out) *out = cg->info;
}

vx_result vx_cone_gi_read_level(vx_cone_gi* cg, uint32_t level, float* out, size_t floats, vx_error* err) {
    if (!cg || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    if (level >= cg->info.levels)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "level %u of a volume of %u levels", level, cg->info.levels);
    const uint32_t* d = cg->info.dims[level];
    size_t n = (size_t)d[0] * d[1] * d[2] * cg->info.entries;
    if (floats < 4 * n) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "level %u needs %zu floats, got %zu", level, 4 * n, floats);
    /* the level copied out of the atlas (filter.comp STAGE 5), then downloaded */
    uint16_t* h = vx_alloc(cg->alloc, n * 8);
    if (!h) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %zu voxels", n);
    vx__frame f;
    vx_result r = vx__buffer_ensure(cg->g, &cg->b[B_VOL], n * 8, "cone level copy", err);
    if (!r) r = light_frame(cg, &f, err);
    push_block pc = {.u2 = {level}};
    if (!r) r = dispatch_n(cg, SH_FILTER, 5, &f, (uint64_t)d[0] * d[1] * d[2], &pc, NULL, err);
    if (!r) r = vx__buffer_download(cg->g, &cg->b[B_VOL], h, n * 8, err);
    for (size_t i = 0; !r && i < 4 * n; i++) out[i] = vx_probe_half_to_float(h[i]);
    vx_free(cg->alloc, h);
    return r;
}
