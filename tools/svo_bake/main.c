/* tools/svo_bake/main.c - svo_bake SCENE.svo OUT.probes [options]
 *                         svo_bake --merge OUT.probes PART.probes... */
#define _GNU_SOURCE /* madvise MADV_HUGEPAGE */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <fcntl.h>
#include <pthread.h>
#include <unistd.h>

#ifdef VX_HAVE_IMAGE
#include "formats/image.h"
#endif
#include "probes/probes.h"
#include "render/compact.h"
#include "tools/common/tool.h"
#ifdef VX_HAVE_MPI
#include "tools/common/mpi.h"
#endif
#include "tools/svo_bake/svo_bake.h"

static options default_options(void) {
    options o = {0};
    o.b = vx_probe_bake_desc_defaults(); /* the library's defaults, printed by --help */
    o.shards = 1;
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    o.threads = n > 0 && n < 64 ? (uint32_t)n : 1;
    return o;
}

_Noreturn static void usage(int status) {
    options d = default_options();
    FILE* f = status == 0 ? stdout : stderr;
    fprintf(f,
            "Usage: %s SCENE.svo OUT.probes [options]\n"
            "       %s --merge OUT.probes PART.probes...\n"
            "\n"
            "Which: bakes light field probes for a .svo scene: per probe octahedral maps of\n"
            "       radiance, normal and radial distance, a low-resolution minimum-distance map,\n"
            "       irradiance and distance moments (docs/FORMAT.md, .probes). Path tracing on the\n"
            "       GPU (Vulkan compute, float), or with --cpu on the CPU reference tracer's rays\n"
            "       (double precision); the two agree statistically, each is reproducible by itself.\n"
            "       --shard I/N bakes a part that --merge joins (bake all parts on the same kind of\n"
            "       device); an interrupted run continues from OUT.probes.partial.\n"
            "       Under MPI (mpirun -n N %s ...; where built with MPI) the ranks share the\n"
            "       probes in batches and each writes its probes into the file (MPI-IO; the ranks'\n"
            "       hosts share the output folder): the same bytes whatever N. Each rank saves\n"
            "       every batch it bakes as OUT.probes.ckpt/bFIRST-END.rRANK.probes; a rerun (any\n"
            "       N) bakes only the probes no batch file or OUT.probes.partial holds.\n"
            "\n"
            "Options:\n"
            "  --grid X,Y,Z       probes per axis (default: from --spacing); over the scene's bounds\n"
            "                     the end probes lie a quarter cell outside them, with --bounds at\n"
            "                     the cell centres of that box\n"
            "  --spacing S        world distance between probes (default: bounds diagonal / 8); the grid\n"
            "                     reaches past the bounds so that outer faces have probes outside\n"
            "  --bounds X0,Y0,Z0,X1,Y1,Z1  world box for the grid (default: scene bounds)\n"
            "  --res R            radiance/normal/distance map side, multiple of 16 (default: %u)\n"
            "  --spp N            paths per texel (default: %u)\n"
            "  --bounces N        diffuse bounces after the first hit (default: %d); a path's first 4 metal\n"
            "                     events and its glass events are not counted\n"
            "  --seed S           random seed; same seed, same bytes (default: %llu)\n"
            "  --light X,Y,Z      direction towards the sun (default: %g,%g,%g)\n"
            "  --sun R,G,B        sun irradiance (default: %g,%g,%g); 0,0,0 for none\n"
            "  --sky R,G,B        sky radiance (default: %g,%g,%g); 0,0,0 for none\n"
            "  --shard I/N        bake the I-th of N parts (0-based) (default: %u/%u)\n"
            "  --frame N          an animation's frame N (default: %u)\n"
            "  --threads N        worker threads of the CPU bake (the GPU bake filters on the GPU) (default: %u,\n"
            "                     the CPU count; under MPI the CPU count over the ranks on the host)\n"
            "  --exr DIR          also write the atlases as EXR images into DIR\n"
            "  --max-memory SIZE  refuse a scene that needs more memory than SIZE to read (e.g. 512M)\n"
            "  --load whole|models  how the scene is read (default: whole). models: through the model reader,\n"
            "                     never whole: one pass builds the GPU's compact layout from the models in turn,\n"
            "                     the probes are placed from the layout, then the device is made; the host holds\n"
            "                     the layout and a model per thread, not the scene and the placement's CPU caster\n"
            "                     (about 60 bytes a cell). The same bytes as whole (lavapipe's tests; an H200's\n"
            "                     Cornell box, eph_monu1 and animated demo; the sun's depth map over either\n"
            "                     layout), slower on the GPU by the compact layout's walk (an H200's bake of 512\n"
            "                     probes at R=128, 64 spp: 0.34 s against 0.27 s, a warm process 1.23x), so not\n"
            "                     the default. The GPU bake only (--cpu casts on the scene's trees), any --frame;\n"
            "                     each MPI rank (mpirun) builds the layout and places the probes itself. An\n"
            "                     interrupted run resumes from OUT.probes.partial either way\n"
            "  --fresh            ignore a checkpoint from an interrupted run (under MPI: remove the\n"
            "                     batch checkpoints of OUT.probes.ckpt/)\n"
            "  --cpu              bake on the CPU (default: the GPU)\n"
            "  --no-shadow-map    the GPU bake's sun rays walk their whole length instead of ending where the\n"
            "                     sun's depth map shows nothing further (the same bytes; slower)\n"
            "  --device N|NAME|gpu:K  Vulkan device: the N-th, the first named like NAME, or the (K mod GPUs)-th\n"
            "                     GPU (default: a discrete GPU, else any; under MPI gpu:L, L the rank's place on\n"
            "                     its host)\n"
            "  -q                 no progress bar;  -v: timings and the effective options\n"
            "  -h, --help         this help;  -version: versions\n"
            "\n"
            "Examples:\n"
            "  %s scene.svo scene.probes --spacing 16 --res 64 --spp 32\n"
            "  %s scene.svo part0.probes --shard 0/2 && %s scene.svo part1.probes --shard 1/2\n"
            "  %s --merge scene.probes part0.probes part1.probes\n",
            vx_tool_name, vx_tool_name, vx_tool_name, d.b.res, d.b.spp, d.b.bounces, (unsigned long long)d.b.seed,
            d.b.light_dir[0], d.b.light_dir[1], d.b.light_dir[2], d.b.sun[0], d.b.sun[1], d.b.sun[2], d.b.sky[0], d.b.sky[1],
            d.b.sky[2], d.shard,
            d.shards, d.frame, d.threads, vx_tool_name, vx_tool_name, vx_tool_name, vx_tool_name);
#ifdef VX_HAVE_MPI
    if (status && vx_tool_mpi_launched() && vx_tool_mpi_env_rank() > 0) vx_tool_mpi_linger(); /* rank 0 prints */
#endif
    exit(status);
}

#define usage_error(...) vx_tool_usage_error(usage, __VA_ARGS__)

#define parse_vec vx_tool_parse_vec

/* ---- progress with ETA ---------------------------------------------------------- */

typedef struct eta {
    double t0, last;
    uint64_t base;  /* probes done before the current bake call */
    uint64_t start; /* probes done before this run (resumed) */
    uint64_t total;
} eta;

