/* tools/svo_bake/mpi.c - svo_bake under MPI: mpirun -n N svo_bake SCENE OUT [options].
 *
 * Every rank reads the scene, opens its device (GPU `local rank mod GPUs` of
 * its host, or --device, or --cpu) and places the same probe grid. Rank 0
 * hands out batches of consecutive probes (guided sizes: a share of what is
 * left, so probes that cost more, near geometry, even out) and bakes
 * batches itself; each worker holds three assignments, so the next is there
 * when it sends a batch's maps back. Rank 0 answers between and during its
 * own batches (from the bake's progress callback), copies each batch into
 * the output set, checkpoints the baked prefix to OUT.probes.partial (the
 * single-process checkpoint: either kind of run resumes the other's) and
 * finally writes OUT.probes atomically.
 *
 * Per-rank checkpoints: every rank also saves each batch it bakes, before
 * sending it, as OUT.probes.ckpt/bFIRST-END.rRANK.probes (a .probes file of
 * that range, written atomically), so a job that dies loses only the batches
 * in flight, not every batch past the first gap of the prefix. A rerun's rank 0
 * takes every batch file of the same job it finds there (and the prefix
 * checkpoint) and hands out only the probes still missing; the files go once
 * the output is written. Across hosts the folder must be shared for the
 * batches of other hosts to count; the bytes are the same either way. A probe's maps depend only on the
 * seed and its index, so the bytes equal a single-process bake whatever N.
 * A rank that fails calls MPI_Abort, which ends every rank before rank 0
 * writes anything under the output name. Ranks must share one byte order.
 *
 * Test hooks (environment): VX_BAKE_MPI_FAIL=R:K[:error] makes rank R die
 * of SIGKILL (or fail with an error) after sending its K-th batch (its
 * batch files for those K batches are on disk by then);
 * VX_BAKE_CHECKPOINT_S sets the seconds between checkpoints (default 20). */
#define _POSIX_C_SOURCE 200809L /* kill() */
#include <dirent.h>
#include <errno.h>
#include <mpi.h>
#include <signal.h>
#include <sys/stat.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "tools/common/mpi.h"
#include "tools/common/tool.h"
#include "tools/svo_bake/svo_bake.h"

enum { TAG_ASSIGN = 1, TAG_RESULT = 2 };
enum { DEPTH = 3 }; /* assignments a worker holds */
enum { HEAD = 16 }; /* a result: first probe (u32), count (u32), bake seconds (f64), then the maps */

/* this rank's place (set once by bake_mpi) */
static vx_tool_mpi g_mpi;
#define die vx_tool_mpi_die

/* per-rank timings, gathered to rank 0 */
enum { ST_WALL, ST_BAKE, ST_WAIT, ST_COMM, ST_PROBES, ST_BATCHES, ST_CKPT, ST_N };

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

