/* tools/svo_render/mpi.c - mpirun -n N svo_render SCENE OUT --mode pathtrace:
 * rows spread over the ranks, gathered bit for bit (render_mpi.h). */
#include <mpi.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tools/common/gpu_open.h"
#include "tools/common/mpi.h"
#include "tools/common/tool.h"
#include "tools/svo_render/render_mpi.h"

/* rows per band: 1, every N-th row, so the ranks' shares differ by at most
 * one row and follow the image's cost row by row (bands of 8 gave 544 and 536
 * rows at 1080p on 2 ranks: 1.5% more work for rank 0) */
enum { BAND = 1 };

static uint8_t* rows_of(int rank, int nranks, uint32_t height) {
    uint8_t* rows = calloc(height ? height : 1, 1);
    if (!rows) return NULL;
    for (uint32_t y = 0; y < height; y++) rows[y] = (int)((y / BAND) % (uint32_t)nranks) == rank;
    return rows;
}

/* per-rank timings gathered to rank 0 */
/* render: the rank's render call (wall); gpu: its dispatches by GPU timestamps
 * (the rest of the call is the pass's own set-up: buffers, pipelines, copies) */
enum { ST_SETUP, ST_RENDER, ST_WAIT, ST_GATHER, ST_ROWS, ST_GPU, ST_N };

static void close_device(void* arg) {
    render_mpi_end* e = arg;
    vx_render_scene_destroy(e->rs);
    vx_gpu_destroy(e->gpu);
    e->rs = NULL, e->gpu = NULL;
}