static bool eta_func(void* user, const char* stage, uint64_t done, uint64_t total) {
    (void)stage, (void)total;
    eta* e = user;
    double now = vx_time_now();
    uint64_t all = e->base + done;
    if (all < e->total && now - e->last < 0.25) return true;
    e->last = now;
    double rate = all > e->start ? (now - e->t0) / (double)(all - e->start) : 0;
    double left = rate * (double)(e->total - all);
    fprintf(stderr, "\r%s: %s/%s probes %3d%%  %.0f s elapsed, ETA %.0f s   ", vx_tool_name, vx_tool_num(all),
            vx_tool_num(e->total), (int)(100.0 * (double)all / (double)(e->total ? e->total : 1)), now - e->t0, left);
    fflush(stderr);
    return true;
}

/* ---- EXR atlases --------------------------------------------------------------------- */

/* Tiles every probe's bordered map (side n+2) into a square-ish atlas. */
static int write_atlas(const char* dir, const char* name, const vx_probe_set* ps, uint32_t n, uint32_t ch,
                       void (*texel)(const vx_probe_set*, size_t probe, size_t t, float* out)) {
    uint32_t side = n + 2, cols = (uint32_t)ceil(sqrt((double)ps->count));
    if (!cols) return 0;
    uint32_t rows = (ps->count + cols - 1) / cols, w = cols * side, h = rows * side;
    float* px = calloc((size_t)w * h * ch, sizeof(float));
    if (!px) return vx_tool_errorf("out of memory for the %s atlas", name);
    for (uint32_t p = 0; p < ps->count; p++)
        for (uint32_t y = 0; y < side; y++)
            for (uint32_t x = 0; x < side; x++) {
                size_t at = ((size_t)(p / cols * side + y) * w + p % cols * side + x) * ch;
                texel(ps, p, (size_t)y * side + x, px + at);
            }
    char path[4096];
    snprintf(path, sizeof path, "%s/%s.exr", dir, name);
    vx_error err = {0};
#ifdef VX_HAVE_IMAGE
    vx_result r = vx_image_write(path, &(vx_image_desc){.width = w, .height = h, .channels = ch, .type = VX_IMAGE_F32, .pixels = px}, &err);
#else
    vx_result r = vx_fail(&err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "built without OpenImageIO: no EXR output");
#endif
    free(px);
    if (r) return vx_tool_error(path, &err);
    return 0;
}

static void tx_radiance(const vx_probe_set* ps, size_t p, size_t t, float* o) {
    size_t n = (size_t)(ps->res + 2) * (ps->res + 2);
    for (int c = 0; c < 3; c++) o[c] = vx_probe_half_to_float(ps->radiance[(p * n + t) * 3 + c]);
}
static void tx_normal(const vx_probe_set* ps, size_t p, size_t t, float* o) {
    size_t n = (size_t)(ps->res + 2) * (ps->res + 2);
    uint32_t v = ps->normal[p * n + t];
    double d[3] = {0, 0, 0};
    if (v) vx_probe_oct_unpack16(v, d);
    for (int c = 0; c < 3; c++) o[c] = (float)d[c];
}
static void tx_distance(const vx_probe_set* ps, size_t p, size_t t, float* o) {
    size_t n = (size_t)(ps->res + 2) * (ps->res + 2);
    uint16_t v = ps->distance[p * n + t];
    o[0] = v == VX_PROBE_DIST_MISS ? INFINITY : (float)(v * ps->dist_step);
}
static void tx_low(const vx_probe_set* ps, size_t p, size_t t, float* o) {
    size_t n = (size_t)(ps->low_res + 2) * (ps->low_res + 2);
    uint16_t v = ps->low[p * n + t];
    o[0] = v == VX_PROBE_DIST_MISS ? INFINITY : (float)(v * ps->dist_step);
}
static void tx_irradiance(const vx_probe_set* ps, size_t p, size_t t, float* o) {
    size_t n = (VX_PROBE_IRR_RES + 2) * (VX_PROBE_IRR_RES + 2);
    for (int c = 0; c < 3; c++) o[c] = vx_probe_half_to_float(ps->irradiance[(p * n + t) * 3 + c]);
}
static void tx_moments(const vx_probe_set* ps, size_t p, size_t t, float* o) {
    size_t n = (VX_PROBE_DIST_RES + 2) * (VX_PROBE_DIST_RES + 2);
    o[0] = ps->moments[(p * n + t) * 2], o[1] = ps->moments[(p * n + t) * 2 + 1], o[2] = 0;
}

int write_exr(const char* dir, const vx_probe_set* ps) {
    mkdir(dir, 0777);
    int rc = 0;
    rc |= write_atlas(dir, "radiance", ps, ps->res, 3, tx_radiance);
    rc |= write_atlas(dir, "normal", ps, ps->res, 3, tx_normal);
    rc |= write_atlas(dir, "distance", ps, ps->res, 1, tx_distance);
    rc |= write_atlas(dir, "low_distance", ps, ps->low_res, 1, tx_low);
    rc |= write_atlas(dir, "irradiance", ps, VX_PROBE_IRR_RES, 3, tx_irradiance);
    rc |= write_atlas(dir, "moments", ps, VX_PROBE_DIST_RES, 3, tx_moments);
    return rc;
}

/* ---- merge ------------------------------------------------------------------------------ */

static int do_merge(const char* out, char** parts, int n) {
    vx_probe_set* sets = calloc((size_t)n, sizeof *sets);
    const vx_probe_set** ptrs = calloc((size_t)n, sizeof *ptrs);
    int rc = 0, loaded = 0;
    vx_error err = {0};
    if (!sets || !ptrs) rc = vx_tool_errorf("out of memory");
    for (int i = 0; i < n && !rc; i++, loaded++) {
        if (vx_probe_read_file(NULL, parts[i], &sets[i], &err)) rc = vx_tool_error(NULL, &err);
        ptrs[i] = &sets[i];
    }
    vx_probe_set m = {0};
    if (!rc && vx_probe_merge(ptrs, (uint32_t)n, NULL, &m, &err)) rc = vx_tool_error(out, &err);
    if (!rc && vx_probe_write_file(NULL, &m, out, &err)) rc = vx_tool_error(out, &err);
    if (!rc) printf("merged %d parts: %u probes -> %s\n", n, m.probe_count, out);
    vx_probe_set_free(&m);
    for (int i = 0; i < loaded; i++) vx_probe_set_free(&sets[i]);
    free(sets);
    free(ptrs);
    return rc;
}

/* ---- the job ----------------------------------------------------------------------- */

/* main()'s start: -v's timeline (a tool's, not the library's) */
static double t_main;

static void stats_line(void* user, vx_log_level level, const char* id, const char* msg) {
    (void)user, (void)level;
    if (!strcmp(id, "gpu.shader_stats")) printf("stats: %s\n", msg);
    if (!strcmp(id, "probe.batch")) printf("batch: %s\n", msg);
    /* the driver's start and each pipeline's compile (or its shader cache's hit) */
    if (!strcmp(id, "gpu.start") || !strcmp(id, "gpu.pipeline")) printf("gpu: at %.3f s: %s\n", vx_time_now() - t_main, msg);
}