/* Saves the baked batch v (probes [v->first, v->first + v->count)). */
static void save_batch(const bake_job* j, const vx_probe_set* v, double* seconds) {
    double t = vx_time_now();
    char path[4200];
    if (snprintf(path, sizeof path, "%s/b%u-%u.r%d.probes", j->ckdir, v->first, v->first + v->count, g_mpi.rank) >=
        (int)sizeof path)
        die("%s: name too long", j->ckdir);
    vx_error err = {0};
    if (vx_probe_write_file(NULL, v, path, &err)) die("batch checkpoint %s", err.msg);
    remember(path);
    *seconds += vx_time_now() - t;
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

typedef struct coord {
    bake_job* j;
    vx_probe_set* ps;       /* output: maps for [first, end), count = baked prefix */
    uint32_t first, end;
    uint32_t next;          /* next probe to hand out */
    uint32_t received;      /* probes stored (own and workers') */
    uint32_t outstanding;   /* probes handed to workers, not yet back */
    uint8_t* done;          /* per probe from first */
    int nranks;
    bool* ended;            /* per rank: sent the empty assignment */
    uint32_t min_batch, cap, byte_cap;
    double per_probe;       /* seconds a probe takes to bake (running estimate), 0 before any */
    size_t pb;              /* bytes per probe */
    uint8_t* buf;           /* receive buffer */
    size_t buf_size;
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
    /* a 1/(2 DEPTH N) share of what is left: a worker holds DEPTH batches,
     * so the last ones are small enough to end the ranks together */
    uint32_t left = c->end - c->next, parts = 2u * DEPTH * (uint32_t)c->nranks;
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

static void advance_prefix(coord* c) {
    uint32_t p = c->ps->first + c->ps->count;
    while (p < c->end && c->done[p - c->first]) p++;
    c->ps->count = p - c->ps->first;
}

static void store(coord* c, uint32_t from, uint32_t n, const uint8_t* maps, int source) {
    if (from < c->first || n > c->end - from) die("rank %d sent probes %u..%u outside %u..%u", source, from, from + n, c->first, c->end);
    for (uint32_t i = from; i < from + n; i++) {
        if (c->done[i - c->first]) die("rank %d sent probe %u twice", source, i);
        c->done[i - c->first] = 1;
    }
    maps_unpack(c->ps, from, n, maps);
    c->received += n;
    advance_prefix(c);
}

/* Receives one result (probed: status) and answers with the next assignment. */
static void take_result(coord* c, MPI_Status* status) {
    double t = vx_time_now();
    int count = 0;
    MPI_Get_count(status, MPI_BYTE, &count);
    if ((size_t)count > c->buf_size) {
        free(c->buf);
        c->buf_size = (size_t)count;
        if (!(c->buf = malloc(c->buf_size))) die("out of memory for a batch of %d bytes", count);
    }
    MPI_Recv(c->buf, count, MPI_BYTE, status->MPI_SOURCE, TAG_RESULT, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    uint32_t h[2];
    double sec = 0;
    if (count < HEAD) die("rank %d sent a %d-byte result", status->MPI_SOURCE, count);
    memcpy(h, c->buf, 8);
    memcpy(&sec, c->buf + 8, 8);
    if ((size_t)count != HEAD + (size_t)h[1] * c->pb)
        die("rank %d sent %d bytes for %u probes (%zu each)", status->MPI_SOURCE, count, h[1], c->pb);
    if (h[1] > c->outstanding) die("rank %d sent probes nobody asked for", status->MPI_SOURCE);
    c->outstanding -= h[1];
    learn(c, h[1], sec);
    hand_out(c, status->MPI_SOURCE);
    store(c, h[0], h[1], c->buf + HEAD, status->MPI_SOURCE);
    c->st[ST_COMM] += vx_time_now() - t;
}

/* Answers every result that has arrived; with block, waits for one first. */
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

static void checkpoint(coord* c, double interval, double* last, uint32_t* last_count) {
    if (c->ps->count == *last_count || c->ps->first + c->ps->count >= c->end) return;
    double now = vx_time_now();
    if (now - *last < interval) return;
    vx_error err = {0};
    if (vx_probe_write_file(NULL, c->ps, c->j->ckpath, &err)) die("%s: %s", c->j->ckpath, err.msg);
    *last = vx_time_now();
    *last_count = c->ps->count;
    c->st[ST_COMM] += *last - now;
}

static void run_coordinator(coord* c, const vx_probe_bake_desc* b) {
    double interval = checkpoint_interval(), last_ck = vx_time_now();
    uint32_t last_count = c->ps->count;
    for (int r = 1; r < c->nranks; r++)
        for (int k = 0; k < DEPTH; k++) hand_out(c, r);
    vx_probe_bake_desc bd = *b;
    bd.progress = (vx_progress){coord_progress, c};
    uint8_t* own = NULL;
    size_t own_size = 0;
    for (uint32_t a, n; take_run(c, &a, &n);) {
        vx_probe_set v = view_at(c->ps, a);
        double t = vx_time_now();
        c->own_done = 0, c->serving = 0;
        vx_error err = {0};
        if (bake_range(c->j, &bd, &v, a + n, &err)) die("%s: %s", c->j->in, err.msg);
        double dt = vx_time_now() - t;
        c->st[ST_BAKE] += dt - c->serving;
        c->st[ST_PROBES] += n, c->st[ST_BATCHES] += 1;
        save_batch(c->j, &v, &c->st[ST_CKPT]);
        t = vx_time_now();
        if (n * c->pb > own_size) {
            free(own);
            own_size = n * c->pb;
            if (!(own = malloc(own_size))) die("out of memory for a batch of %u probes", n);
        }
        maps_pack(&v, a, n, own);
        maps_free(&v);
        c->own_done = 0;
        store(c, a, n, own, 0);
        c->st[ST_COMM] += vx_time_now() - t;
        learn(c, n, dt - c->serving);
        serve(c, false);
        checkpoint(c, interval, &last_ck, &last_count);
        show(c, false);
    }
    free(own);
    while (c->outstanding) {
        serve(c, true);
        checkpoint(c, interval, &last_ck, &last_count);
        show(c, false);
    }
    /* every worker has had its empty assignment by now (each result is
     * answered), except ones that never got work */
    for (int r = 1; r < c->nranks; r++) hand_out(c, r);
    show(c, true);
    if (c->show) fputc('\n', stderr);
}

/* ---- ranks > 0: workers ---------------------------------------------------------- */

static bool worker_progress(void* user, const char* stage, uint64_t done, uint64_t total) {
    (void)stage, (void)done, (void)total;
    int flag;
    MPI_Testall(DEPTH, user, &flag, MPI_STATUSES_IGNORE);
    return true;
}

static void run_worker(bake_job* j, const vx_probe_set* placed, const vx_probe_bake_desc* bd, double st[ST_N]) {
    int fail_rank = -1, fail_after = 0;
    bool fail_error = false;
    const char* f = getenv("VX_BAKE_MPI_FAIL");
    if (f) {
        char kind[16] = "";
        if (sscanf(f, "%d:%d:%15s", &fail_rank, &fail_after, kind) < 2) fail_rank = -1;
        fail_error = !strcmp(kind, "error");
    }
    size_t pb = maps_probe_bytes(placed);
    /* a ring of DEPTH slots: slot k % DEPTH receives assignment k and sends
     * result k, so a result waits for rank 0 only when DEPTH - 1 newer
     * batches are baked (rank 0 answers between its own GPU batches) */
    uint32_t q[DEPTH][2];
    MPI_Request recv[DEPTH], send[DEPTH];
    uint8_t* buf[DEPTH] = {NULL};
    size_t buf_size[DEPTH] = {0};
    /* MPI moves a large message only while the sender calls into it (without
     * single-copy shared memory, e.g. in containers): the bake's progress
     * callback lets the sends of earlier batches proceed during the next */
    vx_probe_bake_desc wbd = *bd;
    if (g_mpi.thread_level >= MPI_THREAD_SERIALIZED || !j->o.cpu || j->o.threads == 1) /* CPU bakes report from their threads */
        wbd.progress = (vx_progress){worker_progress, send};
    for (int k = 0; k < DEPTH; k++) {
        send[k] = MPI_REQUEST_NULL;
        MPI_Irecv(q[k], 2, MPI_UINT32_T, 0, TAG_ASSIGN, MPI_COMM_WORLD, &recv[k]);
    }
    for (uint32_t k = 0;; k++) {
        uint32_t s = k % DEPTH;
        double t = vx_time_now();
        MPI_Wait(&recv[s], MPI_STATUS_IGNORE);
        st[ST_WAIT] += vx_time_now() - t;
        uint32_t a = q[s][0], n = q[s][1] - q[s][0];
        if (!n) break;
        vx_probe_set v = view_at(placed, a);
        t = vx_time_now();
        double t0 = t;
        vx_error err = {0};
        if (bake_range(j, &wbd, &v, a + n, &err)) die("%s: %s", j->in, err.msg);
        st[ST_BAKE] += vx_time_now() - t;
        st[ST_PROBES] += n, st[ST_BATCHES] += 1;
        save_batch(j, &v, &st[ST_CKPT]); /* on disk before rank 0 counts on it */
        t = vx_time_now();
        MPI_Wait(&send[s], MPI_STATUS_IGNORE);
        size_t need = HEAD + n * pb;
        if (need > (size_t)INT32_MAX) die("a batch of %u probes is too large for one message", n);
        if (need > buf_size[s]) {
            free(buf[s]);
            buf_size[s] = need;
            if (!(buf[s] = malloc(need))) die("out of memory for a batch of %u probes", n);
        }
        double sec = vx_time_now() - t0;
        memcpy(buf[s], &a, 4);
        memcpy(buf[s] + 4, &n, 4);
        memcpy(buf[s] + 8, &sec, 8);
        maps_pack(&v, a, n, buf[s] + HEAD);
        maps_free(&v);
        MPI_Isend(buf[s], (int)need, MPI_BYTE, 0, TAG_RESULT, MPI_COMM_WORLD, &send[s]);
        MPI_Irecv(q[s], 2, MPI_UINT32_T, 0, TAG_ASSIGN, MPI_COMM_WORLD, &recv[s]);
        st[ST_COMM] += vx_time_now() - t;
        if (g_mpi.rank == fail_rank && (int)st[ST_BATCHES] >= fail_after) {
            if (fail_error) die("failing after %d batches (VX_BAKE_MPI_FAIL)", fail_after);
            MPI_Wait(&send[s], MPI_STATUS_IGNORE);
            fprintf(stderr, "%s: rank %d: killing itself after %d batches (VX_BAKE_MPI_FAIL)\n", vx_tool_name, g_mpi.rank,
                    fail_after);
            fflush(stderr);
            raise(SIGKILL);
        }
    }
    /* rank 0 sends nothing after the empty assignment: drop the receives
     * still posted, finish the sends */
    double t = vx_time_now();
    for (int k = 0; k < DEPTH; k++) {
        if (recv[k] != MPI_REQUEST_NULL) {
            MPI_Cancel(&recv[k]);
            MPI_Wait(&recv[k], MPI_STATUS_IGNORE);
        }
        MPI_Wait(&send[k], MPI_STATUS_IGNORE);
        free(buf[k]);
    }
    st[ST_COMM] += vx_time_now() - t;
}

/* ---- the job ------------------------------------------------------------------------- */

int bake_mpi(options* o, const char* in, const char* out) {
    vx_tool_mpi_init(&g_mpi);
    int provided = g_mpi.thread_level, nranks = g_mpi.nranks;
    if (!o->threads_set) o->threads = vx_tool_mpi_threads(&g_mpi);
    o->b.threads = o->threads;
    o->b.first = o->b.count = 0;
    bake_job j = {.o = *o, .in = in, .out = out};
    char device[16];
    const char* dev = vx_tool_mpi_device(&g_mpi, o->device, o->cpu, device);
    char who[300];
    snprintf(who, sizeof who, "rank %d (%s): ", g_mpi.rank, g_mpi.host);
    if (bake_job_open(&j, dev, who)) {
        fflush(stderr);
        MPI_Abort(MPI_COMM_WORLD, 1);
    }
    vx_error err = {0};
    vx_probe_set ps;
    if (vx_probe_place(&j.scene, &o->b, &ps, &err)) die("%s: %s", in, err.msg);
    make_ckdir(&j);
    /* one line per rank, in rank order */
    for (int r = 0; r < nranks; r++) {
        if (r == g_mpi.rank) {
            if (j.gpu)
                printf("rank %d (%s): device: %s%s\n", g_mpi.rank, g_mpi.host, vx_gpu_device_name(j.gpu),
                       vx_gpu_is_cpu(j.gpu) ? " (software)" : "");
            else
                printf("rank %d (%s): device: CPU (%u threads, double precision)\n", g_mpi.rank, g_mpi.host, o->threads);
            fflush(stdout);
        }
        MPI_Barrier(MPI_COMM_WORLD);
    }
    double st[ST_N] = {0};
    double t_write = 0, t_start = 0;
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
        resume_checkpoint(&j, &ps, end);
        c.j = &j, c.ps = &ps, c.first = ps.first, c.end = end, c.nranks = nranks;
        c.next = ps.first + ps.count;
        c.received = ps.count;
        c.pb = maps_probe_bytes(&ps);
        c.done = calloc(end - c.first + 1, 1);
        c.ended = calloc((size_t)nranks, sizeof *c.ended);
        if (!c.done || !c.ended || !maps_reserve(&ps, end - c.first))
            die("out of memory for %u probes at res %u", end - c.first, ps.res);
        memset(c.done, 1, ps.count);
        c.received = ps.count + resume_batches(&j, &ps, end, c.done, c.pb);
        advance_prefix(&c);
        fflush(stdout);
        c.min_batch = o->cpu ? o->threads : 1;
        uint64_t bc = (UINT64_C(1) << 28) / c.pb; /* 256 MiB a message */
        c.byte_cap = (uint32_t)(bc < 1 ? 1 : (bc > (1u << 20) ? (1u << 20) : bc));
        if (c.min_batch > c.byte_cap) c.min_batch = c.byte_cap;
        c.cap = 2 * c.min_batch;
        c.serve_in_bake = provided >= MPI_THREAD_SERIALIZED || !o->cpu || o->threads == 1;
        c.show = !o->quiet && isatty(2);
    }
    MPI_Barrier(MPI_COMM_WORLD);
    t_start = vx_time_now();
    c.t0 = t_start;
    if (g_mpi.rank == 0) {
        run_coordinator(&c, &o->b);
        memcpy(st, c.st, sizeof st);
    } else {
        run_worker(&j, &ps, &o->b, st);
    }
    /* workers idle here until rank 0 holds every probe: load imbalance */
    double t = vx_time_now();
    MPI_Barrier(MPI_COMM_WORLD);
    st[ST_WAIT] += vx_time_now() - t;
    st[ST_WALL] = vx_time_now() - t_start;
    if (g_mpi.rank == 0) {
        t = vx_time_now();
        if (vx_probe_write_file(NULL, &ps, out, &err)) rc = vx_tool_error(out, &err);
        t_write = vx_time_now() - t;
        if (!rc) remove(j.ckpath);
    }
    MPI_Bcast(&rc, 1, MPI_INT, 0, MPI_COMM_WORLD);
    if (!rc) remove_batches(&j);
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
                       "batch checkpoints %.3f s\n",
                       r, s[ST_PROBES], s[ST_BATCHES], s[ST_BAKE], s[ST_WAIT], 100 * share, s[ST_COMM], s[ST_CKPT]);
        }
        printf("baked %u probes at %ux%u, %u spp, %u bounces on %d ranks in %.2f s (most waiting: %.1f%%; rank 0 "
               "storing results %.3f s, writing %.3f s); distance step %.4g (max error %.4g)\n",
               ps.count, ps.res, ps.res, ps.spp, ps.bounces, nranks, st[ST_WALL], 100 * wmax, st[ST_COMM], t_write,
               ps.dist_step, ps.dist_max_error);
        printf("wrote %s\n", out);
        if (o->exr_dir) rc = write_exr(o->exr_dir, &ps);
    }
    free(all);
    free(c.done);
    free(c.ended);
    free(c.buf);
    vx_probe_set_free(&ps);
    bake_job_close(&j);
    MPI_Finalize();
    return rc;
}
