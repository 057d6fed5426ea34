/* tools/svo_view/main.c - svo_view FILE [options]: an interactive viewer and
 * scene editor on the Vulkan tracer (GLFW window, swapchain, CPU overlay),
 * scriptable for headless runs under Xvfb. */
#define _POSIX_C_SOURCE 200809L /* clock_gettime with CLOCK_THREAD_CPUTIME_ID */
#include <GLFW/glfw3.h>
#include <math.h>
#include <stdarg.h>
#include <time.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <vulkan/vulkan.h> /* the shown image's layout before the panels' render pass */

#include "convert/convert.h"
#include "formats/image.h"
#include "render/trace.h"
#include "tools/common/tool.h"
#include "tools/svo_view/app.h"
#include "tools/svo_view/batch.h"
#include "tools/svo_view/font.h"
#include "tools/svo_view/panels.h"

#define PI 3.14159265358979323846

/* This thread's CPU seconds (the panels' drawing cost, not disturbed by
 * other processes on a loaded machine); wall time where there is no such clock. */
static double thread_seconds(void) {
#ifdef CLOCK_THREAD_CPUTIME_ID
    struct timespec ts;
    if (!clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts)) return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
#endif
    return vx_time_now();
}



static options default_options(void) {
    options o = {0};
    o.win_w = 1280;
    o.win_h = 800;
    o.fov = 45;
    o.conv = vx_tool_conv_defaults();
    o.passes = VX_PASS_LIST_DEFAULT;
    return o;
}

_Noreturn static void usage(int status) {
    options d = default_options();
    FILE* f = status == 0 ? stdout : stderr;
    fprintf(f,
            "Usage: %s FILE.{svo,vox,gltf,glb,vdb} [options]\n"
            "Which: views and edits a voxel scene with the Vulkan tracer in a window. Files other\n"
            "       than .svo are converted on load (converter options as vox2svo has them).\n"
            "Options:\n"
            "    --screenshot OUT.png  render one frame with svo_render's default camera, save it, exit\n"
            "                          (.exr keeps float data, as svo_render writes it)\n"
            "    --size WxH            render size (default: the window's framebuffer)\n"
            "    --window WxH          window size (default: %ux%u, or --size)\n"
            "    --mode M              color|albedo|normal|depth|instance|iterations, or gi|lightfield\n"
            "                          with --probes\n"
            "                          (default: %s)\n"
            "    --probes FILE         light field probes from svo_bake: mode gi (key 7) shows direct light\n"
            "                          plus the probes' diffuse GI, mode lightfield (key 8) one bounce\n"
            "                          traced through them, exactly as svo_render does\n"
            "    --passes LIST         the colour mode's passes, as svo_render --passes (default: %s);\n"
            "                          key 9 cycles presets (ao, aa, tonemap, dof, gi=cones: voxel cone\n"
            "                          tracing, its volume rebuilt after each edit; gi=photons: photon\n"
            "                          mapping, fresh photons every frame); the overlay shows each\n"
            "                          pass's GPU time\n"
            "    --fov DEG             vertical field of view (default: %g)\n"
            "    --script FILE         play commands from FILE (see below)\n"
            "    --save FILE.svo       where Ctrl+S saves (default: FILE.edited.svo)\n"
            "    --bench N             render N frames, print the median frame time, exit\n"
            "    --fps X               an animation's playback rate (default: the file's, else %g)\n"
            "    --present auto|gpu|host  how frames reach the window: gpu converts the colour passes'\n"
            "                          image and copies it to the swapchain on the GPU; host reads it\n"
            "                          back and converts it on the CPU (default: auto, gpu except on CPU\n"
            "                          devices such as lavapipe; other modes, picks and screenshots: host)\n"
            "    --undo-limit N        undo steps kept (default: %u; 1 to 1000000)\n"
            "    --undo-memory SIZE    bytes the undo steps may hold, the oldest dropped first (default:\n"
            "                          %lluM; a step holds every frame's instance records and the lights,\n"
            "                          or the old model of a voxel edit that rebuilt it)\n"
            "    --no-panels           the text overlay instead of the panels%s\n"
            "    --gpu-panels          draw the panels with ImGui's Vulkan backend in the frame's submission\n"
            "                          (where the swapchain images allow; default: drawn on the CPU into an\n"
            "                          overlay kept between redraws: on an H200 the render pass cost a\n"
            "                          frame 0.16 ms, the kept overlay 0.002 ms)\n"
            "    --batch auto|K        frames in flight submitted K at a time (1 to 4): each frame still\n"
            "                          takes its own input and image and is presented in order, up to\n"
            "                          K - 1 frames later (on an H200 a submission costs about 0.01 ms of\n"
            "                          a 0.08 ms frame). auto (default): K from the measured frame time,\n"
            "                          so that a frame waits at most --batch-latency more; 1 with vsync\n"
            "    --batch-latency MS    the most --batch auto may delay a frame (default: %g ms)\n"
            "    --vsync               start with vsync on (V toggles)\n"
            "    --hidden              do not show the window (scripts, benchmarks)\n"
            "    --device N|NAME       Vulkan device (default: a discrete GPU, else any)\n"
            "    --validate            enable the Vulkan validation layer; prints the error count at exit\n"
            "                          (status 1 when there were any)\n"
            "    --frame N, --keep-hidden, --keep-unused, --no-collapse, --no-dag  (.vox)\n"
            "    --res N (default: %u), --region N, --scene N, --solid, --normals, --y-up  (.gltf/.glb)\n"
            "    --grid NAME, --threshold X, --density, --color NAME   (.vdb)\n"
            "    --max-memory SIZE     refuse a scene that needs more memory than SIZE to read (512M, 4G)\n"
            "    -v, --verbose         print the effective options and timings\n"
            "    -h, --help            print this help and exit;  --version: versions\n"
            "Keys: WASD/Q/E fly, right mouse look, wheel speed (orbit: zoom), O orbit, F frame the\n"
            "      selection or scene, 1-6 modes (7: gi, 8: lightfield, with probes), V vsync, Tab panels\n"
            "      (overlay without them), P screenshot; click picks; Space play/pause, ',' '.' step frames;\n"
            "      B voxel mode: click adds, Shift+click removes, Alt+click paints with the brush;\n"
            "      G/R/M then X/Y/Z move (arrows/mouse, Enter, Esc)/rotate (Shift: back)/mirror;\n"
            "      Shift+D duplicate, Delete, H hide/Alt+H show all, L then 0-9 toggles a layer,\n"
            "      Ctrl+Z/Ctrl+Y undo/redo (instance, voxel, light and material edits), Ctrl+S save, Ctrl+E export .vox, drop a file to add it.\n"
            "Script commands (one a line, # comments): camera EX EY EZ TX TY TZ | camera default |\n"
            "      fly DX DY DZ | look DYAW DPITCH | orbit on|off | mode M | passes LIST | probes FILE |\n"
            "      select N|none |"
            "      pick X Y |"
            " frame | move DX DY DZ | rotate x|y|z [TURNS] | mirror x|y|z | duplicate | delete |\n"
            "      hide | show | layer N hide|show | add FILE | open FILE | undo | redo |\n"
            "      save FILE.svo | export FILE.vox | screenshot FILE | wait N | echo TEXT | quit |\n"
            "      anim frame N|step [K]|play|pause|fps X|tick SECONDS | exposure STOPS | panels on|off |\n"
            "      overlay on|off (the text overlay, shown without panels) | vsync on|off | rename NAME |\n"
            "      setlayer N|none | setmodel N (the selection) |\n"
            "      grab FILE.png (the displayed frame, panels included) | click X Y (on the panels) |\n"
            "      ui click|ctrl-click LABEL (the panels' widget with that label, as a mouse click; ctrl-click\n"
            "      on a slider or drag field edits it as text) | ui type TEXT | ui key enter|escape|tab|backspace |\n"
            "      brush voxel|box|sphere|face [R] | color INDEX|#RRGGBB | voxel add|remove|paint X Y Z [FACE]\n"
            "      (model cells of the selection's model; FACE +x|-x|+y|-y|+z|-z for the face brush: add\n"
            "      extrudes the exposed face region, remove pushes it in, paint recolours it) |\n"
            "      vclick add|remove|paint X Y (as a click in voxel mode) |\n"
            "      light N color R G B|position X Y Z|intensity X|range X (each an undo step) |\n"
            "      material ID type diffuse|metal|glass|emit, material ID rough|metal|spec|trans|ior|emit|flux X\n"
            "      (palette index or material id; each an undo step) |\n"
            "      gi OPTION VALUE (svo_render's gi options without --: bounces, seed, spp, ao-rays, ao-radius,\n"
            "      photons, final-gather, radius, cone-res, cones, cone-aperture, cone-bounces, cone-sun-angle;\n"
            "      on|off: cone-isotropic, cone-ao, cone-half, cone-shadows, cone-no-specular) |\n"
            "      stats (prints the render scenes made and the node words and records uploaded) |\n"
            "      probes bake RES SPP [GX GY GZ] (on the GPU, in steps between frames; the script waits) |\n"
            "      probes grid on|off | probes show N (the panel's maps) | probes save FILE.probes | probes cancel\n"
            "Examples:\n"
            "    %s castle.vox\n"
            "    %s scene.svo --screenshot shot.png --size 640x480 --mode albedo\n"
            "    %s scene.svo --probes scene.probes --mode gi\n"
            "    xvfb-run -a %s scene.svo --script edit.txt --hidden\n",
            vx_tool_name, d.win_w, d.win_h, vx_render_mode_name(d.mode), d.passes, d.fov, SV_FPS_DEFAULT,
            VED_UNDO_STEPS_DEFAULT, (unsigned long long)(VED_UNDO_BYTES_DEFAULT >> 20),
            sv_panels_built() ? "" : " (this build has no panels: no Dear ImGui)", SV_BATCH_LATENCY_MS, d.conv.res, vx_tool_name, vx_tool_name,
            vx_tool_name, vx_tool_name);
    exit(status);
}

#define usage_error(...) vx_tool_usage_error(usage, __VA_ARGS__)

static const char* need_arg(int argc, char** argv, int* i) {
    if (*i + 1 >= argc) usage_error("option %s needs an argument", argv[*i]);
    return argv[++*i];
}

static bool parse_size(const char* s, uint32_t* w, uint32_t* h) {
    unsigned a, b;
    char c;
    if (sscanf(s, "%ux%u%c", &a, &b, &c) != 2 || !a || !b || a > 16384 || b > 16384) return false;
    *w = a, *h = b;
    return true;
}

static options parse(int argc, char** argv) {
    options o = default_options();
    bool window_set = false;
    int npos = 0;
    for (int i = 1; i < argc; i++) {
        const char* a = argv[i];
        if (!strcmp(a, "-h") || !strcmp(a, "-help") || !strcmp(a, "--help")) usage(0);
        else if (!strcmp(a, "--version") || !strcmp(a, "-version")) {
            printf("%s %s (.svo format version %u; reads .svo, .vox, .gltf/.glb, .vdb)\n", vx_tool_name,
                   VX_VERSION_STRING, VX_SVO_FORMAT_VERSION);
            exit(0);
        } else if (!strcmp(a, "--screenshot")) o.screenshot = need_arg(argc, argv, &i);
        else if (!strcmp(a, "--size")) {
            if (!parse_size(need_arg(argc, argv, &i), &o.width, &o.height))
                usage_error("bad --size '%s' (WxH, at most 16384 each)", argv[i]);
        } else if (!strcmp(a, "--window")) {
            if (!parse_size(need_arg(argc, argv, &i), &o.win_w, &o.win_h))
                usage_error("bad --window '%s' (WxH)", argv[i]);
            window_set = true;
        } else if (!strcmp(a, "--mode")) {
            const char* m = need_arg(argc, argv, &i);
            o.gi = !strcmp(m, "gi") || !strcmp(m, "lightfield");
            if (o.gi) vx_probe_render_mode_parse(m, &o.pmode);
            if (!o.gi && !vx_render_mode_parse(m, &o.mode))
                usage_error("unknown mode '%s' (color|albedo|normal|depth|instance|iterations|gi|lightfield)", m);
        } else if (!strcmp(a, "--probes")) {
            o.probes = need_arg(argc, argv, &i);
        } else if (!strcmp(a, "--passes")) {
            o.passes = need_arg(argc, argv, &i);
            vx_pass_list pl;
            vx_error perr = {0};
            if (vx_pass_list_parse(o.passes, &pl, &perr)) usage_error("--passes: %s", perr.msg);
        } else if (!strcmp(a, "--fov")) {
            if (!vx_tool_parse_double(need_arg(argc, argv, &i), &o.fov) || !(o.fov > 0 && o.fov < 180))
                usage_error("bad --fov '%s' (degrees in (0,180))", argv[i]);
        } else if (!strcmp(a, "--script")) o.script = need_arg(argc, argv, &i);
        else if (!strcmp(a, "--save")) o.save = need_arg(argc, argv, &i);
        else if (!strcmp(a, "--bench")) {
            if (!vx_tool_parse_u32(need_arg(argc, argv, &i), &o.bench) || !o.bench || o.bench > 100000)
                usage_error("bad --bench '%s' (1 to 100000 frames)", argv[i]);
        } else if (!strcmp(a, "--fps")) {
            if (!vx_tool_parse_double(need_arg(argc, argv, &i), &o.fps) || !(o.fps > 0 && o.fps <= 1000))
                usage_error("bad --fps '%s' (frames per second in (0,1000])", argv[i]);
        } else if (!strcmp(a, "--present")) {
            o.present = need_arg(argc, argv, &i);
            if (strcmp(o.present, "auto") && strcmp(o.present, "gpu") && strcmp(o.present, "host"))
                usage_error("bad --present '%s' (auto, gpu or host)", o.present);
        } else if (!strcmp(a, "--undo-limit")) {
            if (!vx_tool_parse_u32(need_arg(argc, argv, &i), &o.undo_limit) || !o.undo_limit || o.undo_limit > 1000000)
                usage_error("bad --undo-limit '%s' (1 to 1000000 steps)", argv[i]);
        } else if (!strcmp(a, "--undo-memory")) {
            if (!vx_tool_parse_bytes(need_arg(argc, argv, &i), &o.undo_bytes) || !o.undo_bytes)
                usage_error("bad --undo-memory '%s' (bytes, e.g. 512M, 4G)", argv[i]);
        } else if (!strcmp(a, "--batch")) {
            const char* v = need_arg(argc, argv, &i);
            if (!strcmp(v, "auto")) o.batch = 0;
            else if (!vx_tool_parse_u32(v, &o.batch) || o.batch < 1 || 2 * o.batch > VX_DISPLAY_SLOTS)
                usage_error("bad --batch '%s' (auto, or 1 to %d frames a submission)", v, VX_DISPLAY_SLOTS / 2);
        } else if (!strcmp(a, "--batch-latency")) {
            const char* v = need_arg(argc, argv, &i);
            char* end;
            o.batch_latency = strtod(v, &end);
            if (end == v || *end || !(o.batch_latency > 0) || o.batch_latency > 1e6)
                usage_error("bad --batch-latency '%s' (milliseconds, above 0)", v);
        } else if (!strcmp(a, "--no-panels")) o.no_panels = true;
        else if (!strcmp(a, "--gpu-panels")) o.gpu_panels = true;
        else if (!strcmp(a, "--vsync")) o.vsync = true;
        else if (!strcmp(a, "--hidden")) o.hidden = true;
        else if (!strcmp(a, "--device")) o.device = need_arg(argc, argv, &i);
        else if (!strcmp(a, "--validate") || !strcmp(a, "-validate")) o.validate = true;
        else if (vx_tool_conv_option(argc, argv, &i, &o.conv, usage)) continue;
        else if (!strcmp(a, "-v") || !strcmp(a, "--verbose")) o.verbose = true;
        else if (a[0] == '-' && a[1]) usage_error("\"%s\" is not a valid option", a);
        else if (npos == 0) o.in = a, npos++;
        else usage_error("unexpected argument '%s'", a);
    }
    if (argc == 1) usage(2);
    if (!o.in) usage_error("%s", "no input file given");
    if (o.screenshot && o.script) usage_error("%s", "--screenshot and --script conflict (use the script's screenshot command)");
    if (o.screenshot && o.bench) usage_error("%s", "--screenshot and --bench conflict");
    if (o.gi && !o.probes) usage_error("mode %s needs --probes FILE", vx_probe_render_mode_name(o.pmode));
    if (o.screenshot) {
        const char* ext = vx_tool_ext(o.screenshot);
        if (strcmp(ext, "png") && strcmp(ext, "exr")) usage_error("screenshot '%s' must end in .png or .exr", o.screenshot);
        if (!o.width) o.width = 640, o.height = 480; /* svo_render's default size */
    }
    if (o.width && !window_set) o.win_w = o.width, o.win_h = o.height;
    return o;
}

/* ---- loading ---------------------------------------------------------------------- */

static vx_result load_scene(const options* o, const char* path, vx_svo_scene* out, vx_error* err) {
    vx_logger log = vx_tool_logger(o->verbose);
    return vx_tool_conv_load(path, &o->conv, true, &log, (vx_progress){0}, out, NULL, err);
}

