/* tools/svo_view/main.c - svo_view FILE [options]: an interactive viewer and
 * scene editor on the Vulkan tracer (GLFW window, swapchain, CPU overlay),
 * scriptable for headless runs under Xvfb. */
#include <GLFW/glfw3.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "convert/convert.h"
#include "formats/image.h"
#include "probes/probes.h"
#include "render/pipeline.h"
#include "render/render.h"
#include "tools/common/conv.h"
#include "tools/common/tool.h"
#include "tools/svo_view/editor.h"
#include "tools/svo_view/font.h"
#include "tools/svo_view/present.h"

#define NO_SEL UINT32_MAX
#define PI 3.14159265358979323846

typedef struct options {
    const char* in;
    const char* screenshot;
    const char* script;
    const char* save;       /* Ctrl+S target (default: IN with .svo replaced by .edited.svo) */
    uint32_t width, height; /* render size; 0 == the window's framebuffer */
    uint32_t win_w, win_h;
    vx_render_mode mode;
    bool gi;            /* --mode gi|lightfield: a probe mode (needs probes) */
    vx_probe_render_mode pmode;
    const char* probes; /* light field probes from svo_bake */
    const char* passes; /* the colour mode's pass list (render/pipeline.h) */
    double fov;
    const char* device;
    bool validate, vsync, verbose, hidden;
    uint32_t bench;
    vx_tool_conv conv; /* converter options, as vox2svo has them */
} options;

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
            "                          key 9 cycles presets (ao, aa, tonemap, dof); the overlay shows each\n"
            "                          pass's GPU time\n"
            "    --fov DEG             vertical field of view (default: %g)\n"
            "    --script FILE         play commands from FILE (see below)\n"
            "    --save FILE.svo       where Ctrl+S saves (default: FILE.edited.svo)\n"
            "    --bench N             render N frames, print the median frame time, exit\n"
            "    --vsync               start with vsync on (V toggles)\n"
            "    --hidden              do not show the window (scripts, benchmarks)\n"
            "    --device N|NAME       Vulkan device (default: a discrete GPU, else any)\n"
            "    --validate            enable the Vulkan validation layer; prints the error count at exit\n"
            "                          (status 1 when there were any)\n"
            "    --frame N, --keep-hidden, --keep-unused, --no-collapse, --no-dag  (.vox)\n"
            "    --res N (default: %u), --scene N, --solid, --normals, --y-up  (.gltf/.glb)\n"
            "    --grid NAME, --threshold X, --density, --color NAME   (.vdb)\n"
            "    --max-memory SIZE     refuse a scene that needs more memory than SIZE to read (512M, 4G)\n"
            "    -v, --verbose         print the effective options and timings\n"
            "    -h, --help            print this help and exit;  --version: versions\n"
            "Keys: WASD/Q/E fly, right mouse look, wheel speed (orbit: zoom), O orbit, F frame the\n"
            "      selection or scene, 1-6 modes (7: gi, 8: lightfield, with probes), V vsync, Tab overlay,\n"
            "      P screenshot; click picks;\n"
            "      G/R/M then X/Y/Z move (arrows/mouse, Enter, Esc)/rotate (Shift: back)/mirror;\n"
            "      Shift+D duplicate, Delete, H hide/Alt+H show all, L then 0-9 toggles a layer,\n"
            "      Ctrl+Z/Ctrl+Y undo/redo, Ctrl+S save, Ctrl+E export .vox, drop a file to add it.\n"
            "Script commands (one a line, # comments): camera EX EY EZ TX TY TZ | camera default |\n"
            "      fly DX DY DZ | look DYAW DPITCH | orbit on|off | mode M | passes LIST | probes FILE |\n"
            "      select N|none |"
            "      pick X Y |"
            " frame | move DX DY DZ | rotate x|y|z [TURNS] | mirror x|y|z | duplicate | delete |\n"
            "      hide | show | layer N hide|show | add FILE | open FILE | undo | redo |\n"
            "      save FILE.svo | export FILE.vox | screenshot FILE | wait N | echo TEXT | quit\n"
            "Examples:\n"
            "    %s castle.vox\n"
            "    %s scene.svo --screenshot shot.png --size 640x480 --mode albedo\n"
            "    %s scene.svo --probes scene.probes --mode gi\n"
            "    xvfb-run -a %s scene.svo --script edit.txt --hidden\n",
            vx_tool_name, d.win_w, d.win_h, vx_render_mode_name(d.mode), d.passes, d.fov, d.conv.res, vx_tool_name, vx_tool_name,
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
        } else if (!strcmp(a, "--vsync")) o.vsync = true;
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

