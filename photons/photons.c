/* photons/photons.c - photon mapping on the GPU (photons/photons.h): the
 * sources table, the buffers, the passes (trace, grid build, gather) and the
 * pipeline's gi method. The GPU side is photons/shaders/photon.comp. */
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "photons/photons.h"
#include "probes/light.h"
#include "render/gpu.h"

#include "photon.comp.h" /* shaders/photon.comp, embedded at build time */
#include "photon_small.comp.h" /* the same without the trace and the camera's paths (-DPHOTON_SMALL) */

static const double pi = 3.14159265358979323846;

/* std430 block "Params" of photon.comp */
typedef struct gpu_params {
    uint32_t a[4];    /* photons, capacity, stored bounces, buckets */
    uint32_t seed[4]; /* seed lo, hi, pass, sources */
    float r[4];       /* global radius, caustic radius, 1 / (pi rg^2), 1 / (pi rc^2) */
    uint32_t img[4];  /* width, height, running mean, full */
    float sphere[4];  /* bounding sphere centre (relative to the reference), radius */
    float sky[4];     /* sky radiance (render/shaders/sky.glsl zen), w: emissive voxels' power */
    uint32_t cnt[4];  /* emissive voxels, 2 (loops_intact), final gather rays, a light stands for the voxels */
    float skyh[4], skyg[4], skym[4]; /* the sky by direction: sky.glsl's hor, gnd, map (vx__sky_pack) */
    float fx[4];      /* the gather's fixed-point units (photon.comp fx_add): x per unit of BSDF times power, y of power */
    uint32_t tr[4];   /* x: invocations of the trace */
    uint32_t fu[4];   /* x: the density step's records' first vec4 in Photons, y: 0, z: the pixels' steps'
                         workgroups (STEP_SIZE) */
} gpu_params;
_Static_assert(sizeof(gpu_params) == 208, "gpu_params vs photon.comp");

enum { STEP_CLEAR = 0, STEP_TRACE, STEP_COUNT, STEP_ALLOC, STEP_SCATTER, STEP_GATHER, STEP_RESET, STEP_DENSITY,
       STEP_SIZE = 9 };
/* Counters (photon.comp binding 16), in bytes: the counters, then STEP_SIZE's group counts of the indirect
 * dispatches (the buckets' steps and at 28 the buckets, the stored photons' steps, the pixels' steps) */
enum { CTR_BUCKETS = 16, CTR_BUCKET_COUNT = 28, CTR_STORED = 32, CTR_PIXELS = 48, CTR_BYTES = 64 };
enum { NBIND = 19, SRC_FLOATS = 24, PHOTON_BYTES = 32, FACE_FLOATS = 20 };
/* The kernel's area (photon.comp kernel_factors) looks up some 2 x 33 cells a pixel at the seed's Cornell
 * setting (radius 2.56 cells), each a walk down the octree: about 1 ms of a 7.2-ms pass on the H200. Models
 * of at most 2^OCC_DEPTH cells a side get one bit a cell instead (photon.comp cell_solid), OCC_BITS bits in
 * all at most; the others keep the walk. Beyond about 350 cells a side the default radius (the diagonal /
 * 100) passes KERNEL_CELLS cells and no lookup is made. */
enum { OCC_DEPTH = 9 };
#define OCC_BITS (UINT64_C(1) << 28)
/* Lanes per pixel of the density step (photon.comp DPARTS; its workgroups take 64 x this): 8 where the
 * image has fewer tiles of 8 x 8 pixels than DENSITY_FEW_TILES (about two waves of 64-lane workgroups on a
 * large GPU: the H200 holds 132 x 32), whose time the densest tiles set, 4 on a device whose workgroups
 * cannot take 512 lanes and their 64 bytes of shared memory each; 1 where they fill many waves (H200:
 * 512x512 density 3.33 -> 1.91 ms with 4, 1.25 -> 1.16 with 8; 1920x1080 caustic 1.39 -> 2.78 ms with 4) */
enum { DENSITY_PARTS = 8, DENSITY_FEW_TILES = 8192 };
/* source types of photon.comp (0-4 are vx_light_type) */
enum { SRC_SKY = 5, SRC_VOXELS = 6 };

struct vx_photon_gi {
    vx_render_scene* rs;
    const vx_svo_scene* scene;
    vx_gpu* g;
    vx_photon_desc d; /* resolved */
    vx__prender P;    /* the light (as the probe renderer resolves it) and the scene's bounds */
    float* emit_attr;
    size_t emit_count;
    double* faces;       /* the emissive voxels' exposed faces (FACE_FLOATS each, photon.comp's layout, world) */
    uint32_t face_count;
    double face_power;   /* sum of lum(radiance) * area over the faces */
    double total_power;  /* the sources' luminance power (the photons' fixed-point unit follows it) */
    double centre[3], sphere_r;
    uint32_t buckets, sources;
    uint32_t density_parts; /* lanes per pixel of this pass's density step (DENSITY_PARTS or 1) */
    uint32_t kinds; /* photons a pass can store: 1 caustic ones from a light camera rays cannot meet (F_LIGHT),
                     * 2 ones a direct-pass light brought (F_DIRECT); photon.comp skips the sums of those it cannot */
    bool glossy_diffuse; /* some material is glossy with a diffuse lobe (its photon sums run in the camera's paths) */
    bool tables_for_ref; /* sources and emitters uploaded for ref */
    double ref[3];
    uint32_t spec[VX__SPEC_TRACE_IDS]; /* the tracer's, then STEP, MATS and GROUP, DEEP, FAR and COMPACT (gpu.h) */
    vx__buffer* scene_bufs[7];
    vx__buffer params, emit, mats, src, ems, photons, sorted, cells, counters, img, env;
    vx__buffer occ; /* the models' cells, a bit each: per model its first word (UINT32_MAX: none), then the bits */
    vx__buffer readback; /* host visible: the counters at the end of a pass's submission */
    vx_photon_stats last;
    const vx_allocator* alloc;
};

vx_photon_desc vx_photon_desc_defaults(void) {
    return (vx_photon_desc){.photons = 1u << 20, .alpha = 2.0 / 3.0, .bounces = 8, .capacity = 0, .workgroup = 32, .batch = 0};
}

/* The sky's mean radiance over the sphere of directions (a grid of 256 x 128
 * directions, weighted by solid angle): the uniform sky's radiance, or the
 * mean of the sky by direction (the share of the photons it sends). */
static void sky_mean(const vx__light* L, double out[3]) {
    out[0] = out[1] = out[2] = 0;
    if (L->sky_dir.type == VX_SKY_DEFAULT) {
        memcpy(out, L->sky, 3 * sizeof *out);
        return;
    }
    enum { GW = 256, GH = 128 };
    double wsum = 0;
    for (int y = 0; y < GH; y++) {
        double th = (y + 0.5) * pi / GH, w = sin(th);
        for (int x = 0; x < GW; x++) {
            double ph = (x + 0.5) * 2 * pi / GW, d[3] = {sin(th) * cos(ph), sin(th) * sin(ph), cos(th)}, v[3];
            vx__sky(L, d, v);
            for (int k = 0; k < 3; k++) out[k] += w * v[k];
            wsum += w;
        }
    }
    for (int k = 0; k < 3; k++) out[k] /= wsum;
}

