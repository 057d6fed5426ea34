/* render/pipeline.h - a frame as an ordered list of GPU passes over shared images.
 *
 * The passes, in the only order they may appear:
 *   gbuffer  primary rays through the BVH and the octrees: hit point, depth,
 *            instance, entry face (the normal), albedo, attribute record
 *            (the material id), and with ids wanted the instance id and cell
 *   dof      thin-lens depth of field as primary-ray jitter (see below)
 *   direct   the sun, or the frame's lights (vx_light: directional, point,
 *            spot, sphere, rect) through a light grid culled on the GPU
 *            each frame (see "Many lights" below), with ray-traced shadows
 *   gi       one global illumination method, registered by the caller
 *            (vx_gi_method: probes, lightfield and pathtrace come from probes/)
 *   ao       ray-traced ambient occlusion: short octree rays, radius and count
 *   aa       jittered accumulation over the samples plus an edge filter
 *   tonemap  exposure, a filmic curve (ACES fit) and the sRGB transfer
 * direct, gi and ao may come in any order among themselves. gbuffer, direct,
 * gi and ao run once per sample; a resolve step (always) combines them into
 * the sample's colour and accumulates it; aa's filter and tonemap run once on
 * the average.
 *
 * Depth of field is primary-ray jitter, not a blur of the G-buffer: a blur
 * from one depth image leaks sharp foreground over blurred background at
 * silhouettes and cannot show what the lens sees around an edge, while the
 * tracer already casts the rays; the price is samples (it converges with aa's
 * accumulation, and one sample is a pinhole frame with noise).
 *
 * Light models. Without a gi pass the frame uses the colour mode's model:
 * colour = albedo * (ambient * ao + (1 - ambient) * n.l * visibility), sky
 * (0.62, 0.75, 0.92) on a miss; the default list "gbuffer,direct" then gives
 * the same bytes as vx_render_frame in VX_RENDER_COLOR. With a gi pass the
 * method's radiometric light is used (a sun of irradiance `sun`, a sky of
 * radiance `sky`, emissive attribute records): colour = emission +
 * albedo / pi * sun * n.l * visibility + gi * ao. With lights (and no gi
 * pass) the radiometric model too: colour = emission + albedo / pi * sum of
 * the lights' irradiance + albedo * sky * ao (emission from the scene's
 * materials, per attribute record, as the gi methods take it).
 *
 * Metal seen directly (radiometric model): a pixel whose attribute record is
 * metal (_type _metal) gets the path tracer's BRDF f = kd / pi + GGX
 * (probes/pathtrace.c): the direct pass multiplies the sun's and each
 * light's irradiance by f(v, l) (v towards the pinhole eye, l towards the
 * shadow ray's point of the source), so the direct image holds the radiance
 * leaving the pixel, which resolve adds as it is; the sky term is kd * sky
 * + the sky along the mirror direction * the specular lobe's directional
 * albedo (vx_ggx_albedo_table), times ao. The records' materials are bound
 * only when some record is metal (the shaders are specialised on it: a scene
 * without metal runs the code and gives the pixels it did before). The
 * colour model has no metal.
 *
 * Glass seen directly (radiometric model, the direct pass present): a pixel
 * whose record is glass that transmits gets the path tracer's glass events
 * at bounces 0 in expectation (a dielectric event is no bounce: the path
 * goes on off and through the glass to the first surface that is not
 * glass): F (its Fresnel at the view angle, its ior) times the radiance the
 * reflected ray brings plus (1 - F) times the colour times the radiance the
 * refracted ray brings: walked through the glass cells, out with weight 1 -
 * F_out, the share F_out reflected inside walked on in turn (past the
 * critical angle all of it). Each ray that leaves the glass is traced to the
 * next surface, which gets its direct light (shadowed, Lambert or metal's
 * BRDF), emission and sky term (a miss: the sky); a further glass body is
 * split the same way (its Lambert share shaded as diffuse); an opaque voxel
 * against the glass (the floor a glass block stands on, a voxel set in
 * glass) is such a surface too, seen from inside the glass (its shadow rays
 * meet the glass: its emission and sky term). Rough glass takes the smooth
 * directions; at most 4 glass bodies along a ray, 8 rays a pixel, none of
 * weight below 1e-4, and a step limit a body (pass_bodies.glsl glass_lobe).
 * The direct image holds that radiance, resolve adds it as it is; the
 * Lambert share 1 - transmission is shaded as diffuse. With a gi pass the glass lobe (what
 * the glass reflects and transmits) is the gi method's instead: its paths,
 * photon paths or cones go on through the glass and bring the surface
 * behind it whole, its indirect light included (which the direct pass
 * cannot know: that surface is not a pixel of the G-buffer); the direct
 * pass then gives the Lambert share's direct light alone and resolve adds
 * the gi image as it is (no ao on a glass pixel). Bound and specialised as
 * metal (a scene without glass keeps its code); without the direct pass
 * glass is diffuse.
 *
 * A pass the list leaves out is not dispatched and has no buffer; the
 * resolve shader is specialised on what is present (no AO term without ao,
 * no emission term without emissive records).
 *
 * Merging: when nothing reads the G-buffer between them (no gi, no
 * intermediate shown), gbuffer, direct, ao (on a CPU device only up to 16
 * rays: more are split over dispatches) and resolve run as one kernel per sample
 * (shaders/frame.comp, the same functions as the pass shaders, values kept
 * in registers), reported as one timing row ("gbuffer+direct+resolve");
 * separate_passes turns that off.
 *
 * GPU time per pass comes from timestamps around each dispatch in one
 * submission (the gi method's own dispatches are timed by the method).
 * Float traversal only: scenes that need the float64 variant (a model deeper
 * than VX_RENDER_PRECISE_DEPTH) are refused with VX_ERR_UNSUPPORTED; use
 * vx_render_frame for them. */
