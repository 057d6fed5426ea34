/* tools/svo_render/main.c - svo_render FILE.svo OUT.{png,exr} [options] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cones/cones.h"
#include "formats/image.h"
#include "photons/photons.h"
#include "probes/probes.h"
#include "render/compact.h"
#include "render/pipeline.h"
#include "render/render.h"
#include "tools/common/light.h"
#include "tools/common/tool.h"
#ifdef VX_HAVE_MPI
#include "tools/common/mpi.h"
#include "tools/svo_render/render_mpi.h"
#endif

typedef struct options {
    const char* in;
    const char* out;
    vx_render_desc r;
    const char* device;
    bool cpu, validate, verbose, list;
    uint64_t max_memory; /* --max-memory, 0: no limit */
    vx_render_scene_desc scene_desc; /* --layout, --gpu-budget (issue 18) */
    /* probe modes (CPU): gi, pathtrace, gi-indirect, pathtrace-indirect */
    bool probe_mode;
    vx_probe_render_desc p;
    const char* probes;
    vx_photon_desc photons; /* gi=photons: --photons, --radius (--photon-radius), --final-gather */
    /* the pass pipeline (colour mode on the GPU) */
    const char* passes;
    bool passes_given, show_given, spp_given;
    vx_frame_desc fd;
    const char* timings;
    uint32_t frames; /* --frames N: repeat the frame (timings) */
    double warm_up;  /* --warm-up S: the kernel back to back before the timed frames */
    /* an animation: --frame N, or --frames A..B (a sequence, OUT has a # run) */
    uint32_t frame_first, frame_last;
    bool sequence;
    int img_form; /* what the output gets: 0 RGB8, 1 one float channel, 3 RGB floats */
    vx_light lights[64]; /* --light */
    uint32_t light_count;
    bool sky_given, no_scene_lights, voxel_lights;
    bool load_models; /* --load models: the models one at a time into the compact layout (where it applies) */
    vx_sky sky; /* --sky's */
    const vx_light* frame_lights; /* what the frame uses (gather_lights) */
    uint32_t frame_light_count;
    vx_cone_desc cone; /* gi=cones (--cone-*) */
    /* --view2 EX,EY,EZ,TX,TY,TZ OUT2: a second view of the same scene (single-shader modes), timed as the first:
     * a scene that takes minutes to load (the 65536^3 helmet) is loaded once for both */
    vx_render_camera view2;
    const char* view2_out;
    uint32_t fly; /* --fly N: a fly-through of N frames after the image (single-shader modes), timed */
} options;

static const char* prog = "svo_render";

static options default_options(void) {
    options o = {0};
    o.load_models = true; /* --load models */
    o.r = vx_render_desc_defaults();
    o.fd = vx_frame_desc_defaults();
    o.passes = VX_PASS_LIST_DEFAULT;
    o.frames = 1;
    o.warm_up = 0.25;
    return o;
}

/* Writes the image as options say (img_form). */
static vx_result write_image(const options* o, const char* path, const vx_render_image* img, vx_error* err) {
    size_t npx = (size_t)img->width * img->height;
    vx_image_desc id = {.width = img->width, .height = img->height};
    void* buf = NULL;
    if (o->img_form == 1) {
        float* p = malloc(npx * 4);
        for (size_t i = 0; p && i < npx; i++) p[i] = img->pixels[4 * i];
        buf = p, id.channels = 1, id.type = VX_IMAGE_F32;
    } else if (o->img_form == 3) {
        float* p = malloc(npx * 12);
        for (size_t i = 0; p && i < npx; i++) memcpy(p + 3 * i, img->pixels + 4 * i, 12);
        buf = p, id.channels = 3, id.type = VX_IMAGE_F32;
    } else {
        uint8_t* p = malloc(npx * 3);
        for (size_t i = 0; p && i < 3 * npx; i++) {
            float v = img->pixels[4 * (i / 3) + i % 3];
            v = v < 0 ? 0 : (v > 1 ? 1 : v);
            p[i] = (uint8_t)lrintf(v * 255.0f);
        }
        buf = p, id.channels = 3, id.type = VX_IMAGE_U8;
    }
    id.pixels = buf;
    vx_result r = buf ? vx_image_write(path, &id, err) : vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    free(buf);
    return r;
}

/* OUT with its (last) run of # replaced by the zero-padded frame number. */
static void frame_path(const char* out, uint32_t frame, char* path, size_t size) {
    const char* end = strrchr(out, '#');
    const char* start = end;
    while (start > out && start[-1] == '#') start--;
    snprintf(path, size, "%.*s%0*u%s", (int)(start - out), out, (int)(end - start + 1), frame, end + 1);
}

