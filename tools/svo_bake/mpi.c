/* tools/svo_bake/mpi.c - svo_bake under MPI: mpirun -n N svo_bake SCENE OUT [options].
 *
 * Every rank reads the scene, opens its device (GPU `local rank mod GPUs` of
 * its host, or --device, or --cpu) and places the same probe grid. Rank 0
 * hands out batches of consecutive probes (guided sizes: a share of what is
 * left, so probes that cost more, near geometry, even out) and bakes a full
 * share itself; each worker holds two assignments, so the next is there
 * when it reports a batch. Rank 0 answers between and during its own batches
 * (from the bake's progress callback).
 *
 * The output: a .probes file's blocks have one size and a probe's place is a
 * function of its index (docs/FORMAT.md), so every rank writes the blocks of
 * the batches it bakes straight into the output's temporary file
 * (OUT.probes.ckpt/output.tmp) through MPI-IO, at memory speed and in
 * parallel, and reports only the batch's range and the CRC-32 of its blocks
 * (a few bytes). At the end rank 0 combines the batches' CRCs in probe order
 * into the DATA section's (zlib's crc32_combine), writes the header and the
 * GRID section, every rank syncs, and rank 0 renames the file over OUT.probes:
 * nothing under the output name before the whole file is there. Since the
 * output folder is the file's, the ranks' hosts must share it (as they must
 * for MPI-IO). (Before, rank 0 received every map and wrote the file alone:
 * 845 MB moved at 32 MB/s, and rank 0 baked almost nothing.)
 *
 * Checkpoints: every rank saves each batch it bakes, before reporting it, as
 * OUT.probes.ckpt/bFIRST-END.rRANK.probes (a .probes file of that range,
 * renamed into place; not synced: a checkpoint is checked by its CRCs when
 * it is read, and one fsync per batch made the host's disk the limit of N
 * GPUs), so a job that dies loses only the batches in flight. A rerun's rank
 * 0 takes every batch file of the same job it finds there, and a
 * single-process checkpoint (OUT.probes.partial), writes their blocks itself
 * and hands out only the probes still missing; the files go once the output
 * is written. A probe's maps depend only on the seed and its index, so the
 * bytes equal a single-process bake whatever N. A rank that fails calls
 * MPI_Abort, which ends every rank before rank 0 renames anything to the
 * output name. Ranks must share one byte order.
 *
 * Test hooks (environment): VX_BAKE_MPI_FAIL=R:K[:error] makes rank R die
 * of SIGKILL (or fail with an error) after reporting its K-th batch (its
 * batch files for those K batches are on disk by then). */
#define _GNU_SOURCE /* kill(), sync_file_range() */
#include <fcntl.h>
#include <dirent.h>
#include <errno.h>
#include <mpi.h>
#include <pthread.h>
#include <signal.h>
#include <sys/stat.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <zlib.h>

#include "tools/common/mpi.h"
#include "tools/common/tool.h"
#include "tools/svo_bake/svo_bake.h"

enum { TAG_ASSIGN = 1, TAG_RESULT = 2 };
/* assignments a worker holds: the one it bakes and the next two (a batch is
 * reported when the writer has written it, after the rank baked the next;
 * rank 0 answers from its bake's progress callback, well within a batch) */
enum { DEPTH = 3 };
/* a batch: a 1/(SHARE N) share of what is left (guided sizes) */
enum { SHARE = 4 };
/* a result: first probe (u32), count (u32), bake seconds (f64), CRC-32 of the blocks (u32), 0 (u32) */
enum { HEAD = 24 };

/* this rank's place (set once by bake_mpi) */
static vx_tool_mpi g_mpi;
#define die vx_tool_mpi_die

/* per-rank timings, gathered to rank 0 */
enum { ST_WALL, ST_BAKE, ST_WAIT, ST_COMM, ST_PROBES, ST_BATCHES, ST_CKPT, ST_IO, ST_N };

/* ---- per-rank batch checkpoints (OUT.probes.ckpt/) ------------------------------------ */

/* the batch files this rank wrote or (rank 0) resumed: removed after success */
static char** g_saved;
static size_t g_saved_n, g_saved_cap;

static void remember(const char* path) {
    size_t n = strlen(path) + 1;
    char* p = malloc(n);
    if (p) memcpy(p, path, n);
    if (!p || !vx_grow(NULL, (void**)&g_saved, &g_saved_cap, g_saved_n + 1, sizeof *g_saved)) die("out of memory");
    g_saved[g_saved_n++] = p;
}

/* ---- the output file (MPI-IO) ------------------------------------------------------ */

/* the output's temporary file, in the checkpoint folder */
#define OUTPUT_TMP "output.tmp"

typedef struct outfile {
    MPI_File fh;
    int fd;         /* the same file for sync_file_range, -1 where there is none */
    char tmp[4200];
    uint64_t base;  /* offset of probe 0's block: header, GRID, DATA's head */
    uint64_t block; /* bytes per probe block */
    uint64_t size;
} outfile;

/* Where the blocks go (docs/FORMAT.md, .probes): a header of 16 bytes, GRID
 * (a 16-byte section head, 192 bytes, 28 per probe), DATA's section head and
 * its first and count; each block the six maps with borders. */
static void outfile_layout(const vx_probe_set* ps, outfile* of) {
    uint64_t r = (uint64_t)(ps->res + 2) * (ps->res + 2), l = (uint64_t)(ps->low_res + 2) * (ps->low_res + 2);
    uint64_t i = (VX_PROBE_IRR_RES + 2) * (VX_PROBE_IRR_RES + 2), m = (VX_PROBE_DIST_RES + 2) * (VX_PROBE_DIST_RES + 2);
    of->block = r * (6 + 4 + 2) + l * 2 + i * 6 + m * 8;
    of->base = 16 + 16 + 192 + 28 * (uint64_t)ps->probe_count + 16 + 8;
    of->size = of->base + of->block * ps->probe_count;
}

static void write_at(outfile* of, uint64_t at, const uint8_t* p, uint64_t n) {
    while (n) {
        int k = n > (1u << 30) ? 1 << 30 : (int)n, got = 0;
        MPI_Status st;
        if (MPI_File_write_at(of->fh, (MPI_Offset)at, p, k, MPI_BYTE, &st) != MPI_SUCCESS ||
            MPI_Get_count(&st, MPI_BYTE, &got) != MPI_SUCCESS || got != k)
            die("%s: cannot write %d bytes at %llu", of->tmp, k, (unsigned long long)at);
        at += (uint64_t)k, p += k, n -= (uint64_t)k;
    }
}