#ifndef VX_RENDER_PIPELINE_H
#define VX_RENDER_PIPELINE_H

#include "render/render.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum vx_pass_kind {
    VX_PASS_GBUFFER = 0,
    VX_PASS_DOF,
    VX_PASS_DIRECT,
    VX_PASS_GI,
    VX_PASS_AO,
    VX_PASS_AA,
    VX_PASS_TONEMAP,
    VX_PASS_KIND_COUNT
} vx_pass_kind;

/* A parsed pass list: kinds in order, and the gi method's name ("none" or
 * what follows "gi="). */
typedef struct vx_pass_list {
    uint32_t count;
    vx_pass_kind kinds[VX_PASS_KIND_COUNT];
    char gi[32];
} vx_pass_list;

#define VX_PASS_LIST_DEFAULT "gbuffer,direct"

/* Parses "gbuffer,direct,gi=probes,ao,tonemap". Errors (VX_ERR_INVALID_ARG)
 * name the pass: unknown, repeated, out of order, "gi" without a method, or
 * a pass without gbuffer before it. An empty string is the empty list (the
 * frame is the background). */
vx_result vx_pass_list_parse(const char* s, vx_pass_list* out, vx_error* err);
bool vx_pass_list_has(const vx_pass_list* l, vx_pass_kind k);
const char* vx_pass_name(vx_pass_kind k);
/* Writes the list back as text ("gbuffer,direct,gi=probes"). */
void vx_pass_list_format(const vx_pass_list* l, char* buf, size_t size);

/* The image a frame returns. FINAL is the resolved (and post-processed)
 * colour; the others are the intermediates, averaged over the samples. */
typedef enum vx_show {
    VX_SHOW_FINAL = 0,
    VX_SHOW_ALBEDO,   /* attribute colour (1 without attributes), 0 on a miss */
    VX_SHOW_NORMAL,   /* world normal xyz */
    VX_SHOW_DEPTH,    /* depth in every channel, +inf on a miss (float) */
    VX_SHOW_DIRECT,   /* what the direct pass delivers (before the albedo; a metal or glass pixel: its radiance) */
    VX_SHOW_GI,       /* the gi pass's radiance */
    VX_SHOW_AO,       /* unoccluded share, 1 where ao is absent */
    VX_SHOW_INSTANCE, /* a colour per instance id */
    VX_SHOW_MATERIAL, /* attribute record index (float), -1 on a miss; the compact layout: the record's
                         material id where it carries them (layout_info.material_bytes), else its palette index */
    VX_SHOW_COUNT
} vx_show;
const char* vx_show_name(vx_show s);
bool vx_show_parse(const char* s, vx_show* out);

