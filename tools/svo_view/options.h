/* tools/svo_view/options.h - svo_view's command line (options.c): what the
 * flags set, the defaults that --help prints, the parser. */
#ifndef VX_SVO_VIEW_OPTIONS_H
#define VX_SVO_VIEW_OPTIONS_H

#include <stdbool.h>
#include <stdint.h>

#include "probes/probes.h"
#include "render/render.h"
#include "tools/common/conv.h"

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
    double fps;     /* playback rate of an animation; 0: the file's, else SV_FPS_DEFAULT */
    bool no_panels; /* the text overlay instead of the panels */
    bool gpu_panels; /* the panels drawn on the GPU (ImGui's Vulkan backend) where the swapchain allows */
    const char* present;  /* --present auto|gpu|host */
    uint32_t batch;      /* --batch K: frames in flight submitted K at a time (1: each alone; 0: auto, batch.h) */
    double batch_latency; /* --batch-latency MS (0: SV_BATCH_LATENCY_MS) */
    uint32_t undo_limit; /* --undo-limit, --undo-memory (0: editor.h's defaults) */
    uint64_t undo_bytes;
    vx_tool_conv conv; /* converter options, as vox2svo has them */
} options;

/* The options of argv; --help prints the usage and exits 0, a bad flag
 * prints why and exits 2 (the tool's main owns its exit codes). */
options sv_options_parse(int argc, char** argv);

#endif
