/* formats/vdb_scan.c - the length fields of a .vdb file checked before
 * OpenVDB reads it (vdb_scan.h).
 *
 * OpenVDB's stream reader allocates what a length field says, zero-filled,
 * before it finds the bytes missing: a 40 KB file whose grid name claims
 * 1.7 GB costs 30 s and 1.7 GB (docs/RELIABILITY.md). The layout walked here
 * (format 222..224, OpenVDB 3 and later; io/Archive and io/GridDescriptor):
 *   header: i64 magic 0x56444220, u32 format version, u32 library major and
 *           minor, u8 has_grid_offsets, 36 ASCII characters of UUID;
 *   file metadata: u32 count, then per entry: string name, string type,
 *           u32 value size, value (a string is a u32 length and the bytes);
 *   u32 grid count, then per grid: descriptor (string name, string type,
 *           string instance parent, i64 grid, block and end positions), and
 *           at the grid position: u32 compression, grid metadata (as the file
 *           metadata), string transform type, then the tree.
 * Every length must fit the bytes left and every count the smallest record
 * times itself. The tree cannot be skipped without decoding it, so the grids
 * after the first are reached only through their end positions (files
 * written with grid offsets, as openvdb::io::File writes them); a stream
 * without offsets has the first grid's records checked. */
#include "formats/vdb_scan.h"

#include <stdio.h>
#include <string.h>

typedef struct cur {
    const uint8_t* d;
    size_t n, at;
} cur;

static bool need(cur* c, size_t k) { return k <= c->n - c->at; }

static bool rd_u32(cur* c, uint32_t* v) {
    if (!need(c, 4)) return false;
    const uint8_t* p = c->d + c->at;
    *v = (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
    c->at += 4;
    return true;
}

static bool rd_i64(cur* c, int64_t* v) {
    uint32_t lo, hi;
    if (!rd_u32(c, &lo) || !rd_u32(c, &hi)) return false;
    *v = (int64_t)(((uint64_t)hi << 32) | lo);
    return true;
}

static vx_result ended(cur* c, const char* what, vx_error* err) {
    return vx_fail(err, VX_ERR_TRUNCATED, c->at, "vdb: the file ends inside %s", what);
}

/* A u32 length and that many bytes. */
static vx_result skip_sized(cur* c, const char* what, vx_error* err) {
    uint64_t at = c->at;
    uint32_t len;
    if (!rd_u32(c, &len)) return ended(c, what, err);
    if (!need(c, len))
        return vx_fail(err, VX_ERR_LIMIT, at, "vdb: %s of %u bytes is longer than the %zu bytes left in the file", what,
                       len, c->n - c->at);
    c->at += len;
    return VX_OK;
}

static vx_result scan_meta(cur* c, const char* whose, vx_error* err) {
    uint64_t at = c->at;
    uint32_t count;
    char what[64];
    snprintf(what, sizeof what, "the %s metadata count", whose);
    if (!rd_u32(c, &count)) return ended(c, what, err);
    /* an entry is at least three empty lengths */
    if (count > (c->n - c->at) / 12)
        return vx_fail(err, VX_ERR_LIMIT, at, "vdb: %u %s metadata entries cannot fit in the %zu bytes left", count,
                       whose, c->n - c->at);
    for (uint32_t i = 0; i < count; i++) {
        vx_result r;
        snprintf(what, sizeof what, "the name of %s metadata entry %u", whose, i);
        if ((r = skip_sized(c, what, err))) return r;
        snprintf(what, sizeof what, "the type of %s metadata entry %u", whose, i);
        if ((r = skip_sized(c, what, err))) return r;
        snprintf(what, sizeof what, "the value of %s metadata entry %u", whose, i);
        if ((r = skip_sized(c, what, err))) return r;
    }
    return VX_OK;
}

/* The records of grid g at the cursor: compression, metadata, transform type. */
static vx_result scan_grid(cur* c, uint32_t g, vx_error* err) {
    char what[64];
    uint32_t compression;
    snprintf(what, sizeof what, "grid %u's compression flags", g);
    if (!rd_u32(c, &compression)) return ended(c, what, err);
    snprintf(what, sizeof what, "grid %u's", g);
    vx_result r = scan_meta(c, what, err);
    if (r) return r;
    snprintf(what, sizeof what, "grid %u's transform type", g);
    return skip_sized(c, what, err);
}

vx_result vx__vdb_scan(const void* data, size_t size, vx_error* err) {
    cur c = {data, size, 0};
    int64_t magic;
    uint32_t version, major, minor;
    if (!rd_i64(&c, &magic) || magic != 0x56444220) return vx_fail(err, VX_ERR_BAD_FORMAT, 0, "vdb: not an OpenVDB file (magic)");
    if (!rd_u32(&c, &version) || !rd_u32(&c, &major) || !rd_u32(&c, &minor)) return ended(&c, "the header", err);
    if (version < 222 || version > 224)
        return vx_fail(err, VX_ERR_UNSUPPORTED, 8,
                       "vdb: file format %u (this reader takes 222..224: OpenVDB 3.0 and later)", version);
    if (!need(&c, 37)) return ended(&c, "the header", err);
    bool offsets = c.d[c.at] != 0;
    c.at += 37; /* the flag and the UUID */
    vx_result r = scan_meta(&c, "file", err);
    if (r) return r;
    uint64_t at = c.at;
    uint32_t grids;
    if (!rd_u32(&c, &grids)) return ended(&c, "the grid count", err);
    /* a descriptor is at least three empty names and three positions */
    if (grids > (c.n - c.at) / 36)
        return vx_fail(err, VX_ERR_LIMIT, at, "vdb: %u grids cannot fit in the %zu bytes left", grids, c.n - c.at);
    for (uint32_t g = 0; g < grids; g++) {
        char what[64];
        static const char* const fields[3] = {"name", "type", "instance parent"};
        for (int k = 0; k < 3; k++) {
            snprintf(what, sizeof what, "grid %u's %s", g, fields[k]);
            if ((r = skip_sized(&c, what, err))) return r;
        }
        int64_t pos[3];
        for (int k = 0; k < 3; k++)
            if (!rd_i64(&c, &pos[k])) return ended(&c, "a grid descriptor", err);
        if (!offsets) { /* a stream: the grid follows, its tree cannot be skipped */
            return g == 0 ? scan_grid(&c, g, err) : VX_OK;
        }
        if (pos[0] < 0 || pos[1] < pos[0] || pos[2] < pos[1] || (uint64_t)pos[2] > size)
            return vx_fail(err, VX_ERR_BAD_FORMAT, c.at - 24,
                           "vdb: grid %u's positions %lld, %lld, %lld are not in order inside the %zu-byte file", g,
                           (long long)pos[0], (long long)pos[1], (long long)pos[2], size);
        cur gc = {data, (size_t)pos[1], (size_t)pos[0]}; /* the records lie before the tree's block */
        if ((r = scan_grid(&gc, g, err))) return r;
        c.at = (size_t)pos[2];
    }
    return VX_OK;
}
