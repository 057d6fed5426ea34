/* svo/svo_io.c - the .svo container: header, section table, sections.
 * docs/FORMAT.md is the specification; keep the two in step.
 *
 * The metadata (header, table, SCNE, PALT, MATL) is varint-coded so that a
 * small scene costs a few dozen bytes; node words and attribute records are
 * range-coded in NODE (svo_pack.c), mostly as the bare DAG structure. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <fcntl.h>
#include <pthread.h>
#include <stdatomic.h>
#include <sys/stat.h>

#include "svo/svo_internal.h"

static const uint8_t MAGIC[8] = {'V', 'X', 'S', 'V', 'O', 0, '\r', '\n'};
enum {
    HEADER_SIZE = 12, /* magic, u16 version, u16 section count; the table follows */
    MAX_SECTIONS = 1024,
    /* the most a parse of the header and table reads: MAX_SECTIONS entries of
     * a tag, two varints (up to 10 bytes each before one is refused) and a
     * CRC, then the table's CRC */
    TABLE_MAX = HEADER_SIZE + MAX_SECTIONS * (4 + 10 + 10 + 4) + 4,
    SEC_REQUIRED = 1u << 0,
    SEC_ALIGN4 = 1u << 1,
    SEC_FLAGS = SEC_REQUIRED | SEC_ALIGN4,
    NAME_MAX_LEN = 63,          /* in-memory names are char[64] with their NUL */
    SCNE_WORLD = 1u << 0,       /* world_from_grid stored (else identity) */
    SCNE_BOUNDS_SHIFT = 1,      /* 2 bits: bounds form */
    SCNE_FORM_BITS = 0x7,
    BOUNDS_COMPUTED = 0,
    BOUNDS_INT = 1,
    BOUNDS_F64 = 2,
    XF_ROT = 0,    /* signed permutation matrix: one .vox-style rotation byte */
    XF_SIGNED = 1, /* entries in {-1, 0, 1}: 9 x 2 bits in 3 bytes */
    XF_F64 = 2,    /* 12 f64 */
    PALT_RGB = 1u << 0,
    ROOT_CODE_EMPTY = 0,
    ROOT_CODE_LEAF = 1,
    ROOT_CODE_BACK = 2, /* + (node_count - 1 - root) */
    MODEL_SAME_SIZE = 1u << 5, /* model head: size as the previous model's */
    MODEL_CHUNKED = 1u << 6,   /* model head: its NODE stream is in the chunked form (version 3) */
    VERSION_CHUNKED = 3,       /* the format version that introduced MODEL_CHUNKED */
    MODEL_TAGGED = 1u << 7,    /* model head, with MODEL_CHUNKED: each chunk starts with its codec byte (version 4) */
    VERSION_TAGGED = 4,        /* the format version that introduced MODEL_TAGGED (zstd chunks) */
    MODEL_SPLIT = 1u << 8,     /* model head: its NODE stream is in the split form (version 5) */
    VERSION_SPLIT = 5,         /* the format version that introduced MODEL_SPLIT */
    VERSION_RUNS = 6,          /* the split form's runs stream (svo_split.c, VX__SPLIT_RUNS) */
    INST_NAMED = 1u << 2,      /* instance head: a name follows */
    FRMS_CHANGE_MIN = 7        /* smallest change record: gap, head, model, rotation byte, 3 translations */
};
/* Expanded material dictionaries (one copy per material) are capped: with
 * shared dictionaries a small file could otherwise ask for quadratic memory. */
#define MATL_EXPANDED_MAX ((uint64_t)64 << 20)

/* Known sections, and the format version that introduced each. */
enum { S_SCNE, S_NODE, S_PALT, S_MATL, S_LGHT, S_FRMS, S_COUNT };
static const char TAGS[S_COUNT][5] = {"SCNE", "NODE", "PALT", "MATL", "LGHT", "FRMS"};
static const uint16_t SINCE[S_COUNT] = {1, 1, 1, 1, 2, 2};

/* The version a file is stamped with: the newest that introduced one of its
 * sections, so a file without version-2 sections keeps version 1's bytes
 * (and old readers keep reading it). A reader refuses a section newer than
 * the file's version: each file has one form. */
static uint16_t file_version(const int* order, int n) {
    uint16_t v = 1;
    for (int i = 0; i < n; i++)
        if (SINCE[order[i]] > v) v = SINCE[order[i]];
    return v;
}

/* LGHT: a light's fields in groups, stored only when not all +0.0 (bit i of
 * the light's mask is group i, in this order; docs/FORMAT.md 2.4). */
enum { LGHT_GROUPS = 11, LGHT_TYPE_BITS = 3 };
static double* light_group(vx_light* l, int g, int* n) {
    *n = 0;
    if (g < 0 || g >= LGHT_GROUPS) return NULL;
    double* f[LGHT_GROUPS] = {l->position, l->direction, l->color, &l->intensity, &l->range, &l->inner_cone,
                              &l->outer_cone, &l->radius, &l->angular_diameter, l->tangent, l->size};
    static const int len[LGHT_GROUPS] = {3, 3, 3, 1, 1, 1, 1, 1, 1, 3, 2};
    *n = len[g];
    return f[g];
}
static bool all_pos_zero(const double* v, int n) {
    for (int i = 0; i < n; i++)
        if (v[i] != 0 || signbit(v[i])) return false;
    return true;
}

static int tag_index(const uint8_t t[4]) {
    for (int i = 0; i < S_COUNT; i++)
        if (memcmp(t, TAGS[i], 4) == 0) return i;
    return -1;
}
static void tag_str(const uint8_t t[4], char out[5]) {
    for (int k = 0; k < 4; k++) out[k] = (t[k] >= 32 && t[k] < 127) ? (char)t[k] : '?';
    out[4] = 0;
}

static uint32_t rd32(const uint8_t* p) {
    return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
}

/* ---- varints ----------------------------------------------------------------------------
 * Unsigned LEB128: 7 bits per byte, low group first, bit 7 set on every byte
 * but the last. Readers accept only the shortest encoding (at most 10 bytes,
 * the tenth holding bit 63 alone) so that every value has one byte form. */

static bool buf_var(vx_buf* b, uint64_t v) {
    uint8_t t[10];
    size_t n = 0;
    do {
        t[n] = (uint8_t)(v & 0x7Fu);
        v >>= 7;
        if (v) t[n] |= 0x80u;
        n++;
    } while (v);
    return vx_buf_append(b, t, n);
}
static uint32_t zig32(int32_t v) { return ((uint32_t)v << 1) ^ (uint32_t)(v < 0 ? -1 : 0); }
static int32_t unzig32(uint32_t v) { return (int32_t)(v >> 1) ^ -(int32_t)(v & 1u); }
static uint64_t zig64(int64_t v) { return ((uint64_t)v << 1) ^ (uint64_t)(v < 0 ? -1 : 0); }
static int64_t unzig64(uint64_t v) { return (int64_t)(v >> 1) ^ -(int64_t)(v & 1u); }

/* Reads one varint of at most max; on failure the cursor does not move and
 * err names the section, the byte and the field. */
static vx_result rd_var(vx_rd* rd, uint64_t max, uint64_t* out, const char* sec, const char* what, vx_error* err) {
    uint64_t v = 0, at = vx_rd_pos(rd);
    size_t o = rd->off;
    for (unsigned i = 0;; i++) {
        if (o >= rd->size)
            return vx_fail(err, VX_ERR_TRUNCATED, at, "svo: section %s at byte %llu: %s: varint runs past the end of the section",
                           sec, (unsigned long long)at, what);
        uint8_t c = rd->p[o++];
        if (i == 9 && c > 1)
            return vx_fail(err, VX_ERR_BAD_FORMAT, at, "svo: section %s at byte %llu: %s: varint overflows 64 bits", sec,
                           (unsigned long long)at, what);
        v |= (uint64_t)(c & 0x7Fu) << (7 * i);
        if (!(c & 0x80u)) {
            if (i > 0 && c == 0)
                return vx_fail(err, VX_ERR_BAD_FORMAT, at, "svo: section %s at byte %llu: %s: over-long varint (not the shortest form)",
                               sec, (unsigned long long)at, what);
            break;
        }
        /* byte 9 holds bit 63 only, so it never continues */
    }
    if (v > max)
        return vx_fail(err, VX_ERR_BAD_FORMAT, at, "svo: section %s at byte %llu: %s is %llu, the limit is %llu", sec,
                       (unsigned long long)at, what, (unsigned long long)v, (unsigned long long)max);
    rd->off = o;
    *out = v;
    return VX_OK;
}
static vx_result rd_var32(vx_rd* rd, uint32_t* out, const char* sec, const char* what, vx_error* err) {
    uint64_t v = 0;
    vx_result r = rd_var(rd, UINT32_MAX, &v, sec, what, err);
    if (r == VX_OK) *out = (uint32_t)v;
    return r;
}
static vx_result rd_need(vx_rd* rd, size_t n, const char* sec, const char* what, vx_error* err) {
    if (n > vx_rd_left(rd))
        return vx_fail(err, VX_ERR_TRUNCATED, vx_rd_pos(rd), "svo: section %s at byte %llu: %s needs %zu bytes, %zu left", sec,
                       (unsigned long long)vx_rd_pos(rd), what, n, vx_rd_left(rd));
    return VX_OK;
}
static vx_result rd_f64s(vx_rd* rd, double* v, int n, const char* sec, const char* what, vx_error* err) {
    vx_result r = rd_need(rd, (size_t)n * 8, sec, what, err);
    for (int i = 0; r == VX_OK && i < n; i++) vx_rd_f64le(rd, &v[i]);
    return r;
}
/* A length-prefixed name into a char[64]: at most 63 bytes, no NUL inside. */
static vx_result rd_name(vx_rd* rd, char out[64], const char* sec, const char* what, vx_error* err) {
    uint64_t len, at = vx_rd_pos(rd);
    vx_result r = rd_var(rd, UINT64_MAX, &len, sec, what, err);
    if (r != VX_OK) return r;
    if (len > NAME_MAX_LEN)
        return vx_fail(err, VX_ERR_BAD_FORMAT, at, "svo: section %s at byte %llu: %s is %llu bytes long, the limit is %d", sec,
                       (unsigned long long)at, what, (unsigned long long)len, NAME_MAX_LEN);
    if ((r = rd_need(rd, (size_t)len, sec, what, err)) != VX_OK) return r;
    memset(out, 0, 64);
    vx_rd_bytes(rd, out, (size_t)len);
    if (memchr(out, 0, (size_t)len))
        return vx_fail(err, VX_ERR_BAD_FORMAT, at, "svo: section %s at byte %llu: %s contains a NUL byte", sec,
                       (unsigned long long)at, what);
    return VX_OK;
}
static bool buf_name(vx_buf* b, const char name[64]) {
    size_t len = strnlen(name, 64); /* validated: < 64 */
    return buf_var(b, len) && vx_buf_append(b, name, len);
}

/* ---- transforms ---------------------------------------------------------------------------- */

static bool is_pos_zero(double v) { return v == 0.0 && !signbit(v); }
/* -1, 0 or +1 as exactly these bit patterns (so -0.0 keeps the f64 form) */
static bool unit_entry(double v, int* out) {
    if (is_pos_zero(v)) *out = 0;
    else if (v == 1.0) *out = 1;
    else if (v == -1.0) *out = -1;
    else return false;
    return true;
}
static bool int_translation(double v, int32_t* out) {
    if (!(v >= -2147483648.0 && v <= 2147483647.0) || v != floor(v) || (v == 0.0 && signbit(v))) return false;
    *out = (int32_t)v;
    return true;
}

/* Picks the shortest exact form of an instance transform and appends its
 * payload (the kind goes into the instance's head varint). */
static int xform_kind(const double* x, uint8_t pay[3], size_t* pay_len, int32_t t[3]) {
    int e[9];
    for (int r = 0; r < 3; r++) {
        for (int c = 0; c < 3; c++)
            if (!unit_entry(x[4 * r + c], &e[3 * r + c])) return XF_F64;
        if (!int_translation(x[4 * r + 3], &t[r])) return XF_F64;
    }
    int col[3];
    bool perm = true;
    for (int r = 0; r < 3 && perm; r++) {
        int nz = 0;
        for (int c = 0; c < 3; c++)
            if (e[3 * r + c]) nz++, col[r] = c;
        perm = nz == 1;
    }
    if (perm && col[0] != col[1] && col[0] != col[2] && col[1] != col[2]) {
        pay[0] = (uint8_t)(col[0] | col[1] << 2 | (e[col[0]] < 0) << 4 | (e[3 + col[1]] < 0) << 5 | (e[6 + col[2]] < 0) << 6);
        *pay_len = 1;
        return XF_ROT;
    }
    uint32_t bits = 0;
    for (int i = 0; i < 9; i++) bits |= (uint32_t)(e[i] == 0 ? 0 : e[i] > 0 ? 1 : 2) << (2 * i);
    pay[0] = (uint8_t)bits, pay[1] = (uint8_t)(bits >> 8), pay[2] = (uint8_t)(bits >> 16);
    *pay_len = 3;
    return XF_SIGNED;
}

/* prev: the translation of the previous compact instance (0 0 0 at first);
 * compact translations are stored as differences from it, because the
 * instances of a scene tend to sit near each other. */
static vx_result rd_xform(vx_rd* rd, const char* S, int kind, double* x, int32_t prev[3], vx_error* err) {
    uint64_t at = vx_rd_pos(rd);
    vx_result r;
    if (kind == XF_F64) return rd_f64s(rd, x, 12, S, "instance transform", err);
    if (kind != XF_ROT && kind != XF_SIGNED)
        return vx_fail(err, VX_ERR_BAD_FORMAT, at, "svo: section %s at byte %llu: unknown transform kind %d", S, (unsigned long long)at,
                       kind);
    int e[9] = {0};
    if (kind == XF_ROT) {
        uint8_t b = 0;
        if ((r = rd_need(rd, 1, S, "rotation byte", err)) != VX_OK) return r;
        vx_rd_u8(rd, &b);
        int c0 = b & 3, c1 = (b >> 2) & 3;
        if (c0 > 2 || c1 > 2 || c0 == c1 || (b & 0x80u))
            return vx_fail(err, VX_ERR_BAD_FORMAT, at, "svo: section %s at byte %llu: rotation byte 0x%02x is not a signed permutation",
                           S, (unsigned long long)at, b);
        int c2 = 3 - c0 - c1;
        e[c0] = (b >> 4) & 1 ? -1 : 1;
        e[3 + c1] = (b >> 5) & 1 ? -1 : 1;
        e[6 + c2] = (b >> 6) & 1 ? -1 : 1;
    } else {
        uint8_t b[3];
        if ((r = rd_need(rd, 3, S, "matrix entries", err)) != VX_OK) return r;
        vx_rd_bytes(rd, b, 3);
        uint32_t bits = b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16;
        if (bits >> 18)
            return vx_fail(err, VX_ERR_BAD_FORMAT, at, "svo: section %s at byte %llu: matrix entry bits above bit 17 are set",
                           S, (unsigned long long)at);
        for (int i = 0; i < 9; i++) {
            uint32_t c = bits >> (2 * i) & 3u;
            if (c == 3)
                return vx_fail(err, VX_ERR_BAD_FORMAT, at, "svo: section %s at byte %llu: matrix entry %d has the invalid code 3",
                               S, (unsigned long long)at, i);
            e[i] = c == 0 ? 0 : c == 1 ? 1 : -1;
        }
    }
    for (int k = 0; k < 3; k++) {
        uint64_t z, zat = vx_rd_pos(rd);
        if ((r = rd_var(rd, UINT32_MAX * 2ull, &z, S, "instance translation", err)) != VX_OK) return r;
        int64_t t = prev[k] + unzig64(z);
        if (t < INT32_MIN || t > INT32_MAX)
            return vx_fail(err, VX_ERR_BAD_FORMAT, zat, "svo: section %s at byte %llu: instance translation %lld is outside int32",
                           S, (unsigned long long)zat, (long long)t);
        prev[k] = (int32_t)t;
        x[4 * k + 3] = (double)t;
        for (int c = 0; c < 3; c++) x[4 * k + c] = (double)e[3 * k + c];
    }
    return VX_OK;
}