/* A GI method's GPU pass, registered by the module that implements it.
 * render() fills `out` (a device buffer of width*height vec4: the indirect
 * radiance leaving each pixel's first surface, alpha unused) for sample
 * `sample` of the frame described by `frame` (the same camera as the
 * G-buffer's; spp is 1 and the method traces its own pixel-centre rays);
 * *gpu_seconds receives its GPU time. The light fields are the method's
 * light; emit_attr, when not NULL, holds the emission's terms of each attribute
 * record (4 floats, svo/svo.h vx_material_emitted_terms: radiance = colour * [3] +
 * [0..2]) in the order of the scene's colour buffer (emit_count records). */
typedef struct vx_gi_io {
    const vx_render_desc* frame;
    uint32_t sample;
    void* out; /* the pipeline's gi buffer, opaque (render/gpu.h: vx__buffer) */
} vx_gi_io;

typedef struct vx_gi_method {
    const char* name;
    void* user;
    vx_result (*render)(void* user, const vx_gi_io* io, double* gpu_seconds, vx_error* err);
    double light_dir[3]; /* towards the sun, unit */
    double sun[3];       /* irradiance on a surface facing the sun */
    double sky[3];       /* sky radiance */
    const float* emit_attr;
    size_t emit_count;
    /* the frame lights the method's light includes (a frame with lights and
     * a gi pass must give these, the same array and count) */
    const vx_light* lights;
    uint32_t light_count;
    /* the sky by direction the method's light includes (NULL: the uniform
     * `sky`): the frame's background then shows it (gi=pathtrace takes
     * vx_probe_render_desc.sky and sky_map; borrowed, as long as the method) */
    const vx_sky* sky_dir;
    const vx_sky_texels* sky_map;
    /* the gi image holds the direct light too (gi=cones with cone shadows):
     * a pass list with both direct and this gi pass is refused */
    bool includes_direct;
} vx_gi_method;

/* Lights (vx_light, vx_light_validate) are scene data: svo/svo.h.
 *
 * Many lights. Each light's irradiance is exact for its type: point and
 * spot I cos / d^2 (glTF's cone and range window); sphere the closed form of
 * a sphere's irradiance on a tilted plane, exact also where the horizon
 * clips it (Snyder 1996); rect Lambert's polygon formula on the rectangle
 * clipped to the surface's horizon. Every point, spot, sphere and rect light
 * has a finite reach R, scaled by glTF's window (1 - (d/R)^4)^2 (d from its
 * centre): R is `range` when set, else the cut-off radius where the light's
 * irradiance falls to light_cutoff (point, spot: sqrt(I / cutoff); sphere:
 * radius * sqrt(pi L / cutoff); rect: half its diagonal + sqrt(L area /
 * cutoff)). The cut-off changes a point or spot light's irradiance by at
 * most 1.09 light_cutoff anywhere (the window's loss below R, cutoff (2q^2 -
 * q^6) with q = d/R, peaks at 4/3 sqrt(2/3); the whole light beyond R is
 * below cutoff); sphere and rect lights by about as much. Directional
 * lights reach everywhere and are never culled.
 *
 * Culling (light_culling) finds each pixel's lights in a grid built on the
 * GPU every frame (render/shaders/cull.comp, timing row "cull"): clustered,
 * screen tiles of 32 pixels times 32 depth slices exponential in view depth
 * over the scene's depth range; tiled, screen tiles of 16 pixels each
 * spanning the depths of its G-buffer hits (per sample, after the gbuffer
 * pass, so never merged); or brute force, every light at every pixel. Each
 * light is inserted into the cells its window sphere touches; the shading
 * is the same for every method (equal up to the order of the sums).
 *
 * Lights that stand for emissive voxels (VX_LIGHT_FROM_VOXELS, spheres
 * around a cluster's cells) add nothing to an emissive surface inside their
 * sphere: that surface is one of the voxels the light stands for (or of the
 * next cluster of the same lamp) and shows its own emission; the path
 * tracer, which samples the voxels themselves, gives such a face no light
 * from its lamp (its neighbours lie in its plane or behind it). Lit by its
 * own sphere (pi times the sphere's radiance inside it) a lamp showed 1.5x
 * the path tracer's radiance (tests/probes/test_pathtrace.c).
 *
 * Shadows: the shadow_lights strongest lights of each pixel (by unshadowed
 * irradiance, directional ones included) get one ray-traced shadow ray per
 * sample; the others are added unshadowed, so a light beyond the budget
 * shines through walls. A light with a size (point or spot radius, a
 * sphere, a rect, the sun's angular diameter) sends its ray to a random
 * point of its source (seeded per pixel, sample and light): soft shadows
 * that converge over samples. */