/* The exposed faces of the emissive voxels: a face emits when the cell
 * beyond it is empty in its model (faces on the model's boundary emit), as
 * svo/svo_emissive.c counts a cluster's power. Photons leave these faces
 * only; the probes' emitter table (vx__light em) samples all six faces of a
 * voxel, and a photon from a buried face was lost (5% of the photons were
 * stored on the caustic scene). The radiance is the path tracer's
 * (probes/light.c em_voxel: colour times its material's emission). */
typedef struct face_ctx {
    vx_photon_gi* pg;
    const vx_svo_model* m;
    double w[12];
    size_t cap;
    vx_result r;
} face_ctx;

static bool face_voxel(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    face_ctx* F = user;
    vx_photon_gi* pg = F->pg;
    const vx__light* L = &pg->P.L;
    const vx_svo_model* m = F->m;
    double rad[3];
    if (!vx__light_voxel_radiance(L, pg->scene, m, attr, rad)) return true;
    double l = 0.2126 * rad[0] + 0.7152 * rad[1] + 0.0722 * rad[2];
    if (!(l > 0) || !isfinite(l)) return true;
    uint32_t p[3] = {x, y, z};
    double corner[3], ax[3][3];
    for (int k = 0; k < 3; k++) corner[k] = F->w[4 * k] * x + F->w[4 * k + 1] * y + F->w[4 * k + 2] * z + F->w[4 * k + 3];
    for (int a = 0; a < 3; a++)
        for (int k = 0; k < 3; k++) ax[a][k] = F->w[4 * k + a];
    for (int a = 0; a < 3; a++)
        for (int side = 0; side < 2; side++) {
            uint32_t q[3] = {p[0], p[1], p[2]};
            if (side) q[a]++;
            else if (q[a] == 0) goto exposed;
            else q[a]--;
            if (vx_svo_model_cell_set(m, q[0], q[1], q[2])) continue;
        exposed:
            if (pg->face_count >= (1u << 24)) { /* 80 bytes each on the GPU: 1.3 GB */
                F->r = VX_ERR_LIMIT;
                return false;
            }
            if (!vx_grow(pg->alloc, (void**)&pg->faces, &F->cap, ((size_t)pg->face_count + 1) * FACE_FLOATS, sizeof(double))) {
                F->r = VX_ERR_NOMEM;
                return false;
            }
            const double *u = ax[(a + 1) % 3], *v = ax[(a + 2) % 3], *e = ax[a];
            double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
            double area = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), edge = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
            double out = (n[0] * e[0] + n[1] * e[1] + n[2] * e[2]) * (side ? 1 : -1) < 0 ? -1 : 1;
            double* o = pg->faces + (size_t)FACE_FLOATS * pg->face_count++;
            for (int k = 0; k < 3; k++) {
                o[k] = corner[k] + side * e[k]; /* world here; relative to the frame's ref on upload */
                o[4 + k] = u[k], o[8 + k] = v[k], o[12 + k] = out * n[k] / area, o[16 + k] = rad[k];
            }
            o[3] = area, o[15] = edge, o[11] = o[19] = 0;
            o[7] = l * area; /* the face's power; the alias table's probability on upload */
            pg->face_power += l * area;
        }
    return true;
}

static vx_result make_faces(vx_photon_gi* pg, vx_error* err) {
    const vx_svo_scene* s = pg->scene;
    bool any = pg->P.L.mt.emissive;
    face_ctx F = {.pg = pg};
    for (uint32_t i = 0; any && i < s->instance_count && !F.r; i++) {
        if (!vx_svo_instance_drawn(s, i)) continue;
        F.m = &s->models[s->instances[i].model];
        vx_svo_instance_world(s, &s->instances[i], F.w);
        vx_result r = vx_svo_decode_model(F.m, face_voxel, &F, err);
        if (r && !F.r) return r;
    }
    if (F.r == VX_ERR_LIMIT)
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "photons: more than 2^24 exposed emissive voxel faces");
    if (F.r) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u emissive faces", pg->face_count);
    if (!(pg->face_power > 0) || !isfinite(pg->face_power)) pg->face_count = 0, pg->face_power = 0;
    return VX_OK;
}

static vx_result upload_new(vx_gpu* g, vx__buffer* b, const void* data, size_t size, const char* label,
                            vx_error* err) {
    vx_result r = vx__buffer_create(g, size, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, label, b, err);
    if (!r && data) r = vx__buffer_upload(g, b, data, size, err);
    return r;
}

/* The cell bits of the models (OCC_DEPTH above): from word occ[i] of model i on, bit x + side (y + side z)
 * says whether its cell (x, y, z) is set, as model_cell_attr finds it (vx_svo_decode_model visits exactly
 * the set cells, collapsed leaves expanded); where the scene has glass, as many words after them say
 * whether the cell is glass (photon.comp is_glass of its record: the glass walk's next cell, one load
 * where model_cell_attr walks the octree; cornell's glass sphere took two thirds of the trace). */
typedef struct occ_ctx {
    uint32_t *bits, *glass;
    uint32_t side;
    const uint8_t* is_glass; /* per attribute record of the model, or NULL */
} occ_ctx;

static bool occ_voxel(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    occ_ctx* O = user;
    uint64_t i = x + (uint64_t)O->side * (y + (uint64_t)O->side * z);
    O->bits[i >> 5] |= 1u << (i & 31);
    if (O->is_glass && O->is_glass[attr]) O->glass[i >> 5] |= 1u << (i & 31);
    return true;
}

/* mats: the packed materials of the attribute records (vx__pack_materials, the models' records one model
 * after another, as vx__scene_attr_material counts them), nm records, 0: none */
static vx_result make_occ(vx_photon_gi* pg, const float* mats, size_t nm, vx_error* err) {
    const vx_svo_scene* s = pg->scene;
    uint8_t* glass = vx_calloc(pg->alloc, nm ? nm : 1, 1);
    if (!glass) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %zu glass flags", nm);
    bool any_glass = false;
    for (size_t i = 0; i < nm; i++) /* photon.comp / path_common.glsl is_glass */
        any_glass |= glass[i] = mats[8 * i] == 2.0f && mats[8 * i + 5] > 0.0f;
    uint64_t words = s->model_count ? s->model_count : 1, bits = 0;
    uint32_t* w = NULL;
    vx_result r = VX_OK;
    for (int fill = 0; fill < 2 && !r; fill++) {
        uint64_t at = s->model_count, rec = 0;
        bits = 0;
        for (uint32_t i = 0; i < s->model_count && !r; i++) {
            const vx_svo_model* m = &s->models[i];
            uint64_t side = UINT64_C(1) << (m->depth <= OCC_DEPTH ? m->depth : 0), n = side * side * side;
            uint64_t nw = (n + 31) / 32 * (any_glass ? 2 : 1);
            bool used = m->attrs && m->depth <= OCC_DEPTH && m->root != VX_SVO_ROOT_EMPTY && bits + n <= OCC_BITS;
            if (used) bits += n;
            if (fill) {
                w[i] = used ? (uint32_t)at : UINT32_MAX;
                occ_ctx O = {.bits = w + at, .glass = w + at + (n + 31) / 32, .side = (uint32_t)side,
                             .is_glass = any_glass && rec + m->attr_count <= nm ? glass + rec : NULL};
                if (used) r = vx_svo_decode_model(m, occ_voxel, &O, err);
            }
            if (used) at += nw;
            if (m->attrs) rec += m->attr_count;
        }
        if (!fill) {
            words = at;
            if (!(w = vx_calloc(pg->alloc, words, sizeof *w)))
                r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %llu cell words", (unsigned long long)words);
        }
    }
    if (!r) r = upload_new(pg->g, &pg->occ, w, words * sizeof *w, "photon cells", err);
    vx_free(pg->alloc, w);
    vx_free(pg->alloc, glass);
    return r;
}

