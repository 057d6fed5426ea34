/* svo/svo_io.c - the .svo container: header, section table, sections.
 * docs/FORMAT.md is the specification; keep the two in step. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "svo/svo_internal.h"

static const uint8_t MAGIC[8] = {'V', 'X', 'S', 'V', 'O', 0, '\r', '\n'};
enum {
    HEADER_SIZE = 32,
    ENTRY_SIZE = 32,
    MAX_SECTIONS = 1024,
    SEC_REQUIRED = 1u << 0,
    SCENE_FIXED = 160,
    MODEL_REC = 96,
    INST_REC = 176,
    LAYER_REC = 72
};

/* Known sections; the channel ones are in VX_ATTR_* bit order. */
enum { S_SCNE, S_NODE, S_APAL, S_ARGB, S_ANRM, S_AMAT, S_ADEN, S_PALT, S_MATL, S_COUNT };
static const char TAGS[S_COUNT][5] = {"SCNE", "NODE", "APAL", "ARGB", "ANRM", "AMAT", "ADEN", "PALT", "MATL"};
static const unsigned CH_SIZE[5] = {1, 4, 4, 2, 4};

static int tag_index(const uint8_t t[4]) {
    for (int i = 0; i < S_COUNT; i++)
        if (memcmp(t, TAGS[i], 4) == 0) return i;
    return -1;
}

static uint32_t rd32(const uint8_t* p) {
    return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
}
static uint64_t rd64(const uint8_t* p) { return (uint64_t)rd32(p) | ((uint64_t)rd32(p + 4) << 32); }

typedef struct sec {
    uint8_t tag[4];
    uint32_t flags, crc;
    uint64_t offset, size;
} sec;

/* Header and section table; fills info when non-NULL and secs (count entries)
 * when non-NULL. Checks every bound, not the section CRCs. */
static vx_result parse_table(const uint8_t* d, size_t size, uint32_t* out_version, uint32_t* out_count, sec* secs,
                             vx_error* err) {
    if (size < HEADER_SIZE)
        return vx_fail(err, VX_ERR_TRUNCATED, size, "svo: file is %zu bytes, the header needs %d", size, HEADER_SIZE);
    if (memcmp(d, MAGIC, 8) != 0) return vx_fail(err, VX_ERR_BAD_FORMAT, 0, "svo: not a .svo file (bad magic)");
    uint32_t hcrc = rd32(d + 28);
    if (vx_crc32(0, d, 28) != hcrc) return vx_fail(err, VX_ERR_BAD_FORMAT, 28, "svo: header CRC mismatch");
    uint32_t version = rd32(d + 8), count = rd32(d + 12);
    uint64_t toff = rd64(d + 16);
    if (version == 0 || version > VX_SVO_FORMAT_VERSION)
        return vx_fail(err, VX_ERR_UNSUPPORTED, 8, "svo: format version %u, this reader supports 1..%u", version,
                       VX_SVO_FORMAT_VERSION);
    if (count > MAX_SECTIONS)
        return vx_fail(err, VX_ERR_LIMIT, 12, "svo: %u sections, the limit is %d", count, MAX_SECTIONS);
    if (toff < HEADER_SIZE || toff % 8 || toff > size || (uint64_t)count * ENTRY_SIZE > size - toff)
        return vx_fail(err, VX_ERR_TRUNCATED, 16, "svo: section table at byte %llu (%u entries) does not fit in %zu bytes",
                       (unsigned long long)toff, count, size);
    const uint8_t* t = d + toff;
    size_t tsize = (size_t)count * ENTRY_SIZE;
    if (vx_crc32(0, t, tsize) != rd32(d + 24)) return vx_fail(err, VX_ERR_BAD_FORMAT, 24, "svo: section table CRC mismatch");
    for (uint32_t i = 0; i < count; i++) {
        const uint8_t* e = t + (size_t)i * ENTRY_SIZE;
        uint64_t off = rd64(e + 8), sz = rd64(e + 16);
        uint64_t at = toff + (uint64_t)i * ENTRY_SIZE;
        char tg[5];
        for (int k = 0; k < 4; k++) tg[k] = (e[k] >= 32 && e[k] < 127) ? (char)e[k] : '?';
        tg[4] = 0;
        if (off % 8) return vx_fail(err, VX_ERR_BAD_FORMAT, at, "svo: section %s at byte %llu is not 8-byte aligned", tg, (unsigned long long)off);
        if (off < toff + tsize || off > size || sz > size - off)
            return vx_fail(err, VX_ERR_TRUNCATED, at, "svo: section %s (%llu bytes at byte %llu) lies outside the %zu-byte file data",
                           tg, (unsigned long long)sz, (unsigned long long)off, size);
        if (secs) {
            memcpy(secs[i].tag, e, 4);
            secs[i].flags = rd32(e + 4);
            secs[i].offset = off;
            secs[i].size = sz;
            secs[i].crc = rd32(e + 24);
        }
    }
    *out_version = version;
    *out_count = count;
    return VX_OK;
}