typedef struct app {
    options o;
    vx_budget budget; /* --max-memory: scenes the viewer loads come from it */
    vp* p;
    vx_gpu* gpu;
    vx_render_scene* rs;
    vx_svo_scene scene;
    ved ed;
    /* camera: eye + yaw/pitch (z up); default: svo_render's framing */
    bool cam_default;
    double eye[3], yaw, pitch, speed;
    bool orbit;
    double orbit_center[3], orbit_dist;
    vx_render_mode mode;
    bool gi; /* a probe mode (gi, lightfield): replaces `mode` while probes are loaded */
    vx_probe_render_mode pmode;
    bool overlay;
    /* light field probes (mode gi); nothing of them is touched while none are loaded */
    vx_probe_set probes;
    vx_probe_gpu* probes_gpu; /* their maps on the GPU for rs (made at the first probe frame) */
    /* the colour mode's pass pipeline over rs, its gi method (made at the first frame that needs it) */
    vx_frame_renderer* fr;
    vx_pass_list passes;
    vx_probe_gi* pgi;
    vx_gi_method gm;
    vx_pass_timing timings[VX_PASS_KIND_COUNT + 1];
    uint32_t timing_count;
    double passes_ms;
    bool have_probes;
    char probes_path[1024];
    uint32_t validation_errors;
    uint32_t sel;
    /* pending editor operation: 'g' grab, 'r' rotate, 'm' mirror, 'l' layer */
    char op;
    int op_axis;
    int32_t grab_moved;
    double grab_px;
    bool pick_pending;
    double pick_x, pick_y;
    char msg[256];
    double msg_until;
    bool msg_error;
    double frame_ms[64];
    uint32_t frame_n;
    double trace_ms, rays_per_s, update_ms;
    bool quit;
    int status;
    /* script */
    char** lines;
    uint32_t line_count, line_pos, wait;
    /* frame */
    uint8_t* px8;
    size_t px8_cap;
    vx_render_image img;
    const char* shot;
    char shot_buf[1024];
    uint32_t shot_counter;
    double mouse_x, mouse_y;
    bool rmb, lmb;
} app;

static void message(app* a, bool error, const char* fmt, ...) __attribute__((format(printf, 3, 4)));
static void message(app* a, bool error, const char* fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(a->msg, sizeof a->msg, fmt, ap);
    va_end(ap);
    a->msg_error = error;
    a->msg_until = glfwGetTime() + 6;
    fprintf(error ? stderr : stdout, "%s: %s\n", vx_tool_name, a->msg);
}

static const char* mode_name(const app* a) {
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
    if (a->have_probes) vx_probe_set_free(&a->probes);
    a->probes = ps;
    a->have_probes = true;
    snprintf(a->probes_path, sizeof a->probes_path, "%s", path);
    return VX_OK;
}

static void do_probes(app* a, const char* path) {
    vx_error err = {0};
    if (load_probes(a, path, &err)) {
        message(a, true, "%s", err.msg);
        return;
    }
    message(a, false, "probes %s: %ux%ux%u grid, res %u", path, a->probes.grid[0], a->probes.grid[1],
            a->probes.grid[2], a->probes.res);
}

/* Mode gi is only offered with probes loaded; otherwise a message, and the mode stays. */
static void set_probe_mode(app* a, vx_probe_render_mode m) {
    if (!a->have_probes) {
        message(a, true, "mode %s needs light field probes (--probes FILE, or the script command probes FILE)",
                vx_probe_render_mode_name(m));
        return;
    }
    a->gi = true;
    a->pmode = m;
}

static void world_box(const vx_svo_scene* s, uint32_t i, double lo[3], double hi[3]) {
    double glo[3], ghi[3];
    ved_instance_box(s, i, glo, ghi);
    const double* w = s->world_from_grid;
    for (int k = 0; k < 3; k++) lo[k] = INFINITY, hi[k] = -INFINITY;
    for (int c = 0; c < 8; c++) {
        double p[3] = {(c & 1) ? ghi[0] : glo[0], (c & 2) ? ghi[1] : glo[1], (c & 4) ? ghi[2] : glo[2]};
        for (int r = 0; r < 3; r++) {
            double q = w[4 * r] * p[0] + w[4 * r + 1] * p[1] + w[4 * r + 2] * p[2] + w[4 * r + 3];
            lo[r] = fmin(lo[r], q), hi[r] = fmax(hi[r], q);
        }
    }
}


