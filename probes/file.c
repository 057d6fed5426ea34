/* probes/file.c - the .probes file (docs/FORMAT.md, "## .probes"): a
 * header, a GRID section and an optional DATA section, each with a CRC-32. */
#define _GNU_SOURCE /* sync_file_range */
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>
#ifdef VX_HAVE_LIBDEFLATE
#include <libdeflate.h>
#endif

#include "probes/probes_internal.h"

static const char magic[8] = {'V', 'X', 'P', 'R', 'O', 'B', 'E', 'S'};
#define GRID_FIXED 192u
#define PROBE_REC 28u

/* svo/core.h's CRC-32 (the same values), by libdeflate where it is linked: several GB/s */
static uint32_t file_crc32(uint32_t crc, const void* data, size_t n) {
#ifdef VX_HAVE_LIBDEFLATE
    return libdeflate_crc32(crc, data, n);
#else
    return vx_crc32(crc, data, n);
#endif
}

static size_t block_bytes(uint32_t res, uint32_t low_res) {
    /* res <= VX_PROBE_MAX_RES, so no overflow */
    return vx__bsq(res) * (6 + 4 + 2) + vx__bsq(low_res) * 2 + vx__bsq(VX_PROBE_IRR_RES) * 6 +
           vx__bsq(VX_PROBE_DIST_RES) * 8;
}

/* Arrays of little-endian values: one copy on a little-endian host (a bake's
 * maps are hundreds of MB; per-value appends took 0.8 s for 512 probes at R=128). */
static bool host_le(void) {
    const uint16_t one = 1;
    return *(const uint8_t*)&one == 1;
}
static void put_u16s(vx_buf* b, const uint16_t* v, size_t n) {
    if (host_le()) {
        vx_buf_append(b, v, n * 2);
        return;
    }
    for (size_t i = 0; i < n; i++) vx_buf_u16le(b, v[i]);
}
static void put_u32s(vx_buf* b, const uint32_t* v, size_t n) {
    if (host_le()) {
        vx_buf_append(b, v, n * 4);
        return;
    }
    for (size_t i = 0; i < n; i++) vx_buf_u32le(b, v[i]);
}
static void put_f32s(vx_buf* b, const float* v, size_t n) {
    if (host_le()) {
        vx_buf_append(b, v, n * 4);
        return;
    }
    for (size_t i = 0; i < n; i++) vx_buf_f32le(b, v[i]);
}

static void put_vec(vx_buf* b, const double v[3]) {
    for (int k = 0; k < 3; k++) vx_buf_f64le(b, v[k]);
}

/* Probe p's block (p counted from ps->first): its six maps in the file's order. */
static void put_block(vx_buf* b, const vx_probe_set* ps, size_t p) {
    size_t nr = vx__bsq(ps->res), nl = vx__bsq(ps->low_res), ni = vx__bsq(VX_PROBE_IRR_RES),
           nm = vx__bsq(VX_PROBE_DIST_RES);
    put_u16s(b, ps->radiance + p * nr * 3, nr * 3);
    put_u32s(b, ps->normal + p * nr, nr);
    put_u16s(b, ps->distance + p * nr, nr);
    put_u16s(b, ps->low + p * nl, nl);
    put_u16s(b, ps->irradiance + p * ni * 3, ni * 3);
    put_f32s(b, ps->moments + p * nm * 2, nm * 2);
}

static void section_begin(vx_buf* b, const char tag[4], size_t* at) {
    vx_buf_append(b, tag, 4);
    vx_buf_u32le(b, 0);
    vx_buf_u64le(b, 0);
    *at = b->size;
}

static void section_end(vx_buf* b, size_t at) {
    if (b->failed) return;
    size_t n = b->size - at;
    vx_buf_put_u32le(b->data + at - 12, file_crc32(0, b->data + at, n));
    vx_buf_put_u32le(b->data + at - 8, (uint32_t)n);
    vx_buf_put_u32le(b->data + at - 4, (uint32_t)((uint64_t)n >> 32));
}