static double lum(const double c[3]) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }

/* Integral of a spot's falloff squared over its cone, per steradian of the
 * cone: E[sp^2] for directions uniform in the outer cone (midpoint rule in
 * cos theta, where the cone's solid angle is uniform). */
static double spot_mean(double sc, double off, double co) {
    enum { N = 1024 };
    double s = 0;
    for (int i = 0; i < N; i++) {
        double c = co + (1 - co) * (i + 0.5) / N, sp = fmin(1, fmax(0, c * sc + off));
        s += sp * sp;
    }
    return s / N;
}

/* Walker's alias table over the faces' powers (Vose's construction), into
 * the emitter table e: slot i (drawn uniformly) gives face i with
 * probability e[i].prob, else face e[i].alias; a face in O(1), where a
 * binary search over the cdf took log2(faces) dependent reads per photon. */
static bool alias_table(vx_photon_gi* pg, float* e) {
    size_t n = pg->face_count;
    double* p = vx_alloc(pg->alloc, n * sizeof *p);
    uint32_t* w = vx_alloc(pg->alloc, n * sizeof *w); /* the small slots from the front, the large from the back */
    if (!p || !w) {
        vx_free(pg->alloc, p);
        vx_free(pg->alloc, w);
        return false;
    }
    size_t ns = 0, nl = 0;
    for (size_t i = 0; i < n; i++) {
        p[i] = pg->faces[(size_t)FACE_FLOATS * i + 7] * (double)n / pg->face_power;
        if (p[i] < 1) w[ns++] = (uint32_t)i;
        else w[n - 1 - nl++] = (uint32_t)i;
    }
    for (size_t i = 0; i < n; i++) e[FACE_FLOATS * i + 7] = 1.0f; /* prob (slots left at the end: 1, rounding) */
    for (size_t i = 0; i < n; i++) memcpy(&e[FACE_FLOATS * i + 11], &(uint32_t){(uint32_t)i}, 4);
    while (ns && nl) {
        uint32_t sm = w[--ns], lg = w[n - nl];
        e[FACE_FLOATS * (size_t)sm + 7] = (float)p[sm];
        memcpy(&e[FACE_FLOATS * (size_t)sm + 11], &lg, 4);
        p[lg] = (p[lg] + p[sm]) - 1;
        if (p[lg] < 1) nl--, w[ns++] = lg;
    }
    vx_free(pg->alloc, p);
    vx_free(pg->alloc, w);
    return true;
}

/* The sources table and the emissive voxels relative to ref (photon.comp's
 * Sources and Emitters). Power in luminance picks the source. */
static vx_result upload_sources(vx_photon_gi* pg, const double ref[3], vx_error* err) {
    const vx__light* L = &pg->P.L;
    uint32_t n = 0, cap = 2 + L->light_count + 1;
    float* s = vx_calloc(pg->alloc, cap, SRC_FLOATS * sizeof(float));
    double* pw = vx_calloc(pg->alloc, cap, 4 * sizeof(double)); /* rgb power, luminance */
    size_t ne = pg->face_count;
    float* e = vx_calloc(pg->alloc, ne ? FACE_FLOATS * ne : 4, sizeof(float));
    vx_result r = VX_OK;
    if (!s || !pw || !e) {
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for the photon sources");
        goto done;
    }
    double R = pg->sphere_r, disk = pi * R * R;
    /* the sun: a directional source of irradiance sun */
    if (L->sun[0] > 0 || L->sun[1] > 0 || L->sun[2] > 0) {
        float* o = s + SRC_FLOATS * n;
        for (int k = 0; k < 3; k++) o[4 + k] = (float)L->light_dir[k], pw[4 * n + k] = L->sun[k] * disk;
        o[3] = VX_LIGHT_DIRECTIONAL, o[21] = 1;
        n++;
    }
    /* the sky: photons from directions uniform on the sphere; by direction
     * (gradient, map), a photon's power is scaled by the sky's radiance
     * towards it over the mean radiance (e.xyz), which sets the source's power */
    double mean[3];
    sky_mean(L, mean);
    if (mean[0] > 0 || mean[1] > 0 || mean[2] > 0) {
        float* o = s + SRC_FLOATS * n;
        for (int k = 0; k < 3; k++) pw[4 * n + k] = mean[k] * 4 * pi * disk, o[12 + k] = mean[k] > 0 ? (float)(1 / mean[k]) : 0.f;
        o[3] = SRC_SKY;
        n++;
    }
    for (uint32_t j = 0; j < L->light_count; j++) {
        const vx_light* li = &L->lights[j];
        if (li->flags & VX_LIGHT_FROM_VOXELS) continue; /* the voxels emit themselves */
        float* o = s + SRC_FLOATS * n;
        double nd[3], t[3], dl = 0, tn = 0, tl = 0, c[3];
        for (int k = 0; k < 3; k++) dl += li->direction[k] * li->direction[k];
        dl = sqrt(dl);
        for (int k = 0; k < 3; k++) nd[k] = dl > 0 ? li->direction[k] / dl : 0, tn += li->tangent[k] * nd[k];
        for (int k = 0; k < 3; k++) t[k] = li->tangent[k] - tn * nd[k], tl += t[k] * t[k];
        tl = sqrt(tl);
        for (int k = 0; k < 3; k++) {
            o[k] = (float)(li->position[k] - ref[k]);
            o[4 + k] = (float)nd[k];
            o[16 + k] = tl > 0 ? (float)(t[k] / tl) : 0.0f;
            c[k] = li->color[k] * li->intensity;
        }
        o[3] = (float)li->type, o[7] = (float)li->range, o[15] = (float)li->radius, o[21] = 1;
        double f = 0; /* power per unit of colour * intensity */
        switch (li->type) {
        case VX_LIGHT_DIRECTIONAL:
            f = disk;
            o[14] = (float)(1 - cos(0.5 * li->angular_diameter));
            break;
        case VX_LIGHT_POINT: f = 4 * pi; break;
        case VX_LIGHT_SPOT: {
            double ci = cos(li->inner_cone), co = cos(li->outer_cone), sc = 1.0 / fmax(0.001, ci - co);
            o[12] = (float)sc, o[13] = (float)(-co * sc), o[14] = (float)(1 - co);
            /* the photon's power is multiplied by the falloff in the shader: its mean is in the
             * probability only */
            f = 2 * pi * (1 - co);
            pw[4 * n + 3] = lum(c) * f * spot_mean(sc, -co * sc, co);
            break;
        }
        case VX_LIGHT_SPHERE: f = pi * 4 * pi * li->radius * li->radius; break;
        case VX_LIGHT_RECT:
            f = pi * li->size[0] * li->size[1];
            o[19] = (float)li->size[0], o[20] = (float)li->size[1];
            break;
        default: break;
        }
        for (int k = 0; k < 3; k++) pw[4 * n + k] = c[k] * f;
        n++;
    }
    if (ne) {
        float* o = s + SRC_FLOATS * n;
        o[3] = SRC_VOXELS, o[21] = L->voxel_lights; /* direct when a light stands for them */
        for (int k = 0; k < 3; k++) pw[4 * n + k] = pi * pg->face_power; /* scaled by rad / lum(rad) per face */
        n++;
        for (size_t i = 0; i < ne; i++) {
            float* q = e + FACE_FLOATS * i;
            const double* f = pg->faces + FACE_FLOATS * i;
            for (int k = 0; k < FACE_FLOATS; k++) q[k] = (float)(k < 3 ? f[k] - ref[k] : f[k]);
        }
        if (!alias_table(pg, e)) {
            r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for the alias table of %zu faces", ne);
            goto done;
        }
    }
    double total = 0;
    for (uint32_t i = 0; i < n; i++) {
        if (!(pw[4 * i + 3] > 0)) pw[4 * i + 3] = lum(pw + 4 * i);
        if (!(pw[4 * i + 3] > 0) || !isfinite(pw[4 * i + 3])) pw[4 * i + 3] = 0;
        total += pw[4 * i + 3];
    }
    double acc = 0;
    for (uint32_t i = 0; i < n; i++) {
        float* o = s + SRC_FLOATS * i;
        double p = total > 0 ? pw[4 * i + 3] / total : 0;
        acc += p;
        /* a source never picked keeps power 0; the last cdf entry is 1 whatever the rounding */
        for (int k = 0; k < 3; k++) o[8 + k] = p > 0 ? (float)(pw[4 * i + k] / p) : 0.0f;
        o[11] = i + 1 == n ? 1.0f : (float)acc;
    }
    vx__buffer_destroy(pg->g, &pg->src);
    vx__buffer_destroy(pg->g, &pg->ems);
    if ((r = upload_new(pg->g, &pg->src, s, (n ? n : 1) * SRC_FLOATS * sizeof(float), "photon sources", err)) ||
        (r = upload_new(pg->g, &pg->ems, e, ne ? FACE_FLOATS * sizeof(float) * ne : 16, "photon emitters", err)))
        goto done;
    pg->sources = total > 0 ? n : 0;
    pg->total_power = total;
    pg->kinds = 0;
    for (uint32_t i = 0; i < n; i++) {
        if (!(pw[4 * i + 3] > 0)) continue; /* never picked */
        if (s[SRC_FLOATS * i + 3] < SRC_SKY) pg->kinds |= 1;
        if (s[SRC_FLOATS * i + 21] != 0) pg->kinds |= 2;
    }
done:
    vx_free(pg->alloc, s);
    vx_free(pg->alloc, pw);
    vx_free(pg->alloc, e);
    return r;
}

