/* tests/fail_alloc.h - a test allocator (svo/core.h vx_allocator callbacks)
 * that fails allocation number `fail_at` (1-based), and every later one when
 * persistent, and counts live blocks so that a leak shows without ASan too.
 * Shared by the reader tests and the allocation-failure loops. */
#ifndef VX_TESTS_FAIL_ALLOC_H
#define VX_TESTS_FAIL_ALLOC_H
#include <stdbool.h>
#include <stdlib.h>

typedef struct tfail {
    long n, fail_at, live;
    bool persistent, failed;
} tfail;

static void* tfail_alloc(void* user, size_t size) {
    tfail* f = (tfail*)user;
    f->n++;
    if (f->fail_at && (f->n == f->fail_at || (f->persistent && f->n > f->fail_at))) {
        f->failed = true;
        return NULL;
    }
    void* p = malloc(size);
    if (p) f->live++;
    return p;
}
static void tfail_free(void* user, void* p) {
    tfail* f = (tfail*)user;
    if (p) f->live--;
    free(p);
}
#endif