static void scene_box(const vx_svo_scene* s, double lo[3], double hi[3]) {
    bool any = false;
    for (int k = 0; k < 3; k++) lo[k] = INFINITY, hi[k] = -INFINITY;
    for (uint32_t i = 0; i < s->instance_count; i++) {
        if (!vx_svo_instance_drawn(s, i)) continue;
        double a[3], b[3];
        world_box(s, i, a, b);
        for (int k = 0; k < 3; k++) lo[k] = fmin(lo[k], a[k]), hi[k] = fmax(hi[k], b[k]);
        any = true;
    }
    if (!any)
        for (int k = 0; k < 3; k++) lo[k] = hi[k] = 0;
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
    scene_box(&a->scene, lo, hi);
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
    vx_frame_renderer_destroy(a->fr);
    a->fr = NULL;
}

static void rebuild(app* a) {
    double t0 = vx_time_now();
    vx_probe_gpu_destroy(a->probes_gpu); /* bound to the old render scene */
    a->probes_gpu = NULL;
    drop_passes(a);
    vx_render_scene_destroy(a->rs);
    a->rs = NULL;
    vx_error err = {0};
    if (vx_render_scene_create(a->gpu, &a->scene, &a->rs, &err)) message(a, true, "cannot draw the scene: %s", err.msg);
    else if (vx_frame_renderer_create(a->rs, &a->scene, &a->fr, &err)) message(a, true, "pass pipeline: %s", err.msg);
    a->update_ms = (vx_time_now() - t0) * 1e3;
}

/* Starts an edit: the camera stops following the scene bounds, and the
 * state is saved for undo. */
static bool edit_begin(app* a, bool needs_sel) {
    if (needs_sel && a->sel == NO_SEL) {
        message(a, true, "nothing selected");
        return false;
    }
    a->cam_default = false;
    vx_error err = {0};
    if (ved_begin(&a->ed, &err)) {
        message(a, true, "%s", err.msg);
        return false;
    }
    return true;
}

static void edit_end(app* a, const char* what) {
    rebuild(a);
    if (a->o.verbose) printf("%s: %s (scene update %.2f ms)\n", vx_tool_name, what, a->update_ms);
}

static void set_scene(app* a, vx_svo_scene* s) {
    ved_free(&a->ed);
    vx_svo_scene_free(&a->scene);
    a->scene = *s;
    ved_init(&a->ed, &a->scene);
    a->sel = NO_SEL;
    a->op = 0;
    camera_default(a);
    rebuild(a);
}

static void do_open(app* a, const char* path) {
    vx_svo_scene s;
    vx_error err = {0};
    if (load_scene(&a->o, path, &s, &err)) {
        message(a, true, "%s: %s", path, err.msg);
        return;
    }
    set_scene(a, &s);
    /* probes describe the light of the scene they were baked in */
    bool had = a->have_probes;
    if (had) {
        vx_probe_gpu_destroy(a->probes_gpu);
        a->probes_gpu = NULL;
        vx_probe_gi_destroy(a->pgi);
        a->pgi = NULL;
        vx_probe_set_free(&a->probes);
        a->have_probes = false;
        a->gi = false;
    }
    message(a, false, "opened %s: %u models, %u instances%s", path, a->scene.model_count, a->scene.instance_count,
            had ? " (probes of the previous scene unloaded)" : "");
}

