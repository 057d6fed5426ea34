/* render/compact_gpu.c - the compact layout on the GPU (render/compact.h,
 * issue 18): its geometry DAG, attribute blocks and model table uploaded
 * beside a render scene, traced by shaders/trace_compact.comp with the
 * render scene's frame block, instance table and BVH (bindings 0, 4-6 of
 * vx__render_scene_tables), so both kernels see the same instances and rays. */
#include <string.h>

#include "render/compact.h"
#include "render/render_internal.h"
#include "trace_compact.comp.h"

/* shaders/trace_compact.comp's CModel */
typedef struct cmodel_gpu {
    uint32_t root, depth, flags, box, attr_base, block_log2, kind, rank_base, rebase;
} cmodel_gpu;

struct vx_compact_gpu {
    vx_render_scene* rs;
    vx_gpu* gpu;
    vx__buffer geom, attr, models, palette, pixels, hits;
    double lo[3], hi[3];
    uint32_t deep;
    uint64_t bytes;
};

/* trace.comp's Model.box (render_scene.c model_box) */
static uint32_t model_box(const vx_svo_model* m) {
    uint32_t sh = m->depth > 10 ? m->depth - 10 : 0, b = 0;
    for (int k = 0; k < 3; k++) {
        uint32_t q = m->size[k] ? ((m->size[k] - 1) >> sh) : 0;
        b |= (q > 1023 ? 1023 : q) << (10 * k);
    }
    return b;
}

void vx_compact_gpu_destroy(vx_compact_gpu* cg) {
    if (!cg) return;
    vx__buffer* b[6] = {&cg->geom, &cg->attr, &cg->models, &cg->palette, &cg->pixels, &cg->hits};
    for (int i = 0; i < 6; i++) vx__buffer_destroy(cg->gpu, b[i]);
    vx_free(&cg->gpu->alloc, cg);
}

static vx_result upload(vx_gpu* g, vx__buffer* b, const void* data, uint64_t bytes, const char* label, vx_error* err) {
    vx_result r = vx__buffer_create(g, bytes ? bytes : 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, label, b, err);
    if (!r && bytes) r = vx__buffer_upload(g, b, data, bytes, err);
    return r;
}

vx_result vx_compact_gpu_create(vx_render_scene* rs, const vx_svo_scene* s, const vx_compact_scene* c,
                                vx_compact_gpu** out, vx_error* err) {
    if (!rs || !s || !c || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    if (c->model_count != s->model_count)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "the compact scene has %u models, the scene %u",
                       c->model_count, s->model_count);
    /* the kernel's DEEP constant, as render_scene.c's for trace.comp */
    uint32_t deep = 0;
    for (uint32_t i = 0; i < s->model_count; i++) {
        const vx_svo_model* m = &s->models[i];
        if (m->root >= VX_SVO_ROOT_LEAF) continue;
        if (m->depth > VX_RENDER_REBASE_DEPTH) deep = 2;
        else if (m->depth > VX_RENDER_EXACT_DEPTH && deep < 1) deep = 1;
    }
    vx_gpu* g = vx__render_scene_gpu(rs);
    vx_compact_gpu* cg = vx_calloc(&g->alloc, 1, sizeof *cg);
    if (!cg) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    cg->rs = rs, cg->gpu = g, cg->deep = deep;
    vx_svo_scene_world_bounds(s, cg->lo, cg->hi);
    size_t mcount = s->model_count ? s->model_count : 1;
    cmodel_gpu* cm = vx_calloc(&g->alloc, mcount, sizeof *cm);
    if (!cm) {
        vx_free(&g->alloc, cg);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    }
    for (uint32_t i = 0; i < s->model_count; i++) {
        const vx_compact_model* m = &c->models[i];
        const vx_svo_model* sm = &s->models[i];
        uint32_t flags = m->attr_kind != VX_COMPACT_ATTR_NONE ? 1u : 0u;
        bool deep_model = sm->root < VX_SVO_ROOT_LEAF && sm->depth > VX_RENDER_EXACT_DEPTH;
        if (deep_model) flags |= 2u;
        cm[i] = (cmodel_gpu){.root = m->root, .depth = m->depth, .flags = flags, .box = model_box(sm),
                             .attr_base = m->attr_base, .block_log2 = m->block ? (uint32_t)__builtin_ctz(m->block) : 0,
                             .kind = m->attr_kind, .rank_base = c->slot_count,
                             .rebase = deep_model && sm->depth > VX_RENDER_REBASE_DEPTH
                                           ? sm->depth - VX_RENDER_FRAME_LEVELS
                                           : 0};
    }
    vx_result r = upload(g, &cg->geom, c->geom, (uint64_t)c->geom_words * 4, "compact geometry", err);
    if (!r) r = upload(g, &cg->attr, c->attr, (uint64_t)c->attr_words * 4, "compact attributes", err);
    if (!r) r = upload(g, &cg->models, cm, mcount * sizeof *cm, "compact models", err);
    if (!r) r = upload(g, &cg->palette, c->palette, sizeof c->palette, "compact palette", err);
    vx_free(&g->alloc, cm);
    if (r) {
        vx_compact_gpu_destroy(cg);
        return r;
    }
    cg->bytes = (uint64_t)c->geom_words * 4 + (uint64_t)c->attr_words * 4 + mcount * sizeof(cmodel_gpu) + sizeof c->palette;
    *out = cg;
    return VX_OK;
}