_Noreturn static void usage(int status) {
    options d = default_options();
    vx_cone_desc cd = vx_cone_desc_defaults();
    FILE* f = status == 0 ? stdout : stderr;
    fprintf(f,
            "Usage: %s FILE.svo OUT.{png,exr} [options]\n"
            "       (also .ppm and .pfm; a build without OpenImageIO writes only these)\n"
            "\n"
            "Which: renders a .svo scene with the Vulkan compute tracer (BVH over instances,\n"
            "       sparse voxel octree per model) or with the CPU reference tracer.\n"
            "       8-bit modes write PNG, float modes (depth, normal) EXR.\n"
            "\n"
            "Options:\n"
            "  --mode M             color|albedo|normal|depth|instance|iterations (default: %s),\n"
            "                       or gi|gi-indirect|lightfield|lightfield-indirect (need --probes)\n"
            "                       and pathtrace|pathtrace-indirect\n"
            "                       (float radiance on the GPU, or the CPU with --cpu; EXR keeps the\n"
            "                       values, PNG clamps)\n"
            "  --passes LIST        the frame's passes in order (default: %s):\n"
            "                       gbuffer,dof,direct,gi=METHOD,ao,aa,tonemap (direct, gi, ao in any order);\n"
            "                       colour mode on the GPU; gi=probes|lightfield (need --probes), gi=pathtrace,\n"
            "                       gi=photons (progressive photon mapping: each sample, --spp or --passes-count, is a pass)\n"
            "                       or gi=cones (voxel cone tracing, --cone-* below)\n"
            "  --photons N          gi=photons: photons per pass (default: %u)\n"
            "  --final-gather N     gi=photons: final gather rays per pixel and sample (default: 0, none)\n"
            "  --radius R           gi=photons: first gather radius, world units (default: scene diagonal / 100;\n"
            "                       caustics a quarter; shrinking by alpha %.3g per pass); also --photon-radius\n"
            "  --passes-count K     gi=photons: progressive passes, the same as --spp K (each sample is a pass)\n"
            "  --show IMAGE         write an intermediate: final|albedo|normal|depth|direct|gi|ao|instance|material\n"
            "                       (default: final; normal, depth and material need .exr; direct: the irradiance,\n"
            "                       where the record is metal the radiance it reflects)\n"
            "  --ao-radius R        ambient occlusion ray length in world units (default: 4 cells)\n"
            "  --ao-rays N          ambient occlusion rays per pixel and sample (default: %u)\n"
            "  --aperture A         depth of field lens radius, world units (default: 1/100 of the scene diagonal)\n"
            "  --focus D            depth of field focus distance (default: the camera target's depth)\n"
            "  --exposure EV        tonemap exposure in stops (default: %g)\n"
            "  --separate-passes    never merge passes: by default gbuffer, direct and resolve run as one\n"
            "                       kernel when no ao, gi or --show image needs them apart\n"
            "  --timings FILE.csv   per-pass GPU times, one row per frame and pass\n"
            "  --frames N           render the frame N times (timings; default: 1)\n"
            "  --warm-up S          with --frames N on a GPU: the frame's kernel back to back for S seconds\n"
            "                       before the timed frames, so that they run at the GPU's working clock\n"
            "                       (default: %g; 0: none)\n"
            "  --frame N            an animation's frame N (default: 0)\n"
            "  --frames A..B        an animation's frames A to B, one image each: OUT holds a run of #\n"
            "                       replaced by the zero-padded frame number (render_####.png); the\n"
            "                       models go to the GPU once, the frames are traced in turn (GPU modes)\n"
            "  --probes FILE        light field probes from svo_bake (their sun, sky and light direction)\n"
            "  --bounces N          path tracer bounces (default: the probes' bounces + 1, else 2); a path's\n"
            "                       first 4 metal events and its glass events are not counted\n"
            "  --cone-res R         gi=cones: voxels along the scene's longest side (default: %u)\n"
            "  --cones N            gi=cones: diffuse cones per pixel (default: %u; at most %u)\n"
            "  --cone-aperture DEG  gi=cones: cone half angle (default: acos(1 - 1/cones), %.1f for %u)\n"
            "  --cone-bounces N     gi=cones: diffuse bounces kept in the volume (default: %u)\n"
            "  --cone-isotropic     gi=cones: one radiance per voxel instead of six directions\n"
            "  --cone-ao            gi=cones: the gi image is the cone ambient occlusion (--show gi)\n"
            "  --cone-half          gi=cones: diffuse cones at half resolution, upsampled by depth and normal\n"
            "  --cone-shadows       gi=cones: cone soft shadows; the gi pass brings the direct light (the pass\n"
            "                       list's direct is dropped)\n"
            "  --cone-sun-angle DEG gi=cones: the sun's angular diameter for --cone-shadows (default: %g)\n"
            "  --cone-no-specular   gi=cones: metal shaded as diffuse (no specular cones)\n"
            "  --seed S             path tracer seed (default: 0)\n"
            "  --threads N          CPU threads for the probe modes with --cpu (default: 2)\n"
            "  --max-memory SIZE    refuse a scene or probe file that needs more memory than SIZE to\n"
            "                       read (e.g. 512M, 4G; default: no limit; GPU memory not counted)\n"
            "  --load M             how the file is read: models (default) takes the models one at a time\n"
            "                       into the compact layout where the GPU single-shader modes render it in\n"
            "                       that layout, paged or not (the host holds the layout and a few models,\n"
            "                       not the scene), else reads the scene whole first; whole always reads it\n"
            "                       whole first\n"
            "  --layout L           the scene's layout on the GPU: auto (default), plain or compact. auto\n"
            "                       keeps the plain layout (.svo node words and a colour record per leaf,\n"
            "                       what every pass reads) unless it exceeds --gpu-budget, then the compact\n"
            "                       one (a colour-free geometry DAG, coded exact colours: 3-4x smaller,\n"
            "                       slower; no --lod); -v says which\n"
            "  --gpu-budget SIZE    GPU memory the plain layout may take for auto (default: 3/4 of the\n"
            "                       device's largest device-local heap); where the compact layout exceeds it\n"
            "                       too, it is paged: pages below --page-level loaded as the rays ask for\n"
            "                       them into a pool that the budget bounds, frames repeated until the view's\n"
            "                       pages are resident; pages that do not fit are drawn coarse (-v says so;\n"
            "                       a paged scene: the single-shader modes only)\n"
            "  --grid SIZE|off      GPU memory the grid walk may take (render/grid.h: the single-shader modes\n"
            "                       walk a model's grid of 8^3-cell bricks with empty-space distances instead\n"
            "                       of its octree, the same hits; grids for models of at most 13 levels, in\n"
            "                       model order; default 1G, on a CPU device too); off: none\n"
            "  --page-level L       the paged layout's page level (default: %u, pages of 512^3 cells)\n"
            "  --host-budget SIZE   paging from the file (--load models, the compact layout): the layout is\n"
            "                       paged whatever its size and the host holds its top and a cache of at\n"
            "                       most SIZE bytes of page images (least recently used out first), not\n"
            "                       every page image: a page the cache lacks is cut again from its model,\n"
            "                       read from the file when a frame needs it (default: 0, the pages cut from\n"
            "                       the whole layout in memory; -v gives the cache's counts)\n"
            "  --fly N              after the image, N frames of a fly-through around the scene (the camera\n"
            "                       at three distances), each timed; -v prints a line a frame (paging too)\n"
            "  --buffer-range SIZE  bytes one storage buffer may hold (default: the device's\n"
            "                       maxStorageBufferRange, 4G on NVIDIA); the compact attributes past it\n"
            "                       go to several buffers (single-shader modes only; -v says how many)\n"
            "  --size WxH           image size (default: %ux%u)\n"
            "  --spp N              samples per pixel (default: %u; at most 1024, the probe modes 2^24)\n"
            "  --camera EX,EY,EZ,TX,TY,TZ  eye and target in world units (default: frame the scene bounds)\n"
            "  --view2 EX,EY,EZ,TX,TY,TZ OUT2  then a second view (eye, target) of the same scene into OUT2,\n"
            "                       with the same --frames (single-shader modes; the scene is loaded once)\n"
            "  --up X,Y,Z           up vector (default: 0,0,1)\n"
            "  --fov DEG            vertical field of view (default: %g)\n"
            "  --ortho [H]          orthographic, view height H (default: frame the bounds)\n"
            "  --lod [PIXELS]       stop where a voxel is smaller than PIXELS pixels (default: off, %g)\n"
            "  --light X,Y,Z        direction towards the light (default: %g,%g,%g)\n"
            "  --light SPEC         add a light (repeatable; with any light, the file's or these, the frame\n"
            "                       uses radiometric units):\n"
            "%s"
            "  --no-scene-lights    ignore the lights and the sky stored in the file (LGHT); by default the\n"
            "                       colour mode on the GPU and --mode pathtrace use them, the file's sky of\n"
            "                       any type (constant, gradient, environment map read through OpenImageIO)\n"
            "                       in the radiometric model (with lights or a gi pass): background, sky\n"
            "                       light of the direct pass, gi=pathtrace, gi=cones and gi=photons\n"
            "  --voxel-lights       also light with the file's emissive voxels: one sphere light per cluster\n"
            "                       (vx_svo_emissive_lights; off by default: with any light the frame uses\n"
            "                       the radiometric model, without the colour model's sun and ambient)\n"
            "  --sky SPEC           the sky, replacing the file's (default: the file's sky, else a uniform\n"
            "                       %g,%g,%g); with lights, a gi pass or --mode pathtrace:\n"
            "%s"
            "  --light-culling M    auto|brute|tiled|clustered: how the direct pass finds each pixel's\n"
            "                       lights (default: %s: brute force up to %d lights, else tiled)\n"
            "  --shadow-lights N    lights per pixel with a shadow ray, the strongest (0..%d, 0: none;\n"
            "                       default: %d); the others shine unshadowed\n"
            "  --light-cutoff E     irradiance where a light without a range ends (culling; default:\n"
            "                       pi/1024 * 2^-exposure, a quarter of an 8-bit step on white)\n"
            "  --ambient A          sky light share (default: %g)\n"
            "  --device N|NAME|gpu:K  Vulkan device: the N-th, the first named like NAME, or the (K mod GPUs)-th\n"
            "                       GPU (default: a discrete GPU, else any; under MPI gpu:L, L the rank's place on\n"
            "                       its host)\n"
            "  --list-devices       print the Vulkan devices and exit\n"
            "  --validate           enable the Vulkan validation layer\n"
            "  --cpu                use the CPU reference tracer\n"
            "  -v                   print the effective options as a command line and the per-pass times\n"
            "  -h, --help           this help;  -version: versions\n"
            "\n"
            "Examples:\n"
            "  %s scene.svo out.png\n"
            "  %s scene.svo depth.exr --mode depth --size 1280x720\n"
            "  %s scene.svo top.png --camera 64,64,300,64,64,0 --up 0,1,0 --ortho\n"
            "  %s scene.svo gi.exr --probes scene.probes --mode gi\n"
            "  %s walk.svo walk_####.png --frames 0..23\n",
            prog, vx_render_mode_name(d.r.mode), d.passes, vx_photon_desc_defaults().photons,
            vx_photon_desc_defaults().alpha, d.fd.ao_rays, d.fd.exposure, d.warm_up, cd.res,
            cd.cones, VX_CONE_CONES_MAX, cd.aperture, cd.cones, cd.bounces, cd.sun_angle, VX_RENDER_FRAME_LEVELS, d.r.width,
            d.r.height, d.r.spp,
            d.r.camera.fov, d.r.lod_pixels, d.r.light_dir[0], d.r.light_dir[1], d.r.light_dir[2], vx_tool_light_syntax, d.fd.sky[0], d.fd.sky[1], d.fd.sky[2],
            vx_tool_sky_syntax, vx_light_culling_name(d.fd.light_culling), VX_LIGHT_CULLING_AUTO_MAX, VX_SHADOW_LIGHTS_MAX,
            (int)d.fd.shadow_lights, d.r.ambient, prog, prog, prog, prog, prog);
    exit(status);
}

#define usage_error(...) vx_tool_usage_error(usage, __VA_ARGS__)

#define parse_vec vx_tool_parse_vec

static bool parse_uint(const char* s, uint32_t* out) {
    char* end;
    unsigned long v = strtoul(s, &end, 10);
    if (end == s || *end || v > 1000000) return false;
    *out = (uint32_t)v;
    return true;
}

static bool is_number(const char* s) {
    char* end;
    strtod(s, &end);
    return end != s && *end == 0;
}

static void list_cb(void* user, uint32_t i, const char* name, const char* type) {
    (void)user;
    printf("%u: %s (%s)\n", i, name, type);
}

static void log_cb(void* user, vx_log_level level, const char* id, const char* msg) {
    (void)user;
    if (level >= VX_LOG_WARN || !strcmp(id, "gpu.memory")) fprintf(stderr, "%s: %s: %s\n", prog, id, msg);
}

static const char* ext_of(const char* p) {
    const char* d = strrchr(p, '.');
    return d ? d + 1 : "";
}

/* The frame's lights: the file's (unless --no-scene-lights), then those of
 * its emissive voxels (--voxel-lights), then --light's. *out is malloc'ed. */
static vx_result gather_lights(const options* o, const vx_svo_scene* scene, vx_light** out, uint32_t* count,
                               uint32_t* from_voxels, vx_error* err) {
    vx_light* vox = NULL;
    uint32_t nv = 0, ns = o->no_scene_lights ? 0 : scene->light_count;
    if (o->voxel_lights && !o->no_scene_lights) {
        vx_result r = vx_svo_emissive_lights(scene, NULL, &vox, &nv, err);
        if (r) return r;
    }
    size_t n = (size_t)ns + nv + o->light_count;
    vx_light* all = (vx_light*)malloc((n ? n : 1) * sizeof *all);
    if (!all) {
        vx_free(NULL, vox);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %zu lights", n);
    }
    if (ns) memcpy(all, scene->lights, ns * sizeof *all);
    if (nv) memcpy(all + ns, vox, nv * sizeof *all);
    if (o->light_count) memcpy(all + ns + nv, o->lights, o->light_count * sizeof *all);
    vx_free(NULL, vox);
    *out = all;
    *count = (uint32_t)n;
    *from_voxels = nv;
    return VX_OK;
}

static int cmp_double(const void* a, const void* b) {
    double x = *(const double*)a, y = *(const double*)b;
    return (x > y) - (x < y);
}

/* Whether the pass pipeline cannot render rs (its kernels bind the whole
 * compact layout with its attributes in one buffer, and trace in float): why,
 * the error for --passes/--show/--timings; *note, -v's line for the
 * single-shader colour mode that renders it instead. */
static bool passes_refuse(vx_render_scene* rs, const vx_render_layout_info* li, char* why, size_t n,
                          const char** note) {
    bool compact = li->layout == VX_RENDER_LAYOUT_COMPACT;
    if (compact && li->attr_parts > 1) {
        snprintf(why, n, "the compact attributes are in %u storage buffers: --passes/--show/--timings need them in one",
                 li->attr_parts);
        *note = "the single-shader colour mode renders this scene";
    } else if (compact && li->pages) {
        snprintf(why, n, "the scene is in the paged compact layout: --passes/--show/--timings need all of it on the "
                         "GPU (a larger --gpu-budget, or --layout plain)");
        *note = "paged compact layout: the single-shader colour mode renders this scene";
    } else if (vx_render_scene_precise(rs)) {
        snprintf(why, n, "the scene has models deeper than %u levels: --passes/--show/--timings need float tracing",
                 VX_RENDER_PRECISE_DEPTH);
        *note = "deep models: the float64 single-shader colour mode renders this scene";
    } else {
        return false;
    }
    return true;
}

/* The colour mode through the pass pipeline: options.frames frames (the last
 * one is kept), per-pass times printed with -v and written to --timings. */