vx_result vx_probe_write(const vx_probe_set* ps, const vx_allocator* alloc, uint8_t** out, size_t* out_size,
                         vx_error* err) {
    if (!ps || !out || !out_size) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    if (ps->res < 16 || ps->res > VX_PROBE_MAX_RES || ps->res % 16 || ps->low_res != ps->res / 16 ||
        (uint64_t)ps->first + ps->count > ps->probe_count || !ps->probes)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "inconsistent probe set");
    vx_buf b = {.alloc = alloc};
    vx_buf_append(&b, magic, 8);
    vx_buf_u32le(&b, VX_PROBE_FORMAT_VERSION);
    vx_buf_u32le(&b, ps->count ? 2 : 1);
    size_t at;
    section_begin(&b, "GRID", &at);
    vx_buf_u32le(&b, ps->res);
    vx_buf_u32le(&b, ps->low_res);
    vx_buf_u32le(&b, VX_PROBE_IRR_RES);
    vx_buf_u32le(&b, VX_PROBE_DIST_RES);
    for (int k = 0; k < 3; k++) vx_buf_u32le(&b, ps->grid[k]);
    vx_buf_u32le(&b, ps->probe_count);
    put_vec(&b, ps->origin);
    put_vec(&b, ps->spacing);
    vx_buf_f64le(&b, ps->dist_step);
    vx_buf_f64le(&b, ps->dist_max);
    vx_buf_f64le(&b, ps->dist_max_error);
    vx_buf_u32le(&b, ps->spp);
    vx_buf_u32le(&b, ps->bounces);
    vx_buf_u64le(&b, ps->seed);
    put_vec(&b, ps->light_dir);
    put_vec(&b, ps->sun);
    put_vec(&b, ps->sky);
    for (uint32_t i = 0; i < ps->probe_count; i++) {
        put_vec(&b, ps->probes[i].pos);
        vx_buf_u32le(&b, ps->probes[i].state);
    }
    section_end(&b, at);
    if (ps->count) {
        section_begin(&b, "DATA", &at);
        vx_buf_u32le(&b, ps->first);
        vx_buf_u32le(&b, ps->count);
        for (size_t p = 0; p < ps->count && !b.failed; p++) put_block(&b, ps, p);
        section_end(&b, at);
    }
    if (b.failed) {
        vx_buf_free(&b);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory writing %u probes", ps->count);
    }
    *out = b.data;
    *out_size = b.size;
    return VX_OK;
}

vx_result vx_probe_write_file(const vx_write_desc* desc, const vx_probe_set* ps, const char* path, vx_error* err) {
    const vx_allocator* a = desc ? desc->alloc : NULL;
    uint8_t* data = NULL;
    size_t size = 0;
    vx_result r = vx_probe_write(ps, a, &data, &size, err);
    if (r) return r;
    r = vx_file_write_atomic(path, a, data, size, err);
    vx_free(a, data);
    return r;
}

/* ---- writing while a bake runs --------------------------------------------------------- */

/* What a vx_atomic_file (svo/core.h: a FILE*) needs besides appending: the
 * disk writes of what was appended started at once (so that the commit's
 * fsync finds little left), and a few bytes patched at an offset. */
static void stream_flush(vx_atomic_file* af) {
    FILE* f = (FILE*)af->f;
    if (af->failed_errno) return;
    if (fflush(f) != 0) {
        af->failed_errno = errno ? errno : EIO;
        return;
    }
#ifdef SYNC_FILE_RANGE_WRITE
    (void)sync_file_range(fileno(f), 0, 0, SYNC_FILE_RANGE_WRITE); /* a hint: errors are the commit's */
#endif
}

static void stream_patch(vx_atomic_file* af, uint64_t at, const void* data, size_t n) {
    FILE* f = (FILE*)af->f;
    if (af->failed_errno) return;
    if (fflush(f) != 0 || pwrite(fileno(f), data, n, (off_t)at) != (ssize_t)n) af->failed_errno = errno ? errno : EIO;
}