/* ---- header and section table ------------------------------------------------------------- */

typedef struct sec {
    uint8_t tag[4];
    uint32_t flags, crc;
    uint64_t offset, size;
    const uint8_t* p; /* the section's bytes: in the file's buffer, or (the model
                         reader) read into one of its own; NULL where not read */
} sec;

/* ---- the file's bytes ----------------------------------------------------------------------
 * A file is read with pread into buffers the reader owns, never mapped: a
 * map of a file that another process cuts short while it is read faults
 * (SIGBUS) on the first page past the new end, and a library may not catch
 * signals. With pread a shortened file is a short read: an error naming the
 * file, the byte where it ended and the size it had when opened. */
typedef struct fsrc {
    int fd;
    uint64_t size; /* when opened */
} fsrc;

/* n bytes at off (off + n <= f->size, checked by the caller) into buf. */
static vx_result fsrc_read(const fsrc* f, uint64_t off, void* buf, size_t n, vx_error* err) {
    uint8_t* b = (uint8_t*)buf;
    size_t got = 0;
    while (got < n) {
        size_t want = n - got < ((size_t)1 << 30) ? n - got : ((size_t)1 << 30);
        ssize_t k = pread(f->fd, b + got, want, (off_t)(off + got));
        if (k < 0 && errno == EINTR) continue;
        if (k < 0)
            return vx_fail(err, VX_ERR_IO, off + got, "svo: read error at byte %llu: %s", (unsigned long long)(off + got), strerror(errno));
        if (k == 0)
            return vx_fail(err, VX_ERR_TRUNCATED, off + got,
                           "svo: the file ends at byte %llu, it had %llu bytes when opened (cut short while it was read)",
                           (unsigned long long)(off + got), (unsigned long long)f->size);
        got += (size_t)k;
    }
    return VX_OK;
}

/* Parses the header and the table; fills secs (count entries) when non-NULL.
 * Checks every bound, the table CRC and the zero alignment gaps, not the
 * section CRCs. Section offsets follow from the sizes: sections are stored
 * back to back after the table, and one with ALIGN4 starts at the next
 * multiple of 4; the last one ends at the end of the file. */
/* d holds the file's first avail bytes (the table fits in them: at most
 * TABLE_MAX bytes; a larger file is read through f where a gap byte lies
 * past them); size is the file's. A section's bytes (p) are set only where
 * d holds the whole file. */
static vx_result parse_table(const uint8_t* d, size_t avail, uint64_t fsize, const fsrc* f, uint32_t* out_version, uint32_t* out_count,
                             sec* secs, vx_error* err) {
    size_t size = avail; /* the table's bounds; the sections' are the file's */
    if (size < HEADER_SIZE + 4)
        return vx_fail(err, VX_ERR_TRUNCATED, size, "svo: file is %zu bytes, the header needs %d", size, HEADER_SIZE + 4);
    if (memcmp(d, MAGIC, 8) != 0) return vx_fail(err, VX_ERR_BAD_FORMAT, 0, "svo: not a .svo file (bad magic)");
    uint32_t version = d[8] | (uint32_t)d[9] << 8, count = d[10] | (uint32_t)d[11] << 8;
    if (version == 0 || version > VX_SVO_FORMAT_VERSION)
        return vx_fail(err, VX_ERR_UNSUPPORTED, 8, "svo: format version %u, this reader supports 1..%u", version,
                       VX_SVO_FORMAT_VERSION);
    if (count > MAX_SECTIONS) return vx_fail(err, VX_ERR_LIMIT, 10, "svo: %u sections, the limit is %d", count, MAX_SECTIONS);
    vx_rd rd = vx_rd_make(d, size);
    rd.off = HEADER_SIZE;
    vx_result r;
    for (uint32_t i = 0; i < count; i++) {
        uint64_t at = vx_rd_pos(&rd), flags, sz;
        uint8_t tag[4];
        uint32_t crc;
        if (!vx_rd_bytes(&rd, tag, 4))
            return vx_fail(err, VX_ERR_TRUNCATED, at, "svo: section table entry %u at byte %llu is truncated", i, (unsigned long long)at);
        if ((r = rd_var(&rd, UINT32_MAX, &flags, "table", "section flags", err)) != VX_OK ||
            (r = rd_var(&rd, UINT64_MAX, &sz, "table", "section size", err)) != VX_OK)
            return r;
        if (!vx_rd_u32le(&rd, &crc))
            return vx_fail(err, VX_ERR_TRUNCATED, at, "svo: section table entry %u at byte %llu is truncated", i, (unsigned long long)at);
        if (secs) {
            memcpy(secs[i].tag, tag, 4);
            secs[i].flags = (uint32_t)flags;
            secs[i].size = sz;
            secs[i].crc = crc;
        }
    }
    uint64_t tend = vx_rd_pos(&rd);
    uint32_t tcrc;
    if (!vx_rd_u32le(&rd, &tcrc))
        return vx_fail(err, VX_ERR_TRUNCATED, tend, "svo: the table CRC at byte %llu is truncated", (unsigned long long)tend);
    if (vx_crc32(0, d, (size_t)tend) != tcrc)
        return vx_fail(err, VX_ERR_BAD_FORMAT, tend, "svo: header and section table CRC mismatch");
    /* entries again, now that the CRC vouches for them: layout checks */
    if (secs) {
        uint64_t off = vx_rd_pos(&rd);
        for (uint32_t i = 0; i < count; i++) {
            char tg[5];
            tag_str(secs[i].tag, tg);
            if (secs[i].flags & ~(uint32_t)SEC_FLAGS)
                return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo: section %s has reserved flag bits 0x%x set", tg,
                               secs[i].flags & ~(uint32_t)SEC_FLAGS);
            if (secs[i].flags & SEC_ALIGN4) {
                uint64_t pad = (4 - off % 4) % 4;
                if (pad > fsize - off)
                    return vx_fail(err, VX_ERR_TRUNCATED, off, "svo: section %s: alignment gap at byte %llu runs past the end of the file",
                                   tg, (unsigned long long)off);
                uint8_t gap[4] = {0, 0, 0, 0};
                if (off + pad <= avail) memcpy(gap, d + off, (size_t)pad);
                else if ((r = fsrc_read(f, off, gap, (size_t)pad, err)) != VX_OK)
                    return r;
                for (uint64_t k = 0; k < pad; k++)
                    if (gap[k])
                        return vx_fail(err, VX_ERR_BAD_FORMAT, off + k, "svo: alignment gap byte %llu before section %s is not zero",
                                       (unsigned long long)(off + k), tg);
                off += pad;
            }
            if (secs[i].size > fsize - off)
                return vx_fail(err, VX_ERR_TRUNCATED, off, "svo: section %s (%llu bytes at byte %llu) runs past the end of the %llu-byte file",
                               tg, (unsigned long long)secs[i].size, (unsigned long long)off, (unsigned long long)fsize);
            secs[i].offset = off;
            secs[i].p = avail == fsize ? d + off : NULL;
            off += secs[i].size;
        }
        if (off != fsize)
            return vx_fail(err, VX_ERR_BAD_FORMAT, off, "svo: %llu bytes after the last section", (unsigned long long)(fsize - off));
    }
    *out_version = version;
    *out_count = count;
    return VX_OK;
}

/* parse_table twice: once for the count, once into an allocated array. */
static vx_result load_table(const uint8_t* d, size_t avail, uint64_t fsize, const fsrc* f, const vx_allocator* A, uint32_t* version,
                            uint32_t* count, sec** out, vx_error* err) {
    vx_result r = parse_table(d, avail, fsize, f, version, count, NULL, err);
    if (r != VX_OK) return r;
    sec* secs = (sec*)vx_calloc(A, *count ? *count : 1, sizeof *secs);
    if (!secs) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo: out of memory");
    r = parse_table(d, avail, fsize, f, version, count, secs, err);
    if (r != VX_OK) {
        vx_free(A, secs);
        return r;
    }
    *out = secs;
    return VX_OK;
}