static vx_result render_passes(options* o, vx_render_scene* rs, const vx_svo_scene* scene,
                               const vx_pass_list* passes, const vx_probe_set* probes, vx_render_image* img,
                               vx_error* err) {
    vx_frame_renderer* fr = NULL;
    vx_result r = vx_frame_renderer_create(rs, scene, &fr, err);
    if (r) return r;
    vx_gi_method gm = {0};
    vx_probe_gi* pgi = NULL;
    vx_photon_gi* phg = NULL;
    vx_cone_gi* cgi = NULL;
    if (vx_pass_list_has(passes, VX_PASS_GI) && !strcmp(passes->gi, "photons")) {
        vx_photon_desc pd = o->photons; /* carries the frame's lights; the probes give sun and sky */
        pd.seed = o->p.seed, pd.lights = o->frame_lights, pd.light_count = o->frame_light_count;
        pd.sky_dir = o->fd.sky_dir, pd.sky_map = o->fd.sky_map; /* the file's sky (NULL with --sky) */
        memcpy(pd.light_dir, o->r.light_dir, sizeof pd.light_dir);
        if ((r = vx_photon_gi_create(rs, scene, probes, &pd, &gm, &phg, err))) goto done;
    } else if (vx_pass_list_has(passes, VX_PASS_GI) && !strcmp(passes->gi, "cones")) {
        /* the frame's sun direction, sky and lights are injected into the volume */
        vx_cone_desc cd = o->cone;
        memcpy(cd.light_dir, o->r.light_dir, sizeof cd.light_dir);
        if (o->sky_given) memcpy(cd.sky, o->fd.sky, sizeof cd.sky);
        cd.sky_dir = o->fd.sky_dir, cd.sky_map = o->fd.sky_map; /* the file's sky (NULL with --sky) */
        cd.lights = o->frame_lights, cd.light_count = o->frame_light_count;
        if ((r = vx_cone_gi_create(rs, scene, &cd, &gm, &cgi, err))) goto done;
        if (o->verbose) {
            vx_cone_info ci;
            vx_cone_gi_info(cgi, &ci);
            printf("cones: %u levels, level 0 %ux%ux%u of %g, %u voxels with geometry, %.1f MB; GPU ms: voxelize %.3f, "
                   "inject %.3f, filter %.3f\n", ci.levels, ci.dims[0][0], ci.dims[0][1], ci.dims[0][2], ci.voxel,
                   ci.surface_voxels, ci.bytes / 1e6, ci.voxelize_ms, ci.inject_ms, ci.filter_ms);
        }
    } else if (vx_pass_list_has(passes, VX_PASS_GI)) {
        vx_probe_render_desc pd = o->p;
        pd.base = &o->r;
        /* gi=pathtrace carries the frame's lights along its paths; the probe
         * methods' light is the bake's, and the direct pass shades the lights */
        pd.lights = o->frame_lights, pd.light_count = o->frame_light_count;
        if ((r = vx_probe_gi_create(rs, scene, probes, passes->gi, &pd, &gm, &pgi, err))) goto done;
    }
    vx_frame_desc fd = o->fd;
    fd.base = o->r;
    if (!o->spp_given) fd.base.spp = 0; /* the pipeline's default: 1, or 8 with aa or dof */
    fd.passes = passes;
    fd.gi = pgi || phg || cgi ? &gm : NULL;
    fd.lights = o->frame_lights, fd.light_count = o->frame_light_count;
    FILE* csv = NULL;
    if (o->timings) {
        csv = fopen(o->timings, "w");
        if (!csv) {
            r = vx_fail(err, VX_ERR_IO, VX_NO_OFFSET, "%s: cannot open for writing", o->timings);
            goto done;
        }
        fprintf(csv, "frame,pass,ms,dispatches\n");
    }
    vx_frame_result res = {0};
    for (uint32_t k = 0; k < o->frames && !r; k++) {
        vx_render_image_free(&res.image);
        if ((r = vx_frame_render(fr, &fd, &res, err))) break;
        for (uint32_t t = 0; csv && t < res.timing_count; t++)
            fprintf(csv, "%u,%s,%.6f,%u\n", k, res.timings[t].name, res.timings[t].ms, res.timings[t].dispatches);
        if (csv) fprintf(csv, "%u,frame,%.6f,0\n", k, res.frame_ms);
    }
    if (csv && fclose(csv) && !r) r = vx_fail(err, VX_ERR_IO, VX_NO_OFFSET, "%s: write failed", o->timings);
    if (!r && o->verbose) {
        printf("%-24s %10s %7s %10s\n", "pass", "ms", "share", "dispatches");
        double sum = 0;
        for (uint32_t t = 0; t < res.timing_count; t++) sum += res.timings[t].ms;
        for (uint32_t t = 0; t < res.timing_count; t++)
            printf("%-24s %10.3f %6.1f%% %10u\n", res.timings[t].name, res.timings[t].ms,
                   sum > 0 ? 100 * res.timings[t].ms / sum : 0.0, res.timings[t].dispatches);
        printf("%-24s %10.3f %6.1f%%  (GPU, first pass start to last pass end)\n", "frame", res.frame_ms,
               sum > 0 ? 100 * res.frame_ms / sum : 0.0);
    }
    if (!r) *img = res.image;
    else vx_render_image_free(&res.image);
done:
    vx_probe_gi_destroy(pgi);
    vx_photon_gi_destroy(phg);
    vx_cone_gi_destroy(cgi);
    vx_frame_renderer_destroy(fr);
    return r;
}

/* --frames A..B: the scene's models are on the GPU once; each frame swaps
 * the instance tables and BVH (vx_render_scene_set_frame) and is traced and
 * written in turn. The camera frames the whole animation. */
static vx_result render_sequence(options* o, vx_render_scene* rs, const vx_svo_scene* scene, bool pipeline,
                                 const vx_pass_list* passes, const vx_probe_set* probes, vx_error* err) {
    vx_result r = VX_OK;
    double t0 = vx_time_now(), gpu = 0;
    for (uint32_t f = o->frame_first; f <= o->frame_last && !r; f++) {
        double ts = vx_time_now();
        if (f != o->frame_first && (r = vx_render_scene_set_frame(rs, scene, f, err))) break;
        double t_switch = vx_time_now() - ts;
        vx_render_image img = {0};
        r = pipeline ? render_passes(o, rs, scene, passes, probes, &img, err) : vx_render_frame(rs, &o->r, &img, err);
        char path[4096];
        frame_path(o->out, f, path, sizeof path);
        if (!r) r = write_image(o, path, &img, err);
        if (!r && o->verbose)
            printf("frame %u: switch %.3f ms, trace %.3f ms (GPU) -> %s\n", f, t_switch * 1e3, img.gpu_seconds * 1e3, path);
        gpu += img.gpu_seconds;
        vx_render_image_free(&img);
    }
    if (!r)
        printf("wrote frames %u..%u (%s): %.3f s, %.3f ms GPU per frame\n", o->frame_first, o->frame_last, o->out,
               vx_time_now() - t0, gpu * 1e3 / (o->frame_last - o->frame_first + 1));
    return r;
}

/* -v: the file source's host cache (--host-budget) */
static void print_host_cache(const vx_render_page_stats* ps) {
    printf("paging from the file: host cache %.3f MB of %.3f MB (peak %.3f MB); %llu pages cut from the file (%llu "
           "model reads), %llu of them cut ahead, %llu from the cache, %llu evicted from it; %llu moved pages read back from "
           "the pool\n",
           ps->host_bytes / 1e6, ps->host_budget / 1e6, ps->host_peak_bytes / 1e6, (unsigned long long)ps->file_pages,
           (unsigned long long)ps->file_models, (unsigned long long)ps->file_prefetched, (unsigned long long)ps->host_hits,
           (unsigned long long)ps->host_evictions, (unsigned long long)ps->moved_from_pool);
}

/* --fly N: frames of a camera around the scene's centre at three distances,
 * looking at points near it (compact_bench --fly's path), each timed: the
 * wall time of vx_render_frame (a paged scene's page service, the trace,
 * the image read back) and the GPU's. */
static vx_result fly_frames(const options* o, vx_render_scene* rs, const vx_svo_scene* scene, bool paged, vx_error* err) {
    double lo[3], hi[3];
    vx_svo_scene_world_bounds(scene, lo, hi);
    double* ms = calloc(2 * (size_t)o->fly, sizeof *ms);
    if (!ms) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    double* gpu_ms = ms + o->fly;
    vx_result r = VX_OK;
    uint64_t coarse = 0;
    for (uint32_t f = 0; !r && f < o->fly; f++) {
        vx_render_desc d = o->r;
        double u = (double)f / o->fly, a = 6.2831853 * u, dist = 0.35 + 0.5 * (0.5 + 0.5 * cos(3 * a));
        d.camera.set = true;
        d.want_hits = false;
        for (int k = 0; k < 3; k++) {
            double mid = 0.5 * (lo[k] + hi[k]), ext = hi[k] - lo[k];
            d.camera.target[k] = mid + 0.1 * ext * sin(a + k);
            d.camera.eye[k] = mid + dist * ext * (k == 1 ? 0.4 : (k == 0 ? cos(a) : sin(a)));
        }
        vx_render_image img = {0};
        double t0 = vx_time_now();
        r = vx_render_frame(rs, &d, &img, err);
        ms[f] = (vx_time_now() - t0) * 1e3, gpu_ms[f] = img.gpu_seconds * 1e3;
        vx_render_image_free(&img);
        vx_render_page_stats ps = {0};
        vx_render_scene_page_stats(rs, &ps);
        coarse += ps.coarse;
        if (!r && o->verbose && paged)
            printf("fly %u: %.2f ms (%.3f ms GPU); pages: %u coarse, %u loaded, %u evicted, %u refused, %u resident, "
                   "%u moved; host cache %.3f MB, %llu cut from the file so far\n",
                   f, ms[f], gpu_ms[f], ps.coarse, ps.loaded, ps.evicted, ps.refused, ps.resident, ps.moved,
                   ps.host_bytes / 1e6, (unsigned long long)ps.file_pages);
        else if (!r && o->verbose)
            printf("fly %u: %.2f ms (%.3f ms GPU)\n", f, ms[f], gpu_ms[f]);
        if (o->verbose) fflush(stdout); /* a run stopped by a time limit keeps its lines */
    }
    if (!r) {
        qsort(ms, o->fly, sizeof *ms, cmp_double);
        qsort(gpu_ms, o->fly, sizeof *gpu_ms, cmp_double);
        printf("fly-through: %u frames, median %.2f ms a frame (min %.2f, max %.2f; GPU median %.3f ms)", o->fly,
               ms[o->fly / 2], ms[0], ms[o->fly - 1], gpu_ms[o->fly / 2]);
        if (paged) printf(", %llu pages drawn coarse in all", (unsigned long long)coarse);
        printf(", peak host memory %s\n", vx_tool_bytes(vx_peak_rss()));
        if (paged && o->verbose) {
            vx_render_page_stats ps = {0};
            vx_render_scene_page_stats(rs, &ps);
            if (ps.from_file) print_host_cache(&ps);
        }
    }
    free(ms);
    return r;
}

