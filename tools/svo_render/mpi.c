/* tools/svo_render/mpi.c - mpirun -n N svo_render SCENE OUT --mode pathtrace:
 * rows spread over the ranks (on the GPU handed out as the ranks finish
 * chunks), gathered bit for bit (render_mpi.h). */
#include <mpi.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tools/common/mpi.h"
#include "tools/common/tool.h"
#include "tools/svo_render/render_mpi.h"

/* the CPU renderer's rows: every N-th row (bands of 8 gave 544 and 536 rows
 * at 1080p on 2 ranks: 1.5% more work for rank 0) */
enum { BAND = 1 };

static uint8_t* rows_of(int rank, int nranks, uint32_t height) {
    uint8_t* rows = calloc(height ? height : 1, 1);
    if (!rows) return NULL;
    for (uint32_t y = 0; y < height; y++) rows[y] = (int)((y / BAND) % (uint32_t)nranks) == rank;
    return rows;
}

/* ---- rows handed out while the ranks render (GPU) ------------------------------------ */

/* The rows in an interleaved order (by y mod 8, then y), cut into chunks:
 * first one chunk per rank of STATIC_SHARE / N of the rows, each spread over
 * the whole image (one large dispatch set, no hand-out), then the rest in
 * guided chunks (a 1/(2N) share of what is left, at least 8 rows) that the
 * ranks take in turn from a counter on rank 0 (MPI_Fetch_and_op on a window:
 * no answer from rank 0 needed, which is inside its own render), so a rank
 * that renders faster (another GPU model, one still clocking up) takes more.
 * Which rank renders a row never changes its pixels. */
#define STATIC_SHARE 0.75
enum { SPREAD = 8 };

typedef struct sched {
    uint32_t H, N, rank;
    uint32_t* order;  /* rows in chunk order */
    uint32_t* bound;  /* chunk k: order[bound[k] .. bound[k + 1]) */
    uint32_t nchunks;
    bool started;     /* the rank's static chunk was handed out */
    MPI_Win win;
    uint64_t* counter; /* rank 0: dynamic chunks taken */
    uint8_t* mine;     /* the rows this rank rendered */
    uint32_t taken;    /* dynamic chunks this rank took */
} sched;

static void sched_init(sched* S, uint32_t H, const vx_tool_mpi* m) {
    memset(S, 0, sizeof *S);
    S->H = H, S->N = (uint32_t)m->nranks, S->rank = (uint32_t)m->rank;
    S->order = calloc(H ? H : 1, sizeof *S->order);
    S->bound = calloc((size_t)H + S->N + 2, sizeof *S->bound);
    S->mine = calloc(H ? H : 1, 1);
    if (!S->order || !S->bound || !S->mine) vx_tool_mpi_die("out of memory for %u rows", H);
    uint32_t k = 0;
    for (uint32_t r = 0; r < SPREAD; r++)
        for (uint32_t y = r; y < H; y += SPREAD) S->order[k++] = y;
    uint32_t s0 = (uint32_t)(STATIC_SHARE * H / S->N), at = 0, n = 0;
    for (uint32_t q = 0; q < S->N; q++) S->bound[n++] = at, at += s0;
    uint32_t least = H / (16 * S->N) < 8 ? (H / (16 * S->N) ? H / (16 * S->N) : 1) : 8;
    while (at < H) {
        uint32_t left = H - at, b = (left + 2 * S->N - 1) / (2 * S->N);
        if (b < least) b = least;
        S->bound[n++] = at, at += b < left ? b : left;
    }
    S->bound[n] = H;
    S->nchunks = n;
    MPI_Win_allocate(m->rank == 0 ? sizeof(uint64_t) : 0, sizeof(uint64_t), MPI_INFO_NULL, MPI_COMM_WORLD,
                     &S->counter, &S->win);
    if (m->rank == 0) {
        MPI_Win_lock(MPI_LOCK_EXCLUSIVE, 0, 0, S->win);
        *S->counter = 0;
        MPI_Win_unlock(0, S->win);
    }
    MPI_Barrier(MPI_COMM_WORLD);
    MPI_Win_lock_all(0, S->win);
}

