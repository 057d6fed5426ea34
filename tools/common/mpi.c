/* tools/common/mpi.c - the tools' shared MPI helpers (mpi.h). */
#define _GNU_SOURCE /* sched_getaffinity: the CPUs mpirun bound this rank to */
#include "tools/common/mpi.h"

#include <sched.h>
#include <fcntl.h>
#include <mpi.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

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

int vx_tool_mpi_env_local_rank(void) {
    const char* names[] = {"OMPI_COMM_WORLD_LOCAL_RANK", "MPI_LOCALRANKID", "PMI_LOCAL_RANK", "SLURM_LOCALID"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        const char* v = getenv(names[i]);
        char* end;
        long r = v && *v ? strtol(v, &end, 10) : -1;
        if (v && *v && !*end && r >= 0 && r < 1 << 20) return (int)r;
    }
    return -1;
}

void vx_tool_mpi_linger(void) { sleep(2); }

void vx_tool_mpi_mute(int saved[2]) {
    saved[0] = saved[1] = -1;
    if (!vx_tool_mpi_launched() || vx_tool_mpi_env_rank() == 0) return;
    int null = open("/dev/null", O_WRONLY);
    if (null < 0) return;
    fflush(stdout);
    saved[0] = dup(1), saved[1] = dup(2);
    dup2(null, 1), dup2(null, 2);
    close(null);
}

void vx_tool_mpi_unmute(int saved[2]) {
    if (saved[0] < 0) return;
    fflush(stdout);
    dup2(saved[0], 1), dup2(saved[1], 2);
    close(saved[0]), close(saved[1]);
    saved[0] = saved[1] = -1;
}

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

unsigned vx_tool_mpi_threads(const vx_tool_mpi* m) {
    long cpus = sysconf(_SC_NPROCESSORS_ONLN);
    long t = cpus > 0 && m->local_size > 0 ? cpus / m->local_size : 1;
    cpu_set_t set;
    if (sched_getaffinity(0, sizeof set, &set) == 0 && CPU_COUNT(&set) < t) t = CPU_COUNT(&set);
    return t < 1 ? 1u : t > 64 ? 64u : (unsigned)t;
}

_Noreturn void vx_tool_mpi_die(const char* fmt, ...) {
    /* one write of the whole line: stderr is unbuffered, and the pieces of
     * several fprintf calls could be split by another rank's line or by
     * mpirun's MPI_Abort banner (seen in the ASan suite) */
    char line[1024];
    int n = snprintf(line, sizeof line, "%s: rank %d (%s): ", vx_tool_name, die_rank, die_host);
    if (n < 0 || n >= (int)sizeof line) n = 0;
    va_list ap;
    va_start(ap, fmt);
    int m = vsnprintf(line + n, sizeof line - (size_t)n, fmt, ap);
    va_end(ap);
    n = m < 0 ? n : (n + m >= (int)sizeof line - 17 ? (int)sizeof line - 17 : n + m);
    memcpy(line + n, "; ending the job\n", 17);
    fflush(stdout);
    if (write(2, line, (size_t)n + 17) < 0) { /* nothing left to tell */
    }
    MPI_Abort(MPI_COMM_WORLD, 1);
    exit(1); /* not reached */
}

double vx_tool_wall_clock(void) {
    struct timespec t;
    clock_gettime(CLOCK_REALTIME, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

/* The process's start on the wall clock: /proc/self/stat's starttime (clock
 * ticks after boot, field 22) against CLOCK_BOOTTIME now; 0 where unknown. */
static double exec_stamp(void) {
    char buf[1024];
    FILE* f = fopen("/proc/self/stat", "r");
    if (!f) return 0;
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[n] = 0;
    const char* p = strrchr(buf, ')'); /* the command's name may hold spaces */
    if (!p) return 0;
    unsigned long long start = 0;
    /* after ')': state (3), then fields 4..21, then starttime (22) */
    if (sscanf(p + 2, "%*c %*d %*d %*d %*d %*d %*u %*u %*u %*u %*u %*u %*u %*d %*d %*d %*d %*d %*d %llu", &start) != 1)
        return 0;
    long hz = sysconf(_SC_CLK_TCK);
    struct timespec b;
    if (hz <= 0 || clock_gettime(CLOCK_BOOTTIME, &b) != 0) return 0;
    double age = (double)b.tv_sec + (double)b.tv_nsec * 1e-9 - (double)start / (double)hz;
    return age >= 0 ? vx_tool_wall_clock() - age : 0;
}

void vx_tool_timeline_start(vx_tool_timeline* tl) {
    memset(tl, 0, sizeof *tl);
    tl->t[VX_TL_MAIN] = vx_tool_wall_clock();
    tl->t[VX_TL_EXEC] = exec_stamp();
}

void vx_tool_timeline_print(const vx_tool_timeline* tl, int rank) {
    static const char* const names[VX_TL_N] = {"exec",   "main", "mpi_init", "mpi_ready", "vk_start", "vk_device",
                                               "vk_ready", "work", "done",     "reduced",   "output",   "end"};
    char line[1024];
    int n = snprintf(line, sizeof line, "timeline rank %d:", rank);
    for (int i = 0; i < VX_TL_N && n > 0 && n < (int)sizeof line; i++)
        if (tl->t[i] > 0) n += snprintf(line + n, sizeof line - (size_t)n, " %s %.4f", names[i], tl->t[i]);
    if (n <= 0 || n >= (int)sizeof line - 1) return;
    line[n++] = '\n';
    fflush(stdout);
    if (write(1, line, (size_t)n) < 0) { /* stdout gone: nothing to tell */
    }
}
