/* probes/gi_pass.c - the probe module's GI methods as the pass pipeline's gi
 * pass (render/pipeline.h): "probes" (irradiance probes), "lightfield" (one
 * bounce through the probes' distance maps) and "pathtrace" (the path
 * tracer's indirect light). Each renders the indirect-only mode of
 * vx_probe_gpu_render for the pipeline's camera and puts the radiance into
 * the pipeline's gi buffer; the light (sun, sky, emission) is the probes'
 * (or the bake defaults without probes), and the pipeline shades its direct
 * pass with it, so direct + gi is what the full probe modes render.
 * pathtrace also carries the frame's lights (vx_light) along its paths; the
 * direct pass shades them at the first surface.
 *
 * The image stays on the GPU: the probe renderer's accumulation is divided
 * into the gi buffer by probes/shaders/probe_out.comp; the gi timing row is
 * the GPU time of both. The methods trace their own pixel-centre primary
 * rays (the same camera as the G-buffer). */
#include <string.h>

#include "probes/probes.h"
#include "probes/probes_internal.h"
#include "render/gpu.h"

struct vx_probe_gi {
    vx_gpu* g;
    vx_probe_gpu* pg;
    vx_probe_render_desc desc;
    float* emit_attr;
    size_t emit_count;
    const vx_allocator* alloc;
    vx_sky sky_dir; /* the sky by direction the method renders (VX_SKY_DEFAULT: its uniform sky) */
    vx_sky_texels sky_map;
};

static vx_result gi_render(void* user, const vx_gi_io* io, double* gpu_seconds, vx_error* err) {
    vx_probe_gi* gi = user;
    vx_probe_render_desc d = gi->desc;
    d.base = io->frame;
    /* a fresh random stream per accumulated sample */
    d.seed = gi->desc.seed + (uint64_t)io->sample * UINT64_C(0x9E3779B97F4A7C15);
    /* the probe renderer writes straight into the pipeline's gi buffer */
    return vx_probe_gpu_render_into(gi->pg, &d, io->out, gpu_seconds, err);
}

vx_result vx_probe_gi_create(vx_render_scene* rs, const vx_svo_scene* scene, const vx_probe_set* ps, const char* method,
                             const vx_probe_render_desc* desc, vx_gi_method* out_method, vx_probe_gi** out,
                             vx_error* err) {
    if (!rs || !scene || !method || !out_method || !out)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    *out = NULL;
    vx_probe_render_mode mode;
    if (!strcmp(method, "probes")) mode = VX_PROBE_RENDER_INDIRECT;
    else if (!strcmp(method, "lightfield")) mode = VX_PROBE_RENDER_LF_INDIRECT;
    else if (!strcmp(method, "pathtrace")) mode = VX_PROBE_RENDER_PT_INDIRECT;
    else return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "unknown gi method '%s' (probes, lightfield, pathtrace)", method);
    if (desc && desc->light_count && mode != VX_PROBE_RENDER_PT_INDIRECT)
        return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET,
                       "gi=%s takes no lights (its light is the probes' sun and sky); gi=pathtrace does", method);
    if (vx_probe_render_mode_uses_probes(mode) && !ps)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "gi=%s needs a probe set", method);
    const vx_allocator* a = ps ? ps->alloc : NULL;
    vx_probe_gi* gi = vx_calloc(a, 1, sizeof *gi);
    if (!gi) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    gi->alloc = a;
    gi->g = vx__render_scene_gpu(rs);
    gi->desc = desc ? *desc : (vx_probe_render_desc){0};
    gi->desc.mode = mode;
    gi->desc.stats = NULL;
    gi->desc.pixel_centre = true; /* the G-buffer's rays: the direct pass shades the pixel centre too */
    /* the light the method was made for: resolved the way the probe renderer does */
    vx__prender P;
    vx_result r = vx__prender_setup(scene, ps, ps && ps->first == 0 && ps->count == ps->probe_count, &gi->desc, &P, err);
    uint16_t* pal = NULL; /* material ids per record */
    size_t n = 0;
    if (!r) r = vx__render_scene_attr_material(rs, scene, a, &pal, &n, err);
    if (!r) r = vx_svo_material_table_emission_records(&P.L.mt, pal, n, a, &gi->emit_attr, &gi->emit_count, err);
    if (!r) r = vx_probe_gpu_create(rs, scene, ps, &gi->pg, err);
    vx_free(a, pal);
    for (int k = 0; k < 3; k++) {
        out_method->light_dir[k] = P.L.light_dir[k];
        out_method->sun[k] = P.L.sun[k];
        out_method->sky[k] = P.L.sky[k];
    }
    gi->sky_dir = P.L.sky_dir, gi->sky_map = P.L.sky_map; /* the texels stay the caller's (desc->sky_map) */
    vx__prender_free(&P);
    if (r) {
        vx_probe_gi_destroy(gi);
        return r;
    }
    out_method->name = method, out_method->user = gi, out_method->render = gi_render;
    out_method->emit_attr = gi->emit_attr, out_method->emit_count = gi->emit_count;
    out_method->lights = gi->desc.lights, out_method->light_count = gi->desc.light_count;
    out_method->sky_dir = gi->sky_dir.type != VX_SKY_DEFAULT ? &gi->sky_dir : NULL;
    out_method->sky_map = gi->sky_dir.type != VX_SKY_DEFAULT ? &gi->sky_map : NULL;
    out_method->includes_direct = false; /* the direct pass shades the frame's light */
    *out = gi;
    return VX_OK;
}

void vx_probe_gi_destroy(vx_probe_gi* gi) {
    if (!gi) return;
    vx_probe_gpu_destroy(gi->pg);
    vx_free(gi->alloc, gi->emit_attr);
    vx_free(gi->alloc, gi);
}
