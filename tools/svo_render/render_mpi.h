/* tools/svo_render/render_mpi.h - svo_render under mpirun: the path tracer
 * and probe modes spread over the ranks by image rows (tools/svo_render/mpi.c,
 * built where MPI is found). */
#ifndef VX_SVO_RENDER_MPI_H
#define VX_SVO_RENDER_MPI_H

#include <stdbool.h>

#include "probes/probes.h"
#include "tools/common/gpu_open.h"
#include "tools/common/mpi.h"

typedef struct render_mpi_job {
    const vx_svo_scene* scene;
    const vx_probe_set* probes; /* NULL for the path tracer modes */
    vx_probe_render_desc desc;  /* mode, spp, bounces, seed, base (size, camera) */
    bool cpu;                   /* the double-precision CPU renderer (desc.threads per rank) */
    const char* device;         /* NULL: GPU `local rank mod GPUs` of the host */
    bool validate, verbose;
    vx_tool_timeline* tl;       /* stamps of this rank's start-up and work (the caller's, started in main) */
    struct render_mpi_end* end; /* the caller's, zeroed: what render_mpi_finalize finishes */
} render_mpi_job;

/* The device closing on a thread of its own from the end of the rank's
 * render (while rank 0 gathers and writes the image) to render_mpi_finalize. */
typedef struct render_mpi_end {
    vx_tool_bg close;
    vx_gpu* gpu;
    vx_render_scene* rs;
} render_mpi_end;

/* Every rank calls it. Rows go to the ranks round-robin (rank r renders rows
 * r, r + N, ...: every rank gets an even share of costly rows, and the split
 * is a function of N alone); each rank renders its rows in one call (on the GPU a dispatch of
 * only its own pixels, probes.h's `rows`) and rank 0 gathers them.
 * Since a pixel's value depends only on the seed, the pixel and the sample,
 * the image equals a single-process render bit for bit. On rank 0 *out is the
 * image and *root is true; elsewhere *out is empty. A failure on any rank
 * ends the job (MPI_Abort) with a line naming the rank. */
void render_mpi(const render_mpi_job* job, vx_render_image* out, bool* root);
/* Every rank, after rank 0 has written the output: waits for the device's
 * close (end may be NULL), MPI_Finalize, then with print the rank's timeline
 * line (tl may be NULL). */
void render_mpi_finalize(render_mpi_end* end, vx_tool_timeline* tl, bool print);

#endif