vx_result vx_svo_probe(const void* data, size_t size, vx_svo_file_info* out, vx_error* err) {
    if (!data && size) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo: null data");
    if (!out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo: null output");
    const uint8_t* d = (const uint8_t*)data;
    uint32_t version, count;
    vx_result r = parse_table(d, size, &version, &count, NULL, err);
    if (r != VX_OK) return r;
    vx_svo_file_info info;
    memset(&info, 0, sizeof info);
    info.version = version;
    info.section_count = count;
    info.file_size = size;
    uint64_t toff = rd64(d + 16);
    for (uint32_t i = 0; i < count && i < 64; i++) {
        const uint8_t* e = d + toff + (size_t)i * ENTRY_SIZE;
        vx_svo_section_info* s = &info.sections[i];
        for (int k = 0; k < 4; k++) s->tag[k] = (e[k] >= 32 && e[k] < 127) ? (char)e[k] : '?';
        s->tag[4] = 0;
        s->flags = rd32(e + 4);
        s->offset = rd64(e + 8);
        s->size = rd64(e + 16);
        s->crc = rd32(e + 24);
        s->crc_ok = vx_crc32(0, d + s->offset, (size_t)s->size) == s->crc;
        s->known = tag_index(e) >= 0;
    }
    *out = info;
    return VX_OK;
}

/* ---- reading ---------------------------------------------------------------------------- */

static void str_copy(char* dst, const uint8_t* src, size_t n) { memcpy(dst, src, n); }

vx_result vx_svo_read(const vx_svo_read_desc* desc, const void* data, size_t size, vx_svo_scene* out, vx_error* err) {
    vx_svo_read_desc rdd;
    if (desc) rdd = *desc;
    else memset(&rdd, 0, sizeof rdd);
    if ((!data && size) || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo: null argument");
    const uint8_t* d = (const uint8_t*)data;
    const vx_allocator* A = rdd.alloc;
    uint32_t version, count;
    sec* secs = NULL;
    vx_svo_scene s;
    vx_svo_scene_init(&s, A);
    vx_result r = parse_table(d, size, &version, &count, NULL, err);
    if (r != VX_OK) return r;
    secs = (sec*)vx_calloc(A, count ? count : 1, sizeof *secs);
    if (!secs) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo: out of memory");
    r = parse_table(d, size, &version, &count, secs, err);
    if (r != VX_OK) goto fail;

    const sec* known[S_COUNT] = {0};
    for (uint32_t i = 0; i < count; i++) {
        const sec* e = &secs[i];
        int ti = tag_index(e->tag);
        char tg[5];
        for (int k = 0; k < 4; k++) tg[k] = (e->tag[k] >= 32 && e->tag[k] < 127) ? (char)e->tag[k] : '?';
        tg[4] = 0;
        if (ti < 0) {
            if (e->flags & SEC_REQUIRED) {
                r = vx_fail(err, VX_ERR_UNSUPPORTED, e->offset, "svo: section %s is marked required but unknown to this reader", tg);
                goto fail;
            }
            continue; /* unknown optional sections are skipped */
        }
        if (known[ti]) {
            r = vx_fail(err, VX_ERR_BAD_FORMAT, e->offset, "svo: section %s appears twice", tg);
            goto fail;
        }
        if (!rdd.skip_checksums) {
            uint32_t c = vx_crc32(0, d + e->offset, (size_t)e->size);
            if (c != e->crc) {
                r = vx_fail(err, VX_ERR_BAD_FORMAT, e->offset, "svo: section %s at byte %llu: CRC-32 is 0x%08x, the table says 0x%08x",
                            tg, (unsigned long long)e->offset, c, e->crc);
                goto fail;
            }
        }
        known[ti] = e;
    }
    if (!known[S_SCNE] || !known[S_NODE]) {
        r = vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo: the %s section is missing", known[S_SCNE] ? "NODE" : "SCNE");
        goto fail;
    }

    /* SCNE */
    const sec* sc = known[S_SCNE];
    const uint8_t* p = d + sc->offset;
    if (sc->size < SCENE_FIXED) {
        r = vx_fail(err, VX_ERR_TRUNCATED, sc->offset, "svo: section SCNE is %llu bytes, needs at least %d",
                    (unsigned long long)sc->size, SCENE_FIXED);
        goto fail;
    }
    uint32_t mc = rd32(p), ic = rd32(p + 4), lc = rd32(p + 8);
    uint64_t need = SCENE_FIXED + (uint64_t)mc * MODEL_REC + (uint64_t)ic * INST_REC + (uint64_t)lc * LAYER_REC;
    if (need != sc->size) {
        r = vx_fail(err, VX_ERR_BAD_FORMAT, sc->offset,
                    "svo: section SCNE at byte %llu: %u models, %u instances, %u layers need %llu bytes, the section has %llu",
                    (unsigned long long)sc->offset, mc, ic, lc, (unsigned long long)need, (unsigned long long)sc->size);
        goto fail;
    }
    union { uint64_t u; double f; } cv;
    for (int i = 0; i < 12; i++) cv.u = rd64(p + 16 + 8 * i), s.world_from_grid[i] = cv.f;
    for (int i = 0; i < 3; i++) {
        cv.u = rd64(p + 112 + 8 * i);
        s.bounds_min[i] = cv.f;
        cv.u = rd64(p + 136 + 8 * i);
        s.bounds_max[i] = cv.f;
    }
    uint64_t node_words = known[S_NODE]->size / 4;
    if (known[S_NODE]->size % 4) {
        r = vx_fail(err, VX_ERR_BAD_FORMAT, known[S_NODE]->offset, "svo: section NODE size %llu is not a multiple of 4",
                    (unsigned long long)known[S_NODE]->size);
        goto fail;
    }
    uint64_t ch_recs[5];
    for (unsigned c = 0; c < 5; c++) {
        const sec* cs = known[S_APAL + c];
        ch_recs[c] = cs ? cs->size / CH_SIZE[c] : 0;
        if (cs && cs->size % CH_SIZE[c]) {
            r = vx_fail(err, VX_ERR_BAD_FORMAT, cs->offset, "svo: section %s size %llu is not a multiple of %u", TAGS[S_APAL + c],
                        (unsigned long long)cs->size, CH_SIZE[c]);
            goto fail;
        }
    }
    if (known[S_PALT] && known[S_PALT]->size != 1024) {
        r = vx_fail(err, VX_ERR_BAD_FORMAT, known[S_PALT]->offset, "svo: section PALT is %llu bytes, must be 1024",
                    (unsigned long long)known[S_PALT]->size);
        goto fail;
    }
    s.models = (vx_svo_model*)vx_calloc(A, mc ? mc : 1, sizeof *s.models);
    s.instances = (vx_svo_instance*)vx_calloc(A, ic ? ic : 1, sizeof *s.instances);
    s.layers = (vx_svo_layer*)vx_calloc(A, lc ? lc : 1, sizeof *s.layers);
    if (!s.models || !s.instances || !s.layers) goto nomem;
    for (uint32_t i = 0; i < mc; i++) {
        const uint8_t* q = p + SCENE_FIXED + (size_t)i * MODEL_REC;
        uint64_t at = sc->offset + SCENE_FIXED + (uint64_t)i * MODEL_REC;
        vx_svo_model* m = &s.models[i];
        s.model_count = i + 1; /* so that a failure frees what was copied */
        for (int k = 0; k < 3; k++) m->size[k] = rd32(q + 4 * k);
        m->depth = rd32(q + 12);
        m->root = rd32(q + 16);
        m->root_attr = rd32(q + 20);
        m->attrs = rd32(q + 24);
        m->node_count = rd32(q + 28);
        m->voxel_count = rd64(q + 32);
        uint64_t nf = rd64(q + 40);
        m->attr_count = rd32(q + 48);
        if (m->attrs & ~(uint32_t)VX_ATTR_ALL) {
            r = vx_fail(err, VX_ERR_BAD_FORMAT, at + 24, "svo: SCNE model %u: unknown attribute bits 0x%x", i, m->attrs);
            goto fail;
        }
        if (nf > node_words || m->node_count > node_words - nf) {
            r = vx_fail(err, VX_ERR_BAD_FORMAT, at + 40, "svo: SCNE model %u: node words %llu..+%u outside the %llu words of NODE", i,
                        (unsigned long long)nf, m->node_count, (unsigned long long)node_words);
            goto fail;
        }
        m->nodes = (uint32_t*)vx_calloc(A, m->node_count ? m->node_count : 1, 4);
        if (!m->nodes) goto nomem;
        const uint8_t* np = d + known[S_NODE]->offset + nf * 4;
        for (uint32_t k = 0; k < m->node_count; k++) m->nodes[k] = rd32(np + 4 * (size_t)k);
        for (unsigned c = 0; c < 5; c++) {
            uint64_t af = rd64(q + 56 + 8 * c);
            if (!(m->attrs >> c & 1u)) continue;
            const sec* cs = known[S_APAL + c];
            if (!cs) {
                r = vx_fail(err, VX_ERR_BAD_FORMAT, at + 24, "svo: SCNE model %u uses channel %s but the section is missing", i,
                            TAGS[S_APAL + c]);
                goto fail;
            }
            if (af > ch_recs[c] || m->attr_count > ch_recs[c] - af) {
                r = vx_fail(err, VX_ERR_BAD_FORMAT, at + 56 + 8 * c,
                            "svo: SCNE model %u: records %llu..+%u outside the %llu records of %s", i, (unsigned long long)af,
                            m->attr_count, (unsigned long long)ch_recs[c], TAGS[S_APAL + c]);
                goto fail;
            }
            void* arr = vx_alloc(A, (size_t)m->attr_count * CH_SIZE[c]);
            if (!arr) goto nomem;
            const uint8_t* ap = d + cs->offset + af * CH_SIZE[c];
            for (uint32_t k = 0; k < m->attr_count; k++) {
                const uint8_t* v = ap + (size_t)k * CH_SIZE[c];
                switch (c) {
                case 0: ((uint8_t*)arr)[k] = v[0]; break;
                case 1: ((uint32_t*)arr)[k] = rd32(v); break;
                case 2: ((uint32_t*)arr)[k] = rd32(v); break;
                case 3: ((uint16_t*)arr)[k] = (uint16_t)(v[0] | (v[1] << 8)); break;
                default: {
                    union { uint32_t u; float f; } fv = {rd32(v)};
                    ((float*)arr)[k] = fv.f;
                }
                }
            }
            switch (c) {
            case 0: m->palette = (uint8_t*)arr; break;
            case 1: m->rgba = (uint32_t*)arr; break;
            case 2: m->normal = (uint32_t*)arr; break;
            case 3: m->material = (uint16_t*)arr; break;
            default: m->density = (float*)arr;
            }
        }
        if ((m->attrs & VX_ATTR_PALETTE) && !known[S_PALT]) {
            r = vx_fail(err, VX_ERR_BAD_FORMAT, at + 24, "svo: SCNE model %u uses palette indices but the PALT section is missing", i);
            goto fail;
        }
    }
    for (uint32_t i = 0; i < ic; i++) {
        const uint8_t* q = p + SCENE_FIXED + (size_t)mc * MODEL_REC + (size_t)i * INST_REC;
        vx_svo_instance* in = &s.instances[i];
        for (int k = 0; k < 12; k++) cv.u = rd64(q + 8 * k), in->xform[k] = cv.f;
        in->model = rd32(q + 96);
        in->layer = rd32(q + 100);
        in->flags = rd32(q + 104);
        str_copy(in->name, q + 112, 64);
    }
    s.instance_count = ic;
    for (uint32_t i = 0; i < lc; i++) {
        const uint8_t* q = p + SCENE_FIXED + (size_t)mc * MODEL_REC + (size_t)ic * INST_REC + (size_t)i * LAYER_REC;
        str_copy(s.layers[i].name, q, 64);
        s.layers[i].flags = rd32(q + 64);
        s.layers[i].rgba = rd32(q + 68);
    }
    s.layer_count = lc;
    if (known[S_PALT]) {
        s.has_palette = true;
        for (int i = 0; i < 256; i++) s.palette[i] = rd32(d + known[S_PALT]->offset + 4 * i);
    }
    if (known[S_MATL]) {
        const sec* ms = known[S_MATL];
        vx_rd rd = vx_rd_make(d + ms->offset, (size_t)ms->size);
        rd.base = ms->offset;
        uint32_t n;
        if (!vx_rd_u32le(&rd, &n)) {
            r = vx_fail(err, VX_ERR_TRUNCATED, ms->offset, "svo: section MATL is too short for its count");
            goto fail;
        }
        if (n > vx_rd_left(&rd) / 8) {
            r = vx_fail(err, VX_ERR_BAD_FORMAT, ms->offset, "svo: section MATL declares %u materials, %zu bytes left", n,
                        vx_rd_left(&rd));
            goto fail;
        }
        s.materials = (vx_svo_material*)vx_calloc(A, n ? n : 1, sizeof *s.materials);
        if (!s.materials) goto nomem;
        for (uint32_t i = 0; i < n; i++) {
            vx_svo_material* mt = &s.materials[i];
            uint64_t at = vx_rd_pos(&rd);
            if (!vx_rd_u32le(&rd, &mt->id) || !vx_rd_u32le(&rd, &mt->dict_size)) {
                r = vx_fail(err, VX_ERR_TRUNCATED, at, "svo: section MATL: material %u header is truncated", i);
                goto fail;
            }
            size_t padded = ((size_t)mt->dict_size + 3) & ~(size_t)3;
            if (mt->dict_size > vx_rd_left(&rd) || padded > vx_rd_left(&rd)) {
                r = vx_fail(err, VX_ERR_TRUNCATED, at, "svo: section MATL: material %u dictionary of %u bytes, %zu left", i,
                            mt->dict_size, vx_rd_left(&rd));
                mt->dict_size = 0;
                goto fail;
            }
            s.material_count = i + 1;
            if (mt->dict_size) {
                mt->dict = (char*)vx_alloc(A, mt->dict_size);
                if (!mt->dict) {
                    mt->dict_size = 0;
                    goto nomem;
                }
                vx_rd_bytes(&rd, mt->dict, mt->dict_size);
                vx_rd_skip(&rd, padded - mt->dict_size);
            }
        }
        s.material_count = n;
        if (vx_rd_left(&rd)) {
            r = vx_fail(err, VX_ERR_BAD_FORMAT, vx_rd_pos(&rd), "svo: section MATL has %zu trailing bytes", vx_rd_left(&rd));
            goto fail;
        }
    }
    r = vx_svo_validate_scene(&s, err);
    if (r != VX_OK) {
        if (r == VX_ERR_INVALID_ARG) r = VX_ERR_BAD_FORMAT;
        if (err) err->code = r;
        vx_error_prefix(err, "svo: structure");
        goto fail;
    }
    vx_free(A, secs);
    *out = s;
    return VX_OK;
nomem:
    r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo: out of memory");
fail:
    vx_free(A, secs);
    vx_svo_scene_free(&s);
    return r;
}

vx_result vx_svo_read_file(const vx_svo_read_desc* desc, const char* path, vx_svo_scene* out, vx_error* err) {
    const vx_allocator* A = desc ? desc->alloc : NULL;
    uint8_t* data = NULL;
    size_t size = 0;
    vx_result r = vx_file_read(path, A, 0, &data, &size, err);
    if (r != VX_OK) {
        vx_error_prefix(err, path);
        return r;
    }
    r = vx_svo_read(desc, data, size, out, err);
    vx_free(A, data);
    return r;
}

/* ---- writing ------------------------------------------------------------------------------ */

static bool pad8(vx_buf* b) { return vx_buf_zeros(b, (8 - b->size % 8) % 8); }

vx_result vx_svo_write(const vx_svo_scene* s, const vx_allocator* alloc, uint8_t** out_data, size_t* out_size,
                       vx_error* err) {
    if (!s || !out_data || !out_size) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo write: null argument");
    vx_result r = vx_svo_validate_scene(s, err);
    if (r != VX_OK) {
        vx_error_prefix(err, "svo write");
        return r;
    }
    uint32_t used = 0;
    for (uint32_t i = 0; i < s->model_count; i++) used |= s->models[i].attrs;
    int order[S_COUNT], ns = 0;
    order[ns++] = S_SCNE;
    order[ns++] = S_NODE;
    for (unsigned c = 0; c < 5; c++)
        if (used >> c & 1u) order[ns++] = S_APAL + (int)c;
    if (used & VX_ATTR_PALETTE) order[ns++] = S_PALT;
    if (s->material_count) order[ns++] = S_MATL;

    vx_buf b = {0};
    b.alloc = alloc;
    vx_buf_zeros(&b, HEADER_SIZE + (size_t)ns * ENTRY_SIZE);
    uint64_t offs[S_COUNT], sizes[S_COUNT];
    for (int si = 0; si < ns; si++) {
        int t = order[si];
        pad8(&b);
        offs[si] = b.size;
        if (t == S_SCNE) {
            vx_buf_u32le(&b, s->model_count);
            vx_buf_u32le(&b, s->instance_count);
            vx_buf_u32le(&b, s->layer_count);
            vx_buf_u32le(&b, 0);
            for (int i = 0; i < 12; i++) vx_buf_f64le(&b, s->world_from_grid[i]);
            for (int i = 0; i < 3; i++) vx_buf_f64le(&b, s->bounds_min[i]);
            for (int i = 0; i < 3; i++) vx_buf_f64le(&b, s->bounds_max[i]);
            uint64_t nf = 0, af[5] = {0};
            for (uint32_t i = 0; i < s->model_count; i++) {
                const vx_svo_model* m = &s->models[i];
                for (int k = 0; k < 3; k++) vx_buf_u32le(&b, m->size[k]);
                vx_buf_u32le(&b, m->depth);
                vx_buf_u32le(&b, m->root);
                vx_buf_u32le(&b, m->root_attr);
                vx_buf_u32le(&b, m->attrs);
                vx_buf_u32le(&b, m->node_count);
                vx_buf_u64le(&b, m->voxel_count);
                vx_buf_u64le(&b, nf);
                vx_buf_u32le(&b, m->attr_count);
                vx_buf_u32le(&b, 0);
                nf += m->node_count;
                for (unsigned c = 0; c < 5; c++) {
                    bool has = m->attrs >> c & 1u;
                    vx_buf_u64le(&b, has ? af[c] : 0);
                    if (has) af[c] += m->attr_count;
                }
            }
            for (uint32_t i = 0; i < s->instance_count; i++) {
                const vx_svo_instance* in = &s->instances[i];
                for (int k = 0; k < 12; k++) vx_buf_f64le(&b, in->xform[k]);
                vx_buf_u32le(&b, in->model);
                vx_buf_u32le(&b, in->layer);
                vx_buf_u32le(&b, in->flags);
                vx_buf_u32le(&b, 0);
                /* bytes after the NUL are written as zeros so output is deterministic */
                char name[64] = {0};
                size_t len = strnlen(in->name, sizeof in->name);
                memcpy(name, in->name, len);
                vx_buf_append(&b, name, 64);
            }
            for (uint32_t i = 0; i < s->layer_count; i++) {
                char name[64] = {0};
                size_t len = strnlen(s->layers[i].name, sizeof s->layers[i].name);
                memcpy(name, s->layers[i].name, len);
                vx_buf_append(&b, name, 64);
                vx_buf_u32le(&b, s->layers[i].flags);
                vx_buf_u32le(&b, s->layers[i].rgba);
            }
        } else if (t == S_NODE) {
            for (uint32_t i = 0; i < s->model_count; i++) {
                const vx_svo_model* m = &s->models[i];
                for (uint32_t k = 0; k < m->node_count; k++) vx_buf_u32le(&b, m->nodes[k]);
            }
        } else if (t >= S_APAL && t <= S_ADEN) {
            unsigned c = (unsigned)(t - S_APAL);
            for (uint32_t i = 0; i < s->model_count; i++) {
                const vx_svo_model* m = &s->models[i];
                if (!(m->attrs >> c & 1u)) continue;
                for (uint32_t k = 0; k < m->attr_count; k++) {
                    switch (c) {
                    case 0: vx_buf_u8(&b, m->palette[k]); break;
                    case 1: vx_buf_u32le(&b, m->rgba[k]); break;
                    case 2: vx_buf_u32le(&b, m->normal[k]); break;
                    case 3: vx_buf_u16le(&b, m->material[k]); break;
                    default: vx_buf_f32le(&b, m->density[k]);
                    }
                }
            }
        } else if (t == S_PALT) {
            for (int i = 0; i < 256; i++) vx_buf_u32le(&b, s->palette[i]);
        } else if (t == S_MATL) {
            vx_buf_u32le(&b, s->material_count);
            for (uint32_t i = 0; i < s->material_count; i++) {
                const vx_svo_material* mt = &s->materials[i];
                vx_buf_u32le(&b, mt->id);
                vx_buf_u32le(&b, mt->dict_size);
                if (mt->dict_size) vx_buf_append(&b, mt->dict, mt->dict_size);
                vx_buf_zeros(&b, (4 - mt->dict_size % 4) % 4);
            }
        }
        sizes[si] = b.size - offs[si];
    }
    /* no padding after the last section: any truncation cuts into a section */
    if (b.failed) {
        vx_buf_free(&b);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo write: out of memory");
    }
    uint8_t* h = b.data;
    memcpy(h, MAGIC, 8);
    vx_buf_put_u32le(h + 8, VX_SVO_FORMAT_VERSION);
    vx_buf_put_u32le(h + 12, (uint32_t)ns);
    vx_buf_put_u32le(h + 16, HEADER_SIZE);
    vx_buf_put_u32le(h + 20, 0);
    for (int si = 0; si < ns; si++) {
        uint8_t* e = h + HEADER_SIZE + (size_t)si * ENTRY_SIZE;
        memcpy(e, TAGS[order[si]], 4);
        vx_buf_put_u32le(e + 4, SEC_REQUIRED);
        vx_buf_put_u32le(e + 8, (uint32_t)offs[si]);
        vx_buf_put_u32le(e + 12, (uint32_t)(offs[si] >> 32));
        vx_buf_put_u32le(e + 16, (uint32_t)sizes[si]);
        vx_buf_put_u32le(e + 20, (uint32_t)(sizes[si] >> 32));
        vx_buf_put_u32le(e + 24, vx_crc32(0, h + offs[si], (size_t)sizes[si]));
        vx_buf_put_u32le(e + 28, 0);
    }
    vx_buf_put_u32le(h + 24, vx_crc32(0, h + HEADER_SIZE, (size_t)ns * ENTRY_SIZE));
    vx_buf_put_u32le(h + 28, vx_crc32(0, h, 28));
    *out_data = b.data;
    *out_size = b.size;
    return VX_OK;
}

vx_result vx_svo_write_file(const vx_svo_scene* s, const char* path, vx_error* err) {
    uint8_t* data = NULL;
    size_t size = 0;
    vx_result r = vx_svo_write(s, NULL, &data, &size, err);
    if (r != VX_OK) return r;
    r = vx_file_write_atomic(path, data, size, err);
    if (r != VX_OK) vx_error_prefix(err, path);
    vx_free(NULL, data);
    return r;
}