vx_result vx_probe_stream_open(vx_probe_stream* st, const vx_probe_set* ps, uint32_t end, const char* path,
                               const vx_allocator* alloc, vx_error* err) {
    memset(st, 0, sizeof *st);
    if (!ps || !path) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    if (end > ps->probe_count || end <= ps->first)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "stream end %u outside %u..%u", end, ps->first + 1,
                       ps->probe_count);
    /* the header and GRID of the set without maps, then DATA's head with its CRC to come */
    vx_probe_set g = *ps;
    g.count = 0;
    uint8_t* head = NULL;
    size_t hn = 0;
    vx_result r = vx_probe_write(&g, alloc, &head, &hn, err);
    if (r) return r;
    head[12] = 2; /* sections: GRID and DATA */
    uint32_t count = end - ps->first;
    uint8_t d[24];
    memcpy(d, "DATA", 4);
    vx_buf_put_u32le(d + 4, 0);
    uint64_t size = 8 + (uint64_t)count * block_bytes(ps->res, ps->low_res);
    vx_buf_put_u32le(d + 8, (uint32_t)size);
    vx_buf_put_u32le(d + 12, (uint32_t)(size >> 32));
    vx_buf_put_u32le(d + 16, ps->first);
    vx_buf_put_u32le(d + 20, count);
    st->crc_at = hn + 4;
    st->crc = file_crc32(0, d + 16, 8);
    st->first = ps->first, st->end = end, st->next = ps->first;
    st->alloc = alloc;
    if (!(r = vx_atomic_open(&st->file, path, alloc, err))) {
        vx_atomic_write(&st->file, head, hn);
        vx_atomic_write(&st->file, d, sizeof d);
        st->open = true;
    }
    vx_free(alloc, head);
    return r;
}

vx_result vx_probe_stream_put(vx_probe_stream* st, const vx_probe_set* ps, uint32_t upto, vx_error* err) {
    if (!st->open) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "stream not open");
    if (upto > st->end || upto > ps->first + ps->count || ps->first > st->next)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "stream: probes up to %u not in the set (%u..%u)", upto,
                       ps->first, ps->first + ps->count);
    vx_buf b = {.alloc = st->alloc};
    for (; st->next < upto; st->next++) {
        b.size = 0;
        put_block(&b, ps, st->next - ps->first);
        if (b.failed) {
            vx_buf_free(&b);
            return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory writing probe %u", st->next);
        }
        st->crc = file_crc32(st->crc, b.data, b.size);
        vx_atomic_write(&st->file, b.data, b.size);
    }
    vx_buf_free(&b);
    stream_flush(&st->file); /* the disk writes start now, while the bake goes on */
    if (st->file.failed_errno) return vx_fail(err, VX_ERR_IO, VX_NO_OFFSET, "cannot write: %s", strerror(st->file.failed_errno));
    return VX_OK;
}

vx_result vx_probe_stream_commit(vx_probe_stream* st, vx_error* err) {
    if (!st->open) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "stream not open");
    st->open = false;
    if (st->next != st->end) {
        vx_atomic_abort(&st->file);
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "stream: probes %u..%u never written", st->next, st->end);
    }
    uint8_t c[4];
    vx_buf_put_u32le(c, st->crc);
    stream_patch(&st->file, st->crc_at, c, 4);
    return vx_atomic_commit(&st->file, err);
}

void vx_probe_stream_abort(vx_probe_stream* st) {
    if (st->open) vx_atomic_abort(&st->file);
    st->open = false;
}

/* ---- reading ------------------------------------------------------------------------- */

static bool rd_vec(vx_rd* r, double v[3]) {
    for (int k = 0; k < 3; k++)
        if (!vx_rd_f64le(r, &v[k]) || !isfinite(v[k])) return false;
    return true;
}