/* ---- application state ---------------------------------------------------------------- */



void sv_message(app* a, bool error, const char* fmt, ...) __attribute__((format(printf, 3, 4)));
void sv_message(app* a, bool error, const char* fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(a->msg, sizeof a->msg, fmt, ap);
    va_end(ap);
    a->msg_error = error;
    a->msg_until = glfwGetTime() + 6;
    fprintf(error ? stderr : stdout, "%s: %s\n", vx_tool_name, a->msg);
}

const char* sv_mode_name(const app* a) {
    return a->gi ? vx_probe_render_mode_name(a->pmode) : vx_render_mode_name(a->mode);
}

/* Reads a complete probe set; the current one stays on failure. */
static vx_result load_probes(app* a, const char* path, vx_error* err) {
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
    vx_probe_gpu_destroy(a->probes_gpu);
    a->probes_gpu = NULL;
    vx_probe_gi_destroy(a->pgi); /* made for the old set */
    a->pgi = NULL;
    vx_photon_gi_destroy(a->phgi); /* borrows the old set's sun and sky */
    a->phgi = NULL;
    if (a->have_probes) vx_probe_set_free(&a->probes);
    a->probes = ps;
    a->have_probes = true;
    snprintf(a->probes_path, sizeof a->probes_path, "%s", path);
    return VX_OK;
}

