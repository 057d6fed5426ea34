/* tools/svo_bake/svo_bake.h - what svo_bake's single-process path (main.c)
 * and its MPI path (mpi.c) share: the options, the opened job (scene,
 * device, checkpoint name), baking a probe range on the CPU or the GPU, the
 * checkpoint check, and moving a range of probe maps in and out of a byte
 * buffer (a message, or a part of the output set). */
#ifndef VX_SVO_BAKE_H
#define VX_SVO_BAKE_H

#include <stdbool.h>
#include <stdint.h>

#include "probes/probes.h"
#include "tools/common/gpu_open.h"

typedef struct options {
    vx_probe_bake_desc b;
    uint32_t shard, shards;
    const char* exr_dir;
    const char* device;
    bool merge, cpu, quiet, verbose, fresh;
    bool threads_set; /* --threads given (MPI: otherwise the CPUs are split over the host's ranks) */
    uint64_t max_memory; /* --max-memory for reading the scene, 0: no limit */
    uint32_t threads;
    uint32_t frame; /* --frame: an animation's frame to bake (default 0) */
    bool load_models; /* --load models: the scene through the model reader (bake_job_models) */
} options;

typedef struct bake_job {
    options o;
    const char* in;
    const char* out;
    char ckpath[4096]; /* OUT.probes.partial (OUT.probes.fN.partial for frame N > 0) */
    char ckdir[4096];  /* OUT.probes.ckpt (.fN.ckpt): the MPI ranks' batch checkpoints */
    vx_budget budget;     /* --max-memory (the scene's arrays come from it) */
    vx_svo_scene file;    /* what was read */
    vx_svo_scene scene;   /* the view of o.frame: what is baked */
    vx_gpu* gpu;          /* NULL with --cpu */
    vx_render_scene* rs;  /* NULL with --cpu */
    vx_probe_baker* baker; /* the GPU bake kept across bake_range calls (made at the first) */
    vx_tool_gpu_open go;  /* the device opening on its own thread */
    bool opening;         /* go started, not waited for */
    const char* fallback; /* a rank whose driver sees only its GPU: the device where that fails, */
    void (*widen)(void);  /* after widen() (vx_tool_gpu_open_start_narrowed); NULL elsewhere */
    double t_device;      /* seconds the device and the scene's upload took on its thread */
    double t_vk;          /* of it the device's (vx_gpu_create) */
    double t_wait;        /* seconds bake_job_device waited for it */
    double t_close[3];    /* seconds bake_job_close took for the baker, the scene and the device */
    /* --load models: the reader (closed once the GPU scene is made), the two passes' and the device's times */
    vx_svo_model_reader* rd;
    double t_pass[2]; /* the compact layout (pass 1), the placement */
    bool place_passes; /* the placement by a second pass (VX_BAKE_PLACE=reader), not from the layout */
    double t_scene;   /* the GPU scene from the layout (upload) */
    double t_sun;     /* the sun map's node list from the layout (before the upload; 0: none made) */
} bake_job;

/* Reads the scene and starts opening the device (o.device; NULL: the default
 * pick) on a thread of its own, so that the driver's start-up overlaps the
 * placement (and MPI_Init); bake_job_device waits for it. On failure prints
 * one line (prefixed with `who`, e.g. "rank 1: ", may be "") and returns 1;
 * bake_job_close is safe either way. */
int bake_job_open(bake_job* j, const char* device, const char* who);
/* --load models, instead of bake_job_open and vx_probe_place: the scene
 * through the model reader (svo/svo.h), never whole. One pass builds the
 * compact layout (vx_compact_build_reader), the probes are placed into *ps
 * from it (vx_probe_place_compact, j->o.b's grid; VX_BAKE_PLACE=reader: a
 * second pass, vx_probe_place_reader), then
 * the device is made and the GPU scene is the built layout
 * (vx_render_scene_create_compact), with the sun's depth map's node list
 * made from the layout where the bake uses the map (vx_render_sun_nodes_desc
 * .layout); j->scene is the view of frame j->o.frame
 * of the graph (no model arrays), which the GPU bake needs beside the layout
 * (materials, instances, bounds): frame N > 0 with its own bounds from the
 * models' boxes of the pass (vx_svo_reader_update_bounds) and its instances
 * set on the GPU scene (vx_render_scene_set_frame). The host holds the
 * layout, a model per build thread and the graph; the device is made after
 * the placement (an idle device lowers its clock, branch load2). The GPU only
 * (the CPU bake casts on the scene's trees). On failure prints one line as
 * bake_job_open and returns 1. */
int bake_job_models(bake_job* j, vx_probe_set* ps, const char* who);
/* Waits for the device (nothing to wait for with --cpu); on failure prints
 * one line as bake_job_open and returns 1. */
int bake_job_device(bake_job* j, const char* who);
void bake_job_close(bake_job* j);

/* Bakes probes [ps->first + ps->count, end) of ps on the job's device; every
 * ps of one job shares its placement's probes (views of the placed set). */
vx_result bake_range(bake_job* j, const vx_probe_bake_desc* bd, vx_probe_set* ps, uint32_t end, vx_error* err);

/* Whether the probe set ck (a checkpoint, a batch, a shard) belongs to the
 * job that placed `placed`: its grid section (probes, grid and bake
 * parameters) is byte-identical to the placement's, whatever range it holds. */
bool same_grid(const vx_probe_set* placed, const vx_probe_set* ck);

/* Seconds between checkpoints of the baked prefix (OUT.probes.partial), in
 * one process and on MPI's rank 0: VX_BAKE_CHECKPOINT_S, default 20. */
double checkpoint_interval(void);

/* Replaces *ps (placed, nothing baked) by the checkpoint j->ckpath when that
 * belongs to the same job and lies within [ps->first, end); says so on
 * stdout. Returns whether it did. */
bool resume_checkpoint(const bake_job* j, vx_probe_set* ps, uint32_t end);

/* ---- probe maps as bytes ------------------------------------------------------- */

/* Bytes one probe's six maps take (radiance, normal, distance, low,
 * irradiance, moments; the layout of probes.h). */
size_t maps_probe_bytes(const vx_probe_set* ps);
/* Copies probes [from, from + n) (grid indices, inside what ps holds) into
 * buf: each map's n probes in turn, native byte order. */
void maps_pack(const vx_probe_set* ps, uint32_t from, uint32_t n, uint8_t* buf);
/* The reverse, into arrays that hold probes [from, from + n) (maps_reserve). */
void maps_unpack(vx_probe_set* ps, uint32_t from, uint32_t n, const uint8_t* buf);
/* Makes the arrays hold n probes from ps->first (keeping the ps->count
 * baked ones, zeroing the rest); ps->count is unchanged. */
bool maps_reserve(vx_probe_set* ps, uint32_t n);
/* Frees the maps only (a view sharing another set's probes array). */
void maps_free(vx_probe_set* ps);

/* The atlases as EXR images into dir (--exr). */
int write_exr(const char* dir, const vx_probe_set* ps);

#ifdef VX_HAVE_MPI
/* The whole MPI bake (every rank calls it after parsing the options);
 * returns the exit status (failures end the job through MPI_Abort). */
int bake_mpi(options* o, const char* in, const char* out);
#endif

#endif /* VX_SVO_BAKE_H */