vx_result vx_svo_probe(const void* data, size_t size, vx_svo_file_info* out, vx_error* err) {
    if (!data && size) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo: null data");
    if (!out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo: null output");
    const uint8_t* d = (const uint8_t*)data;
    uint32_t version, count;
    sec* secs = NULL;
    vx_result r = load_table(d, size, size, NULL, NULL, &version, &count, &secs, err);
    if (r != VX_OK) return r;
    vx_svo_file_info info;
    memset(&info, 0, sizeof info);
    info.version = version;
    info.section_count = count;
    info.file_size = size;
    for (uint32_t i = 0; i < count && i < 64; i++) {
        vx_svo_section_info* s = &info.sections[i];
        tag_str(secs[i].tag, s->tag);
        s->flags = secs[i].flags;
        s->offset = secs[i].offset;
        s->size = secs[i].size;
        s->crc = secs[i].crc;
        s->crc_ok = vx__svo_crc32(0, d + s->offset, (size_t)s->size) == s->crc;
        s->known = tag_index(secs[i].tag) >= 0;
    }
    vx_free(NULL, secs);
    *out = info;
    return VX_OK;
}

/* ---- reading ---------------------------------------------------------------------------- */

static const double IDENTITY12[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};

/* SCNE into s (the models' words and records are decoded from NODE later,
 * against the counts declared here); *bounds_form says whether bounds are
 * still to be computed. */
/* chunked: receives, for a file of version 3 or later, one byte per model
 * (1: MODEL_CHUNKED, 2: MODEL_CHUNKED and MODEL_TAGGED), freed by the caller. */
static vx_result read_scne(const sec* const* known, uint32_t version, const vx_allocator* A, vx_svo_scene* s,
                           int* bounds_form, uint8_t** chunked, vx_error* err) {
    const char* S = "SCNE";
    const sec* sc = known[S_SCNE];
    vx_rd rd = vx_rd_make(sc->p, (size_t)sc->size);
    rd.base = sc->offset;
    vx_result r;
    uint8_t form;
    if (!vx_rd_u8(&rd, &form))
        return vx_fail(err, VX_ERR_TRUNCATED, sc->offset, "svo: section SCNE at byte %llu is empty", (unsigned long long)sc->offset);
    *bounds_form = form >> SCNE_BOUNDS_SHIFT & 3;
    if ((form & ~(unsigned)SCNE_FORM_BITS) || *bounds_form > BOUNDS_F64)
        return vx_fail(err, VX_ERR_BAD_FORMAT, sc->offset, "svo: section SCNE at byte %llu: unknown form byte 0x%02x",
                       (unsigned long long)sc->offset, form);
    if (form & SCNE_WORLD) {
        if ((r = rd_f64s(&rd, s->world_from_grid, 12, S, "world_from_grid", err)) != VX_OK) return r;
    } else {
        memcpy(s->world_from_grid, IDENTITY12, sizeof IDENTITY12);
    }
    if (*bounds_form == BOUNDS_F64) {
        if ((r = rd_f64s(&rd, s->bounds_min, 3, S, "bounds", err)) != VX_OK ||
            (r = rd_f64s(&rd, s->bounds_max, 3, S, "bounds", err)) != VX_OK)
            return r;
    } else if (*bounds_form == BOUNDS_INT) {
        for (int i = 0; i < 6; i++) {
            uint32_t z;
            if ((r = rd_var32(&rd, &z, S, "bounds", err)) != VX_OK) return r;
            (i < 3 ? s->bounds_min : s->bounds_max)[i % 3] = (double)unzig32(z);
        }
    }
    uint32_t mc, ic, lc;
    uint64_t at = vx_rd_pos(&rd);
    if ((r = rd_var32(&rd, &mc, S, "model count", err)) != VX_OK || (r = rd_var32(&rd, &ic, S, "instance count", err)) != VX_OK ||
        (r = rd_var32(&rd, &lc, S, "layer count", err)) != VX_OK)
        return r;
    /* smallest records: model 4 bytes, instance 7, layer 3 (bounds every allocation) */
    uint64_t least = 4ull * mc + 7ull * ic + 3ull * lc;
    if (least > vx_rd_left(&rd))
        return vx_fail(err, VX_ERR_BAD_FORMAT, at,
                       "svo: section SCNE at byte %llu: %u models, %u instances, %u layers need at least %llu bytes, %zu left",
                       (unsigned long long)at, mc, ic, lc, (unsigned long long)least, vx_rd_left(&rd));
    s->models = (vx_svo_model*)vx_calloc(A, mc ? mc : 1, sizeof *s->models);
    s->instances = (vx_svo_instance*)vx_calloc(A, ic ? ic : 1, sizeof *s->instances);
    s->layers = (vx_svo_layer*)vx_calloc(A, lc ? lc : 1, sizeof *s->layers);
    if (version >= VERSION_CHUNKED && !(*chunked = (uint8_t*)vx_calloc(A, mc ? mc : 1, 1)))
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo: out of memory");
    if (!s->models || !s->instances || !s->layers) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo: out of memory");

    for (uint32_t i = 0; i < mc; i++) {
        vx_svo_model* m = &s->models[i];
        s->model_count = i + 1; /* so that a failure frees what was copied */
        at = vx_rd_pos(&rd);
        uint64_t root_code;
        uint32_t mhead;
        if ((r = rd_var32(&rd, &mhead, S, "model head", err)) != VX_OK) return r;
        uint32_t known_bits = VX_ATTR_ALL | MODEL_SAME_SIZE | (version >= VERSION_CHUNKED ? MODEL_CHUNKED : 0u) |
                              (version >= VERSION_TAGGED ? MODEL_TAGGED : 0u) | (version >= VERSION_SPLIT ? MODEL_SPLIT : 0u);
        uint32_t unknown = mhead & ~known_bits;
        if (unknown)
            return vx_fail(err, VX_ERR_BAD_FORMAT, at, "svo: section SCNE at byte %llu: model %u: unknown attribute bits 0x%x in the head%s",
                           (unsigned long long)at, i, unknown,
                           unknown == MODEL_CHUNKED   ? " (the chunked form needs format version 3)"
                           : unknown == MODEL_TAGGED || unknown == (MODEL_TAGGED | MODEL_CHUNKED) ? " (zstd chunks need format version 4)"
                           : unknown == MODEL_SPLIT ? " (the split form needs format version 5)"
                                                      : "");
        if ((mhead & MODEL_TAGGED) && !(mhead & MODEL_CHUNKED))
            return vx_fail(err, VX_ERR_BAD_FORMAT, at, "svo: section SCNE at byte %llu: model %u: codec-tagged chunks without the chunked form",
                           (unsigned long long)at, i);
        if ((mhead & MODEL_SPLIT) && (mhead & MODEL_CHUNKED))
            return vx_fail(err, VX_ERR_BAD_FORMAT, at, "svo: section SCNE at byte %llu: model %u: both the split and the chunked form",
                           (unsigned long long)at, i);
        m->attrs = mhead & VX_ATTR_ALL;
        if (mhead & MODEL_CHUNKED) (*chunked)[i] = mhead & MODEL_TAGGED ? 2 : 1;
        if (mhead & MODEL_SPLIT) (*chunked)[i] = version >= VERSION_RUNS ? 4 : 3; /* 4: the runs stream allowed */
        if (mhead & MODEL_SAME_SIZE) {
            if (i == 0)
                return vx_fail(err, VX_ERR_BAD_FORMAT, at, "svo: section SCNE at byte %llu: model 0 repeats the size of a previous model",
                               (unsigned long long)at);
            memcpy(m->size, m[-1].size, sizeof m->size);
        } else if ((r = rd_var32(&rd, &m->size[0], S, "model size", err)) != VX_OK ||
                   (r = rd_var32(&rd, &m->size[1], S, "model size", err)) != VX_OK ||
                   (r = rd_var32(&rd, &m->size[2], S, "model size", err)) != VX_OK) {
            return r;
        }
        if ((r = rd_var32(&rd, &m->node_count, S, "model node_count", err)) != VX_OK ||
            (r = rd_var(&rd, (uint64_t)UINT32_MAX + 2, &root_code, S, "model root", err)) != VX_OK ||
            (r = rd_var(&rd, UINT64_MAX, &m->voxel_count, S, "model voxel_count", err)) != VX_OK)
            return r;
        if (m->attrs && ((r = rd_var32(&rd, &m->attr_count, S, "model attr_count", err)) != VX_OK ||
                         (r = rd_var32(&rd, &m->root_attr, S, "model root_attr", err)) != VX_OK))
            return r;
        uint32_t mxs = m->size[0] > m->size[1] ? m->size[0] : m->size[1];
        if (m->size[2] > mxs) mxs = m->size[2];
        while (m->depth < 31 && (1u << m->depth) < mxs) m->depth++;
        if (root_code == ROOT_CODE_EMPTY) m->root = VX_SVO_ROOT_EMPTY;
        else if (root_code == ROOT_CODE_LEAF) m->root = VX_SVO_ROOT_LEAF;
        else if (root_code - ROOT_CODE_BACK < m->node_count) m->root = m->node_count - 1 - (uint32_t)(root_code - ROOT_CODE_BACK);
        else
            return vx_fail(err, VX_ERR_BAD_FORMAT, at, "svo: section SCNE at byte %llu: model %u: root code %llu, the model has %u words",
                           (unsigned long long)at, i, (unsigned long long)root_code, m->node_count);
        if ((m->attrs & VX_ATTR_PALETTE) && !known[S_PALT])
            return vx_fail(err, VX_ERR_BAD_FORMAT, at, "svo: section SCNE at byte %llu: model %u uses palette indices but PALT is missing",
                           (unsigned long long)at, i);
        if ((mhead & (MODEL_CHUNKED | MODEL_SPLIT)) && m->root >= m->node_count)
            return vx_fail(err, VX_ERR_BAD_FORMAT, at, "svo: section SCNE at byte %llu: model %u is marked %s but has no root descriptor",
                           (unsigned long long)at, i, mhead & MODEL_SPLIT ? "split" : "chunked");
    }
    int32_t prev[3] = {0, 0, 0};
    for (uint32_t i = 0; i < ic; i++) {
        vx_svo_instance* in = &s->instances[i];
        uint64_t head, layer;
        if ((r = rd_var(&rd, (uint64_t)UINT32_MAX << 3 | 7u, &head, S, "instance head", err)) != VX_OK ||
            (r = rd_var32(&rd, &in->model, S, "instance model", err)) != VX_OK ||
            (r = rd_var(&rd, UINT32_MAX, &layer, S, "instance layer", err)) != VX_OK ||
            (r = rd_xform(&rd, S, (int)(head & 3u), in->xform, prev, err)) != VX_OK)
            return r;
        if (head & INST_NAMED) {
            uint64_t nat = vx_rd_pos(&rd);
            if ((r = rd_name(&rd, in->name, S, "instance name", err)) != VX_OK) return r;
            if (!in->name[0]) /* one form per scene: unnamed instances store no name */
                return vx_fail(err, VX_ERR_BAD_FORMAT, nat, "svo: section SCNE at byte %llu: instance %u is marked named but its name is empty",
                               (unsigned long long)nat, i);
        }
        in->flags = (uint32_t)(head >> 3);
        in->layer = layer == 0 ? UINT32_MAX : (uint32_t)(layer - 1);
        s->instance_count = i + 1;
    }
    for (uint32_t i = 0; i < lc; i++) {
        vx_svo_layer* l = &s->layers[i];
        if ((r = rd_name(&rd, l->name, S, "layer name", err)) != VX_OK || (r = rd_var32(&rd, &l->flags, S, "layer flags", err)) != VX_OK ||
            (r = rd_var32(&rd, &l->rgba, S, "layer colour", err)) != VX_OK)
            return r;
        s->layer_count = i + 1;
    }
    if (vx_rd_left(&rd))
        return vx_fail(err, VX_ERR_BAD_FORMAT, vx_rd_pos(&rd), "svo: section SCNE has %zu trailing bytes at byte %llu", vx_rd_left(&rd),
                       (unsigned long long)vx_rd_pos(&rd));
    return VX_OK;
}

static vx_result read_palt(const sec* ps, vx_svo_scene* s, vx_error* err) {
    vx_rd rd = vx_rd_make(ps->p, (size_t)ps->size);
    rd.base = ps->offset;
    uint8_t form, bits[32];
    if (!vx_rd_u8(&rd, &form) || !vx_rd_bytes(&rd, bits, 32))
        return vx_fail(err, VX_ERR_TRUNCATED, ps->offset, "svo: section PALT at byte %llu is %llu bytes, the bitmap needs 33",
                       (unsigned long long)ps->offset, (unsigned long long)ps->size);
    if (form & ~(unsigned)PALT_RGB)
        return vx_fail(err, VX_ERR_BAD_FORMAT, ps->offset, "svo: section PALT: unknown form byte 0x%02x", form);
    size_t n = 0, esz = (form & PALT_RGB) ? 3 : 4;
    for (int i = 0; i < 32; i++) n += (size_t)__builtin_popcount(bits[i]);
    if (vx_rd_left(&rd) != n * esz)
        return vx_fail(err, VX_ERR_BAD_FORMAT, ps->offset, "svo: section PALT: %zu entries of %zu bytes need %zu bytes, the section has %zu",
                       n, esz, n * esz, vx_rd_left(&rd));
    memset(s->palette, 0, sizeof s->palette);
    for (int i = 0; i < 256; i++) {
        if (!(bits[i >> 3] >> (i & 7) & 1u)) continue;
        uint8_t c[4] = {0, 0, 0, 0xFF};
        vx_rd_bytes(&rd, c, esz);
        s->palette[i] = rd32(c);
    }
    s->has_palette = true;
    return VX_OK;
}

static vx_result read_matl(const sec* ms, const vx_allocator* A, vx_svo_scene* s, vx_error* err) {
    const char* S = "MATL";
    vx_rd rd = vx_rd_make(ms->p, (size_t)ms->size);
    rd.base = ms->offset;
    vx_result r;
    uint64_t nd, at = vx_rd_pos(&rd);
    if ((r = rd_var(&rd, UINT32_MAX, &nd, S, "dictionary count", err)) != VX_OK) return r;
    if (nd > vx_rd_left(&rd)) /* each dictionary takes at least its length byte */
        return vx_fail(err, VX_ERR_BAD_FORMAT, at, "svo: section MATL at byte %llu: %llu dictionaries, %zu bytes left",
                       (unsigned long long)at, (unsigned long long)nd, vx_rd_left(&rd));
    size_t* doff = (size_t*)vx_calloc(A, nd ? (size_t)nd : 1, sizeof *doff);
    uint32_t* dsz = (uint32_t*)vx_calloc(A, nd ? (size_t)nd : 1, sizeof *dsz);
    if (!doff || !dsz) {
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo: out of memory");
        goto done;
    }
    for (uint64_t i = 0; i < nd; i++) {
        if ((r = rd_var32(&rd, &dsz[i], S, "dictionary size", err)) != VX_OK ||
            (r = rd_need(&rd, dsz[i], S, "dictionary", err)) != VX_OK)
            goto done;
        doff[i] = rd.off;
        vx_rd_skip(&rd, dsz[i]);
    }
    uint64_t nm;
    at = vx_rd_pos(&rd);
    if ((r = rd_var(&rd, UINT32_MAX, &nm, S, "material count", err)) != VX_OK) goto done;
    if (nm > vx_rd_left(&rd) / 2) {
        r = vx_fail(err, VX_ERR_BAD_FORMAT, at, "svo: section MATL at byte %llu: %llu materials, %zu bytes left", (unsigned long long)at,
                    (unsigned long long)nm, vx_rd_left(&rd));
        goto done;
    }
    s->materials = (vx_svo_material*)vx_calloc(A, nm ? (size_t)nm : 1, sizeof *s->materials);
    if (!s->materials) {
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo: out of memory");
        goto done;
    }
    uint64_t expanded = 0;
    for (uint64_t i = 0; i < nm; i++) {
        vx_svo_material* mt = &s->materials[i];
        uint64_t di;
        at = vx_rd_pos(&rd);
        if ((r = rd_var32(&rd, &mt->id, S, "material id", err)) != VX_OK ||
            (r = rd_var(&rd, nd ? nd - 1 : 0, &di, S, "material dictionary index", err)) != VX_OK)
            goto done;
        if (nd == 0) {
            r = vx_fail(err, VX_ERR_BAD_FORMAT, at, "svo: section MATL at byte %llu: material %llu refers to a dictionary, there are none",
                        (unsigned long long)at, (unsigned long long)i);
            goto done;
        }
        expanded += dsz[di];
        if (expanded > MATL_EXPANDED_MAX) {
            r = vx_fail(err, VX_ERR_LIMIT, at, "svo: section MATL: material dictionaries expand to more than %llu bytes",
                        (unsigned long long)MATL_EXPANDED_MAX);
            goto done;
        }
        s->material_count = (uint32_t)i + 1;
        if (dsz[di]) {
            mt->dict = (char*)vx_alloc(A, dsz[di]);
            if (!mt->dict) {
                r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo: out of memory");
                goto done;
            }
            memcpy(mt->dict, rd.p + doff[di], dsz[di]);
            mt->dict_size = dsz[di];
        }
    }
    if (vx_rd_left(&rd))
        r = vx_fail(err, VX_ERR_BAD_FORMAT, vx_rd_pos(&rd), "svo: section MATL has %zu trailing bytes", vx_rd_left(&rd));
done:
    vx_free(A, doff);
    vx_free(A, dsz);
    return r;
}

/* A sky or light the validator refused: a malformed file, at byte `at`. */
static vx_result lght_bad(vx_error* err, uint64_t at) {
    char p[64];
    snprintf(p, sizeof p, "svo: section LGHT at byte %llu", (unsigned long long)at);
    vx_error_prefix(err, p);
    if (err) err->code = VX_ERR_BAD_FORMAT, err->offset = at;
    return VX_ERR_BAD_FORMAT;
}

static vx_result read_lght(const sec* ls, const vx_allocator* A, vx_svo_scene* s, vx_error* err) {
    const char* S = "LGHT";
    vx_rd rd = vx_rd_make(ls->p, (size_t)ls->size);
    rd.base = ls->offset;
    vx_result r;
    uint64_t sky_type, at = vx_rd_pos(&rd);
    if ((r = rd_var(&rd, VX_SKY_TYPE_COUNT - 1, &sky_type, S, "sky type", err)) != VX_OK) return r;
    vx_sky* k = &s->sky;
    k->type = (vx_sky_type)sky_type;
    if (k->type == VX_SKY_CONSTANT || k->type == VX_SKY_GRADIENT) {
        if ((r = rd_f64s(&rd, k->color, 3, S, "sky colour", err)) != VX_OK) return r;
        if (k->type == VX_SKY_GRADIENT && ((r = rd_f64s(&rd, k->horizon, 3, S, "sky horizon", err)) != VX_OK ||
                                           (r = rd_f64s(&rd, k->ground, 3, S, "sky ground", err)) != VX_OK))
            return r;
    } else if (k->type == VX_SKY_ENVMAP) {
        uint64_t len, pat;
        if ((r = rd_f64s(&rd, &k->intensity, 1, S, "sky intensity", err)) != VX_OK ||
            (r = rd_f64s(&rd, &k->rotation, 1, S, "sky rotation", err)) != VX_OK)
            return r;
        pat = vx_rd_pos(&rd);
        if ((r = rd_var(&rd, VX_SKY_PATH_MAX, &len, S, "sky path length", err)) != VX_OK ||
            (r = rd_need(&rd, (size_t)len, S, "sky path", err)) != VX_OK)
            return r;
        vx_rd_bytes(&rd, k->path, (size_t)len);
        if (len == 0 || memchr(k->path, 0, (size_t)len))
            return vx_fail(err, VX_ERR_BAD_FORMAT, pat, "svo: section LGHT at byte %llu: the sky path is empty or holds a NUL byte",
                           (unsigned long long)pat);
    }
    if (vx_sky_validate(k, err) != VX_OK) return lght_bad(err, at);
    uint64_t n;
    at = vx_rd_pos(&rd);
    if ((r = rd_var(&rd, UINT32_MAX, &n, S, "light count", err)) != VX_OK) return r;
    if (n > vx_rd_left(&rd)) /* a light is at least its head byte */
        return vx_fail(err, VX_ERR_BAD_FORMAT, at, "svo: section LGHT at byte %llu: %llu lights, %zu bytes left", (unsigned long long)at,
                       (unsigned long long)n, vx_rd_left(&rd));
    s->lights = (vx_light*)vx_calloc(A, n ? (size_t)n : 1, sizeof *s->lights);
    if (!s->lights) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo: out of memory");
    for (uint64_t i = 0; i < n; i++) {
        vx_light* l = &s->lights[i];
        uint64_t head;
        at = vx_rd_pos(&rd);
        if ((r = rd_var(&rd, ((uint64_t)1 << (LGHT_TYPE_BITS + LGHT_GROUPS)) - 1, &head, S, "light head", err)) != VX_OK) return r;
        if ((head & 7u) >= VX_LIGHT_TYPE_COUNT)
            return vx_fail(err, VX_ERR_BAD_FORMAT, at, "svo: section LGHT at byte %llu: light %llu has the unknown type %u",
                           (unsigned long long)at, (unsigned long long)i, (unsigned)(head & 7u));
        l->type = (vx_light_type)(head & 7u);
        for (int g = 0; g < LGHT_GROUPS; g++) {
            if (!(head >> (LGHT_TYPE_BITS + g) & 1u)) continue;
            int gn;
            double* v = light_group(l, g, &gn);
            uint64_t gat = vx_rd_pos(&rd);
            if ((r = rd_f64s(&rd, v, gn, S, "light field", err)) != VX_OK) return r;
            if (all_pos_zero(v, gn))
                return vx_fail(err, VX_ERR_BAD_FORMAT, gat, "svo: section LGHT at byte %llu: light %llu stores field group %d as zeros",
                               (unsigned long long)gat, (unsigned long long)i, g);
        }
        s->light_count = (uint32_t)i + 1;
        if (vx_light_validate(l, (uint32_t)i, err) != VX_OK) return lght_bad(err, at);
    }
    if (vx_rd_left(&rd))
        return vx_fail(err, VX_ERR_BAD_FORMAT, vx_rd_pos(&rd), "svo: section LGHT has %zu trailing bytes", vx_rd_left(&rd));
    return VX_OK;
}

/* FRMS after SCNE (the instance and model counts): frames 1.. as changes
 * against the frame before. The frame records are allocated only after the
 * counts are checked against the bytes left and the expansion limit. */
static vx_result read_frms(const sec* fs, vx_svo_scene* s, vx_error* err) {
    const char* S = "FRMS";
    vx_rd rd = vx_rd_make(fs->p, (size_t)fs->size);
    rd.base = fs->offset;
    vx_result r;
    uint32_t F = 0;
    uint64_t at = vx_rd_pos(&rd);
    if ((r = rd_var32(&rd, &F, S, "frame count", err)) != VX_OK) return r;
    if (F < 2)
        return vx_fail(err, VX_ERR_BAD_FORMAT, at, "svo: section FRMS at byte %llu: frame count %u, an animation has at least 2",
                       (unsigned long long)at, F);
    at = vx_rd_pos(&rd);
    if ((r = rd_f64s(&rd, &s->frame_rate, 1, S, "frame rate", err)) != VX_OK) return r;
    if (!isfinite(s->frame_rate) || s->frame_rate < 0)
        return vx_fail(err, VX_ERR_BAD_FORMAT, at, "svo: section FRMS at byte %llu: frame rate %g is not finite and >= 0",
                       (unsigned long long)at, s->frame_rate);
    at = vx_rd_pos(&rd);
    if (F - 1 > vx_rd_left(&rd)) /* every frame takes at least its change count */
        return vx_fail(err, VX_ERR_BAD_FORMAT, at, "svo: section FRMS at byte %llu: %u frames need at least %u bytes, %zu left",
                       (unsigned long long)at, F, F - 1, vx_rd_left(&rd));
    if ((r = vx_svo_scene_alloc_frames(s, F, err)) != VX_OK) {
        vx_error_prefix(err, "svo: section FRMS");
        return r;
    }
    uint32_t I = s->instance_count;
    int32_t prev[3] = {0, 0, 0};
    for (uint32_t f = 1; f < F; f++) {
        vx_svo_instance* cur = (vx_svo_instance*)vx_svo_scene_frame_instances(s, f);
        if (f > 1 && I) memcpy(cur, vx_svo_scene_frame_instances(s, f - 1), (size_t)I * sizeof *cur);
        uint32_t n = 0;
        at = vx_rd_pos(&rd);
        if ((r = rd_var32(&rd, &n, S, "change count", err)) != VX_OK) return r;
        if (n > I || (uint64_t)n * FRMS_CHANGE_MIN > vx_rd_left(&rd))
            return vx_fail(err, VX_ERR_BAD_FORMAT, at, "svo: section FRMS at byte %llu: frame %u changes %u of %u instances, %zu bytes left",
                           (unsigned long long)at, f, n, I, vx_rd_left(&rd));
        uint64_t next = 0; /* the smallest instance index the next change may name */
        for (uint32_t k = 0; k < n; k++) {
            uint64_t gap = 0, head = 0;
            uint32_t model = 0;
            at = vx_rd_pos(&rd);
            if ((r = rd_var(&rd, UINT32_MAX, &gap, S, "instance gap", err)) != VX_OK) return r;
            if (next + gap >= I)
                return vx_fail(err, VX_ERR_BAD_FORMAT, at, "svo: section FRMS at byte %llu: frame %u changes instance %llu, the scene has %u",
                               (unsigned long long)at, f, (unsigned long long)(next + gap), I);
            uint32_t i = (uint32_t)(next + gap);
            next = (uint64_t)i + 1;
            if ((r = rd_var(&rd, (uint64_t)UINT32_MAX << 2 | 3u, &head, S, "change head", err)) != VX_OK) return r;
            uint64_t mat = vx_rd_pos(&rd);
            if ((r = rd_var32(&rd, &model, S, "change model", err)) != VX_OK) return r;
            if (model >= s->model_count)
                return vx_fail(err, VX_ERR_BAD_FORMAT, mat, "svo: section FRMS at byte %llu: frame %u instance %u uses model %u of %u",
                               (unsigned long long)mat, f, i, model, s->model_count);
            if ((uint32_t)(head >> 2) & ~(uint32_t)VX_SVO_INSTANCE_HIDDEN)
                return vx_fail(err, VX_ERR_BAD_FORMAT, at, "svo: section FRMS at byte %llu: frame %u instance %u has unknown flags 0x%x",
                               (unsigned long long)at, f, i, (unsigned)(head >> 2));
            if ((r = rd_xform(&rd, S, (int)(head & 3u), cur[i].xform, prev, err)) != VX_OK) return r;
            cur[i].model = model;
            cur[i].flags = (uint32_t)(head >> 2);
        }
    }
    if (vx_rd_left(&rd))
        return vx_fail(err, VX_ERR_BAD_FORMAT, vx_rd_pos(&rd), "svo: section FRMS has %zu trailing bytes at byte %llu", vx_rd_left(&rd),
                       (unsigned long long)vx_rd_pos(&rd));
    return VX_OK;
}

/* The known sections of a file's table in known[] (each at most once, none
 * newer than the file's version, an unknown required one refused), their
 * CRCs verified unless skip_crc; with skip_node_crc the NODE section's is
 * left to the caller (the model reader's pass over it, in model order). */
static vx_result check_sections(const sec* secs, uint32_t count, uint32_t version, bool skip_crc, bool skip_node_crc,
                                const sec* known[S_COUNT], vx_error* err) {
    for (uint32_t i = 0; i < count; i++) {
        const sec* e = &secs[i];
        int ti = tag_index(e->tag);
        char tg[5];
        tag_str(e->tag, tg);
        if (ti < 0) {
            if (e->flags & SEC_REQUIRED)
                return vx_fail(err, VX_ERR_UNSUPPORTED, e->offset, "svo: section %s is marked required but unknown to this reader", tg);
            continue; /* unknown optional sections are skipped */
        }
        if (known[ti]) return vx_fail(err, VX_ERR_BAD_FORMAT, e->offset, "svo: section %s appears twice", tg);
        if (SINCE[ti] > version)
            return vx_fail(err, VX_ERR_BAD_FORMAT, e->offset, "svo: section %s needs format version %u, the file says %u", tg,
                           SINCE[ti], version);
        if (!skip_crc && !(skip_node_crc && ti == S_NODE)) {
            uint32_t c = vx__svo_crc32(0, e->p, (size_t)e->size);
            if (c != e->crc)
                return vx_fail(err, VX_ERR_BAD_FORMAT, e->offset, "svo: section %s at byte %llu: CRC-32 is 0x%08x, the table says 0x%08x",
                               tg, (unsigned long long)e->offset, c, e->crc);
        }
        known[ti] = e;
    }
    if (!known[S_SCNE] || !known[S_NODE])
        return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo: the %s section is missing", known[S_SCNE] ? "NODE" : "SCNE");
    return VX_OK;
}

vx_result vx_svo_read(const vx_svo_read_desc* desc, const void* data, size_t size, vx_svo_scene* out, vx_error* err) {
    vx_svo_read_desc rdd;
    if (desc) rdd = *desc;
    else memset(&rdd, 0, sizeof rdd);
    if ((!data && size) || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo: null argument");
    if (rdd.chunk_stats) memset(rdd.chunk_stats, 0, sizeof *rdd.chunk_stats);
    const uint8_t* d = (const uint8_t*)data;
    const vx_allocator* A = rdd.alloc;
    uint32_t version, count;
    sec* secs = NULL;
    vx__svo_extent* ext = NULL;
    uint8_t* chunked = NULL;
    uint8_t* rebuilt = NULL;
    vx_svo_scene s;
    vx_svo_scene_init(&s, A);
    vx_result r = load_table(d, size, size, NULL, A, &version, &count, &secs, err);
    if (r != VX_OK) return r;

    const sec* known[S_COUNT] = {0};
    if ((r = check_sections(secs, count, version, rdd.skip_checksums, false, known, err)) != VX_OK) goto fail;
    int bounds_form = BOUNDS_COMPUTED;
    if ((r = read_scne(known, version, A, &s, &bounds_form, &chunked, err)) != VX_OK) goto fail;
    /* the validation's extents give the bounds of form 0 without another
     * pass over the trees; models rebuilt from the structural form come
     * with theirs and are not walked again (vx__svo_check_rebuilt) */
    if (s.model_count && (!(ext = (vx__svo_extent*)vx_calloc(A, s.model_count, sizeof *ext)) ||
                          !(rebuilt = (uint8_t*)vx_calloc(A, s.model_count, 1)))) {
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo: out of memory");
        goto fail;
    }
    if ((r = vx__svo_pack_read(known[S_NODE]->p, (size_t)known[S_NODE]->size, known[S_NODE]->offset, &s, chunked, A, rdd.threads,
                               &rdd.testing, rdd.chunk_stats, ext, rebuilt, err)) != VX_OK)
        goto fail;
    if (known[S_PALT] && (r = read_palt(known[S_PALT], &s, err)) != VX_OK) goto fail;
    if (known[S_MATL] && (r = read_matl(known[S_MATL], A, &s, err)) != VX_OK) goto fail;
    if (known[S_LGHT] && (r = read_lght(known[S_LGHT], A, &s, err)) != VX_OK) goto fail;
    if (known[S_FRMS] && (r = read_frms(known[S_FRMS], &s, err)) != VX_OK) goto fail;
    r = vx__svo_validate_scene_opt(&s, ext, rdd.threads, &rdd.testing, true, rebuilt, err);
    if (r != VX_OK) {
        if (r == VX_ERR_INVALID_ARG) r = VX_ERR_BAD_FORMAT;
        if (err) err->code = r;
        vx_error_prefix(err, "svo: structure");
        goto fail;
    }
    if (bounds_form == BOUNDS_COMPUTED) vx__svo_scene_bounds_ext(&s, ext, s.bounds_min, s.bounds_max);
    vx__svo_set_checks(&s, ext, rdd.threads, &rdd.testing);
    vx_free(A, ext);
    vx_free(A, rebuilt);
    vx_free(A, secs);
    vx_free(A, chunked);
    *out = s;
    return VX_OK;
fail:
    vx_free(A, ext);
    vx_free(A, rebuilt);
    vx_free(A, secs);
    vx_free(A, chunked);
    vx_svo_scene_free(&s);
    return r;
}

/* Opens path for reading: a regular file (its size at most max), or an
 * error that names the path. The hook of desc, if any, runs now (a test
 * changes the file there, between the size taken and the bytes read). */
static vx_result open_file(const vx_svo_read_desc* desc, const char* path, uint64_t max, fsrc* f, vx_error* err) {
    f->fd = open(path, O_RDONLY | O_CLOEXEC);
    if (f->fd < 0) return vx_fail(err, VX_ERR_IO, VX_NO_OFFSET, "%s: cannot open: %s", path, strerror(errno));
    struct stat st;
    if (fstat(f->fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        close(f->fd);
        return vx_fail(err, VX_ERR_IO, VX_NO_OFFSET, "%s: not a regular file", path);
    }
    if ((uint64_t)st.st_size > max || (uint64_t)st.st_size > SIZE_MAX / 2) {
        close(f->fd);
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "%s: file is %llu bytes, limit is %llu", path, (unsigned long long)st.st_size,
                       (unsigned long long)max);
    }
    f->size = (uint64_t)st.st_size;
    if (desc && desc->on_open) desc->on_open(desc->on_open_user, path);
    return VX_OK;
}

/* The whole file read in pieces on several threads: the copy from the page
 * cache and the first touch of the buffer's fresh pages (the kernel zeroes
 * them) are most of the time a read adds to the parse, and on two threads
 * both cores do them. The first piece that fails (the lowest byte) is the
 * one reported. */
enum { READ_PIECE = 1 << 20 }; /* a file of 4 MiB or more is read on the threads */
typedef struct read_job {
    const fsrc* f;
    uint8_t* buf;
    pthread_mutex_t lock;
    bool failed;
    uint64_t bad_at; /* the lowest piece that failed, and its error */
    vx_error bad;
} read_job;

static void read_piece(void* ctx, unsigned thread, uint32_t i) {
    (void)thread;
    read_job* j = (read_job*)ctx;
    uint64_t off = (uint64_t)i * READ_PIECE, n = j->f->size - off < READ_PIECE ? j->f->size - off : READ_PIECE;
    vx_error e;
    if (fsrc_read(j->f, off, j->buf + off, (size_t)n, &e) == VX_OK) return;
    pthread_mutex_lock(&j->lock);
    if (!j->failed || off < j->bad_at) j->failed = true, j->bad_at = off, j->bad = e;
    pthread_mutex_unlock(&j->lock);
}

static vx_result read_whole(const fsrc* f, uint8_t* buf, unsigned threads, vx_error* err) {
    uint64_t pieces = (f->size + READ_PIECE - 1) / READ_PIECE;
    if (threads < 2 || pieces < 4) return fsrc_read(f, 0, buf, (size_t)f->size, err);
    read_job j = {.f = f, .buf = buf};
    pthread_mutex_init(&j.lock, NULL);
    vx_run_jobs(threads < pieces ? threads : (unsigned)pieces, (uint32_t)pieces, read_piece, &j);
    pthread_mutex_destroy(&j.lock);
    if (!j.failed) return VX_OK;
    if (err) *err = j.bad;
    return j.bad.code;
}

vx_result vx_svo_read_file(const vx_svo_read_desc* desc, const char* path, vx_svo_scene* out, vx_error* err) {
    if (!path || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo: null argument");
    const vx_allocator* A = desc ? desc->alloc : NULL;
    /* the file the caller named: no size limit by default but the address
     * space's (memory that is not there is VX_ERR_NOMEM) */
    uint64_t max = desc && desc->max_file_bytes ? desc->max_file_bytes : UINT64_MAX;
    fsrc f;
    vx_result r = open_file(desc, path, max, &f, err);
    if (r != VX_OK) return r;
    /* fresh pages (a large block is its own map), asked for as 2 MB pages
     * before the read touches them: fewer faults */
    uint8_t* data = f.size ? (uint8_t*)vx_alloc(A, (size_t)f.size) : NULL;
    if (f.size && !data) {
        close(f.fd);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "%s: cannot allocate %llu bytes for the file", path, (unsigned long long)f.size);
    }
    vx__svo_advise_huge(data, (size_t)f.size);
    r = read_whole(&f, data, vx__svo_cpus(desc ? desc->threads : 0), err);
    close(f.fd);
    if (r == VX_OK) r = vx_svo_read(desc, data, (size_t)f.size, out, err);
    if (r != VX_OK) vx_error_prefix(err, path); /* a damaged file's error names it too */
    vx_free(A, data);
    return r;
}

/* ---- models one at a time ------------------------------------------------------------
 * The file is read, not mapped (see fsrc): the header, the table and the
 * sections but NODE at open, and each model's stream into a buffer of its
 * own when its model is asked for, freed once decoded, so the host holds the
 * models being decoded and not the file (the 65536^3 helmet's file is 20.7
 * GB). The streams are read in model order under the lock, and the NODE
 * section's CRC is summed as they are read and checked by finish. */
struct vx_svo_model_reader {
    vx_allocator alloc;
    const vx_allocator* A; /* &alloc, or NULL for the default */
    char* path;
    fsrc src; /* the open file */
    bool skip_crc;
    vx_svo_scene s; /* the scene graph: models without their arrays */
    uint8_t* chunked;
    int bounds_form;
    vx__svo_extent* ext;
    size_t node_n; /* the NODE section: its size, its offset in the file */
    uint64_t node_base;
    uint32_t node_crc; /* as the table says */
    unsigned cpus;
    vx_svo_testing testing; /* vx_svo_read_desc.testing */
    pthread_mutex_t lock;
    /* under lock: */
    size_t pos;    /* in NODE: the next model's length varint */
    uint32_t next; /* the next model to hand over */
    uint32_t crc;  /* of NODE[0, pos) */
    bool failed;   /* a model or the stream table failed: nothing more is handed over */
    uint32_t done; /* models decoded and validated */
    unsigned active; /* calls of next decoding now (they share the CPUs) */
    unsigned active_random; /* calls of vx_svo_reader_model decoding now (the CPUs too, not the pass's state) */
    bool finished;   /* finish succeeded on this pass: a rewind may start the next */
    uint32_t pass;   /* 0, then 1, 2 ... after each vx_svo_reader_rewind */
    bool indexed;    /* a pass that finish accepted walked the stream table: stream_at/len are
                        every model's (vx_svo_reader_model) */
    /* per model: its stream's first byte in the file and its length, as the
     * first pass found them (random access needs the table's lengths, which
     * only a walk from model 0 gives) */
    uint64_t* stream_at;
    uint64_t* stream_len;
};

static void reader_free(vx_svo_model_reader* r) {
    if (!r) return;
    const vx_allocator* A = r->A;
    if (r->src.fd >= 0) close(r->src.fd);
    vx_svo_scene_free(&r->s);
    vx_free(A, r->chunked);
    vx_free(A, r->ext);
    vx_free(A, r->stream_at);
    vx_free(A, r->stream_len);
    vx_free(A, r->path);
    pthread_mutex_destroy(&r->lock);
    vx_free(A, r);
}

/* The header and table (from the file's first TABLE_MAX bytes), then every
 * known section but NODE into one buffer (*bytes, the caller frees it; the
 * sections are disjoint parts of the file, so it is at most the file). */
static vx_result reader_sections(vx_svo_model_reader* r, uint32_t* version, uint32_t* count, sec** secs, uint8_t** bytes, vx_error* err) {
    const vx_allocator* A = r->A;
    const fsrc* f = &r->src;
    size_t head_n = f->size < TABLE_MAX ? (size_t)f->size : (size_t)TABLE_MAX;
    uint8_t* head = (uint8_t*)vx_alloc(A, head_n ? head_n : 1);
    if (!head) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo: out of memory");
    vx_result res = fsrc_read(f, 0, head, head_n, err);
    if (res == VX_OK) res = load_table(head, head_n, f->size, f, A, version, count, secs, err);
    if (res != VX_OK || head_n == f->size) { /* a small file: every section is in head (their p set) */
        if (res == VX_OK) *bytes = head;
        else vx_free(A, head);
        return res;
    }
    vx_free(A, head);
    uint64_t total = 0;
    for (uint32_t i = 0; i < *count; i++) {
        int ti = tag_index((*secs)[i].tag);
        if (ti >= 0 && ti != S_NODE) total += (*secs)[i].size; /* disjoint parts of the file: no overflow */
    }
    uint8_t* b = (uint8_t*)vx_alloc(A, total ? (size_t)total : 1);
    if (!b) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo: out of memory for %llu bytes of sections", (unsigned long long)total);
    uint64_t at = 0;
    for (uint32_t i = 0; i < *count; i++) {
        sec* e = &(*secs)[i];
        int ti = tag_index(e->tag);
        if (ti < 0 || ti == S_NODE) continue;
        e->p = b + at;
        if ((res = fsrc_read(f, e->offset, b + at, (size_t)e->size, err)) != VX_OK) {
            vx_free(A, b);
            return res;
        }
        at += e->size;
    }
    *bytes = b;
    return VX_OK;
}

vx_result vx_svo_reader_open(const vx_svo_read_desc* desc, const char* path, vx_svo_model_reader** out, vx_error* err) {
    if (!path || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo: null argument");
    *out = NULL;
    vx_svo_read_desc rdd;
    if (desc) rdd = *desc;
    else memset(&rdd, 0, sizeof rdd);
    vx_svo_model_reader* r = (vx_svo_model_reader*)vx_calloc(rdd.alloc, 1, sizeof *r);
    size_t plen = strlen(path);
    if (!r) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo: out of memory");
    if (rdd.alloc) r->alloc = *rdd.alloc, r->A = &r->alloc;
    const vx_allocator* A = r->A;
    r->src.fd = -1;
    pthread_mutex_init(&r->lock, NULL);
    vx_svo_scene_init(&r->s, A);
    r->skip_crc = rdd.skip_checksums;
    r->cpus = vx__svo_cpus(rdd.threads);
    r->testing = rdd.testing;
    sec* secs = NULL;
    uint8_t* bytes = NULL;
    uint32_t version, count;
    vx_result res;
    if (!(r->path = (char*)vx_alloc(A, plen + 1))) {
        reader_free(r);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo: out of memory");
    }
    memcpy(r->path, path, plen + 1);
    if ((res = open_file(&rdd, path, rdd.max_file_bytes ? rdd.max_file_bytes : UINT64_MAX, &r->src, err)) != VX_OK) {
        r->src.fd = -1;
        reader_free(r);
        return res;
    }
#ifdef POSIX_FADV_SEQUENTIAL
    (void)posix_fadvise(r->src.fd, 0, 0, POSIX_FADV_SEQUENTIAL); /* read once, front to back: read-ahead (advice only) */
#endif
    const sec* known[S_COUNT] = {0};
    if ((res = reader_sections(r, &version, &count, &secs, &bytes, err)) != VX_OK ||
        (res = check_sections(secs, count, version, r->skip_crc, true, known, err)) != VX_OK)
        goto fail;
    r->bounds_form = BOUNDS_COMPUTED;
    if ((res = read_scne(known, version, A, &r->s, &r->bounds_form, &r->chunked, err)) != VX_OK) goto fail;
    if (r->s.model_count && (!(r->ext = (vx__svo_extent*)vx_calloc(A, r->s.model_count, sizeof *r->ext)) ||
                             !(r->stream_at = (uint64_t*)vx_calloc(A, r->s.model_count, sizeof *r->stream_at)) ||
                             !(r->stream_len = (uint64_t*)vx_calloc(A, r->s.model_count, sizeof *r->stream_len)))) {
        res = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo: out of memory");
        goto fail;
    }
    r->node_n = (size_t)known[S_NODE]->size;
    r->node_base = known[S_NODE]->offset;
    r->node_crc = known[S_NODE]->crc;
    if (!r->s.model_count && r->node_n) {
        res = vx_fail(err, VX_ERR_BAD_FORMAT, r->node_base, "svo: section NODE has %zu bytes but there are no models", r->node_n);
        goto fail;
    }
    if ((known[S_PALT] && (res = read_palt(known[S_PALT], &r->s, err)) != VX_OK) ||
        (known[S_MATL] && (res = read_matl(known[S_MATL], A, &r->s, err)) != VX_OK) ||
        (known[S_LGHT] && (res = read_lght(known[S_LGHT], A, &r->s, err)) != VX_OK) ||
        (known[S_FRMS] && (res = read_frms(known[S_FRMS], &r->s, err)) != VX_OK))
        goto fail;
    /* the scene's own rules now (the models' as they are read) */
    if ((res = vx__svo_validate_scene_opt(&r->s, NULL, 1, &r->testing, false, NULL, err)) != VX_OK) {
        if (res == VX_ERR_INVALID_ARG) res = VX_ERR_BAD_FORMAT;
        if (err) err->code = res;
        vx_error_prefix(err, "svo: structure");
        goto fail;
    }
    vx_free(A, secs);
    vx_free(A, bytes); /* the scene graph holds copies */
    *out = r;
    return VX_OK;
fail:
    vx_free(A, secs);
    vx_free(A, bytes);
    vx_error_prefix(err, path);
    reader_free(r);
    return res;
}

const vx_svo_scene* vx_svo_reader_scene(const vx_svo_model_reader* r) { return r ? &r->s : NULL; }

/* Under the lock: the next model's stream from the stream table, read into
 * *stream (allocated with the reader's allocator; the caller frees it). */
static vx_result reader_take(vx_svo_model_reader* r, uint32_t* mi, uint8_t** stream, size_t* len, uint64_t* where, vx_error* err) {
    size_t n = r->node_n, pos = r->pos, at = pos;
    uint64_t base = r->node_base, v = 0;
    uint8_t var[10];
    size_t var_n = n - pos < sizeof var ? n - pos : sizeof var;
    *mi = r->next;
    *stream = NULL;
    char what[48];
    snprintf(what, sizeof what, "model %u's stream", *mi);
    vx_result res = fsrc_read(&r->src, base + pos, var, var_n, err);
    if (res != VX_OK) {
        vx_error_prefix(err, what);
        return res;
    }
    for (unsigned shift = 0, k = 0;; shift += 7) {
        if (k >= var_n)
            return vx_fail(err, VX_ERR_TRUNCATED, base + at, "svo: section NODE at byte %llu: model %u: stream length cut off",
                           (unsigned long long)(base + at), *mi);
        uint8_t c = var[k++];
        pos++;
        if (shift > 63 || (shift == 63 && (c & 0x7Eu)))
            return vx_fail(err, VX_ERR_BAD_FORMAT, base + at, "svo: section NODE at byte %llu: model %u: stream length overflows",
                           (unsigned long long)(base + at), *mi);
        v |= (uint64_t)(c & 0x7Fu) << shift;
        if (!(c & 0x80u)) break;
    }
    if (v > n - pos)
        return vx_fail(err, VX_ERR_TRUNCATED, base + at, "svo: section NODE at byte %llu: model %u: stream of %llu bytes, %zu left",
                       (unsigned long long)(base + at), *mi, (unsigned long long)v, n - pos);
    uint8_t* b = (uint8_t*)vx_alloc(r->A, v ? (size_t)v : 1);
    if (!b)
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo: model %u: out of memory for its stream of %llu bytes", *mi,
                       (unsigned long long)v);
    vx__svo_advise_huge(b, (size_t)v);
    if ((res = fsrc_read(&r->src, base + pos, b, (size_t)v, err)) != VX_OK) {
        vx_free(r->A, b);
        vx_error_prefix(err, what);
        return res;
    }
    if (!r->skip_crc) r->crc = vx__svo_crc32(vx__svo_crc32(r->crc, var, pos - at), b, (size_t)v);
    *stream = b;
    *len = (size_t)v;
    *where = base + pos;
    if (!r->pass) r->stream_at[*mi] = base + pos, r->stream_len[*mi] = v; /* later passes find the same (or fail) */
    r->pos = pos + (size_t)v;
    r->next++;
    return VX_OK;
}

/* Decodes and validates model mi's stream (len bytes, its first at byte
 * stream_at of the file) into *out, on the reader's CPUs shared by `share`
 * calls at once; its check set, and with `again` (a later pass, a model
 * read again) compared with the one the first pass left in the graph (`when`
 * says in the error when the file changed). On failure *out holds nothing
 * and the error names the file. */
static vx_result reader_decode(vx_svo_model_reader* r, uint32_t mi, const uint8_t* stream, size_t len, uint64_t stream_at,
                               unsigned share, bool again, const char* when, vx_svo_model* out, vx_error* err) {
    vx_result res;
    /* the calls decoding at once share the CPUs: each model its part of them */
    unsigned threads = r->cpus / share ? r->cpus / share : 1;
    vx_svo_model m = r->s.models[mi];
    memset(&m.check, 0, sizeof m.check);
    vx__svo_extent ext = {0}, tree = {0};
    uint8_t rebuilt = 0;
    res = vx__svo_unpack_one(stream, len, stream_at, &m, mi, r->chunked ? r->chunked[mi] : 0, r->A, threads, &r->testing,
                             &tree, &rebuilt, err);
    if (res == VX_OK) {
        res = rebuilt == VX__SVO_SKIP_REBUILT ? vx__svo_check_rebuilt(&m, &tree, &ext, err)
                                              : vx__svo_analyze_mt(&m, &ext, false, threads, err);
        if (res != VX_OK) {
            char p[32];
            snprintf(p, sizeof p, "model %u", mi);
            if (res == VX_ERR_INVALID_ARG) res = VX_ERR_BAD_FORMAT;
            if (err) err->code = res;
            vx_error_prefix(err, p);
            vx_error_prefix(err, "svo: structure");
        }
    }
    if (res == VX_OK) {
        m.check.digest = vx_svo_model_digest(&m);
        memcpy(m.check.min, ext.min, sizeof ext.min);
        memcpy(m.check.max, ext.max, sizeof ext.max);
        /* a later pass (vx_svo_reader_rewind) hands over the models the first
         * pass validated, or fails: a consumer that builds from both passes
         * (the compact layout's second build) must not mix two files */
        const vx_svo_model_check* was = &r->s.models[mi].check;
        if (again && (was->digest != m.check.digest || memcmp(was->min, m.check.min, sizeof was->min) ||
                        memcmp(was->max, m.check.max, sizeof was->max))) {
            res = vx_fail(err, VX_ERR_BAD_FORMAT, stream_at,
                          "svo: model %u is not the model the first pass read (digest %08x, was %08x): the file "
                          "changed %s",
                          mi, (unsigned)m.check.digest, (unsigned)was->digest, when);
        }
    }
    if (res == VX_OK) {
        if (!again) {
            r->s.models[mi].check = m.check; /* the graph's copy: its cells' box, for the caller */
            r->ext[mi] = ext;
        }
    } else {
        vx_svo_model_free(r->A, &m);
        vx_error_prefix(err, r->path);
    }
    if (res == VX_OK) *out = m;
    return res;
}

vx_result vx_svo_reader_next(vx_svo_model_reader* r, uint32_t* index, vx_svo_model* out, vx_error* err) {
    if (!r || !index || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo: null argument");
    memset(out, 0, sizeof *out);
    uint32_t mi = 0;
    uint8_t* stream = NULL;
    size_t len = 0;
    uint64_t stream_at = 0; /* its byte in the file */
    vx_result res = VX_OK;
    unsigned share;
    pthread_mutex_lock(&r->lock);
    if (r->failed) {
        pthread_mutex_unlock(&r->lock);
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "%s: the model reader stopped at an earlier error", r->path);
    }
    if (r->next >= r->s.model_count) {
        *index = r->s.model_count;
        pthread_mutex_unlock(&r->lock);
        return VX_OK;
    }
    if ((res = reader_take(r, &mi, &stream, &len, &stream_at, err)) != VX_OK) {
        r->failed = true;
        pthread_mutex_unlock(&r->lock);
        vx_error_prefix(err, r->path);
        return res;
    }
    share = ++r->active + r->active_random;
    bool again = r->pass != 0;
    pthread_mutex_unlock(&r->lock);
    vx_svo_model m;
    res = reader_decode(r, mi, stream, len, stream_at, share, again, "between the passes", &m, err);
    vx_free(r->A, stream);
    pthread_mutex_lock(&r->lock);
    r->active--;
    if (res == VX_OK) r->done++;
    else r->failed = true;
    pthread_mutex_unlock(&r->lock);
    if (res != VX_OK) return res;
    *index = mi;
    *out = m;
    return VX_OK;
}

vx_result vx_svo_reader_model(vx_svo_model_reader* r, uint32_t index, vx_svo_model* out, vx_error* err) {
    if (!r || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo: null argument");
    memset(out, 0, sizeof *out);
    pthread_mutex_lock(&r->lock);
    bool failed = r->failed, indexed = r->indexed;
    unsigned share = 0;
    if (!failed && indexed && index < r->s.model_count) share = r->active + ++r->active_random;
    pthread_mutex_unlock(&r->lock);
    if (failed) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "%s: the model reader stopped at an earlier error", r->path);
    if (!indexed)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                       "%s: model %u: the model reader reads a model again only after a pass that finish accepted", r->path,
                       index);
    if (index >= r->s.model_count)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "%s: no model %u (the file has %u)", r->path, index,
                       r->s.model_count);
    uint64_t at = r->stream_at[index], len = r->stream_len[index]; /* set by the first pass, read-only since */
    vx_svo_model m;
    vx_result res = VX_OK;
    uint8_t* stream = (uint8_t*)vx_alloc(r->A, len ? (size_t)len : 1);
    if (!stream)
        res = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo: model %u: out of memory for its stream of %llu bytes", index,
                      (unsigned long long)len);
    else if ((res = fsrc_read(&r->src, at, stream, (size_t)len, err)) != VX_OK) {
        char what[48];
        snprintf(what, sizeof what, "model %u's stream", index);
        vx_error_prefix(err, what);
    }
    if (res != VX_OK) vx_error_prefix(err, r->path);
    else res = reader_decode(r, index, stream, (size_t)len, at, share, true, "since that pass", &m, err);
    vx_free(r->A, stream);
    pthread_mutex_lock(&r->lock);
    r->active_random--;
    pthread_mutex_unlock(&r->lock);
    if (res != VX_OK) return res;
    *out = m;
    return VX_OK;
}