/* Every rank: creates (or reuses, a killed job's) the temporary file at its
 * final size. */
static void outfile_open(const bake_job* j, const vx_probe_set* ps, outfile* of) {
    outfile_layout(ps, of);
    if (snprintf(of->tmp, sizeof of->tmp, "%s/" OUTPUT_TMP, j->ckdir) >= (int)sizeof of->tmp) die("%s: name too long", j->ckdir);
    if (MPI_File_open(MPI_COMM_WORLD, of->tmp, MPI_MODE_CREATE | MPI_MODE_WRONLY, MPI_INFO_NULL, &of->fh) != MPI_SUCCESS)
        die("%s: cannot create the output's temporary file", of->tmp);
    if (MPI_File_set_size(of->fh, (MPI_Offset)of->size) != MPI_SUCCESS)
        die("%s: cannot make it %llu bytes", of->tmp, (unsigned long long)of->size);
    of->fd = open(of->tmp, O_WRONLY);
}

/* Starts the disk writes of blocks just written, so that the final sync
 * does not write the whole file while the job waits (a local file system;
 * elsewhere a no-op or an error, both ignored). */
static void start_writeback(const outfile* of, uint64_t at, uint64_t n) {
#ifdef SYNC_FILE_RANGE_WRITE
    if (of->fd >= 0) (void)sync_file_range(of->fd, (off_t)at, (off_t)n, SYNC_FILE_RANGE_WRITE);
#else
    (void)of, (void)at, (void)n;
#endif
}

/* A batch checkpoint: written to a temporary name and renamed, not synced
 * (see the top of the file). Returns 0 or an errno. */
static int write_ckpt(const char* path, const uint8_t* data, size_t size) {
    char tmp[4300];
    snprintf(tmp, sizeof tmp, "%s.tmp%ld", path, (long)getpid());
    FILE* f = fopen(tmp, "wb");
    if (!f) return errno ? errno : EIO;
    bool ok = fwrite(data, 1, size, f) == size;
    int e = ok ? 0 : (errno ? errno : EIO);
    if (fclose(f) != 0 && !e) e = errno ? errno : EIO;
    if (!e && rename(tmp, path) != 0) e = errno ? errno : EIO;
    if (e) remove(tmp);
    return e;
}

/* ---- a baked batch's serialising, CRC and writes, on a thread of their own ------------- */

/* A rank's batch goes to disk twice (its batch file, its blocks in the
 * output: 1.7 GB for the 4,096-probe goal bake) and is checksummed: on the
 * rank's thread that took 2.2 s of a 10 s bake between its GPU batches (H200,
 * one rank). The writer does all of it while the rank bakes its next batch,
 * and hands back the batch's range and its blocks' CRC, which the rank then
 * reports (a worker) or stores (rank 0): a report comes one batch later, so a
 * worker holds DEPTH = 3 assignments. One batch waits at most: a rank hands
 * the next over only when the last is done. Writes go through the output's
 * own descriptor (pwrite), so the thread makes no MPI call. */
typedef struct wjob {
    vx_probe_set v;  /* a view holding the batch's maps (the writer frees them) */
    bool ckpt;       /* also its batch file */
    double sec;      /* its bake time (for the report) */
    char path[4200]; /* the batch file */
} wjob;

typedef struct wdone {
    uint32_t first, count, crc;
    double sec;
} wdone;

typedef void (*wdone_fn)(void* user, const wdone* d);

typedef struct writer {
    pthread_t thread;
    pthread_mutex_t mu;
    pthread_cond_t cv;
    bool started, busy, quit;
    wjob job;
    wdone done[2]; /* finished, not collected */
    int ndone;
    outfile* of;
    double ser_s, io_s; /* serialising and CRC; the writes */
    char failed[8800];
} writer;

static int pwrite_all(int fd, const uint8_t* p, uint64_t n, uint64_t at) {
    while (n) {
        size_t k = n > (1u << 30) ? (size_t)1 << 30 : (size_t)n;
        ssize_t w = pwrite(fd, p, k, (off_t)at);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) return w < 0 && errno ? errno : EIO;
        p += w, at += (uint64_t)w, n -= (uint64_t)w;
    }
    return 0;
}

/* The batch as a .probes file of its range, its blocks' CRC (derived from
 * the DATA section's, which vx_probe_write computed over (first, count,
 * blocks): one pass over the maps instead of two), the batch file, then the
 * blocks at their place in the output (pwrite; through MPI-IO on the rank's
 * own thread where there is no descriptor). A failure is kept in w->failed
 * (the rank's thread ends the job). */
static void do_job(writer* w, wjob* jb, bool mpi_io) {
    double t = vx_time_now();
    outfile* of = w->of;
    const vx_probe_set* v = &jb->v;
    uint8_t* data = NULL;
    size_t size = 0;
    vx_error err = {0};
    uint64_t nb = (uint64_t)v->count * of->block;
    if (vx_probe_write(v, NULL, &data, &size, &err)) {
        snprintf(w->failed, sizeof w->failed, "probes %u..%u: %s", v->first, v->first + v->count, err.msg);
    } else if (size != of->base + nb) {
        /* a .probes file of the range has the output's header and GRID, so its blocks start at base too */
        snprintf(w->failed, sizeof w->failed, "a batch of %u probes took %zu bytes, not %llu", v->count, size,
                 (unsigned long long)(of->base + nb));
    } else {
        const uint8_t* d = data + of->base - 24; /* DATA's head: tag, CRC, size, then first and count */
        uint32_t data_crc = (uint32_t)d[4] | (uint32_t)d[5] << 8 | (uint32_t)d[6] << 16 | (uint32_t)d[7] << 24;
        /* crc(A B) = shift(crc(A), |B|) ^ crc(B), and crc32_combine(x, 0, n) is that shift */
        uint32_t crc = data_crc ^ (uint32_t)crc32_combine(vx_crc32(0, d + 16, 8), 0, (z_off_t)nb);
        double t2 = vx_time_now();
        w->ser_s += t2 - t;
        uint64_t at = of->base + (uint64_t)v->first * of->block;
        int e = jb->ckpt ? write_ckpt(jb->path, data, size) : 0;
        if (e) {
            snprintf(w->failed, sizeof w->failed, "batch checkpoint %s: %s", jb->path, strerror(e));
        } else if (mpi_io) {
            write_at(of, at, data + of->base, nb); /* dies on a failure: the rank's own thread */
        } else if ((e = pwrite_all(of->fd, data + of->base, nb, at))) {
            snprintf(w->failed, sizeof w->failed, "%s: cannot write %llu bytes at %llu: %s", of->tmp,
                     (unsigned long long)nb, (unsigned long long)at, strerror(e));
        }
        if (!w->failed[0]) {
            start_writeback(of, at, nb);
            pthread_mutex_lock(&w->mu);
            w->done[w->ndone++] = (wdone){v->first, v->count, crc, jb->sec};
            pthread_mutex_unlock(&w->mu);
        }
        w->io_s += vx_time_now() - t2;
    }
    free(data);
    maps_free(&jb->v);
}

