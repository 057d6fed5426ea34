/* formats/vdb_scan.h - checks a .vdb file's length fields against its size
 * before the OpenVDB shim hands it to OpenVDB (private to formats/vdb). */
#ifndef VX_VDB_SCAN_H
#define VX_VDB_SCAN_H

#include <stddef.h>

#include "svo/core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* VX_OK when the header, the metadata and the grid descriptors (and each
 * reachable grid's metadata and transform name) fit the file; else the
 * first field that does not, with its offset (VX_ERR_LIMIT for a length
 * past the end, VX_ERR_TRUNCATED, VX_ERR_BAD_FORMAT, VX_ERR_UNSUPPORTED for
 * a format version outside 222..224). */
vx_result vx__vdb_scan(const void* data, size_t size, vx_error* err);

#ifdef __cplusplus
}
#endif
#endif