static vx_result read_grid(vx_rd* r, const vx_probe_read_desc* d, vx_probe_set* ps, vx_error* err) {
    uint64_t at = vx_rd_pos(r);
    if (vx_rd_left(r) < GRID_FIXED)
        return vx_fail(err, VX_ERR_TRUNCATED, at, "GRID section at byte %llu: %zu bytes, at least %u needed",
                       (unsigned long long)at, vx_rd_left(r), GRID_FIXED);
    uint32_t irr, dres, bounces;
    vx_rd_u32le(r, &ps->res);
    vx_rd_u32le(r, &ps->low_res);
    vx_rd_u32le(r, &irr);
    vx_rd_u32le(r, &dres);
    for (int k = 0; k < 3; k++) vx_rd_u32le(r, &ps->grid[k]);
    vx_rd_u32le(r, &ps->probe_count);
    uint32_t max_res = d->max_res ? d->max_res : VX_PROBE_MAX_RES;
    uint32_t max_probes = d->max_probes ? d->max_probes : VX_PROBE_MAX_PROBES;
    if (ps->res < 16 || ps->res % 16 || ps->res > max_res || ps->res > VX_PROBE_MAX_RES)
        return vx_fail(err, VX_ERR_BAD_FORMAT, at, "GRID at byte %llu: resolution %u (a multiple of 16, 16..%u)",
                       (unsigned long long)at, ps->res, max_res);
    if (ps->low_res != ps->res / 16 || irr != VX_PROBE_IRR_RES || dres != VX_PROBE_DIST_RES)
        return vx_fail(err, VX_ERR_UNSUPPORTED, at + 4, "GRID at byte %llu: map sizes %u/%u/%u (expected %u/%u/%u)",
                       (unsigned long long)at, ps->low_res, irr, dres, ps->res / 16, VX_PROBE_IRR_RES, VX_PROBE_DIST_RES);
    uint64_t total = 1;
    for (int k = 0; k < 3; k++) {
        if (!ps->grid[k] || ps->grid[k] > max_probes)
            return vx_fail(err, VX_ERR_BAD_FORMAT, at + 16, "GRID at byte %llu: grid axis %d has %u probes",
                           (unsigned long long)at, k, ps->grid[k]);
        if (!vx_mul_u64(total, ps->grid[k], &total) || total > max_probes) {
            total = UINT64_MAX;
            break;
        }
    }
    if (total != ps->probe_count || total > max_probes)
        return vx_fail(err, VX_ERR_BAD_FORMAT, at + 28, "GRID at byte %llu: %u probes declared for a %ux%ux%u grid (limit %u)",
                       (unsigned long long)at, ps->probe_count, ps->grid[0], ps->grid[1], ps->grid[2], max_probes);
    if (!rd_vec(r, ps->origin) || !rd_vec(r, ps->spacing) || !vx_rd_f64le(r, &ps->dist_step) ||
        !vx_rd_f64le(r, &ps->dist_max) || !vx_rd_f64le(r, &ps->dist_max_error))
        return vx_fail(err, VX_ERR_BAD_FORMAT, at + 32, "GRID at byte %llu: origin, spacing or distances not finite",
                       (unsigned long long)at);
    for (int k = 0; k < 3; k++)
        if (!(ps->spacing[k] > 0)) return vx_fail(err, VX_ERR_BAD_FORMAT, at + 56, "GRID: spacing must be positive");
    if (!(ps->dist_step > 0) || !isfinite(ps->dist_max) || !(ps->dist_max_error >= 0))
        return vx_fail(err, VX_ERR_BAD_FORMAT, at + 80, "GRID: distance step must be positive");
    vx_rd_u32le(r, &ps->spp);
    vx_rd_u32le(r, &bounces);
    ps->bounces = bounces;
    vx_rd_u64le(r, &ps->seed);
    if (!rd_vec(r, ps->light_dir) || !rd_vec(r, ps->sun) || !rd_vec(r, ps->sky))
        return vx_fail(err, VX_ERR_BAD_FORMAT, at + 120, "GRID at byte %llu: light parameters not finite",
                       (unsigned long long)at);
    size_t need;
    if (!vx_mul_size(ps->probe_count, PROBE_REC, &need) || need != vx_rd_left(r))
        return vx_fail(err, VX_ERR_BAD_FORMAT, vx_rd_pos(r), "GRID at byte %llu: %zu bytes of probe records for %u probes",
                       (unsigned long long)at, vx_rd_left(r), ps->probe_count);
    ps->probes = vx_calloc(ps->alloc, ps->probe_count, sizeof *ps->probes);
    if (!ps->probes) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u probes", ps->probe_count);
    for (uint32_t i = 0; i < ps->probe_count; i++) {
        uint64_t pa = vx_rd_pos(r);
        if (!rd_vec(r, ps->probes[i].pos) || !vx_rd_u32le(r, &ps->probes[i].state) || ps->probes[i].state > VX_PROBE_DISABLED)
            return vx_fail(err, VX_ERR_BAD_FORMAT, pa, "probe %u at byte %llu: position not finite or bad state", i,
                           (unsigned long long)pa);
    }
    return VX_OK;
}

