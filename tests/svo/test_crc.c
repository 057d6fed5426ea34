/* tests/svo/test_crc.c - vx_crc32 (svo/core.h) against a bit-at-a-time
 * CRC-32 written here from the definition (an independent path): the check
 * value of "123456789", every length 0..64 and every split point of a
 * buffer (the slicing-by-8 loop, its tail, and continuation), and the first
 * call made from several threads at once (the table built once under
 * pthread_once, svo/core.c): each thread's results are the reference's. */
#define _POSIX_C_SOURCE 200809L
#include <pthread.h>
#include <stdatomic.h>

#include "svo/core.h"
#include "tests/test.h"

/* CRC-32/ISO-HDLC bit by bit: reflected polynomial 0xEDB88320, init and
 * final xor 0xFFFFFFFF; crc = 0 starts, a result fed back continues. */
static uint32_t ref_crc(uint32_t crc, const uint8_t* p, size_t n) {
    uint32_t c = ~crc;
    for (size_t i = 0; i < n; i++) {
        c ^= p[i];
        for (int k = 0; k < 8; k++) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
    }
    return ~c;
}

enum { NBUF = 4096, NTHREADS = 8 };
static uint8_t buf[NBUF];
static _Atomic int go, bad;

static void* first_calls(void* arg) {
    (void)arg;
    while (!atomic_load(&go)) {
    }
    /* lengths that take the table's every row (slices of 8) and its first (the tail) */
    for (size_t n = 0; n < 300; n += 7)
        if (vx_crc32(0, buf, n) != ref_crc(0, buf, n)) atomic_fetch_add(&bad, 1);
    return NULL;
}

/* first: before any other call in this process, so that the threads race
 * to build the table */
static void test_first_call_threads(void) {
    pthread_t th[NTHREADS];
    int started = 0;
    for (int i = 0; i < NTHREADS; i++) started += pthread_create(&th[i], NULL, first_calls, NULL) == 0;
    atomic_store(&go, 1);
    for (int i = 0; i < NTHREADS; i++) pthread_join(th[i], NULL);
    REQUIRE(started == NTHREADS);
    CHECKF(atomic_load(&bad) == 0, "%d checksums differ from the bitwise CRC", atomic_load(&bad));
}

static void test_check_value(void) {
    CHECK(vx_crc32(0, "123456789", 9) == 0xCBF43926u);
    CHECK(vx_crc32(0, NULL, 0) == 0);
}

static void test_lengths_and_splits(void) {
    for (size_t n = 0; n <= 64; n++) CHECKF(vx_crc32(0, buf + 3, n) == ref_crc(0, buf + 3, n), "length %zu", n);
    const uint32_t whole = ref_crc(0, buf, NBUF);
    CHECK(vx_crc32(0, buf, NBUF) == whole);
    for (size_t cut = 0; cut <= NBUF; cut += 37) {
        uint32_t c = vx_crc32(vx_crc32(0, buf, cut), buf + cut, NBUF - cut);
        CHECKF(c == whole, "split at %zu: %08x against %08x", cut, c, whole);
    }
}

int main(void) {
    uint32_t s = 12345;
    for (size_t i = 0; i < NBUF; i++) {
        s = s * 1103515245u + 12345u;
        buf[i] = (uint8_t)(s >> 16);
    }
    RUN(test_first_call_threads);
    RUN(test_check_value);
    RUN(test_lengths_and_splits);
    return vx_test_finish();
}