static void do_add(app* a, const char* path) {
    vx_svo_scene s;
    vx_error err = {0};
    if (load_scene(&a->o, path, &s, &err)) {
        message(a, true, "%s: %s", path, err.msg);
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
    if (!edit_begin(a, false)) {
        vx_svo_scene_free(&s);
        return;
    }
    if (ved_add_scene(&a->scene, &s, d, &first, &err)) {
        message(a, true, "%s: %s", path, err.msg);
        ved_undo(&a->ed, NULL);
    } else {
        a->sel = n ? first : NO_SEL;
        message(a, false, "added %s: %u instances", path, n);
    }
    vx_svo_scene_free(&s);
    edit_end(a, "add");
}

static void do_save(app* a, const char* path) {
    vx_error err = {0};
    vx_svo_scene_update_bounds(&a->scene);
    if (vx_svo_write_file(&a->scene, path, &err)) message(a, true, "%s: %s", path, err.msg);
    else message(a, false, "saved %s", path);
}

static void do_export(app* a, const char* path) {
    vx_error err = {0};
    vx_vox_scene vs;
    vx_result r = vx_conv_svo_to_vox(&a->scene, NULL, &vs, &err);
    if (!r) {
        r = vx_vox_write_file(&vs, path, &err);
        vx_vox_scene_free(&vs);
    }
    if (r) message(a, true, "%s: %s", path, err.msg);
    else message(a, false, "exported %s", path);
}

static void do_frame(app* a) {
    double lo[3], hi[3], f[3];
    if (a->sel != NO_SEL) world_box(&a->scene, a->sel, lo, hi);
    else scene_box(&a->scene, lo, hi);
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

static void do_rotate(app* a, int axis, int turns) {
    if (!edit_begin(a, true)) return;
    ved_rotate(&a->scene, a->sel, axis, turns);
    edit_end(a, "rotate");
}

static void do_mirror(app* a, int axis) {
    if (!edit_begin(a, true)) return;
    ved_mirror(&a->scene, a->sel, axis);
    edit_end(a, "mirror");
}

static void do_duplicate(app* a) {
    if (!edit_begin(a, true)) return;
    vx_error err = {0};
    uint32_t n;
    if (ved_duplicate(&a->scene, a->sel, &n, &err)) message(a, true, "%s", err.msg);
    else a->sel = n;
    edit_end(a, "duplicate");
}

static void do_delete(app* a) {
    if (!edit_begin(a, true)) return;
    ved_delete(&a->scene, a->sel);
    a->sel = NO_SEL;
    edit_end(a, "delete");
}

static void do_hide(app* a, bool hide) {
    if (!edit_begin(a, hide)) return;
    if (hide) a->scene.instances[a->sel].flags |= VX_SVO_INSTANCE_HIDDEN;
    else
        for (uint32_t i = 0; i < a->scene.instance_count; i++) a->scene.instances[i].flags &= ~VX_SVO_INSTANCE_HIDDEN;
    edit_end(a, hide ? "hide" : "show");
}

static void do_layer(app* a, uint32_t l, int hide /* -1 toggles */) {
    if (l >= a->scene.layer_count) {
        message(a, true, "no layer %u (the scene has %u)", l, a->scene.layer_count);
        return;
    }
    if (!edit_begin(a, false)) return;
    uint32_t* f = &a->scene.layers[l].flags;
    bool h = hide < 0 ? !(*f & VX_SVO_LAYER_HIDDEN) : hide > 0;
    *f = h ? (*f | VX_SVO_LAYER_HIDDEN) : (*f & ~VX_SVO_LAYER_HIDDEN);
    message(a, false, "layer %u '%s' %s", l, a->scene.layers[l].name, h ? "hidden" : "shown");
    edit_end(a, "layer");
}

static void do_undo(app* a, bool redo) {
    a->cam_default = false;
    bool ok = redo ? ved_redo(&a->ed, NULL) : ved_undo(&a->ed, NULL);
    if (!ok) {
        message(a, false, "nothing to %s", redo ? "redo" : "undo");
        return;
    }
    if (a->sel != NO_SEL && a->sel >= a->scene.instance_count) a->sel = NO_SEL;
    edit_end(a, redo ? "redo" : "undo");
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

static void draw_selection(app* a, vf_canvas* cv) {
    if (a->sel == NO_SEL || a->sel >= a->scene.instance_count) return;
    double lo[3], hi[3], f[3];
    world_box(&a->scene, a->sel, lo, hi);
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
    snprintf(buf[nl], sizeof buf[0], "mode: %s  camera: %s  vsync: %s  size %ux%u", mode_name(a),
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
static vx_result render_passes(app* a, const vx_render_desc* d, vx_error* err) {
    if (vx_pass_list_has(&a->passes, VX_PASS_GI) && !a->pgi) {
        vx_probe_render_desc pd = {0};
        vx_result r = vx_probe_gi_create(a->rs, &a->scene, a->have_probes ? &a->probes : NULL, a->passes.gi, &pd,
                                         &a->gm, &a->pgi, err);
        if (r) return r;
    }
    vx_frame_desc fd = vx_frame_desc_defaults();
    fd.base = *d;
    fd.base.mode = VX_RENDER_COLOR;
    fd.base.spp = 0;
    fd.passes = &a->passes;
    fd.gi = a->pgi ? &a->gm : NULL;
    fd.want_ids = d->want_hits;
    vx_frame_result res;
    vx_result r = vx_frame_render(a->fr, &fd, &res, err);
    if (r) return r;
    a->img = res.image;
    memcpy(a->timings, res.timings, sizeof a->timings);
    a->timing_count = res.timing_count;
    a->passes_ms = res.frame_ms;
    return VX_OK;
}

/* Sets the pass list (script command `passes LIST`, key 9 cycles presets). */
static bool set_passes(app* a, const char* list) {
    vx_pass_list pl;
    vx_error err = {0};
    if (vx_pass_list_parse(list, &pl, &err)) {
        message(a, true, "passes: %s", err.msg);
        return false;
    }
    if (vx_pass_list_has(&pl, VX_PASS_GI) && strcmp(pl.gi, "pathtrace") && !a->have_probes) {
        message(a, true, "gi=%s needs light field probes (--probes FILE, or the script command probes FILE)", pl.gi);
        return false;
    }
    vx_probe_gi_destroy(a->pgi);
    a->pgi = NULL;
    a->passes = pl;
    a->timing_count = 0;
    char t[160];
    vx_pass_list_format(&pl, t, sizeof t);
    message(a, false, "passes %s", t[0] ? t : "(none)");
    return true;
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
            message(a, true, "mode %s: %s", vx_probe_render_mode_name(a->pmode), err->msg);
            a->gi = false;
        } else if (a->pick_pending && (r = vx_render_frame(a->rs, &d, &pick_img, err))) {
            return r;
        }
    }
    if (a->rs && !a->gi && a->mode == VX_RENDER_COLOR && a->fr && !vx_render_scene_precise(a->rs)) {
        vx_result r = render_passes(a, &d, err);
        if (r) return r;
    } else if (a->rs && !a->gi) {
        vx_result r = vx_render_frame(a->rs, &d, &a->img, err);
        if (r) return r;
    }
    if (a->rs && a->img.pixels) {
        a->trace_ms = a->img.gpu_seconds * 1e3;
        a->rays_per_s = a->img.gpu_seconds > 0 ? a->img.rays / a->img.gpu_seconds : 0;
    }
    if (a->pick_pending) {
        a->pick_pending = false;
        uint32_t x = (uint32_t)a->pick_x, y = (uint32_t)a->pick_y;
        uint32_t hit = VX_RENDER_NO_HIT;
        const vx_render_hit* hits = pick_img.hits ? pick_img.hits : a->img.hits;
        if (hits && a->pick_x >= 0 && a->pick_y >= 0 && x < w && y < h) hit = hits[(size_t)y * w + x].instance;
        vx_render_image_free(&pick_img);
        a->sel = hit == VX_RENDER_NO_HIT ? NO_SEL : hit;
        if (hit == VX_RENDER_NO_HIT) printf("%s: pick %u %u: nothing\n", vx_tool_name, x, y);
        else printf("%s: pick %u %u: instance %u\n", vx_tool_name, x, y, hit);
    }
    if (a->shot && a->img.pixels) {
        vx_result r = save_image(&a->img, a->shot, err);
        if (r) message(a, true, "%s: %s", a->shot, err->msg);
        else printf("%s: wrote %s (%ux%u, mode %s)\n", vx_tool_name, a->shot, w, h, mode_name(a));
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
    if (a->img.pixels) convert(a, &a->img, &cv);
    else memset(a->px8, 0, need);
    if (!a->o.screenshot && !a->o.bench) {
        draw_selection(a, &cv);
        if (a->overlay) draw_overlay(a, &cv);
    }
    vx_result r = vp_present(a->p, a->px8, w, h, err);
    if (r) return r;
    a->frame_ms[a->frame_n++ % 64] = (vx_time_now() - t0) * 1e3;
    return VX_OK;
}

/* ---- input ---------------------------------------------------------------------------- */

static int axis_key(int key) { return key == GLFW_KEY_X ? 0 : key == GLFW_KEY_Y ? 1 : key == GLFW_KEY_Z ? 2 : -1; }

static void grab_end(app* a, bool keep) {
    if (!keep) {
        ved_undo(&a->ed, NULL); /* back to the snapshot taken at G */
        rebuild(a);
    }
    a->op = 0;
}

static void key_cb(GLFWwindow* win, int key, int sc, int action, int mods) {
    (void)sc;
    app* a = glfwGetWindowUserPointer(win);
    if (action == GLFW_RELEASE) return;
    bool ctrl = mods & GLFW_MOD_CONTROL, shift = mods & GLFW_MOD_SHIFT, alt = mods & GLFW_MOD_ALT;
    if (a->op) {
        int ax = axis_key(key);
        if (a->op == 'l' && key >= GLFW_KEY_0 && key <= GLFW_KEY_9) {
            a->op = 0;
            do_layer(a, (uint32_t)(key - GLFW_KEY_0), -1);
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
                rebuild(a);
                return;
            }
            if (key == GLFW_KEY_ENTER || key == GLFW_KEY_KP_ENTER) return grab_end(a, true);
            if (key == GLFW_KEY_ESCAPE) return grab_end(a, false);
            return;
        }
        if (ax >= 0 && a->op == 'r') do_rotate(a, ax, shift ? -1 : 1);
        else if (ax >= 0 && a->op == 'm') do_mirror(a, ax);
        a->op = 0;
        return;
    }
    if (ctrl) {
        if (key == GLFW_KEY_Z) do_undo(a, shift);
        else if (key == GLFW_KEY_Y) do_undo(a, true);
        else if (key == GLFW_KEY_S) {
            char path[1024];
            if (a->o.save) snprintf(path, sizeof path, "%s", a->o.save);
            else {
                const char* dot = strrchr(a->o.in, '.');
                int n = dot ? (int)(dot - a->o.in) : (int)strlen(a->o.in);
                snprintf(path, sizeof path, "%.*s.edited.svo", n, a->o.in);
            }
            do_save(a, path);
        } else if (key == GLFW_KEY_E) {
            char path[1024];
            const char* dot = strrchr(a->o.in, '.');
            int n = dot ? (int)(dot - a->o.in) : (int)strlen(a->o.in);
            snprintf(path, sizeof path, "%.*s.edited.vox", n, a->o.in);
            do_export(a, path);
        } else if (key == GLFW_KEY_Q) a->quit = true;
        return;
    }
    if (key >= GLFW_KEY_1 && key <= GLFW_KEY_6) a->mode = (vx_render_mode)(key - GLFW_KEY_1), a->gi = false;
    else if (key == GLFW_KEY_7) set_probe_mode(a, VX_PROBE_RENDER_GI);
    else if (key == GLFW_KEY_8) set_probe_mode(a, VX_PROBE_RENDER_LIGHTFIELD);
    else if (key == GLFW_KEY_9) {
        static const char* const presets[] = {VX_PASS_LIST_DEFAULT, "gbuffer,direct,ao", "gbuffer,direct,ao,aa,tonemap",
                                              "gbuffer,dof,direct,ao,aa,tonemap"};
        char cur[160];
        vx_pass_list_format(&a->passes, cur, sizeof cur);
        size_t k = 0, n = sizeof presets / sizeof presets[0];
        while (k < n && strcmp(cur, presets[k])) k++;
        set_passes(a, presets[(k + 1) % n]);
        a->mode = VX_RENDER_COLOR, a->gi = false;
    }
    else if (key == GLFW_KEY_V) vp_set_vsync(a->p, !vp_vsync(a->p));
    else if (key == GLFW_KEY_TAB) a->overlay = !a->overlay;
    else if (key == GLFW_KEY_F) do_frame(a);
    else if (key == GLFW_KEY_O) {
        a->orbit = !a->orbit;
        if (a->orbit) {
            double f[3];
            cam_fwd(a, f);
            if (a->sel != NO_SEL) {
                double lo[3], hi[3];
                world_box(&a->scene, a->sel, lo, hi);
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
        if (edit_begin(a, true)) a->op = 'g', a->op_axis = -1, a->grab_moved = 0;
    } else if ((key == GLFW_KEY_R || key == GLFW_KEY_M) && a->sel != NO_SEL) a->op = key == GLFW_KEY_R ? 'r' : 'm';
    else if (key == GLFW_KEY_L) a->op = 'l';
    else if (key == GLFW_KEY_D && shift) do_duplicate(a);
    else if (key == GLFW_KEY_DELETE || key == GLFW_KEY_BACKSPACE) do_delete(a);
    else if (key == GLFW_KEY_H) do_hide(a, !alt);
    else if (key == GLFW_KEY_ESCAPE) a->sel = NO_SEL;
}

static void mouse_cb(GLFWwindow* win, int button, int action, int mods) {
    (void)mods;
    app* a = glfwGetWindowUserPointer(win);
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
}

static void cursor_cb(GLFWwindow* win, double x, double y) {
    app* a = glfwGetWindowUserPointer(win);
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
            rebuild(a);
        }
    }
}

static void scroll_cb(GLFWwindow* win, double dx, double dy) {
    (void)dx;
    app* a = glfwGetWindowUserPointer(win);
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
    app* a = glfwGetWindowUserPointer(win);
    for (int i = 0; i < n; i++) do_add(a, paths[i]);
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
        if (nt == 2 && !strcmp(tok[1], "gi")) set_probe_mode(a, VX_PROBE_RENDER_GI);
        else if (nt == 2 && !strcmp(tok[1], "lightfield")) set_probe_mode(a, VX_PROBE_RENDER_LIGHTFIELD);
        else if (nt != 2 || !vx_render_mode_parse(tok[1], &a->mode)) BAD();
        else a->gi = false;
    } else if (!strcmp(c, "passes") && nt <= 2) {
        if (!set_passes(a, nt == 2 ? tok[1] : "")) return false;
    } else if (!strcmp(c, "probes") && nt == 2) {
        do_probes(a, tok[1]);
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
        a->pick_x = v[0], a->pick_y = v[1], a->pick_pending = true;
    } else if (!strcmp(c, "frame")) do_frame(a);
    else if (!strcmp(c, "move")) {
        if (nt != 4 || !parse_doubles(tok + 1, 3, v)) BAD();
        int32_t d[3];
        for (int k = 0; k < 3; k++) {
            if (v[k] != floor(v[k]) || fabs(v[k]) > 1e9) BAD();
            d[k] = (int32_t)v[k];
        }
        if (!edit_begin(a, true)) return false;
        ved_move(&a->scene, a->sel, d);
        edit_end(a, "move");
    } else if (!strcmp(c, "rotate") || !strcmp(c, "mirror")) {
        int ax = parse_axis(tok[1]);
        double turns = 1;
        if (ax < 0 || nt > 3 || (nt == 3 && (!parse_doubles(tok + 2, 1, &turns) || turns != floor(turns)))) BAD();
        if (a->sel == NO_SEL) {
            message(a, true, "%s:%u: nothing selected", a->o.script, lineno);
            return false;
        }
        if (c[0] == 'r') do_rotate(a, ax, (int)fmod(turns, 4));
        else do_mirror(a, ax);
    } else if (!strcmp(c, "duplicate") || !strcmp(c, "delete") || !strcmp(c, "hide")) {
        if (a->sel == NO_SEL) {
            message(a, true, "%s:%u: nothing selected", a->o.script, lineno);
            return false;
        }
        if (c[1] == 'u') do_duplicate(a);
        else if (c[0] == 'd') do_delete(a);
        else do_hide(a, true);
    } else if (!strcmp(c, "show")) do_hide(a, false);
    else if (!strcmp(c, "layer")) {
        uint32_t l;
        if (nt != 3 || !vx_tool_parse_u32(tok[1], &l) || (strcmp(tok[2], "hide") && strcmp(tok[2], "show"))) BAD();
        do_layer(a, l, !strcmp(tok[2], "hide"));
    } else if (!strcmp(c, "add") && nt == 2) do_add(a, tok[1]);
    else if (!strcmp(c, "open") && nt == 2) do_open(a, tok[1]);
    else if (!strcmp(c, "undo")) do_undo(a, false);
    else if (!strcmp(c, "redo")) do_undo(a, true);
    else if (!strcmp(c, "save") && nt == 2) do_save(a, tok[1]);
    else if (!strcmp(c, "export") && nt == 2) do_export(a, tok[1]);
    else if (!strcmp(c, "screenshot") && nt == 2) {
        snprintf(a->shot_buf, sizeof a->shot_buf, "%s", tok[1]);
        a->shot = a->shot_buf;
    } else if (!strcmp(c, "wait") && nt == 2) {
        if (!vx_tool_parse_u32(tok[1], &a->wait)) BAD();
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
    double last = glfwGetTime();
    double* bench = a->o.bench ? calloc(a->o.bench, sizeof *bench) : NULL;
    double* bench_trace = a->o.bench ? calloc(a->o.bench, sizeof *bench_trace) : NULL;
    uint32_t frames = 0;
    GLFWwindow* w = vp_window(a->p);
    if (a->o.screenshot) a->shot = a->o.screenshot;
    while (!a->quit && !glfwWindowShouldClose(w)) {
        glfwPollEvents();
        double now = glfwGetTime();
        fly(a, fmin(now - last, 0.25));
        last = now;
        if (a->lines && !a->pick_pending) {
            if (a->wait) a->wait--;
            else {
                /* commands up to the next one that needs a frame (pick, screenshot, wait) */
                while (a->line_pos < a->line_count && !a->quit && !a->pick_pending && !a->shot && !a->wait) {
                    uint32_t ln = a->line_pos++;
                    if (!run_command(a, a->lines[ln], ln + 1)) {
                        a->status = 1;
                        a->quit = true;
                    }
                }
            }
            if (a->quit && !a->shot && !a->pick_pending) break;
        }
        double t0 = vx_time_now();
        vx_result r = frame(a, &err);
        if (r) {
            fprintf(stderr, "%s: %s\n", vx_tool_name, err.msg);
            a->status = 1;
            break;
        }
        if (a->o.bench) {
            bench[frames] = (vx_time_now() - t0) * 1e3;
            bench_trace[frames] = a->trace_ms;
            if (++frames == a->o.bench) break;
        }
        if (a->o.screenshot) break;
    }
    if (a->o.bench && frames) {
        qsort(bench, frames, sizeof *bench, cmp_double);
        qsort(bench_trace, frames, sizeof *bench_trace, cmp_double);
        uint32_t fw = a->o.width, fh = a->o.height;
        if (!fw) vp_frame_size(a->p, &fw, &fh);
        printf("%s: %u frames %ux%u mode %s on %s: median frame %.3f ms, median trace %.3f ms (GPU timestamps)\n",
               vx_tool_name, frames, fw, fh, mode_name(a), vx_gpu_device_name(a->gpu),
               bench[frames / 2], bench_trace[frames / 2]);
    }
    free(bench);
    free(bench_trace);
    return a->status;
}

int main(int argc, char** argv) {
    vx_tool_init(argc, argv);
    app a = {0};
    a.o = parse(argc, argv);
    vx_budget_init(&a.budget, a.o.conv.max_memory, NULL);
    if (a.o.conv.max_memory) a.o.conv.alloc = &a.budget.allocator;
    a.sel = NO_SEL;
    a.mode = a.o.mode;
    a.gi = a.o.gi;
    a.pmode = a.o.pmode;
    a.overlay = true;
    vx_pass_list_parse(a.o.passes, &a.passes, NULL); /* checked by parse() */
    if (a.o.verbose)
        printf("%s %s --mode %s --fov %g%s%s%s%s\n", vx_tool_name, a.o.in, mode_name(&a), a.o.fov,
               a.o.screenshot ? " --screenshot " : "", a.o.screenshot ? a.o.screenshot : "",
               a.o.script ? " --script " : "", a.o.script ? a.o.script : "");
    if (a.o.script && load_script(&a)) return 1;
    vx_error err = {0};
    double t0 = vx_time_now();
    if (load_scene(&a.o, a.o.in, &a.scene, &err)) {
        if (a.lines) free(a.lines[0]), free(a.lines);
        return vx_tool_error_budget(a.o.in, &err, &a.budget);
    }
    double t_load = vx_time_now() - t0;
    if (a.o.probes && load_probes(&a, a.o.probes, &err)) {
        vx_svo_scene_free(&a.scene);
        if (a.lines) free(a.lines[0]), free(a.lines);
        return vx_tool_errorf("%s", err.msg); /* the message names the file */
    }
    ved_init(&a.ed, &a.scene);
    int status = 1;
    char title[512];
    snprintf(title, sizeof title, "svo_view - %s", a.o.in);
    vx_logger logger = {log_cb, NULL};
    vx_gpu_desc gd = {.validate = a.o.validate, .logger = &logger};
    if (vp_create(&(vp_desc){.width = a.o.win_w, .height = a.o.win_h, .title = title, .device = a.o.device,
                             .validate = a.o.validate, .validation_errors = &a.validation_errors,
                             .logger = &logger, .vsync = a.o.vsync, .hidden = a.o.hidden},
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
    glfwGetCursorPos(w, &a.mouse_x, &a.mouse_y);
    camera_default(&a);
    rebuild(&a);
    if (!a.rs && (a.o.screenshot || a.o.bench)) goto done; /* the message names the problem */
    if (a.o.verbose)
        printf("%s: %s: %u models, %u instances (load %.1f ms, scene upload %.1f ms) on %s\n", vx_tool_name, a.o.in,
               a.scene.model_count, a.scene.instance_count, t_load * 1e3, a.update_ms, vx_gpu_device_name(a.gpu));
    status = run(&a);
done:
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
    ved_free(&a.ed);
    vx_svo_scene_free(&a.scene);
    free(a.px8);
    if (a.lines) free(a.lines[0]), free(a.lines);
    return status;
}