static vx_result read_data(vx_rd* r, vx_probe_set* ps, vx_error* err) {
    uint64_t at = vx_rd_pos(r);
    uint32_t first, count;
    if (!vx_rd_u32le(r, &first) || !vx_rd_u32le(r, &count))
        return vx_fail(err, VX_ERR_TRUNCATED, at, "DATA section at byte %llu: truncated header", (unsigned long long)at);
    if ((uint64_t)first + count > ps->probe_count || !count)
        return vx_fail(err, VX_ERR_BAD_FORMAT, at, "DATA at byte %llu: probes %u..%u outside the %u of the grid",
                       (unsigned long long)at, first, first + count, ps->probe_count);
    size_t need;
    if (!vx_mul_size(block_bytes(ps->res, ps->low_res), count, &need) || need != vx_rd_left(r))
        return vx_fail(err, VX_ERR_BAD_FORMAT, at + 8, "DATA at byte %llu: %zu bytes for %u probes of %zu bytes",
                       (unsigned long long)at, vx_rd_left(r), count, block_bytes(ps->res, ps->low_res));
    size_t nr = vx__bsq(ps->res), nl = vx__bsq(ps->low_res), ni = vx__bsq(VX_PROBE_IRR_RES), nm = vx__bsq(VX_PROBE_DIST_RES);
    ps->radiance = vx_calloc(ps->alloc, nr * 3 * count, 2);
    ps->normal = vx_calloc(ps->alloc, nr * count, 4);
    ps->distance = vx_calloc(ps->alloc, nr * count, 2);
    ps->low = vx_calloc(ps->alloc, nl * count, 2);
    ps->irradiance = vx_calloc(ps->alloc, ni * 3 * count, 2);
    ps->moments = vx_calloc(ps->alloc, nm * 2 * count, 4);
    if (!ps->radiance || !ps->normal || !ps->distance || !ps->low || !ps->irradiance || !ps->moments)
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u probes", count);
    for (size_t p = 0; p < count; p++) {
        for (size_t i = 0; i < nr * 3; i++) vx_rd_u16le(r, &ps->radiance[p * nr * 3 + i]);
        for (size_t i = 0; i < nr; i++) vx_rd_u32le(r, &ps->normal[p * nr + i]);
        for (size_t i = 0; i < nr; i++) vx_rd_u16le(r, &ps->distance[p * nr + i]);
        for (size_t i = 0; i < nl; i++) vx_rd_u16le(r, &ps->low[p * nl + i]);
        for (size_t i = 0; i < ni * 3; i++) vx_rd_u16le(r, &ps->irradiance[p * ni * 3 + i]);
        for (size_t i = 0; i < nm * 2; i++) {
            uint64_t fa = vx_rd_pos(r);
            float v = 0;
            vx_rd_f32le(r, &v);
            if (!isfinite(v) || v < 0)
                return vx_fail(err, VX_ERR_BAD_FORMAT, fa, "DATA: distance moment at byte %llu is negative or not finite",
                               (unsigned long long)fa);
            ps->moments[p * nm * 2 + i] = v;
        }
    }
    ps->first = first;
    ps->count = count;
    return VX_OK;
}