/* A pass's steps recorded into one submission (vx__seq), each step's GPU ms added into its stats field after
 * the wait. */
typedef struct pass_rec {
    vx__seq seq;
    double* into[VX__SEQ_MAX];
    bool open;
} pass_rec;

static vx_result rec_begin(vx_photon_gi* pg, pass_rec* q, vx_error* err) {
    vx_result r = vx__seq_begin(pg->g, &q->seq, err);
    q->open = !r;
    return r;
}

/* Records step st over items invocations, or with ind >= 0 over the group counts STEP_SIZE wrote at byte ind of
 * the counters (items then unused). */
static vx_result step(vx_photon_gi* pg, pass_rec* q, int st, uint64_t items, int ind, vx__buffer* out, double* ms,
                      vx_error* err) {
    if (!items && ind < 0) return VX_OK;
    /* the trace's workgroup is the desc's (a tuning knob photons_bench measures); the density step's 64 lanes a
     * tile times its parts; the other steps' 64 */
    uint32_t wg = st == STEP_TRACE ? pg->d.workgroup : (st == STEP_DENSITY ? 64 * pg->density_parts : 64);
    pg->spec[VX__SPEC_COUNT] = (uint32_t)st, pg->spec[VX__SPEC_COUNT + 2] = wg;
    /* the trace and the camera's paths from the whole module, the other steps from the one without them (the
     * same code for those steps; a driver translates the whole module for every pipeline: photon.comp) */
    bool whole = st == STEP_TRACE || st == STEP_GATHER;
    vx_gpu_compute_pipeline_desc pd = {.spirv = whole ? vx__photon_spv_arr : vx__photon_small_spv_arr,
                                       .spirv_size = whole ? sizeof vx__photon_spv_arr : sizeof vx__photon_small_spv_arr,
                                       .binding_count = NBIND, .spec_count = VX__SPEC_TRACE_IDS,
                                       .label = whole ? "photon" : "photon (small step)"};
    pd.bindings[0] = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    for (uint32_t i = 1; i < NBIND; i++) pd.bindings[i] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    memcpy(pd.spec, pg->spec, sizeof pg->spec);
    uint64_t key = vx__spec_key(0x9407035ull, pg->spec, VX__SPEC_TRACE_IDS);
    vx__pipeline* p;
    vx_result r = vx__pipeline_get(pg->g, key, &pd, &p, err);
    if (r) return r;
    /* photon.comp S_SIZE splits its group counts the same way */
    uint64_t groups = (items + wg - 1) / wg;
    uint32_t gx = groups < 4096 ? (uint32_t)groups : 4096, gy = gx ? (uint32_t)((groups + gx - 1) / gx) : 0;
    vx__dispatch_desc dd = {.pipeline = p, .buffer_count = NBIND, .groups = {gx, gy, 1}, .label = "photon"};
    for (int i = 0; i < 7; i++) dd.buffers[i] = pg->scene_bufs[i];
    vx__buffer* own[] = {&pg->params, &pg->emit, &pg->mats, &pg->src, &pg->ems, &pg->photons,
                         &pg->sorted, &pg->cells, out,        &pg->counters, &pg->env, &pg->occ};
    for (int i = 0; i < 12; i++) dd.buffers[7 + i] = own[i];
    q->into[q->seq.count] = ms;
    return vx__seq_dispatch(pg->g, &q->seq, &dd, ind >= 0 ? &pg->counters : NULL, ind >= 0 ? (VkDeviceSize)ind : 0,
                            err);
}

/* Submits the recorded steps with a copy of the counters into pg->readback last, waits, adds the steps' GPU ms. */
static vx_result rec_submit(vx_photon_gi* pg, pass_rec* q, vx_error* err) {
    vx__seq_copy(pg->g, &q->seq, &pg->counters, 0, &pg->readback, 0, 16);
    q->open = false;
    vx_result r = vx__seq_submit(pg->g, &q->seq, err);
    for (uint32_t k = 0; !r && k < q->seq.count; k++) *q->into[k] += q->seq.seconds[k] * 1e3;
    return r;
}

static void rec_abandon(vx_photon_gi* pg, pass_rec* q) {
    if (q->open) vx__seq_abandon(pg->g, &q->seq);
    q->open = false;
}

