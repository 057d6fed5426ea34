/* bench/startup/mpit.c - one rank's MPI start and end (issue 23): the
 * process's start against the launch stamp VX_T0 (`date +%s.%N` before
 * mpirun, passed with -x VX_T0), MPI_Init_thread, the communicator split the
 * tools make, MPI_Finalize. Built by hand: mpicc -O2 -o mpit bench/startup/mpit.c */
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
static double now(void) { struct timespec t; clock_gettime(CLOCK_REALTIME, &t); return t.tv_sec + t.tv_nsec * 1e-9; }
int main(int argc, char** argv) {
    double t0 = now();
    const char* l = getenv("VX_T0");
    double launch = l ? atof(l) : t0;
    int prov, rank, n;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_SERIALIZED, &prov);
    double t1 = now();
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &n);
    MPI_Comm local;
    MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank, MPI_INFO_NULL, &local);
    MPI_Comm_free(&local);
    MPI_Barrier(MPI_COMM_WORLD);
    double t2 = now();
    MPI_Finalize();
    double t3 = now();
    printf("mpit rank %d/%d: exec %.3f MPI_Init %.3f split+barrier %.3f finalize %.3f end %.3f\n", rank, n, t0 - launch, t1 - t0, t2 - t1, t3 - t2, t3 - launch);
    return 0;
}
