/* tests/fuzz/vdb_fuzz.c - .vdb bytes -> OpenVDB shim -> svo scene -> validate.
 * One of the cell rules runs (fog/surface by grid class, or solid); a cell cap
 * keeps a mutated tile table from turning one input into much work (2^16:
 * the seeds, tests/fuzz/make_vdb_seeds.cpp, have a few hundred cells; a
 * mutated tile of 2^15 cells still converts).
 *
 * OpenVDB leaks the node it was reading when a garbled file makes the read
 * throw (tests/convert/vdb_new_guard.cpp): after a failed conversion the
 * blocks OpenVDB allocated with operator new during the call and never freed
 * are reclaimed, so a campaign's memory stays flat and LeakSanitizer, which
 * libFuzzer runs when an input ends with more mallocs than frees, is left to
 * find leaks of ours. After a successful one nothing may be left (what
 * OpenVDB allocates once on first use is kept). The regression inputs
 * tests/fuzz/regress/vdb/reclaim-*.vdb are the two files whose runs freed
 * blocks still in use (OpenVDB's type registry; TBB's scheduler, now left
 * alone as vdb_new_guard.cpp lists only blocks asked for by this program's
 * and libopenvdb's code). */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "convert/volume.h"
#include "tests/convert/vdb_new_guard.h"

/* Reclaiming starts after the first conversion that succeeds: OpenVDB
 * registers its types (openvdb::initialize) in the shim's first read that
 * passes the length scan, and those blocks live for good. Reclaimed after a
 * failed first read, they were used after being freed (the first campaign's
 * job that began with a bad input). */
static bool g_warm;

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    /* One conversion per input (OpenVDB's read is most of the time), the
     * cell rule by the size's parity: inserting or erasing a byte switches
     * it, so every file reaches both rules. */
    const int solid = (int)(size & 1);
    {
        vx_conv_vdb_desc d = {0};
        d.solid = solid != 0;
        d.density = true;
        d.color_grid = solid ? "Cd" : NULL; /* absent in most inputs: exercises the error path */
        d.max_cells = 1u << 16;
        vx_svo_scene s;
        vx_error err;
        vx_test_new_track(true);
        vx_result r = vx_conv_vdb_memory(&d, data, size, &s, NULL, &err);
        vx_test_new_track(false);
        if (r == VX_OK) {
            vx_test_new_forget();
            g_warm = true;
            (void)vx_svo_validate_scene(&s, NULL);
            vx_svo_scene_free(&s);
        } else if (g_warm) {
            vx_test_new_reclaim();
        } else {
            vx_test_new_forget();
        }
    }
    return 0;
}