static void* writer_main(void* arg) {
    writer* w = arg;
    pthread_mutex_lock(&w->mu);
    for (;;) {
        while (!w->busy && !w->quit) pthread_cond_wait(&w->cv, &w->mu);
        if (!w->busy) break;
        wjob* jb = &w->job;
        pthread_mutex_unlock(&w->mu);
        do_job(w, jb, false);
        pthread_mutex_lock(&w->mu);
        w->busy = false;
        pthread_cond_broadcast(&w->cv);
    }
    pthread_mutex_unlock(&w->mu);
    return NULL;
}

static void writer_start(writer* w, outfile* of) {
    memset(w, 0, sizeof *w);
    w->of = of;
    pthread_mutex_init(&w->mu, NULL);
    pthread_cond_init(&w->cv, NULL);
    /* without the output's descriptor or a thread, the work happens in writer_put */
    w->started = of->fd >= 0 && pthread_create(&w->thread, NULL, writer_main, w) == 0;
}

/* Waits until the writer is idle, ends the job if it failed, and hands
 * every finished batch to fn. */
static void writer_flush(writer* w, wdone_fn fn, void* user) {
    pthread_mutex_lock(&w->mu);
    while (w->busy) pthread_cond_wait(&w->cv, &w->mu);
    wdone d[2];
    int n = w->ndone;
    memcpy(d, w->done, sizeof d);
    w->ndone = 0;
    pthread_mutex_unlock(&w->mu);
    if (w->failed[0]) die("%s", w->failed);
    for (int i = 0; i < n; i++) fn(user, &d[i]);
}

/* The baked batch v (its maps handed over; v is emptied): with ckpt its batch
 * file too. Finished batches go to fn first (the one before this, at most). */
static void writer_put(writer* w, const bake_job* j, vx_probe_set* v, bool ckpt, double sec, wdone_fn fn, void* user) {
    writer_flush(w, fn, user);
    wjob jb = {.v = *v, .ckpt = ckpt, .sec = sec};
    memset(v, 0, sizeof *v);
    if (ckpt) {
        if (snprintf(jb.path, sizeof jb.path, "%s/b%u-%u.r%d.probes", j->ckdir, jb.v.first, jb.v.first + jb.v.count,
                     g_mpi.rank) >= (int)sizeof jb.path)
            die("%s: name too long", j->ckdir);
        remember(jb.path);
    }
    if (!w->started) {
        do_job(w, &jb, w->of->fd < 0);
        writer_flush(w, fn, user);
        return;
    }
    pthread_mutex_lock(&w->mu);
    w->job = jb;
    w->busy = true;
    pthread_cond_broadcast(&w->cv);
    pthread_mutex_unlock(&w->mu);
}

/* Flushes and ends the thread. */
static void writer_stop(writer* w, wdone_fn fn, void* user) {
    writer_flush(w, fn, user);
    if (w->started) {
        pthread_mutex_lock(&w->mu);
        w->quit = true;
        pthread_cond_broadcast(&w->cv);
        pthread_mutex_unlock(&w->mu);
        pthread_join(w->thread, NULL);
        w->started = false;
    }
    pthread_mutex_destroy(&w->mu);
    pthread_cond_destroy(&w->cv);
}

/* Whether name is a batch file's, bFIRST-END.rRANK.probes. */
static bool batch_name(const char* name, uint32_t* a, uint32_t* b) {
    int rank = -1, len = 0;
    return sscanf(name, "b%u-%u.r%d.probes%n", a, b, &rank, &len) == 3 && name[len] == 0 && *a < *b && rank >= 0;
}

/* Whether name is the temporary file of a batch file (bFIRST-END.rRANK.probes
 * .tmpPID, vx_atomic_open's name) whose writer is gone: a rank killed while
 * saving it. No later write has that name, so nothing else would remove it
 * (svo/core.c removes only the stale temporary files of the name it writes);
 * the test for a dead pid is core.c's. */
static bool stale_batch_tmp(const char* name) {
    const char* t = strstr(name, ".probes.tmp");
    char base[256];
    uint32_t a, b;
    size_t n = t ? (size_t)(t - name) + strlen(".probes") : 0;
    if (!t || n >= sizeof base) return false;
    memcpy(base, name, n);
    base[n] = 0;
    if (!batch_name(base, &a, &b)) return false;
    const char* p = t + strlen(".probes.tmp");
    char* end;
    if (*p < '0' || *p > '9') return false;
    long pid = strtol(p, &end, 10);
    if (*end || pid <= 0 || pid == (long)getpid()) return false;
    return kill((pid_t)pid, 0) != 0 && errno == ESRCH;
}

/* Every rank: the folder exists (on a shared file system the ranks make the
 * same one). */
static void make_ckdir(const bake_job* j) {
    if (mkdir(j->ckdir, 0777) != 0 && errno != EEXIST) die("%s: cannot make the checkpoint folder: %s", j->ckdir, strerror(errno));
}

/* Rank 0 after the prefix checkpoint: each batch file of this job in the
 * folder fills its probes not done yet (done[] per probe from ps->first,
 * the maps reserved); --fresh removes them instead. Temporary files of
 * killed writers go. Returns the probes taken. */