vx_result vx_svo_reader_finish(vx_svo_model_reader* r, vx_error* err) {
    if (!r) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo: null argument");
    pthread_mutex_lock(&r->lock);
    bool failed = r->failed, all = r->done == r->s.model_count && r->active == 0;
    size_t pos = r->pos;
    uint32_t crc = r->crc;
    pthread_mutex_unlock(&r->lock);
    vx_result res = VX_OK;
    if (failed) res = vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "the model reader stopped at an earlier error");
    else if (!all)
        res = vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "%u of %u models read: finish after the last", r->done, r->s.model_count);
    else if (pos != r->node_n)
        res = vx_fail(err, VX_ERR_BAD_FORMAT, r->node_base + pos, "svo: section NODE: %zu bytes after the last model's stream",
                      r->node_n - pos);
    else if (!r->skip_crc && crc != r->node_crc)
        res = vx_fail(err, VX_ERR_BAD_FORMAT, r->node_base, "svo: section NODE at byte %llu: CRC-32 is 0x%08x, the table says 0x%08x",
                      (unsigned long long)r->node_base, crc, r->node_crc);
    if (res != VX_OK) {
        vx_error_prefix(err, r->path);
        return res;
    }
    if (r->bounds_form == BOUNDS_COMPUTED) vx__svo_scene_bounds_ext(&r->s, r->ext, r->s.bounds_min, r->s.bounds_max);
    pthread_mutex_lock(&r->lock);
    r->finished = true;
    r->indexed = true;
    pthread_mutex_unlock(&r->lock);
    return VX_OK;
}