/* The checkpoint's names (a checkpoint of another frame must not be resumed) and the --max-memory budget. */
static const vx_allocator* job_start(bake_job* j) {
    if (j->o.frame) snprintf(j->ckpath, sizeof j->ckpath, "%s.f%u.partial", j->out, j->o.frame);
    else snprintf(j->ckpath, sizeof j->ckpath, "%s.partial", j->out);
    if (j->o.frame) snprintf(j->ckdir, sizeof j->ckdir, "%s.f%u.ckpt", j->out, j->o.frame);
    else snprintf(j->ckdir, sizeof j->ckdir, "%s.ckpt", j->out);
    vx_budget_init(&j->budget, j->o.max_memory, NULL);
    return j->o.max_memory ? &j->budget.allocator : NULL;
}

/* A failed read of the scene (whole or by the reader): one line naming the file once. */
static int read_error(const bake_job* j, const char* who, const vx_error* err) {
    if (j->budget.refused)
        fprintf(stderr, "%s: %s%s: needs more than --max-memory %s: %s\n", vx_tool_name, who, j->in,
                vx_tool_bytes(j->budget.limit), err->msg);
    else if (vx_tool_names_file(j->in, err->msg))
        fprintf(stderr, "%s: %s%s\n", vx_tool_name, who, err->msg); /* the library named the file (I/O errors) */
    else
        fprintf(stderr, "%s: %s%s: %s\n", vx_tool_name, who, j->in, err->msg);
    return 1;
}

int bake_job_open(bake_job* j, const char* device, const char* who) {
    vx_error err = {0};
    const vx_allocator* A = job_start(j);
    if (vx_svo_read_file(&(vx_svo_read_desc){.alloc = A}, j->in, &j->file, &err)) return read_error(j, who, &err);
    if (!vx_svo_scene_frame(&j->file, j->o.frame, &j->scene)) {
        fprintf(stderr, "%s: %s%s: no frame %u (the scene has %u)\n", vx_tool_name, who, j->in, j->o.frame,
                vx_svo_scene_frames(&j->file));
        return 1;
    }
    if (j->o.frame) vx_svo_scene_update_bounds(&j->scene); /* the frame's own bounds (the view has frame 0's) */
    if (j->o.cpu) return 0;
    /* -v with VX_GPU_SHADER_STATS=1: the driver's statistics of the bake's kernels (registers, spills) */
    static const vx_logger stats_log = {stats_line, NULL};
    vx_tool_gpu_open_start_narrowed(&j->go, &(vx_gpu_desc){.device = device, .logger = j->o.verbose ? &stats_log : NULL},
                                    &j->scene, j->fallback, j->widen);
    j->opening = true;
    return 0;
}

/* Whether the GPU bake of ps builds the sun's depth map (probe_gpu.c ctx_sun_map: a sun, a light direction). */
static bool bake_uses_sun_map(const vx_probe_bake_desc* b, const vx_probe_set* ps) {
    bool sun = ps->sun[0] > 0 || ps->sun[1] > 0 || ps->sun[2] > 0;
    bool dir = ps->light_dir[0] != 0 || ps->light_dir[1] != 0 || ps->light_dir[2] != 0;
    return !b->no_shadow_map && sun && dir;
}

int bake_job_models(bake_job* j, vx_probe_set* ps, const char* who) {
    vx_error err = {0};
    const vx_allocator* A = job_start(j);
    if (vx_svo_reader_open(&(vx_svo_read_desc){.alloc = A}, j->in, &j->rd, &err)) return read_error(j, who, &err);
    /* pass 1: the compact layout, the models taken in turn (the reader finished: the NODE checksum, the bounds) */
    double t = vx_time_now();
    vx_compact_scene c;
    vx_compact_desc cd = {.alloc = A, .attr_regions = true, .bricks = VX_COMPACT_BRICKS_INLINE};
    if (vx_compact_build_reader(&cd, j->rd, &c, &err)) return read_error(j, who, &err);
    double t_build = vx_time_now() - t;
    j->t_pass[0] = t_build;
    /* the graph with the first pass's bounds: what the placement's grid and the bake read of the scene; frame N > 0
     * with its own bounds, from the models' boxes the pass found (bake_job_open's vx_svo_scene_update_bounds) */
    vx_result r = vx_svo_reader_copy_graph(j->rd, A, &j->file, &err);
    if (!r && !vx_svo_scene_frame(&j->file, j->o.frame, &j->scene)) {
        vx_compact_free(&c);
        fprintf(stderr, "%s: %s%s: no frame %u (the scene has %u)\n", vx_tool_name, who, j->in, j->o.frame,
                vx_svo_scene_frames(&j->file));
        return 1;
    }
    if (!r && j->o.frame) r = vx_svo_reader_update_bounds(j->rd, &j->scene, &err);
    /* the placement from the layout: its geometry answers the caster's test, so no second pass over the file and
     * no caster (VX_BAKE_PLACE=reader: a second pass with vx_probe_place_reader, each model's caster in turn; the
     * same probes, kept to measure against) */
    t = vx_time_now();
    const char* penv = getenv("VX_BAKE_PLACE");
    j->place_passes = penv && !strcmp(penv, "reader");
    if (!r && j->place_passes) r = vx_svo_reader_rewind(j->rd, &err);
    if (!r && j->place_passes) r = vx_probe_place_reader(j->rd, &j->scene, &j->o.b, ps, &err);
    else if (!r) r = vx_probe_place_compact(&c, &j->scene, &j->o.b, ps, &err);
    j->t_pass[1] = vx_time_now() - t;
    if (r) {
        vx_compact_free(&c);
        return read_error(j, who, &err);
    }
    /* the device after the pass and the placement, the GPU scene from the built layout (c taken) */
    t = vx_time_now();
    static const vx_logger stats_log = {stats_line, NULL};
    r = vx_gpu_create(&(vx_gpu_desc){.device = j->o.device, .logger = j->o.verbose ? &stats_log : NULL}, &j->gpu, &err);
    j->t_vk = vx_time_now() - t;
    if (r) {
        vx_compact_free(&c);
        vx_probe_set_free(ps);
        fprintf(stderr, "%s: %sno usable Vulkan device (%s); use --cpu to bake on the CPU\n", vx_tool_name, who, err.msg);
        return 1;
    }
    /* the sun's depth map's node list from the host's layout before it goes (the scene would read its geometry
     * back from the GPU at the map's first build) */
    vx_render_sun_nodes* sun_nodes = NULL;
    j->t_sun = vx_time_now();
    if (bake_uses_sun_map(&j->o.b, ps))
        vx_render_sun_nodes_make(&j->scene, &(vx_render_sun_nodes_desc){.max_side = VX_PROBE_SUN_MAP_SIDE,
                                 .cpu_device = vx_gpu_is_cpu(j->gpu), .layout = &c}, &sun_nodes,
                                 NULL); /* none made: the build lists them */
    j->t_sun = vx_time_now() - j->t_sun;
    r = vx_render_scene_create_compact(j->gpu, j->rd, &c, t_build, NULL, &j->rs, &err);
    if (!r) vx_render_scene_take_sun_nodes(j->rs, sun_nodes);
    else vx_render_sun_nodes_free(sun_nodes);
    /* the GPU scene was made with the graph's instances (frame 0): frame N's from the copy of the graph */
    if (!r && j->o.frame) r = vx_render_scene_set_frame(j->rs, &j->file, j->o.frame, &err);
    j->t_device = vx_time_now() - t;
    j->t_scene = j->t_device - j->t_vk - j->t_sun;
    vx_svo_reader_close(j->rd); /* its buffers and the file: the layout is on the GPU */
    j->rd = NULL;
    if (r) {
        vx_probe_set_free(ps);
        fprintf(stderr, "%s: %s%s: %s (--load whole or --cpu)\n", vx_tool_name, who, j->in, err.msg);
        return 1;
    }
    return 0;
}

