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

/* "tool: rank R (host): message; ending the job" on stderr, then MPI_Abort. */
_Noreturn void vx_tool_mpi_die(const char* fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 1, 2)))
#endif
    ;

#endif