vx_result vx_svo_reader_rewind(vx_svo_model_reader* r, vx_error* err) {
    if (!r) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo: null argument");
    pthread_mutex_lock(&r->lock);
    bool ok = r->finished && !r->failed && r->active == 0;
    if (ok) {
        /* the stream table from its start; the NODE CRC summed again */
        r->pos = 0, r->next = 0, r->crc = 0, r->done = 0;
        r->finished = false;
        r->pass++;
    }
    pthread_mutex_unlock(&r->lock);
    if (!ok)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "%s: the model reader rewinds only after a pass that finish accepted",
                       r->path);
    return VX_OK;
}

vx_result vx_svo_reader_copy_graph(const vx_svo_model_reader* r, const vx_allocator* alloc, vx_svo_scene* out, vx_error* err) {
    if (!r || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo: null argument");
    const vx_svo_scene* g = &r->s;
    vx_svo_scene s = *g;
    s.alloc = alloc;
    s.models = NULL, s.instances = NULL, s.layers = NULL, s.materials = NULL, s.lights = NULL, s.frame_instances = NULL;
    s.model_count = s.instance_count = s.layer_count = s.material_count = s.light_count = 0;
    size_t frames = g->frame_instances && g->frame_count > 1 ? (size_t)(g->frame_count - 1) * g->instance_count : 0;
    bool ok = (!g->model_count || (s.models = (vx_svo_model*)vx_alloc(alloc, g->model_count * sizeof *s.models))) &&
              (!g->instance_count || (s.instances = (vx_svo_instance*)vx_alloc(alloc, g->instance_count * sizeof *s.instances))) &&
              (!g->layer_count || (s.layers = (vx_svo_layer*)vx_alloc(alloc, g->layer_count * sizeof *s.layers))) &&
              (!g->material_count || (s.materials = (vx_svo_material*)vx_calloc(alloc, g->material_count, sizeof *s.materials))) &&
              (!g->light_count || (s.lights = (vx_light*)vx_alloc(alloc, g->light_count * sizeof *s.lights))) &&
              (!frames || (s.frame_instances = (vx_svo_instance*)vx_alloc(alloc, frames * sizeof *s.frame_instances)));
    if (ok) {
        s.model_count = g->model_count, s.instance_count = g->instance_count, s.layer_count = g->layer_count;
        s.material_count = g->material_count, s.light_count = g->light_count;
        if (s.models) memcpy(s.models, g->models, g->model_count * sizeof *s.models); /* the graph's models hold no arrays */
        if (s.instances) memcpy(s.instances, g->instances, g->instance_count * sizeof *s.instances);
        if (s.layers) memcpy(s.layers, g->layers, g->layer_count * sizeof *s.layers);
        if (s.lights) memcpy(s.lights, g->lights, g->light_count * sizeof *s.lights);
        if (frames) memcpy(s.frame_instances, g->frame_instances, frames * sizeof *s.frame_instances);
        for (uint32_t i = 0; ok && i < g->material_count; i++) {
            s.materials[i] = g->materials[i];
            s.materials[i].dict = NULL;
            if (g->materials[i].dict_size && (ok = (s.materials[i].dict = (char*)vx_alloc(alloc, g->materials[i].dict_size)) != NULL))
                memcpy(s.materials[i].dict, g->materials[i].dict, g->materials[i].dict_size);
        }
    }
    if (!ok) {
        vx_svo_scene_free(&s);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo: out of memory for the scene graph");
    }
    *out = s;
    return VX_OK;
}

vx_result vx_svo_reader_update_bounds(vx_svo_model_reader* r, vx_svo_scene* s, vx_error* err) {
    if (!r || !s) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo: null argument");
    /* the extents are the first pass's, written before its finish set indexed and never again (a later pass
     * compares), so they are read here without the lock, beside a later pass too */
    pthread_mutex_lock(&r->lock);
    bool indexed = r->indexed;
    pthread_mutex_unlock(&r->lock);
    if (!indexed)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "%s: the models' boxes are known after a pass that finish accepted",
                       r->path);
    if (s->model_count != r->s.model_count)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "%s: the scene has %u models, the file %u", r->path,
                       s->model_count, r->s.model_count);
    vx__svo_scene_bounds_ext(s, r->ext, s->bounds_min, s->bounds_max);
    return VX_OK;
}