static void sched_free(sched* S) {
    MPI_Win_unlock_all(S->win);
    MPI_Win_free(&S->win);
    free(S->order), free(S->bound), free(S->mine);
}

/* vx_probe_render_desc.next_rows: the rank's static chunk, then dynamic ones */
static uint32_t next_rows(void* user, uint32_t* out, uint32_t max) {
    sched* S = user;
    for (;;) {
        uint32_t k;
        if (!S->started) {
            S->started = true;
            k = S->rank;
        } else {
            uint64_t one = 1, got = 0;
            MPI_Fetch_and_op(&one, &got, MPI_UINT64_T, 0, 0, MPI_SUM, S->win);
            MPI_Win_flush(0, S->win);
            if (got >= S->nchunks) return 0;
            k = S->N + (uint32_t)got;
            S->taken++;
        }
        if (k >= S->nchunks) return 0;
        uint32_t a = S->bound[k], n = S->bound[k + 1] - a;
        if (n > max) vx_tool_mpi_die("internal: a chunk of %u rows", n);
        if (!n) continue; /* an empty static chunk (tiny images) */
        for (uint32_t i = 0; i < n; i++) out[i] = S->order[a + i], S->mine[S->order[a + i]] = 1;
        return n;
    }
}

/* per-rank timings gathered to rank 0 */
/* render: the rank's render call (wall); gpu: its dispatches by GPU timestamps
 * (the rest of the call is the pass's own set-up: buffers, pipelines, copies) */
enum { ST_SETUP, ST_RENDER, ST_WAIT, ST_GATHER, ST_ROWS, ST_GPU, ST_CHUNKS, ST_N };

