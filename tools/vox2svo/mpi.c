/* tools/vox2svo/mpi.c - vox2svo under mpirun (mpi.h).
 *
 * Every rank reads the mesh, bins its triangles and computes the same
 * partition of the regions (vx_conv_mesh_share: no messages before the
 * gather); each voxelizes and builds its own regions' models and codes each
 * into its stream of the file's NODE section (vx_svo_model_encode, on the
 * rank's threads), freeing the model's arrays and keeping its fields. Rank 0
 * gathers every part's fields and coded summary, assembles the scene with
 * vx_conv_mesh_assemble (the code one process runs, here on models without
 * their arrays), and writes the file with vx_svo_write_file_coded, taking
 * the streams in model order: its own from memory, the others' from their
 * ranks, which send them in region order, one at a time. So the file is the
 * single-process file byte for byte (test_vox2svo_mpi), rank 0 never holds
 * the scene's trees (its own streams and one received stream), and the
 * entropy coding runs on every rank at once. A region is one model and the
 * file format shares subtrees within a model only, so no subtree has to be
 * looked up across ranks: identical subtrees of a region are shared (the
 * DAG) by the rank that builds it, exactly as one process shares them. The
 * parts' fields travel as raw structs: the ranks run the same binary on
 * hosts of one byte order. */
#include "tools/vox2svo/mpi.h"

#include <mpi.h>
#include <pthread.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "convert/mesh.h"
#include "tools/common/mpi.h"
#include "tools/common/tool.h"

#define die vx_tool_mpi_die

enum { TAG_COUNT = 1, TAG_META, TAG_DATA, TAG_MATS };
#define CHUNK ((size_t)1 << 30) /* MPI counts are ints: arrays go in pieces of 1 GiB */

static vx_tool_mpi g_mpi;

/* What each rank reports at the end (-v). */
enum { F_REGIONS, F_VOXELS, F_READ, F_CONVERT, F_ENCODE, F_GATHER, F_WALL, F_PEAK, F_SENT, F_COUNT };
static double g_fig[F_COUNT];
static double g_t0;
static bool g_verbose;

/* The fixed fields of a part and its coded summary; its stream follows,
 * in region order, when rank 0 writes. */
typedef struct part_meta {
    uint64_t index, voxel_count;
    uint32_t origin[3], size[3];
    uint32_t depth, root, root_attr, attrs, node_count, attr_count;
    vx_svo_build_stats build;
    double seconds_build;
    vx_svo_model_coded coded;
    uint32_t material_id_count; /* then that many uint16_t (TAG_MATS) when not 0 */
} part_meta;

/* A part on rank 0: where its stream is (owner rank, or in memory). */
typedef struct held {
    size_t index;
    vx_svo_model_coded coded;
    int owner;
    uint8_t* stream; /* owner 0: the stream until written */
} held;

static int held_cmp(const void* a, const void* b) {
    size_t x = ((const held*)a)->index, y = ((const held*)b)->index;
    return x < y ? -1 : x > y;
}

static void send_bytes(const void* p, size_t n) {
    for (size_t o = 0; o < n; o += CHUNK) {
        size_t k = n - o < CHUNK ? n - o : CHUNK;
        MPI_Send((const char*)p + o, (int)k, MPI_BYTE, 0, TAG_DATA, MPI_COMM_WORLD);
    }
}