int bake_job_device(bake_job* j, const char* who) {
    if (!j->opening) return 0;
    j->opening = false;
    double t = vx_time_now();
    const char* failed = NULL;
    vx_error err = {0};
    vx_result r = vx_tool_gpu_open_wait(&j->go, &j->gpu, &j->rs, &failed, &err);
    j->t_wait = vx_time_now() - t, j->t_device = j->go.seconds, j->t_vk = j->go.device_s;
    if (!r) return 0;
    if (failed && !strcmp(failed, "scene"))
        fprintf(stderr, "%s: %s%s: %s (--cpu bakes on the CPU)\n", vx_tool_name, who, j->in, err.msg);
    else
        fprintf(stderr, "%s: %sno usable Vulkan device (%s); use --cpu to bake on the CPU\n", vx_tool_name, who, err.msg);
    return 1;
}

void bake_job_close(bake_job* j) {
    if (j->opening) { /* a failure before the wait: the thread uses the scene */
        vx_gpu* g = NULL;
        vx_render_scene* rs = NULL;
        if (!vx_tool_gpu_open_wait(&j->go, &g, &rs, NULL, NULL)) j->gpu = g, j->rs = rs;
        j->opening = false;
    }
    double t0 = vx_time_now();
    vx_probe_baker_destroy(j->baker);
    double t1 = vx_time_now();
    vx_render_scene_destroy(j->rs);
    double t2 = vx_time_now();
    vx_gpu_destroy(j->gpu);
    double t3 = vx_time_now();
    vx_svo_scene_free(&j->file);
    vx_svo_reader_close(j->rd);
    j->rd = NULL;
    j->t_close[0] = t1 - t0, j->t_close[1] = t2 - t1, j->t_close[2] = t3 - t2;
    memset(&j->scene, 0, sizeof j->scene);
    j->rs = NULL, j->gpu = NULL, j->baker = NULL;
}

vx_result bake_range(bake_job* j, const vx_probe_bake_desc* bd, vx_probe_set* ps, uint32_t end, vx_error* err) {
    if (j->o.cpu) return vx_probe_bake_more(&j->scene, bd, ps, end, err);
    if (bd->host_filter) return vx_probe_bake_more_gpu(j->rs, &j->scene, bd, ps, end, err);
    /* one set-up for every range: MPI batches took about 45 ms each besides their probes */
    vx_result r = j->baker ? VX_OK : vx_probe_baker_create(j->rs, &j->scene, bd, ps, &j->baker, err);
    return r ? r : vx_probe_baker_run(j->baker, bd, ps, end, err);
}

/* ---- probe maps as bytes --------------------------------------------------------------- */

/* element bytes per probe of the six maps, in the order of probes.h */
static void map_sizes(const vx_probe_set* ps, size_t z[6]) {
    size_t nb = (size_t)(ps->res + 2) * (ps->res + 2), lb = (size_t)(ps->low_res + 2) * (ps->low_res + 2);
    z[0] = nb * 3 * 2;
    z[1] = nb * 4;
    z[2] = nb * 2;
    z[3] = lb * 2;
    z[4] = (VX_PROBE_IRR_RES + 2) * (VX_PROBE_IRR_RES + 2) * 3 * 2;
    z[5] = (VX_PROBE_DIST_RES + 2) * (VX_PROBE_DIST_RES + 2) * 2 * 4;
}

static void map_arrays(vx_probe_set* ps, void*** a) {
    a[0] = (void**)&ps->radiance, a[1] = (void**)&ps->normal, a[2] = (void**)&ps->distance;
    a[3] = (void**)&ps->low, a[4] = (void**)&ps->irradiance, a[5] = (void**)&ps->moments;
}

size_t maps_probe_bytes(const vx_probe_set* ps) {
    size_t z[6], n = 0;
    map_sizes(ps, z);
    for (int i = 0; i < 6; i++) n += z[i];
    return n;
}

void maps_pack(const vx_probe_set* ps, uint32_t from, uint32_t n, uint8_t* buf) {
    size_t z[6];
    void** a[6];
    map_sizes(ps, z);
    map_arrays((vx_probe_set*)ps, a);
    for (int i = 0; i < 6; i++) {
        memcpy(buf, (const uint8_t*)*a[i] + z[i] * (from - ps->first), z[i] * n);
        buf += z[i] * n;
    }
}

void maps_unpack(vx_probe_set* ps, uint32_t from, uint32_t n, const uint8_t* buf) {
    size_t z[6];
    void** a[6];
    map_sizes(ps, z);
    map_arrays(ps, a);
    for (int i = 0; i < 6; i++) {
        memcpy((uint8_t*)*a[i] + z[i] * (from - ps->first), buf, z[i] * n);
        buf += z[i] * n;
    }
}

bool maps_reserve(vx_probe_set* ps, uint32_t n) {
    size_t z[6];
    void** a[6];
    map_sizes(ps, z);
    map_arrays(ps, a);
    for (int i = 0; i < 6; i++) {
        uint8_t* p = vx_calloc(ps->alloc, n ? n : 1, z[i]);
        if (!p) return false;
        if (*a[i] && ps->count) memcpy(p, *a[i], z[i] * (ps->count < n ? ps->count : n));
        vx_free(ps->alloc, *a[i]);
        *a[i] = p;
    }
    return true;
}

void maps_free(vx_probe_set* ps) {
    void** a[6];
    map_arrays(ps, a);
    for (int i = 0; i < 6; i++) {
        vx_free(ps->alloc, *a[i]);
        *a[i] = NULL;
    }
    ps->count = 0;
}

/* ---- checkpoint ------------------------------------------------------------------------ */

bool same_grid(const vx_probe_set* placed, const vx_probe_set* ck) {
    vx_probe_set a = *placed, b = *ck;
    a.count = b.count = 0;
    a.first = b.first = 0;
    uint8_t *da = NULL, *db = NULL;
    size_t na = 0, nb = 0;
    bool same = !vx_probe_write(&a, NULL, &da, &na, NULL) && !vx_probe_write(&b, NULL, &db, &nb, NULL) && na == nb &&
                !memcmp(da, db, na);
    free(da);
    free(db);
    return same;
}

/* The GPU side of a finished bake (baker, scene on the GPU, device) torn down on a thread of its own while the
 * output's end (its last blocks, sync and rename) runs: the driver's teardown (0.045 s on an H200 for an empty
 * device, 0.07 s with 1 GiB allocated, bench/out's vkstart; the same whether explicit or in exit()) overlaps the
 * final sync (0.03 s) instead of following the file. The output needs nothing of the GPU by then: the baked
 * maps are in the host's probe set. */