static uint32_t resume_batches(const bake_job* j, vx_probe_set* ps, uint32_t end, uint8_t* done, size_t pb) {
    DIR* d = opendir(j->ckdir);
    if (!d) return 0;
    uint32_t taken = 0, files = 0;
    uint8_t* one = malloc(pb);
    if (!one) die("out of memory");
    for (struct dirent* e; (e = readdir(d));) {
        uint32_t a, b;
        char path[4400];
        if (snprintf(path, sizeof path, "%s/%s", j->ckdir, e->d_name) >= (int)sizeof path) continue;
        if (stale_batch_tmp(e->d_name)) {
            remove(path);
            continue;
        }
        if (!batch_name(e->d_name, &a, &b)) continue;
        if (j->o.fresh) {
            remove(path);
            continue;
        }
        vx_probe_set ck;
        vx_error err = {0};
        if (vx_probe_read_file(NULL, path, &ck, &err)) {
            fprintf(stderr, "%s: %s: %s; ignored\n", vx_tool_name, path, err.msg);
            continue;
        }
        if (!same_grid(ps, &ck) || ck.first != a || ck.count != b - a || a < ps->first || b > end) {
            fprintf(stderr, "%s: %s: not a batch of this job; ignored\n", vx_tool_name, path);
        } else {
            for (uint32_t i = a; i < b; i++) {
                if (done[i - ps->first]) continue;
                maps_pack(&ck, i, 1, one);
                maps_unpack(ps, i, 1, one);
                done[i - ps->first] = 1;
                taken++;
            }
            files++;
            remember(path);
        }
        vx_probe_set_free(&ck);
    }
    closedir(d);
    free(one);
    if (files) printf("resuming from %s: %u probes from %u batch checkpoints\n", j->ckdir, taken, files);
    return taken;
}

/* Whether the checkpoint folder holds anything but the output's temporary
 * file: batch files to resume, or files resume_batches removes. */
static bool ckdir_has_files(const bake_job* j) {
    DIR* d = opendir(j->ckdir);
    bool any = false;
    for (struct dirent* e; d && !any && (e = readdir(d));)
        any = strcmp(e->d_name, ".") && strcmp(e->d_name, "..") && strcmp(e->d_name, OUTPUT_TMP);
    if (d) closedir(d);
    return any;
}

/* After the output is written: every rank removes its batch files, then
 * rank 0 the folder (when no other files are in it). */
static void remove_batches(const bake_job* j) {
    for (size_t i = 0; i < g_saved_n; i++) remove(g_saved[i]);
    MPI_Barrier(MPI_COMM_WORLD);
    if (g_mpi.rank == 0) rmdir(j->ckdir);
}

static void free_saved(void) {
    for (size_t i = 0; i < g_saved_n; i++) free(g_saved[i]);
    free(g_saved);
    g_saved = NULL, g_saved_n = g_saved_cap = 0;
}

/* A set that shares placed's probes and grid and holds maps for a batch
 * from `first` (none yet): what vx_probe_place would give for that range. */
static vx_probe_set view_at(const vx_probe_set* placed, uint32_t first) {
    vx_probe_set v = *placed;
    v.first = first, v.count = 0;
    v.radiance = NULL, v.normal = NULL, v.distance = NULL, v.low = NULL, v.irradiance = NULL, v.moments = NULL;
    return v;
}

/* ---- rank 0: the coordinator ------------------------------------------------------ */

typedef struct batch_rec {
    uint32_t first, count, crc;
} batch_rec;

typedef struct coord {
    bake_job* j;
    vx_probe_set* ps;       /* placed; maps only of the probes resumed from checkpoints */
    outfile* of;
    writer* w;              /* the output's and the batch files' writes */
    uint32_t first, end;
    uint32_t next;          /* next probe to hand out */
    uint32_t received;      /* probes in the output (own, workers', resumed) */
    uint32_t outstanding;   /* probes handed to workers, not yet back */
    uint8_t* done;          /* per probe from first */
    int nranks;
    bool* ended;            /* per rank: sent the empty assignment */
    uint32_t min_batch, cap, byte_cap;
    double per_probe;       /* seconds a probe takes to bake (running estimate), 0 before any */
    batch_rec* recs;        /* every batch in the output: its range and its blocks' CRC */
    size_t nrec, rec_cap;
    bool serve_in_bake;     /* the progress callback may call MPI */
    double st[ST_N];
    /* progress line */
    bool show;
    double t0, last_show;
    uint32_t own_done;
    double serving; /* seconds answering inside the current own batch */
} coord;

/* A batch should take about TARGET_S seconds: long enough that the per-batch
 * costs (a GPU bake's set-up, a message) stay small, short enough for the load
 * balance. Every batch's bake time (any rank's) refines the estimate. */
#define TARGET_S 3.0
static void learn(coord* c, uint32_t n, double sec) {
    if (!n || !(sec > 0)) return;
    double per = sec / n;
    c->per_probe = c->per_probe > 0 ? 0.7 * c->per_probe + 0.3 * per : per;
    double want = TARGET_S / c->per_probe;
    c->cap = want < c->min_batch ? c->min_batch : (want > c->byte_cap ? c->byte_cap : (uint32_t)want);
}

static uint32_t batch_size(const coord* c) {
    /* a 1/(SHARE N) share of what is left: the last ones are small enough
     * to end the ranks together */
    uint32_t left = c->end - c->next, parts = SHARE * (uint32_t)c->nranks;
    uint32_t b = (left + parts - 1) / parts;
    if (b > c->cap) b = c->cap;
    if (b < c->min_batch) b = c->min_batch;
    return b < left ? b : left;
}

/* The next batch: from the first probe neither done (a resumed batch) nor
 * handed out, at most batch_size probes, ending before a done one. */
static bool take_run(coord* c, uint32_t* a, uint32_t* n) {
    while (c->next < c->end && c->done[c->next - c->first]) c->next++;
    if (c->next >= c->end) return false;
    uint32_t want = batch_size(c), k = 1;
    while (k < want && c->next + k < c->end && !c->done[c->next + k - c->first]) k++;
    *a = c->next, *n = k;
    c->next += k;
    return true;
}

static void hand_out(coord* c, int to) {
    uint32_t a[2], n;
    if (take_run(c, &a[0], &n)) {
        a[1] = a[0] + n;
        c->outstanding += n;
    } else if (!c->ended[to]) {
        a[0] = a[1] = c->end;
        c->ended[to] = true;
    } else {
        return;
    }
    MPI_Send(a, 2, MPI_UINT32_T, to, TAG_ASSIGN, MPI_COMM_WORLD);
}

/* Probes [from, from + n) are in the output, their blocks' CRC crc. */
static void store(coord* c, uint32_t from, uint32_t n, uint32_t crc, int source) {
    if (from < c->first || n > c->end - from || !n)
        die("rank %d reported probes %u..%u outside %u..%u", source, from, from + n, c->first, c->end);
    for (uint32_t i = from; i < from + n; i++) {
        if (c->done[i - c->first] == 2) die("rank %d reported probe %u twice", source, i);
        c->done[i - c->first] = 2;
    }
    if (!vx_grow(NULL, (void**)&c->recs, &c->rec_cap, c->nrec + 1, sizeof *c->recs)) die("out of memory");
    c->recs[c->nrec++] = (batch_rec){from, n, crc};
    c->received += n;
}

