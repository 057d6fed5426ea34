/* tools/common/mpi.c - the tools' shared MPI helpers (mpi.h). */
#include "tools/common/mpi.h"

#include <mpi.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "render/render.h"
#include "tools/common/tool.h"

/* set once by vx_tool_mpi_init, read by vx_tool_mpi_die */
static int die_rank;
static char die_host[256];

bool vx_tool_mpi_launched(void) {
    return getenv("OMPI_COMM_WORLD_SIZE") || getenv("PMIX_RANK") || getenv("PMI_RANK") || getenv("PMI_SIZE");
}

int vx_tool_mpi_env_rank(void) {
    const char* v = getenv("OMPI_COMM_WORLD_RANK");
    if (!v) v = getenv("PMIX_RANK");
    if (!v) v = getenv("PMI_RANK");
    return v ? atoi(v) : 0;
}

void vx_tool_mpi_linger(void) { sleep(2); }

void vx_tool_mpi_init(vx_tool_mpi* m) {
    memset(m, 0, sizeof *m);
    MPI_Init_thread(NULL, NULL, MPI_THREAD_SERIALIZED, &m->thread_level);
    MPI_Comm_rank(MPI_COMM_WORLD, &m->rank);
    MPI_Comm_size(MPI_COMM_WORLD, &m->nranks);
    char host[MPI_MAX_PROCESSOR_NAME];
    int len = 0;
    MPI_Get_processor_name(host, &len);
    snprintf(m->host, sizeof m->host, "%s", host);
    MPI_Comm local;
    MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, m->rank, MPI_INFO_NULL, &local);
    MPI_Comm_rank(local, &m->local_rank);
    MPI_Comm_size(local, &m->local_size);
    MPI_Comm_free(&local);
    die_rank = m->rank;
    memcpy(die_host, m->host, sizeof die_host);
}

typedef struct gpu_list {
    unsigned index[64];
    unsigned n;
} gpu_list;

static void list_fn(void* user, uint32_t index, const char* name, const char* type) {
    (void)name;
    gpu_list* l = user;
    if (strcmp(type, "cpu") && strcmp(type, "other") && l->n < 64) l->index[l->n++] = index;
}

const char* vx_tool_mpi_device(const vx_tool_mpi* m, const char* device, bool cpu, char buf[16]) {
    if (device || cpu) return device;
    gpu_list gl = {.n = 0};
    vx_error err = {0};
    if (vx_gpu_list_devices(list_fn, &gl, &err) || !gl.n) return NULL;
    snprintf(buf, 16, "%u", gl.index[(unsigned)m->local_rank % gl.n]);
    return buf;
}

_Noreturn void vx_tool_mpi_die(const char* fmt, ...) {
    va_list ap;
    fprintf(stderr, "%s: rank %d (%s): ", vx_tool_name, die_rank, die_host);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputs("; ending the job\n", stderr);
    fflush(stderr);
    MPI_Abort(MPI_COMM_WORLD, 1);
    exit(1); /* not reached */
}