void vx_svo_reader_close(vx_svo_model_reader* r) { reader_free(r); }

/* ---- writing ------------------------------------------------------------------------------ */

static bool f64s_int32(const double* v, int n, int32_t* out) {
    for (int i = 0; i < n; i++)
        if (!int_translation(v[i], &out[i])) return false;
    return true;
}

/* A transform's payload after the head that holds its kind (xform_kind). */
static void buf_xform(vx_buf* b, const double* x, int kind, const uint8_t* pay, size_t pay_len, const int32_t t[3], int32_t prev[3]) {
    if (kind == XF_F64) {
        for (int k = 0; k < 12; k++) vx_buf_f64le(b, x[k]);
        return;
    }
    vx_buf_append(b, pay, pay_len);
    for (int k = 0; k < 3; k++) {
        buf_var(b, zig64((int64_t)t[k] - prev[k]));
        prev[k] = t[k];
    }
}

/* chunked: per model, whether its NODE stream is in the chunked form (1:
 * version 3's DEFLATE chunks, 2: version 4's tagged chunks; NULL: none). */
static void write_scne(vx_buf* b, const vx_svo_scene* s, const vx__svo_extent* ext, const uint8_t* chunked) {
    /* (a model head with MODEL_CHUNKED for 1 and 2, MODEL_SPLIT for 3) */
    double bmin[3], bmax[3];
    vx__svo_scene_bounds_ext(s, ext, bmin, bmax);
    int32_t bi[6];
    int bounds_form = BOUNDS_F64;
    if (memcmp(bmin, s->bounds_min, sizeof bmin) == 0 && memcmp(bmax, s->bounds_max, sizeof bmax) == 0)
        bounds_form = BOUNDS_COMPUTED;
    else if (f64s_int32(s->bounds_min, 3, bi) && f64s_int32(s->bounds_max, 3, bi + 3))
        bounds_form = BOUNDS_INT;
    bool world = memcmp(s->world_from_grid, IDENTITY12, sizeof IDENTITY12) != 0;
    vx_buf_u8(b, (uint8_t)((world ? SCNE_WORLD : 0) | bounds_form << SCNE_BOUNDS_SHIFT));
    if (world)
        for (int i = 0; i < 12; i++) vx_buf_f64le(b, s->world_from_grid[i]);
    if (bounds_form == BOUNDS_F64) {
        for (int i = 0; i < 3; i++) vx_buf_f64le(b, s->bounds_min[i]);
        for (int i = 0; i < 3; i++) vx_buf_f64le(b, s->bounds_max[i]);
    } else if (bounds_form == BOUNDS_INT) {
        for (int i = 0; i < 6; i++) buf_var(b, zig32(bi[i]));
    }
    buf_var(b, s->model_count);
    buf_var(b, s->instance_count);
    buf_var(b, s->layer_count);
    for (uint32_t i = 0; i < s->model_count; i++) {
        const vx_svo_model* m = &s->models[i];
        bool same = i > 0 && memcmp(m->size, m[-1].size, sizeof m->size) == 0;
        buf_var(b, m->attrs | (same ? MODEL_SAME_SIZE : 0u) | (chunked && (chunked[i] == 1 || chunked[i] == 2) ? MODEL_CHUNKED : 0u) |
                       (chunked && chunked[i] == 2 ? MODEL_TAGGED : 0u) | (chunked && chunked[i] == 3 ? MODEL_SPLIT : 0u));
        if (!same)
            for (int k = 0; k < 3; k++) buf_var(b, m->size[k]);
        buf_var(b, m->node_count);
        /* the writer puts the root last, so the usual code is one byte */
        buf_var(b, m->root == VX_SVO_ROOT_EMPTY  ? ROOT_CODE_EMPTY
                   : m->root == VX_SVO_ROOT_LEAF ? ROOT_CODE_LEAF
                                                 : ROOT_CODE_BACK + (uint64_t)(m->node_count - 1 - m->root));
        buf_var(b, m->voxel_count);
        if (m->attrs) {
            buf_var(b, m->attr_count);
            buf_var(b, m->root_attr);
        }
    }
    int32_t prev[3] = {0, 0, 0};
    for (uint32_t i = 0; i < s->instance_count; i++) {
        const vx_svo_instance* in = &s->instances[i];
        uint8_t pay[3];
        size_t pay_len = 0;
        int32_t t[3];
        int kind = xform_kind(in->xform, pay, &pay_len, t);
        bool named = in->name[0] != 0;
        buf_var(b, (uint64_t)in->flags << 3 | (named ? INST_NAMED : 0u) | (uint64_t)kind);
        buf_var(b, in->model);
        buf_var(b, in->layer == UINT32_MAX ? 0 : (uint64_t)in->layer + 1);
        buf_xform(b, in->xform, kind, pay, pay_len, t, prev);
        if (named) buf_name(b, in->name);
    }
    for (uint32_t i = 0; i < s->layer_count; i++) {
        buf_name(b, s->layers[i].name);
        buf_var(b, s->layers[i].flags);
        buf_var(b, s->layers[i].rgba);
    }
}

