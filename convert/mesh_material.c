/* convert/mesh_material.c - the MATL ids of a mesh's cells (mesh_internal.h,
 * "materials"): which glTF materials sample their metallic-roughness and
 * emissive textures per cell, the levels those are quantized to, and the id
 * of each (material, levels) combination. */
#include <math.h>
#include <string.h>

#include "convert/mesh_internal.h"

/* The image a material's texture names, when it can be sampled (uv set). */
static const vx_gltf_image* tex_image(const vx_gltf_mesh* mesh, const vx_gltf_tex* t, const float* uv) {
    if (t->image < 0 || (uint32_t)t->image >= mesh->image_count || !uv) return NULL;
    const vx_gltf_image* im = &mesh->images[t->image];
    return im->rgba && im->width && im->height ? im : NULL;
}

/* Whether each channel of mask (bit c: channel c) holds one value over the
 * whole image, and that value (the first pixel's). Stops once every channel
 * of mask varies (any: once one does; then the others' answers are only
 * "varies" or "not seen to vary"): a varying texture costs the pixels up to
 * the first that differs, not a pass over 2048^2 of them (the plan is made
 * three times a conversion; docs/PERFORMANCE.md section 3). */
static void channel_uniform(const vx_gltf_image* im, unsigned mask, bool any, bool uniform[4], uint8_t value[4]) {
    memcpy(value, im->rgba, 4);
    unsigned varies = 0;
    size_t n = (size_t)im->width * im->height; /* the reader allocated n * 4 bytes */
    uint32_t first;
    memcpy(&first, im->rgba, 4);
    for (size_t i = 1; i < n && (any ? !(varies & mask) : (varies & mask) != mask); i++) {
        uint32_t px;
        memcpy(&px, im->rgba + 4 * i, 4);
        if (px == first) continue; /* the common case in a dark emissive map: 427,213 pixels of DamagedHelmet's */
        const uint8_t* p = im->rgba + 4 * i;
        for (unsigned c = 0; c < 4; c++) varies |= (unsigned)(p[c] != value[c]) << c;
    }
    for (unsigned c = 0; c < 4; c++) uniform[c] = !(varies & (1u << c));
}

/* The effective factors and sampled channels of glTF material g. */
static void plan_one(const vx_gltf_mesh* mesh, const vx_gltf_material* g, const float lin[256], vx__mesh_mat* o) {
    memset(o, 0, sizeof *o);
    o->metal = g->metallic;
    o->rough = g->roughness;
    memcpy(o->emit, g->emissive, sizeof o->emit);
    o->trans = g->transmission;
    bool rough_varies = false;
    const vx_gltf_image* mr = tex_image(mesh, &g->metal_rough, mesh->uv_mr);
    if (mr) {
        bool uni[4];
        uint8_t val[4];
        channel_uniform(mr, 1u << 1 | 1u << 2, false, uni, val);
        /* a channel uniform over the image is its factor (the file is then
         * the one the equivalent factor gives) */
        if (uni[2]) o->metal *= val[2] / 255.0f;
        else if (o->metal > 0) o->sample |= VX__MESH_SAMPLE_METAL;
        if (uni[1]) o->rough *= val[1] / 255.0f;
        else rough_varies = o->rough > 0;
    }
    const vx_gltf_image* em = tex_image(mesh, &g->emissive_tex, mesh->uv_emissive);
    if (em) {
        bool uni[4];
        uint8_t val[4];
        /* any of RGB varying samples the whole emission: stop at the first */
        channel_uniform(em, 7u, true, uni, val);
        if (uni[0] && uni[1] && uni[2]) {
            for (int k = 0; k < 3; k++) o->emit[k] *= lin[val[k]];
        } else if (o->emit[0] > 0 || o->emit[1] > 0 || o->emit[2] > 0) {
            o->sample |= VX__MESH_SAMPLE_EMIT;
        }
    }
    o->emit_max = fmaxf(o->emit[0], fmaxf(o->emit[1], o->emit[2]));
    o->special = o->metal > 0 || o->trans > 0 || o->emit_max > 0;
    /* roughness only matters in a record */
    if (rough_varies && (o->special || o->sample)) o->sample |= VX__MESH_SAMPLE_ROUGH;
}

/* Whether emission channel c of m is quantized per cell: every channel
 * above 0 of a sampled emission (one that is 0 stays 0 whatever the
 * texture says, so it needs no levels). */
static bool emit_sampled(const vx__mesh_mat* m, int c) { return (m->sample & VX__MESH_SAMPLE_EMIT) && m->emit[c] > 0; }

/* levels^(channels sampled), the emission's counted per channel */
static uint32_t block_of(const vx__mesh_mat* m, uint32_t levels) {
    uint32_t b = 1;
    if (m->sample & VX__MESH_SAMPLE_METAL) b *= levels;
    if (m->sample & VX__MESH_SAMPLE_ROUGH) b *= levels;
    for (int c = 0; c < 3; c++)
        if (emit_sampled(m, c)) b *= levels;
    return b;
}