/* --frames N: the same frame again, for its times (the last image is left in *img). */
/* -v: the share of pixels that hit geometry, from a frame rendered with its hits */
static void print_hit_share(const vx_render_image* img) {
    if (!img->hits) return;
    size_t hit = 0, n = (size_t)img->width * img->height;
    for (size_t i = 0; i < n; i++) hit += img->hits[i].instance != VX_RENDER_NO_HIT;
    printf("view: %.1f%% of pixels hit geometry\n", n ? 100.0 * (double)hit / (double)n : 0.0);
}

static vx_result timed_frames(const options* o, vx_render_scene* rs, bool warm, vx_render_image* img, vx_error* err) {
    if (o->frames <= 1) return VX_OK;
    double* gpu_ms = calloc(o->frames, 2 * sizeof *gpu_ms);
    if (!gpu_ms) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    double* wall_ms = gpu_ms + o->frames;
    vx_result r = VX_OK;
    gpu_ms[0] = img->gpu_seconds * 1e3, wall_ms[0] = 0;
    /* The kernel back to back first (a GPU, not a CPU device): the H200's SM clock falls from 1980 to
     * 345 MHz within 2-3 s of idleness and the frames alone (a few percent of the time busy, the rest
     * reading back) did not raise it: 4.7x the frame time after a load that left the device idle for
     * seconds; 0.2 s of this brought the clock and the times back (docs/PERFORMANCE.md, issue 18, load2) */
    if (warm && o->warm_up > 0) {
        double wms = 0, tw = vx_time_now();
        r = vx_render_scene_warm_up(rs, &o->r, o->warm_up, &wms, err);
        if (!r && o->verbose)
            printf("warm-up: the frame's kernel back to back for %.3f s (its last frames %.3f ms GPU)\n",
                   vx_time_now() - tw, wms);
    }
    uint32_t n = 1;
    for (; !r && n < o->frames; n++) {
        vx_render_image_free(img);
        double tf = vx_time_now();
        r = vx_render_frame(rs, &o->r, img, err);
        wall_ms[n] = (vx_time_now() - tf) * 1e3, gpu_ms[n] = img->gpu_seconds * 1e3;
    }
    if (!r) {
        /* frame 0 warms caches and compiles: the medians are of frames 1..N-1 */
        qsort(gpu_ms + 1, n - 1, sizeof *gpu_ms, cmp_double);
        qsort(wall_ms + 1, n - 1, sizeof *wall_ms, cmp_double);
        printf("frames: %u after the first: GPU ms median %.3f (min %.3f, max %.3f); wall ms a frame "
               "(trace and read back) median %.3f; first frame %.3f ms GPU\n",
               n - 1, gpu_ms[1 + (n - 1) / 2], gpu_ms[1], gpu_ms[n - 1], wall_ms[1 + (n - 1) / 2], gpu_ms[0]);
    }
    free(gpu_ms);
    return r;
}