typedef enum vx_light_culling {
    VX_LIGHT_CULLING_AUTO = 0,  /* brute force up to VX_LIGHT_CULLING_AUTO_MAX lights, tiled above */
    VX_LIGHT_CULLING_BRUTE,
    VX_LIGHT_CULLING_TILED,
    VX_LIGHT_CULLING_CLUSTERED,
    VX_LIGHT_CULLING_COUNT
} vx_light_culling;
/* Measured on an H100 at 1920x1080 (docs/PERFORMANCE.md, "Many lights"):
 * brute force wins up to between 32 and 100 lights; above, tiled beats
 * clustered at every count (its cells hold only the depths of their hits,
 * and a warp's pixels share one list), so auto takes tiled. Clustered
 * stays: it needs no G-buffer (the frame kernel stays merged) and culls once
 * per frame, not per sample. */
#define VX_LIGHT_CULLING_AUTO_MAX 64
#define VX_SHADOW_LIGHTS_DEFAULT 4
#define VX_SHADOW_LIGHTS_MAX 16
const char* vx_light_culling_name(vx_light_culling c);
bool vx_light_culling_parse(const char* s, vx_light_culling* out);

/* Frame options; zero-initialised means the defaults (vx_frame_desc_defaults
 * gives them, and the tools' --help prints them).
 *  base:        size, camera, spp (samples accumulated; 0: 1, or 8 with aa),
 *               light_dir and ambient of the colour model
 *  passes:      NULL: VX_PASS_LIST_DEFAULT
 *  gi:          the method for "gi=NAME" (its name must match)
 *  ao_radius:   world units; 0: 4 cells of the largest instance cell
 *  ao_rays:     per pixel and sample; 0: 4
 *  aperture:    lens radius in world units; 0: 1/100 of the scene's diagonal
 *  focus:       focus distance in world units; 0: the depth at the image centre
 *  exposure:    stops; tonemap multiplies by 2^exposure
 *  edge_threshold: aa's luma contrast that counts as an edge; 0: 0.1
 *  seed:        random streams of ao and dof
 *  lights:      light_count lights for the direct pass; with any, the frame
 *               uses the radiometric model (the colour model's sun and
 *               ambient are not added): colour = emission + albedo / pi *
 *               irradiance + albedo * sky * ao, sky radiance `sky` (also the
 *               background).
 *               With a gi pass only the lights the method was made with
 *               (vx_gi_method.lights: gi=pathtrace takes them).
 *  sky_dir, sky_map: the sky by direction (svo/svo.h vx_sky, the file's
 *               sky; borrowed): NULL or VX_SKY_DEFAULT: the uniform `sky`;
 *               constant: its colour replaces `sky`; gradient or environment
 *               map (texels in sky_map, which the caller reads: vx_sky_path,
 *               vx_image_read): in the radiometric model (with lights or a
 *               gi pass) the background is vx_sky_radiance of each primary
 *               ray's direction (render/shaders/sky.glsl, the path tracer's
 *               code) and the sky term albedo * E(n) / pi * ao, E the sky's
 *               irradiance on a surface of normal n, unoccluded (a table of
 *               32 x 17 normals read bilinearly, integrated over the sky on
 *               the CPU when the sky changes). With a gi pass the method's
 *               sky (vx_gi_method.sky_dir) replaces these.
 *  light_culling: how the direct pass finds each pixel's lights (above)
 *  shadow_lights: lights per pixel with a shadow ray, the strongest; 0:
 *               VX_SHADOW_LIGHTS_DEFAULT, -1: none, at most VX_SHADOW_LIGHTS_MAX
 *  light_cutoff: irradiance where a light without a range ends (above);
 *               0: pi / 1024 * 2^-exposure, a quarter of an 8-bit step of a
 *               white diffuse surface at the frame's exposure
 *  want_ids:    also fill hits[] (sample 0: instance id, cell, depth)
 *  no_readback: benchmarks: leave the image on the GPU (image.pixels NULL),
 *               so back-to-back frames keep the GPU busy and at its clocks
 *  separate_passes: never merge passes (each pass its own dispatch and
 *               timing row); by default gbuffer, direct and resolve run as
 *               one dispatch ("gbuffer+direct+resolve") when no ao, gi or
 *               intermediate image needs their results in between
 *  no_timestamps: a recorded frame (vx_frame_record) without its passes'
 *               timestamps and their query reset (its result then has no
 *               times: frame_ms 0, timing rows with 0 ms); on an H200 they
 *               cost a 0.08 ms frame in flight a few microseconds, so a
 *               viewer times one frame in several. Frames rendered and
 *               waited for are always timed. */