void render_mpi(const render_mpi_job* job, vx_render_image* out, bool* root) {
    vx_tool_mpi m;
    double t_in = vx_time_now();
    /* the device opens on a thread while MPI starts (the rank's GPU from the
     * launcher's local rank; where that is unknown, after MPI_Init) */
    vx_logger logger = vx_tool_logger(job->verbose);
    vx_tool_gpu_open go;
    char device[16];
    int lr = vx_tool_mpi_env_local_rank();
    bool early = !job->cpu && lr >= 0;
    vx_tool_timeline no_tl, *tl = job->tl ? job->tl : &no_tl;
    if (!job->tl) vx_tool_timeline_start(tl);
    /* the rank's driver sees only the rank's GPU (vx_tool_mpi_gpu_only: every
     * rank attaching every GPU made the ranks' Vulkan starts wait for each other) */
    int node = -1;
    char wide[16];
    if (early) {
        const char* dev = vx_tool_mpi_device_narrowed(lr, job->device, job->cpu, device, &node);
        vx_tool_gpu_open_start_narrowed(&go,
                                        &(vx_gpu_desc){.device = dev, .validate = job->validate, .logger = &logger},
                                        job->scene, node >= 0 ? vx_tool_mpi_device(lr, job->device, job->cpu, wide) : NULL,
                                        node >= 0 ? vx_tool_mpi_gpu_all : NULL);
    }
    vx_tool_timeline_mark(tl, VX_TL_MPI_INIT);
    vx_tool_mpi_init(&m);
    vx_tool_timeline_mark(tl, VX_TL_MPI_READY);
    double t_init = vx_time_now() - t_in;
    memset(out, 0, sizeof *out);
    *root = m.rank == 0;
    double st[ST_N] = {0};
    double t0 = vx_time_now();
    vx_error err = {0};
    vx_gpu* gpu = NULL;
    vx_render_scene* rs = NULL;
    if (!job->cpu) {
        if (!early) {
            const char* dev = vx_tool_mpi_device(m.local_rank, job->device, job->cpu, device);
            vx_tool_gpu_open_start(&go, &(vx_gpu_desc){.device = dev, .validate = job->validate, .logger = &logger},
                                   job->scene);
        }
        if (vx_tool_gpu_open_wait(&go, &gpu, &rs, NULL, &err)) vx_tool_mpi_die("%s", err.msg);
        memcpy(&tl->t[VX_TL_VK_START], go.at, sizeof go.at);
    }
    /* the render's size: base, or the defaults */
    vx_render_desc base = job->desc.base ? *job->desc.base : vx_render_desc_defaults();
    uint32_t W = base.width ? base.width : vx_render_desc_defaults().width;
    uint32_t H = base.height ? base.height : vx_render_desc_defaults().height;
    uint8_t* rows = rows_of(m.rank, m.nranks, H);
    if (!rows) vx_tool_mpi_die("out of memory for %u rows", H);
    for (uint32_t y = 0; y < H; y++) st[ST_ROWS] += rows[y];
    for (int r = 0; r < m.nranks; r++) { /* one line per rank, in rank order */
        if (r == m.rank) {
            char seen[64] = "";
            if (node >= 0)
                snprintf(seen, sizeof seen, go.fell_back ? " (every GPU: /dev/nvidia%d alone failed)" : " (sees /dev/nvidia%d alone)", node);
            printf("rank %d (%s): device: %s%s%s, %.0f of %u rows\n", m.rank, m.host,
                   gpu ? vx_gpu_device_name(gpu) : "CPU (double precision)", gpu && vx_gpu_is_cpu(gpu) ? " (software)" : "",
                   seen, st[ST_ROWS], H);
            fflush(stdout);
        }
        MPI_Barrier(MPI_COMM_WORLD);
    }
    st[ST_SETUP] = vx_time_now() - t0;
    vx_probe_render_desc d = job->desc;
    d.rows = rows;
    vx_render_image img = {0};
    vx_tool_timeline_mark(tl, VX_TL_WORK);
    double t = vx_time_now();
    vx_result r = job->cpu ? vx_probe_render(job->scene, job->probes, &d, &img, &err)
                           : vx_probe_render_gpu(rs, job->scene, job->probes, &d, &img, &err);
    if (r) vx_tool_mpi_die("%s", err.msg);
    if (img.width != W || img.height != H)
        vx_tool_mpi_die("rendered %ux%u, expected %ux%u", img.width, img.height, W, H);
    st[ST_RENDER] = vx_time_now() - t;
    vx_tool_timeline_mark(tl, VX_TL_DONE);
    st[ST_GPU] = img.gpu_seconds;
    /* ranks that finished early wait here: the load imbalance */
    t = vx_time_now();
    MPI_Barrier(MPI_COMM_WORLD);
    st[ST_WAIT] = vx_time_now() - t;
    /* then the device closes, beside the gather and the image's write: not
     * before every rank has rendered, since the driver serialises across
     * processes (a rank that closed its device while others still rendered
     * left their render calls up to 0.9 s longer than their GPU time, 4 H200) */
    if (job->end) {
        job->end->gpu = gpu, job->end->rs = rs;
        vx_tool_bg_start(&job->end->close, close_device, job->end);
    } else {
        vx_render_scene_destroy(rs);
        vx_gpu_destroy(gpu);
    }
    /* rank 0 takes each rank's rows from its image (whole images: a few
     * tens of MB at 1080p, one message each) */
    t = vx_time_now();
    size_t row_floats = (size_t)W * 4;
    if (row_floats * H > (size_t)INT32_MAX) vx_tool_mpi_die("a %ux%u image is too large for one message", W, H);
    int count = (int)(row_floats * H);
    if (m.rank == 0) {
        float* other = m.nranks > 1 ? malloc((size_t)count * sizeof(float)) : NULL;
        if (m.nranks > 1 && !other) vx_tool_mpi_die("out of memory for a %ux%u image", W, H);
        uint64_t rays = img.rays;
        for (int q = 1; q < m.nranks; q++) {
            MPI_Recv(other, count, MPI_FLOAT, q, 7, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            uint64_t rq = 0;
            MPI_Recv(&rq, 1, MPI_UINT64_T, q, 8, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            rays += rq;
            uint8_t* their = rows_of(q, m.nranks, H);
            if (!their) vx_tool_mpi_die("out of memory for %u rows", H);
            for (uint32_t y = 0; y < H; y++)
                if (their[y])
                    memcpy(img.pixels + y * row_floats, other + y * row_floats, row_floats * sizeof(float));
            free(their);
        }
        free(other);
        img.rays = rays;
    } else {
        MPI_Send(img.pixels, count, MPI_FLOAT, 0, 7, MPI_COMM_WORLD);
        MPI_Send(&img.rays, 1, MPI_UINT64_T, 0, 8, MPI_COMM_WORLD);
        vx_render_image_free(&img);
    }
    st[ST_GATHER] = vx_time_now() - t;
    if (m.rank == 0) vx_tool_timeline_mark(tl, VX_TL_REDUCED);
    double* all = m.rank == 0 ? calloc((size_t)m.nranks * ST_N, sizeof(double)) : NULL;
    MPI_Gather(st, ST_N, MPI_DOUBLE, all, ST_N, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    if (m.rank == 0) {
        double wall = vx_time_now() - t0, wmax = 0, rmax = 0;
        for (int q = 0; q < m.nranks && all; q++) {
            const double* s = all + (size_t)q * ST_N;
            double busy = s[ST_RENDER] + s[ST_WAIT];
            double share = busy > 0 ? s[ST_WAIT] / busy : 0;
            if (share > wmax) wmax = share;
            if (s[ST_RENDER] > rmax) rmax = s[ST_RENDER];
            if (job->verbose)
                printf("rank %d: %.0f rows, set-up %.3f s, render %.3f s (GPU %.3f s), wait %.3f s (%.1f%%), gather %.3f s\n",
                       q, s[ST_ROWS], s[ST_SETUP], s[ST_RENDER], s[ST_GPU], s[ST_WAIT], 100 * share, s[ST_GATHER]);
        }
        printf("rendered %ux%u on %d ranks in %.2f s (slowest render %.3f s, most waiting %.1f%%, gather %.3f s)\n", W,
               H, m.nranks, wall, rmax, 100 * wmax, st[ST_GATHER]);
        if (job->verbose)
            printf("rank 0: MPI_Init %.3f s, device and scene %.3f s (the device %.3f s; on a thread %s), %.3f s "
                   "from the start to the gathered image\n",
                   t_init, job->cpu ? 0.0 : go.seconds, job->cpu ? 0.0 : go.device_s,
                   early ? "from the start" : "after MPI_Init", vx_time_now() - t_in);
        img.gpu_seconds = rmax;
        *out = img;
    }
    free(all);
    free(rows);
}

void render_mpi_finalize(render_mpi_end* end, vx_tool_timeline* tl, bool print) {
    if (end) vx_tool_bg_wait(&end->close);
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Finalize();
    if (!tl) return;
    vx_tool_timeline_mark(tl, VX_TL_END);
    if (print) vx_tool_timeline_print(tl, rank);
}