/* The steps after the trace, sized on the GPU from the photons stored (STEP_SIZE): the buckets this pass uses
 * follow the photons stored (at least twice as many, a power of two; clearing and claiming ranges over buckets
 * sized for the capacity cost 2.4 ms a pass at 10M photons where 5% were stored), copied into Params for the
 * steps after; a pass whose stores passed the capacity gets no group at all (run_pass traces it again). */
static vx_result record_rest(vx_photon_gi* pg, pass_rec* q, bool fused, vx__buffer* out, vx_photon_stats* st,
                             double* build, vx_error* err) {
    vx_result r = step(pg, q, STEP_SIZE, 1, -1, out, build, err);
    if (r) return r;
    vx__seq_copy(pg->g, &q->seq, &pg->counters, CTR_BUCKET_COUNT, &pg->params, offsetof(gpu_params, a) + 12, 4);
    if (!r) r = step(pg, q, STEP_CLEAR, 0, CTR_BUCKETS, out, build, err);
    if (!r) r = step(pg, q, STEP_COUNT, 0, CTR_STORED, out, build, err);
    if (!r) r = step(pg, q, STEP_ALLOC, 0, CTR_BUCKETS, out, build, err);
    if (!r) r = step(pg, q, STEP_SCATTER, 0, CTR_STORED, out, build, err);
    if (!r && !fused) r = step(pg, q, STEP_GATHER, 0, CTR_PIXELS, out, &st->paths_ms, err);
    if (!r) r = step(pg, q, STEP_DENSITY, 0, CTR_PIXELS, out, &st->density_ms, err);
    return r;
}

static uint32_t pow2_at_least(uint64_t n) {
    uint32_t b = 1;
    while (b < n && b < (1u << 31)) b <<= 1;
    return b;
}

/* The radius of pass k: r_k^2 = r_0^2 prod_{i=1..k} (i + alpha) / (i + 1). */
static double pass_radius(double r0, double alpha, uint32_t k) {
    double f = 1;
    for (uint32_t i = 1; i <= k; i++) f *= (i + alpha) / (i + 1);
    return r0 * sqrt(f);
}

/* Photons 0..n-1 of the pass to trace (each carries 1/n of the sources' power): the trace's
 * invocations and the gather's fixed-point units. */
static void set_emitted(const vx_photon_gi* pg, gpu_params* p, uint32_t n) {
    p->a[0] = n;
    /* batch 0: 4 photons an invocation, fewer while that leaves under 2^17 invocations (H200: 500k
     * photons traced in 3.25 ms at 2 and 1, 3.38 ms at 4; 1M and 10M fastest at 4) */
    uint32_t batch = pg->d.batch;
    if (!batch)
        for (batch = 4; batch > 1 && n / batch < (1u << 17);) batch /= 2;
    p->tr[0] = (uint32_t)(((uint64_t)n + batch - 1) / batch);
    /* the gather's fixed-point unit: 2^-32 of an emitted photon's (luminance) power */
    double unit = pg->total_power > 0 && n ? pg->total_power / n : 1;
    p->fx[0] = (float)(4294967296.0 / unit);
    /* a Lambert surface's sums of powers: 2^-27 of it (a photon of up to 32 emitted photons' power, as
     * a saturated colour's channel has, adds in one word) */
    p->fx[1] = (float)(134217728.0 / unit);
    for (int k = 0; k < 2; k++)
        if (!(p->fx[k] > 0) || !isfinite(p->fx[k])) p->fx[k] = 1;
}

/* One pass: photons traced, both grids built, the estimate written into out
 * (running mean over the passes when mean). */