/* Receives one report (probed: status) and answers with the next assignment. */
static void take_result(coord* c, MPI_Status* status) {
    double t = vx_time_now();
    int count = 0;
    MPI_Get_count(status, MPI_BYTE, &count);
    uint8_t m[HEAD];
    if (count != HEAD) die("rank %d sent a %d-byte report", status->MPI_SOURCE, count);
    MPI_Recv(m, HEAD, MPI_BYTE, status->MPI_SOURCE, TAG_RESULT, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    uint32_t h[2], crc;
    double sec = 0;
    memcpy(h, m, 8);
    memcpy(&sec, m + 8, 8);
    memcpy(&crc, m + 16, 4);
    if (h[1] > c->outstanding) die("rank %d sent probes nobody asked for", status->MPI_SOURCE);
    c->outstanding -= h[1];
    learn(c, h[1], sec);
    hand_out(c, status->MPI_SOURCE);
    store(c, h[0], h[1], crc, status->MPI_SOURCE);
    c->st[ST_COMM] += vx_time_now() - t;
}

/* Answers every report that has arrived; with block, waits for one first. */
static void serve(coord* c, bool block) {
    for (;;) {
        MPI_Status s;
        int flag = 1;
        if (block) {
            double t = vx_time_now();
            MPI_Probe(MPI_ANY_SOURCE, TAG_RESULT, MPI_COMM_WORLD, &s);
            c->st[ST_WAIT] += vx_time_now() - t;
            block = false;
        } else {
            MPI_Iprobe(MPI_ANY_SOURCE, TAG_RESULT, MPI_COMM_WORLD, &flag, &s);
        }
        if (!flag) return;
        take_result(c, &s);
    }
}

static void show(coord* c, bool force) {
    if (!c->show) return;
    double now = vx_time_now();
    if (!force && now - c->last_show < 0.25) return;
    c->last_show = now;
    uint32_t all = c->received + c->own_done, total = c->end - c->first;
    fprintf(stderr, "\r%s: %s/%s probes %3d%% on %d ranks  %.0f s elapsed   ", vx_tool_name, vx_tool_num(all),
            vx_tool_num(total), (int)(100.0 * all / (total ? total : 1)), c->nranks, now - c->t0);
    fflush(stderr);
}

/* rank 0's own bake: serve the workers while it runs */
static bool coord_progress(void* user, const char* stage, uint64_t done, uint64_t total) {
    (void)stage, (void)total;
    coord* c = user;
    c->own_done = (uint32_t)done;
    if (c->serve_in_bake) {
        double t = vx_time_now();
        serve(c, false);
        c->serving += vx_time_now() - t; /* answering is not baking */
    }
    show(c, false);
    return true;
}

/* The probes resumed from checkpoints (done[] == 1, their maps in c->ps):
 * their blocks into the output, run by run. */
/* rank 0's own batch (or a resumed run) in the output: recorded */
static void coord_done(void* user, const wdone* d) { store(user, d->first, d->count, d->crc, 0); }

static void put_resumed(coord* c) {
    size_t pb = maps_probe_bytes(c->ps);
    for (uint32_t a = c->first; a < c->end;) {
        if (c->done[a - c->first] != 1) {
            a++;
            continue;
        }
        uint32_t b = a;
        while (b < c->end && c->done[b - c->first] == 1 && b - a < c->byte_cap) b++;
        uint32_t n = b - a;
        vx_probe_set v = view_at(c->ps, a);
        uint8_t* buf = malloc(n * pb);
        if (!buf || !maps_reserve(&v, n)) die("out of memory for %u probes", n);
        maps_pack(c->ps, a, n, buf);
        maps_unpack(&v, a, n, buf);
        free(buf);
        v.count = n;
        c->received -= n; /* counted again when stored (they stay marked resumed until then) */
        writer_put(c->w, c->j, &v, false, 0, coord_done, c);
        a = b;
    }
}

static void run_coordinator(coord* c, const vx_probe_bake_desc* b) {
    for (int r = 1; r < c->nranks; r++)
        for (int k = 0; k < DEPTH; k++) hand_out(c, r);
    put_resumed(c);
    vx_probe_bake_desc bd = *b;
    bd.progress = (vx_progress){coord_progress, c};
    for (uint32_t a, n; take_run(c, &a, &n);) {
        vx_probe_set v = view_at(c->ps, a);
        double t = vx_time_now();
        c->own_done = 0, c->serving = 0;
        vx_error err = {0};
        if (bake_range(c->j, &bd, &v, a + n, &err)) die("%s: %s", c->j->in, err.msg);
        double dt = vx_time_now() - t;
        c->st[ST_BAKE] += dt - c->serving;
        c->st[ST_PROBES] += n, c->st[ST_BATCHES] += 1;
        writer_put(c->w, c->j, &v, true, dt - c->serving, coord_done, c);
        c->own_done = 0;
        learn(c, n, dt - c->serving);
        serve(c, false);
        show(c, false);
    }
    writer_flush(c->w, coord_done, c);
    while (c->outstanding) {
        serve(c, true);
        show(c, false);
    }
    /* every worker has had its empty assignment by now (each result is
     * answered), except ones that never got work */
    for (int r = 1; r < c->nranks; r++) hand_out(c, r);
    show(c, true);
    if (c->show) fputc('\n', stderr);
}

static int rec_cmp(const void* x, const void* y) {
    const batch_rec *a = x, *b = y;
    return a->first < b->first ? -1 : a->first > b->first;
}

/* Rank 0 once every block is written: the header, GRID and DATA's head, with
 * DATA's CRC combined from the batches' in probe order. */
static void put_head(coord* c) {
    outfile* of = c->of;
    qsort(c->recs, c->nrec, sizeof *c->recs, rec_cmp);
    uint8_t fc[8];
    uint32_t count = c->end - c->first;
    for (int k = 0; k < 4; k++) fc[k] = (uint8_t)(c->first >> 8 * k), fc[4 + k] = (uint8_t)(count >> 8 * k);
    uint32_t crc = vx_crc32(0, fc, 8), at = c->first;
    for (size_t i = 0; i < c->nrec; i++) {
        if (c->recs[i].first != at) die("internal: the output misses probes %u..%u", at, c->recs[i].first);
        crc = (uint32_t)crc32_combine(crc, c->recs[i].crc, (z_off_t)((uint64_t)c->recs[i].count * of->block));
        at += c->recs[i].count;
    }
    if (at != c->end) die("internal: the output misses probes %u..%u", at, c->end);
    /* the header and GRID as the library writes them (a set with no maps), then DATA's head */
    vx_probe_set g = *c->ps;
    g.first = 0, g.count = 0;
    uint8_t* data = NULL;
    size_t size = 0;
    vx_error err = {0};
    if (vx_probe_write(&g, NULL, &data, &size, &err)) die("%s: %s", c->j->out, err.msg);
    if (size + 24 != of->base) die("internal: a header of %zu bytes", size);
    uint8_t* h = realloc(data, of->base);
    if (!h) die("out of memory");
    uint64_t dsize = 8 + (uint64_t)count * of->block;
    h[12] = 2, h[13] = h[14] = h[15] = 0; /* sections: GRID, DATA */
    memcpy(h + size, "DATA", 4);
    for (int k = 0; k < 4; k++) h[size + 4 + k] = (uint8_t)(crc >> 8 * k);
    for (int k = 0; k < 8; k++) h[size + 8 + k] = (uint8_t)(dsize >> 8 * k);
    memcpy(h + size + 16, fc, 8);
    write_at(of, 0, h, of->base);
    free(h);
}

/* ---- ranks > 0: workers ---------------------------------------------------------- */

/* A worker's batch in the output: reported to rank 0 (the VX_BAKE_MPI_FAIL
 * hook fires after the K-th report, when K batch files are on disk). */
typedef struct wreport {
    double* st;
    int fail_rank, fail_after, reports;
    bool fail_error;
} wreport;

static void worker_done(void* user, const wdone* d) {
    wreport* r = user;
    double t = vx_time_now();
    uint8_t m[HEAD] = {0};
    memcpy(m, &d->first, 4);
    memcpy(m + 4, &d->count, 4);
    memcpy(m + 8, &d->sec, 8);
    memcpy(m + 16, &d->crc, 4);
    MPI_Send(m, HEAD, MPI_BYTE, 0, TAG_RESULT, MPI_COMM_WORLD);
    r->st[ST_COMM] += vx_time_now() - t;
    if (g_mpi.rank == r->fail_rank && ++r->reports >= r->fail_after) {
        if (r->fail_error) die("failing after %d batches (VX_BAKE_MPI_FAIL)", r->fail_after);
        fprintf(stderr, "%s: rank %d: killing itself after %d batches (VX_BAKE_MPI_FAIL)\n", vx_tool_name, g_mpi.rank,
                r->fail_after);
        fflush(stderr);
        raise(SIGKILL);
    }
}

static void run_worker(bake_job* j, writer* w, const vx_probe_set* placed, const vx_probe_bake_desc* bd, double st[ST_N]) {
    wreport rep = {.st = st, .fail_rank = -1};
    const char* f = getenv("VX_BAKE_MPI_FAIL");
    if (f) {
        char kind[16] = "";
        if (sscanf(f, "%d:%d:%15s", &rep.fail_rank, &rep.fail_after, kind) < 2) rep.fail_rank = -1;
        rep.fail_error = !strcmp(kind, "error");
    }
    /* a ring of DEPTH assignments: slot k % DEPTH receives assignment k */
    uint32_t q[DEPTH][2];
    MPI_Request recv[DEPTH];
    for (int k = 0; k < DEPTH; k++) MPI_Irecv(q[k], 2, MPI_UINT32_T, 0, TAG_ASSIGN, MPI_COMM_WORLD, &recv[k]);
    for (uint32_t k = 0;; k++) {
        uint32_t s = k % DEPTH;
        double t = vx_time_now();
        MPI_Wait(&recv[s], MPI_STATUS_IGNORE);
        st[ST_WAIT] += vx_time_now() - t;
        uint32_t a = q[s][0], n = q[s][1] - q[s][0];
        if (!n) break;
        /* the slot takes assignment k + DEPTH (posted receives match in order) */
        MPI_Irecv(q[s], 2, MPI_UINT32_T, 0, TAG_ASSIGN, MPI_COMM_WORLD, &recv[s]);
        vx_probe_set v = view_at(placed, a);
        t = vx_time_now();
        vx_error err = {0};
        if (bake_range(j, bd, &v, a + n, &err)) die("%s: %s", j->in, err.msg);
        double sec = vx_time_now() - t;
        st[ST_BAKE] += sec;
        st[ST_PROBES] += n, st[ST_BATCHES] += 1;
        /* the batch file and the blocks in the output before rank 0 hears of the batch */
        writer_put(w, j, &v, true, sec, worker_done, &rep);
    }
    writer_flush(w, worker_done, &rep);
    /* rank 0 sends nothing after the empty assignment: drop the receives still posted */
    for (int k = 0; k < DEPTH; k++) {
        if (recv[k] != MPI_REQUEST_NULL) {
            MPI_Cancel(&recv[k]);
            MPI_Wait(&recv[k], MPI_STATUS_IGNORE);
        }
    }
}

/* ---- the job ------------------------------------------------------------------------- */

/* After the last flush nothing is left in the writer. */
static void no_more(void* user, const wdone* d) {
    (void)user;
    die("internal: probes %u..%u written after the last report", d->first, d->first + d->count);
}

/* A rank's device once its batches are baked (bake_job_close then has only
 * the scene to free). */
static void close_device(void* arg) {
    bake_job* j = arg;
    vx_probe_baker_destroy(j->baker);
    vx_render_scene_destroy(j->rs);
    vx_gpu_destroy(j->gpu);
    j->baker = NULL, j->rs = NULL, j->gpu = NULL;
}

/* The placement on a thread of its own while MPI starts (it needs only the scene). */
typedef struct place_job {
    const vx_svo_scene* scene;
    vx_probe_bake_desc d;
    vx_probe_set ps;
    vx_result r;
    vx_error err;
    pthread_t thread;
    bool started;
    double seconds;
} place_job;

static void* place_main(void* arg) {
    place_job* p = arg;
    double t = vx_time_now();
    p->r = vx_probe_place(p->scene, &p->d, &p->ps, &p->err);
    p->seconds = vx_time_now() - t;
    return NULL;
}

int bake_mpi(options* o, const char* in, const char* out) {
    /* rank 0's start-up and end, for -v: where the time outside the bake goes */
    double t_in = vx_time_now(), tl[6];
    vx_tool_timeline line; /* the same on the wall clock, every rank's (-v) */
    vx_tool_timeline_start(&line);
    o->b.first = o->b.count = 0;
    bake_job j = {.o = *o, .in = in, .out = out};
    char device[16], who[300], host[256] = "";
    if (gethostname(host, sizeof host - 1) != 0) host[0] = 0;
    snprintf(who, sizeof who, "rank %d (%s): ", vx_tool_mpi_env_rank(), host);
    /* the scene is read and the device opens on its own thread while MPI
     * starts (the rank's GPU from the launcher's local rank; where that is
     * unknown, after MPI_Init) and while the probes are placed: with two
     * ranks starting together the device took 0.52-0.64 s after an MPI_Init
     * of 0.26 s (H200 x2) */
    int lr = vx_tool_mpi_env_local_rank();
    /* --load models: after MPI_Init, each rank builds the compact layout from the reader, places the probes from
     * it and makes the device on this thread (bake_job_models: the layout first, an idle device lowers the clock),
     * on the rank's GPU (the launcher's local rank, else MPI's) */
    bool models = o->load_models;
    bool early = !models && (o->cpu || o->device || lr >= 0);
    /* the rank's driver sees only the rank's GPU (vx_tool_mpi_gpu_only: every
     * rank attaching every GPU made the ranks' Vulkan starts wait for each other) */
    int node = -1;
    char wide[16];
    const char* dev = early ? vx_tool_mpi_device_narrowed(lr, o->device, o->cpu, device, &node) : NULL;
    if (node >= 0) j.fallback = vx_tool_mpi_device(lr, o->device, o->cpu, wide), j.widen = vx_tool_mpi_gpu_all;
    int open_rc = early ? bake_job_open(&j, dev, who) : 0;
    place_job pj = {.scene = &j.scene, .d = o->b};
    if (early && !open_rc) pj.started = pthread_create(&pj.thread, NULL, place_main, &pj) == 0;
    tl[0] = vx_time_now();
    vx_tool_timeline_mark(&line, VX_TL_MPI_INIT);
    vx_tool_mpi_init(&g_mpi);
    vx_tool_timeline_mark(&line, VX_TL_MPI_READY);
    tl[1] = vx_time_now();
    int provided = g_mpi.thread_level, nranks = g_mpi.nranks;
    if (!o->threads_set) o->threads = vx_tool_mpi_threads(&g_mpi);
    o->b.threads = o->threads;
    j.o.threads = o->threads, j.o.b.threads = o->threads;
    snprintf(who, sizeof who, "rank %d (%s): ", g_mpi.rank, g_mpi.host);
    if (!early && !models) open_rc = bake_job_open(&j, vx_tool_mpi_device(g_mpi.local_rank, o->device, o->cpu, device), who);
    if (models) {
        j.o.device = vx_tool_mpi_device(g_mpi.local_rank, o->device, o->cpu, device);
        double t = vx_time_now();
        open_rc = bake_job_models(&j, &pj.ps, who);
        pj.seconds = vx_time_now() - t; /* (the layout, the placement and the device) */
    }
    if (open_rc) {
        fflush(stderr);
        MPI_Abort(MPI_COMM_WORLD, 1);
    }
    vx_error err = {0};
    if (pj.started) pthread_join(pj.thread, NULL);
    else if (!models) place_main(&pj);
    if (pj.r) die("%s: %s", in, pj.err.msg);
    vx_probe_set ps = pj.ps;
    tl[2] = vx_time_now();
    if (bake_job_device(&j, who)) {
        fflush(stderr);
        MPI_Abort(MPI_COMM_WORLD, 1);
    }
    tl[3] = vx_time_now();
    if (j.gpu) memcpy(&line.t[VX_TL_VK_START], j.go.at, sizeof j.go.at);
    make_ckdir(&j);
    outfile of = {0};
    outfile_open(&j, &ps, &of);
    writer w;
    writer_start(&w, &of);
    tl[4] = vx_time_now();
    /* one line per rank, in rank order */
    for (int r = 0; r < nranks; r++) {
        if (r == g_mpi.rank) {
            char seen[64] = "";
            if (node >= 0)
                snprintf(seen, sizeof seen, j.go.fell_back ? " (every GPU: /dev/nvidia%d alone failed)" : " (sees /dev/nvidia%d alone)", node);
            if (j.gpu)
                printf("rank %d (%s): device: %s%s%s\n", g_mpi.rank, g_mpi.host, vx_gpu_device_name(j.gpu),
                       vx_gpu_is_cpu(j.gpu) ? " (software)" : "", seen);
            else
                printf("rank %d (%s): device: CPU (%u threads, double precision)\n", g_mpi.rank, g_mpi.host, o->threads);
            fflush(stdout);
        }
        MPI_Barrier(MPI_COMM_WORLD);
    }
    double st[ST_N] = {0};
    double t_write = 0, t_sync = 0, t_start = 0;
    int rc = 0;
    coord c = {0};
    if (g_mpi.rank == 0) {
        uint32_t moved = 0, disabled = 0;
        for (uint32_t i = 0; i < ps.probe_count; i++)
            moved += ps.probes[i].state == VX_PROBE_MOVED, disabled += ps.probes[i].state == VX_PROBE_DISABLED;
        printf("grid: %ux%ux%u = %s probes (%u moved out of voxels, %u disabled), spacing %g,%g,%g; %d ranks\n",
               ps.grid[0], ps.grid[1], ps.grid[2], vx_tool_num(ps.probe_count), moved, disabled, ps.spacing[0],
               ps.spacing[1], ps.spacing[2], nranks);
        uint32_t end = ps.probe_count;
        bool prefix = resume_checkpoint(&j, &ps, end);
        if (ps.first != 0) die("%s: a checkpoint from probe %u", j.ckpath, ps.first);
        c.j = &j, c.ps = &ps, c.of = &of, c.w = &w, c.first = ps.first, c.end = end, c.nranks = nranks;
        c.next = ps.first + ps.count;
        size_t pb = maps_probe_bytes(&ps);
        c.done = calloc(end - c.first + 1, 1);
        c.ended = calloc((size_t)nranks, sizeof *c.ended);
        /* maps for the probes resumed from checkpoints, only where there may be
         * some (they are zeroed: 845 MB took rank 0 about 0.4 s at each start) */
        bool any = prefix || ckdir_has_files(&j);
        if (!c.done || !c.ended || (any && !maps_reserve(&ps, end - c.first)))
            die("out of memory for %u probes at res %u", end - c.first, ps.res);
        memset(c.done, 1, ps.count);
        c.received = ps.count + (any ? resume_batches(&j, &ps, end, c.done, pb) : 0);
        fflush(stdout);
        /* a GPU batch costs about 45 ms besides its probes (H200, R=128: 1.2 ms a
         * probe), so batches of fewer than 64 probes are left to small jobs */
        uint32_t small = ps.probe_count / (8u * (uint32_t)nranks);
        c.min_batch = o->cpu ? o->threads : (small < 1 ? 1 : (small > 64 ? 64 : small));
        uint64_t bc = (UINT64_C(1) << 28) / of.block; /* 256 MiB a write */
        c.byte_cap = (uint32_t)(bc < 1 ? 1 : (bc > (1u << 20) ? (1u << 20) : bc));
        if (c.min_batch > c.byte_cap) c.min_batch = c.byte_cap;
        c.cap = 2 * c.min_batch;
        c.serve_in_bake = provided >= MPI_THREAD_SERIALIZED || !o->cpu || o->threads == 1;
        c.show = !o->quiet && isatty(2);
    }
    MPI_Barrier(MPI_COMM_WORLD);
    t_start = vx_time_now();
    vx_tool_timeline_mark(&line, VX_TL_WORK);
    c.t0 = t_start;
    if (g_mpi.rank == 0) {
        run_coordinator(&c, &o->b);
        memcpy(st, c.st, sizeof st);
    } else {
        run_worker(&j, &w, &ps, &o->b, st);
    }
    writer_stop(&w, no_more, NULL); /* every block of this rank written and reported */
    vx_tool_timeline_mark(&line, VX_TL_DONE);
    st[ST_CKPT] = w.ser_s, st[ST_IO] = w.io_s;
    /* ranks idle here until every block is written: load imbalance */
    double t = vx_time_now();
    MPI_Barrier(MPI_COMM_WORLD);
    st[ST_WAIT] += vx_time_now() - t;
    /* the device closes beside the head and the rename; not before every
     * rank has baked: the driver serialises across processes, and a close
     * slowed the ranks still at work (svo_render/mpi.c) */
    vx_tool_bg closing = {0};
    vx_tool_bg_start(&closing, close_device, &j);
    st[ST_WALL] = vx_time_now() - t_start;
    /* the head, every rank's data on disk, then the name */
    t = vx_time_now();
    if (g_mpi.rank == 0) put_head(&c);
    if (g_mpi.rank == 0) vx_tool_timeline_mark(&line, VX_TL_REDUCED);
    double ts = vx_time_now();
    if (MPI_File_sync(of.fh) != MPI_SUCCESS) die("%s: cannot sync", of.tmp);
    t_sync = vx_time_now() - ts;
    if (MPI_File_close(&of.fh) != MPI_SUCCESS) die("%s: cannot close", of.tmp);
    if (of.fd >= 0) close(of.fd);
    if (g_mpi.rank == 0) {
        if (rename(of.tmp, out) != 0) {
            fprintf(stderr, "%s: %s: cannot write: %s\n", vx_tool_name, out, strerror(errno));
            remove(of.tmp);
            rc = 1;
        }
        t_write = vx_time_now() - t;
        vx_tool_timeline_mark(&line, VX_TL_OUTPUT);
        if (!rc) remove(j.ckpath);
    }
    MPI_Bcast(&rc, 1, MPI_INT, 0, MPI_COMM_WORLD);
    tl[5] = vx_time_now();
    if (!rc) remove_batches(&j);
    double t_rm = vx_time_now() - tl[5];
    free_saved();
    double* all = g_mpi.rank == 0 ? calloc((size_t)nranks * ST_N, sizeof(double)) : NULL;
    MPI_Gather(st, ST_N, MPI_DOUBLE, all, ST_N, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    if (g_mpi.rank == 0 && !rc) {
        double wmax = 0;
        for (int r = 0; r < nranks && all; r++) {
            const double* s = all + (size_t)r * ST_N;
            double share = s[ST_WALL] > 0 ? s[ST_WAIT] / s[ST_WALL] : 0;
            if (share > wmax) wmax = share;
            if (o->verbose)
                printf("rank %d: %.0f probes in %.0f batches, bake %.3f s, wait %.3f s (%.1f%%), messages %.3f s, "
                       "batches serialised and checksummed %.3f s, batch files and output writes %.3f s (both on a thread)\n",
                       r, s[ST_PROBES], s[ST_BATCHES], s[ST_BAKE], s[ST_WAIT], 100 * share, s[ST_COMM], s[ST_CKPT],
                       s[ST_IO]);
        }
        if (o->verbose) {
            printf("output: %llu bytes through MPI-IO; head + sync + rename %.3f s (sync %.3f s)\n",
                   (unsigned long long)of.size, t_write, t_sync);
            printf("rank 0 outside the bake: scene %.3f s, MPI_Init %.3f s, placement %.3f s (%s; waited %.3f s), "
                   "device %.3f s on its thread (Vulkan %.3f s; %s; waited %.3f s), output file %.3f s, to the start %.3f s; after "
                   "it: writing %.3f s, batch files removed %.3f s; %.3f s from start to MPI_Finalize\n",
                   tl[0] - t_in, tl[1] - tl[0], pj.seconds,
                   models ? "--load models: the layout, the placement and the device after it"
                          : pj.started ? "on a thread while MPI starts" : "after it",
                   tl[2] - tl[1], j.t_device, j.t_vk, early ? "from the start" : "after MPI_Init", j.t_wait, tl[4] - tl[3],
                   t_start - tl[4], t_write, t_rm, vx_time_now() - t_in);
        }
        printf("baked %u probes at %ux%u, %u spp, %u bounces on %d ranks in %.2f s (most waiting: %.1f%%; rank 0 "
               "reports %.3f s, writing %.3f s); distance step %.4g (max error %.4g)\n",
               c.received, ps.res, ps.res, ps.spp, ps.bounces, nranks, st[ST_WALL], 100 * wmax, st[ST_COMM], t_write,
               ps.dist_step, ps.dist_max_error);
        printf("wrote %s\n", out);
        if (o->exr_dir) {
            /* the maps are in the file, not in rank 0's memory */
            vx_probe_set_free(&ps);
            if (vx_probe_read_file(NULL, out, &ps, &err)) rc = vx_tool_error(out, &err);
            else rc = write_exr(o->exr_dir, &ps);
        }
    }
    free(all);
    free(c.done);
    free(c.ended);
    free(c.recs);
    vx_probe_set_free(&ps);
    vx_tool_bg_wait(&closing);
    bake_job_close(&j);
    int rank = g_mpi.rank;
    MPI_Finalize();
    vx_tool_timeline_mark(&line, VX_TL_END);
    if (o->verbose) vx_tool_timeline_print(&line, rank);
    return rc;
}