vx_result vx_probe_read(const vx_probe_read_desc* desc, const void* data, size_t size, vx_probe_set* out,
                        vx_error* err) {
    if (!data || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    vx_probe_read_desc d = desc ? *desc : (vx_probe_read_desc){0};
    vx_rd r = vx_rd_make(data, size);
    char m[8];
    uint32_t version, nsec;
    if (!vx_rd_bytes(&r, m, 8) || memcmp(m, magic, 8))
        return vx_fail(err, VX_ERR_BAD_FORMAT, 0, "not a .probes file (magic 'VXPROBES' missing at byte 0)");
    if (!vx_rd_u32le(&r, &version) || !vx_rd_u32le(&r, &nsec))
        return vx_fail(err, VX_ERR_TRUNCATED, 8, "header truncated at byte %zu", r.off);
    if (version != VX_PROBE_FORMAT_VERSION)
        return vx_fail(err, VX_ERR_UNSUPPORTED, 8, "format version %u (this reader knows %u)", version,
                       VX_PROBE_FORMAT_VERSION);
    if (nsec > 64) return vx_fail(err, VX_ERR_BAD_FORMAT, 12, "%u sections (at most 64)", nsec);
    vx_probe_set ps = {.alloc = d.alloc};
    bool grid = false, have_data = false;
    vx_result res = VX_OK;
    for (uint32_t s = 0; s < nsec && !res; s++) {
        uint64_t at = vx_rd_pos(&r);
        char tag[5] = {0};
        uint32_t crc;
        uint64_t len;
        if (!vx_rd_bytes(&r, tag, 4) || !vx_rd_u32le(&r, &crc) || !vx_rd_u64le(&r, &len)) {
            r.off = (size_t)at;
            res = vx_fail(err, VX_ERR_TRUNCATED, at, "section %u header at byte %llu truncated", s, (unsigned long long)at);
            break;
        }
        vx_rd sub;
        if (len > vx_rd_left(&r) || !vx_rd_sub(&r, (size_t)len, &sub)) {
            res = vx_fail(err, VX_ERR_TRUNCATED, at + 8, "section '%s' at byte %llu: %llu bytes declared, %zu left", tag,
                          (unsigned long long)at, (unsigned long long)len, vx_rd_left(&r));
            break;
        }
        uint32_t c = file_crc32(0, sub.p, sub.size);
        if (c != crc) {
            res = vx_fail(err, VX_ERR_BAD_FORMAT, at + 4, "section '%s' at byte %llu: CRC-32 %08x, stored %08x", tag,
                          (unsigned long long)at, c, crc);
            break;
        }
        if (!memcmp(tag, "GRID", 4)) {
            if (grid) res = vx_fail(err, VX_ERR_BAD_FORMAT, at, "second GRID section at byte %llu", (unsigned long long)at);
            else res = read_grid(&sub, &d, &ps, err);
            grid = true;
        } else if (!memcmp(tag, "DATA", 4)) {
            if (!grid || have_data)
                res = vx_fail(err, VX_ERR_BAD_FORMAT, at, "DATA section at byte %llu %s", (unsigned long long)at,
                              have_data ? "repeated" : "before GRID");
            else res = read_data(&sub, &ps, err);
            have_data = true;
        } /* unknown sections are skipped by their size */
    }
    if (!res && !grid) res = vx_fail(err, VX_ERR_BAD_FORMAT, r.off, "no GRID section");
    if (!res && vx_rd_left(&r))
        res = vx_fail(err, VX_ERR_BAD_FORMAT, r.off, "%zu bytes after the last section at byte %zu", vx_rd_left(&r), r.off);
    if (res) {
        vx_probe_set_free(&ps);
        return res;
    }
    *out = ps;
    return VX_OK;
}

vx_result vx_probe_read_file(const vx_probe_read_desc* desc, const char* path, vx_probe_set* out, vx_error* err) {
    const vx_allocator* a = desc ? desc->alloc : NULL;
    uint8_t* data = NULL;
    size_t size = 0;
    vx_result r = vx_file_read(path, a, 0, &data, &size, err);
    if (r) return r;
    r = vx_probe_read(desc, data, size, out, err);
    vx_free(a, data);
    if (r) vx_error_prefix(err, path);
    return r;
}