typedef struct vx_frame_desc {
    vx_render_desc base;
    const vx_pass_list* passes;
    const vx_gi_method* gi;
    vx_show show;
    double ao_radius;
    uint32_t ao_rays;
    double aperture, focus;
    double exposure;
    double edge_threshold;
    uint64_t seed;
    const vx_light* lights;
    uint32_t light_count;
    double sky[3];
    const vx_sky* sky_dir;
    const vx_sky_texels* sky_map;
    vx_light_culling light_culling;
    int32_t shadow_lights;
    double light_cutoff;
    bool want_ids;
    bool no_readback;
    bool separate_passes;
    bool no_timestamps;
} vx_frame_desc;

/* The resolved defaults of a desc, for --help and for callers who want to
 * see them (fields that depend on the scene stay 0: radius, aperture, focus). */
vx_frame_desc vx_frame_desc_defaults(void);

typedef struct vx_pass_timing {
    const char* name; /* a pass name, or "resolve" */
    double ms;        /* GPU time summed over the frame's samples */
    uint32_t dispatches;
} vx_pass_timing;

typedef struct vx_frame_result {
    vx_render_image image;    /* mode VX_RENDER_COLOR; hits when want_ids */
    vx_pass_timing timings[VX_PASS_KIND_COUNT + 1];
    uint32_t timing_count;
    double frame_ms; /* GPU time from the first pass's start to the last's end, summed over submissions */
    vx_light_culling light_culling; /* the method that ran (with lights) */
    uint64_t light_entries;         /* light list entries of the grid (last sample) */
    /* the direct pass's sun rays ended by the scene's sun depth map (vx_render_shadow_map_info; built, as for
     * vx_render_frame, at a frame whose light the frame before had; base.no_shadow_map: never; the same image) */
    bool shadow_map;
} vx_frame_result;

/* The per-scene state of the pipeline (buffers sized to the last frame). */
typedef struct vx_frame_renderer vx_frame_renderer;

/* `scene` is the one rs was made from; borrowed only during the call. */
vx_result vx_frame_renderer_create(vx_render_scene* rs, const vx_svo_scene* scene, vx_frame_renderer** out,
                                   vx_error* err);