/* Only the entries that some palette record refers to are stored. */
static void palette_bits(const vx_svo_model* m, uint8_t bits[32]) {
    if (!(m->attrs & VX_ATTR_PALETTE)) return;
    for (uint32_t k = 0; k < m->attr_count; k++) bits[m->palette[k] >> 3] |= (uint8_t)(1u << (m->palette[k] & 7));
}

/* The models' streams when they were coded elsewhere (vx_svo_write_file_coded). */
typedef struct coded_src {
    const vx_svo_model_coded* info;
    const vx_svo_stream_source* src;
    bool read_failed;
} coded_src;

static void write_palt(vx_buf* b, const vx_svo_scene* s, const coded_src* cs) {
    uint8_t bits[32] = {0};
    for (uint32_t i = 0; i < s->model_count; i++) {
        if (!cs) palette_bits(&s->models[i], bits);
        else if (s->models[i].attrs & VX_ATTR_PALETTE)
            for (int k = 0; k < 32; k++) bits[k] |= cs->info[i].palette_used[k];
    }
    bool rgb = true;
    for (int i = 0; i < 256; i++)
        if ((bits[i >> 3] >> (i & 7) & 1u) && (s->palette[i] >> 24) != 0xFFu) rgb = false;
    vx_buf_u8(b, rgb ? PALT_RGB : 0);
    vx_buf_append(b, bits, 32);
    for (int i = 0; i < 256; i++) {
        if (!(bits[i >> 3] >> (i & 7) & 1u)) continue;
        uint8_t c[4] = {(uint8_t)s->palette[i], (uint8_t)(s->palette[i] >> 8), (uint8_t)(s->palette[i] >> 16),
                        (uint8_t)(s->palette[i] >> 24)};
        vx_buf_append(b, c, rgb ? 3 : 4);
    }
}

static uint64_t dict_hash(const vx_svo_material* m) {
    uint64_t h = 0xcbf29ce484222325ull ^ m->dict_size;
    for (uint32_t i = 0; i < m->dict_size; i++) h = (h ^ (uint8_t)m->dict[i]) * 0x100000001b3ull;
    return h;
}
static bool dict_equal(const vx_svo_material* a, const vx_svo_material* b) {
    return a->dict_size == b->dict_size && (a->dict_size == 0 || memcmp(a->dict, b->dict, a->dict_size) == 0);
}

/* Identical dictionaries are stored once, in order of first use; a hash
 * table keeps this linear for scenes with many materials. */
static bool write_matl(vx_buf* b, const vx_svo_scene* s, const vx_allocator* A) {
    uint32_t n = s->material_count;
    size_t cap = 16;
    while (cap < 2 * (size_t)n) cap *= 2;
    uint32_t* slot = (uint32_t*)vx_calloc(A, cap, sizeof *slot); /* first material with that dictionary, + 1 */
    uint32_t* dix = (uint32_t*)vx_calloc(A, n ? n : 1, sizeof *dix);
    uint32_t* first = (uint32_t*)vx_calloc(A, n ? n : 1, sizeof *first);
    bool ok = slot && dix && first;
    uint32_t nd = 0;
    for (uint32_t i = 0; ok && i < n; i++) {
        const vx_svo_material* m = &s->materials[i];
        size_t h = (size_t)dict_hash(m) & (cap - 1);
        while (slot[h] && !dict_equal(&s->materials[slot[h] - 1], m)) h = (h + 1) & (cap - 1);
        if (!slot[h]) {
            slot[h] = i + 1;
            dix[i] = nd;
            first[nd++] = i;
        } else {
            dix[i] = dix[slot[h] - 1];
        }
    }
    if (ok) {
        buf_var(b, nd);
        for (uint32_t k = 0; k < nd; k++) {
            const vx_svo_material* m = &s->materials[first[k]];
            buf_var(b, m->dict_size);
            if (m->dict_size) vx_buf_append(b, m->dict, m->dict_size);
        }
        buf_var(b, n);
        for (uint32_t i = 0; i < n; i++) {
            buf_var(b, s->materials[i].id);
            buf_var(b, dix[i]);
        }
    }
    vx_free(A, slot);
    vx_free(A, dix);
    vx_free(A, first);
    return ok;
}

static void write_lght(vx_buf* b, const vx_svo_scene* s) {
    const vx_sky* k = &s->sky;
    buf_var(b, (uint64_t)k->type);
    if (k->type == VX_SKY_CONSTANT || k->type == VX_SKY_GRADIENT) {
        for (int i = 0; i < 3; i++) vx_buf_f64le(b, k->color[i]);
        if (k->type == VX_SKY_GRADIENT) {
            for (int i = 0; i < 3; i++) vx_buf_f64le(b, k->horizon[i]);
            for (int i = 0; i < 3; i++) vx_buf_f64le(b, k->ground[i]);
        }
    } else if (k->type == VX_SKY_ENVMAP) {
        vx_buf_f64le(b, k->intensity);
        vx_buf_f64le(b, k->rotation);
        size_t len = strnlen(k->path, sizeof k->path); /* validated: 1..255 */
        buf_var(b, len);
        vx_buf_append(b, k->path, len);
    }
    buf_var(b, s->light_count);
    for (uint32_t i = 0; i < s->light_count; i++) {
        vx_light l = s->lights[i];
        uint64_t mask = 0;
        for (int g = 0; g < LGHT_GROUPS; g++) {
            int gn;
            const double* v = light_group(&l, g, &gn);
            if (!all_pos_zero(v, gn)) mask |= 1u << g;
        }
        buf_var(b, (uint64_t)l.type | mask << LGHT_TYPE_BITS);
        for (int g = 0; g < LGHT_GROUPS; g++) {
            int gn;
            double* v = light_group(&l, g, &gn);
            if (mask >> g & 1u)
                for (int j = 0; j < gn; j++) vx_buf_f64le(b, v[j]);
        }
    }
}

static bool instance_state_equal(const vx_svo_instance* a, const vx_svo_instance* b) {
    return a->model == b->model && a->flags == b->flags && memcmp(a->xform, b->xform, sizeof a->xform) == 0;
}

/* Frames 1.. as changes against the frame before (frame 0 is SCNE's
 * instances): an animation where little moves costs little. */
static void write_frms(vx_buf* b, const vx_svo_scene* s) {
    uint32_t I = s->instance_count;
    buf_var(b, s->frame_count);
    vx_buf_f64le(b, s->frame_rate);
    int32_t prev[3] = {0, 0, 0};
    for (uint32_t f = 1; f < s->frame_count; f++) {
        const vx_svo_instance* cur = vx_svo_scene_frame_instances(s, f);
        const vx_svo_instance* before = vx_svo_scene_frame_instances(s, f - 1);
        uint32_t n = 0;
        for (uint32_t i = 0; i < I; i++) n += !instance_state_equal(&cur[i], &before[i]);
        buf_var(b, n);
        uint32_t last = 0;
        bool first = true;
        for (uint32_t i = 0; i < I; i++) {
            if (instance_state_equal(&cur[i], &before[i])) continue;
            uint8_t pay[3];
            size_t pay_len = 0;
            int32_t t[3];
            int kind = xform_kind(cur[i].xform, pay, &pay_len, t);
            buf_var(b, first ? i : i - last - 1);
            buf_var(b, (uint64_t)cur[i].flags << 2 | (uint64_t)kind);
            buf_var(b, cur[i].model);
            buf_xform(b, cur[i].xform, kind, pay, pay_len, t, prev);
            last = i;
            first = false;
        }
    }
}

/* What a writer needs before producing sections: the validated scene's
 * model extents (for SCNE's bounds) and the sections to write, in order. */
typedef struct wplan {
    vx__svo_extent* ext;
    uint8_t* chunked; /* per model: stored in the chunked form, 1 DEFLATE, 2 tagged; 3 the split form (NULL: none is) */
    uint32_t split_min; /* vx__svo_split_min: VX__SPLIT_WORDS, 0 with vx_write_desc.svo_range_coded */
    uint8_t* trusted;   /* per model: its check current (vx__svo_trusted_models), or NULL */
    uint16_t version;
    unsigned threads;   /* the caller's limit (vx_write_desc.threads) */
    uint32_t chunk_min; /* vx_write_desc.svo_chunk_words */
    int chunk_mode;     /* vx_write_desc.svo_chunk_stored / svo_chunk_fast: VX__CHUNK_* */
    const vx_svo_testing* t; /* vx_write_desc.testing (NULL: none) */
    int order[S_COUNT], ns;
    uint64_t sizes[S_COUNT];
    uint32_t flags[S_COUNT], crcs[S_COUNT];
} wplan;

static void plan_free(const vx_allocator* alloc, wplan* w) {
    vx_free(alloc, w->ext);
    vx_free(alloc, w->chunked);
    vx_free(alloc, w->trusted);
    w->ext = NULL;
    w->chunked = NULL;
    w->trusted = NULL;
}

static vx_result plan_write(const vx_svo_scene* s, const vx_write_desc* desc, const coded_src* cs, wplan* w, vx_error* err) {
    const vx_allocator* alloc = desc ? desc->alloc : NULL;
    memset(w, 0, sizeof *w);
    w->threads = desc ? desc->threads : 0;
    w->chunk_min = desc ? desc->svo_chunk_words : 0;
    w->chunk_mode = vx__svo_chunk_mode(desc);
    w->split_min = vx__svo_split_min(desc);
    w->t = vx__svo_write_testing(desc);
    /* validation analyses every model; the extents it finds give the bounds
     * written to SCNE without a second pass over the trees (models coded
     * elsewhere bring theirs) */
    w->ext = s->model_count ? (vx__svo_extent*)vx_calloc(alloc, s->model_count, sizeof *w->ext) : NULL;
    if (s->model_count && !w->ext) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo write: out of memory");
    /* chunked models that the reader validated and nobody changed since (their
     * check's digest current) are not validated again (svo.h vx_svo_model.check) */
    uint8_t* skip = !cs && s->model_count ? (uint8_t*)vx_calloc(alloc, s->model_count, 1) : NULL;
    if (skip) vx__svo_trusted_models(s, alloc, w->chunk_min, w->threads, w->t, skip, w->ext);
    vx_result r = vx__svo_unchecked(w->t) && !cs ? VX_OK : vx__svo_validate_scene_opt(s, w->ext, w->threads, w->t, !cs, skip, err);
    w->trusted = skip; /* the coder takes those models' checks too (freed with the plan) */
    for (uint32_t i = 0; cs && r == VX_OK && i < s->model_count; i++) {
        const vx_svo_model_coded* c = &cs->info[i];
        if (c->cells != s->models[i].voxel_count || c->stream_size == 0)
            r = vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "model %u: coded with %llu cells in %llu bytes, the model declares %llu cells",
                        i, (unsigned long long)c->cells, (unsigned long long)c->stream_size, (unsigned long long)s->models[i].voxel_count);
        w->ext[i].cells = c->cells;
        memcpy(w->ext[i].min, c->min, sizeof c->min);
        memcpy(w->ext[i].max, c->max, sizeof c->max);
    }
    if (r != VX_OK) {
        vx_free(alloc, w->ext);
        vx_free(alloc, w->trusted);
        w->ext = NULL;
        w->trusted = NULL;
        vx_error_prefix(err, "svo write");
        return r;
    }
    if (vx__svo_unchecked(w->t) && w->ext) {
        vx_free(alloc, w->ext); /* tests writing deliberately broken models: analyse lazily */
        w->ext = NULL;
    }
    uint32_t used = 0;
    for (uint32_t i = 0; i < s->model_count; i++) used |= s->models[i].attrs;
    w->order[w->ns++] = S_SCNE;
    w->order[w->ns++] = S_NODE;
    if (used & VX_ATTR_PALETTE) w->order[w->ns++] = S_PALT;
    if (s->material_count) w->order[w->ns++] = S_MATL;
    if (s->light_count || s->sky.type != VX_SKY_DEFAULT) w->order[w->ns++] = S_LGHT;
    if (vx_svo_scene_frames(s) > 1) w->order[w->ns++] = S_FRMS;
    for (int si = 0; si < w->ns; si++) w->flags[si] = SEC_REQUIRED;
    /* the chunked form of a large model needs version 3, its zstd chunks
     * version 4; files without one keep the bytes of versions 1 and 2 */
    w->version = file_version(w->order, w->ns);
    for (uint32_t i = 0; i < s->model_count; i++) {
        bool ch = cs ? cs->info[i].chunked : vx__svo_model_chunked(&s->models[i], w->chunk_min);
        bool sp = !ch && (cs ? cs->info[i].split : vx__svo_model_split(&s->models[i], w->chunk_min, w->split_min));
        if (!ch && !sp) continue;
        if (!w->chunked && !(w->chunked = (uint8_t*)vx_calloc(alloc, s->model_count, 1))) {
            plan_free(alloc, w);
            return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo write: out of memory");
        }
        if (sp) { /* the split form (version 5; with attributes its runs stream, version 6) */
            w->chunked[i] = 3;
            uint16_t v = s->models[i].attrs && vx__svo_split_runs(w->t) ? VERSION_RUNS : VERSION_SPLIT;
            if (w->version < v) w->version = v;
            continue;
        }
        const bool tagged = cs ? cs->info[i].chunk_tagged : w->chunk_mode == VX__CHUNK_ZSTD;
        w->chunked[i] = tagged ? 2 : 1;
        if (w->version < (tagged ? VERSION_TAGGED : VERSION_CHUNKED)) w->version = tagged ? VERSION_TAGGED : VERSION_CHUNKED;
    }
    return VX_OK;
}

/* Appends section si of the plan to b (NODE flushed through sink, if any). */
/* NODE from streams coded elsewhere: each is read into the output buffer
 * right after its length, then flushed, so one stream is held at a time. */