static void recv_bytes(void* p, size_t n, int src) {
    for (size_t o = 0; o < n; o += CHUNK) {
        size_t k = n - o < CHUNK ? n - o : CHUNK;
        MPI_Recv((char*)p + o, (int)k, MPI_BYTE, src, TAG_DATA, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    }
}

/* ---- coding this rank's parts on its threads ---- */

typedef struct encode_jobs {
    vx_conv_mesh_part* parts;
    vx_svo_model_coded* coded;
    uint8_t** streams;
    size_t n, next;
    pthread_mutex_t lock;
    const vx_allocator* alloc;
    vx_write_desc chunking; /* svo_chunk_words, svo_chunk_fast, svo_chunk_deflate (--chunked, --chunked-fast, --chunked-deflate) */
    int failed; /* first failing part + 1 */
    vx_error err;
} encode_jobs;

static void* encode_worker(void* arg) {
    encode_jobs* j = (encode_jobs*)arg;
    for (;;) {
        pthread_mutex_lock(&j->lock);
        size_t i = j->next++;
        bool stop = j->failed != 0;
        pthread_mutex_unlock(&j->lock);
        if (stop || i >= j->n) return NULL;
        vx_svo_model* m = &j->parts[i].model;
        vx_write_desc wd = j->chunking;
        wd.alloc = j->alloc, wd.threads = 1;
        vx_error e = {0};
        if (vx_svo_model_encode(&wd, m, &j->coded[i], &j->streams[i], &e) != VX_OK) {
            pthread_mutex_lock(&j->lock);
            if (!j->failed) j->failed = (int)i + 1, j->err = e;
            pthread_mutex_unlock(&j->lock);
            return NULL;
        }
        /* coded: only the model's fields stay (the scene's SCNE needs them) */
        vx_svo_model keep = *m;
        keep.nodes = NULL, keep.palette = NULL, keep.normal = NULL, keep.material = NULL, keep.density = NULL, keep.rgba = NULL;
        vx_svo_model_free(j->alloc, m);
        *m = keep;
    }
}

static void encode_parts(vx_conv_mesh_part* parts, size_t n, unsigned threads, const vx_allocator* alloc,
                         const vx_write_desc* chunking, vx_svo_model_coded* coded, uint8_t** streams) {
    encode_jobs j = {.parts = parts, .coded = coded, .streams = streams, .n = n, .alloc = alloc, .chunking = *chunking};
    pthread_mutex_init(&j.lock, NULL);
    unsigned nt = threads < 1 ? 1 : threads > 64 ? 64 : threads;
    if (nt > n) nt = n ? (unsigned)n : 1;
    pthread_t tid[64];
    unsigned started = 0;
    for (unsigned t = 1; t < nt; t++)
        if (pthread_create(&tid[started], NULL, encode_worker, &j) == 0) started++;
    encode_worker(&j);
    for (unsigned t = 0; t < started; t++) pthread_join(tid[t], NULL);
    pthread_mutex_destroy(&j.lock);
    if (j.failed) die("region %zu: %s", parts[j.failed - 1].index, j.err.msg);
}

static void send_part(const vx_conv_mesh_part* p, const vx_svo_model_coded* coded) {
    const vx_svo_model* m = &p->model;
    part_meta h;
    memset(&h, 0, sizeof h);
    h.index = p->index;
    h.voxel_count = m->voxel_count;
    memcpy(h.origin, p->origin, sizeof h.origin);
    memcpy(h.size, m->size, sizeof h.size);
    h.depth = m->depth, h.root = m->root, h.root_attr = m->root_attr, h.attrs = m->attrs;
    h.node_count = m->node_count, h.attr_count = m->attr_count;
    h.build = p->build;
    h.seconds_build = p->seconds_build;
    h.coded = *coded;
    h.material_id_count = p->material_id_count;
    MPI_Send(&h, (int)sizeof h, MPI_BYTE, 0, TAG_META, MPI_COMM_WORLD);
    /* the material ids the part's cells name (at most 65535: one message) */
    if (h.material_id_count)
        MPI_Send(p->material_ids, (int)h.material_id_count, MPI_UINT16_T, 0, TAG_MATS, MPI_COMM_WORLD);
}

static void recv_part(int src, vx_conv_mesh_part* p, held* hp, const vx_allocator* alloc) {
    part_meta h;
    MPI_Recv(&h, (int)sizeof h, MPI_BYTE, src, TAG_META, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    memset(p, 0, sizeof *p);
    p->index = (size_t)h.index;
    memcpy(p->origin, h.origin, sizeof p->origin);
    p->build = h.build;
    p->seconds_build = h.seconds_build;
    vx_svo_model* m = &p->model;
    memcpy(m->size, h.size, sizeof m->size);
    m->depth = h.depth, m->root = h.root, m->root_attr = h.root_attr, m->attrs = h.attrs;
    m->voxel_count = h.voxel_count, m->node_count = h.node_count, m->attr_count = h.attr_count;
    if (h.material_id_count > 65535u) die("rank %d sent %u material ids", src, h.material_id_count);
    if (h.material_id_count) {
        p->material_ids = (uint16_t*)vx_alloc(alloc, h.material_id_count * sizeof *p->material_ids);
        if (!p->material_ids) die("out of memory for %u material ids", h.material_id_count);
        MPI_Recv(p->material_ids, (int)h.material_id_count, MPI_UINT16_T, src, TAG_MATS, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        p->material_id_count = h.material_id_count;
    }
    hp->index = p->index;
    hp->coded = h.coded;
    hp->owner = src;
    hp->stream = NULL;
}

/* Rank 0: its own parts, then every other rank's fields, in the order the
 * ranks finish (each rank's parts arrive in one run after its count). */
static vx_conv_mesh_part* gather(vx_conv_mesh_part* parts, size_t* count, held** hs, const vx_allocator* alloc) {
    size_t cap = *count, hcap = *count;
    for (int k = 1; k < g_mpi.nranks; k++) {
        uint64_t n = 0;
        MPI_Status st;
        MPI_Recv(&n, 1, MPI_UINT64_T, MPI_ANY_SOURCE, TAG_COUNT, MPI_COMM_WORLD, &st);
        if (n > SIZE_MAX / sizeof *parts - *count) die("rank %d sent %llu regions", st.MPI_SOURCE, (unsigned long long)n);
        if (n && (!vx_grow(alloc, (void**)&parts, &cap, *count + (size_t)n, sizeof *parts) ||
                  !vx_grow(alloc, (void**)hs, &hcap, *count + (size_t)n, sizeof **hs)))
            die("out of memory for %zu regions", *count + (size_t)n);
        for (uint64_t i = 0; i < n; i++, (*count)++) recv_part(st.MPI_SOURCE, &parts[*count], &(*hs)[*count], alloc);
    }
    return parts;
}

/* Rank 0's state between vox2svo_mpi and vox2svo_mpi_write: every part in
 * model (region) order. */
static held* g_held;
static size_t g_nheld;
static const vx_allocator* g_alloc;

static bool read_stream(void* user, uint32_t model, uint8_t* buf, uint64_t size) {
    (void)user;
    if (model >= g_nheld || size != g_held[model].coded.stream_size) return false;
    held* h = &g_held[model];
    if (h->owner == 0) {
        memcpy(buf, h->stream, (size_t)size);
        vx_free(g_alloc, h->stream);
        h->stream = NULL;
    } else {
        recv_bytes(buf, (size_t)size, h->owner);
    }
    return true;
}

vx_result vox2svo_mpi_write(const vx_svo_scene* scene, const char* path, vx_error* err) {
    if (scene->model_count != g_nheld) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "%s: scene of %u models for %zu coded parts", path, scene->model_count, g_nheld);
    vx_svo_model_coded* info = (vx_svo_model_coded*)vx_calloc(g_alloc, g_nheld ? g_nheld : 1, sizeof *info);
    if (!info) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "%s: out of memory", path);
    for (size_t i = 0; i < g_nheld; i++) info[i] = g_held[i].coded;
    vx_svo_stream_source src = {read_stream, NULL};
    vx_result r = vx_svo_write_file_coded(NULL, scene, info, &src, path, err);
    vx_free(g_alloc, info);
    for (size_t i = 0; i < g_nheld; i++) vx_free(g_alloc, g_held[i].stream);
    vx_free(g_alloc, g_held);
    g_held = NULL;
    g_nheld = 0;
    return r;
}

bool vox2svo_mpi(const char* in, const vx_tool_conv* conv, const vx_write_desc* chunking, bool quiet, bool verbose, vx_svo_scene* scene,
                 vx_tool_loaded* info) {
    vx_tool_mpi_init(&g_mpi);
    g_t0 = vx_time_now();
    g_verbose = verbose;
    bool root = g_mpi.rank == 0;
    vx_logger log = vx_tool_logger(verbose && root);
    vx_conv_file_desc fd = vx_tool_conv_file_desc(conv, false, &log, vx_tool_progress(quiet || !root));
    vx_conv_mesh_desc md = vx_conv_mesh_desc_from_file(&fd);
    md.threads = vx_tool_mpi_threads(&g_mpi);
    vx_error err = {0};
    vx_gltf_mesh mesh;
    if (vx_conv_mesh_read(&md, in, &mesh, &err)) die("%s: %s", in, err.msg);
    double t1 = vx_time_now();
    g_fig[F_READ] = t1 - g_t0;
    vx_conv_mesh_part* parts = NULL;
    size_t n = 0;
    vx_conv_stats st = {0};
    if (vx_conv_mesh_share(&md, &mesh, (uint32_t)g_mpi.rank, (uint32_t)g_mpi.nranks, &parts, &n, &st, &err))
        die("%s: %s", in, err.msg);
    vx_tool_progress_done();
    double t2 = vx_time_now();
    g_fig[F_CONVERT] = t2 - t1;
    g_fig[F_REGIONS] = (double)n;
    g_fig[F_VOXELS] = (double)st.build.voxels;
    vx_svo_model_coded* coded = (vx_svo_model_coded*)vx_calloc(md.alloc, n ? n : 1, sizeof *coded);
    uint8_t** streams = (uint8_t**)vx_calloc(md.alloc, n ? n : 1, sizeof *streams);
    if (!coded || !streams) die("out of memory for %zu regions", n);
    encode_parts(parts, n, md.threads, md.alloc, chunking, coded, streams);
    double t3 = vx_time_now();
    g_fig[F_ENCODE] = t3 - t2;
    if (!root) {
        uint64_t n64 = n;
        MPI_Send(&n64, 1, MPI_UINT64_T, 0, TAG_COUNT, MPI_COMM_WORLD);
        for (size_t i = 0; i < n; i++) send_part(&parts[i], &coded[i]);
        vx_conv_mesh_parts_free(md.alloc, parts, n);
        vx_gltf_mesh_free(&mesh);
        /* the streams in region order (share's order): rank 0 takes them in
         * model order, so each send meets its receive */
        for (size_t i = 0; i < n; i++) {
            send_bytes(streams[i], (size_t)coded[i].stream_size);
            g_fig[F_SENT] += (double)coded[i].stream_size;
            vx_free(md.alloc, streams[i]);
        }
        vx_free(md.alloc, streams);
        vx_free(md.alloc, coded);
        g_fig[F_GATHER] = vx_time_now() - t3;
        vox2svo_mpi_end(0);
        return false;
    }
    held* hs = (held*)vx_calloc(md.alloc, n ? n : 1, sizeof *hs);
    if (!hs) die("out of memory for %zu regions", n);
    for (size_t i = 0; i < n; i++) hs[i] = (held){parts[i].index, coded[i], 0, streams[i]};
    vx_free(md.alloc, streams);
    vx_free(md.alloc, coded);
    parts = gather(parts, &n, &hs, md.alloc);
    if (n > 1) qsort(hs, n, sizeof *hs, held_cmp); /* the scene's model order (vx_conv_mesh_assemble sorts the parts so) */
    g_held = hs;
    g_nheld = n;
    g_alloc = md.alloc;
    vx_conv_stats cs = {0};
    cs.seconds_read = g_fig[F_READ];
    vx_result r = vx_conv_mesh_assemble(&md, &mesh, parts, n, scene, &cs, &err);
    vx_conv_mesh_parts_free(md.alloc, parts, n);
    vx_gltf_mesh_free(&mesh);
    if (r) die("%s: %s", in, err.msg);
    if (scene->model_count != n) die("%s: %u models assembled from %zu regions", in, scene->model_count, n);
    /* the bounds from the ranks' extents (the models here have no trees) */
    {
        vx_svo_model_coded* info = (vx_svo_model_coded*)vx_calloc(md.alloc, n ? n : 1, sizeof *info);
        if (!info) die("out of memory");
        for (size_t i = 0; i < n; i++) info[i] = hs[i].coded;
        vx_svo_scene_update_bounds_coded(scene, info);
        vx_free(md.alloc, info);
    }
    g_fig[F_GATHER] = vx_time_now() - t3;
    struct stat sb;
    memset(info, 0, sizeof *info);
    info->kind = vx_conv_file_kind(in);
    info->in_bytes = stat(in, &sb) == 0 ? (uint64_t)sb.st_size : 0;
    info->seconds_read = g_fig[F_READ];
    info->seconds_total = vx_time_now() - g_t0;
    info->stats = cs;
    return true;
}

void vox2svo_mpi_end(double seconds_write) {
    g_fig[F_WALL] = vx_time_now() - g_t0;
    g_fig[F_PEAK] = (double)vx_peak_rss();
    int N = g_mpi.nranks;
    double* all = g_mpi.rank == 0 ? (double*)vx_calloc(NULL, (size_t)N * F_COUNT, sizeof *all) : NULL;
    if (g_mpi.rank == 0 && !all) die("out of memory");
    MPI_Gather(g_fig, F_COUNT, MPI_DOUBLE, all, F_COUNT, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    if (g_mpi.rank == 0 && g_verbose) {
        double most = 0, sum = 0, peak = 0, received = 0;
        int most_r = 0, peak_r = 0;
        for (int r = 1; r < N; r++) received += all[(size_t)r * F_COUNT + F_SENT];
        for (int r = 0; r < N; r++) {
            const double* f = all + (size_t)r * F_COUNT;
            printf("rank %d: %.0f regions, %s voxels; read %.2f s, convert %.2f s, encode %.2f s, %s %.2f s (%s bytes), "
                   "wall %.2f s, peak %s\n",
                   r, f[F_REGIONS], vx_tool_num((uint64_t)f[F_VOXELS]), f[F_READ], f[F_CONVERT], f[F_ENCODE],
                   r ? "send (as rank 0 writes)" : "gather+assemble", f[F_GATHER],
                   vx_tool_num((uint64_t)(r ? f[F_SENT] : received)), f[F_WALL], vx_tool_bytes((uint64_t)f[F_PEAK]));
            sum += f[F_CONVERT];
            if (f[F_CONVERT] > most) most = f[F_CONVERT], most_r = r;
            if (f[F_PEAK] > peak) peak = f[F_PEAK], peak_r = r;
        }
        printf("converted on %d ranks: convert most %.2f s (rank %d), mean %.2f s (balance %.0f%%); rank 0 gathered "
               "and assembled in %.2f s, wrote in %.2f s; largest peak %s (rank %d)\n",
               N, most, most_r, sum / N, most > 0 ? 100.0 * sum / N / most : 100.0, all[F_GATHER], seconds_write,
               vx_tool_bytes((uint64_t)peak), peak_r);
    }
    vx_free(NULL, all);
    MPI_Finalize();
}