vx_result vx__mesh_mats_make(const vx_gltf_mesh* mesh, const vx_allocator* a, vx__mesh_mats* out, vx_error* err) {
    memset(out, 0, sizeof *out);
    uint32_t n = mesh->materials ? mesh->material_count : 0;
    out->m = (vx__mesh_mat*)vx_calloc(a, n ? n : 1, sizeof *out->m);
    if (!out->m) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "%u materials", n);
    out->count = n;
    float thr[256], lin[256], a255[256];
    uint32_t* guess = (uint32_t*)vx_alloc(a, 4097 * sizeof *guess); /* only lin is wanted here */
    if (!guess) {
        vx__mesh_mats_free(a, out);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "colour tables");
    }
    vx__mesh_color_tables(thr, guess, lin, a255);
    vx_free(a, guess);
    for (uint32_t i = 0; i < n; i++) {
        plan_one(mesh, &mesh->materials[i], lin, &out->m[i]);
        out->sampled |= out->m[i].sample != 0;
    }
    /* the ids: index + 1 without sampling (as before per-cell materials);
     * else blocks, with fewer levels when they do not fit in 16 bits */
    static const uint32_t tries[] = {VX__MESH_LEVELS, 4, 3, 2};
    uint64_t next = 1;
    out->levels = VX__MESH_LEVELS;
    for (size_t t = 0; out->sampled && t < sizeof tries / sizeof tries[0]; t++) {
        next = 1;
        for (uint32_t i = 0; i < n; i++) next += block_of(&out->m[i], tries[t]);
        out->levels = tries[t];
        if (next - 1 <= 65535u) break;
    }
    if (out->sampled && next - 1 > 65535u) {
        vx_result r = vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET,
                              "glTF materials: %u materials need %llu material ids with their textures at 2 levels, "
                              "more than 65535",
                              n, (unsigned long long)(next - 1));
        vx__mesh_mats_free(a, out);
        return r;
    }
    next = 1;
    for (uint32_t i = 0; i < n; i++) {
        vx__mesh_mat* m = &out->m[i];
        m->block = block_of(m, out->levels);
        m->base = next <= 65535u ? (uint32_t)next : 0;
        next += m->block;
    }
    for (size_t t = 0; mesh->material && t < mesh->tri_count && !out->any_special; t++) {
        uint32_t mi = mesh->material[t];
        out->any_special = mi < n && out->m[mi].base && (out->m[mi].special || out->m[mi].sample);
    }
    return VX_OK;
}

void vx__mesh_mats_free(const vx_allocator* a, vx__mesh_mats* p) {
    vx_free(a, p->m);
    memset(p, 0, sizeof *p);
}

/* The level of a cell's average v of a channel whose factor is f: v / f in
 * [0, 1] rounded to the nearest of levels steps. */
static uint32_t level_of(float v, float f, uint32_t levels) {
    double q = f > 0 ? (double)v / f : 0;
    if (!(q > 0)) return 0;
    if (q >= 1) return levels - 1;
    return (uint32_t)lrint(q * (levels - 1));
}

uint16_t vx__mesh_mats_id(const vx__mesh_mats* p, uint32_t mi, float metal, float rough, const float emit[3]) {
    if (mi >= p->count || !p->m[mi].base) return 0;
    const vx__mesh_mat* m = &p->m[mi];
    if (!m->sample) return m->special ? (uint16_t)m->base : 0;
    uint32_t L = p->levels, km = 0, kr = 0, ke = 0, Le = 1;
    uint32_t Lr = (m->sample & VX__MESH_SAMPLE_ROUGH) ? L : 1;
    bool lit = m->emit_max > 0, metallic = m->metal > 0;
    if (m->sample & VX__MESH_SAMPLE_METAL) metallic = (km = level_of(metal, m->metal, L)) > 0;
    if (m->sample & VX__MESH_SAMPLE_ROUGH) kr = level_of(rough, m->rough, L);
    if (m->sample & VX__MESH_SAMPLE_EMIT) {
        lit = false;
        for (int c = 0; c < 3; c++)
            if (emit_sampled(m, c)) {
                uint32_t k = level_of(emit[c], m->emit[c], L);
                ke = ke * L + k, Le *= L;
                lit |= k > 0;
            }
    }
    if (!metallic && !lit && !(m->trans > 0)) return 0; /* diffuse: no record */
    return (uint16_t)(m->base + (km * Lr + kr) * Le + ke);
}

bool vx__mesh_mats_record(const vx__mesh_mats* p, uint32_t id, uint32_t* mi, float v[4], float emit_rgb[3]) {
    if (id == 0) return false;
    /* the material whose block holds id: the last with a base <= id (bases
     * ascend with the index, then are 0 beyond the id space) */
    uint32_t lo = 0, hi = p->count;
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (p->m[mid].base && p->m[mid].base <= id) lo = mid + 1;
        else hi = mid;
    }
    if (lo == 0) return false;
    lo--;
    const vx__mesh_mat* m = &p->m[lo];
    if (!m->base || id < m->base || id - m->base >= m->block) return false;
    uint32_t L = p->levels, k = id - m->base, Le = 1;
    for (int c = 0; c < 3; c++)
        if (emit_sampled(m, c)) Le *= L;
    uint32_t Lr = (m->sample & VX__MESH_SAMPLE_ROUGH) ? L : 1;
    uint32_t ke = k % Le, kr = (k / Le) % Lr, km = k / Le / Lr;
    *mi = lo;
    v[0] = (m->sample & VX__MESH_SAMPLE_METAL) ? m->metal * (float)km / (float)(L - 1) : m->metal;
    v[1] = (m->sample & VX__MESH_SAMPLE_ROUGH) ? m->rough * (float)kr / (float)(L - 1) : m->rough;
    memcpy(emit_rgb, m->emit, sizeof m->emit);
    v[2] = m->emit_max;
    if (m->sample & VX__MESH_SAMPLE_EMIT) {
        /* ke's digits, B last (the least significant) */
        for (int c = 2; c >= 0; c--)
            if (emit_sampled(m, c)) emit_rgb[c] = m->emit[c] * (float)(ke % L) / (float)(L - 1), ke /= L;
        v[2] = fmaxf(emit_rgb[0], fmaxf(emit_rgb[1], emit_rgb[2]));
    }
    v[3] = m->trans;
    return v[0] > 0 || v[2] > 0 || v[3] > 0;
}