void render_mpi(const render_mpi_job* job, vx_render_image* out, bool* root) {
    vx_tool_mpi m;
    double t_in = vx_time_now();
    vx_tool_mpi_init(&m);
    double t_init = vx_time_now() - t_in;
    memset(out, 0, sizeof *out);
    *root = m.rank == 0;
    double st[ST_N] = {0};
    double t0 = vx_time_now();
    vx_error err = {0};
    vx_gpu* gpu = NULL;
    vx_render_scene* rs = NULL;
    char device[16];
    const char* dev = vx_tool_mpi_device(&m, job->device, job->cpu, device);
    if (!job->cpu) {
        vx_logger logger = vx_tool_logger(job->verbose);
        if (vx_gpu_create(&(vx_gpu_desc){.device = dev, .validate = job->validate, .logger = &logger}, &gpu, &err) ||
            vx_render_scene_create(gpu, job->scene, &rs, &err))
            vx_tool_mpi_die("%s", err.msg);
    }
    /* the render's size: base, or the defaults */
    vx_render_desc base = job->desc.base ? *job->desc.base : vx_render_desc_defaults();
    uint32_t W = base.width ? base.width : vx_render_desc_defaults().width;
    uint32_t H = base.height ? base.height : vx_render_desc_defaults().height;
    /* the CPU renderer: every N-th row; the GPU: rows handed out as it goes */
    uint8_t* rows = job->cpu ? rows_of(m.rank, m.nranks, H) : NULL;
    if (job->cpu && !rows) vx_tool_mpi_die("out of memory for %u rows", H);
    sched S;
    if (!job->cpu) sched_init(&S, H, &m);
    for (int r = 0; r < m.nranks; r++) { /* one line per rank, in rank order */
        if (r == m.rank) {
            printf("rank %d (%s): device: %s%s\n", m.rank, m.host,
                   gpu ? vx_gpu_device_name(gpu) : "CPU (double precision)", gpu && vx_gpu_is_cpu(gpu) ? " (software)" : "");
            fflush(stdout);
        }
        MPI_Barrier(MPI_COMM_WORLD);
    }
    st[ST_SETUP] = vx_time_now() - t0;
    vx_probe_render_desc d = job->desc;
    d.rows = rows;
    if (!job->cpu) d.next_rows = next_rows, d.next_rows_user = &S;
    vx_render_image img = {0};
    double t = vx_time_now();
    vx_result r = job->cpu ? vx_probe_render(job->scene, job->probes, &d, &img, &err)
                           : vx_probe_render_gpu(rs, job->scene, job->probes, &d, &img, &err);
    if (r) vx_tool_mpi_die("%s", err.msg);
    if (img.width != W || img.height != H)
        vx_tool_mpi_die("rendered %ux%u, expected %ux%u", img.width, img.height, W, H);
    st[ST_RENDER] = vx_time_now() - t;
    st[ST_GPU] = img.gpu_seconds;
    if (!job->cpu) {
        rows = S.mine, S.mine = NULL;
        st[ST_CHUNKS] = S.taken;
        sched_free(&S);
    }
    for (uint32_t y = 0; y < H; y++) st[ST_ROWS] += rows[y];
    vx_render_scene_destroy(rs);
    vx_gpu_destroy(gpu);
    /* ranks that finished early wait here: the load imbalance */
    t = vx_time_now();
    MPI_Barrier(MPI_COMM_WORLD);
    st[ST_WAIT] = vx_time_now() - t;
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
        uint8_t* their = malloc(H ? H : 1);
        uint8_t* seen = malloc(H ? H : 1);
        if (!their || !seen) vx_tool_mpi_die("out of memory for %u rows", H);
        memcpy(seen, rows, H);
        for (int q = 1; q < m.nranks; q++) {
            MPI_Recv(their, (int)H, MPI_BYTE, q, 6, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            MPI_Recv(other, count, MPI_FLOAT, q, 7, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            uint64_t rq = 0;
            MPI_Recv(&rq, 1, MPI_UINT64_T, q, 8, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            rays += rq;
            for (uint32_t y = 0; y < H; y++)
                if (their[y]) {
                    if (seen[y]) vx_tool_mpi_die("internal: row %u rendered twice", y);
                    seen[y] = 1;
                    memcpy(img.pixels + y * row_floats, other + y * row_floats, row_floats * sizeof(float));
                }
        }
        for (uint32_t y = 0; y < H; y++)
            if (!seen[y]) vx_tool_mpi_die("internal: row %u not rendered", y);
        free(their);
        free(seen);
        free(other);
        img.rays = rays;
    } else {
        MPI_Send(rows, (int)H, MPI_BYTE, 0, 6, MPI_COMM_WORLD);
        MPI_Send(img.pixels, count, MPI_FLOAT, 0, 7, MPI_COMM_WORLD);
        MPI_Send(&img.rays, 1, MPI_UINT64_T, 0, 8, MPI_COMM_WORLD);
        vx_render_image_free(&img);
    }
    st[ST_GATHER] = vx_time_now() - t;
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
                printf("rank %d: %.0f rows (%.0f chunks handed out), set-up %.3f s, render %.3f s (GPU %.3f s), wait "
                       "%.3f s (%.1f%%), gather %.3f s\n",
                       q, s[ST_ROWS], s[ST_CHUNKS], s[ST_SETUP], s[ST_RENDER], s[ST_GPU], s[ST_WAIT], 100 * share,
                       s[ST_GATHER]);
        }
        printf("rendered %ux%u on %d ranks in %.2f s (slowest render %.3f s, most waiting %.1f%%, gather %.3f s)\n", W,
               H, m.nranks, wall, rmax, 100 * wmax, st[ST_GATHER]);
        if (job->verbose)
            printf("rank 0: MPI_Init %.3f s, %.3f s from the start to the gathered image\n", t_init,
                   vx_time_now() - t_in);
        img.gpu_seconds = rmax;
        *out = img;
    }
    free(all);
    free(rows);
}

void render_mpi_finalize(void) { MPI_Finalize(); }
