/* tests/svo/test_jobs.c - vx_run_jobs (svo/core.h): every job runs exactly
 * once, on a thread index below the threads asked for, index 0 on the
 * caller's own thread, and the jobs really run side by side (checked by a
 * rendezvous only concurrent jobs can pass). */
#define _POSIX_C_SOURCE 200809L
#include <pthread.h>
#include <stdatomic.h>
#include <time.h>

#include "svo/core.h"
#include "tests/test.h"

enum { MAXJ = 5000 };

typedef struct count_ctx {
    _Atomic uint32_t runs[MAXJ];
    _Atomic uint32_t bad_thread, caller_mismatch;
    _Atomic uint32_t used[VX_MAX_THREADS];
    unsigned threads;
    pthread_t caller;
} count_ctx;

static void count_job(void* ctx, unsigned thread, uint32_t i) {
    count_ctx* c = (count_ctx*)ctx;
    atomic_fetch_add(&c->runs[i], 1);
    if (thread >= c->threads || thread >= VX_MAX_THREADS) {
        atomic_fetch_add(&c->bad_thread, 1);
        return;
    }
    atomic_fetch_add(&c->used[thread], 1);
    /* thread 0 is the caller's thread, and only it */
    if ((thread == 0) != (pthread_equal(pthread_self(), c->caller) != 0)) atomic_fetch_add(&c->caller_mismatch, 1);
}

static void test_jobs_each_once(void) {
    static count_ctx c; /* large: not on the stack */
    const unsigned threads[] = {0, 1, 2, 3, 8, 64, 200};
    const uint32_t counts[] = {0, 1, 2, 7, 100, MAXJ};
    for (size_t a = 0; a < sizeof threads / sizeof *threads; a++)
        for (size_t b = 0; b < sizeof counts / sizeof *counts; b++) {
            memset(&c, 0, sizeof c);
            unsigned want = threads[a] ? threads[a] : 1;
            c.threads = want > VX_MAX_THREADS ? VX_MAX_THREADS : want;
            c.caller = pthread_self();
            vx_run_jobs(threads[a], counts[b], count_job, &c);
            uint32_t wrong = 0, total = 0;
            for (uint32_t i = 0; i < MAXJ; i++) {
                uint32_t r = atomic_load(&c.runs[i]);
                if (r != (i < counts[b] ? 1u : 0u)) wrong++;
                total += r;
            }
            CHECKF(wrong == 0 && total == counts[b], "threads %u, %u jobs: %u jobs ran a wrong number of times", threads[a],
                   counts[b], wrong);
            CHECK(atomic_load(&c.bad_thread) == 0);
            CHECK(atomic_load(&c.caller_mismatch) == 0);
            /* one thread: everything on the caller's */
            if (want == 1) CHECK(atomic_load(&c.used[0]) == counts[b]);
        }
}

/* Jobs that can only finish when `need` of them run at the same time: with
 * 4 threads and 4 jobs each waits (bounded) for the others to arrive. A
 * runner that ran them one after the other would time out every wait. */
typedef struct meet_ctx {
    _Atomic int arrived;
    _Atomic int met;
    int need;
} meet_ctx;

static void meet_job(void* ctx, unsigned thread, uint32_t i) {
    (void)thread;
    (void)i;
    meet_ctx* m = (meet_ctx*)ctx;
    atomic_fetch_add(&m->arrived, 1);
    for (int k = 0; k < 20000 && atomic_load(&m->arrived) < m->need; k++) {
        struct timespec ts = {0, 100000}; /* 0.1 ms, 2 s at most */
        nanosleep(&ts, NULL);
    }
    if (atomic_load(&m->arrived) >= m->need) atomic_fetch_add(&m->met, 1);
}

static void test_jobs_concurrent(void) {
    meet_ctx m = {0, 0, 4};
    vx_run_jobs(4, 4, meet_job, &m);
    CHECKF(atomic_load(&m.met) == 4, "%d of 4 jobs met the others", atomic_load(&m.met));
    /* and one thread cannot meet anyone: the wait runs out */
    meet_ctx one = {0, 0, 2};
    vx_run_jobs(1, 1, meet_job, &one);
    CHECK(atomic_load(&one.met) == 0);
}

int main(void) {
    RUN(test_jobs_each_once);
    RUN(test_jobs_concurrent);
    return vx_test_finish();
}