int main(int argc, char** argv) {
#ifdef VX_HAVE_MPI
    vx_tool_timeline tl; /* under mpirun: this rank's start-up and end, printed with -v */
    vx_tool_timeline_start(&tl);
    render_mpi_end mpi_end = {0};
#endif
    vx_tool_init(argc, argv);
    prog = vx_tool_name;
    options o = default_options();
    const char* pos[2];
    int npos = 0;
    for (int i = 1; i < argc; i++) {
        const char* a = argv[i];
/* the option's argument, argv[i] after it (vx_tool_arg: a usage error where none is left) */
#define ARG() vx_tool_arg(argc, argv, &i, usage)
        if (!strcmp(a, "-h") || !strcmp(a, "-help") || !strcmp(a, "--help")) usage(0);
        else if (!strcmp(a, "-version") || !strcmp(a, "--version")) {
            printf("%s %s (svo format %u, max octree depth %u)\n", prog, VX_VERSION_STRING, VX_SVO_FORMAT_VERSION,
                   VX_RENDER_MAX_DEPTH);
            return 0;
        } else if (!strcmp(a, "--mode")) {
            const char* m = ARG();
            o.probe_mode = false;
            if (!vx_render_mode_parse(m, &o.r.mode)) {
                if (!vx_probe_render_mode_parse(m, &o.p.mode)) usage_error("unknown mode '%s'", m);
                o.probe_mode = true;
            }
        } else if (!strcmp(a, "--probes")) {
            o.probes = ARG();
        } else if (!strcmp(a, "--photons")) {
            if (!parse_uint(ARG(), &o.photons.photons) || !o.photons.photons || o.photons.photons > (1u << 26))
                usage_error("bad photon count '%s' (1..2^26)", argv[i]);
        } else if (!strcmp(a, "--final-gather")) {
            if (!parse_uint(ARG(), &o.photons.final_gather) || o.photons.final_gather > 1024)
                usage_error("bad final gather rays '%s' (0..1024)", argv[i]);
        } else if (!strcmp(a, "--radius") || !strcmp(a, "--photon-radius")) { /* the name, the old one */
            char* end;
            o.photons.radius = strtod(ARG(), &end);
            if (*end || !(o.photons.radius > 0) || !isfinite(o.photons.radius))
                usage_error("bad %s '%s'", a, argv[i]);
        } else if (!strcmp(a, "--bounces")) {
            if (!parse_uint(ARG(), &o.p.bounces) || !o.p.bounces || o.p.bounces > 64)
                usage_error("bad bounces '%s' (1..64)", argv[i]);
        } else if (!strcmp(a, "--cone-res")) {
            if (!parse_uint(ARG(), &o.cone.res) || o.cone.res < 2 || o.cone.res > VX_CONE_RES_MAX)
                usage_error("bad cone resolution '%s' (2..%u)", argv[i], VX_CONE_RES_MAX);
        } else if (!strcmp(a, "--cones")) {
            if (!parse_uint(ARG(), &o.cone.cones) || !o.cone.cones || o.cone.cones > VX_CONE_CONES_MAX)
                usage_error("bad cone count '%s' (1..%u)", argv[i], VX_CONE_CONES_MAX);
        } else if (!strcmp(a, "--cone-aperture")) {
            if (!parse_vec(ARG(), &o.cone.aperture, 1) || !(o.cone.aperture > 0 && o.cone.aperture < 89))
                usage_error("bad cone aperture '%s' (degrees, above 0 and below 89)", argv[i]);
        } else if (!strcmp(a, "--cone-bounces")) {
            if (!parse_uint(ARG(), &o.cone.bounces) || !o.cone.bounces || o.cone.bounces > 4)
                usage_error("bad cone bounces '%s' (1..4)", argv[i]);
        } else if (!strcmp(a, "--cone-isotropic")) {
            o.cone.isotropic = true;
        } else if (!strcmp(a, "--cone-ao")) {
            o.cone.output = VX_CONE_OUTPUT_AO;
        } else if (!strcmp(a, "--cone-half")) {
            o.cone.half_res = true;
        } else if (!strcmp(a, "--cone-shadows")) {
            o.cone.shadows = true;
        } else if (!strcmp(a, "--cone-no-specular")) {
            o.cone.no_specular = true;
        } else if (!strcmp(a, "--cone-sun-angle")) {
            if (!parse_vec(ARG(), &o.cone.sun_angle, 1) || !(o.cone.sun_angle > 0 && o.cone.sun_angle < 30))
                usage_error("bad sun angle '%s' (degrees, above 0 and below 30)", argv[i]);
        } else if (!strcmp(a, "--seed")) {
            uint32_t sd;
            if (!parse_uint(ARG(), &sd)) usage_error("bad seed '%s'", argv[i]);
            o.p.seed = sd;
            o.fd.seed = sd;
        } else if (!strcmp(a, "--threads")) {
            if (!parse_uint(ARG(), &o.p.threads) || !o.p.threads || o.p.threads > 64)
                usage_error("bad threads '%s' (1..64)", argv[i]);
        } else if (!strcmp(a, "--load")) {
            const char* l = ARG();
            if (!strcmp(l, "whole")) o.load_models = false;
            else if (!strcmp(l, "models")) o.load_models = true;
            else usage_error("bad --load '%s' (models or whole)", l);
        } else if (!strcmp(a, "--layout")) {
            const char* l = ARG();
            if (!strcmp(l, "auto")) o.scene_desc.layout = VX_RENDER_LAYOUT_AUTO;
            else if (!strcmp(l, "plain")) o.scene_desc.layout = VX_RENDER_LAYOUT_PLAIN;
            else if (!strcmp(l, "compact")) o.scene_desc.layout = VX_RENDER_LAYOUT_COMPACT;
            else usage_error("bad --layout '%s' (auto, plain or compact)", l);
        } else if (!strcmp(a, "--page-level")) {
            if (!parse_uint(ARG(), &o.scene_desc.page_level) || o.scene_desc.page_level < 3 ||
                o.scene_desc.page_level > 31)
                usage_error("bad --page-level '%s' (3..31)", argv[i]);
        } else if (!strcmp(a, "--buffer-range")) {
            if (!vx_tool_parse_bytes(ARG(), &o.scene_desc.max_buffer_range) || o.scene_desc.max_buffer_range < 64)
                usage_error("bad --buffer-range value '%s' (bytes, at least 64, e.g. 1M)", argv[i]);
        } else if (!strcmp(a, "--gpu-budget")) {
            if (!vx_tool_parse_bytes(ARG(), &o.scene_desc.memory_budget) || !o.scene_desc.memory_budget)
                usage_error("bad --gpu-budget value '%s' (bytes, e.g. 512M or 4G)", argv[i]);
        } else if (!strcmp(a, "--grid")) {
            const char* g = ARG();
            if (!strcmp(g, "off")) o.scene_desc.grid_budget = VX_RENDER_NO_GRID;
            else if (!vx_tool_parse_bytes(g, &o.scene_desc.grid_budget) || o.scene_desc.grid_budget < 64)
                usage_error("bad --grid value '%s' (bytes, at least 64, e.g. 256M; or off)", g);
        } else if (!strcmp(a, "--host-budget")) {
            if (!vx_tool_parse_bytes(ARG(), &o.scene_desc.host_budget) || !o.scene_desc.host_budget)
                usage_error("bad --host-budget value '%s' (bytes, e.g. 64M)", argv[i]);
        } else if (!strcmp(a, "--fly")) {
            if (!parse_uint(ARG(), &o.fly) || !o.fly || o.fly > 100000) usage_error("bad --fly '%s' (frames)", argv[i]);
        } else if (!strcmp(a, "--max-memory")) {
            if (!vx_tool_parse_bytes(ARG(), &o.max_memory) || !o.max_memory)
                usage_error("bad --max-memory value '%s' (bytes, e.g. 512M or 4G)", argv[i]);
        } else if (!strcmp(a, "--size")) {
            unsigned w, h;
            char c;
            if (sscanf(ARG(), "%ux%u%c", &w, &h, &c) != 2 || !w || !h || w > 16384 || h > 16384)
                usage_error("bad size '%s' (WxH, at most 16384 each)", argv[i]);
            o.r.width = w, o.r.height = h;
        } else if (!strcmp(a, "--spp") || !strcmp(a, "--passes-count")) { /* gi=photons: one pass a sample */
            if (!parse_uint(ARG(), &o.r.spp) || !o.r.spp || o.r.spp > (1u << 24)) usage_error("bad %s '%s'", a, argv[i]);
            o.spp_given = true;
        } else if (!strcmp(a, "--camera")) {
            double v[6];
            if (!parse_vec(ARG(), v, 6)) usage_error("bad camera '%s' (EX,EY,EZ,TX,TY,TZ)", argv[i]);
            o.r.camera.set = true;
            memcpy(o.r.camera.eye, v, sizeof o.r.camera.eye);
            memcpy(o.r.camera.target, v + 3, sizeof o.r.camera.target);
        } else if (!strcmp(a, "--view2")) {
            if (i + 2 >= argc) usage_error("%s needs EX,EY,EZ,TX,TY,TZ and an output", a);
            double v[6];
            if (!parse_vec(argv[++i], v, 6)) usage_error("bad view '%s' (EX,EY,EZ,TX,TY,TZ)", argv[i]);
            o.view2.set = true;
            memcpy(o.view2.eye, v, sizeof o.view2.eye);
            memcpy(o.view2.target, v + 3, sizeof o.view2.target);
            o.view2_out = argv[++i];
        } else if (!strcmp(a, "--up")) {
            if (!parse_vec(ARG(), o.r.camera.up, 3)) usage_error("bad up vector '%s'", argv[i]);
        } else if (!strcmp(a, "--light")) {
            if (strchr(ARG(), ':')) {
                if (o.light_count >= 64) usage_error("%s", "at most 64 --light lights");
                char why[160];
                if (!vx_tool_parse_light(argv[i], &o.lights[o.light_count], why, sizeof why))
                    usage_error("bad light '%s': %s", argv[i], why);
                vx_error lerr = {0};
                if (vx_light_validate(&o.lights[o.light_count], o.light_count, &lerr))
                    usage_error("--light %s: %s", argv[i], lerr.msg);
                o.light_count++;
            } else if (!parse_vec(argv[i], o.r.light_dir, 3)) {
                usage_error("bad light direction '%s'", argv[i]);
            }
        } else if (!strcmp(a, "--no-scene-lights")) {
            o.no_scene_lights = true;
        } else if (!strcmp(a, "--voxel-lights")) {
            o.voxel_lights = true;
        } else if (!strcmp(a, "--sky")) {
            char why[256];
            if (!vx_tool_parse_sky(ARG(), false, &o.sky, why, sizeof why)) usage_error("bad --sky '%s': %s", argv[i], why);
            if (o.sky.type == VX_SKY_CONSTANT) memcpy(o.fd.sky, o.sky.color, sizeof o.fd.sky);
            o.sky_given = true;
        } else if (!strcmp(a, "--light-culling")) {
            if (!vx_light_culling_parse(ARG(), &o.fd.light_culling))
                usage_error("bad light culling '%s' (auto, brute, tiled, clustered)", argv[i]);
        } else if (!strcmp(a, "--shadow-lights")) {
            uint32_t n;
            if (!parse_uint(ARG(), &n) || n > VX_SHADOW_LIGHTS_MAX)
                usage_error("bad shadow light count '%s' (0..%d)", argv[i], VX_SHADOW_LIGHTS_MAX);
            o.fd.shadow_lights = n ? (int32_t)n : -1;
        } else if (!strcmp(a, "--light-cutoff")) {
            if (!parse_vec(ARG(), &o.fd.light_cutoff, 1) || !(o.fd.light_cutoff > 0 && o.fd.light_cutoff < 1e30))
                usage_error("bad light cut-off '%s' (irradiance > 0)", argv[i]);
        } else if (!strcmp(a, "--fov")) {
            if (!parse_vec(ARG(), &o.r.camera.fov, 1) || !(o.r.camera.fov > 0 && o.r.camera.fov < 180))
                usage_error("bad fov '%s' (degrees in (0,180))", argv[i]);
        } else if (!strcmp(a, "--ambient")) {
            if (!parse_vec(ARG(), &o.r.ambient, 1) || !(o.r.ambient >= 0 && o.r.ambient <= 1))
                usage_error("bad ambient '%s' (0..1)", argv[i]);
        } else if (!strcmp(a, "--ortho")) {
            o.r.camera.ortho = true;
            if (i + 1 < argc && is_number(argv[i + 1])) {
                if (!parse_vec(argv[++i], &o.r.camera.ortho_height, 1) || !(o.r.camera.ortho_height > 0))
                    usage_error("bad ortho height '%s'", argv[i]);
            }
        } else if (!strcmp(a, "--lod")) {
            o.r.lod = true;
            if (i + 1 < argc && is_number(argv[i + 1])) {
                if (!parse_vec(argv[++i], &o.r.lod_pixels, 1) || !(o.r.lod_pixels > 0))
                    usage_error("bad lod pixels '%s'", argv[i]);
            }
        } else if (!strcmp(a, "--passes")) {
            o.passes = ARG();
            o.passes_given = true;
        } else if (!strcmp(a, "--show")) {
            if (!vx_show_parse(ARG(), &o.fd.show)) usage_error("unknown image '%s' for --show", argv[i]);
            o.show_given = true;
        } else if (!strcmp(a, "--ao-radius")) {
            if (!parse_vec(ARG(), &o.fd.ao_radius, 1) || !(o.fd.ao_radius > 0 && o.fd.ao_radius < 1e30))
                usage_error("bad ao radius '%s'", argv[i]);
        } else if (!strcmp(a, "--ao-rays")) {
            if (!parse_uint(ARG(), &o.fd.ao_rays) || !o.fd.ao_rays || o.fd.ao_rays > 4096)
                usage_error("bad ao rays '%s' (1..4096)", argv[i]);
        } else if (!strcmp(a, "--aperture")) {
            if (!parse_vec(ARG(), &o.fd.aperture, 1) || !(o.fd.aperture > 0 && o.fd.aperture < 1e30))
                usage_error("bad aperture '%s'", argv[i]);
        } else if (!strcmp(a, "--focus")) {
            if (!parse_vec(ARG(), &o.fd.focus, 1) || !(o.fd.focus > 0 && o.fd.focus < 1e30))
                usage_error("bad focus distance '%s'", argv[i]);
        } else if (!strcmp(a, "--exposure")) {
            if (!parse_vec(ARG(), &o.fd.exposure, 1) || !(fabs(o.fd.exposure) <= 64))
                usage_error("bad exposure '%s' (stops, -64..64)", argv[i]);
        } else if (!strcmp(a, "--separate-passes")) {
            o.fd.separate_passes = true;
            o.passes_given = true;
        } else if (!strcmp(a, "--timings")) {
            o.timings = ARG();
        } else if (!strcmp(a, "--frames") && i + 1 < argc && strstr(argv[i + 1], "..")) {
            const char* v = argv[++i];
            char a0[16] = {0};
            size_t n = (size_t)(strstr(v, "..") - v);
            if (n >= sizeof a0 || (memcpy(a0, v, n), !parse_uint(a0, &o.frame_first)) || !parse_uint(v + n + 2, &o.frame_last) ||
                o.frame_last < o.frame_first)
                usage_error("bad frame range '%s' (A..B with A <= B)", v);
            o.sequence = true;
        } else if (!strcmp(a, "--frame")) {
            if (!parse_uint(ARG(), &o.frame_first)) usage_error("bad frame number '%s'", argv[i]);
            o.frame_last = o.frame_first;
        } else if (!strcmp(a, "--frames")) {
            if (!parse_uint(ARG(), &o.frames) || !o.frames || o.frames > 100000)
                usage_error("bad frame count '%s'", argv[i]);
        } else if (!strcmp(a, "--warm-up")) {
            char* end = NULL;
            o.warm_up = strtod(ARG(), &end);
            if (!end || *end || !(o.warm_up >= 0 && o.warm_up <= 60)) usage_error("bad --warm-up '%s' (seconds, 0..60)", argv[i]);
        } else if (!strcmp(a, "--device")) {
            o.device = ARG();
        } else if (!strcmp(a, "--list-devices")) o.list = true;
        else if (!strcmp(a, "--validate") || !strcmp(a, "-validate")) o.validate = true;
        else if (!strcmp(a, "--cpu")) o.cpu = true;
        else if (!strcmp(a, "-v")) o.verbose = true;
        else if (a[0] == '-' && a[1]) usage_error("\"%s\" is not a valid option", a);
        else if (npos < 2) pos[npos++] = a;
        else usage_error("unexpected argument '%s'", a);
#undef ARG
    }
    if (o.list) {
        vx_error err = {0};
        if (vx_gpu_list_devices(list_cb, NULL, &err)) {
            fprintf(stderr, "%s: %s\n", prog, err.msg);
            return 1;
        }
        return 0;
    }
    if (npos != 2) usage_error("%s", npos == 0 ? "no input and output given" : "no output file given");
    o.in = pos[0], o.out = pos[1];
    const char* ext = ext_of(o.out);
    vx_pass_list passes;
    {
        vx_error perr = {0};
        if (vx_pass_list_parse(o.passes, &passes, &perr)) usage_error("--passes: %s", perr.msg);
    }
    /* the pass pipeline renders the colour mode on the GPU */
    bool pipeline = !o.cpu && !o.probe_mode && o.r.mode == VX_RENDER_COLOR;
    if ((o.passes_given || o.show_given || o.timings) && !pipeline)
        usage_error("%s", "--passes, --show and --timings need the GPU colour mode (no --cpu, no other --mode)");
    bool cones = vx_pass_list_has(&passes, VX_PASS_GI) && !strcmp(passes.gi, "cones");
    if (cones && o.cone.shadows) {
        /* the gi pass brings the direct light (with cone shadows): no direct pass */
        uint32_t k = 0;
        for (uint32_t j = 0; j < passes.count; j++)
            if (passes.kinds[j] != VX_PASS_DIRECT) passes.kinds[k++] = passes.kinds[j];
        passes.count = k;
    }
    /* the method's name first: a misspelt one is not asked for a probe file */
    if (vx_pass_list_has(&passes, VX_PASS_GI) && !vx_tool_gi_method_known(passes.gi))
        usage_error("unknown gi method '%s' (" VX_TOOL_GI_METHODS ")", passes.gi);
    if (vx_pass_list_has(&passes, VX_PASS_GI) && !o.probes && vx_tool_gi_method_needs_probes(passes.gi))
        usage_error("gi=%s needs --probes FILE (bake them: svo_bake %s OUT.probes)", passes.gi, o.in);
    if (o.voxel_lights && o.no_scene_lights) usage_error("%s", "--voxel-lights and --no-scene-lights exclude each other");
    vx_show show = o.fd.show;
    bool want_float = o.r.mode == VX_RENDER_DEPTH || o.r.mode == VX_RENDER_NORMAL ||
                      (pipeline && (show == VX_SHOW_DEPTH || show == VX_SHOW_NORMAL || show == VX_SHOW_MATERIAL));
    /* float outputs: .exr, or .pfm (what a build without OpenImageIO writes);
     * 8-bit: .png, or .ppm */
    bool exr = !strcmp(ext, "exr") || !strcmp(ext, "EXR") || !strcmp(ext, "pfm") || !strcmp(ext, "PFM");
    bool one_channel = pipeline ? show == VX_SHOW_DEPTH || show == VX_SHOW_MATERIAL : o.r.mode == VX_RENDER_DEPTH;
    o.img_form = want_float && one_channel ? 1 : want_float || exr ? 3 : 0;
    if (!exr && strcmp(ext, "png") && strcmp(ext, "PNG") && strcmp(ext, "ppm") && strcmp(ext, "PPM"))
        usage_error("output '%s' must end in .png or .exr (or .ppm, .pfm)", o.out);
    if (want_float && !exr)
        usage_error("%s %s writes float data: use an .exr (or .pfm) output", pipeline ? "--show" : "mode",
                    pipeline ? vx_show_name(show) : vx_render_mode_name(o.r.mode));
    bool needs_probes = o.probe_mode && vx_probe_render_mode_uses_probes(o.p.mode);
    if (needs_probes && !o.probes)
        usage_error("mode %s needs --probes FILE (bake them: svo_bake %s OUT.probes)", vx_probe_render_mode_name(o.p.mode),
                    o.in);
    if (o.probe_mode && o.r.lod) usage_error("%s", "--lod is not supported by the probe modes");
    if (o.cpu && o.r.lod) usage_error("%s", "--lod is not supported by the CPU reference");
    if (!o.probe_mode && o.r.spp > 1024) usage_error("--spp %u: at most 1024 outside the probe modes", o.r.spp);
    bool mpi = false;
#ifdef VX_HAVE_MPI
    /* under mpirun: the probe and path tracer modes, rows over the ranks */
    mpi = vx_tool_mpi_launched();
    if (mpi && !o.probe_mode) {
        if (vx_tool_mpi_env_rank() > 0) { /* rank 0 says why */
            vx_tool_mpi_linger();
            return 2;
        }
        usage_error("%s", "under mpirun, svo_render renders the probe modes (--mode pathtrace, gi, ...)");
    }
    bool tl_print = o.verbose; /* every rank's timeline */
    if (mpi && vx_tool_mpi_env_rank() > 0) o.verbose = false; /* one header */
#endif
    if (o.cpu && (o.device || o.validate)) usage_error("%s", "--cpu conflicts with --device/--validate");
    if (o.sequence && (o.cpu || o.probe_mode))
        usage_error("%s", "--frames A..B renders with the GPU tracer (no --cpu, no probe modes)");
    if (o.sequence && !strchr(o.out, '#')) usage_error("--frames A..B: the output '%s' needs a run of # for the frame number", o.out);
    if (o.verbose) {
        /* the pipeline's own default: 8 samples with aa or dof, else 1 */
        uint32_t spp = pipeline && !o.spp_given
                           ? (vx_pass_list_has(&passes, VX_PASS_AA) || vx_pass_list_has(&passes, VX_PASS_DOF) ? 8 : 1)
                           : o.r.spp;
        printf("%s %s %s --mode %s --size %ux%u --spp %u --fov %g --ambient %g%s%s", prog, o.in, o.out,
               vx_render_mode_name(o.r.mode), o.r.width, o.r.height, spp, o.r.camera.fov, o.r.ambient,
               o.r.camera.ortho ? " --ortho" : "", o.cpu ? " --cpu" : "");
        if (o.r.camera.set)
            printf(" --camera %g,%g,%g,%g,%g,%g", o.r.camera.eye[0], o.r.camera.eye[1], o.r.camera.eye[2],
                   o.r.camera.target[0], o.r.camera.target[1], o.r.camera.target[2]);
        if (o.r.lod) printf(" --lod %g", o.r.lod_pixels);
        if (o.device) printf(" --device %s", o.device);
        if (!o.load_models) printf(" --load whole");
        if (o.frames > 1) printf(" --frames %u --warm-up %g", o.frames, o.warm_up);
        if (pipeline) {
            char pl[160];
            vx_pass_list_format(&passes, pl, sizeof pl);
            printf(" --passes '%s' --show %s", pl, vx_show_name(show));
            printf(" --light-culling %s --shadow-lights %d", vx_light_culling_name(o.fd.light_culling),
                   o.fd.shadow_lights < 0 ? 0 : o.fd.shadow_lights ? o.fd.shadow_lights : VX_SHADOW_LIGHTS_DEFAULT);
            if (o.fd.light_cutoff > 0) printf(" --light-cutoff %g", o.fd.light_cutoff);
        }
        printf("\n");
    }

    vx_error err = {0};
    vx_svo_scene owned, scene; /* the file, and the view of the (first) frame rendered */
    double t0 = vx_time_now();
    vx_budget budget; /* --max-memory for what the files make us allocate; outlives the scene */
    vx_budget_init(&budget, o.max_memory, NULL);
    const vx_allocator* A = o.max_memory ? &budget.allocator : NULL;
    /* --load models (the default): the models one at a time into the GPU layout where the GPU scene is
     * all that reads them (the single-shader modes: no CPU render, passes, probes or voxel lights) and it
     * may be compact; the scene graph (instances, lights, sky, frames) is read first. Its frames time as
     * the scene read whole's since the layout is built before the device is made (below) */
    vx_svo_model_reader* rd = NULL;
    bool by_models = o.load_models && !mpi && !o.cpu && !o.probe_mode && !pipeline && !o.voxel_lights && !o.probes &&
                     o.scene_desc.layout != VX_RENDER_LAYOUT_PLAIN; /* over --gpu-budget: paged from the layout */
    if (o.scene_desc.host_budget && !by_models)
        usage_error("%s", "--host-budget pages the compact layout from the file: with --load models in the GPU "
                          "single-shader modes (not --layout plain, passes, probes, --cpu or --voxel-lights)");
    if (o.fly && (o.sequence || pipeline || o.cpu || o.probe_mode || mpi))
        usage_error("%s", "--fly: the GPU single-shader modes (not passes, a sequence, --cpu or the probe modes)");
    if (by_models ? vx_svo_reader_open(&(vx_svo_read_desc){.alloc = A}, o.in, &rd, &err) ||
                        vx_svo_reader_copy_graph(rd, A, &owned, &err)
                  : vx_svo_read_file(&(vx_svo_read_desc){.alloc = A}, o.in, &owned, &err)) {
        vx_svo_reader_close(rd);
        return vx_tool_error_budget(o.in, &err, &budget);
    }
    double t_load = vx_time_now() - t0;
    if (o.verbose) {
        /* now, not after the frame: a scene too large for the next step still says what it took */
        printf("read: %.3f s%s, peak host memory %s\n", t_load, rd ? " (the scene graph: the models come with the GPU scene)" : "",
               vx_tool_bytes(vx_peak_rss()));
        fflush(stdout);
    }
    if (o.frame_last >= vx_svo_scene_frames(&owned)) {
        fprintf(stderr, "%s: %s: no frame %u (the scene has %u)\n", prog, o.in, o.frame_last, vx_svo_scene_frames(&owned));
        vx_svo_scene_free(&owned), vx_svo_reader_close(rd);
        return 1;
    }
    vx_svo_scene_frame(&owned, o.frame_first, &scene);
    /* An animation's default camera frames all its frames (it holds still over
     * --frames A..B); the paths that render the frame's view (the CPU
     * reference, the probe modes, the pass pipeline) would frame that frame
     * alone, so they get the animation's camera stated. (With rd the GPU scene
     * comes from the reader and frames every frame itself.) */
    if (!o.r.camera.set && !rd && vx_svo_scene_frames(&owned) > 1) {
        double lo[3], hi[3];
        vx_svo_scene_world_bounds(&owned, lo, hi);
        vx_render_camera_default(lo, hi, &o.r, &o.r.camera);
    }
    vx_light* frame_lights = NULL;
    float* sky_rgb = NULL; /* the path tracer's environment map (the file's sky) */
    uint32_t from_voxels = 0;
    if (gather_lights(&o, &scene, &frame_lights, &o.frame_light_count, &from_voxels, &err)) {
        fprintf(stderr, "%s: %s: %s\n", prog, o.in, err.msg);
        vx_svo_scene_free(&owned), vx_svo_reader_close(rd);
        free(frame_lights), vx_free(NULL, sky_rgb);
        return 1;
    }
    o.frame_lights = frame_lights;
    if (o.sky_given && !o.frame_light_count && !(pipeline && vx_pass_list_has(&passes, VX_PASS_GI)) &&
        !(o.probe_mode && (o.p.mode == VX_PROBE_RENDER_PATHTRACE || o.p.mode == VX_PROBE_RENDER_PT_INDIRECT)))
        usage_error("%s", "--sky goes with lights (--light, or the file's), a gi pass or --mode pathtrace");
    if (!o.no_scene_lights && !o.sky_given && scene.sky.type == VX_SKY_CONSTANT && o.frame_light_count)
        memcpy(o.fd.sky, scene.sky.color, sizeof o.fd.sky);
    bool pt_mode = o.probe_mode && (o.p.mode == VX_PROBE_RENDER_PATHTRACE || o.p.mode == VX_PROBE_RENDER_PT_INDIRECT);
    /* the file's sky by direction (an environment map read here, through
     * OpenImageIO): the path tracer's, and the pass pipeline's background,
     * sky term and gi=pathtrace's */
    vx_sky_texels sky_map = {0};
    const vx_sky* sky = o.sky_given ? &o.sky : !o.no_scene_lights ? &scene.sky : NULL; /* --sky replaces the file's */
    if (sky && (pt_mode || pipeline) && sky->type != VX_SKY_DEFAULT) {
        char map[4096];
        /* a file's map is relative to the file, --sky's to the working folder */
        if (vx_sky_path(sky, o.sky_given ? NULL : o.in, map, sizeof map)) {
            uint32_t ch = 0;
            float* px = NULL;
            if (vx_image_read(map, VX_IMAGE_F32, 0, &sky_map.width, &sky_map.height, &ch, (void**)&px, &err)) {
                fprintf(stderr, "%s: %s: the sky's environment map: %s\n", prog, o.sky_given ? "--sky" : o.in, err.msg);
                vx_svo_scene_free(&owned), vx_svo_reader_close(rd);
                free(frame_lights);
                return 1;
            }
            /* RGB per texel whatever the file has (grey: one channel; alpha dropped) */
            sky_rgb = vx_calloc(NULL, (size_t)sky_map.width * sky_map.height, 3 * sizeof(float));
            for (size_t i = 0; sky_rgb && i < (size_t)sky_map.width * sky_map.height; i++)
                for (uint32_t k = 0; k < 3; k++) sky_rgb[3 * i + k] = px[i * ch + (k < ch ? k : 0)];
            vx_free(NULL, px);
            if (!sky_rgb) {
                fprintf(stderr, "%s: %s: out of memory for the sky's environment map\n", prog, map);
                vx_svo_scene_free(&owned), vx_svo_reader_close(rd);
                free(frame_lights);
                return 1;
            }
            sky_map.rgb = sky_rgb;
            o.p.sky_map = &sky_map, o.fd.sky_map = &sky_map;
        }
        o.p.sky = sky, o.fd.sky_dir = sky;
    }
    if (pt_mode) /* the path tracer carries the lights, on the GPU and the CPU */
        o.p.lights = o.frame_lights, o.p.light_count = o.frame_light_count;
    else if (o.frame_light_count && (!pipeline || o.cpu))
        fprintf(stderr, "%s: note: %u lights ignored: lights need the colour mode on the GPU or --mode pathtrace\n", prog,
                o.frame_light_count);
    if (o.verbose && o.frame_light_count)
        printf("lights: %u from the file, %u from emissive voxels, %u from --light\n",
               o.frame_light_count - from_voxels - o.light_count, from_voxels, o.light_count);
    vx_render_image img = {0};
    vx_result r;
    vx_gpu* gpu = NULL;
    vx_render_scene* rs = NULL;
    vx_logger logger = {log_cb, NULL};
    vx_probe_set probes = {0};
    vx_probe_render_stats lf_stats = {0};
    o.p.stats = &lf_stats;
    if (o.probes) {
        if (vx_probe_read_file(&(vx_probe_read_desc){.alloc = A}, o.probes, &probes, &err)) {
            vx_tool_error_budget(NULL, &err, &budget);
            vx_svo_scene_free(&owned), vx_svo_reader_close(rd);
            free(frame_lights), vx_free(NULL, sky_rgb);
            return 1;
        }
    }
    if (mpi) {
#ifdef VX_HAVE_MPI
        bool root = true;
        o.p.base = &o.r;
        if (!o.p.threads) o.p.threads = o.cpu ? 2 : 1;
        if (o.r.spp > 1) o.p.spp = o.r.spp;
        render_mpi_job job = {.scene = &scene, .probes = o.probes ? &probes : NULL, .desc = o.p, .cpu = o.cpu,
                              .device = o.device, .validate = o.validate, .verbose = o.verbose, .tl = &tl, .end = &mpi_end};
        render_mpi(&job, &img, &root); /* a failure ends the job */
        r = VX_OK;
        if (!root) {
            vx_probe_set_free(&probes);
            free(frame_lights), vx_free(NULL, sky_rgb);
            vx_svo_scene_free(&owned), vx_svo_reader_close(rd);
            render_mpi_finalize(&mpi_end, &tl, tl_print);
            return 0;
        }
#endif
    } else if (o.probe_mode && o.cpu) {
        printf("device: CPU (probe GI / path tracer, double precision)\n");
        o.p.base = &o.r;
        if (!o.p.threads) o.p.threads = 2;
        if (o.r.spp > 1) o.p.spp = o.r.spp;
        r = vx_probe_render(&scene, o.probes ? &probes : NULL, &o.p, &img, &err);
    } else if (o.probe_mode) {
        o.p.base = &o.r;
        if (o.r.spp > 1) o.p.spp = o.r.spp;
        r = vx_gpu_create(&(vx_gpu_desc){.device = o.device, .validate = o.validate, .logger = &logger}, &gpu, &err);
        if (r) {
            fprintf(stderr, "%s: no usable Vulkan device; --cpu renders the probe modes on the CPU\n", prog);
        } else {
            printf("device: %s%s (probe %s)\n", vx_gpu_device_name(gpu), vx_gpu_is_cpu(gpu) ? " (software)" : "",
                   vx_probe_render_mode_name(o.p.mode));
            r = vx_render_scene_create(gpu, &scene, &rs, &err);
        }
        if (!r) r = vx_probe_render_gpu(rs, &scene, o.probes ? &probes : NULL, &o.p, &img, &err);
        if (!r && vx_gpu_validation_errors(gpu))
            r = vx_fail(&err, VX_ERR_GPU, VX_NO_OFFSET, "%u Vulkan validation errors", vx_gpu_validation_errors(gpu));
    } else if (o.cpu) {
        printf("device: CPU reference (double precision)\n");
        r = vx_render_cpu(&scene, &o.r, NULL, &img, &err);
    } else {
        /* --load models: the compact layout is built from the reader before the device is made. A device
         * left idle for the seconds a build takes ran every later frame 4.7x slower on the H200 (0.6 ms
         * against 2.8, the sphere at 8192 in 3,944 regions; the same after --load whole with the device
         * idle 3 s: docs/PERFORMANCE.md, issue 18, branch load2). AUTO's choice needs the device's memory:
         * a first device answers it and is closed before the build (or the read, where AUTO is plain), and
         * gives the budget AUTO's bricks compare with: over it, the dictionary's second pass over the file
         * runs here too, before the device (after it, the H200's clock fell to 345 MHz for the frames:
         * 3.35 ms against 0.68, branch rdr2's batch 1) */
        vx_compact_scene built;
        vx_compact_paged paged; /* --host-budget: the file source's top and page table */
        bool have_built = false, have_paged = false;
        double built_s = 0, tb = vx_time_now();
        r = VX_OK;
        vx_gpu_desc gd = {.device = o.device, .validate = o.validate, .logger = &logger};
        vx_render_scene_desc sdesc = o.scene_desc; /* for create_compact: AUTO's bricks decided here */
        if (rd) {
            vx_render_layout lay = o.scene_desc.layout;
            bool auto_bricks = o.scene_desc.compact_bricks == VX_RENDER_BRICKS_AUTO;
            uint64_t budget = o.scene_desc.memory_budget;
            bool from_file = o.scene_desc.host_budget != 0; /* pages keep their bricks in blocks: no brick choice */
            if (lay == VX_RENDER_LAYOUT_AUTO || (auto_bricks && !from_file && !budget && lay == VX_RENDER_LAYOUT_COMPACT)) {
                r = vx_gpu_create(&gd, &gpu, &err);
                if (!r && lay == VX_RENDER_LAYOUT_AUTO)
                    r = vx_render_scene_choose_layout(gpu, vx_svo_reader_scene(rd), &o.scene_desc, &lay, &err);
                if (!r) budget = vx_render_scene_budget(gpu, &o.scene_desc);
                vx_gpu_destroy(gpu);
                gpu = NULL;
            }
            if (!r && lay == VX_RENDER_LAYOUT_COMPACT && from_file) {
                r = vx_render_page_build_reader(rd, &o.scene_desc, &paged, &err);
                have_paged = !r;
                built_s = vx_time_now() - tb;
            } else if (!r && lay == VX_RENDER_LAYOUT_COMPACT) {
                vx_compact_desc cd = {.attr_regions = true,
                                      .bricks = o.scene_desc.compact_bricks == VX_RENDER_BRICKS_DICT
                                                    ? VX_COMPACT_BRICKS_DICT
                                                    : VX_COMPACT_BRICKS_INLINE};
                r = vx_compact_build_reader(&cd, rd, &built, &err);
                have_built = !r;
                uint32_t passes = 1;
                if (!r && auto_bricks) {
                    r = vx_render_compact_auto_bricks(rd, &o.scene_desc, budget, &built, &passes, &err);
                    if (r) vx_compact_free(&built), have_built = false; /* the second pass failed: nothing built */
                }
                sdesc.bricks_decided = true, sdesc.file_passes = passes;
                built_s = vx_time_now() - tb;
            } else if (!r) { /* plain: the scene whole, read before the device as --load whole reads it */
                vx_svo_reader_close(rd);
                rd = NULL;
                vx_svo_scene_free(&owned);
                double tr = vx_time_now();
                r = vx_svo_read_file(&(vx_svo_read_desc){.alloc = A}, o.in, &owned, &err);
                if (!r) vx_svo_scene_frame(&owned, o.frame_first, &scene);
                if (o.verbose && !r)
                    printf("note: the layout is plain: the scene was read whole in %.3f s, peak host memory %s%s\n",
                           vx_time_now() - tr, vx_tool_bytes(vx_peak_rss()),
                           o.scene_desc.host_budget ? " (--host-budget: nothing paged)" : "");
            }
        }
        if (!r) r = vx_gpu_create(&gd, &gpu, &err);
        if (r && have_built) vx_compact_free(&built), have_built = false;
        if (r && have_paged) vx_compact_paged_free(&paged), have_paged = false;
        if (!r) {
            printf("device: %s%s\n", vx_gpu_device_name(gpu), vx_gpu_is_cpu(gpu) ? " (software)" : "");
            /* the whole animation: its models, and a camera that frames every frame */
            double t1 = have_built || have_paged ? tb : vx_time_now();
            if (rd) {
                r = have_paged  ? vx_render_scene_create_paged(gpu, rd, &paged, built_s, &sdesc, &rs, &err)
                    : have_built ? vx_render_scene_create_compact(gpu, rd, &built, built_s, &sdesc, &rs, &err)
                                 : vx_render_scene_create_reader(gpu, rd, &o.scene_desc, &rs, &err);
                if (!r) { /* the bounds (where the reader computes them) and the cells' boxes, known now */
                    const vx_svo_scene* g = vx_svo_reader_scene(rd);
                    memcpy(owned.bounds_min, g->bounds_min, sizeof owned.bounds_min);
                    memcpy(owned.bounds_max, g->bounds_max, sizeof owned.bounds_max);
                    for (uint32_t i = 0; i < owned.model_count; i++) owned.models[i].check = g->models[i].check;
                    vx_svo_scene_frame(&owned, o.frame_first, &scene);
                }
                if (!have_paged) { /* the file source reads pages from it until the scene is destroyed */
                    vx_svo_reader_close(rd);
                    rd = NULL;
                }
            } else {
                r = vx_render_scene_create_ex(gpu, &owned, &o.scene_desc, &rs, &err);
            }
            if (!r && o.verbose)
                printf("gpu scene: %.3f s (layout built and uploaded), peak host memory %s\n", vx_time_now() - t1,
                       vx_tool_bytes(vx_peak_rss()));
            if (!r && o.frame_first) r = vx_render_scene_set_frame(rs, &owned, o.frame_first, &err);
        }
        vx_render_layout_info li;
        vx_render_scene_layout(rs, &li);
        if (!r && o.verbose) {
            printf("layout: %s%s, %.3f MB on the GPU, %.3f bytes per voxel (plain: %.3f MB; %s budget %.1f MB)\n",
                   vx_render_layout_name(li.layout), li.brick_dict ? " (brick dictionary)" : "", li.bytes / 1e6, li.voxels ? (double)li.bytes / (double)li.voxels : 0.0,
                   li.plain_bytes / 1e6, o.scene_desc.layout != VX_RENDER_LAYOUT_AUTO ? "asked for; the" : "auto:",
                   li.budget / 1e6);
            if (li.grid_models)
                printf("grid walk: %u models with a grid, %.3f MB on the GPU, built in %.3f s\n", li.grid_models,
                       li.grid_bytes / 1e6, li.grid_seconds);
            if (li.compact_bytes && have_paged)
                printf("compact: paged from the file (the models' own layouts %.3f MB): its top and page table built "
                       "model by model in %.3f s, the top and pool made in %.3f s\n",
                       li.compact_bytes / 1e6, li.build_seconds, li.upload_seconds);
            else if (li.compact_bytes && by_models)
                printf("compact: geometry %.3f MB, attributes %.3f MB; built model by model from the file in %.3f s%s (the "
                       "models read, their geometry and attributes on %u threads %.3f s, the regions placed %.3f s), "
                       "tables and upload %.3f s\n",
                       li.geom_bytes / 1e6, (li.compact_bytes - li.geom_bytes) / 1e6, li.build_seconds,
                       li.file_passes > 1 ? ", two passes over the file (over the budget: built again with the brick dictionary)"
                                          : "",
                       li.geom_threads, li.geom_seconds, li.attr_seconds, li.upload_seconds);
            else if (li.compact_bytes)
                printf("compact: geometry %.3f MB, attributes %.3f MB; built in %.3f s (geometry %.3f s on %u threads, "
                       "attributes %.3f s), tables and upload %.3f s\n",
                       li.geom_bytes / 1e6, (li.compact_bytes - li.geom_bytes) / 1e6, li.build_seconds, li.geom_seconds,
                       li.geom_threads, li.attr_seconds, li.upload_seconds);
            if (li.material_bytes)
                printf("compact: material ids %.3f MB (%.3f bytes per voxel; a model names non-diffuse materials through "
                       "its material channel)\n",
                       li.material_bytes / 1e6, li.voxels ? (double)li.material_bytes / (double)li.voxels : 0.0);
            if (li.attr_parts > 1) printf("note: the compact attributes are in %u storage buffers (past one buffer's range)\n", li.attr_parts);
        }
        char why[256];
        const char* note = NULL;
        if (!r && pipeline && passes_refuse(rs, &li, why, sizeof why, &note)) {
            /* --light lights need the passes in the colour mode (else dropped) */
            if (o.passes_given || o.show_given || o.timings || o.light_count)
                r = vx_fail(&err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "%s", why);
            pipeline = false;
            if (o.verbose) printf("note: %s\n", note);
        }
        if (!r && o.view2_out && (o.sequence || pipeline))
            r = vx_fail(&err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "--view2: the single-shader modes only (not passes, not a sequence)");
        if (!r && o.sequence) {
            r = render_sequence(&o, rs, &owned, pipeline, &passes, o.probes ? &probes : NULL, &err);
            if (!r) {
                vx_probe_set_free(&probes);
                vx_render_scene_destroy(rs);
                vx_gpu_destroy(gpu);
                vx_svo_scene_free(&owned), vx_svo_reader_close(rd);
                free(frame_lights), vx_free(NULL, sky_rgb);
                return 0;
            }
        } else if (!r && pipeline) {
            r = render_passes(&o, rs, &owned, &passes, o.probes ? &probes : NULL, &img, &err);
        } else if (!r) {
            /* -v: the first frame also returns its hits, for the share of pixels that hit geometry */
            bool counted = o.verbose && !o.r.want_hits;
            if (counted) o.r.want_hits = true;
            r = vx_render_frame(rs, &o.r, &img, &err);
            if (counted) {
                o.r.want_hits = false;
                if (!r) print_hit_share(&img);
            }
            /* paged (the compact layout over --gpu-budget): frames until the
             * pages the view needs are resident, or the pool takes no more */
            vx_render_page_stats ps = {0};
            for (uint32_t f = 1; !r && li.pages && f < 64; f++) {
                vx_render_scene_page_stats(rs, &ps);
                if (!ps.coarse || (f > 1 && !ps.loaded)) break;
                vx_render_image_free(&img);
                r = vx_render_frame(rs, &o.r, &img, &err);
            }
            if (!r && li.pages) {
                vx_render_scene_page_stats(rs, &ps);
                if (o.verbose)
                    printf("paging: level %u, %u pages; after %llu frames %u resident (%.3f MB of the pool's %.3f MB; "
                           "top %.3f MB), %u drawn coarse (%u refused, %.3f MB over the budget)\n",
                           li.page_level, li.pages, (unsigned long long)ps.frames, ps.resident, ps.used_bytes / 1e6,
                           ps.pool_bytes / 1e6, ps.top_bytes / 1e6, ps.coarse, ps.refused, ps.refused_bytes / 1e6);
                else if (ps.coarse)
                    printf("note: %u pages drawn coarse: they do not fit --gpu-budget (-v says more)\n", ps.coarse);
                if (o.verbose && ps.from_file) print_host_cache(&ps);
            }
            if (!r && o.fly) r = fly_frames(&o, rs, &scene, li.pages != 0, &err);
            if (!r) r = timed_frames(&o, rs, !vx_gpu_is_cpu(gpu), &img, &err);
            if (!r && o.view2_out) {
                /* the second view: its share of hits, its frames, its image */
                vx_render_image img2 = {0};
                vx_render_camera first = o.r.camera;
                o.r.camera.set = true; /* up, fov and projection stay the first view's */
                memcpy(o.r.camera.eye, o.view2.eye, sizeof o.r.camera.eye);
                memcpy(o.r.camera.target, o.view2.target, sizeof o.r.camera.target);
                printf("view2 (%s):\n", o.view2_out);
                o.r.want_hits = o.verbose;
                r = vx_render_frame(rs, &o.r, &img2, &err);
                o.r.want_hits = false;
                if (!r) print_hit_share(&img2);
                if (!r) r = timed_frames(&o, rs, !vx_gpu_is_cpu(gpu), &img2, &err);
                if (!r) r = write_image(&o, o.view2_out, &img2, &err);
                if (!r) printf("wrote %s\n", o.view2_out);
                vx_render_image_free(&img2);
                o.r.camera = first;
            }
            vx_render_shadow_map_info sm;
            vx_render_scene_shadow_map_info(rs, &sm);
            if (!r && o.verbose && sm.used)
                printf("shadow map: %u texels a side (texel %g), %u nodes listed in %.3f s, built in %.3f ms "
                       "(%.3f ms GPU): shadow rays end where nothing lies further towards the light\n",
                       sm.side, sm.texel, sm.nodes, sm.list_seconds, sm.build_seconds * 1e3, sm.build_gpu_seconds * 1e3);
        }
        if (!r && vx_gpu_validation_errors(gpu))
            r = vx_fail(&err, VX_ERR_GPU, VX_NO_OFFSET, "%u Vulkan validation errors", vx_gpu_validation_errors(gpu));
    }
    vx_probe_set_free(&probes);
    if (r) {
        vx_tool_error_budget(o.in, &err, &budget); /* the file once: the model reader's errors name it already */
        vx_render_scene_destroy(rs);
        vx_gpu_destroy(gpu);
        vx_svo_scene_free(&owned), vx_svo_reader_close(rd);
        free(frame_lights), vx_free(NULL, sky_rgb);
        return 1;
    }
    size_t npx = (size_t)img.width * img.height;
    r = write_image(&o, o.out, &img, &err);
#ifdef VX_HAVE_MPI
    if (mpi) vx_tool_timeline_mark(&tl, VX_TL_OUTPUT);
#endif
    if (!r) {
        printf("scene: %u models, %u instances (load %.3f s%s)\n", scene.model_count, scene.instance_count, t_load,
               "");
        printf("render: %ux%u, %u spp, %s %s: %.3f ms (%s), %.2f Mrays/s\n", img.width, img.height,
               (uint32_t)(img.rays / (npx ? npx : 1)), pipeline ? "passes" : "mode",
               pipeline ? o.passes : o.probe_mode ? vx_probe_render_mode_name(o.p.mode) : vx_render_mode_name(o.r.mode),
               img.gpu_seconds * 1e3,
               o.cpu ? "wall clock" : "GPU timestamps",
               img.gpu_seconds > 0 ? img.rays / img.gpu_seconds * 1e-6 : 0.0);
        if (lf_stats.rays)
            printf("light field: %llu rays: %.1f%% hit a probe's surface, %.1f%% sky, %.1f%% traced in the octree; "
                   "%.2f probes and %.1f texels per ray, %llu coarse texels skipped\n",
                   (unsigned long long)lf_stats.rays, 100.0 * lf_stats.hits / lf_stats.rays,
                   100.0 * lf_stats.misses / lf_stats.rays, 100.0 * lf_stats.fallbacks / lf_stats.rays,
                   (double)lf_stats.probe_traces / lf_stats.rays, (double)lf_stats.texels / lf_stats.rays,
                   (unsigned long long)lf_stats.coarse_skips);
        printf("wrote %s\n", o.out);
    } else {
        fprintf(stderr, "%s: %s\n", prog, err.msg);
    }
    vx_render_image_free(&img);
    vx_render_scene_destroy(rs);
    vx_gpu_destroy(gpu);
    vx_svo_scene_free(&owned), vx_svo_reader_close(rd);
    free(frame_lights), vx_free(NULL, sky_rgb);
#ifdef VX_HAVE_MPI
    if (mpi) render_mpi_finalize(&mpi_end, &tl, tl_print);
#endif
    return r ? 1 : 0;
}