uint64_t vx_compact_gpu_bytes(const vx_compact_gpu* cg) { return cg ? cg->bytes : 0; }

static vx_result dispatch(vx_compact_gpu* cg, const vx_render_desc* desc, bool want_hits, uint32_t repeat, vx__frame* f,
                          double* seconds, vx_error* err) {
    vx_gpu* g = cg->gpu;
    vx_result r = vx__frame_setup(cg->lo, cg->hi, desc, f, err);
    if (r) return r;
    vx__buffer* scene[7];
    uint32_t sp[VX__SPEC_COUNT];
    if ((r = vx__render_scene_tables(cg->rs, f, scene, sp, err))) return r;
    VkDeviceSize npx = (VkDeviceSize)f->width * f->height;
    if ((r = vx__buffer_ensure(g, &cg->pixels, npx * 16, "compact pixels", err))) return r;
    if ((r = vx__buffer_ensure(g, &cg->hits, want_hits ? npx * 32 : 16, "compact hits", err))) return r;
    uint32_t spec[10] = {(uint32_t)f->mode, sp[VX__SPEC_HAS_COLOR], sp[VX__SPEC_USE_BVH], 0, want_hits, 0, 0, 0,
                         cg->deep, 0};
    uint64_t key = 0xC0AC7000u;
    for (int i = 0; i < 10; i++) key = key * 131 + spec[i];
    vx_gpu_compute_pipeline_desc pd = {.spirv = vx__trace_compact_spv_arr, .spirv_size = sizeof vx__trace_compact_spv_arr,
                                       .binding_count = 10, .spec_count = 10, .label = "trace compact"};
    pd.bindings[0] = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    for (uint32_t i = 1; i < 10; i++) pd.bindings[i] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    memcpy(pd.spec, spec, sizeof spec);
    vx__pipeline* p;
    if ((r = vx__pipeline_get(g, key, &pd, &p, err))) return r;
    vx__dispatch_desc dd = {.pipeline = p,
                            .buffer_count = 10,
                            .buffers = {scene[0], &cg->geom, &cg->attr, &cg->models, scene[4], scene[5], scene[6],
                                        &cg->pixels, &cg->hits, &cg->palette},
                            .groups = {(f->width + 7) / 8, (f->height + 7) / 8, 1},
                            .repeat = repeat,
                            .label = "trace compact"};
    return vx__dispatch(g, &dd, seconds, err);
}

vx_result vx_compact_gpu_frame(vx_compact_gpu* cg, const vx_render_desc* desc, vx_render_image* out, vx_error* err) {
    if (!cg || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    bool want_hits = desc && desc->want_hits;
    vx__frame f;
    double sec = 0;
    vx_result r = dispatch(cg, desc, want_hits, 1, &f, &sec, err);
    if (r) return r;
    vx_render_image img = {.width = f.width, .height = f.height, .mode = f.mode, .alloc = &cg->gpu->alloc};
    if ((r = vx__image_read(cg->gpu, &cg->pixels, want_hits ? &cg->hits : NULL, &img, err))) return r;
    img.gpu_seconds = sec;
    img.rays = (uint64_t)f.width * f.height * f.spp;
    *out = img;
    return VX_OK;
}

vx_result vx_compact_gpu_time(vx_compact_gpu* cg, const vx_render_desc* desc, uint32_t repeat, double* seconds,
                              vx_error* err) {
    if (!cg || !seconds) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    vx__frame f;
    return dispatch(cg, desc, false, repeat ? repeat : 1, &f, seconds, err);
}
