/* tools/vox2svo/mpi.c - vox2svo under mpirun (mpi.h).
 *
 * Every rank reads the mesh, bins its triangles and computes the same
 * partition of the regions (vx_conv_mesh_share: no messages before the
 * gather); each voxelizes and builds its own regions' models, then sends
 * them to rank 0, freeing each as it goes. Rank 0 assembles all parts with
 * vx_conv_mesh_assemble, the code one process runs, so the file is the
 * single-process file byte for byte (test_vox2svo_mpi). A region is one
 * model and the file format shares subtrees within a model only, so no
 * subtree has to be looked up across ranks: identical subtrees of a region
 * are shared (the DAG) by the rank that builds it, exactly as one process
 * shares them. The parts travel as raw structs and arrays: the ranks run
 * the same binary on hosts of one byte order. */
#include "tools/vox2svo/mpi.h"

#include <mpi.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "convert/mesh.h"
#include "tools/common/mpi.h"
#include "tools/common/tool.h"

#define die vx_tool_mpi_die

enum { TAG_COUNT = 1, TAG_META, TAG_DATA };
#define CHUNK ((size_t)1 << 30) /* MPI counts are ints: arrays go in pieces of 1 GiB */

static vx_tool_mpi g_mpi;

/* What each rank reports at the end (-v). */
enum { F_REGIONS, F_VOXELS, F_READ, F_CONVERT, F_GATHER, F_WALL, F_PEAK, F_SENT, F_COUNT };
static double g_fig[F_COUNT];
static double g_t0;
static bool g_verbose;

/* The fixed fields of a part; the node words and attribute channels follow. */
typedef struct part_meta {
    uint64_t index, voxel_count;
    uint32_t origin[3], size[3];
    uint32_t depth, root, root_attr, attrs, node_count, attr_count;
    vx_svo_build_stats build;
    double seconds_build;
} part_meta;

/* The model's arrays in a fixed order, with their element sizes. */
typedef struct model_arrays {
    void** ptr[6];
    size_t bytes[6];
} model_arrays;

static model_arrays arrays_of(vx_svo_model* m) {
    model_arrays a;
    size_t na = m->attr_count;
    a.ptr[0] = (void**)&m->nodes, a.bytes[0] = (size_t)m->node_count * 4;
    a.ptr[1] = (void**)&m->palette, a.bytes[1] = (m->attrs & VX_ATTR_PALETTE) ? na : 0;
    a.ptr[2] = (void**)&m->rgba, a.bytes[2] = (m->attrs & VX_ATTR_RGBA8) ? na * 4 : 0;
    a.ptr[3] = (void**)&m->normal, a.bytes[3] = (m->attrs & VX_ATTR_NORMAL) ? na * 4 : 0;
    a.ptr[4] = (void**)&m->material, a.bytes[4] = (m->attrs & VX_ATTR_MATERIAL) ? na * 2 : 0;
    a.ptr[5] = (void**)&m->density, a.bytes[5] = (m->attrs & VX_ATTR_DENSITY) ? na * 4 : 0;
    return a;
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

static void send_part(vx_conv_mesh_part* p) {
    vx_svo_model* m = &p->model;
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
    MPI_Send(&h, (int)sizeof h, MPI_BYTE, 0, TAG_META, MPI_COMM_WORLD);
    model_arrays a = arrays_of(m);
    for (int k = 0; k < 6; k++) {
        send_bytes(*a.ptr[k], a.bytes[k]);
        g_fig[F_SENT] += (double)a.bytes[k];
    }
}

static void recv_part(int src, const vx_allocator* alloc, vx_conv_mesh_part* p) {
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
    model_arrays a = arrays_of(m);
    for (int k = 0; k < 6; k++) {
        if (!a.bytes[k]) continue;
        *a.ptr[k] = vx_alloc(alloc, a.bytes[k]);
        if (!*a.ptr[k]) die("out of memory receiving region %zu from rank %d (%zu bytes)", p->index, src, a.bytes[k]);
        recv_bytes(*a.ptr[k], a.bytes[k], src);
    }
}

/* Rank 0: its own parts, then every other rank's, in the order the ranks
 * finish (each rank's parts arrive in one run after its count). */
static vx_conv_mesh_part* gather(vx_conv_mesh_part* parts, size_t* count, const vx_allocator* alloc) {
    size_t cap = *count;
    for (int k = 1; k < g_mpi.nranks; k++) {
        uint64_t n = 0;
        MPI_Status st;
        MPI_Recv(&n, 1, MPI_UINT64_T, MPI_ANY_SOURCE, TAG_COUNT, MPI_COMM_WORLD, &st);
        if (n > SIZE_MAX / sizeof *parts - *count) die("rank %d sent %llu regions", st.MPI_SOURCE, (unsigned long long)n);
        if (n && !vx_grow(alloc, (void**)&parts, &cap, *count + (size_t)n, sizeof *parts))
            die("out of memory for %zu regions", *count + (size_t)n);
        for (uint64_t i = 0; i < n; i++) recv_part(st.MPI_SOURCE, alloc, &parts[(*count)++]);
    }
    return parts;
}

bool vox2svo_mpi(const char* in, const vx_tool_conv* conv, bool quiet, bool verbose, vx_svo_scene* scene,
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
    if (!root) {
        uint64_t n64 = n;
        MPI_Send(&n64, 1, MPI_UINT64_T, 0, TAG_COUNT, MPI_COMM_WORLD);
        for (size_t i = 0; i < n; i++) {
            send_part(&parts[i]);
            vx_svo_model_free(md.alloc, &parts[i].model); /* sent: nothing of it stays here */
        }
        vx_conv_mesh_parts_free(md.alloc, parts, n);
        vx_gltf_mesh_free(&mesh);
        g_fig[F_GATHER] = vx_time_now() - t2;
        vox2svo_mpi_end(0);
        return false;
    }
    parts = gather(parts, &n, md.alloc);
    vx_conv_stats cs = {0};
    cs.seconds_read = g_fig[F_READ];
    vx_result r = vx_conv_mesh_assemble(&md, &mesh, parts, n, scene, &cs, &err);
    vx_conv_mesh_parts_free(md.alloc, parts, n);
    vx_gltf_mesh_free(&mesh);
    if (r) die("%s: %s", in, err.msg);
    g_fig[F_GATHER] = vx_time_now() - t2;
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
            printf("rank %d: %.0f regions, %s voxels; read %.2f s, convert %.2f s, %s %.2f s (%s bytes), wall %.2f s, "
                   "peak %s\n",
                   r, f[F_REGIONS], vx_tool_num((uint64_t)f[F_VOXELS]), f[F_READ], f[F_CONVERT],
                   r ? "send" : "gather+assemble", f[F_GATHER], vx_tool_num((uint64_t)(r ? f[F_SENT] : received)), f[F_WALL],
                   vx_tool_bytes((uint64_t)f[F_PEAK]));
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