static vx_result run_pass(vx_photon_gi* pg, const vx_render_desc* frame, uint32_t pass, vx__buffer* out, bool mean,
                          bool full, double* seconds, vx_error* err) {
    double t0 = vx_time_now();
    vx_render_desc base = frame ? *frame : (vx_render_desc){0};
    base.mode = VX_RENDER_COLOR, base.spp = 1, base.lod = false;
    vx__frame f;
    vx_result r = vx__frame_setup(pg->P.lo, pg->P.hi, &base, &f, err);
    if (r) return r;
    size_t npx = (size_t)f.width * f.height;
    if (out->size < npx * 16)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "a buffer of %llu bytes holds less than a %ux%u image",
                       (unsigned long long)out->size, f.width, f.height);
    if ((r = vx__render_scene_bind(pg->rs, &f, pg->scene_bufs, pg->spec, err))) return r;
    if (!pg->tables_for_ref || memcmp(pg->ref, f.ref, sizeof pg->ref)) {
        if ((r = upload_sources(pg, f.ref, err))) return r;
        memcpy(pg->ref, f.ref, sizeof pg->ref);
        pg->tables_for_ref = true;
    }
    /* The camera's paths need no photon where every sum they make is a Lambert surface's, deferred to the
     * density step (no final gather, no G_LIGHTS sums, no glossy surface with a diffuse lobe): then their
     * dispatch follows the trace's with no barrier between them (vx__seq.beside) and fills the GPU while the
     * trace's last photons bounce on. Their records then lie after the photons (48 bytes a pixel more), which
     * the trace is still writing; otherwise in the photons' buffer once the photons are sorted. (Before, both
     * ran in one pipeline: at the trace's workgroup 32 it took the trace's registers, 4.1 ms against 2.6 + 1.0
     * apart on the H200.) Only with the trace's workgroups of 32 and 64, the ones measured; test_fused_paths
     * runs 128 to compare. */
    const vx_photon_desc* d = &pg->d;
    bool fused = d->workgroup <= 64 && !d->final_gather && !pg->kinds && !pg->glossy_diffuse;
    uint64_t ph_bytes = (uint64_t)d->capacity * PHOTON_BYTES, rec_bytes = (uint64_t)npx * 48;
    ph_bytes = fused ? ph_bytes + rec_bytes : (rec_bytes > ph_bytes ? rec_bytes : ph_bytes);
    if ((r = vx__buffer_ensure(pg->g, &pg->photons, ph_bytes, "photons", err))) return r;
    pg->spec[VX__SPEC_COUNT + 1] = pg->P.L.materials;
    vx__render_scene_trace_ids(pg->rs, pg->spec);
    vx_photon_stats st = {.pass = pass};
    st.radius = pass_radius(d->radius, d->alpha, pass);
    st.caustic_radius = pass_radius(d->caustic_radius, d->alpha, pass);
    gpu_params* p = pg->params.map;
    memset(p, 0, sizeof *p);
    uint64_t seed = d->seed + (uint64_t)pass * UINT64_C(0x9E3779B97F4A7C15);
    p->a[0] = pg->sources ? d->photons : 0, p->a[1] = d->capacity, p->a[2] = d->bounces, p->a[3] = pg->buckets;
    p->seed[0] = (uint32_t)seed, p->seed[1] = (uint32_t)(seed >> 32), p->seed[2] = pass, p->seed[3] = pg->sources;
    p->r[0] = (float)st.radius, p->r[1] = (float)st.caustic_radius;
    p->r[2] = (float)(1 / (pi * st.radius * st.radius)), p->r[3] = (float)(1 / (pi * st.caustic_radius * st.caustic_radius));
    p->img[0] = f.width, p->img[1] = f.height, p->img[2] = mean, p->img[3] = full;
    p->tr[2] = pg->kinds, p->tr[3] = pg->scene->instance_count > 1;
    float sk[16];
    vx__sky_pack(&pg->P.L.sky_dir, &pg->P.L.sky_map, pg->P.L.sky, sk);
    for (int k = 0; k < 3; k++) p->sphere[k] = (float)(pg->centre[k] - f.ref[k]), p->sky[k] = sk[k];
    memcpy(p->skyh, sk + 4, sizeof p->skyh), memcpy(p->skyg, sk + 8, sizeof p->skyg), memcpy(p->skym, sk + 12, sizeof p->skym);
    p->sphere[3] = (float)pg->sphere_r, p->sky[3] = (float)pg->face_power;
    p->cnt[0] = pg->face_count, p->cnt[1] = 2, p->cnt[2] = d->final_gather, p->cnt[3] = pg->P.L.voxel_lights;
    uint32_t ctr[4] = {0};
    double build = 0;
    set_emitted(pg, p, p->a[0]);
    /* tiles of 8 x 8 pixels, 64 invocations each: the camera's paths, then the Lambert sums (photon.comp
     * density_pixel: that loop in a kernel of its own registers, not the tracer's) */
    uint64_t tiles = (uint64_t)((f.width + 7) / 8) * ((f.height + 7) / 8) * 64;
    p->fu[0] = fused ? 2 * d->capacity : 0;
    p->fu[2] = (uint32_t)(tiles / 64);
    const VkPhysicalDeviceLimits* lim = &pg->g->props.limits;
    uint32_t parts = DENSITY_PARTS;
    while (parts > 4 && (lim->maxComputeWorkGroupInvocations < 64 * parts || lim->maxComputeWorkGroupSize[0] < 64 * parts ||
                         lim->maxComputeSharedMemorySize < 64 * 64 * parts + 4096))
        parts /= 2;
    pg->density_parts = tiles / 64 < DENSITY_FEW_TILES ? parts : 1;
    st.fused = fused;
    /* One submission: the trace, then the steps after it sized on the GPU (record_rest), one wait; the host
     * paid 2.4-2.8 ms a pass on the H200 for a submission and wait per step and the counters' downloads. */
    pass_rec q = {0};
    const uint32_t* rb = pg->readback.map;
    if ((r = rec_begin(pg, &q, err))) return r;
    if (!(r = step(pg, &q, STEP_RESET, 4, -1, out, &build, err))) {
        q.seq.beside = fused;
        r = step(pg, &q, STEP_TRACE, p->tr[0], -1, out, &st.trace_ms, err);
        if (!r && fused) r = step(pg, &q, STEP_GATHER, tiles, -1, out, &st.trace_ms, err);
    }
    if (!r) r = record_rest(pg, &q, fused, out, &st, &build, err);
    if (!r) r = rec_submit(pg, &q, err);
    rec_abandon(pg, &q);
    if (r) return r;
    memcpy(ctr, rb, sizeof ctr);
    st.emitted = p->a[0];
    if (ctr[0] > d->capacity) {
        /* Over the capacity (the steps after the trace had no groups): which photons the atomic counter had
         * left out depended on the GPU's order. The pass is traced again to count each photon's stores
         * (nothing stored), and then a third time with photons 0..C-1 alone, C the most whose stores fit,
         * each carrying 1/C of the sources' power (the photons are independent draws: the estimate keeps its
         * expected value, and the same seed gives the same photons and image). A photon stores at most
         * bounces + 1 times: C >= 1. */
        uint32_t n = p->a[0], c = 0;
        uint32_t* counts = vx_alloc(pg->alloc, (size_t)n * sizeof *counts);
        if (!counts) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u photon counts", n);
        p->tr[1] = 1;
        p->a[3] = pg->buckets; /* (STEP_SIZE's copy had set this pass's) */
        r = rec_begin(pg, &q, err);
        if (!r) r = step(pg, &q, STEP_RESET, 4, -1, out, &build, err);
        if (!r) r = step(pg, &q, STEP_TRACE, p->tr[0], -1, out, &st.trace_ms, err);
        if (!r) r = rec_submit(pg, &q, err);
        rec_abandon(pg, &q);
        if (!r) r = vx__buffer_download(pg->g, &pg->cells, counts, (size_t)n * sizeof *counts, err);
        for (uint64_t sum = 0; !r && c < n && sum + counts[c] <= d->capacity; c++) sum += counts[c];
        vx_free(pg->alloc, counts);
        p->tr[1] = 0;
        set_emitted(pg, p, c);
        if (!r) r = rec_begin(pg, &q, err);
        if (!r) r = step(pg, &q, STEP_RESET, 4, -1, out, &build, err);
        if (!r) r = step(pg, &q, STEP_TRACE, p->tr[0], -1, out, &st.trace_ms, err);
        if (!r) r = record_rest(pg, &q, fused, out, &st, &build, err);
        if (!r) r = rec_submit(pg, &q, err);
        rec_abandon(pg, &q);
        if (r) return r;
        memcpy(ctr, rb, sizeof ctr);
        if (ctr[0] > d->capacity) /* the counts and the trace disagree: a device fault, not a state to go on from */
            return vx_fail(err, VX_ERR_GPU, VX_NO_OFFSET, "photon pass %u: %u photons stored again, capacity %u", pass,
                           ctr[0], d->capacity);
        st.emitted = c;
        st.dropped = n - c;
    }
    st.stored = ctr[0];
    if (ctr[2]) { /* photon.comp sets one bit for each step whose loops were cut: the message names them */
        static const char* const step_name[3] = {"the photon trace", "the camera paths' gathers", "the density step"};
        char steps[96] = "";
        for (int k = 0; k < 3; k++)
            if (ctr[2] >> k & 1) strcat(strcat(steps, steps[0] ? " and " : ""), step_name[k]);
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET,
                       "photon pass %u: the loop limit of %s was reached in %s (fewer photons, a smaller radius%s)",
                       pass, vx_gpu_device_name(pg->g), steps[0] ? steps : "a step",
                       ctr[2] & 2 && d->final_gather ? ", fewer final gather rays" : "");
    }
    st.build_ms = build;
    st.gather_ms = st.paths_ms + st.density_ms;
    st.wall_ms = (vx_time_now() - t0) * 1e3;
    pg->last = st;
    *seconds = (st.trace_ms + st.build_ms + st.gather_ms) * 1e-3;
    return VX_OK;
}

static vx_result gi_render(void* user, const vx_gi_io* io, double* gpu_seconds, vx_error* err) {
    vx_photon_gi* pg = user;
    return run_pass(pg, io->frame, io->sample, io->out, false, false, gpu_seconds, err);
}


