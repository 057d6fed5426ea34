/* tools/common/mpi.h - what the tools' MPI paths share (svo_bake, svo_render
 * under mpirun): launcher detection before MPI_Init, the rank's place on its
 * host, the device a rank uses, and ending the whole job with one line that
 * names the rank. Built only where MPI is found (VX_HAVE_MPI). */
#ifndef VX_TOOL_MPI_H
#define VX_TOOL_MPI_H

#include <stdbool.h>

/* Whether this process was started by an MPI launcher (mpirun, srun);
 * callable before MPI_Init. */
bool vx_tool_mpi_launched(void);
/* This process's rank from the launcher's environment (0 when unknown), for
 * deciding before MPI_Init which rank prints a usage error. */
int vx_tool_mpi_env_rank(void);

/* Under a launcher, ranks > 0 print nothing while the command line is
 * parsed, so that a usage error (and what rank 0 prints of its options)
 * appears once: vx_tool_mpi_mute(saved) before parsing, and
 * vx_tool_mpi_unmute(saved) after (callable before MPI_Init). */
void vx_tool_mpi_mute(int saved[2]);
void vx_tool_mpi_unmute(int saved[2]);

/* A rank > 0 that stops on a usage error (printed by rank 0 only) calls this
 * before it exits: mpirun ends the whole job as soon as one rank exits
 * nonzero, which under load can kill rank 0 before its message is out; a
 * short wait (2 s) lets rank 0 finish first. */
void vx_tool_mpi_linger(void);

typedef struct vx_tool_mpi {
    int rank, nranks;
    int local_rank, local_size; /* among the ranks of this host */
    int thread_level;           /* what MPI_Init_thread provided */
    char host[256];
} vx_tool_mpi;

/* MPI_Init_thread (serialized) and the ranks' places. Remembers the rank and
 * host for vx_tool_mpi_die. */
void vx_tool_mpi_init(vx_tool_mpi* m);

/* CPU threads for a rank: the host's online CPUs shared by its ranks
 * (1..64), and no more than the CPUs the launcher bound it to. */
unsigned vx_tool_mpi_threads(const vx_tool_mpi* m);

/* This process's rank among the ranks of its host from the launcher's
 * environment (OpenMPI, MPICH/Hydra, Slurm), -1 when unknown: callable before
 * MPI_Init, so that a rank can start opening its GPU while MPI starts. */
int vx_tool_mpi_env_local_rank(void);

/* The device a rank opens: `device` when given, none with cpu, else the GPU
 * `local_rank mod GPUs` of its host ("gpu:K", render.h: counted by the
 * instance that opens it, no second one; the default pick where there is no
 * GPU). In vx_tool_mpi_device (mpi_device.c: Vulkan's tools only). */
const char* vx_tool_mpi_device(int local_rank, const char* device, bool cpu, char buf[16]);

/* Makes this process's Vulkan driver see only the rank's GPU: the NVIDIA GPU
 * node (/dev/nvidiaN) at place `local_rank mod nodes` among the host's, the
 * other nodes refused when the driver opens them (gpu_only.c says why and
 * how). Call before the first Vulkan call; the rank then opens "gpu:0".
 * Returns N, or -1 where nothing is left out (fewer than two NVIDIA GPUs,
 * local_rank < 0). vx_tool_mpi_gpu_all undoes it (before another instance). */
int vx_tool_mpi_gpu_only(int local_rank);
void vx_tool_mpi_gpu_all(void);

/* vx_tool_mpi_device, with the driver narrowed to the rank's GPU where the
 * device is the rank's pick (no `device`, no cpu, local_rank known) and the
 * environment does not say VX_MPI_ALL_GPUS=1: then "gpu:0" and *node the
 * GPU node kept (else -1). Where making that device fails, the caller calls
 * vx_tool_mpi_gpu_all and opens vx_tool_mpi_device's pick instead
 * (vx_tool_gpu_open_start_narrowed does both). */
const char* vx_tool_mpi_device_narrowed(int local_rank, const char* device, bool cpu, char buf[16], int* node);

/* "tool: rank R (host): message; ending the job" on stderr, then MPI_Abort. */
_Noreturn void vx_tool_mpi_die(const char* fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 1, 2)))
#endif
    ;

/* A rank's start-up and end as wall-clock stamps (CLOCK_REALTIME seconds:
 * comparable between the processes of a host and with `date +%s.%N`). With
 * -v every rank prints them as one "timeline" line after MPI_Finalize, so
 * that bench/mpi_scaling.sh can place them against its own launch of mpirun
 * and mpirun's return: the launcher's share (launch to exec, the last rank's
 * end to mpirun's return) is what no clock inside the tool sees. A stamp
 * never taken is 0 and not printed. */
typedef enum vx_tool_tl {
    VX_TL_EXEC,      /* the process started (/proc, 10 ms steps) */
    VX_TL_MAIN,      /* main began (svo_bake: its MPI path, after the options) */
    VX_TL_MPI_INIT,  /* MPI_Init called */
    VX_TL_MPI_READY, /* MPI_Init and the ranks' places done */
    VX_TL_VK_START,  /* the device thread began (vx_tool_gpu_open) */
    VX_TL_VK_DEVICE, /* vx_gpu_create done (instance, device) */
    VX_TL_VK_READY,  /* the scene bound to it too */
    VX_TL_WORK,      /* the rank's work began (after the start-up barrier) */
    VX_TL_DONE,      /* the rank's work ended */
    VX_TL_REDUCED,   /* every rank's results at rank 0 (image gathered, the file's head written) */
    VX_TL_OUTPUT,    /* the output file in place (rank 0) */
    VX_TL_END,       /* MPI_Finalize returned */
    VX_TL_N
} vx_tool_tl;

typedef struct vx_tool_timeline {
    double t[VX_TL_N];
} vx_tool_timeline;

/* CLOCK_REALTIME in seconds. */
double vx_tool_wall_clock(void);
/* Zeroes tl, then stamps VX_TL_EXEC (when the kernel started this process)
 * and VX_TL_MAIN (now). */
void vx_tool_timeline_start(vx_tool_timeline* tl);
static inline void vx_tool_timeline_mark(vx_tool_timeline* tl, vx_tool_tl m) { tl->t[m] = vx_tool_wall_clock(); }
/* "timeline rank R: exec S main S ..." on stdout, one write. */
void vx_tool_timeline_print(const vx_tool_timeline* tl, int rank);

#endif