typedef struct gpu_closer {
    bake_job* j;
    pthread_t thread;
    bool started;
    double seconds;
} gpu_closer;

static void* close_gpu_main(void* arg) {
    gpu_closer* c = arg;
    double t0 = vx_time_now();
    vx_probe_baker_destroy(c->j->baker);
    double t1 = vx_time_now();
    vx_render_scene_destroy(c->j->rs);
    double t2 = vx_time_now();
    vx_gpu_destroy(c->j->gpu);
    double t3 = vx_time_now();
    c->j->baker = NULL, c->j->rs = NULL, c->j->gpu = NULL;
    c->j->t_close[0] = t1 - t0, c->j->t_close[1] = t2 - t1, c->j->t_close[2] = t3 - t2;
    c->seconds = t3 - t0;
    return NULL;
}

/* Whether a finished single-process bake ends without freeing the rest of its memory (the GPU side is torn
 * down by then, close_gpu_main): the file is written, synced and renamed, and the system returns the memory at
 * exit anyway. Builds with AddressSanitizer (whose leak check runs at exit) and VX_BAKE_TEARDOWN=1 (valgrind)
 * free it. */
static bool exit_without_teardown(void) {
#if defined(__SANITIZE_ADDRESS__)
    return false;
#else
#if defined(__has_feature)
#if __has_feature(address_sanitizer)
    return false;
#endif
#endif
    const char* env = getenv("VX_BAKE_TEARDOWN");
    return !(env && !strcmp(env, "1"));
#endif
}

double checkpoint_interval(void) {
    const char* env = getenv("VX_BAKE_CHECKPOINT_S");
    double s = env ? atof(env) : 20.0;
    return s >= 0 ? s : 20.0;
}

bool resume_checkpoint(const bake_job* j, vx_probe_set* ps, uint32_t end) {
    if (j->o.fresh || access(j->ckpath, F_OK) != 0) return false;
    vx_probe_set ck;
    vx_error e2 = {0};
    /* the checkpoint is a baked prefix of this job's range */
    if (!vx_probe_read_file(NULL, j->ckpath, &ck, &e2) && same_grid(ps, &ck) && ck.first == ps->first &&
        ck.first + ck.count <= end) {
        printf("resuming from %s: %u of %u probes done\n", j->ckpath, ck.count, end - ps->first);
        vx_probe_set_free(ps);
        *ps = ck;
        return true;
    }
    if (!e2.code) vx_probe_set_free(&ck);
    fprintf(stderr, "%s: %s: not a checkpoint of this job, starting over\n", vx_tool_name, j->ckpath);
    return false;
}

/* ---- one process ---------------------------------------------------------------------- */

/* The GPU bake's progress (after each batch, the maps of a prefix of the
 * range in the set): the progress line, and the baked prefix written as a
 * checkpoint when checkpoint_interval() has passed since the last one. */
typedef struct ck_state {
    eta* e;           /* NULL: no progress line */
    vx_probe_set* ps; /* the set being baked (its count is updated at the end) */
    vx_probe_stream* out; /* the output, written as the batches come (NULL: at the end) */
    double t_out;         /* seconds spent writing it here */
    const char* path;
    uint32_t base, total; /* baked before the call; the range's probes */
    double interval, t_ck;
    vx_error err;            /* a failed write (ends the bake) */
    const char* failed_path; /* of which file */
} ck_state;

static bool ck_progress(void* user, const char* stage, uint64_t done, uint64_t total) {
    ck_state* c = user;
    if (c->e) eta_func(c->e, stage, done, total);
    double now = vx_time_now();
    if (c->out && c->base + done < c->total) {
        /* the batch's maps into the output while the GPU traces the next batch (the last batch's after the
         * loop, beside the GPU's teardown) */
        vx_probe_set v = *c->ps;
        v.count = c->base + (uint32_t)done;
        if (vx_probe_stream_put(c->out, &v, v.first + v.count, &c->err)) {
            c->failed_path = c->out->file.path;
            return false;
        }
        c->t_out += vx_time_now() - now;
    }
    if (now - c->t_ck < c->interval || c->base + done >= c->total) return true;
    vx_probe_set v = *c->ps;
    v.count = c->base + (uint32_t)done;
    if (vx_probe_write_file(NULL, &v, c->path, &c->err)) {
        c->failed_path = c->path;
        return false;
    }
    c->t_ck = vx_time_now();
    return true;
}

/* The probe set's memory (its maps: 105 MB for 512 probes at R=128) in transparent huge pages where the
 * system gives them on request (MADV_HUGEPAGE): the bake copies every batch's maps into fresh pages and frees
 * them at the end; in 4 KiB pages the copies and the unmapping took 52 ms and 10 ms for 105 MB on the dev
 * machine, in 2 MiB pages 12 ms and 0.5 ms. On an H200 host the last batch's copy (after the GPU's last batch)
 * took 0.005 -> 0.003 s, the maps' release 0.007 -> 0.001 s, and the whole process 0.628 -> 0.610 s.
 * Small blocks come from malloc. A header before each block says which. */
enum { HUGE_MIN = 4 << 20, HUGE_PAGE = 2 << 20, HUGE_HEAD = 64 };
typedef struct huge_head {
    void* base;    /* the mapping (NULL: a malloc block starting at the header) */
    size_t length; /* its length */
} huge_head;