vx_result vx_photon_gi_create(vx_render_scene* rs, const vx_svo_scene* scene, const vx_probe_set* light,
                              const vx_photon_desc* desc, vx_gi_method* method, vx_photon_gi** out, vx_error* err) {
    if (!rs || !scene || !method || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    *out = NULL;
    const vx_photon_desc D = vx_photon_desc_defaults();
    vx_photon_desc d = desc ? *desc : (vx_photon_desc){0};
    if (!d.photons) d.photons = D.photons;
    if (!(d.alpha > 0)) d.alpha = D.alpha;
    if (!d.bounces) d.bounces = D.bounces;
    if (!d.workgroup) d.workgroup = D.workgroup;
    if (d.batch > 256) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "photons: a batch of %u (at most 256)", d.batch);
    if (d.workgroup > 1024 || (d.workgroup & (d.workgroup - 1)) || d.workgroup < 32)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "photons: a workgroup of %u (a power of two, 32..1024)",
                       d.workgroup);
    if (!(d.alpha <= 1) || !(d.radius >= 0) || !(d.caustic_radius >= 0) || !isfinite(d.radius) ||
        !isfinite(d.caustic_radius))
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                       "photons: alpha %g (0..1], radius %g and caustic radius %g (>= 0, finite)", d.alpha, d.radius,
                       d.caustic_radius);
    if (d.final_gather > 1024)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "photons: %u final gather rays (at most 1024)",
                       d.final_gather);
    if (d.photons > (1u << 26))
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "%u photons per pass: at most 2^26", d.photons);
    if (!d.capacity) d.capacity = 4 * d.photons;
    if (d.capacity <= d.bounces) /* one photon's stores must fit (a pass over the capacity keeps whole photons) */
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "photons: a capacity of %u under bounces + 1 = %u",
                       d.capacity, d.bounces + 1);
    if (d.capacity > (1u << 28))
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "a capacity of %u photons: at most 2^28", d.capacity);
    const vx_allocator* a = scene->alloc;
    vx_photon_gi* pg = vx_calloc(a, 1, sizeof *pg);
    if (!pg) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    pg->alloc = a, pg->rs = rs, pg->scene = scene, pg->g = vx__render_scene_gpu(rs);
    vx_render_desc sun = {.light_dir = {d.light_dir[0], d.light_dir[1], d.light_dir[2]}};
    vx_probe_render_desc pd = {.base = &sun, .mode = VX_PROBE_RENDER_PT_INDIRECT, .lights = d.lights,
                               .light_count = d.light_count, .sky = d.sky_dir, .sky_map = d.sky_map};
    vx_result r = vx__prender_setup(scene, light, light && light->first == 0 && light->count == light->probe_count, &pd,
                                    &pg->P, err);
    if (r) {
        vx_free(a, pg);
        return r;
    }
    double diag = 0;
    for (int k = 0; k < 3; k++) {
        double e = pg->P.hi[k] - pg->P.lo[k];
        pg->centre[k] = 0.5 * (pg->P.lo[k] + pg->P.hi[k]);
        diag += e * e;
    }
    diag = sqrt(diag);
    pg->sphere_r = 0.5 * diag * 1.001 + 1e-6;
    if (!(d.radius > 0)) d.radius = diag / 100;
    if (!(d.caustic_radius > 0)) d.caustic_radius = d.radius / 4;
    if (!(d.radius > 0) || !(d.caustic_radius > 0)) r = vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "photons: an empty scene");
    pg->d = d;
    /* the buckets hold the photons' store counts too (two a bucket) in a pass over the capacity */
    pg->buckets = pow2_at_least(2 * (uint64_t)d.capacity);
    if (pg->buckets < pow2_at_least(d.photons / 2 + 1)) pg->buckets = pow2_at_least(d.photons / 2 + 1);
    if (!r) r = make_faces(pg, err);
    uint16_t* pal = NULL; /* material ids per record */
    size_t n = 0;
    float* m = NULL;
    if (!r) r = vx__render_scene_attr_material(rs, scene, a, &pal, &n, err);
    if (!r) r = vx_svo_material_table_emission_records(&pg->P.L.mt, pal, n, a, &pg->emit_attr, &pg->emit_count, err);
    if (!r && !(m = vx_calloc(a, n ? 8 * n : 4, sizeof(float))))
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %zu attribute records", n);
    if (!r) {
        vx__pack_materials(&pg->P.L, pal, pg->P.L.materials ? n : 0, m);
        size_t nm = pg->P.L.materials ? n : 0;
        for (size_t i = 0; i < nm; i++) /* photon.comp bsdf_of: kd = (1 - metalness) (1 - 0.08 specular) albedo */
            pg->glossy_diffuse |= m[8 * i] == 1.0f && m[8 * i + 2] < 1.0f;
        r = make_occ(pg, m, nm, err);
        uint64_t ph = (uint64_t)d.capacity * PHOTON_BYTES;
        /* The photon and grid buffers are bound whole: a capacity past the device's storage-buffer range
         * would be a binding the device refuses (lavapipe: 128 MiB, 4 M photons), so say so here. */
        uint64_t range = pg->g->props.limits.maxStorageBufferRange;
        if (!r && (ph > range || (uint64_t)pg->buckets * 8 > range))
            r = vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET,
                        "photons: a capacity of %u photons needs %llu-byte buffers, over the device's %llu-byte "
                        "storage-buffer range (set a smaller capacity or fewer photons per pass)",
                        d.capacity, (unsigned long long)(ph > (uint64_t)pg->buckets * 8 ? ph : (uint64_t)pg->buckets * 8),
                        (unsigned long long)range);
        if (!r) r = upload_new(pg->g, &pg->emit, pg->emit_attr, (pg->emit_count ? pg->emit_count : 1) * 4 * sizeof(float),
                                "photon emission", err);
        if (!r) r = upload_new(pg->g, &pg->mats, m, nm ? 32 * nm : 16, "photon materials", err);
        if (!r) r = upload_new(pg->g, &pg->photons, NULL, ph, "photons", err);
        if (!r) r = upload_new(pg->g, &pg->sorted, NULL, ph, "photons sorted", err);
        if (!r) r = upload_new(pg->g, &pg->cells, NULL, (uint64_t)pg->buckets * 8, "photon grid", err);
        if (!r) r = upload_new(pg->g, &pg->src, NULL, 16, "photon sources", err);
        if (!r) r = upload_new(pg->g, &pg->ems, NULL, 16, "photon emitters", err);
        const vx_sky_texels* t = &pg->P.L.sky_map; /* the sky's map (binding 17), when the sky is one */
        bool map = pg->P.L.sky_dir.type == VX_SKY_ENVMAP && t->rgb;
        if (!r) r = upload_new(pg->g, &pg->env, map ? t->rgb : NULL, map ? (size_t)t->width * t->height * 12 : 16, "photon sky map", err);
        if (!r)
            r = vx__buffer_create(pg->g, CTR_BYTES, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT,
                                  false, "photon counters", &pg->counters, err);
        if (!r)
            r = vx__buffer_create(pg->g, 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true, "photon counters readback",
                                  &pg->readback, err);
        if (!r && !pg->readback.map) r = vx_fail(err, VX_ERR_GPU, VX_NO_OFFSET, "photon readback is not host visible");
        if (!r)
            r = vx__buffer_create(pg->g, sizeof(gpu_params), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true, "photon params",
                                  &pg->params, err);
        if (!r && !pg->params.map) r = vx_fail(err, VX_ERR_GPU, VX_NO_OFFSET, "photon parameters are not host visible");
    }
    vx_free(a, pal);
    vx_free(a, m);
    if (r) {
        vx_photon_gi_destroy(pg);
        return r;
    }
    *method = (vx_gi_method){.name = "photons", .user = pg, .render = gi_render, .emit_attr = pg->emit_attr,
                             .emit_count = pg->emit_count, .lights = d.lights, .light_count = d.light_count};
    for (int k = 0; k < 3; k++) {
        method->light_dir[k] = pg->P.L.light_dir[k];
        method->sun[k] = pg->P.L.sun[k];
        method->sky[k] = pg->P.L.sky[k];
    }
    if (pg->P.L.sky_dir.type != VX_SKY_DEFAULT) method->sky_dir = &pg->P.L.sky_dir, method->sky_map = &pg->P.L.sky_map;
    *out = pg;
    return VX_OK;
}

