/* svo/svo_jobs.c - per-model work spread over threads.
 *
 * Models of a scene are independent (their own node arrays, their own coded
 * streams), so validation, bounds and the NODE coder run one model per job.
 * Threads are only used for large scenes: small ones stay on the caller's
 * thread, which keeps allocation order (and the OOM tests) exact. Results
 * never depend on the thread count. The jobs themselves run on vx_run_jobs
 * (svo/core.h). */
#define _POSIX_C_SOURCE 200809L
#define _DEFAULT_SOURCE /* madvise(MADV_HUGEPAGE) */
#include <stdint.h>
#include <stdatomic.h>
#include <sys/mman.h>

#include "svo/svo_internal.h"

#define MAX_THREADS VX_MAX_THREADS /* every CPU of a 64-CPU host (the read of a 65536^3 scene: docs/PERFORMANCE.md issue 18) */

unsigned vx__svo_cpus(unsigned want) {
    if (want) return want > MAX_THREADS ? MAX_THREADS : want;
    return vx_cpu_count(MAX_THREADS);
}

unsigned vx__svo_threads(const vx_svo_scene* s, unsigned want, const vx_svo_testing* hooks) {
    uint64_t words = 0;
    for (uint32_t i = 0; i < s->model_count; i++) words += s->models[i].node_count;
    if (s->model_count < 2 || words < vx__svo_parallel_words(hooks)) return 1;
    unsigned t = vx__svo_cpus(want);
    return t < s->model_count ? t : s->model_count;
}

void vx__svo_advise_huge(void* p, size_t n) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    const uintptr_t huge = (uintptr_t)2 << 20;
    if (!p || n < 2 * huge) return;
    uintptr_t a = ((uintptr_t)p + huge - 1) & ~(huge - 1), e = ((uintptr_t)p + n) & ~(huge - 1);
    if (e > a) (void)madvise((void*)a, e - a, MADV_HUGEPAGE); /* advice only: a failure changes nothing */
#else
    (void)p, (void)n;
#endif
}

void vx__svo_gate_init(vx__svo_gate* g, size_t step) {
    atomic_init(&g->val, 0);
    atomic_init(&g->want, 0);
    g->closed = false;
    g->step = step;
    g->next = step;
    pthread_mutex_init(&g->lock, NULL);
    pthread_cond_init(&g->cond, NULL);
}

void vx__svo_gate_destroy(vx__svo_gate* g) {
    pthread_cond_destroy(&g->cond);
    pthread_mutex_destroy(&g->lock);
}

void vx__svo_gate_publish(vx__svo_gate* g, size_t v) {
    if (v < g->next) return;
    g->next = v + g->step;
    /* seq_cst store then load, against the waiter's seq_cst store of want
     * then load of val: one of the two sees the other's write, so either
     * the waiter sees v and does not sleep or this sees its want and wakes
     * it (no wake-up is lost) */
    atomic_store(&g->val, v);
    size_t w = atomic_load(&g->want);
    if (w && v >= w && atomic_compare_exchange_strong(&g->want, &w, 0)) {
        pthread_mutex_lock(&g->lock); /* the waiter holds it until it sleeps */
        pthread_cond_signal(&g->cond);
        pthread_mutex_unlock(&g->lock);
    }
}

void vx__svo_gate_close(vx__svo_gate* g, size_t v) {
    pthread_mutex_lock(&g->lock);
    atomic_store(&g->val, v);
    g->closed = true;
    pthread_cond_signal(&g->cond);
    pthread_mutex_unlock(&g->lock);
}

size_t vx__svo_gate_wait(vx__svo_gate* g, size_t have, size_t more) {
    size_t v = atomic_load_explicit(&g->val, memory_order_acquire);
    if (v > have) return v;
    size_t target = have + (more ? more : 1);
    pthread_mutex_lock(&g->lock);
    for (;;) {
        atomic_store(&g->want, target);
        v = atomic_load(&g->val);
        if (v >= target || g->closed) break;
        pthread_cond_wait(&g->cond, &g->lock);
    }
    atomic_store(&g->want, 0);
    v = atomic_load(&g->val);
    pthread_mutex_unlock(&g->lock);
    return v;
}