void sv_probes(app* a, const char* path) {
    vx_error err = {0};
    if (load_probes(a, path, &err)) {
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
static void probe_bake_step(app* a) {
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
    vx_probe_gpu_destroy(a->probes_gpu);
    a->probes_gpu = NULL;
    vx_probe_gi_destroy(a->pgi);
    a->pgi = NULL;
    if (a->have_probes) vx_probe_set_free(&a->probes);
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

/* World box of instance i as the frame shown places it. */
static void world_box(const app* a, uint32_t i, double lo[3], double hi[3]) {
    vx_svo_instance_world_box(&a->scene, vx_svo_scene_frame_instances(&a->scene, a->anim_frame) + i, lo, hi);
}

static void cam_fwd(const app* a, double f[3]) {
    f[0] = cos(a->pitch) * cos(a->yaw);
    f[1] = cos(a->pitch) * sin(a->yaw);
    f[2] = sin(a->pitch);
}

/* Places the camera to frame a box from direction `dir` (towards the eye),
 * exactly as the tracer's default camera does for the scene bounds. */
static void frame_box(app* a, const double lo[3], const double hi[3], const double dir_in[3]) {
    double c[3], rad = 0, dir[3] = {dir_in[0], dir_in[1], dir_in[2]};
    double l = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
    for (int k = 0; k < 3; k++) dir[k] /= l;
    for (int k = 0; k < 3; k++) c[k] = 0.5 * (lo[k] + hi[k]), rad += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    rad = 0.5 * sqrt(rad);
    if (!(rad > 0)) rad = 1;
    double dist = rad / sin(0.5 * a->o.fov * PI / 180.0) * 1.05;
    for (int k = 0; k < 3; k++) a->eye[k] = c[k] + dir[k] * dist, a->orbit_center[k] = c[k];
    a->orbit_dist = dist;
    a->yaw = atan2(-dir[1], -dir[0]);
    a->pitch = asin(-dir[2]);
    a->speed = rad > 0 ? rad * 0.5 : 1;
}

static void camera_default(app* a) {
    double lo[3], hi[3], dir[3] = {0.45, -1.0, 0.65};
    vx_svo_scene_world_bounds(&a->scene, lo, hi); /* the tracer's default framing: every frame */
    frame_box(a, lo, hi, dir);
    a->cam_default = true;
}

static vx_render_camera camera_desc(const app* a) {
    vx_render_camera c = {.fov = a->o.fov};
    if (a->cam_default) return c; /* the tracer's own framing: svo_render's image exactly */
    double f[3];
    cam_fwd(a, f);
    c.set = true;
    for (int k = 0; k < 3; k++) c.eye[k] = a->eye[k], c.target[k] = a->eye[k] + f[k];
    return c;
}

/* The pipeline's objects bound to rs (and its gi method bound to the probes). */
static void drop_passes(app* a) {
    vx_probe_gi_destroy(a->pgi);
    a->pgi = NULL;
    vx_cone_gi_destroy(a->cgi);
    a->cgi = NULL;
    vx_photon_gi_destroy(a->phgi);
    a->phgi = NULL;
    vx_frame_renderer_destroy(a->fr);
    a->fr = NULL;
}

void sv_rebuild(app* a) {
    double t0 = vx_time_now();
    sv_probe_bake_cancel(a, "the scene changed");
    a->name_for = NO_SEL; /* the panel's name field shows the name again */
    vx_probe_gpu_destroy(a->probes_gpu); /* bound to the old render scene */
    a->probes_gpu = NULL;
    drop_passes(a);
    vx_render_scene_stats st;
    vx_render_scene_get_stats(a->rs, &st);
    a->words_before += st.node_words_uploaded, a->records_before += st.records_uploaded;
    vx_render_scene_destroy(a->rs);
    a->rs = NULL;
    a->scenes_made++;
    vx_error err = {0};
    uint32_t nf = vx_svo_scene_frames(&a->scene);
    if (a->anim_frame >= nf) a->anim_frame = nf - 1; /* an undo may have made the scene still */
    if (vx_render_scene_create(a->gpu, &a->scene, &a->rs, &err)) sv_message(a, true, "cannot draw the scene: %s", err.msg);
    else if (a->anim_frame && vx_render_scene_set_frame(a->rs, &a->scene, a->anim_frame, &err))
        sv_message(a, true, "frame %u: %s", a->anim_frame, err.msg);
    else if (vx_frame_renderer_create(a->rs, &a->scene, &a->fr, &err)) sv_message(a, true, "pass pipeline: %s", err.msg);
    a->rs_models = a->scene.model_count;
    a->update_ms = (vx_time_now() - t0) * 1e3;
}

void sv_uploads(const app* a, uint64_t* words, uint64_t* records) {
    vx_render_scene_stats st;
    vx_render_scene_get_stats(a->rs, &st);
    *words = a->words_before + st.node_words_uploaded;
    *records = a->records_before + st.records_uploaded;
}

/* After an edit of instances only (the models as rs has them): the instance
 * tables and the BVH are made again from the frame shown
 * (vx_render_scene_set_frame, which takes any instance count); the models'
 * node words stay on the GPU. The pass pipeline's and the probes' objects
 * hold scene facts (bounds, cell sizes, lights): the probes' and the gi
 * methods' are made again, which costs no GPU work until the next frame;
 * the frame renderer takes its facts again and keeps its buffers and frames
 * in flight. */
static void update_instances(app* a) {
    sv_probe_bake_cancel(a, "the scene changed");
    if (!a->rs || a->scene.model_count != a->rs_models) {
        sv_rebuild(a);
        return;
    }
    double t0 = vx_time_now();
    a->name_for = NO_SEL;
    vx_probe_gpu_destroy(a->probes_gpu);
    a->probes_gpu = NULL;
    /* the gi methods are made again; the frame renderer keeps its buffers (and
     * its frames in flight): only its scene facts change */
    vx_frame_renderer* fr = a->fr;
    a->fr = NULL;
    drop_passes(a);
    a->fr = fr;
    uint32_t nf = vx_svo_scene_frames(&a->scene);
    if (a->anim_frame >= nf) a->anim_frame = nf - 1;
    vx_error err = {0};
    if (vx_render_scene_set_frame(a->rs, &a->scene, a->anim_frame, &err)) {
        sv_message(a, true, "instance update: %s", err.msg);
        sv_rebuild(a);
        return;
    }
    if (a->fr && vx_frame_renderer_update_scene(a->fr, &a->scene, &err)) {
        vx_frame_renderer_destroy(a->fr);
        a->fr = NULL;
    }
    if (!a->fr && vx_frame_renderer_create(a->rs, &a->scene, &a->fr, &err))
        sv_message(a, true, "pass pipeline: %s", err.msg);
    a->update_ms = (vx_time_now() - t0) * 1e3;
}

/* Starts an edit: the camera stops following the scene bounds, and the
 * state is saved for undo. */
bool sv_edit_begin(app* a, bool needs_sel) {
    if (needs_sel && a->sel == NO_SEL) {
        sv_message(a, true, "nothing selected");
        return false;
    }
    a->cam_default = false;
    vx_error err = {0};
    if (ved_begin(&a->ed, &err)) {
        sv_message(a, true, "%s", err.msg);
        return false;
    }
    return true;
}

void sv_edit_end(app* a, const char* what) {
    update_instances(a); /* models changed: sv_rebuild */
    if (a->o.verbose) printf("%s: %s (scene update %.2f ms)\n", vx_tool_name, what, a->update_ms);
}

static void set_scene(app* a, vx_svo_scene* s) {
    ved_free(&a->ed);
    vx_svo_scene_free(&a->scene);
    a->scene = *s;
    ved_init(&a->ed, &a->scene);
    a->ed.undo_limit = a->o.undo_limit, a->ed.undo_bytes = a->o.undo_bytes;
    a->sel = NO_SEL;
    a->sel_light = NO_SEL;
    a->light_step_for = NO_SEL;
    a->mat_step_for = NO_SEL;
    a->light_serial++;
    a->op = 0;
    a->anim_frame = 0;
    a->playing = false;
    a->fps = a->o.fps > 0 ? a->o.fps : a->scene.frame_rate > 0 ? a->scene.frame_rate : SV_FPS_DEFAULT;
    camera_default(a);
    sv_rebuild(a);
}

void sv_open(app* a, const char* path) {
    vx_svo_scene s;
    vx_error err = {0};
    if (load_scene(&a->o, path, &s, &err)) {
        sv_message(a, true, "%s: %s", path, err.msg);
        return;
    }
    set_scene(a, &s);
    snprintf(a->scene_file, sizeof a->scene_file, "%s", path);
    /* probes describe the light of the scene they were baked in */
    bool had = a->have_probes;
    if (had) {
        vx_probe_gpu_destroy(a->probes_gpu);
        a->probes_gpu = NULL;
        vx_probe_gi_destroy(a->pgi);
        a->pgi = NULL;
        vx_photon_gi_destroy(a->phgi);
        a->phgi = NULL;
        vx_probe_set_free(&a->probes);
        a->have_probes = false;
        a->gi = false;
    }
    sv_message(a, false, "opened %s: %u models, %u instances%s", path, a->scene.model_count, a->scene.instance_count,
            had ? " (probes of the previous scene unloaded)" : "");
}

void sv_add(app* a, const char* path) {
    vx_svo_scene s;
    vx_error err = {0};
    if (load_scene(&a->o, path, &s, &err)) {
        sv_message(a, true, "%s: %s", path, err.msg);
        return;
    }
    /* next to the scene along +x, in grid cells */
    int32_t d[3] = {0, 0, 0};
    vx_svo_scene_update_bounds(&a->scene);
    vx_svo_scene_update_bounds(&s);
    if (a->scene.instance_count) {
        d[0] = (int32_t)(ceil(a->scene.bounds_max[0]) + 1 - floor(s.bounds_min[0]));
        d[1] = (int32_t)(floor(a->scene.bounds_min[1]) - floor(s.bounds_min[1]));
        d[2] = (int32_t)(floor(a->scene.bounds_min[2]) - floor(s.bounds_min[2]));
    }
    uint32_t first = 0, n = s.instance_count;
    if (!sv_edit_begin(a, false)) {
        vx_svo_scene_free(&s);
        return;
    }
    if (ved_add_scene(&a->scene, &s, d, &first, &err)) {
        sv_message(a, true, "%s: %s", path, err.msg);
        ved_undo(&a->ed, NULL);
    } else {
        a->sel = n ? first : NO_SEL;
        sv_message(a, false, "added %s: %u instances", path, n);
    }
    vx_svo_scene_free(&s);
    sv_edit_end(a, "add");
}

/* The file holds the compacted models (vvx_file_scene). */
void sv_save(app* a, const char* path) {
    vx_error err = {0};
    vx_svo_scene_update_bounds(&a->scene);
    vx_svo_scene fs;
    vx_result r = vvx_file_scene(&a->ed, &fs, &err);
    if (!r) {
        r = vx_svo_write_file(NULL, &fs, path, &err);
        vvx_file_scene_free(&a->ed, &fs);
    }
    if (r) sv_message(a, true, "%s: %s", path, err.msg);
    else sv_message(a, false, "saved %s", path);
}

void sv_export(app* a, const char* path) {
    vx_error err = {0};
    vx_vox_scene vs;
    vx_svo_scene fs;
    vx_result r = vvx_file_scene(&a->ed, &fs, &err);
    if (!r) {
        r = vx_conv_svo_to_vox(&fs, NULL, &vs, &err);
        vvx_file_scene_free(&a->ed, &fs);
    }
    if (!r) {
        r = vx_vox_write_file(NULL, &vs, path, &err);
        vx_vox_scene_free(&vs);
    }
    if (r) sv_message(a, true, "%s: %s", path, err.msg);
    else sv_message(a, false, "exported %s", path);
}

void sv_frame_camera(app* a) {
    double lo[3], hi[3], f[3];
    if (a->sel != NO_SEL) world_box(a, a->sel, lo, hi);
    else vx_svo_scene_world_bounds(&a->scene, lo, hi);
    cam_fwd(a, f);
    double dir[3] = {-f[0], -f[1], -f[2]};
    frame_box(a, lo, hi, dir);
    a->cam_default = false;
}

static void edit_move(app* a, int axis, int32_t n) {
    int32_t d[3] = {0, 0, 0};
    d[axis] = n;
    ved_move(&a->scene, a->sel, d);
}

void sv_rotate(app* a, int axis, int turns) {
    if (!sv_edit_begin(a, true)) return;
    ved_rotate(&a->scene, a->anim_frame, a->sel, axis, turns);
    sv_edit_end(a, "rotate");
}

void sv_mirror(app* a, int axis) {
    if (!sv_edit_begin(a, true)) return;
    ved_mirror(&a->scene, a->anim_frame, a->sel, axis);
    sv_edit_end(a, "mirror");
}

void sv_duplicate(app* a) {
    if (!sv_edit_begin(a, true)) return;
    vx_error err = {0};
    uint32_t n;
    if (ved_duplicate(&a->scene, a->sel, &n, &err)) sv_message(a, true, "%s", err.msg);
    else a->sel = n;
    sv_edit_end(a, "duplicate");
}

void sv_delete(app* a) {
    if (!sv_edit_begin(a, true)) return;
    ved_delete(&a->scene, a->sel);
    a->sel = NO_SEL;
    sv_edit_end(a, "delete");
}

void sv_hide(app* a, bool hide) {
    if (!sv_edit_begin(a, hide)) return;
    if (hide) ved_hide(&a->scene, a->sel, true);
    else
        for (uint32_t i = 0; i < a->scene.instance_count; i++) ved_hide(&a->scene, i, false);
    sv_edit_end(a, hide ? "hide" : "show");
}

void sv_hide_instance(app* a, uint32_t i, bool hide) {
    if (i >= a->scene.instance_count || !sv_edit_begin(a, false)) return;
    ved_hide(&a->scene, i, hide);
    sv_edit_end(a, hide ? "hide" : "show");
}

void sv_rename(app* a, const char* name) {
    if (!sv_edit_begin(a, true)) return;
    ved_rename(&a->scene, a->sel, name);
    sv_edit_end(a, "rename");
}

void sv_set_layer(app* a, uint32_t layer) {
    if (layer != UINT32_MAX && layer >= a->scene.layer_count) {
        sv_message(a, true, "no layer %u (the scene has %u)", layer, a->scene.layer_count);
        return;
    }
    if (!sv_edit_begin(a, true)) return;
    ved_set_layer(&a->scene, a->sel, layer);
    sv_edit_end(a, "layer");
}

void sv_set_model(app* a, uint32_t model) {
    if (model >= a->scene.model_count) {
        sv_message(a, true, "no model %u (the scene has %u)", model, a->scene.model_count);
        return;
    }
    if (!sv_edit_begin(a, true)) return;
    ved_set_model(&a->scene, a->sel, model);
    sv_edit_end(a, "model");
}

void sv_select(app* a, uint32_t i) { a->sel = i < a->scene.instance_count ? i : NO_SEL; }

void sv_move(app* a, const int32_t d[3]) {
    if (!sv_edit_begin(a, true)) return;
    ved_move(&a->scene, a->sel, d);
    sv_edit_end(a, "move");
}

/* ---- animation ------------------------------------------------------------------------ */

void sv_set_frame(app* a, uint32_t f) {
    uint32_t nf = vx_svo_scene_frames(&a->scene);
    if (f >= nf) f = nf - 1;
    if (f == a->anim_frame) return;
    a->anim_frame = f;
    if (!a->rs) return;
    double t0 = vx_time_now();
    vx_error err = {0};
    /* the instance tables and the BVH only: the models stay on the GPU */
    if (vx_render_scene_set_frame(a->rs, &a->scene, f, &err)) sv_message(a, true, "frame %u: %s", f, err.msg);
    a->switch_ms = (vx_time_now() - t0) * 1e3;
}

void sv_play(app* a, bool play) {
    a->playing = play && vx_svo_scene_frames(&a->scene) > 1;
    a->play_clock = 0;
}

void sv_set_fps(app* a, double fps) {
    if (fps > 0 && fps <= 1000) a->fps = fps;
}

/* Advances playback by dt seconds of wall time (whole frames, wrapping). */
static void play(app* a, double dt) {
    uint32_t nf = vx_svo_scene_frames(&a->scene);
    if (!a->playing || nf < 2) return;
    a->play_clock += dt * a->fps;
    if (a->play_clock < 1) return;
    uint32_t steps = (uint32_t)fmin(a->play_clock, (double)nf);
    a->play_clock -= floor(a->play_clock);
    sv_set_frame(a, (a->anim_frame + steps) % nf);
}

/* ---- voxel editing ---------------------------------------------------------------------- */

bool sv_brush_palette(app* a, uint32_t i) {
    if (i < 1 || i > 255) return false;
    if (a->scene.has_palette && !a->scene.palette[i]) {
        /* a .svo stores the entries in use only (docs/FORMAT.md 2.2) */
        sv_message(a, true, "palette entry %u is empty in this file; give a colour (#RRGGBB) instead", i);
        return false;
    }
    a->brush.palette = (uint8_t)i;
    if (a->scene.has_palette) a->brush.rgba = a->scene.palette[i];
    return true;
}

bool sv_brush_rgba(app* a, uint32_t rgba) {
    a->brush.rgba = rgba;
    if (!a->scene.has_palette) return true;
    /* palette models take the entry of that colour, or the first empty one */
    uint32_t free_i = 0;
    for (uint32_t i = 1; i < 256; i++) {
        if (a->scene.palette[i] == rgba) {
            a->brush.palette = (uint8_t)i;
            return true;
        }
        if (!free_i && !a->scene.palette[i]) free_i = i;
    }
    if (!free_i) {
        sv_message(a, true, "the palette is full: pick one of its colours");
        return false;
    }
    a->scene.palette[free_i] = rgba; /* stored in the file once a cell uses it */
    a->brush.palette = (uint8_t)free_i;
    return true;
}

/* After a voxel edit through the model's editor, or the undo or redo of
 * one: only the model's new words go to the GPU
 * (vx_render_scene_update_model); the gi methods' and the probes' objects,
 * which hold per-record tables, are made again at the next frame that needs
 * them, the pass pipeline's scene facts only when the model's size changed. */
static void update_model(app* a, uint32_t model, uint32_t words_from, uint32_t records_from, const uint32_t size[3]) {
    sv_probe_bake_cancel(a, "the scene changed");
    if (!a->rs || a->scene.model_count != a->rs_models) {
        sv_rebuild(a);
        return;
    }
    double t0 = vx_time_now();
    vx_error err = {0};
    if (vx_render_scene_update_model(a->rs, &a->scene, model, words_from, records_from, &err)) {
        sv_message(a, true, "model update: %s", err.msg);
        sv_rebuild(a);
        return;
    }
    a->update_ms = (vx_time_now() - t0) * 1e3;
    vx_probe_gpu_destroy(a->probes_gpu);
    a->probes_gpu = NULL;
    const uint32_t* ns = a->scene.models[model].size;
    if (ns[0] != size[0] || ns[1] != size[1] || ns[2] != size[2]) {
        /* a new size moves the bounds: the gi methods made again, the frame renderer's facts taken again */
        vx_frame_renderer* fr = a->fr;
        a->fr = NULL;
        drop_passes(a);
        a->fr = fr;
        if (a->fr && vx_frame_renderer_update_scene(a->fr, &a->scene, &err)) {
            vx_frame_renderer_destroy(a->fr);
            a->fr = NULL;
        }
        if (!a->fr && vx_frame_renderer_create(a->rs, &a->scene, &a->fr, &err))
            sv_message(a, true, "pass pipeline: %s", err.msg);
    } else {
        vx_probe_gi_destroy(a->pgi);
        a->pgi = NULL;
        vx_cone_gi_destroy(a->cgi);
        a->cgi = NULL;
        vx_photon_gi_destroy(a->phgi);
        a->phgi = NULL;
        /* records appended: the pipeline's emission per record */
        if (records_from != UINT32_MAX && a->fr && vx_frame_renderer_update_scene(a->fr, &a->scene, &err))
            sv_message(a, true, "pass pipeline: %s", err.msg);
    }
}

bool sv_voxels(app* a, vvx_op op, const int64_t c[3]) {
    if (a->sel == NO_SEL) {
        sv_message(a, true, "voxel %s: nothing selected", vvx_op_name(op));
        return false;
    }
    uint32_t model = vx_svo_scene_frame_instances(&a->scene, a->anim_frame)[a->sel].model;
    uint32_t size[3];
    memcpy(size, a->scene.models[model].size, sizeof size);
    double t0 = vx_time_now();
    uint64_t n = 0;
    vx_error err = {0};
    if (vvx_apply(&a->ed, model, op, &a->brush, c, &n, &err)) {
        sv_message(a, true, "voxel %s: %s", vvx_op_name(op), err.msg);
        return false;
    }
    double t_model = (vx_time_now() - t0) * 1e3;
    a->cam_default = false;
    if (!n) return true;
    const ved_voxel_step* st = &a->ed.last;
    if (st->incremental) update_model(a, model, st->words_from, st->records_from, size);
    else sv_rebuild(a);
    if (a->o.verbose)
        printf("%s: voxel %s at %lld,%lld,%lld: %llu cells (model %s %.2f ms, scene update %.2f ms)\n", vx_tool_name,
               vvx_op_name(op), (long long)c[0], (long long)c[1], (long long)c[2], (unsigned long long)n,
               st->incremental ? "edit" : "decode + rebuild", t_model, a->update_ms);
    return true;
}

void sv_layer(app* a, uint32_t l, int hide /* -1 toggles */) {
    if (l >= a->scene.layer_count) {
        sv_message(a, true, "no layer %u (the scene has %u)", l, a->scene.layer_count);
        return;
    }
    if (!sv_edit_begin(a, false)) return;
    uint32_t* f = &a->scene.layers[l].flags;
    bool h = hide < 0 ? !(*f & VX_SVO_LAYER_HIDDEN) : hide > 0;
    *f = h ? (*f | VX_SVO_LAYER_HIDDEN) : (*f & ~VX_SVO_LAYER_HIDDEN);
    sv_message(a, false, "layer %u '%s' %s", l, a->scene.layers[l].name, h ? "hidden" : "shown");
    sv_edit_end(a, "layer");
}

void sv_undo(app* a, bool redo) {
    a->cam_default = false;
    bool ok = redo ? ved_redo(&a->ed, NULL) : ved_undo(&a->ed, NULL);
    if (!ok) {
        sv_message(a, false, "nothing to %s", redo ? "redo" : "undo");
        return;
    }
    if (a->sel != NO_SEL && a->sel >= a->scene.instance_count) a->sel = NO_SEL;
    if (a->sel_light != NO_SEL && a->sel_light >= a->scene.light_count) a->sel_light = NO_SEL;
    a->light_step_for = a->mat_step_for = NO_SEL; /* the next light or material edit is a step of its own */
    a->light_serial++;          /* the step may hold other lights */
    /* the step just swapped went to the other list: did it hold a model? */
    const ved_snapshot* sn = redo ? &a->ed.undo[a->ed.undo_count - 1] : &a->ed.redo[a->ed.redo_count - 1];
    if (sn->has_header) /* a header restored: the words are on the GPU (or uploaded if it never had them) */
        update_model(a, sn->model_index, UINT32_MAX, UINT32_MAX, sn->header.size);
    else if (sn->has_model) sv_rebuild(a);
    else update_instances(a);
    if (a->o.verbose) printf("%s: %s (scene update %.2f ms)\n", vx_tool_name, redo ? "redo" : "undo", a->update_ms);
}

bool sv_set_light(app* a, uint32_t l, const vx_light* t, bool merge) {
    vx_error err = {0};
    if (l >= a->scene.light_count) {
        sv_message(a, true, "no light %u (the scene has %u)", l, a->scene.light_count);
        return false;
    }
    if (vx_light_validate(t, l, &err)) {
        sv_message(a, true, "%s", err.msg);
        return false;
    }
    if (!memcmp(t, &a->scene.lights[l], sizeof *t)) return true;
    bool same = merge && a->light_step_for == l && a->light_step == a->ed.serial && a->ed.undo_count > 0 &&
                a->ed.redo_count == 0;
    if (!same && !sv_edit_begin(a, false)) return false;
    a->scene.lights[l] = *t;
    a->light_serial++;
    a->light_step_for = merge ? l : NO_SEL, a->light_step = a->ed.serial;
    return true;
}

/* After the materials changed (an edit; undo and redo go through
 * update_instances, which does the same): the gi methods read them when made
 * (metal and glass, emission) and the frame renderer's emission table. */
static void materials_changed(app* a) {
    sv_probe_bake_cancel(a, "the materials changed");
    vx_frame_renderer* fr = a->fr;
    a->fr = NULL;
    drop_passes(a); /* the gi methods; the frame renderer keeps its buffers and frames in flight */
    a->fr = fr;
    vx_error err = {0};
    if (a->fr && vx_frame_renderer_update_scene(a->fr, &a->scene, &err)) {
        vx_frame_renderer_destroy(a->fr);
        a->fr = NULL;
    }
    if (!a->fr && a->rs && vx_frame_renderer_create(a->rs, &a->scene, &a->fr, &err))
        sv_message(a, true, "pass pipeline: %s", err.msg);
}

bool sv_set_material(app* a, uint32_t id, const char* field, const char* value, bool merge) {
    const char* keys[2];
    char values[2][32], why[256];
    uint32_t n;
    if (!sv_material_field(field, value, keys, values, &n, why, sizeof why)) {
        sv_message(a, true, "material %u: %s", id, why);
        return false;
    }
    /* nothing to do when every pair is there already */
    const vx_svo_material* m = NULL;
    for (uint32_t i = 0; i < a->scene.material_count && !m; i++)
        if (a->scene.materials[i].id == id) m = &a->scene.materials[i];
    bool same = true;
    for (uint32_t k = 0; k < n; k++) {
        const char* v = vx_svo_material_get(m, keys[k]);
        same = same && v && !strcmp(v, values[k]);
    }
    if (same) return true;
    bool merged = merge && a->mat_step_for == id && a->mat_step == a->ed.serial && a->ed.undo_count > 0 &&
                  a->ed.redo_count == 0;
    vx_error err = {0};
    if (!merged) {
        if (ved_begin_materials(&a->ed, &err)) {
            sv_message(a, true, "%s", err.msg);
            return false;
        }
    }
    for (uint32_t k = 0; k < n; k++)
        if (ved_material_set(&a->scene, id, keys[k], values[k], &err)) {
            sv_message(a, true, "%s", err.msg); /* out of memory: the pairs set so far stay (an undo step) */
            break;
        }
    a->mat_step_for = merge ? id : NO_SEL, a->mat_step = a->ed.serial;
    materials_changed(a);
    if (a->o.verbose) printf("%s: material %u %s %s\n", vx_tool_name, id, field, value);
    return true;
}

bool sv_set_gi_option(app* a, const char* name, const char* value) {
    char why[320];
    if (!sv_gi_option(&a->gis, name, value, why, sizeof why)) {
        sv_message(a, true, "gi: %s", why);
        return false;
    }
    /* the gi methods are made with these at the next frame */
    vx_frame_renderer* fr = a->fr;
    a->fr = NULL;
    drop_passes(a);
    a->fr = fr;
    a->timing_count = 0;
    return true;
}

/* ---- frames -------------------------------------------------------------------------- */

static uint8_t to8(float v) {
    v = v < 0 ? 0 : (v > 1 ? 1 : v);
    return (uint8_t)lrintf(v * 255.0f);
}

/* Float pixels -> display bytes: colour modes exactly as svo_render's PNG;
 * normals as 0.5 n + 0.5; depth as grey, near = bright. */
static void convert(app* a, const vx_render_image* img, vf_canvas* cv) {
    size_t n = (size_t)img->width * img->height;
    float dmax = 0;
    if (img->mode == VX_RENDER_DEPTH)
        for (size_t i = 0; i < n; i++)
            if (isfinite(img->pixels[4 * i]) && img->pixels[4 * i] > dmax) dmax = img->pixels[4 * i];
    int r = cv->bgra ? 2 : 0, b = cv->bgra ? 0 : 2;
    for (size_t i = 0; i < n; i++) {
        const float* s = img->pixels + 4 * i;
        uint8_t* d = cv->pixels + 4 * i;
        float c[3] = {s[0], s[1], s[2]};
        if (img->mode == VX_RENDER_NORMAL) {
            for (int k = 0; k < 3; k++) c[k] = 0.5f * c[k] + 0.5f;
        } else if (img->mode == VX_RENDER_DEPTH) {
            float g = isfinite(s[0]) && dmax > 0 ? 1.0f - 0.8f * s[0] / dmax : 0.0f;
            c[0] = c[1] = c[2] = g;
        }
        d[r] = to8(c[0]);
        d[1] = to8(c[1]);
        d[b] = to8(c[2]);
        d[3] = 255;
    }
    (void)a;
}

/* Writes the tracer's image the way svo_render does. */
static vx_result save_image(const vx_render_image* img, const char* path, vx_error* err) {
    size_t npx = (size_t)img->width * img->height;
    bool exr = !strcmp(vx_tool_ext(path), "exr");
    vx_image_desc id = {.width = img->width, .height = img->height};
    void* buf = NULL;
    if (exr && img->mode == VX_RENDER_DEPTH) {
        float* p = malloc(npx * 4);
        for (size_t i = 0; p && i < npx; i++) p[i] = img->pixels[4 * i];
        buf = p, id.channels = 1, id.type = VX_IMAGE_F32;
    } else if (exr) {
        float* p = malloc(npx * 12);
        for (size_t i = 0; p && i < npx; i++) memcpy(p + 3 * i, img->pixels + 4 * i, 12);
        buf = p, id.channels = 3, id.type = VX_IMAGE_F32;
    } else {
        uint8_t* p = malloc(npx * 3);
        for (size_t i = 0; p && i < npx; i++) {
            const float* s = img->pixels + 4 * i;
            for (int k = 0; k < 3; k++) {
                float v = s[k];
                if (img->mode == VX_RENDER_NORMAL) v = 0.5f * v + 0.5f;
                p[3 * i + k] = to8(v);
            }
        }
        buf = p, id.channels = 3, id.type = VX_IMAGE_U8;
    }
    if (!buf) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    id.pixels = buf;
    vx_result r = vx_image_write(path, &id, err);
    free(buf);
    return r;
}

/* Writes the displayed 8-bit frame (panels and overlay included) as PNG. */
static vx_result save_canvas(const vf_canvas* cv, const char* path, vx_error* err) {
    size_t npx = (size_t)cv->width * cv->height;
    uint8_t* p = malloc(npx * 3);
    if (!p) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    int r = cv->bgra ? 2 : 0, b = cv->bgra ? 0 : 2;
    for (size_t i = 0; i < npx; i++) {
        p[3 * i] = cv->pixels[4 * i + r];
        p[3 * i + 1] = cv->pixels[4 * i + 1];
        p[3 * i + 2] = cv->pixels[4 * i + b];
    }
    vx_image_desc id = {.width = cv->width, .height = cv->height, .channels = 3, .type = VX_IMAGE_U8, .pixels = p};
    vx_result res = vx_image_write(path, &id, err);
    free(p);
    return res;
}

/* Projects a world point with the frame's camera (as the tracer sets it up). */
static bool project(const app* a, const double eye[3], const double f[3], uint32_t w, uint32_t h, const double p[3],
                    double* sx, double* sy) {
    double up[3] = {0, 0, 1}, r[3], u[3];
    r[0] = f[1] * up[2] - f[2] * up[1], r[1] = f[2] * up[0] - f[0] * up[2], r[2] = f[0] * up[1] - f[1] * up[0];
    double rl = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    if (!(rl > 0)) return false;
    for (int k = 0; k < 3; k++) r[k] /= rl;
    u[0] = r[1] * f[2] - r[2] * f[1], u[1] = r[2] * f[0] - r[0] * f[2], u[2] = r[0] * f[1] - r[1] * f[0];
    double v[3] = {p[0] - eye[0], p[1] - eye[1], p[2] - eye[2]};
    double z = v[0] * f[0] + v[1] * f[1] + v[2] * f[2];
    if (z < 1e-6) return false;
    double hh = tan(0.5 * a->o.fov * PI / 180.0), aspect = (double)w / h;
    double x = (v[0] * r[0] + v[1] * r[1] + v[2] * r[2]) / (z * hh * aspect);
    double y = (v[0] * u[0] + v[1] * u[1] + v[2] * u[2]) / (z * hh);
    *sx = (x + 1) * 0.5 * w;
    *sy = (1 - y) * 0.5 * h;
    return true;
}

/* The probe grid (panel: show grid): each probe a square at its position,
 * green at its grid point, yellow moved out of a voxel, red disabled; the
 * probe whose maps the panel shows larger and white; baked probes filled. */
static void draw_probe_grid(app* a, vf_canvas* cv) {
    const vx_probe_set* ps = sv_probe_shown(a);
    if (!a->probe_grid || !ps) return;
    double f[3];
    cam_fwd(a, f);
    for (uint32_t i = 0; i < ps->probe_count; i++) {
        double x, y;
        if (!project(a, a->eye, f, cv->width, cv->height, ps->probes[i].pos, &x, &y)) continue;
        uint32_t st = ps->probes[i].state;
        uint32_t c = i == a->probe_sel ? 0x00FFFFFFu : st == VX_PROBE_OK ? 0x0040E040u : st == VX_PROBE_MOVED ? 0x0030E0F0u
                                                                                                            : 0x002020F0u;
        int r = i == a->probe_sel ? 4 : 2;
        bool baked = i >= ps->first && i < ps->first + ps->count;
        if (baked) vf_fill_rect(cv, (int)x - r, (int)y - r, 2 * r + 1, 2 * r + 1, c, 255);
        else {
            vf_fill_rect(cv, (int)x - r, (int)y - r, 2 * r + 1, 1, c, 255);
            vf_fill_rect(cv, (int)x - r, (int)y + r, 2 * r + 1, 1, c, 255);
            vf_fill_rect(cv, (int)x - r, (int)y - r, 1, 2 * r + 1, c, 255);
            vf_fill_rect(cv, (int)x + r, (int)y - r, 1, 2 * r + 1, c, 255);
        }
    }
}

static void draw_selection(app* a, vf_canvas* cv) {
    if (a->sel == NO_SEL || a->sel >= a->scene.instance_count) return;
    double lo[3], hi[3], f[3];
    world_box(a, a->sel, lo, hi);
    cam_fwd(a, f);
    static const int edges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                     {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
    for (int e = 0; e < 12; e++) {
        double p[2][3], s[2][2];
        bool ok = true;
        for (int j = 0; j < 2; j++) {
            int c = edges[e][j];
            p[j][0] = (c & 1) ? hi[0] : lo[0], p[j][1] = (c & 2) ? hi[1] : lo[1], p[j][2] = (c & 4) ? hi[2] : lo[2];
            ok &= project(a, a->eye, f, cv->width, cv->height, p[j], &s[j][0], &s[j][1]);
        }
        if (ok) vf_line(cv, s[0][0], s[0][1], s[1][0], s[1][1], 0x00FFB020u, 2);
    }
}

static void draw_overlay(app* a, vf_canvas* cv) {
    char line[512];
    int y = 6, sc = cv->height >= 900 ? 2 : 1, lh = 10 * sc;
    double sorted[64];
    uint32_t n = a->frame_n < 64 ? a->frame_n : 64;
    memcpy(sorted, a->frame_ms, n * sizeof *sorted);
    double med = 0;
    for (uint32_t i = 0; i < n; i++) med += sorted[i];
    med = n ? med / n : 0;
    uint64_t voxels = 0;
    uint32_t nd = 0;
    for (uint32_t i = 0; i < a->scene.instance_count; i++)
        if (vx_svo_instance_drawn(&a->scene, i)) nd++, voxels += a->scene.models[a->scene.instances[i].model].voxel_count;
    const char* lines[10];
    char buf[10][256];
    int nl = 0;
    snprintf(buf[nl], sizeof buf[0], "FPS %.1f  frame %.2f ms  trace %.2f ms  %.1f Mrays/s  edit+BVH %.2f ms",
             med > 0 ? 1000.0 / med : 0.0, med, a->trace_ms, a->rays_per_s * 1e-6, a->update_ms);
    lines[nl] = buf[nl], nl++;
    snprintf(buf[nl], sizeof buf[0], "device: %s%s", vx_gpu_device_name(a->gpu), vx_gpu_is_cpu(a->gpu) ? " (software)" : "");
    lines[nl] = buf[nl], nl++;
    snprintf(buf[nl], sizeof buf[0], "scene: %u models, %u instances (%u drawn), %s voxels, %u layers",
             a->scene.model_count, a->scene.instance_count, nd, vx_tool_num(voxels), a->scene.layer_count);
    lines[nl] = buf[nl], nl++;
    snprintf(buf[nl], sizeof buf[0], "mode: %s  camera: %s  vsync: %s  size %ux%u", sv_mode_name(a),
             a->orbit ? "orbit" : "fly", vp_vsync(a->p) ? "on" : "off", cv->width, cv->height);
    lines[nl] = buf[nl], nl++;
    if (a->timing_count && !a->gi && a->mode == VX_RENDER_COLOR) {
        int at = snprintf(buf[nl], sizeof buf[0], "passes (9 cycles):");
        for (uint32_t t = 0; t < a->timing_count && at > 0 && at < (int)sizeof buf[0]; t++)
            at += snprintf(buf[nl] + at, sizeof buf[0] - (size_t)at, " %s %.2f", a->timings[t].name, a->timings[t].ms);
        if (at > 0 && at < (int)sizeof buf[0]) snprintf(buf[nl] + at, sizeof buf[0] - (size_t)at, " ms  (GPU %.2f)", a->passes_ms);
        lines[nl] = buf[nl], nl++;
    }
    if (a->have_probes) {
        const vx_probe_set* ps = &a->probes;
        snprintf(buf[nl], sizeof buf[0], "probes: %ux%ux%u grid (%u probes, res %u, %u bounces)%s", ps->grid[0],
                 ps->grid[1], ps->grid[2], ps->probe_count, ps->res, ps->bounces, a->gi ? "" : "  7: gi  8: lightfield");
        lines[nl] = buf[nl], nl++;
    }
    if (a->sel != NO_SEL) {
        const vx_svo_instance* in = &a->scene.instances[a->sel];
        snprintf(buf[nl], sizeof buf[0], "selected: instance %u '%s' model %u at %g,%g,%g", a->sel, in->name, in->model,
                 in->xform[3], in->xform[7], in->xform[11]);
        lines[nl] = buf[nl], nl++;
    }
    if (a->op) {
        const char* what = a->op == 'g' ? "move" : a->op == 'r' ? "rotate" : a->op == 'm' ? "mirror" : "layer";
        if (a->op == 'l') snprintf(buf[nl], sizeof buf[0], "layer: press 0-9 to hide/show a layer");
        else if (a->op == 'g' && a->op_axis >= 0)
            snprintf(buf[nl], sizeof buf[0], "move along %c: %d voxels (arrows or mouse, Enter, Esc)", 'X' + a->op_axis,
                     a->grab_moved);
        else snprintf(buf[nl], sizeof buf[0], "%s: press X, Y or Z", what);
        lines[nl] = buf[nl], nl++;
    }
    int w = 0;
    for (int i = 0; i < nl; i++) w = fmax(w, (int)strlen(lines[i]));
    vf_fill_rect(cv, 0, 0, w * 6 * sc + 12, nl * lh + 8, 0, 150);
    for (int i = 0; i < nl; i++, y += lh) vf_text(cv, 6, y, sc, 0x00FFFFFFu, lines[i]);
    if (a->msg[0] && glfwGetTime() < a->msg_until) {
        snprintf(line, sizeof line, "%s", a->msg);
        int my = (int)cv->height - 2 * lh - 8;
        vf_fill_rect(cv, 0, my - 4, (int)strlen(line) * 6 * sc + 12, lh + 6, 0, 170);
        vf_text(cv, 6, my, sc, a->msg_error ? 0x004060FFu : 0x0060FF60u, line);
    }
}

/* The colour mode through the pass pipeline (a->passes): svo_render's
 * --passes frame for the same camera; per-pass times kept for the overlay. */
/* The file's sky for the passes, as svo_render uses it: constant and
 * gradient as stored, an environment map's texels read through OpenImageIO
 * (once per map); *sky NULL without one or when the map cannot be read (a
 * message says why, once). */
static void file_sky(app* a, const vx_sky** sky, const vx_sky_texels** map) {
    *sky = NULL, *map = NULL;
    const vx_sky* k = &a->scene.sky;
    if (k->type == VX_SKY_DEFAULT) return;
    if (k->type != VX_SKY_ENVMAP) {
        *sky = k;
        return;
    }
    char path[sizeof a->sky_file];
    if (!vx_sky_path(k, a->scene_file, path, sizeof path)) return;
    if (strcmp(path, a->sky_file)) {
        vx_free(NULL, a->sky_rgb);
        a->sky_rgb = NULL, a->sky_map = (vx_sky_texels){0};
        snprintf(a->sky_file, sizeof a->sky_file, "%s", path);
        uint32_t w = 0, h = 0, ch = 0;
        float* px = NULL;
        vx_error err = {0};
        if (vx_image_read(path, VX_IMAGE_F32, 0, &w, &h, &ch, (void**)&px, &err)) {
            sv_message(a, true, "the sky's environment map: %s", err.msg);
            return;
        }
        /* RGB per texel whatever the file has (grey: one channel; alpha dropped) */
        a->sky_rgb = vx_calloc(NULL, (size_t)w * h, 3 * sizeof(float));
        for (size_t i = 0; a->sky_rgb && i < (size_t)w * h; i++)
            for (uint32_t c = 0; c < 3; c++) a->sky_rgb[3 * i + c] = px[i * ch + (c < ch ? c : 0)];
        vx_free(NULL, px);
        if (!a->sky_rgb) {
            sv_message(a, true, "%s: out of memory for the sky's environment map", path);
            return;
        }
        a->sky_map = (vx_sky_texels){.rgb = a->sky_rgb, .width = w, .height = h};
    }
    if (a->sky_rgb) *sky = k, *map = &a->sky_map;
}

/* A frame's pass times: the overlay's and the statistics panel's numbers
 * and history. */
static void take_timings(app* a, const vx_frame_result* res) {
    memcpy(a->timings, res->timings, sizeof a->timings);
    a->timing_count = res->timing_count;
    a->passes_ms = res->frame_ms;
    /* the statistics panel's history; a different pass list starts it again */
    bool same = a->hist_layers == res->timing_count;
    for (uint32_t t = 0; same && t < res->timing_count; t++) same = a->hist_names[t] == res->timings[t].name ||
                                                                    !strcmp(a->hist_names[t], res->timings[t].name);
    if (!same) a->hist_n = 0, a->hist_layers = res->timing_count;
    for (uint32_t t = 0; t < res->timing_count; t++) a->hist_names[t] = res->timings[t].name;
    if (a->hist_n == SV_HISTORY) memmove(a->hist[0], a->hist[1], (SV_HISTORY - 1) * sizeof a->hist[0]);
    else a->hist_n++;
    for (uint32_t t = 0; t < res->timing_count; t++) a->hist[a->hist_n - 1][t] = (float)res->timings[t].ms;
}

/* The colour passes: rendered and waited for (cmd NULL), or recorded into
 * cmd for frame slot `slot` (frames in flight: the times come with the
 * slot's next frame, take_timings). */
/* The frame's description (the state the pass pipeline renders). */
static vx_result frame_desc(app* a, const vx_render_desc* d, bool on_gpu, vx_frame_desc* out, vx_error* err) {
    const vx_sky* sky;
    const vx_sky_texels* sky_map;
    file_sky(a, &sky, &sky_map);
    /* the gi methods are made with the file's lights (as in svo_render:
     * gi=pathtrace and gi=cones carry them, the probe methods give them to
     * the direct pass): made again when the lights changed */
    if ((a->pgi || a->cgi || a->phgi) && a->gi_light_serial != a->light_serial) {
        vx_probe_gi_destroy(a->pgi);
        a->pgi = NULL;
        vx_cone_gi_destroy(a->cgi);
        a->cgi = NULL;
        vx_photon_gi_destroy(a->phgi);
        a->phgi = NULL;
    }
    a->gi_light_serial = a->light_serial;
    bool made = a->pgi || a->cgi || a->phgi;
    if (vx_pass_list_has(&a->passes, VX_PASS_GI) && !made && !strcmp(a->passes.gi, "cones")) {
        /* the render panel's settings (svo_render's --cone-*), the file's lights and sky */
        vx_cone_desc cd = a->gis.cone;
        cd.sky_dir = sky, cd.sky_map = sky_map, cd.lights = a->scene.lights, cd.light_count = a->scene.light_count;
        vx_result r = vx_cone_gi_create(a->rs, &a->scene, &cd, &a->gm, &a->cgi, err);
        if (r) return r;
    } else if (vx_pass_list_has(&a->passes, VX_PASS_GI) && !made && !strcmp(a->passes.gi, "photons")) {
        /* svo_render's gi=photons with the render panel's settings (--photons, --radius, --final-gather, --seed;
         * zero: photons.h's defaults), the file's lights and sky */
        vx_photon_desc pd = a->gis.photon;
        pd.seed = a->gis.seed;
        pd.sky_dir = sky, pd.sky_map = sky_map, pd.lights = a->scene.lights, pd.light_count = a->scene.light_count;
        vx_result r = vx_photon_gi_create(a->rs, &a->scene, a->have_probes ? &a->probes : NULL, &pd, &a->gm, &a->phgi, err);
        if (r) return r;
    } else if (vx_pass_list_has(&a->passes, VX_PASS_GI) && !made) {
        vx_probe_render_desc pd = {.sky = sky, .sky_map = sky_map, .bounces = a->gis.bounces, .seed = a->gis.seed};
        pd.lights = a->scene.lights, pd.light_count = a->scene.light_count;
        vx_result r = vx_probe_gi_create(a->rs, &a->scene, a->have_probes ? &a->probes : NULL, a->passes.gi, &pd,
                                         &a->gm, &a->pgi, err);
        if (r) return r;
    }
    vx_frame_desc fd = vx_frame_desc_defaults();
    fd.base = *d;
    fd.base.mode = VX_RENDER_COLOR;
    fd.base.spp = a->gis.spp; /* 0: the pipeline's default (1, or 8 with aa or dof) */
    fd.seed = a->gis.seed;
    fd.ao_rays = a->gis.ao_rays, fd.ao_radius = a->gis.ao_radius;
    fd.passes = &a->passes;
    if (a->gis.cone.shadows && vx_pass_list_has(&a->passes, VX_PASS_GI) && !strcmp(a->passes.gi, "cones")) {
        /* cone shadows: the gi pass brings the direct light, so no direct pass (as svo_render drops it) */
        a->passes_run = a->passes;
        uint32_t k = 0;
        for (uint32_t j = 0; j < a->passes.count; j++)
            if (a->passes.kinds[j] != VX_PASS_DIRECT) a->passes_run.kinds[k++] = a->passes.kinds[j];
        a->passes_run.count = k;
        fd.passes = &a->passes_run;
    }
    fd.gi = a->pgi || a->cgi || a->phgi ? &a->gm : NULL;
    fd.want_ids = d->want_hits;
    fd.no_readback = on_gpu; /* the image stays on the GPU for vx_display */
    fd.exposure = a->exposure;
    /* the file's lights, as svo_render uses them by default (edited in the properties panel) */
    fd.lights = a->scene.lights;
    fd.light_count = a->scene.light_count;
    fd.sky_dir = sky, fd.sky_map = sky_map; /* and its sky */
    *out = fd;
    return VX_OK;
}

/* A frame submitted and waited for (frames in flight: present_in_flight). */
static vx_result render_passes(app* a, const vx_render_desc* d, bool on_gpu, vx_error* err) {
    vx_frame_desc fd;
    vx_frame_result res;
    vx_result r = frame_desc(a, d, on_gpu, &fd, err);
    if (r || (r = vx_frame_render(a->fr, &fd, &res, err))) return r;
    a->img = res.image;
    take_timings(a, &res);
    return VX_OK;
}

/* Frames in flight (render/display.h): the passes, the conversion with the
 * overlay and the copy into the swapchain image in one command buffer,
 * submitted and presented without waiting for it; vx_display_frame_begin
 * waits only for the frame VX_DISPLAY_FRAMES before, whose pass times the
 * statistics then show. Where the swapchain images are storage images the
 * frame's last pass writes the image itself (vx_display_record_frame: no
 * conversion pass), so the image is acquired before the passes are
 * recorded. VX_ERR_UNSUPPORTED, nothing submitted: a frame the recorder
 * refuses (lights that need a culling grid), which takes the waited path. */
static vx_result batch_drain(app* a, vx_error* err);

static vx_result present_in_flight(app* a, const vx_render_desc* d, const vx_display_desc* dd, vx_error* err) {
    uint32_t slot;
    void* cmd;
    if (!a->o.batch) { /* --batch auto: the batch the measured frames ask for, the held frames presented first */
        uint32_t want = sv_batch_want(&a->batch, vp_vsync(a->p));
        if (want != a->batch.cur) {
            vx_result br = batch_drain(a, err);
            if (!br) br = vx_display_set_queue(a->disp, want > 1 ? 2 * want : 0, want, false, err);
            if (br) return br;
            if (a->o.verbose)
                printf("%s: %u frames a submission from frame %llu (--batch auto)\n", vx_tool_name, want,
                       (unsigned long long)a->frames_recorded);
            sv_batch_set(&a->batch, want);
        }
    }
    vx_result r = vx_display_frame_begin(a->disp, &slot, &cmd, err);
    if (r) return r;
    vx_frame_result done;
    bool timed = !vx_frame_record_result(a->fr, slot, &done, NULL) && done.frame_ms > 0;
    sv_batch_frame(&a->batch, timed ? done.frame_ms : 0);
    if (timed) { /* a frame that was timed */
        take_timings(a, &done);
        a->trace_ms = done.image.gpu_seconds * 1e3;
        a->rays_per_s = done.image.gpu_seconds > 0 ? done.image.rays / done.image.gpu_seconds : 0;
    }
    vx_frame_desc fd;
    vp_image im;
    r = frame_desc(a, d, true, &fd, err);
    /* the passes' timestamps in one frame of 8, fewer for short frames (the statistics' times; each timed frame
     * costs an H200 a few microseconds more: batch.h) */
    fd.no_timestamps = !sv_batch_timed(&a->batch);
    vx_display_times dt;
    if (a->batch.max > 1 && vp_stale(a->p)) {
        /* a new swapchain next: the held frames submitted and their images presented before the old one goes */
        vx_result wr = vx_display_wait(a->disp, err);
        vx_display_frame_times(a->disp, &dt);
        if (!r && !wr) wr = vp_present_submitted(a->p, dt.frames_submitted, err);
        if (!r) r = wr;
    }
    vx_display_frame_times(a->disp, &dt);
    vp_set_frame_number(a->p, a->frames_recorded); /* the display numbers its frames as they are submitted */
    if (r || (r = vx_frame_recordable(&fd, err)) || (r = vp_acquire(a->p, slot, &im, err))) {
        vx_display_frame_cancel(a->disp);
        return r;
    }
    /* without an image (minimised, a new swapchain next frame) the passes still run, unseen */
    vx_frame_result res;
    bool fused = im.image && im.view;
    /* the panels drawn over the image after the last pass wrote it, in the same command buffer */
    bool panels = fused && a->panels_gpu_now;
    r = fused ? vx_display_record_frame(a->disp, a->fr, &fd, dd, im.image, im.view, im.width, im.height,
                                        panels ? VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL : im.layout, &res, err)
              : vx_frame_record(a->fr, &fd, cmd, slot, &res, err);
    char why[256];
    if (!r && panels && !sv_panels_gpu_record(a, cmd, slot, im.view, im.width, im.height, why, sizeof why))
        r = vx_fail(err, VX_ERR_GPU, VX_NO_OFFSET, "%s", why);
    if (r) {
        /* the acquired image is still presented (its semaphore waited for): cleared, in the slot's frame again */
        vx_frame_record_cancel(a->fr);
        vx_display_frame_cancel(a->disp);
        vx_error again;
        if (!im.image || vx_display_frame_begin(a->disp, &slot, &cmd, &again)) return r;
        vx_display_copy_to_image(cmd, 0, dd->width, dd->height, im.image, im.width, im.height, im.layout);
    } else if (im.image && !fused) {
        a->img = res.image;
        uint64_t bytes = 0;
        r = vx_display_record(a->disp, cmd, dd, &bytes, err);
        vx_display_copy_to_image(cmd, r ? 0 : bytes, dd->width, dd->height, im.image, im.width, im.height, im.layout);
    } else {
        a->img = res.image;
    }
    vx_result sr = vx_display_frame_submit(a->disp, im.acquired, im.rendered, err);
    if (!sr) a->frames_recorded++;
    if (!sr && im.image) sr = vp_present_acquired(a->p, err);
    if (!sr && a->batch.max > 1) { /* the frames submitted by now (this batch, or held ones an edit submitted) */
        vx_display_frame_times(a->disp, &dt);
        sr = vp_present_submitted(a->p, dt.frames_submitted, err);
    }
    return sr ? sr : r;
}

/* Before a frame that is not a frame in flight (a grab, another mode, the
 * host path): the frames a batch holds submitted and presented, so that the
 * images go to the screen in the order they were made. */
static vx_result batch_drain(app* a, vx_error* err) {
    if (a->batch.max <= 1 || !a->disp) return VX_OK;
    vx_result r = vx_display_wait(a->disp, err);
    vx_display_times dt;
    vx_display_frame_times(a->disp, &dt);
    vx_result pr = vp_present_submitted(a->p, dt.frames_submitted, err);
    return r ? r : pr;
}

/* Sets the pass list (script command `passes LIST`, key 9 cycles presets). */
bool sv_set_passes(app* a, const char* list) {
    vx_pass_list pl;
    vx_error err = {0};
    if (vx_pass_list_parse(list, &pl, &err)) {
        sv_message(a, true, "passes: %s", err.msg);
        return false;
    }
    if (vx_pass_list_has(&pl, VX_PASS_GI) && strcmp(pl.gi, "pathtrace") && strcmp(pl.gi, "cones") &&
        strcmp(pl.gi, "photons") && !a->have_probes) {
        sv_message(a, true, "gi=%s needs light field probes (--probes FILE, or the script command probes FILE)", pl.gi);
        return false;
    }
    vx_probe_gi_destroy(a->pgi);
    a->pgi = NULL;
    vx_cone_gi_destroy(a->cgi);
    a->cgi = NULL;
    vx_photon_gi_destroy(a->phgi);
    a->phgi = NULL;
    a->passes = pl;
    a->timing_count = 0;
    char t[160];
    vx_pass_list_format(&pl, t, sizeof t);
    sv_message(a, false, "passes %s", t[0] ? t : "(none)");
    return true;
}

/* The model cell a voxel click edits: for add the empty cell in front of the
 * hit face (the face the pixel's ray enters the hit cell through, found by
 * the slab test in model space with the tracer's own ray), else the hit cell;
 * with the face brush the hit cell and that face (*face, 0..5). */
static void click_target(const app* a, const vx_render_desc* d, uint32_t x, uint32_t y, const vx_render_hit* hit,
                         vvx_op op, int64_t out[3], uint8_t* face) {
    for (int k = 0; k < 3; k++) out[k] = hit->cell[k];
    bool want_face = a->brush.shape == VVX_FACE;
    if (op != VVX_ADD && !want_face) return;
    double lo[3], hi[3], wi[12], mi[12];
    vx_svo_scene_world_bounds(&a->scene, lo, hi);
    vx__frame f;
    const vx_svo_instance* in = vx_svo_scene_frame_instances(&a->scene, a->anim_frame) + hit->instance;
    if (vx__frame_setup(lo, hi, d, &f, NULL) || !vx__affine_inverse(a->scene.world_from_grid, wi) ||
        !vx__affine_inverse(in->xform, mi))
        return;
    double u = ((x + 0.5) / f.width) * 2 - 1, v = 1 - ((y + 0.5) / f.height) * 2, o[3], dir[3], og[3], dg[3], om[3], dm[3];
    for (int k = 0; k < 3; k++) {
        double off = u * f.rx[k] + v * f.uy[k];
        o[k] = f.ref[k] + (f.ortho ? off : f.t_start * off);
        dir[k] = f.ortho ? f.fwd[k] : f.fwd[k] + off;
    }
    vx__affine_apply(wi, o, og);
    vx__affine_apply(mi, og, om);
    for (int r = 0; r < 3; r++) dg[r] = wi[4 * r] * dir[0] + wi[4 * r + 1] * dir[1] + wi[4 * r + 2] * dir[2];
    for (int r = 0; r < 3; r++) dm[r] = mi[4 * r] * dg[0] + mi[4 * r + 1] * dg[1] + mi[4 * r + 2] * dg[2];
    int axis = -1;
    double best = -INFINITY;
    for (int k = 0; k < 3; k++) {
        if (dm[k] == 0) continue; /* parallel to the slab: never the entry face */
        double t1 = ((double)hit->cell[k] - om[k]) / dm[k], t2 = ((double)hit->cell[k] + 1 - om[k]) / dm[k];
        double tn = fmin(t1, t2);
        if (tn > best) best = tn, axis = k;
    }
    if (axis >= 0 && want_face) *face = (uint8_t)(2 * axis + (dm[axis] > 0 ? 0 : 1));
    else if (axis >= 0) out[axis] += dm[axis] > 0 ? -1 : 1;
}

/* Renders, converts, overlays and presents one frame. */
static vx_result frame(app* a, vx_error* err) {
    uint32_t w = a->o.width, h = a->o.height;
    if (!w) {
        vp_frame_size(a->p, &w, &h);
        if (!w || !h) return VX_OK;
    }
    double t0 = vx_time_now();
    vx_render_image_free(&a->img);
    vx_render_desc d = {.width = w, .height = h, .mode = a->mode, .camera = camera_desc(a), .want_hits = a->pick_pending};
    vx_render_image pick_img = {0}; /* gi frames carry no hit records: a pick traces its own */
    if (a->rs && a->gi) {
        /* svo_render --mode gi|lightfield: its default spp, seed and bounces, the probes' light */
        vx_render_desc base = {.width = w, .height = h, .camera = d.camera};
        vx_probe_render_desc pd = {.base = &base, .mode = a->pmode};
        /* the probe maps stay on the GPU between frames (light field maps: up to
         * hundreds of MB) until the scene is rebuilt or other probes load */
        vx_result r = a->probes_gpu ? VX_OK : vx_probe_gpu_create(a->rs, &a->scene, &a->probes, &a->probes_gpu, err);
        if (!r) r = vx_probe_gpu_render(a->probes_gpu, &pd, &a->img, err);
        if (r && (a->o.screenshot || a->o.bench)) return r;
        if (r) {
            sv_message(a, true, "mode %s: %s", vx_probe_render_mode_name(a->pmode), err->msg);
            a->gi = false;
        } else if (a->pick_pending && (r = vx_render_frame(a->rs, &d, &pick_img, err))) {
            return r;
        }
    }
    bool passes = a->rs && !a->gi && a->mode == VX_RENDER_COLOR && a->fr && !vx_render_scene_precise(a->rs);
    /* the GPU path: the colour passes' image, unless this frame's pixels are wanted on the host */
    bool on_gpu = a->disp && passes && !a->pick_pending && !a->shot && !a->o.screenshot;
    /* frames in flight: all GPU-path frames but grabs (read back after a wait) */
    bool fly = on_gpu && !a->grab;
    if (passes && !fly) {
        vx_result r = render_passes(a, &d, on_gpu, err);
        if (r) return r;
    } else if (a->rs && !a->gi && !passes) {
        vx_result r = vx_render_frame(a->rs, &d, &a->img, err);
        if (r) return r;
    }
    if (a->rs && (a->img.pixels || (on_gpu && !fly))) {
        a->trace_ms = a->img.gpu_seconds * 1e3;
        a->rays_per_s = a->img.gpu_seconds > 0 ? a->img.rays / a->img.gpu_seconds : 0;
    }
    if (a->pick_pending) {
        a->pick_pending = false;
        uint32_t x = (uint32_t)a->pick_x, y = (uint32_t)a->pick_y;
        uint32_t hit = VX_RENDER_NO_HIT;
        const vx_render_hit* hits = pick_img.hits ? pick_img.hits : a->img.hits;
        vx_render_hit hr = {.instance = VX_RENDER_NO_HIT};
        if (hits && a->pick_x >= 0 && a->pick_y >= 0 && x < w && y < h) hr = hits[(size_t)y * w + x];
        hit = hr.instance;
        vx_render_image_free(&pick_img);
        if (a->pick_op >= 0) {
            /* a voxel click edits the hit instance's model (and selects it) */
            vvx_op op = (vvx_op)a->pick_op;
            a->pick_op = -1;
            if (hit == VX_RENDER_NO_HIT || hit >= a->scene.instance_count) {
                printf("%s: voxel %s at %u %u: nothing there\n", vx_tool_name, vvx_op_name(op), x, y);
            } else {
                int64_t c[3];
                click_target(a, &d, x, y, &hr, op, c, &a->brush.face);
                a->sel = hit;
                printf("%s: voxel %s at %u %u: instance %u cell %lld %lld %lld\n", vx_tool_name, vvx_op_name(op), x, y,
                       hit, (long long)c[0], (long long)c[1], (long long)c[2]);
                sv_voxels(a, op, c);
            }
        } else {
            a->sel = hit == VX_RENDER_NO_HIT ? NO_SEL : hit;
            if (hit == VX_RENDER_NO_HIT) printf("%s: pick %u %u: nothing\n", vx_tool_name, x, y);
            else printf("%s: pick %u %u: instance %u cell %u %u %u\n", vx_tool_name, x, y, hit, hr.cell[0], hr.cell[1], hr.cell[2]);
        }
    }
    if (a->shot && a->img.pixels) {
        vx_result r = save_image(&a->img, a->shot, err);
        if (r) sv_message(a, true, "%s: %s", a->shot, err->msg);
        else printf("%s: wrote %s (%ux%u, mode %s)\n", vx_tool_name, a->shot, w, h, sv_mode_name(a));
        if (r && a->o.screenshot) return r;
    }
    a->shot = NULL;
    size_t need = (size_t)w * h * 4;
    if (need > a->px8_cap) {
        free(a->px8);
        a->px8 = malloc(need);
        a->px8_cap = a->px8 ? need : 0;
        if (!a->px8) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for a %ux%u frame", w, h);
    }
    vf_canvas cv = {.pixels = a->px8, .width = w, .height = h, .bgra = vp_frame_bgra(a->p)};
    /* the panels on the GPU (frames in flight into storage and colour-attachment swapchain images): the overlay
     * then holds only what the CPU still draws (selection, probe grid), and none when nothing */
    bool panels_gpu_was = a->panels_gpu_now;
    a->panels_gpu_now = fly && a->panels_gpu && a->ui && a->panels && vp_colour(a->p);
    if (a->panels_gpu_now != panels_gpu_was) a->ui_dirty = true; /* the other way's panels to draw */
    bool draws = !a->o.screenshot &&
                 ((a->ui && a->panels && !a->panels_gpu_now) ||
                  (!a->o.bench && ((a->overlay && !(a->ui && a->panels)) || a->sel != NO_SEL || a->probe_grid)));
    bool panels_draw = a->ui && a->panels && !a->o.screenshot;
    a->frame_on_gpu = on_gpu;
    if (on_gpu) {
        /* the overlay (selection, panels, text) is drawn on the CPU into the
         * display's mapped buffer, again only when something may have changed
         * it: input, a script command, the camera, playback, a bake, a
         * message, a grab, or 250 ms passed (the statistics' numbers) */
        vf_canvas ov = cv;
        double now = vx_time_now(), cam[5] = {a->eye[0], a->eye[1], a->eye[2], a->yaw, a->pitch};
        bool redraw = (draws || panels_draw) &&
                      (a->ui_dirty || !a->ov_valid || a->ov_w != w || a->ov_h != h || a->grab || a->playing ||
                       a->bake.active || a->op || now - a->ov_time > 0.25 || now < a->msg_until + 0.1 ||
                       memcmp(cam, a->ov_cam, sizeof cam) || a->cam_default != a->ov_cam_default);
        if (redraw && draws && !(ov.pixels = vx_display_overlay(a->disp, w, h, err))) return VX_ERR_GPU;
        a->ov_valid = (draws || panels_draw) && (a->ov_valid || redraw);
        a->panels_ms = 0;
        if (redraw) {
            a->ui_dirty = false;
            a->ov_time = now, a->ov_w = w, a->ov_h = h, a->ov_cam_default = a->cam_default;
            memcpy(a->ov_cam, cam, sizeof cam);
            if (draws) {
                draw_probe_grid(a, &ov);
                draw_selection(a, &ov);
            }
            double tp = thread_seconds();
            if (a->ui && a->panels) sv_panels_draw(a, &ov); /* on the GPU: only the draw lists (ov unused) */
            else if (a->overlay) draw_overlay(a, &ov);
            a->panels_ms = a->ui && a->panels ? (thread_seconds() - tp) * 1e3 : 0;
        }
        vx_display_desc dd = {.fr = a->fr, .width = w, .height = h, .bgra = cv.bgra, .overlay = draws};
        vx_result r = VX_ERR_UNSUPPORTED;
        a->frame_in_flight = fly && (r = present_in_flight(a, &d, &dd, err)) != VX_ERR_UNSUPPORTED;
        if (a->frame_in_flight && r) return r;
        if (!a->frame_in_flight && a->panels_gpu_now) {
            /* a frame the recorder refused takes the waited path: the panels drawn on the CPU from now on */
            a->panels_gpu = a->panels_gpu_now = false;
            a->ui_dirty = true;
        }
        if (!a->frame_in_flight) {
            /* the waited path: a grab (read back after the wait), or a frame the recorder refused */
            if ((r = batch_drain(a, err))) return r;
            if (fly) {
                if ((r = render_passes(a, &d, true, err))) return r;
                a->trace_ms = a->img.gpu_seconds * 1e3;
                a->rays_per_s = a->img.gpu_seconds > 0 ? a->img.rays / a->img.gpu_seconds : 0;
            }
            if ((r = vp_present_display(a->p, a->disp, &dd, a->grab ? a->px8 : NULL, err))) return r;
        }
    } else {
        vx_result r = batch_drain(a, err);
        if (r) return r;
        a->ov_valid = false;
        if (a->img.pixels) convert(a, &a->img, &cv);
        else memset(a->px8, 0, need);
        if (draws) {
            draw_probe_grid(a, &cv);
            draw_selection(a, &cv);
            double tp = thread_seconds();
            if (a->ui && a->panels) sv_panels_draw(a, &cv);
            else if (a->overlay) draw_overlay(a, &cv);
            a->panels_ms = a->ui && a->panels ? (thread_seconds() - tp) * 1e3 : 0;
        }
    }
    if (a->grab) {
        vx_result r = save_canvas(&cv, a->grab, err);
        if (r) sv_message(a, true, "%s: %s", a->grab, err->msg);
        else printf("%s: wrote %s (%ux%u, the displayed frame%s)\n", vx_tool_name, a->grab, w, h,
                    on_gpu ? ", read back from the GPU path" : "");
        a->grab = NULL;
    }
    if (!on_gpu) {
        vx_result r = vp_present(a->p, a->px8, w, h, err);
        if (r) return r;
    }
    a->frame_ms[a->frame_n++ % 64] = (vx_time_now() - t0) * 1e3;
    return VX_OK;
}

/* ---- input ---------------------------------------------------------------------------- */

static int axis_key(int key) { return key == GLFW_KEY_X ? 0 : key == GLFW_KEY_Y ? 1 : key == GLFW_KEY_Z ? 2 : -1; }

static void grab_end(app* a, bool keep) {
    if (!keep) {
        ved_undo(&a->ed, NULL); /* back to the snapshot taken at G */
        update_instances(a);
    }
    a->op = 0;
}

static void key_cb(GLFWwindow* win, int key, int sc, int action, int mods) {
    (void)sc;
    app* a = glfwGetWindowUserPointer(win);
    a->ui_dirty = true;
    sv_panels_key(a, key, action != GLFW_RELEASE, mods);
    if (action == GLFW_RELEASE || sv_panels_wants_keyboard(a)) return;
    bool ctrl = mods & GLFW_MOD_CONTROL, shift = mods & GLFW_MOD_SHIFT, alt = mods & GLFW_MOD_ALT;
    if (a->op) {
        int ax = axis_key(key);
        if (a->op == 'l' && key >= GLFW_KEY_0 && key <= GLFW_KEY_9) {
            a->op = 0;
            sv_layer(a, (uint32_t)(key - GLFW_KEY_0), -1);
            return;
        }
        if (a->op == 'g') {
            if (ax >= 0 && a->op_axis < 0) {
                a->op_axis = ax;
                a->grab_px = 0;
                return;
            }
            if (a->op_axis >= 0 && (key == GLFW_KEY_RIGHT || key == GLFW_KEY_UP || key == GLFW_KEY_LEFT ||
                                    key == GLFW_KEY_DOWN || key == GLFW_KEY_PAGE_UP || key == GLFW_KEY_PAGE_DOWN)) {
                int32_t n = (key == GLFW_KEY_RIGHT || key == GLFW_KEY_UP || key == GLFW_KEY_PAGE_UP) ? 1 : -1;
                if (shift) n *= 10;
                edit_move(a, a->op_axis, n);
                a->grab_moved += n;
                update_instances(a);
                return;
            }
            if (key == GLFW_KEY_ENTER || key == GLFW_KEY_KP_ENTER) return grab_end(a, true);
            if (key == GLFW_KEY_ESCAPE) return grab_end(a, false);
            return;
        }
        if (ax >= 0 && a->op == 'r') sv_rotate(a, ax, shift ? -1 : 1);
        else if (ax >= 0 && a->op == 'm') sv_mirror(a, ax);
        a->op = 0;
        return;
    }
    if (ctrl) {
        if (key == GLFW_KEY_Z) sv_undo(a, shift);
        else if (key == GLFW_KEY_Y) sv_undo(a, true);
        else if (key == GLFW_KEY_S) {
            char path[1024];
            if (a->o.save) snprintf(path, sizeof path, "%s", a->o.save);
            else {
                const char* dot = strrchr(a->o.in, '.');
                int n = dot ? (int)(dot - a->o.in) : (int)strlen(a->o.in);
                snprintf(path, sizeof path, "%.*s.edited.svo", n, a->o.in);
            }
            sv_save(a, path);
        } else if (key == GLFW_KEY_E) {
            char path[1024];
            const char* dot = strrchr(a->o.in, '.');
            int n = dot ? (int)(dot - a->o.in) : (int)strlen(a->o.in);
            snprintf(path, sizeof path, "%.*s.edited.vox", n, a->o.in);
            sv_export(a, path);
        } else if (key == GLFW_KEY_Q) a->quit = true;
        return;
    }
    if (key >= GLFW_KEY_1 && key <= GLFW_KEY_6) a->mode = (vx_render_mode)(key - GLFW_KEY_1), a->gi = false;
    else if (key == GLFW_KEY_7) sv_set_probe_mode(a, VX_PROBE_RENDER_GI);
    else if (key == GLFW_KEY_8) sv_set_probe_mode(a, VX_PROBE_RENDER_LIGHTFIELD);
    else if (key == GLFW_KEY_9) {
        static const char* const presets[] = {VX_PASS_LIST_DEFAULT, "gbuffer,direct,ao", "gbuffer,direct,ao,aa,tonemap",
                                              "gbuffer,dof,direct,ao,aa,tonemap", "gbuffer,direct,gi=cones,aa,tonemap",
                                              "gbuffer,direct,gi=photons,aa,tonemap"};
        char cur[160];
        vx_pass_list_format(&a->passes, cur, sizeof cur);
        size_t k = 0, n = sizeof presets / sizeof presets[0];
        while (k < n && strcmp(cur, presets[k])) k++;
        sv_set_passes(a, presets[(k + 1) % n]);
        a->mode = VX_RENDER_COLOR, a->gi = false;
    }
    else if (key == GLFW_KEY_V) vp_set_vsync(a->p, !vp_vsync(a->p));
    else if (key == GLFW_KEY_TAB && a->ui) a->panels = !a->panels;
    else if (key == GLFW_KEY_TAB) a->overlay = !a->overlay;
    else if (key == GLFW_KEY_SPACE) sv_play(a, !a->playing);
    else if (key == GLFW_KEY_COMMA || key == GLFW_KEY_PERIOD) {
        uint32_t nf = vx_svo_scene_frames(&a->scene);
        sv_set_frame(a, (a->anim_frame + (key == GLFW_KEY_PERIOD ? 1 : nf - 1)) % nf);
    } else if (key == GLFW_KEY_B) {
        a->voxel_mode = !a->voxel_mode;
        sv_message(a, false, "voxel mode %s (click: add, Shift: remove, Alt: paint; brush %s %u)",
                   a->voxel_mode ? "on" : "off", vvx_shape_name(a->brush.shape), a->brush.radius);
    }
    else if (key == GLFW_KEY_F) sv_frame_camera(a);
    else if (key == GLFW_KEY_O) {
        a->orbit = !a->orbit;
        if (a->orbit) {
            double f[3];
            cam_fwd(a, f);
            if (a->sel != NO_SEL) {
                double lo[3], hi[3];
                world_box(a, a->sel, lo, hi);
                for (int k = 0; k < 3; k++) a->orbit_center[k] = 0.5 * (lo[k] + hi[k]);
            }
            double v[3] = {a->orbit_center[0] - a->eye[0], a->orbit_center[1] - a->eye[1], a->orbit_center[2] - a->eye[2]};
            a->orbit_dist = fmax(1e-3, sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
            a->yaw = atan2(v[1], v[0]);
            a->pitch = asin(fmax(-1, fmin(1, v[2] / a->orbit_dist)));
        }
    } else if (key == GLFW_KEY_P) {
        snprintf(a->shot_buf, sizeof a->shot_buf, "svo_view_%03u.png", a->shot_counter++);
        a->shot = a->shot_buf;
    } else if (key == GLFW_KEY_G && a->sel != NO_SEL) {
        if (sv_edit_begin(a, true)) a->op = 'g', a->op_axis = -1, a->grab_moved = 0;
    } else if ((key == GLFW_KEY_R || key == GLFW_KEY_M) && a->sel != NO_SEL) a->op = key == GLFW_KEY_R ? 'r' : 'm';
    else if (key == GLFW_KEY_L) a->op = 'l';
    else if (key == GLFW_KEY_D && shift) sv_duplicate(a);
    else if (key == GLFW_KEY_DELETE || key == GLFW_KEY_BACKSPACE) sv_delete(a);
    else if (key == GLFW_KEY_H) sv_hide(a, !alt);
    else if (key == GLFW_KEY_ESCAPE) a->sel = NO_SEL;
}

static void mouse_cb(GLFWwindow* win, int button, int action, int mods) {
    ((app*)glfwGetWindowUserPointer(win))->ui_dirty = true;
    app* a = glfwGetWindowUserPointer(win);
    sv_panels_button(a, button, action == GLFW_PRESS);
    if (sv_panels_wants_mouse(a) && action == GLFW_PRESS) return;
    if (button == GLFW_MOUSE_BUTTON_RIGHT) a->rmb = action == GLFW_PRESS;
    if (button != GLFW_MOUSE_BUTTON_LEFT) return;
    a->lmb = action == GLFW_PRESS;
    if (action != GLFW_PRESS) return;
    if (a->op == 'g') return grab_end(a, true); /* a click confirms a move */
    /* the cursor is in screen coordinates; the frame in framebuffer pixels */
    int ww, wh;
    glfwGetWindowSize(win, &ww, &wh);
    uint32_t fw, fh;
    if (a->o.width) fw = a->o.width, fh = a->o.height;
    else vp_frame_size(a->p, &fw, &fh);
    if (ww <= 0 || wh <= 0) return;
    a->pick_x = a->mouse_x * fw / ww;
    a->pick_y = a->mouse_y * fh / wh;
    a->pick_pending = true;
    a->pick_op = !a->voxel_mode ? -1 : (mods & GLFW_MOD_SHIFT) ? VVX_REMOVE : (mods & GLFW_MOD_ALT) ? VVX_PAINT : VVX_ADD;
}

static void cursor_cb(GLFWwindow* win, double x, double y) {
    ((app*)glfwGetWindowUserPointer(win))->ui_dirty = true;
    app* a = glfwGetWindowUserPointer(win);
    {
        /* the panels work in frame pixels, the cursor comes in screen coordinates */
        int ww, wh;
        uint32_t fw, fh;
        glfwGetWindowSize(win, &ww, &wh);
        if (a->o.width) fw = a->o.width, fh = a->o.height;
        else vp_frame_size(a->p, &fw, &fh);
        if (ww > 0 && wh > 0) sv_panels_mouse(a, x * fw / ww, y * fh / wh);
    }
    double dx = x - a->mouse_x, dy = y - a->mouse_y;
    a->mouse_x = x, a->mouse_y = y;
    if (a->rmb) {
        a->cam_default = false;
        a->yaw -= dx * 0.004;
        a->pitch = fmax(-1.55, fmin(1.55, a->pitch - dy * 0.004));
        if (a->orbit) {
            double f[3];
            cam_fwd(a, f);
            for (int k = 0; k < 3; k++) a->eye[k] = a->orbit_center[k] - f[k] * a->orbit_dist;
        }
    }
    if (a->op == 'g' && a->op_axis >= 0 && a->sel != NO_SEL) {
        /* whole voxels: about 8 pixels of horizontal motion per cell */
        a->grab_px += dx;
        int32_t n = (int32_t)(a->grab_px / 8);
        if (n) {
            a->grab_px -= n * 8;
            edit_move(a, a->op_axis, n);
            a->grab_moved += n;
            update_instances(a);
        }
    }
}

static void char_cb(GLFWwindow* win, unsigned int c) {
    ((app*)glfwGetWindowUserPointer(win))->ui_dirty = true;
    sv_panels_char(glfwGetWindowUserPointer(win), c);
}

static void scroll_cb(GLFWwindow* win, double dx, double dy) {
    ((app*)glfwGetWindowUserPointer(win))->ui_dirty = true;
    (void)dx;
    app* a = glfwGetWindowUserPointer(win);
    sv_panels_wheel(a, dy);
    if (sv_panels_wants_mouse(a)) return;
    if (a->orbit) {
        a->orbit_dist *= pow(0.9, dy);
        double f[3];
        cam_fwd(a, f);
        for (int k = 0; k < 3; k++) a->eye[k] = a->orbit_center[k] - f[k] * a->orbit_dist;
        a->cam_default = false;
    } else {
        a->speed *= pow(1.2, dy);
    }
}

static void drop_cb(GLFWwindow* win, int n, const char** paths) {
    ((app*)glfwGetWindowUserPointer(win))->ui_dirty = true;
    app* a = glfwGetWindowUserPointer(win);
    for (int i = 0; i < n; i++) sv_add(a, paths[i]);
}

static void fly(app* a, double dt) {
    GLFWwindow* w = vp_window(a->p);
    double f[3], r[3];
    cam_fwd(a, f);
    r[0] = sin(a->yaw), r[1] = -cos(a->yaw), r[2] = 0;
    double m[3] = {0, 0, 0}, s = a->speed * dt;
    if (glfwGetKey(w, GLFW_KEY_W) == GLFW_PRESS)
        for (int k = 0; k < 3; k++) m[k] += f[k];
    if (glfwGetKey(w, GLFW_KEY_S) == GLFW_PRESS)
        for (int k = 0; k < 3; k++) m[k] -= f[k];
    if (glfwGetKey(w, GLFW_KEY_D) == GLFW_PRESS && !(glfwGetKey(w, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS))
        for (int k = 0; k < 3; k++) m[k] += r[k];
    if (glfwGetKey(w, GLFW_KEY_A) == GLFW_PRESS)
        for (int k = 0; k < 3; k++) m[k] -= r[k];
    if (glfwGetKey(w, GLFW_KEY_E) == GLFW_PRESS) m[2] += 1;
    if (glfwGetKey(w, GLFW_KEY_Q) == GLFW_PRESS) m[2] -= 1;
    if (m[0] == 0 && m[1] == 0 && m[2] == 0) return;
    if (glfwGetKey(w, GLFW_KEY_LEFT_CONTROL) == GLFW_PRESS) return;
    a->cam_default = false;
    for (int k = 0; k < 3; k++) a->eye[k] += m[k] * s, a->orbit_center[k] += m[k] * s;
}

/* ---- scripts ---------------------------------------------------------------------------- */

static int parse_axis(const char* s) {
    if (!s || s[1]) return -1;
    return s[0] == 'x' || s[0] == 'X' ? 0 : s[0] == 'y' || s[0] == 'Y' ? 1 : s[0] == 'z' || s[0] == 'Z' ? 2 : -1;
}

static bool parse_doubles(char** tok, int n, double* v) {
    for (int i = 0; i < n; i++)
        if (!tok[i] || !vx_tool_parse_double(tok[i], &v[i]) || !isfinite(v[i])) return false;
    return true;
}

/* Runs one script line; false (with a message) on a malformed command. */
static bool run_command(app* a, char* line, uint32_t lineno) {
    a->ui_dirty = true; /* the panels may show what the command changed */
    char* tok[8] = {0};
    int nt = 0;
    for (char* t = strtok(line, " \t\r"); t && nt < 8; t = strtok(NULL, " \t\r")) tok[nt++] = t;
    if (!nt || tok[0][0] == '#') return true;
    const char* c = tok[0];
    double v[6];
#define BAD()                                                                                           \
    do {                                                                                                \
        fprintf(stderr, "%s: %s:%u: bad command '%s'\n", vx_tool_name, a->o.script, lineno, c);          \
        return false;                                                                                   \
    } while (0)
    if (!strcmp(c, "quit")) a->quit = true;
    else if (!strcmp(c, "camera") && nt == 2 && !strcmp(tok[1], "default")) camera_default(a);
    else if (!strcmp(c, "camera")) {
        if (nt != 7 || !parse_doubles(tok + 1, 6, v)) BAD();
        double d[3] = {v[0] - v[3], v[1] - v[4], v[2] - v[5]};
        double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (!(l > 0)) BAD();
        memcpy(a->eye, v, sizeof a->eye);
        a->yaw = atan2(-d[1], -d[0]);
        a->pitch = asin(-d[2] / l);
        memcpy(a->orbit_center, v + 3, sizeof a->orbit_center);
        a->orbit_dist = l;
        a->cam_default = false;
    } else if (!strcmp(c, "fly")) {
        if (nt != 4 || !parse_doubles(tok + 1, 3, v)) BAD();
        double f[3], r[3] = {sin(a->yaw), -cos(a->yaw), 0};
        cam_fwd(a, f);
        for (int k = 0; k < 3; k++) a->eye[k] += v[0] * f[k] + v[1] * r[k] + (k == 2 ? v[2] : 0);
        a->cam_default = false;
    } else if (!strcmp(c, "look")) {
        if (nt != 3 || !parse_doubles(tok + 1, 2, v)) BAD();
        a->yaw += v[0] * PI / 180, a->pitch = fmax(-1.55, fmin(1.55, a->pitch + v[1] * PI / 180));
        a->cam_default = false;
    } else if (!strcmp(c, "orbit")) {
        if (nt != 2) BAD();
        a->orbit = !strcmp(tok[1], "on");
    } else if (!strcmp(c, "mode")) {
        if (nt == 2 && !strcmp(tok[1], "gi")) sv_set_probe_mode(a, VX_PROBE_RENDER_GI);
        else if (nt == 2 && !strcmp(tok[1], "lightfield")) sv_set_probe_mode(a, VX_PROBE_RENDER_LIGHTFIELD);
        else if (nt != 2 || !vx_render_mode_parse(tok[1], &a->mode)) BAD();
        else a->gi = false;
    } else if (!strcmp(c, "passes") && nt <= 2) {
        if (!sv_set_passes(a, nt == 2 ? tok[1] : "")) return false;
    } else if (!strcmp(c, "probes") && nt >= 2 && !strcmp(tok[1], "bake")) {
        uint32_t res, spp, g[3] = {0, 0, 0};
        if ((nt != 4 && nt != 7) || !vx_tool_parse_u32(tok[2], &res) || !vx_tool_parse_u32(tok[3], &spp) ||
            (nt == 7 && (!vx_tool_parse_u32(tok[4], &g[0]) || !vx_tool_parse_u32(tok[5], &g[1]) ||
                         !vx_tool_parse_u32(tok[6], &g[2]))))
            BAD();
        sv_probe_bake(a, res, spp, g);
        if (!a->bake.active) return false; /* refused: the message says why */
    } else if (!strcmp(c, "probes") && nt == 3 && !strcmp(tok[1], "grid")) {
        if (strcmp(tok[2], "on") && strcmp(tok[2], "off")) BAD();
        a->probe_grid = !strcmp(tok[2], "on");
    } else if (!strcmp(c, "probes") && nt == 3 && !strcmp(tok[1], "show")) {
        uint32_t n;
        const vx_probe_set* ps = sv_probe_shown(a);
        if (!vx_tool_parse_u32(tok[2], &n)) BAD();
        if (!ps || n >= ps->probe_count) {
            fprintf(stderr, "%s: %s:%u: no probe %u (%u probes)\n", vx_tool_name, a->o.script, lineno, n,
                    ps ? ps->probe_count : 0);
            return false;
        }
        a->probe_sel = n;
    } else if (!strcmp(c, "probes") && nt == 3 && !strcmp(tok[1], "save")) {
        if (!sv_probe_save(a, tok[2])) return false;
    } else if (!strcmp(c, "probes") && nt == 2 && !strcmp(tok[1], "cancel")) {
        sv_probe_bake_cancel(a, "asked");
    } else if (!strcmp(c, "probes") && nt == 2) {
        sv_probes(a, tok[1]);
    } else if (!strcmp(c, "select")) {
        uint32_t n;
        if (nt == 2 && !strcmp(tok[1], "none")) a->sel = NO_SEL;
        else if (nt == 2 && vx_tool_parse_u32(tok[1], &n)) {
            if (n >= a->scene.instance_count) {
                fprintf(stderr, "%s: %s:%u: no instance %u (the scene has %u)\n", vx_tool_name, a->o.script, lineno, n,
                        a->scene.instance_count);
                return false;
            }
            a->sel = n;
        } else BAD();
    } else if (!strcmp(c, "pick")) {
        if (nt != 3 || !parse_doubles(tok + 1, 2, v)) BAD();
        a->pick_x = v[0], a->pick_y = v[1], a->pick_pending = true, a->pick_op = -1;
    } else if (!strcmp(c, "frame")) sv_frame_camera(a);
    else if (!strcmp(c, "move")) {
        if (nt != 4 || !parse_doubles(tok + 1, 3, v)) BAD();
        int32_t d[3];
        for (int k = 0; k < 3; k++) {
            if (v[k] != floor(v[k]) || fabs(v[k]) > 1e9) BAD();
            d[k] = (int32_t)v[k];
        }
        if (!sv_edit_begin(a, true)) return false;
        ved_move(&a->scene, a->sel, d);
        sv_edit_end(a, "move");
    } else if (!strcmp(c, "rotate") || !strcmp(c, "mirror")) {
        int ax = parse_axis(tok[1]);
        double turns = 1;
        if (ax < 0 || nt > 3 || (nt == 3 && (!parse_doubles(tok + 2, 1, &turns) || turns != floor(turns)))) BAD();
        if (a->sel == NO_SEL) {
            sv_message(a, true, "%s:%u: nothing selected", a->o.script, lineno);
            return false;
        }
        if (c[0] == 'r') sv_rotate(a, ax, (int)fmod(turns, 4));
        else sv_mirror(a, ax);
    } else if (!strcmp(c, "duplicate") || !strcmp(c, "delete") || !strcmp(c, "hide")) {
        if (a->sel == NO_SEL) {
            sv_message(a, true, "%s:%u: nothing selected", a->o.script, lineno);
            return false;
        }
        if (c[1] == 'u') sv_duplicate(a);
        else if (c[0] == 'd') sv_delete(a);
        else sv_hide(a, true);
    } else if (!strcmp(c, "show")) sv_hide(a, false);
    else if (!strcmp(c, "layer")) {
        uint32_t l;
        if (nt != 3 || !vx_tool_parse_u32(tok[1], &l) || (strcmp(tok[2], "hide") && strcmp(tok[2], "show"))) BAD();
        sv_layer(a, l, !strcmp(tok[2], "hide"));
    } else if (!strcmp(c, "add") && nt == 2) sv_add(a, tok[1]);
    else if (!strcmp(c, "open") && nt == 2) sv_open(a, tok[1]);
    else if (!strcmp(c, "undo")) sv_undo(a, false);
    else if (!strcmp(c, "redo")) sv_undo(a, true);
    else if (!strcmp(c, "save") && nt == 2) sv_save(a, tok[1]);
    else if (!strcmp(c, "export") && nt == 2) sv_export(a, tok[1]);
    else if (!strcmp(c, "screenshot") && nt == 2) {
        snprintf(a->shot_buf, sizeof a->shot_buf, "%s", tok[1]);
        a->shot = a->shot_buf;
    } else if (!strcmp(c, "wait") && nt == 2) {
        if (!vx_tool_parse_u32(tok[1], &a->wait)) BAD();
    } else if (!strcmp(c, "anim")) {
        uint32_t nf = vx_svo_scene_frames(&a->scene), n;
        if (nt == 3 && !strcmp(tok[1], "frame") && vx_tool_parse_u32(tok[2], &n)) {
            if (n >= nf) {
                fprintf(stderr, "%s: %s:%u: no frame %u (the scene has %u)\n", vx_tool_name, a->o.script, lineno, n, nf);
                return false;
            }
            sv_set_frame(a, n);
        } else if ((nt == 2 || nt == 3) && !strcmp(tok[1], "step")) {
            double k = 1;
            if (nt == 3 && (!parse_doubles(tok + 2, 1, &k) || k != floor(k) || fabs(k) > 1e9)) BAD();
            int64_t f = ((int64_t)a->anim_frame + (int64_t)k) % (int64_t)nf;
            sv_set_frame(a, (uint32_t)(f < 0 ? f + nf : f));
        } else if (nt == 2 && !strcmp(tok[1], "play")) sv_play(a, true);
        else if (nt == 2 && !strcmp(tok[1], "pause")) sv_play(a, false);
        else if (nt == 3 && !strcmp(tok[1], "fps") && parse_doubles(tok + 2, 1, v) && v[0] > 0 && v[0] <= 1000)
            sv_set_fps(a, v[0]);
        else if (nt == 3 && !strcmp(tok[1], "tick") && parse_doubles(tok + 2, 1, v) && v[0] >= 0) play(a, v[0]);
        else BAD();
        if (!strcmp(tok[1], "frame") || !strcmp(tok[1], "step") || !strcmp(tok[1], "tick"))
            printf("%s: frame %u of %u\n", vx_tool_name, a->anim_frame, nf);
    } else if (!strcmp(c, "exposure")) {
        if (nt != 2 || !parse_doubles(tok + 1, 1, v) || fabs(v[0]) > 64) BAD();
        a->exposure = v[0];
    } else if (!strcmp(c, "rename") || !strcmp(c, "setlayer") || !strcmp(c, "setmodel")) {
        uint32_t n;
        if (nt != 2) BAD();
        if (a->sel == NO_SEL) {
            sv_message(a, true, "%s:%u: nothing selected", a->o.script, lineno);
            return false;
        }
        if (c[0] == 'r') sv_rename(a, tok[1]);
        else if (!strcmp(c, "setlayer") && !strcmp(tok[1], "none")) sv_set_layer(a, UINT32_MAX);
        else if (!vx_tool_parse_u32(tok[1], &n)) BAD();
        else if (c[3] == 'l') sv_set_layer(a, n);
        else sv_set_model(a, n);
    } else if (!strcmp(c, "vsync")) { /* the render panel's checkbox, key V */
        if (nt != 2 || (strcmp(tok[1], "on") && strcmp(tok[1], "off"))) BAD();
        vp_set_vsync(a->p, !strcmp(tok[1], "on"));
    } else if (!strcmp(c, "overlay")) {
        if (nt != 2 || (strcmp(tok[1], "on") && strcmp(tok[1], "off"))) BAD();
        a->overlay = !strcmp(tok[1], "on");
    } else if (!strcmp(c, "panels")) {
        if (nt != 2 || (strcmp(tok[1], "on") && strcmp(tok[1], "off"))) BAD();
        a->panels = !strcmp(tok[1], "on");
        if (a->panels && !a->ui) sv_message(a, true, "no panels: %s", sv_panels_built() ? "none made" : "built without Dear ImGui");
    } else if (!strcmp(c, "grab") && nt == 2) {
        snprintf(a->grab_buf, sizeof a->grab_buf, "%s", tok[1]);
        a->grab = a->grab_buf;
    } else if (!strcmp(c, "click")) {
        if (nt != 3 || !parse_doubles(tok + 1, 2, v)) BAD();
        a->click_x = v[0], a->click_y = v[1], a->click_state = 2;
    } else if (!strcmp(c, "ui")) { /* input through the panels' widgets, as a user's mouse and keys give it */
        if (nt < 3 || !a->ui) BAD();
        char text[128] = "";
        for (int k = 2; k < nt; k++) /* the rest of the line, single-spaced: a widget's label or the text to type */
            snprintf(text + strlen(text), sizeof text - strlen(text), "%s%s", k > 2 ? " " : "", tok[k]);
        if (!strcmp(tok[1], "click") || !strcmp(tok[1], "ctrl-click")) {
            snprintf(a->ui_label, sizeof a->ui_label, "%s", text);
            sv_panels_find(a, a->ui_label);
            a->ui_finding = 4; /* frames to wait for the panels to draw it */
            a->ui_ctrl = !strcmp(tok[1], "ctrl-click");
        } else if (!strcmp(tok[1], "type")) {
            for (const char* t = text; *t; t++) sv_panels_char(a, (unsigned char)*t);
        } else if (!strcmp(tok[1], "key") && nt == 3) {
            static const struct { const char* name; int key; } keys[] = {
                {"enter", GLFW_KEY_ENTER}, {"escape", GLFW_KEY_ESCAPE}, {"tab", GLFW_KEY_TAB}, {"backspace", GLFW_KEY_BACKSPACE}};
            for (size_t k = 0; k < sizeof keys / sizeof keys[0]; k++)
                if (!strcmp(tok[2], keys[k].name)) a->ui_key_up = keys[k].key;
            if (!a->ui_key_up) BAD();
            sv_panels_key(a, a->ui_key_up, true, 0); /* released after a frame */
        } else BAD();
    } else if (!strcmp(c, "voxel") || !strcmp(c, "vclick")) {
        vvx_op op = VVX_OP_COUNT;
        for (int k = 0; k < VVX_OP_COUNT && nt >= 2; k++)
            if (!strcmp(tok[1], vvx_op_name((vvx_op)k))) op = (vvx_op)k;
        bool cells = c[0] == 'v' && c[1] == 'o';
        static const char* const faces[6] = {"-x", "+x", "-y", "+y", "-z", "+z"};
        int face = -1;
        for (int k = 0; k < 6 && cells && nt == 6; k++)
            if (!strcmp(tok[5], faces[k])) face = k;
        if (op == VVX_OP_COUNT || (nt != (cells ? 5 : 4) && !(face >= 0 && nt == 6)) ||
            !parse_doubles(tok + 2, cells ? 3 : 2, v))
            BAD();
        if (face >= 0) a->brush.face = (uint8_t)face;
        if (cells) {
            int64_t p[3];
            for (int k = 0; k < 3; k++) {
                if (v[k] != floor(v[k]) || fabs(v[k]) > 1e8) BAD();
                p[k] = (int64_t)v[k];
            }
            if (!sv_voxels(a, op, p)) return false;
        } else {
            a->pick_x = v[0], a->pick_y = v[1], a->pick_pending = true, a->pick_op = (int)op;
        }
    } else if (!strcmp(c, "brush")) {
        vvx_shape sh;
        if (nt < 2 || nt > 3 || !vvx_shape_parse(tok[1], &sh) || (nt == 3 && !parse_doubles(tok + 2, 1, v)) ||
            (nt == 3 && (v[0] != floor(v[0]) || v[0] < 0 || v[0] > VVX_MAX_RADIUS)))
            BAD();
        a->brush.shape = sh;
        if (nt == 3) a->brush.radius = (uint32_t)v[0];
    } else if (!strcmp(c, "color")) {
        uint32_t idx;
        unsigned rgb;
        char extra;
        if (nt == 2 && tok[1][0] == '#' && strlen(tok[1]) == 7 && sscanf(tok[1] + 1, "%6x%c", &rgb, &extra) == 1) {
            if (!sv_brush_rgba(a, 0xFF000000u | ((rgb >> 16) & 0xFF) | (rgb & 0xFF00) | ((rgb & 0xFF) << 16))) return false;
        } else if (nt == 2 && vx_tool_parse_u32(tok[1], &idx) && idx >= 1 && idx <= 255) {
            if (!sv_brush_palette(a, idx)) return false;
        } else BAD();
    } else if (!strcmp(c, "light")) {
        uint32_t l;
        if (nt < 4 || !vx_tool_parse_u32(tok[1], &l)) BAD();
        if (l >= a->scene.light_count) {
            fprintf(stderr, "%s: %s:%u: no light %u (the scene has %u)\n", vx_tool_name, a->o.script, lineno, l,
                    a->scene.light_count);
            return false;
        }
        vx_light t = a->scene.lights[l];
        const char* f = tok[2];
        if (!strcmp(f, "color") && nt == 6 && parse_doubles(tok + 3, 3, v)) memcpy(t.color, v, sizeof t.color);
        else if (!strcmp(f, "position") && nt == 6 && parse_doubles(tok + 3, 3, v)) memcpy(t.position, v, sizeof t.position);
        else if (!strcmp(f, "intensity") && nt == 4 && parse_doubles(tok + 3, 1, v)) t.intensity = v[0];
        else if (!strcmp(f, "range") && nt == 4 && parse_doubles(tok + 3, 1, v)) t.range = v[0];
        else BAD();
        vx_error lerr = {0};
        if (vx_light_validate(&t, l, &lerr)) {
            fprintf(stderr, "%s: %s:%u: %s\n", vx_tool_name, a->o.script, lineno, lerr.msg);
            return false;
        }
        if (!sv_set_light(a, l, &t, false)) return false; /* an undo step of its own */
    } else if (!strcmp(c, "material")) {
        uint32_t id;
        if (nt != 4 || !vx_tool_parse_u32(tok[1], &id) || id > 65535) BAD();
        if (!sv_set_material(a, id, tok[2], tok[3], false)) return false; /* an undo step of its own */
    } else if (!strcmp(c, "gi")) {
        if (nt != 3) BAD();
        if (!sv_set_gi_option(a, tok[1], tok[2])) return false;
    } else if (!strcmp(c, "stats") && nt == 1) {
        vx_render_scene_stats st;
        vx_render_scene_get_stats(a->rs, &st);
        uint64_t w, rec;
        sv_uploads(a, &w, &rec);
        printf("%s: stats: render scenes made %u, node words uploaded %llu, records uploaded %llu; this scene: "
               "%llu words, %u model updates, %u instance table rebuilds (%u in place)\n",
               vx_tool_name, a->scenes_made, (unsigned long long)w, (unsigned long long)rec,
               (unsigned long long)st.node_words_uploaded, st.model_updates, st.instance_rebuilds,
               st.instance_updates_in_place);
    } else if (!strcmp(c, "echo")) {
        for (int i = 1; i < nt; i++) printf("%s%s", tok[i], i + 1 < nt ? " " : "\n");
    } else BAD();
#undef BAD
    return true;
}

static int load_script(app* a) {
    uint8_t* data = NULL;
    size_t size = 0;
    vx_error err = {0};
    if (vx_file_read(a->o.script, NULL, 1u << 20, &data, &size, &err)) return vx_tool_error(a->o.script, &err);
    uint32_t n = 1;
    for (size_t i = 0; i < size; i++) n += data[i] == '\n';
    a->lines = calloc(n, sizeof *a->lines);
    char* text = malloc(size + 1);
    if (!a->lines || !text) {
        free(text);
        vx_free(NULL, data);
        return vx_tool_errorf("out of memory");
    }
    memcpy(text, data, size);
    text[size] = 0;
    vx_free(NULL, data);
    /* the lines point into one block, owned through lines[0] */
    char* s = text;
    for (uint32_t i = 0; i < n; i++) {
        a->lines[i] = s;
        char* nl = strchr(s, '\n');
        if (nl) *nl = 0, s = nl + 1;
        else s += strlen(s);
    }
    a->line_count = n;
    return 0;
}

/* ---- main ------------------------------------------------------------------------------- */

static int cmp_double(const void* x, const void* y) {
    double a = *(const double*)x, b = *(const double*)y;
    return (a > b) - (a < b);
}

static void log_cb(void* user, vx_log_level level, const char* id, const char* msg) {
    (void)user;
    if (level >= VX_LOG_WARN) fprintf(stderr, "%s: %s: %s\n", vx_tool_name, id, msg);
}

static int run(app* a) {
    vx_error err = {0};
    double last = glfwGetTime(), last_play = last;
    double* bench = a->o.bench ? calloc(a->o.bench, sizeof *bench) : NULL;
    double* bench_trace = a->o.bench ? calloc(a->o.bench, sizeof *bench_trace) : NULL;
    double* bench_switch = a->o.bench ? calloc(a->o.bench, sizeof *bench_switch) : NULL;
    double* bench_panels = a->o.bench ? calloc(a->o.bench, sizeof *bench_panels) : NULL;
    double* bench_edit = a->o.bench ? calloc(a->o.bench, sizeof *bench_edit) : NULL;
    if (a->o.bench && (!bench || !bench_trace || !bench_switch || !bench_panels || !bench_edit)) a->quit = true, a->status = 1;
    uint32_t frames = 0;
    GLFWwindow* w = vp_window(a->p);
    if (a->o.screenshot) a->shot = a->o.screenshot;
    while (!a->quit && !glfwWindowShouldClose(w)) {
        glfwPollEvents();
        double now = glfwGetTime();
        fly(a, fmin(now - last, 0.25));
        last = now;
        if (a->ui_key_up) { /* `ui key K`: released a frame after the press */
            sv_panels_key(a, a->ui_key_up, false, 0);
            a->ui_key_up = 0;
            a->ui_dirty = true;
        }
        if (a->ui_finding) { /* `ui click LABEL`: at the widget's centre once the panels drew it */
            float r[4];
            a->ui_dirty = true;
            if (sv_panels_found(a, r)) {
                a->click_x = 0.5 * (r[0] + r[2]), a->click_y = 0.5 * (r[1] + r[3]);
                a->click_state = 2, a->ui_finding = 0;
            } else if (!--a->ui_finding) {
                fprintf(stderr, "%s: %s: ui click: no widget '%s' on the panels\n", vx_tool_name, a->o.script, a->ui_label);
                a->status = 1, a->quit = true;
            }
        }
        if (a->click_state == 1) { /* a scripted panel click: released one frame after the press */
            sv_panels_button(a, 0, false);
            if (a->ui_ctrl) sv_panels_key(a, GLFW_KEY_LEFT_CONTROL, false, 0), a->ui_ctrl = false;
            a->click_state = 0;
            a->ui_dirty = true;
        } else if (a->click_state == 2) {
            sv_panels_mouse(a, a->click_x, a->click_y);
            if (a->ui_ctrl) sv_panels_key(a, GLFW_KEY_LEFT_CONTROL, true, GLFW_MOD_CONTROL);
            sv_panels_button(a, 0, true);
            a->click_state = 1;
            a->ui_dirty = true;
        }
        play(a, fmin(now - last_play, 0.25));
        last_play = now;
        probe_bake_step(a); /* a step of a running bake, between frames */
        double t_edit = vx_time_now();
        if (a->lines && !a->pick_pending && !a->click_state && !a->ui_finding && !a->ui_key_up && !a->bake.active) {
            if (a->wait) a->wait--;
            else {
                /* commands up to the next one that needs a frame (pick, screenshot, wait) */
                while (a->line_pos < a->line_count && !a->quit && !a->pick_pending && !a->shot && !a->wait &&
                       !a->grab && !a->click_state && !a->ui_finding && !a->ui_key_up && !a->bake.active) {
                    uint32_t ln = a->line_pos++;
                    if (!run_command(a, a->lines[ln], ln + 1)) {
                        a->status = 1;
                        a->quit = true;
                    }
                }
            }
            if (a->quit && !a->shot && !a->pick_pending && !a->grab && !a->click_state && !a->ui_finding && !a->ui_key_up)
                break;
        }
        double t0 = vx_time_now();
        if (a->o.bench && vx_svo_scene_frames(&a->scene) > 1) {
            /* an animation plays, one frame per bench frame: the frame switch is in the time */
            sv_set_frame(a, (a->anim_frame + 1) % vx_svo_scene_frames(&a->scene));
            bench_switch[frames] = a->switch_ms;
        }
        vx_result r = frame(a, &err);
        if (r) {
            fprintf(stderr, "%s: %s\n", vx_tool_name, err.msg);
            a->status = 1;
            break;
        }
        if (a->o.bench) {
            bench[frames] = (vx_time_now() - t0) * 1e3;
            bench_trace[frames] = a->trace_ms;
            bench_panels[frames] = a->panels_ms;
            bench_edit[frames] = (t0 - t_edit) * 1e3; /* the script's commands before this frame (edits) */
            if (++frames == a->o.bench) break;
        }
        if (a->o.screenshot) break;
    }
    if (a->disp && a->frames_recorded) {
        /* the frames a batch still holds go to the screen; with -v what became of the frames in flight */
        vx_error derr = {0};
        if (batch_drain(a, &derr)) fprintf(stderr, "%s: %s\n", vx_tool_name, derr.msg);
        vx_display_times dt;
        vx_display_frame_times(a->disp, &dt);
        vp_present_counts pc;
        vp_get_present_counts(a->p, &pc);
        if (a->o.verbose)
            printf("%s: frames in flight: %llu recorded, %llu submitted in %llu vkQueueSubmit calls, %llu presented "
                   "(%llu out of order, %u still queued)\n",
                   vx_tool_name, (unsigned long long)a->frames_recorded, (unsigned long long)dt.frames_submitted,
                   (unsigned long long)dt.submits, (unsigned long long)pc.presented, (unsigned long long)pc.out_of_order,
                   pc.queued);
    }
    if (a->o.bench && frames) {
        double sum = 0; /* the mean too: with --batch the frames come in bursts, so the median is not the rate */
        for (uint32_t k = 0; k < frames; k++) sum += bench[k];
        qsort(bench, frames, sizeof *bench, cmp_double);
        qsort(bench_trace, frames, sizeof *bench_trace, cmp_double);
        uint32_t fw = a->o.width, fh = a->o.height;
        if (!fw) vp_frame_size(a->p, &fw, &fh);
        printf("%s: %u frames %ux%u mode %s on %s: median frame %.3f ms (mean %.3f ms), median trace %.3f ms (GPU "
               "timestamps)\n",
               vx_tool_name, frames, fw, fh, sv_mode_name(a), vx_gpu_device_name(a->gpu), bench[frames / 2], sum / frames,
               bench_trace[frames / 2]);
        qsort(bench_panels, frames, sizeof *bench_panels, cmp_double);
        qsort(bench_edit, frames, sizeof *bench_edit, cmp_double);
        printf("%s: panels %s (median %.3f ms of CPU time drawing them), present %s, script commands before a frame "
               "median %.3f ms (max %.3f ms)\n",
               vx_tool_name, a->ui && a->panels ? "on" : "off", bench_panels[frames / 2],
               a->frame_on_gpu ? "GPU" : "host readback", bench_edit[frames / 2], bench_edit[frames - 1]);
        if (vx_svo_scene_frames(&a->scene) > 1) {
            qsort(bench_switch, frames, sizeof *bench_switch, cmp_double);
            printf("%s: animation of %u frames played, one per bench frame: median frame switch %.3f ms "
                   "(instance tables and BVH; no model upload)\n",
                   vx_tool_name, vx_svo_scene_frames(&a->scene), bench_switch[frames / 2]);
        }
    }
    free(bench);
    free(bench_trace);
    free(bench_switch);
    free(bench_panels);
    free(bench_edit);
    return a->status;
}

/* --present: the GPU path on devices that are not the CPU (auto), or as
 * asked; it needs vx_display (a compute pipeline on the window's device). */
static void choose_present(app* a) {
    const char* want = a->o.present ? a->o.present : "auto";
    bool cpu = vx_gpu_is_cpu(a->gpu);
    if (!strcmp(want, "host") || (!strcmp(want, "auto") && cpu)) {
        snprintf(a->present_note, sizeof a->present_note, "host readback (%s)",
                 !strcmp(want, "host") ? "--present host" : "a CPU device: its memory is the host's");
        return;
    }
    vx_error err = {0};
    if (vx_display_create(a->gpu, &a->disp, &err)) {
        snprintf(a->present_note, sizeof a->present_note, "host readback (the GPU path failed: %.100s)", err.msg);
        a->disp = NULL;
        return;
    }
    vx_display_set_timestamps(a->disp, false); /* the viewer reads the passes' times, not the display's */
    /* batches: twice their frames in flight, so that one batch runs while the next is recorded */
    if (a->batch.cur > 1 && vx_display_set_queue(a->disp, 2 * a->batch.cur, a->batch.cur, false, &err)) {
        snprintf(a->present_note, sizeof a->present_note, "host readback (the GPU path failed: %.100s)", err.msg);
        vx_display_destroy(a->disp);
        a->disp = NULL;
        return;
    }
    /* the panels drawn on the GPU where the swapchain images take the last pass's writes and a render pass */
    char why[256] = "", batch_text[96];
    if (a->o.batch) snprintf(batch_text, sizeof batch_text, "%u", a->batch.cur);
    else snprintf(batch_text, sizeof batch_text, "1 to %u (--batch auto: from the frame time, at most %g ms later; 1 with vsync)",
                  a->batch.max, a->batch.latency_ms);
    if (a->o.gpu_panels && a->ui && vp_colour(a->p)) a->panels_gpu = sv_panels_gpu_init(a, why, sizeof why);
    snprintf(a->present_note, sizeof a->present_note,
             "GPU: colour passes -> display conversion + overlay %s the swapchain image in one submission, %u "
             "frames in flight, %s a submission (%s); panels %s; grabs wait for theirs; other modes, picks, screenshots: "
             "host readback",
             vp_storage(a->p) ? "fused into the last pass, written into" : "-> a copy to",
             a->batch.cur > 1 ? 2 * a->batch.cur : VX_DISPLAY_FRAMES, batch_text,
             strcmp(want, "gpu") ? "auto" : "--present gpu",
             a->panels_gpu        ? "drawn on the GPU (ImGui's Vulkan backend) in that submission"
             : why[0]             ? why
             : !a->o.gpu_panels   ? "drawn on the CPU into the overlay (--gpu-panels: on the GPU)"
                                  : "drawn on the CPU into the overlay (the swapchain images are not storage and colour images)");
}

int main(int argc, char** argv) {
    vx_tool_init(argc, argv);
    app a = {0};
    a.o = parse(argc, argv);
    a.batch = sv_batch_make(a.o.batch ? a.o.batch : VX_DISPLAY_SLOTS / 2, a.o.batch_latency);
    if (a.o.batch) a.batch.cur = a.o.batch; /* fixed: never changed */
    vx_budget_init(&a.budget, a.o.conv.max_memory, NULL);
    if (a.o.conv.max_memory) a.o.conv.alloc = &a.budget.allocator;
    a.sel = NO_SEL;
    a.sel_light = NO_SEL;
    a.light_step_for = a.mat_step_for = NO_SEL;
    a.mat_sel = 1; /* the properties panel's material: palette entry 1 */
    a.name_for = NO_SEL;
    a.pick_op = -1;
    a.bake_res_i = 1, a.bake_spp = 8, a.bake_grid = 4; /* the probe panel's bake: res 32, 8 spp, 4^3 probes */
    a.mode = a.o.mode;
    a.gi = a.o.gi;
    a.pmode = a.o.pmode;
    a.overlay = true;
    vx_pass_list_parse(a.o.passes, &a.passes, NULL); /* checked by parse() */
    if (a.o.verbose)
        printf("%s %s --mode %s --fov %g%s%s%s%s\n", vx_tool_name, a.o.in, sv_mode_name(&a), a.o.fov,
               a.o.screenshot ? " --screenshot " : "", a.o.screenshot ? a.o.screenshot : "",
               a.o.script ? " --script " : "", a.o.script ? a.o.script : "");
    if (a.o.script && load_script(&a)) return 1;
    vx_error err = {0};
    double t0 = vx_time_now();
    if (load_scene(&a.o, a.o.in, &a.scene, &err)) {
        if (a.lines) free(a.lines[0]), free(a.lines);
        return vx_tool_error_budget(a.o.in, &err, &a.budget);
    }
    snprintf(a.scene_file, sizeof a.scene_file, "%s", a.o.in);
    double t_load = vx_time_now() - t0;
    if (a.o.probes && load_probes(&a, a.o.probes, &err)) {
        vx_svo_scene_free(&a.scene);
        if (a.lines) free(a.lines[0]), free(a.lines);
        return vx_tool_errorf("%s", err.msg); /* the message names the file */
    }
    ved_init(&a.ed, &a.scene);
    a.ed.undo_limit = a.o.undo_limit, a.ed.undo_bytes = a.o.undo_bytes;
    a.fps = a.o.fps > 0 ? a.o.fps : a.scene.frame_rate > 0 ? a.scene.frame_rate : SV_FPS_DEFAULT;
    int status = 1;
    char title[512];
    snprintf(title, sizeof title, "svo_view - %s", a.o.in);
    vx_logger logger = {log_cb, NULL};
    vx_gpu_desc gd = {.validate = a.o.validate, .logger = &logger};
    if (vp_create(&(vp_desc){.width = a.o.win_w, .height = a.o.win_h, .title = title, .device = a.o.device,
                             .validate = a.o.validate, .validation_errors = &a.validation_errors,
                             .logger = &logger, .vsync = a.o.vsync, .hidden = a.o.hidden,
                             .batch = a.batch.max},
                  &a.p, &err)) {
        vx_tool_error(a.o.in, &err);
        goto done;
    }
    vp_external(a.p, &gd);
    if (vx_gpu_create(&gd, &a.gpu, &err)) {
        vx_tool_error(a.o.in, &err);
        goto done;
    }
    GLFWwindow* w = vp_window(a.p);
    glfwSetWindowUserPointer(w, &a);
    glfwSetKeyCallback(w, key_cb);
    glfwSetMouseButtonCallback(w, mouse_cb);
    glfwSetCursorPosCallback(w, cursor_cb);
    glfwSetScrollCallback(w, scroll_cb);
    glfwSetDropCallback(w, drop_cb);
    glfwSetCharCallback(w, char_cb);
    glfwGetCursorPos(w, &a.mouse_x, &a.mouse_y);
    if (!a.o.screenshot && !a.o.no_panels) a.panels = sv_panels_create(&a);
    choose_present(&a);
    camera_default(&a);
    sv_rebuild(&a);
    if (!a.rs && (a.o.screenshot || a.o.bench)) goto done; /* the message names the problem */
    if (a.o.verbose) {
        printf("%s: %s: %u models, %u instances (load %.1f ms, scene upload %.1f ms) on %s\n", vx_tool_name, a.o.in,
               a.scene.model_count, a.scene.instance_count, t_load * 1e3, a.update_ms, vx_gpu_device_name(a.gpu));
        printf("%s: present: %s\n", vx_tool_name, a.present_note);
    }
    status = run(&a);
done:
    sv_panels_destroy(&a);
    vx_display_destroy(a.disp);
    vx_render_image_free(&a.img);
    vx_probe_gpu_destroy(a.probes_gpu);
    drop_passes(&a);
    vx_render_scene_destroy(a.rs);
    uint32_t gpu_errors = vx_gpu_validation_errors(a.gpu);
    vx_gpu_destroy(a.gpu);
    /* the window's callbacks point at `a`; the presenter goes last */
    vp_destroy(a.p);
    if (a.o.validate) {
        /* the tracer runs on the window's device, so the window's messenger sees its errors too */
        uint32_t n = a.validation_errors + gpu_errors;
        fprintf(n ? stderr : stdout, "%s: %u Vulkan validation error%s\n", vx_tool_name, n, n == 1 ? "" : "s");
        if (n && !status) status = 1;
    }
    if (a.have_probes) vx_probe_set_free(&a.probes);
    if (a.bake.active) vx_probe_set_free(&a.bake.ps);
    ved_free(&a.ed);
    vx_svo_scene_free(&a.scene);
    vx_free(NULL, a.sky_rgb);
    free(a.px8);
    if (a.lines) free(a.lines[0]), free(a.lines);
    return status;
}