static bool write_node_coded(vx_buf* b, const vx_svo_scene* s, coded_src* cs, const vx__svo_sink* sink) {
    for (uint32_t mi = 0; mi < s->model_count; mi++) {
        uint64_t n = cs->info[mi].stream_size;
        uint64_t v = n;
        do {
            uint8_t c = (uint8_t)(v & 0x7Fu);
            v >>= 7;
            vx_buf_u8(b, (uint8_t)(c | (v ? 0x80u : 0u)));
        } while (v);
        if (n > SIZE_MAX - b->size || !vx_buf_zeros(b, (size_t)n)) return false;
        if (!cs->src->read(cs->src->user, mi, b->data + b->size - (size_t)n, n)) {
            cs->read_failed = true;
            return false;
        }
        if (!sink->flush(sink->user, b)) return false;
    }
    return !b->failed;
}

static bool write_section(vx_buf* b, const wplan* w, int si, const vx_svo_scene* s, const vx_allocator* alloc,
                          const vx__svo_sink* sink, coded_src* cs) {
    int t = w->order[si];
    if (t == S_SCNE) write_scne(b, s, w->ext, w->chunked);
    else if (t == S_NODE && cs) return write_node_coded(b, s, cs, sink);
    else if (t == S_NODE) return vx__svo_pack_write(b, s, alloc, w->threads, w->t, w->chunk_min, w->chunk_mode, w->split_min, w->trusted, sink) && !b->failed;
    else if (t == S_PALT) write_palt(b, s, cs);
    else if (t == S_MATL) return write_matl(b, s, alloc) && !b->failed;
    else if (t == S_LGHT) write_lght(b, s);
    else if (t == S_FRMS) write_frms(b, s);
    return !b->failed;
}

/* The header and section table; fin[] receives each section's file offset. */
static bool write_head(vx_buf* head, const wplan* w, uint64_t fin[S_COUNT]) {
    vx_buf_append(head, MAGIC, 8);
    vx_buf_u16le(head, w->version);
    vx_buf_u16le(head, (uint16_t)w->ns);
    for (int si = 0; si < w->ns; si++) {
        vx_buf_append(head, TAGS[w->order[si]], 4);
        buf_var(head, w->flags[si]);
        buf_var(head, w->sizes[si]);
        vx_buf_u32le(head, w->crcs[si]);
    }
    vx_buf_u32le(head, head->failed ? 0 : vx_crc32(0, head->data, head->size));
    uint64_t fo = head->size;
    for (int si = 0; si < w->ns; si++) {
        if (w->flags[si] & SEC_ALIGN4) fo += (4 - fo % 4) % 4;
        fin[si] = fo;
        fo += w->sizes[si];
    }
    return !head->failed;
}

vx_result vx_svo_write(const vx_svo_scene* s, const vx_allocator* alloc, uint8_t** out_data, size_t* out_size,
                       vx_error* err) {
    vx_write_desc d = {.alloc = alloc};
    return vx_svo_write_ex(&d, s, out_data, out_size, err);
}

vx_result vx_svo_write_ex(const vx_write_desc* desc, const vx_svo_scene* s, uint8_t** out_data, size_t* out_size,
                          vx_error* err) {
    if (!s || !out_data || !out_size) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo write: null argument");
    const vx_allocator* alloc = desc ? desc->alloc : NULL;
    wplan w;
    vx_result r = plan_write(s, desc, NULL, &w, err);
    if (r != VX_OK) return r;
    /* sections first (their sizes and CRCs go into the table), then the
     * header and table in front of them */
    vx_buf body = {0}, head = {0};
    body.alloc = head.alloc = alloc;
    uint64_t offs[S_COUNT], fin[S_COUNT];
    bool ok = true;
    for (int si = 0; si < w.ns; si++) {
        offs[si] = body.size;
        ok = write_section(&body, &w, si, s, alloc, NULL, NULL) && ok;
        w.sizes[si] = body.size - offs[si];
        w.crcs[si] = body.failed ? 0 : vx__svo_crc32(0, body.data + offs[si], (size_t)w.sizes[si]);
    }
    plan_free(alloc, &w);
    ok = write_head(&head, &w, fin) && ok;
    /* The body was laid out from 0 without gaps; shift it behind the head in
     * place (last section first, so no source is overwritten before it has
     * moved) instead of copying it, which would double peak memory. */
    uint64_t end_all = w.ns ? fin[w.ns - 1] + w.sizes[w.ns - 1] : head.size;
    bool failed = !ok || !vx_buf_zeros(&body, (size_t)(end_all - body.size));
    if (!failed) {
        for (int si = w.ns - 1; si >= 0; si--) memmove(body.data + fin[si], body.data + offs[si], (size_t)w.sizes[si]);
        uint64_t end = head.size;
        for (int si = 0; si < w.ns; si++) {
            memset(body.data + end, 0, (size_t)(fin[si] - end));
            end = fin[si] + w.sizes[si];
        }
        memcpy(body.data, head.data, head.size);
    }
    vx_buf_free(&head);
    if (failed) {
        vx_buf_free(&body);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo write: out of memory");
    }
    *out_data = body.data;
    *out_size = body.size;
    return VX_OK;
}

/* ---- writing a file: sections streamed to disk --------------------------------------------- */

/* The small sections are made in memory first; the NODE section goes
 * straight into the output's temporary file as it is coded (in pieces of
 * 16 MB or one chunk), its size and CRC counted on the way, behind a
 * placeholder for the header and table. Only the length of NODE's size
 * varint in the table is not known before NODE is written: it is guessed
 * (vx__svo_pack_estimate; exact for streams coded elsewhere) and, when the
 * guess was wrong, the sections behind the header are moved once (the copy
 * every write made when NODE went to a scratch file first: about a tenth of
 * the 4096^3 helmet's chunked write, docs/PERFORMANCE.md issue 18). Peak
 * memory is the scene plus a few pieces, not the scene plus the file. */
typedef struct spill {
    FILE* f;
    uint32_t crc;
    uint64_t size;
    bool failed;
} spill;

static bool spill_flush(void* user, vx_buf* out) {
    spill* sp = (spill*)user;
    if (sp->failed || out->failed) return false;
    if (out->size && fwrite(out->data, 1, out->size, sp->f) != out->size) {
        sp->failed = true;
        return false;
    }
    sp->crc = vx__svo_crc32(sp->crc, out->data, out->size);
    sp->size += out->size;
    out->size = 0;
    return true;
}

/* Moves the n bytes at offset from of the temporary file af to offset to
 * (the header came out shorter or longer than guessed), through buf of cap
 * bytes, and cuts what is left behind a shorter body. The file is written
 * through af's stream and read through a second one without a buffer, so
 * no stale bytes are read; the order of the pieces never reads a byte
 * already overwritten. */
static bool move_body(vx_atomic_file* af, uint64_t from, uint64_t to, uint64_t n, uint8_t* buf, size_t cap) {
    FILE* f = (FILE*)af->f;
    if (fflush(f) != 0) return false;
    FILE* r = fopen(af->tmp, "rb");
    if (!r) return false;
    setvbuf(r, NULL, _IONBF, 0);
    bool ok = true;
    for (uint64_t done = 0; ok && done < n;) {
        size_t k = n - done < cap ? (size_t)(n - done) : cap;
        /* left: the first piece first; right: the last first */
        uint64_t off = to < from ? done : n - done - k;
        ok = fseeko(r, (off_t)(from + off), SEEK_SET) == 0 && fread(buf, 1, k, r) == k &&
             fseeko(f, (off_t)(to + off), SEEK_SET) == 0 && fwrite(buf, 1, k, f) == k && fflush(f) == 0;
        done += k;
    }
    fclose(r);
    return ok && (to > from || ftruncate(fileno(f), (off_t)(to + n)) == 0);
}

static vx_result write_file(const vx_write_desc* desc, const vx_svo_scene* s, coded_src* cs, const char* path, vx_error* err) {
    if (!s || !path) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo write: null argument");
    const vx_allocator* a = desc ? desc->alloc : NULL;
    wplan w;
    vx_result r = plan_write(s, desc, cs, &w, err);
    if (r != VX_OK) return vx_error_prefix(err, path), r;
    vx_buf secs[S_COUNT], head = {.alloc = a};
    int node = -1;
    bool nomem = false, io = false;
    int e = 0;
    for (int si = 0; si < w.ns; si++) {
        secs[si] = (vx_buf){.alloc = a};
        if (w.order[si] == S_NODE) {
            node = si;
            continue;
        }
        nomem = nomem || !write_section(&secs[si], &w, si, s, a, NULL, cs);
        w.sizes[si] = secs[si].size;
        w.crcs[si] = secs[si].failed ? 0 : vx__svo_crc32(0, secs[si].data, secs[si].size);
    }
    /* NODE's guessed size: streams coded elsewhere are known exactly */
    uint64_t guess = 0;
    for (uint32_t mi = 0; cs && mi < s->model_count; mi++) {
        uint64_t n = cs->info[mi].stream_size, v = n;
        guess += n + 1;
        while (v >>= 7) guess++;
    }
    if (!cs) guess = vx__svo_pack_estimate(s, w.chunk_min, w.chunk_mode, w.split_min);
    if (node >= 0) w.sizes[node] = guess;
    uint64_t fin[S_COUNT];
    nomem = nomem || !write_head(&head, &w, fin);
    const size_t guessed = head.size;
    vx_atomic_file af;
    memset(&af, 0, sizeof af);
    bool opened = false;
    if (!nomem) {
        r = vx_atomic_open(&af, path, a, err);
        opened = r == VX_OK;
    }
    if (opened) {
        /* the header's place (its bytes are rewritten at the end), then the
         * sections one behind the other: the writer sets no ALIGN4 flag */
        vx_atomic_write(&af, head.data, head.size);
        for (int si = 0; !io && !nomem && si < w.ns; si++) {
            if (si != node) {
                io = !vx_atomic_write(&af, secs[si].data, secs[si].size);
                continue;
            }
            vx_buf b = {.alloc = a};
            spill sp = {.f = (FILE*)af.f};
            vx__svo_sink sink = {spill_flush, &sp, vx__svo_flush_bytes(w.t)};
            bool ok = write_section(&b, &w, si, s, a, &sink, cs) && spill_flush(&sp, &b);
            if (!ok) io = sp.failed || (cs && cs->read_failed), nomem = !io, e = sp.failed ? errno : EIO;
            w.sizes[si] = sp.size;
            w.crcs[si] = sp.crc;
            vx_buf_free(&b);
        }
        if (io && !e) e = af.failed_errno ? af.failed_errno : EIO;
        head.size = 0;
        nomem = nomem || !write_head(&head, &w, fin);
        if (!io && !nomem && head.size != guessed) {
            uint64_t body = 0;
            for (int si = 0; si < w.ns; si++) body += w.sizes[si];
            const size_t cap = (size_t)4 << 20;
            uint8_t* buf = (uint8_t*)vx_alloc(a, cap);
            nomem = !buf;
            io = buf && !move_body(&af, guessed, head.size, body, buf, cap);
            if (io) e = errno ? errno : EIO;
            vx_free(a, buf);
        }
        if (!io && !nomem) {
            io = fflush((FILE*)af.f) != 0 || fseeko((FILE*)af.f, 0, SEEK_SET) != 0;
            if (io) e = errno;
            else vx_atomic_write(&af, head.data, head.size);
        }
        if (io || nomem) vx_atomic_abort(&af);
        else {
            r = vx_atomic_commit(&af, err);
            if (r) vx_error_prefix(err, path);
        }
    }
    plan_free(a, &w);
    for (int si = 0; si < w.ns; si++) vx_buf_free(&secs[si]);
    vx_buf_free(&head);
    if (nomem) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "%s: svo write: out of memory", path);
    if (io && cs && cs->read_failed)
        return vx_fail(err, VX_ERR_IO, VX_NO_OFFSET, "%s: svo write: a model's coded stream could not be read", path);
    if (io) return vx_fail(err, VX_ERR_IO, VX_NO_OFFSET, "%s: cannot write: %s", path, strerror(e));
    if (!opened) vx_error_prefix(err, path);
    return r;
}

vx_result vx_svo_write_file(const vx_write_desc* desc, const vx_svo_scene* s, const char* path, vx_error* err) {
    return write_file(desc, s, NULL, path, err);
}

vx_result vx_svo_write_file_coded(const vx_write_desc* desc, const vx_svo_scene* s, const vx_svo_model_coded* info,
                                  const vx_svo_stream_source* src, const char* path, vx_error* err) {
    if (!s || (s->model_count && !info) || !src || !src->read)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "%s: svo write: null argument", path ? path : "(null)");
    coded_src cs = {info, src, false};
    return write_file(desc, s, &cs, path, err);
}

vx_result vx_svo_model_encode(const vx_write_desc* desc, const vx_svo_model* m, vx_svo_model_coded* info, uint8_t** stream,
                              vx_error* err) {
    if (!m || !info || !stream) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo encode: null argument");
    const vx_allocator* a = desc ? desc->alloc : NULL;
    memset(info, 0, sizeof *info);
    *stream = NULL;
    vx__svo_extent ext;
    /* a model whose check is current (the builder's or the reader's): its
     * box from the check, coded without the validation (and, structural with
     * the check's settings, without the rebuild), as vx_svo_write does it
     * (vx__svo_trusted_models): mpirun vox2svo's ranks code what they built */
    const uint32_t chunk_words = desc ? desc->svo_chunk_words : 0;
    bool trusted = m->check.digest && (vx__svo_model_chunked(m, chunk_words) || m->check.structural) &&
                   vx_svo_model_digest(m) == m->check.digest;
    if (trusted) {
        ext.cells = m->voxel_count;
        memcpy(ext.min, m->check.min, sizeof ext.min);
        memcpy(ext.max, m->check.max, sizeof ext.max);
    } else {
        vx_result r = vx__svo_analyze(m, &ext, err);
        if (r != VX_OK) return vx_error_prefix(err, "svo encode"), r;
    }
    vx_buf b = {.alloc = a};
    info->chunked = vx__svo_model_chunked(m, chunk_words);
    info->split = vx__svo_model_split(m, desc ? desc->svo_chunk_words : 0, vx__svo_split_min(desc));
    int mode = info->split ? VX__CHUNK_SPLIT : !info->chunked ? VX__CHUNK_NONE : vx__svo_chunk_mode(desc);
    info->chunk_tagged = mode == VX__CHUNK_ZSTD;
    if (!vx__svo_pack_model(m, a, mode, vx__svo_cpus(desc ? desc->threads : 0), vx__svo_write_testing(desc), trusted, &b)) {
        vx_buf_free(&b);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo encode: out of memory");
    }
    info->stream_size = b.size;
    info->cells = ext.cells;
    memcpy(info->min, ext.min, sizeof info->min);
    memcpy(info->max, ext.max, sizeof info->max);
    palette_bits(m, info->palette_used);
    *stream = b.data;
    return VX_OK;
}