static void* huge_alloc(void* user, size_t size) {
    (void)user;
    if (size > SIZE_MAX - 2 * HUGE_PAGE) return NULL;
    if (size < HUGE_MIN) {
        uint8_t* p = malloc(size + HUGE_HEAD);
        if (!p) return NULL;
        ((huge_head*)p)->base = NULL;
        return p + HUGE_HEAD;
    }
    size_t length = size + HUGE_HEAD + HUGE_PAGE;
    uint8_t* base = mmap(NULL, length, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (base == MAP_FAILED) return NULL;
    /* the block's start on a huge page's boundary: the header is the first 64 bytes of that page */
    uint8_t* at = (uint8_t*)(((uintptr_t)base + HUGE_PAGE - 1) & ~(uintptr_t)(HUGE_PAGE - 1));
    (void)madvise(at, size + HUGE_HEAD, MADV_HUGEPAGE); /* a hint: 4 KiB pages where refused */
    *(huge_head*)at = (huge_head){base, length};
    return at + HUGE_HEAD;
}

static void huge_free(void* user, void* ptr) {
    (void)user;
    if (!ptr) return;
    huge_head* h = (huge_head*)((uint8_t*)ptr - HUGE_HEAD);
    if (h->base) munmap(h->base, h->length);
    else free(h);
}

static const vx_allocator huge_allocator = {huge_alloc, huge_free, NULL};

static int bake_single(bake_job* j) {
    options* o = &j->o;
    vx_error err = {0};
    double t_in = vx_time_now();
    vx_probe_set ps;
    o->b.first = o->b.count = 0;
    if (!o->b.alloc) o->b.alloc = &huge_allocator;
    /* --load models: the layout from the file, the placement from the layout, then the device */
    if (o->load_models && bake_job_models(j, &ps, "")) {
        bake_job_close(j);
        return 1;
    }
    /* the device opens on its own thread while the probes are placed */
    if (!o->load_models && bake_job_open(j, o->device, "")) {
        bake_job_close(j);
        return 1;
    }
    double t0 = vx_time_now();
    if (!o->load_models && vx_probe_place(&j->scene, &o->b, &ps, &err)) {
        bake_job_close(j);
        return vx_tool_error(j->in, &err);
    }
    uint32_t total = ps.probe_count;
    uint32_t first = (uint32_t)((uint64_t)total * o->shard / o->shards),
             end = (uint32_t)((uint64_t)total * (o->shard + 1) / o->shards);
    /* the shard's range (what vx_probe_place gives for it; an empty shard,
     * more shards than probes, still gets a valid file) */
    o->b.first = first;
    o->b.count = end - first;
    ps.first = first, ps.count = 0;
    double t_place = vx_time_now() - t0;
    /* the sun's depth map's node list on the host while the device opens, rather than after it (from the node
     * words read back: 0.009-0.015 s of the set-up on an H200 host, which waited 0.03-0.09 s for its device) */
    vx_render_sun_nodes* sun_nodes = NULL;
    double t_ahead = vx_time_now();
    /* (made for a GPU: a CPU device's scene lists its own, with its coarser texels) */
    if (j->opening && bake_uses_sun_map(&o->b, &ps))
        vx_render_sun_nodes_make(&j->scene, &(vx_render_sun_nodes_desc){.max_side = VX_PROBE_SUN_MAP_SIDE}, &sun_nodes,
                                 NULL); /* none made: the build lists them */
    t_ahead = o->load_models ? j->t_sun : vx_time_now() - t_ahead;
    if (bake_job_device(j, "")) {
        vx_render_sun_nodes_free(sun_nodes);
        vx_probe_set_free(&ps);
        bake_job_close(j);
        return 1;
    }
    if (j->rs && sun_nodes) vx_render_scene_take_sun_nodes(j->rs, sun_nodes); /* (--load models took its own) */
    else vx_render_sun_nodes_free(sun_nodes);
    if (j->gpu) printf("device: %s%s\n", vx_gpu_device_name(j->gpu), vx_gpu_is_cpu(j->gpu) ? " (software)" : "");
    else printf("device: CPU (%u threads, double precision)\n", o->threads);
    /* the host's peak so far: the scene (or the layout from the reader's passes), the placement, the GPU scene (on a
     * CPU device its buffers are host memory too); the bake's own comes after */
    if (o->verbose) printf("host: peak %s before the bake (%s)\n", vx_tool_bytes(vx_peak_rss()), o->load_models ? "--load models" : "--load whole");
    if (o->load_models && o->verbose) {
        vx_render_layout_info li;
        vx_render_scene_layout(j->rs, &li);
        printf("load: models (the model reader): the compact layout %.3f s (%.3f MB, %s; %u pass%s over the file), "
               "the placement %.3f s (%s), then the device %.3f s and the GPU scene %.3f s\n",
               j->t_pass[0], li.compact_bytes / 1e6, li.brick_dict ? "brick dictionary" : "bricks in blocks",
               li.file_passes, li.file_passes == 1 ? "" : "es", j->t_pass[1],
               j->place_passes ? "a second pass, each model's caster" : "from the layout", j->t_vk, j->t_scene);
    }
    int rc = 0;
    uint32_t moved = 0, disabled = 0;
    for (uint32_t i = 0; i < ps.probe_count; i++)
        moved += ps.probes[i].state == VX_PROBE_MOVED, disabled += ps.probes[i].state == VX_PROBE_DISABLED;
    printf("grid: %ux%ux%u = %s probes (%u moved out of voxels, %u disabled), spacing %g,%g,%g; baking %u..%u\n",
           ps.grid[0], ps.grid[1], ps.grid[2], vx_tool_num(ps.probe_count), moved, disabled, ps.spacing[0],
           ps.spacing[1], ps.spacing[2], first, end);
    /* resume from a checkpoint of the same job */
    resume_checkpoint(j, &ps, end);
    double t_bake0 = vx_time_now();
    eta e = {.t0 = vx_time_now(), .base = ps.count, .start = ps.count, .total = end - first};
    bool show = !o->quiet && isatty(2);
    vx_probe_bake_desc bd = o->b;
    /* VX_BAKE_KERNEL=inline|one: the GPU bake's kernel fixed (vx_probe_bake_desc.kernel; the same bytes), to
     * measure each where the default takes the one the driver has ready first */
    const char* kenv = getenv("VX_BAKE_KERNEL");
    if (kenv && !strcmp(kenv, "inline")) bd.kernel = VX_PROBE_KERNEL_INLINE;
    if (kenv && !strcmp(kenv, "one")) bd.kernel = VX_PROBE_KERNEL_ONE_WALK;
    /* VX_BAKE_BEAM=off: the camera rays walk from their probe (vx_probe_bake_desc.no_beam; the same bytes), to
     * measure the beam pass and to test that its start distances change nothing, in either layout */
    const char* benv = getenv("VX_BAKE_BEAM");
    if (benv && !strcmp(benv, "off")) bd.no_beam = true;
    vx_probe_bake_stats st = {0};
    if (o->verbose && j->gpu) bd.stats = &st;
    if (show) bd.progress = (vx_progress){eta_func, &e};
    double interval = checkpoint_interval(), t_ck = vx_time_now();
    /* the output is written as the probes are baked (an empty shard's at the end) */
    vx_probe_stream out;
    bool streamed = end > first;
    double t_open = vx_time_now();
    if (streamed && vx_probe_stream_open(&out, &ps, end, j->out, NULL, &err)) {
        vx_probe_set_free(&ps);
        bake_job_close(j);
        return vx_tool_error(j->out, &err);
    }
    double t_out = 0;
    t_open = vx_time_now() - t_open;
    if (j->gpu) {
        /* the GPU bakes the whole range in one call (one set-up, its batches
         * overlapped), checkpointing the baked prefix between batches; steps of
         * 16 probes and more, each a call of its own, took 2.4 s for 512
         * probes at R=128 on an H200 where one call takes 0.9 s */
        ck_state c = {.e = show ? &e : NULL, .ps = &ps, .out = streamed ? &out : NULL, .path = j->ckpath,
                      .base = ps.count, .total = end - first, .interval = interval, .t_ck = t_ck};
        bd.progress = (vx_progress){ck_progress, &c};
        if (ps.first + ps.count < end && bake_range(j, &bd, &ps, end, &err))
            rc = c.failed_path ? vx_tool_error(c.failed_path, &c.err) : vx_tool_error(j->in, &err);
        t_out = c.t_out;
    }
    /* the CPU bakes in steps of about 5-40 s of work (at least one probe),
     * writing the baked prefix as a checkpoint when checkpoint_interval() has
     * passed since the last one. The step is sized by the bake's own time:
     * when it also counted the checkpoint writes, a prefix that took over 5 s
     * to write stopped the steps from growing, and every small step then
     * rewrote the whole growing prefix (4,096 probes at R=128 on an H200:
     * 170 s, the bake itself 15 s) */
    uint32_t step = 2 * o->threads;
    while (!rc && !j->gpu && ps.first + ps.count < end) {
        uint32_t at = ps.first + ps.count, to = at + step > end ? end : at + step;
        e.base = ps.count;
        double t_step = vx_time_now();
        if (bake_range(j, &bd, &ps, to, &err)) {
            rc = vx_tool_error(j->in, &err);
            break;
        }
        double now = vx_time_now(), dt = now - t_step;
        if (ps.first + ps.count < end) {
            if (now - t_ck >= interval) {
                if (vx_probe_write_file(NULL, &ps, j->ckpath, &err)) {
                    rc = vx_tool_error(j->ckpath, &err);
                    break;
                }
                t_ck = vx_time_now();
            }
            step = dt < 5 ? step * 2 : (dt > 40 ? (step > 1 ? step / 2 : 1) : step);
        }
        double tw = vx_time_now();
        if (streamed && vx_probe_stream_put(&out, &ps, ps.first + ps.count, &err)) rc = vx_tool_error(j->out, &err);
        t_out += vx_time_now() - tw;
    }
    if (show) fprintf(stderr, "\n");
    double t1 = vx_time_now(), t_bake = t1 - t0;
    /* the GPU's teardown beside the output's end (a bake that failed tears down after its message) */
    gpu_closer closer = {.j = j};
    bool on_gpu = j->gpu != NULL;
    if (!rc && j->gpu) closer.started = !pthread_create(&closer.thread, NULL, close_gpu_main, &closer);
    /* what is left of the output (probes resumed and not passed yet, the last batch), its CRC, sync and name */
    double t_put = vx_time_now(), t_commit = 0;
    if (!rc && streamed && vx_probe_stream_put(&out, &ps, end, &err)) rc = vx_tool_error(j->out, &err);
    t_put = vx_time_now() - t_put;
    if (!rc && streamed) {
        t_commit = vx_time_now();
        if (vx_probe_stream_commit(&out, &err)) rc = vx_tool_error(j->out, &err);
        t_commit = vx_time_now() - t_commit;
    }
    if (!rc && !streamed && vx_probe_write_file(NULL, &ps, j->out, &err)) rc = vx_tool_error(j->out, &err);
    if (rc && streamed) vx_probe_stream_abort(&out);
    double t_write = vx_time_now() - t1, t_file = vx_time_now() - t_in;
    /* the maps' memory freed while the GPU's teardown runs rather than unmapped by the exit after it */
    vx_probe_set done = ps; /* what the lines below print */
    double t_free = vx_time_now();
    if (!o->exr_dir) vx_probe_set_free(&ps);
    t_free = vx_time_now() - t_free;
    double t_join = vx_time_now();
    if (closer.started) pthread_join(closer.thread, NULL);
    t_join = vx_time_now() - t_join;
    if (!rc) {
        remove(j->ckpath);
        printf("baked %u probes at %ux%u, %u spp, %u bounces in %.2f s (%.3f s per probe); distance step %.4g (max error %.4g)\n",
               done.count, done.res, done.res, done.spp, done.bounces, t_bake, done.count ? t_bake / done.count : 0.0,
               done.dist_step, done.dist_max_error);
        printf("wrote %s\n", j->out);
        if (o->verbose) {
            printf("times: scene %.3f s, placement %.3f s, device %.3f s on its thread (Vulkan %.3f s; waited %.3f s), "
                   "bake %.3f s (of it writing the output %.3f s), the output's end %.3f s (last blocks %.3f s, CRC, "
                   "sync and rename %.3f s); %.3f s from the scene to the file; the maps freed in %.3f s\n",
                   t0 - t_in, t_place, j->t_device, j->t_vk, j->t_wait, t1 - t_bake0, t_out, t_write, t_put, t_commit,
                   t_file, t_free);
            if (on_gpu)
                printf("bake: output opened %.3f s, setup %.3f s (context %.3f of it sun map %.3f, pipelines %.3f, slots %.3f), arrays %.3f s, "
                       "loop %.3f s (%u batches), GPU trace %.3f s, filter %.3f s, copy %.3f s, busy %.0f%% of the loop, "
                       "waits %.3f s, stores %.3f s; first batch's latency %.3f s, after the last batch's wait %.3f s; "
                       "kernel: %s\n",
                       t_open, st.setup, st.setup_ctx, st.sun_map, st.setup_pipes, st.setup_slots, st.grow, st.loop, st.batches,
                       st.gpu_trace, st.gpu_filter, st.gpu_copy, 100 * st.busy, st.wait, st.download, st.first_latency, st.tail,
                       st.one_walk ? "one walk" : "four walks");
            if (on_gpu && st.sun_map_side)
                printf("sun map: %u texels a side, %u nodes listed in %.3f s, built in %.3f ms GPU; %.3f s in all; "
                       "listed ahead in %.3f s (%s); build %.3f s wall\n",
                       st.sun_map_side, st.sun_map_nodes, st.sun_map_list, st.sun_map_gpu * 1e3, st.sun_map, t_ahead,
                       st.sun_map_ahead > 0 ? "used" : "not used", st.sun_map_build);
        }
    }
    if (!rc && o->exr_dir) rc = write_exr(o->exr_dir, &ps);
    vx_probe_set_free(&ps);
    if (!rc && o->verbose && on_gpu)
        printf("timeline: s since main(): scene read %.3f, placed %.3f, device ready %.3f, bake from %.3f, set up %.3f, "
               "loop end %.3f, file renamed %.3f, teardown joined %.3f\n",
               t0 - t_main, t0 + t_place - t_main, t0 + t_place + t_ahead + j->t_wait - t_main, t_bake0 - t_main,
               t_bake0 + t_open + st.setup - t_main, t1 - t_main, t1 + t_write - t_main, vx_time_now() - t_main);
    if (!rc && o->verbose && closer.started)
        printf("close: the GPU torn down beside the output's end in %.3f s (baker %.3f, scene %.3f, device %.3f), "
               "waited for %.3f s after it\n",
               closer.seconds, j->t_close[0], j->t_close[1], j->t_close[2], t_join);
    if (!rc && exit_without_teardown()) {
        if (o->verbose) printf("close: the host's memory left to the process's exit (VX_BAKE_TEARDOWN=1: freed here)\n");
        fflush(stdout);
        fflush(stderr);
        _exit(0);
    }
    /* the end of the process besides exit(): the baker's, the scene's and the
     * device's teardown, the part of the fixed cost the lines above miss */
    double t_close = vx_time_now();
    bake_job_close(j);
    if (!rc && o->verbose)
        printf("close: %.3f s (baker %.3f, scene %.3f, device %.3f); %.3f s from the scene to here\n",
               vx_time_now() - t_close, j->t_close[0], j->t_close[1], j->t_close[2], vx_time_now() - t_in);
    return rc;
}

int main(int argc, char** argv) {
    t_main = vx_time_now();
    vx_tool_init(argc, argv);
    options o = default_options();
#ifdef VX_HAVE_MPI
    /* under mpirun only rank 0 prints usage errors and the effective options */
    int saved[2];
    vx_tool_mpi_mute(saved);
#endif
    const char* pos[2];
    int npos = 0;
    char** merge_parts = NULL;
    int nmerge = 0;
    for (int i = 1; i < argc; i++) {
        const char* a = argv[i];
/* the option's argument, argv[i] after it (vx_tool_arg: a usage error where none is left) */
#define ARG() vx_tool_arg(argc, argv, &i, usage)
        if (!strcmp(a, "-h") || !strcmp(a, "-help") || !strcmp(a, "--help")) usage(0);
        else if (!strcmp(a, "-version") || !strcmp(a, "--version")) {
            printf("%s %s (probes format %u, svo format %u)\n", vx_tool_name, VX_VERSION_STRING, VX_PROBE_FORMAT_VERSION,
                   VX_SVO_FORMAT_VERSION);
            return 0;
        } else if (!strcmp(a, "--merge")) {
            o.merge = true;
            merge_parts = argv + i + 1;
            nmerge = argc - i - 1;
            break;
        } else if (!strcmp(a, "--grid")) {
            double v[3];
            if (!parse_vec(ARG(), v, 3)) usage_error("bad grid '%s' (X,Y,Z)", argv[i]);
            for (int k = 0; k < 3; k++) {
                if (!(v[k] >= 1 && v[k] <= 4096 && v[k] == floor(v[k]))) usage_error("bad grid '%s' (1..4096 each)", argv[i]);
                o.b.grid[k] = (uint32_t)v[k];
            }
        } else if (!strcmp(a, "--spacing")) {
            if (!parse_vec(ARG(), &o.b.spacing, 1) || !(o.b.spacing > 0)) usage_error("bad spacing '%s'", argv[i]);
        } else if (!strcmp(a, "--bounds")) {
            double v[6];
            if (!parse_vec(ARG(), v, 6)) usage_error("bad bounds '%s' (X0,Y0,Z0,X1,Y1,Z1)", argv[i]);
            o.b.bounds_set = true;
            memcpy(o.b.bounds_lo, v, 24);
            memcpy(o.b.bounds_hi, v + 3, 24);
        } else if (!strcmp(a, "--res")) {
            if (!vx_tool_parse_u32(ARG(), &o.b.res) || o.b.res < 16 || o.b.res % 16 || o.b.res > VX_PROBE_MAX_RES)
                usage_error("bad res '%s' (a multiple of 16, 16..1024)", argv[i]);
        } else if (!strcmp(a, "--spp")) {
            if (!vx_tool_parse_u32(ARG(), &o.b.spp) || !o.b.spp || o.b.spp > 65536) usage_error("bad spp '%s'", argv[i]);
        } else if (!strcmp(a, "--bounces")) {
            uint32_t v;
            if (!vx_tool_parse_u32(ARG(), &v) || v > 64) usage_error("bad bounces '%s' (0..64)", argv[i]);
            o.b.bounces = v ? (int32_t)v : -1;
        } else if (!strcmp(a, "--seed")) {
            char* end;
            o.b.seed = strtoull(ARG(), &end, 10);
            if (end == argv[i] || *end) usage_error("bad seed '%s'", argv[i]);
        } else if (!strcmp(a, "--light")) {
            if (!parse_vec(ARG(), o.b.light_dir, 3)) usage_error("bad light direction '%s'", argv[i]);
        } else if (!strcmp(a, "--sun")) {
            if (!parse_vec(ARG(), o.b.sun, 3)) usage_error("bad sun '%s'", argv[i]);
            o.b.no_sun = !o.b.sun[0] && !o.b.sun[1] && !o.b.sun[2];
        } else if (!strcmp(a, "--sky")) {
            if (!parse_vec(ARG(), o.b.sky, 3)) usage_error("bad sky '%s'", argv[i]);
            o.b.black_sky = !o.b.sky[0] && !o.b.sky[1] && !o.b.sky[2];
        } else if (!strcmp(a, "--frame")) {
            if (!vx_tool_parse_u32(ARG(), &o.frame)) usage_error("bad frame '%s'", argv[i]);
        } else if (!strcmp(a, "--shard")) {
            char c;
            if (sscanf(ARG(), "%u/%u%c", &o.shard, &o.shards, &c) != 2 || !o.shards || o.shard >= o.shards)
                usage_error("bad shard '%s' (I/N with I < N)", argv[i]);
        } else if (!strcmp(a, "--threads")) {
            if (!vx_tool_parse_u32(ARG(), &o.threads) || !o.threads || o.threads > 64)
                usage_error("bad threads '%s' (1..64)", argv[i]);
            o.threads_set = true;
        } else if (!strcmp(a, "--max-memory")) {
            if (!vx_tool_parse_bytes(ARG(), &o.max_memory) || !o.max_memory)
                usage_error("bad --max-memory value '%s' (bytes, e.g. 512M or 4G)", argv[i]);
        } else if (!strcmp(a, "--load")) {
            const char* v = ARG();
            if (strcmp(v, "whole") && strcmp(v, "models")) usage_error("bad --load '%s' (whole or models)", v);
            o.load_models = !strcmp(v, "models");
        } else if (!strcmp(a, "--exr")) {
            o.exr_dir = ARG();
#ifndef VX_HAVE_IMAGE
            usage_error("%s", "--exr: this svo_bake was built without OpenImageIO");
#endif
        } else if (!strcmp(a, "--device")) {
            o.device = ARG();
        } else if (!strcmp(a, "--cpu")) o.cpu = true;
        else if (!strcmp(a, "--fresh")) o.fresh = true;
        else if (!strcmp(a, "--no-shadow-map")) o.b.no_shadow_map = true;
        else if (!strcmp(a, "-q")) o.quiet = true;
        else if (!strcmp(a, "-v")) o.verbose = true;
        else if (a[0] == '-' && a[1]) usage_error("\"%s\" is not a valid option", a);
        else if (npos < 2) pos[npos++] = a;
        else usage_error("unexpected argument '%s'", a);
#undef ARG
    }
    if (o.merge) {
        if (npos != 0 || nmerge < 2) usage_error("%s", "--merge needs OUT.probes and at least one part");
        return do_merge(merge_parts[0], merge_parts + 1, nmerge - 1);
    }
    if (npos != 2) usage_error("%s", npos == 0 ? "no scene and output given" : "no output file given");
    if ((o.b.grid[0] || o.b.grid[1] || o.b.grid[2]) && o.b.spacing) usage_error("%s", "give --grid or --spacing, not both");
    if (o.cpu && o.device) usage_error("%s", "--cpu conflicts with --device");
    if (o.load_models && o.cpu) usage_error("%s", "--load models is for the GPU bake (--cpu casts on the scene's trees: --load whole)");
    o.b.threads = o.threads;
    if (o.verbose)
        printf("%s %s %s --res %u --spp %u --bounces %d --seed %llu --shard %u/%u --threads %u\n", vx_tool_name, pos[0],
               pos[1], o.b.res, o.b.spp, o.b.bounces < 0 ? 0 : o.b.bounces, (unsigned long long)o.b.seed, o.shard,
               o.shards, o.threads);
#ifdef VX_HAVE_MPI
    if (vx_tool_mpi_launched() && o.shards > 1)
        usage_error("%s", "--shard is for separate processes; under mpirun the ranks share the probes");
    vx_tool_mpi_unmute(saved);
    if (vx_tool_mpi_launched()) return bake_mpi(&o, pos[0], pos[1]);
#endif
    bake_job j = {.o = o, .in = pos[0], .out = pos[1]};
    return bake_single(&j);
}