void vx_frame_renderer_destroy(vx_frame_renderer* fr);
/* After the scene changed without a new render scene (instances moved:
 * vx_render_scene_set_frame; attribute records appended:
 * vx_render_scene_update_model; the materials changed): the renderer's
 * scene facts taken from `scene` again: the bounds (default framing, dof,
 * light grid), the largest cell (ao's default radius), the emission per
 * record that the radiometric model and the direct pass read. No buffer
 * changes and nothing waits for the device (frames in flight keep running);
 * a changed emission table goes to the GPU with the next frame. */
vx_result vx_frame_renderer_update_scene(vx_frame_renderer* fr, const vx_svo_scene* scene, vx_error* err);
/* Renders one frame; out->image is freed with vx_render_image_free. */
vx_result vx_frame_render(vx_frame_renderer* fr, const vx_frame_desc* desc, vx_frame_result* out, vx_error* err);

/* Frames in flight. vx_frame_render submits each frame and waits for it: on a
 * fast GPU the submission and the wait cost more than the frame (1920x1080,
 * a 0.08 ms trace: 0.28 ms of wall time). vx_frame_record instead records
 * the frame into `cmd` (a VkCommandBuffer in the recording state, on the
 * renderer's device and queue), which the caller submits with what shows the
 * image (render/display.h: the conversion and the copy to a swapchain image
 * in the same command buffer), while up to VX_FRAME_SLOTS frames before it
 * may still run. The frame's per-frame data (the frame block, the instance
 * tables and BVH nodes relative to the camera, the lights) are written by
 * commands in cmd, between barriers, so each frame reads its own and the
 * frames run one after another on the queue. `slot` names the frame's
 * descriptor set and timestamps: a slot is recorded again only after the
 * device has run its last frame (the caller waited for that submission),
 * and then vx_frame_record_result gives that frame's pass times (the rows
 * and frame_ms as vx_frame_render's; VX_ERR_INVALID_ARG when it has not
 * run). The image stays on the GPU (no pixels, no hits).
 *
 * The scene's tables are written only when they differ from the last
 * recorded frame's (a still camera and scene: none), so a frame recorded and
 * then not submitted must be reported with vx_frame_record_cancel before the
 * next is recorded (a failed vx_frame_record reports itself).
 *
 * Refused (VX_ERR_UNSUPPORTED; use vx_frame_render): want_ids, a readback
 * (no_readback false), a gi pass (the method submits its own work), light
 * culling other than brute force (the grid's size is read back).
 * Every other call on the renderer or its scene that writes what the frames
 * read from the host (vx_frame_render, vx_render_frame, model and instance
 * updates, a new frame size) waits for the queue to go idle first. */
#define VX_FRAME_SLOTS 8
vx_result vx_frame_record(vx_frame_renderer* fr, const vx_frame_desc* desc, void* cmd, uint32_t slot,
                          vx_frame_result* out, vx_error* err);
vx_result vx_frame_record_result(vx_frame_renderer* fr, uint32_t slot, vx_frame_result* out, vx_error* err);
/* VX_ERR_UNSUPPORTED where vx_frame_record refuses desc for the reasons
 * above (other errors it finds when recording); VX_OK otherwise: for
 * presenters that acquire the image a frame writes before recording it. */
vx_result vx_frame_recordable(const vx_frame_desc* desc, vx_error* err);
/* The frame last recorded will not be submitted (its command buffer was
 * dropped): the next frame writes the scene's tables whatever they are. */
void vx_frame_record_cancel(vx_frame_renderer* fr);

/* The directional albedo of the metal lobe's specular part (the path
 * tracer's: GGX, alpha = max(rough^2, 1e-3), Smith height-correlated G2,
 * Schlick's Fresnel) as f0 A + B: n x n entries of four floats (A, B, 0, 0),
 * the cosine of the view angle (i + 0.5) / n across, the roughness
 * (j + 0.5) / n down, each from 32 x 32 stratified visible-normal samples.
 * The pass pipeline's sky term for metal (pass_bodies.glsl) and the cones'
 * specular cone (cones/cones.c) read it. out holds 4 n^2 floats. */
void vx_ggx_albedo_table(uint32_t n, float* out);

#ifdef __cplusplus
}
#endif
#endif /* VX_RENDER_PIPELINE_H */
