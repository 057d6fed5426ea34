/* tests/convert/vdb_new_guard.h - what vdb_new_guard.cpp adds for the fuzz
 * target: reclaiming OpenVDB's leaked nodes after each input. */
#ifndef VX_VDB_NEW_GUARD_H
#define VX_VDB_NEW_GUARD_H
#include <stdbool.h>
#include <stddef.h>
#ifdef __cplusplus
extern "C" {
#endif
/* While on, every block that code of the executable or of libopenvdb gets
 * from operator new is listed until it is deleted. */
void vx_test_new_track(bool on);
/* Frees the listed blocks (operator new blocks made while tracking that were
 * never deleted) and returns their count. Only between calls into OpenVDB:
 * nothing may point to them any more. */
size_t vx_test_new_reclaim(void);
/* Unlists them without freeing (blocks that stay in use, such as what
 * OpenVDB allocates once on first use); returns their count. */
size_t vx_test_new_forget(void);
#ifdef __cplusplus
}
#endif
#endif