void vx_photon_gi_destroy(vx_photon_gi* pg) {
    if (!pg) return;
    vx__buffer* b[] = {&pg->params, &pg->emit, &pg->mats, &pg->src,      &pg->ems,
                       &pg->photons, &pg->sorted, &pg->cells, &pg->counters, &pg->img, &pg->env, &pg->occ, &pg->readback};
    for (size_t i = 0; i < sizeof b / sizeof b[0]; i++) vx__buffer_destroy(pg->g, b[i]);
    vx__prender_free(&pg->P);
    vx_free(pg->alloc, pg->emit_attr);
    vx_free(pg->alloc, pg->faces);
    vx_free(pg->alloc, pg);
}

vx_result vx_photon_render(vx_photon_gi* pg, const vx_render_desc* base, uint32_t passes, bool full,
                           vx_render_image* out, vx_error* err) {
    if (!pg || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    vx_render_desc b = base ? *base : (vx_render_desc){0};
    vx__frame f;
    vx_result r = vx__frame_setup(pg->P.lo, pg->P.hi, &b, &f, err);
    if (r) return r;
    size_t npx = (size_t)f.width * f.height;
    if ((r = vx__buffer_ensure(pg->g, &pg->img, npx * 16, "photon image", err))) return r;
    double total = 0;
    for (uint32_t k = 0; k < (passes ? passes : 1) && !r; k++) {
        double s = 0;
        r = run_pass(pg, &b, k, &pg->img, true, full, &s, err);
        total += s;
    }
    if (r) return r;
    vx_render_image img = {.width = f.width, .height = f.height, .mode = VX_RENDER_COLOR};
    if (!(img.pixels = vx_alloc(NULL, npx * 16)))
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for a %ux%u image", f.width, f.height);
    if ((r = vx__buffer_download(pg->g, &pg->img, img.pixels, npx * 16, err))) {
        vx_free(NULL, img.pixels);
        return r;
    }
    img.gpu_seconds = total;
    img.rays = (uint64_t)pg->last.emitted * (passes ? passes : 1);
    *out = img;
    return VX_OK;
}

void vx_photon_last_stats(const vx_photon_gi* pg, vx_photon_stats* out) {
    if (pg && out) *out = pg->last;
}

/* The last pass's n stored photons as the trace wrote them (8 floats each), from the sorted array (the
 * photons' own buffer holds the density step's records by then): its first halves, then its second. */
static vx_result download_photons(vx_photon_gi* pg, float* out, size_t n, vx_error* err) {
    if (!n) return VX_OK;
    size_t half = (size_t)pg->d.capacity * (PHOTON_BYTES / 2);
    float* tmp = vx_alloc(pg->alloc, 2 * half);
    if (!tmp) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %zu photons", n);
    vx_result r = vx__buffer_download(pg->g, &pg->sorted, tmp, 2 * half, err);
    for (size_t i = 0; !r && i < n; i++) {
        memcpy(out + 8 * i, tmp + 4 * i, 16);
        memcpy(out + 8 * i + 4, (const char*)tmp + half + 16 * i, 16);
    }
    vx_free(pg->alloc, tmp);
    return r;
}

vx_result vx_photon_power(vx_photon_gi* pg, double first[3], double all[3], vx_error* err) {
    if (!pg || !first || !all) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    size_t n = (size_t)pg->last.stored;
    float* ph = vx_alloc(pg->alloc, n ? n * PHOTON_BYTES : 16);
    if (!ph) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %zu photons", n);
    vx_result r = download_photons(pg, ph, n, err);
    for (int k = 0; k < 3; k++) first[k] = all[k] = 0;
    for (size_t i = 0; !r && i < n; i++) {
        const float* q = ph + 8 * i;
        uint32_t wi;
        memcpy(&wi, q + 7, 4);
        for (int k = 0; k < 3; k++) {
            all[k] += q[4 + k];
            if (wi & 1u) first[k] += q[4 + k]; /* photon.comp's F_FIRST */
        }
    }
    vx_free(pg->alloc, ph);
    return r;
}

/* photon.comp's unpackSnorm2x16 + oct_decode */
static void oct_decode(uint32_t bits, float out[3]) {
    int16_t ix = (int16_t)(bits & 0xFFFFu), iy = (int16_t)(bits >> 16);
    float u = fmaxf(-1.0f, ix / 32767.0f), v = fmaxf(-1.0f, iy / 32767.0f);
    float p[3] = {u, v, 1.0f - fabsf(u) - fabsf(v)};
    if (p[2] < 0) {
        p[0] = (1.0f - fabsf(v)) * (u < 0 ? -1.0f : 1.0f);
        p[1] = (1.0f - fabsf(u)) * (v < 0 ? -1.0f : 1.0f);
    }
    float l = sqrtf(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    for (int k = 0; k < 3; k++) out[k] = p[k] / l;
}

vx_result vx_photon_stored(vx_photon_gi* pg, vx_photon_record** out, size_t* count, vx_error* err) {
    if (!pg || !out || !count) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    *out = NULL, *count = 0;
    size_t n = (size_t)pg->last.stored;
    float* ph = vx_alloc(pg->alloc, n ? n * PHOTON_BYTES : 16);
    vx_photon_record* rec = vx_calloc(pg->alloc, n ? n : 1, sizeof *rec);
    vx_result r = !ph || !rec ? vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %zu photons", n) : VX_OK;
    if (!r) r = download_photons(pg, ph, n, err);
    for (size_t i = 0; !r && i < n; i++) {
        const float* q = ph + 8 * i;
        uint32_t wb, nb;
        memcpy(&nb, q + 3, 4), memcpy(&wb, q + 7, 4);
        vx_photon_record* o = &rec[i];
        for (int k = 0; k < 3; k++) o->position[k] = q[k] + pg->ref[k], o->power[k] = q[4 + k];
        oct_decode(wb, o->direction); /* its lowest bit, F_FIRST, is 1/32767 of u: left in */
        oct_decode(nb & ~7u, o->normal);
        o->flags = (nb & 1u ? VX_PHOTON_CAUSTIC : 0) | (nb & 2u ? VX_PHOTON_DIRECT : 0) | (wb & 1u ? VX_PHOTON_FIRST : 0) |
                   (nb & 4u ? VX_PHOTON_LIGHT : 0);
    }
    vx_free(pg->alloc, ph);
    if (r) {
        vx_free(pg->alloc, rec);
        return r;
    }
    *out = rec, *count = n;
    return VX_OK;
}
