/* tools/svo_view/options.c - svo_view's command line: the defaults (which
 * --help prints), the parser and its checks (options.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tools/common/tool.h"
#include "tools/svo_view/app.h"
#include "tools/svo_view/options.h"
#include "tools/svo_view/panels.h"

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
            "      save FILE.svo | export FILE.vox [quantize] (over 255 colours: a 255-entry palette) |\n"
            "      export FILE.glb | export FILE.vdb (as svo_info --to-glb / --to-vdb of the saved scene) |\n"
            "      screenshot FILE | wait N | echo TEXT | quit |\n"
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
            "      material ID type diffuse|metal|glass|emit, material ID rough|metal|spec|trans|ior|emit|flux X,\n"
            "      material ID emit_color R,G,B|none (palette index or material id; each an undo step) |\n"
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

static bool parse_size(const char* s, uint32_t* w, uint32_t* h) {
    unsigned a, b;
    char c;
    if (sscanf(s, "%ux%u%c", &a, &b, &c) != 2 || !a || !b || a > 16384 || b > 16384) return false;
    *w = a, *h = b;
    return true;
}

options sv_options_parse(int argc, char** argv) {
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
        } else if (!strcmp(a, "--screenshot")) o.screenshot = vx_tool_arg(argc, argv, &i, usage);
        else if (!strcmp(a, "--size")) {
            if (!parse_size(vx_tool_arg(argc, argv, &i, usage), &o.width, &o.height))
                usage_error("bad --size '%s' (WxH, at most 16384 each)", argv[i]);
        } else if (!strcmp(a, "--window")) {
            if (!parse_size(vx_tool_arg(argc, argv, &i, usage), &o.win_w, &o.win_h))
                usage_error("bad --window '%s' (WxH)", argv[i]);
            window_set = true;
        } else if (!strcmp(a, "--mode")) {
            const char* m = vx_tool_arg(argc, argv, &i, usage);
            o.gi = !strcmp(m, "gi") || !strcmp(m, "lightfield");
            if (o.gi) vx_probe_render_mode_parse(m, &o.pmode);
            if (!o.gi && !vx_render_mode_parse(m, &o.mode))
                usage_error("unknown mode '%s' (color|albedo|normal|depth|instance|iterations|gi|lightfield)", m);
        } else if (!strcmp(a, "--probes")) {
            o.probes = vx_tool_arg(argc, argv, &i, usage);
        } else if (!strcmp(a, "--passes")) {
            o.passes = vx_tool_arg(argc, argv, &i, usage);
            vx_pass_list pl;
            vx_error perr = {0};
            if (vx_pass_list_parse(o.passes, &pl, &perr)) usage_error("--passes: %s", perr.msg);
            if (vx_pass_list_has(&pl, VX_PASS_GI) && !vx_tool_gi_method_known(pl.gi))
                usage_error("--passes: unknown gi method '%s' (" VX_TOOL_GI_METHODS ")", pl.gi);
        } else if (!strcmp(a, "--fov")) {
            if (!vx_tool_parse_double(vx_tool_arg(argc, argv, &i, usage), &o.fov) || !(o.fov > 0 && o.fov < 180))
                usage_error("bad --fov '%s' (degrees in (0,180))", argv[i]);
        } else if (!strcmp(a, "--script")) o.script = vx_tool_arg(argc, argv, &i, usage);
        else if (!strcmp(a, "--save")) o.save = vx_tool_arg(argc, argv, &i, usage);
        else if (!strcmp(a, "--bench")) {
            if (!vx_tool_parse_u32(vx_tool_arg(argc, argv, &i, usage), &o.bench) || !o.bench || o.bench > 100000)
                usage_error("bad --bench '%s' (1 to 100000 frames)", argv[i]);
        } else if (!strcmp(a, "--fps")) {
            if (!vx_tool_parse_double(vx_tool_arg(argc, argv, &i, usage), &o.fps) || !(o.fps > 0 && o.fps <= 1000))
                usage_error("bad --fps '%s' (frames per second in (0,1000])", argv[i]);
        } else if (!strcmp(a, "--present")) {
            o.present = vx_tool_arg(argc, argv, &i, usage);
            if (strcmp(o.present, "auto") && strcmp(o.present, "gpu") && strcmp(o.present, "host"))
                usage_error("bad --present '%s' (auto, gpu or host)", o.present);
        } else if (!strcmp(a, "--undo-limit")) {
            if (!vx_tool_parse_u32(vx_tool_arg(argc, argv, &i, usage), &o.undo_limit) || !o.undo_limit ||
                o.undo_limit > 1000000)
                usage_error("bad --undo-limit '%s' (1 to 1000000 steps)", argv[i]);
        } else if (!strcmp(a, "--undo-memory")) {
            if (!vx_tool_parse_bytes(vx_tool_arg(argc, argv, &i, usage), &o.undo_bytes) || !o.undo_bytes)
                usage_error("bad --undo-memory '%s' (bytes, e.g. 512M, 4G)", argv[i]);
        } else if (!strcmp(a, "--batch")) {
            const char* v = vx_tool_arg(argc, argv, &i, usage);
            if (!strcmp(v, "auto")) o.batch = 0;
            else if (!vx_tool_parse_u32(v, &o.batch) || o.batch < 1 || 2 * o.batch > VX_DISPLAY_SLOTS)
                usage_error("bad --batch '%s' (auto, or 1 to %d frames a submission)", v, VX_DISPLAY_SLOTS / 2);
        } else if (!strcmp(a, "--batch-latency")) {
            const char* v = vx_tool_arg(argc, argv, &i, usage);
            char* end;
            o.batch_latency = strtod(v, &end);
            if (end == v || *end || !(o.batch_latency > 0) || o.batch_latency > 1e6)
                usage_error("bad --batch-latency '%s' (milliseconds, above 0)", v);
        } else if (!strcmp(a, "--no-panels")) o.no_panels = true;
        else if (!strcmp(a, "--gpu-panels")) o.gpu_panels = true;
        else if (!strcmp(a, "--vsync")) o.vsync = true;
        else if (!strcmp(a, "--hidden")) o.hidden = true;
        else if (!strcmp(a, "--device")) o.device = vx_tool_arg(argc, argv, &i, usage);
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
    if (o.gi && !o.probes)
        usage_error("mode %s needs --probes FILE (bake them: svo_bake %s OUT.probes)", vx_probe_render_mode_name(o.pmode),
                    o.in);
    if (o.screenshot) {
        const char* ext = vx_tool_ext(o.screenshot);
        if (strcmp(ext, "png") && strcmp(ext, "exr")) usage_error("screenshot '%s' must end in .png or .exr", o.screenshot);
        if (!o.width) o.width = 640, o.height = 480; /* svo_render's default size */
    }
    if (o.width && !window_set) o.win_w = o.width, o.win_h = o.height;
    return o;
}
