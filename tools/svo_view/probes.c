/* tools/svo_view/probes.c - light field probes in the viewer (app.h): a set
 * read from a file, a bake over the scene shown run in steps between frames,
 * the probe modes. */
#include <stdio.h>
#include <string.h>

#include "tools/common/tool.h"
#include "tools/svo_view/app.h"

/* Reads a complete probe set; the current one stays on failure. */
vx_result sv_load_probes(app* a, const char* path, vx_error* err) {
    vx_probe_set ps;
    vx_result r = vx_probe_read_file(NULL, path, &ps, err);
    if (r) {
        /* the reader names the file; vx_file_read's messages may not */
        if (strncmp(err->msg, path, strlen(path))) vx_error_prefix(err, path);
        return r;
    }
    if (ps.first != 0 || ps.count != ps.probe_count) {
        r = vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                    "%s: a shard (probes %u to %u of %u): merge the shards with svo_bake first", path, ps.first,
                    ps.first + ps.count, ps.probe_count);
        vx_probe_set_free(&ps);
        return r;
    }
    sv_drop_probes(a);
    a->probes = ps;
    a->have_probes = true;
    snprintf(a->probes_path, sizeof a->probes_path, "%s", path);
    return VX_OK;
}

void sv_probes(app* a, const char* path) {
    vx_error err = {0};
    if (sv_load_probes(a, path, &err)) {
        sv_message(a, true, "%s", err.msg);
        return;
    }
    sv_message(a, false, "probes %s: %ux%ux%u grid, res %u", path, a->probes.grid[0], a->probes.grid[1],
            a->probes.grid[2], a->probes.res);
}

/* ---- probe bake in steps ------------------------------------------------------------- */

const vx_probe_set* sv_probe_shown(const app* a) {
    return a->bake.active ? &a->bake.ps : a->have_probes ? &a->probes : NULL;
}

void sv_probe_bake_cancel(app* a, const char* why) {
    if (!a->bake.active) return;
    vx_probe_set_free(&a->bake.ps);
    a->bake.active = false;
    sv_message(a, true, "probe bake cancelled: %s", why);
}

void sv_probe_bake(app* a, uint32_t res, uint32_t spp, const uint32_t grid[3]) {
    if (a->bake.active) {
        sv_message(a, true, "a probe bake is running (probes cancel stops it)");
        return;
    }
    if (!a->rs || vx_render_scene_precise(a->rs)) {
        sv_message(a, true, "probe bake: %s", a->rs ? "the scene needs the float64 tracer, which the GPU bake lacks"
                                                  : "no scene on the GPU");
        return;
    }
    /* svo_bake's options: the library's defaults with res, spp and the grid */
    vx_probe_bake_desc d = vx_probe_bake_desc_defaults();
    d.res = res, d.spp = spp;
    memcpy(d.grid, grid, sizeof d.grid);
    vx_error err = {0};
    vx_svo_scene v;
    if (!vx_svo_scene_frame(&a->scene, a->anim_frame, &v)) v = a->scene;
    if (vx_probe_place(&v, &d, &a->bake.ps, &err)) {
        sv_message(a, true, "probe bake: %s", err.msg);
        return;
    }
    a->bake.desc = d;
    a->bake.active = true;
    a->bake.step = 1;
    a->bake.t0 = vx_time_now();
    a->bake.ms = 0;
    if (a->probe_sel >= a->bake.ps.probe_count) a->probe_sel = 0;
    sv_message(a, false, "baking %u probes (%ux%ux%u, res %u, %u spp)", a->bake.ps.probe_count, a->bake.ps.grid[0],
               a->bake.ps.grid[1], a->bake.ps.grid[2], res, spp);
}

/* One step between frames: as many probes as took about 40 ms at the last
 * step's rate, so the frame rate stays interactive while it runs. */
void sv_probe_bake_step(app* a) {
    struct sv_bake* b = &a->bake;
    if (!b->active) return;
    vx_probe_set* ps = &b->ps;
    uint32_t end = ps->count + b->step;
    if (end > ps->probe_count || end < ps->count) end = ps->probe_count;
    vx_error err = {0};
    vx_svo_scene v;
    if (!vx_svo_scene_frame(&a->scene, a->anim_frame, &v)) v = a->scene;
    double t0 = vx_time_now();
    uint32_t before = ps->count;
    if (vx_probe_bake_more_gpu(a->rs, &v, &b->desc, ps, end, &err)) {
        vx_probe_set_free(ps);
        b->active = false;
        sv_message(a, true, "probe bake: %s", err.msg);
        return;
    }
    double ms = (vx_time_now() - t0) * 1e3;
    b->ms += ms;
    uint32_t done = ps->count - before;
    double per = done ? ms / done : ms;
    double want = per > 0 ? 40.0 / per : 2.0 * b->step;
    b->step = want < 1 ? 1 : want > 4096 ? 4096 : (uint32_t)want;
    if (ps->count < ps->probe_count) return;
    /* done: the set replaces the loaded probes (the gi method and the probes' GPU maps follow) */
    sv_drop_probes(a);
    a->probes = *ps;
    memset(ps, 0, sizeof *ps);
    a->have_probes = true;
    b->active = false;
    snprintf(a->probes_path, sizeof a->probes_path, "(baked here)");
    printf("%s: baked %u probes (res %u, %u spp) in %.2f s (%.1f ms baking, %.1f ms a probe)\n", vx_tool_name,
           a->probes.probe_count, a->probes.res, a->probes.spp, vx_time_now() - b->t0, b->ms,
           b->ms / (a->probes.probe_count ? a->probes.probe_count : 1));
    sv_message(a, false, "baked %u probes", a->probes.probe_count);
}

bool sv_probe_save(app* a, const char* path) {
    vx_error err = {0};
    if (!a->have_probes) {
        sv_message(a, true, "no probes to save (bake or load them first)");
        return false;
    }
    if (vx_probe_write_file(NULL, &a->probes, path, &err)) {
        sv_message(a, true, "%s: %s", path, err.msg);
        return false;
    }
    printf("%s: saved probes %s\n", vx_tool_name, path);
    return true;
}

/* Mode gi is only offered with probes loaded; otherwise a message, and the mode stays. */
void sv_set_probe_mode(app* a, vx_probe_render_mode m) {
    if (!a->have_probes) {
        sv_message(a, true, "mode %s needs light field probes (--probes FILE, or the script command probes FILE)",
                vx_probe_render_mode_name(m));
        return;
    }
    a->gi = true;
    a->pmode = m;
}
