/* tests/reliability/test_alloc_fail.c - allocation-failure injection
 * (issue 17). A test allocator fails the N-th allocation (transient: that one
 * only; persistent: that one and every later one) and counts live blocks.
 * Each operation runs for N = 1, 2, ... until it succeeds without a failed
 * allocation; every failing run must return VX_ERR_NOMEM, leave the output
 * untouched and zero live blocks. Operations: the .vox reader and writer (to
 * memory), the .vox -> .svo converter, the .svo -> .vox export, the .svo
 * writer (to memory), the .svo reader (memory and file), the .probes reader
 * (memory and file) and writer (to memory), and every writer to a file
 * (vx_svo_write_file, vx_vox_write_file, vx_probe_write_file,
 * vx_file_write_atomic, svo_info's --to-glb and --to-vdb exports where they
 * are built), over small inputs built here or checked in
 * (tests/probes/fuzz_seeds). A writer to a file writes over an old file: a
 * failing run must leave that file as it was and no other file beside it (no
 * temporary or scratch file). Prints the number of injection points per
 * operation (docs/RELIABILITY.md).
 *
 * Not reachable through vx_allocator (so not injected here): zlib's own
 * allocations (compress2 and uncompress in svo_pack.c), what stdio,
 * tinygltf and OpenVDB allocate inside the .glb and .vdb writers, and thread
 * start-up. */
#define _DEFAULT_SOURCE
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <dirent.h>
#include <sys/stat.h>

#include "convert/convert.h"
#include "formats/vox.h"
#include "probes/probes.h"
#include "svo/svo.h"
#include "tests/fail_alloc.h"
#include "tests/test.h"
#if defined(VX_HAVE_GLB) || defined(VX_HAVE_VDB)
#include "convert/export.h"
#endif


/* One operation under test: runs with allocator a and, on success, writes
 * what it made as bytes (the .vox or .svo or .probes writer with the default
 * allocator) to *digest, then frees it through a. */
typedef struct op_ctx {
    const uint8_t* d; /* input bytes, or */
    size_t n;
    const char* path; /* input file */
    const void* obj;  /* input object (writers) */
} op_ctx;
typedef vx_result (*op_fn)(const vx_allocator* a, const op_ctx* c, uint8_t** digest, size_t* digest_n, vx_error* err);

/* Injection points covered (transient runs, all operations), for the summary. */
static long points_total;

static void oom_loop(const char* what, op_fn fn, const op_ctx* c) {
    uint8_t *ref = NULL, *got = NULL;
    size_t ref_n = 0, got_n = 0;
    vx_error e = {0};
    vx_result r = fn(NULL, c, &ref, &ref_n, &e);
    if (r != VX_OK) {
        CHECKF(0, "%s: fails without injection: %s (%s)", what, vx_result_str(r), e.msg);
        return;
    }
    for (int persistent = 0; persistent < 2; persistent++) {
        long fails = 0, recovered = 0;
        for (long at = 1;; at++) {
            tfail f = {.fail_at = at, .persistent = persistent != 0};
            vx_allocator a = {tfail_alloc, tfail_free, &f};
            got = NULL;
            r = fn(&a, c, &got, &got_n, &e);
            CHECKF(f.live == 0, "%s: allocation %ld failed (%s): %ld blocks leaked", what, at, vx_result_str(r), f.live);
            if (r == VX_OK) {
                /* success after a failed allocation is a fallback: the result must not change */
                CHECKF(got_n == ref_n && !memcmp(got, ref, ref_n), "%s: allocation %ld failed: different result",
                       what, at);
                free(got);
                if (!f.failed) {
                    fprintf(stderr, "  %-26s %-10s %4ld failing runs, %ld recovered (%ld allocations)\n", what,
                            persistent ? "persistent" : "transient", fails, recovered, f.n);
                    if (!persistent) points_total += fails + recovered;
                    break;
                }
                recovered++;
            } else {
                fails++;
                CHECKF(f.failed, "%s: failed with %s (%s) before the injected failure %ld", what, vx_result_str(r),
                       e.msg, at);
                CHECKF(r == VX_ERR_NOMEM, "%s: allocation %ld failed: %s (%s)", what, at, vx_result_str(r), e.msg);
            }
            if (vx_t_cur_failed || at > 100000) break;
        }
    }
    free(ref);
}

/* ---- a small .vox file: two models, a group with three shapes (one hidden,
 * one on a layer, rotations), a palette, materials, layers ---------------- */

static void u32(vx_buf* b, uint32_t v) { vx_buf_u32le(b, v); }
static void str(vx_buf* b, const char* s) {
    u32(b, (uint32_t)strlen(s));
    vx_buf_append(b, s, strlen(s));
}
static void dict(vx_buf* b, int n, ...) {
    va_list ap;
    va_start(ap, n);
    u32(b, (uint32_t)n);
    for (int i = 0; i < 2 * n; i++) str(b, va_arg(ap, const char*));
    va_end(ap);
}
static size_t begin(vx_buf* b, const char* id) {
    size_t at = b->size;
    vx_buf_append(b, id, 4);
    u32(b, 0);
    u32(b, 0);
    return at;
}
static void end(vx_buf* b, size_t at) { vx_buf_put_u32le(b->data + at + 4, (uint32_t)(b->size - at - 12)); }
static void trn(vx_buf* b, uint32_t id, uint32_t child, int32_t layer, const char* r, const char* t) {
    size_t at = begin(b, "nTRN");
    u32(b, id);
    dict(b, 1, "_name", "node");
    u32(b, child);
    u32(b, UINT32_MAX);
    u32(b, (uint32_t)layer);
    u32(b, 1);
    dict(b, 2, "_r", r, "_t", t);
    end(b, at);
}
static void shp(vx_buf* b, uint32_t id, uint32_t model) {
    size_t at = begin(b, "nSHP");
    u32(b, id);
    dict(b, 0);
    u32(b, 1);
    u32(b, model);
    dict(b, 0);
    end(b, at);
}

static vx_buf make_vox(void) {
    vx_buf b = {0};
    vx_buf_append(&b, "VOX ", 4);
    u32(&b, 200);
    begin(&b, "MAIN");
    for (int m = 0; m < 2; m++) {
        uint32_t s = m ? 5 : 8;
        size_t at = begin(&b, "SIZE");
        u32(&b, s), u32(&b, s + 1), u32(&b, s + 2);
        end(&b, at);
        at = begin(&b, "XYZI");
        uint32_t n = 0;
        size_t cnt = b.size;
        u32(&b, 0);
        for (uint32_t z = 0; z < s + 2; z++)
            for (uint32_t y = 0; y < s + 1; y++)
                for (uint32_t x = 0; x < s; x++)
                    if ((x + y + z) % 3 == 0 || z == 0) {
                        uint8_t v[4] = {(uint8_t)x, (uint8_t)y, (uint8_t)z, (uint8_t)(1 + (x * 7 + z) % 9 + m * 10)};
                        vx_buf_append(&b, v, 4);
                        n++;
                    }
        vx_buf_put_u32le(b.data + cnt, n);
        end(&b, at);
    }
    trn(&b, 0, 1, -1, "4", "0 0 0");
    size_t at = begin(&b, "nGRP");
    u32(&b, 1);
    dict(&b, 0);
    u32(&b, 3), u32(&b, 2), u32(&b, 4), u32(&b, 6);
    end(&b, at);
    trn(&b, 2, 3, 0, "4", "10 0 0");
    shp(&b, 3, 0);
    trn(&b, 4, 5, 1, "17", "-3 4 5");
    shp(&b, 5, 1);
    trn(&b, 6, 7, 0, "98", "0 -9 2");
    shp(&b, 7, 0);
    for (int l = 0; l < 2; l++) {
        at = begin(&b, "LAYR");
        u32(&b, (uint32_t)l);
        dict(&b, 1, "_name", l ? "second" : "first");
        u32(&b, UINT32_MAX);
        end(&b, at);
    }
    at = begin(&b, "RGBA");
    for (int i = 0; i < 256; i++) u32(&b, 0xFF000000u | (uint32_t)i * 0x010305u);
    end(&b, at);
    for (int i = 1; i < 4; i++) {
        at = begin(&b, "MATL");
        u32(&b, (uint32_t)i);
        dict(&b, 2, "_type", i == 1 ? "_emit" : "_metal", "_rough", "0.25");
        end(&b, at);
    }
    vx_buf_put_u32le(b.data + 16, (uint32_t)(b.size - 20));
    return b;
}

/* ---- operations ------------------------------------------------------------------------ */

static vx_result svo_digest(const vx_svo_scene* s, uint8_t** d, size_t* n, vx_error* err) {
    return vx_svo_write(s, NULL, d, n, err);
}

static vx_result op_vox_read(const vx_allocator* a, const op_ctx* c, uint8_t** d, size_t* n, vx_error* err) {
    vx_vox_scene s;
    memset(&s, 0xAB, sizeof s);
    vx_result r = vx_vox_read(&(vx_vox_read_desc){.alloc = a, .keep_hidden = true}, c->d, c->n, &s, err);
    if (r) {
        CHECK(s.model_count == 0xABABABABu); /* output untouched */
        return r;
    }
    r = vx_vox_write(&s, NULL, d, n, err);
    vx_vox_scene_free(&s);
    return r;
}

/* .vox bytes -> scene -> svo scene (what vox2svo does in memory) */
static vx_result op_vox_convert(const vx_allocator* a, const op_ctx* c, uint8_t** d, size_t* n, vx_error* err) {
    vx_vox_scene vs;
    vx_result r = vx_vox_read(&(vx_vox_read_desc){.alloc = a}, c->d, c->n, &vs, err);
    if (r) return r;
    vx_svo_scene s;
    memset(&s, 0xAB, sizeof s);
    vx_conv_vox_desc cd = {.alloc = a, .build = {.alloc = a}};
    r = vx_conv_vox(&cd, &vs, &s, NULL, err);
    vx_vox_scene_free(&vs);
    if (r) {
        CHECK(s.model_count == 0xABABABABu);
        return r;
    }
    r = svo_digest(&s, d, n, err);
    vx_svo_scene_free(&s);
    return r;
}

/* The end of every in-memory writer's op: the writer's output (allocated
 * through the injecting allocator a) copied to plain malloc memory for the
 * digest, and given back to a. */
static vx_result take_output(const vx_allocator* a, uint8_t* out, size_t on, uint8_t** d, size_t* n) {
    *d = (uint8_t*)malloc(on);
    if (*d) memcpy(*d, out, on);
    *n = on;
    vx_free(a, out);
    return *d ? VX_OK : VX_ERR_NOMEM;
}

static vx_result op_svo_write(const vx_allocator* a, const op_ctx* c, uint8_t** d, size_t* n, vx_error* err) {
    uint8_t* out = (uint8_t*)&out;
    size_t on = 12345;
    vx_result r = vx_svo_write((const vx_svo_scene*)c->obj, a, &out, &on, err);
    if (r) {
        CHECK(out == (uint8_t*)&out || out == NULL);
        return r;
    }
    return take_output(a, out, on, d, n);
}

static vx_result op_svo_read(const vx_allocator* a, const op_ctx* c, uint8_t** d, size_t* n, vx_error* err) {
    vx_svo_scene s;
    memset(&s, 0xAB, sizeof s);
    vx_result r = c->path ? vx_svo_read_file(&(vx_svo_read_desc){.alloc = a}, c->path, &s, err)
                          : vx_svo_read(&(vx_svo_read_desc){.alloc = a}, c->d, c->n, &s, err);
    if (r) {
        CHECK(s.model_count == 0xABABABABu);
        return r;
    }
    r = svo_digest(&s, d, n, err);
    vx_svo_scene_free(&s);
    return r;
}

static vx_result op_probes_read(const vx_allocator* a, const op_ctx* c, uint8_t** d, size_t* n, vx_error* err) {
    vx_probe_set ps;
    memset(&ps, 0xAB, sizeof ps);
    vx_probe_read_desc pd = {.alloc = a};
    vx_result r = c->path ? vx_probe_read_file(&pd, c->path, &ps, err) : vx_probe_read(&pd, c->d, c->n, &ps, err);
    if (r) {
        CHECK(ps.res == 0xABABABABu);
        return r;
    }
    r = vx_probe_write(&ps, NULL, d, n, err);
    vx_probe_set_free(&ps);
    return r;
}

static vx_result op_probes_write(const vx_allocator* a, const op_ctx* c, uint8_t** d, size_t* n, vx_error* err) {
    uint8_t* out = NULL;
    size_t on = 0;
    vx_result r = vx_probe_write((const vx_probe_set*)c->obj, a, &out, &on, err);
    if (r) {
        CHECK(out == NULL);
        return r;
    }
    return take_output(a, out, on, d, n);
}

/* svo scene -> .vox scene (svo_info --to-vox, the viewer's export), quantized
 * or not, then written */
static vx_result vox_export(const vx_allocator* a, bool quantize, const op_ctx* c, uint8_t** d, size_t* n, vx_error* err) {
    vx_vox_scene vs;
    memset(&vs, 0xAB, sizeof vs);
    vx_conv_vox_export_stats st;
    const vx_svo_scene* s = (const vx_svo_scene*)c->obj;
    vx_result r = quantize ? vx_conv_svo_to_vox_ex(&(vx_conv_vox_export_desc){.alloc = a, .quantize = true}, s, &vs, &st, err)
                           : vx_conv_svo_to_vox(s, a, &vs, err);
    if (r) {
        CHECK(vs.model_count == 0xABABABABu);
        return r;
    }
    if (quantize) CHECK(st.quantized);
    r = vx_vox_write(&vs, NULL, d, n, err);
    vx_vox_scene_free(&vs);
    return r;
}

static vx_result op_vox_export(const vx_allocator* a, const op_ctx* c, uint8_t** d, size_t* n, vx_error* err) {
    return vox_export(a, false, c, d, n, err);
}

/* the same with more than 255 colours, quantized */
static vx_result op_vox_export_quantize(const vx_allocator* a, const op_ctx* c, uint8_t** d, size_t* n, vx_error* err) {
    return vox_export(a, true, c, d, n, err);
}

static vx_result op_vox_write(const vx_allocator* a, const op_ctx* c, uint8_t** d, size_t* n, vx_error* err) {
    uint8_t* out = NULL;
    size_t on = 0;
    vx_result r = vx_vox_write((const vx_vox_scene*)c->obj, a, &out, &on, err);
    if (r) {
        CHECK(out == NULL);
        return r;
    }
    return take_output(a, out, on, d, n);
}

/* ---- writers to a file ------------------------------------------------------------------- */

static char tmpdir[64];

static void write_file(const char* path, const void* d, size_t n) {
    FILE* f = fopen(path, "wb");
    if (f) {
        fwrite(d, 1, n, f);
        fclose(f);
    }
}

/* Files in dir (without . and ..); the first name goes to first. */
static int count_files(const char* dir, char* first, size_t cap) {
    DIR* d = opendir(dir);
    int n = 0;
    struct dirent* e;
    while (d && (e = readdir(d)))
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) {
            if (!n && first) snprintf(first, cap, "%s", e->d_name);
            n++;
        }
    if (d) closedir(d);
    return n;
}

/* A writer under test: obj to path, allocating through wd. */
typedef vx_result (*file_writer)(const vx_write_desc* wd, const void* obj, const char* path, vx_error* err);
typedef struct file_op {
    file_writer write;
    const void* obj;
    size_t skip_at, skip_n; /* bytes left out of the digest (the .vdb header's random UUID) */
} file_op;

static const char old_file[] = "the old file: a failed write leaves it as it was\n";

/* c->path is the output in a folder of its own, c->obj the file_op. */
static vx_result op_write_file(const vx_allocator* a, const op_ctx* c, uint8_t** d, size_t* n, vx_error* err) {
    const file_op* op = (const file_op*)c->obj;
    write_file(c->path, old_file, sizeof old_file - 1);
    char dir[128], name[256];
    snprintf(dir, sizeof dir, "%s/out", tmpdir);
    vx_result r = op->write(&(vx_write_desc){.alloc = a}, op->obj, c->path, err);
    vx_error e2;
    uint8_t* got = NULL;
    size_t got_n = 0;
    vx_result rr = vx_file_read(c->path, NULL, 0, &got, &got_n, &e2);
    int files = count_files(dir, name, sizeof name);
    CHECKF(files == 1, "%s: %d files in the output folder after a %s (%s)", c->path, files,
           r ? "failed write" : "write", name);
    if (r) {
        /* the output name holds the old file */
        CHECKF(rr == VX_OK && got_n == sizeof old_file - 1 && !memcmp(got, old_file, got_n),
               "%s: changed by a failed write (%s)", c->path, err->msg);
        free(got);
        return r;
    }
    if (rr) {
        *err = e2;
        return rr;
    }
    if (op->skip_n && op->skip_at + op->skip_n <= got_n) memset(got + op->skip_at, 0, op->skip_n);
    *d = got;
    *n = got_n;
    return VX_OK;
}

static vx_result w_svo(const vx_write_desc* wd, const void* obj, const char* path, vx_error* err) {
    return vx_svo_write_file(wd, (const vx_svo_scene*)obj, path, err);
}
static vx_result w_vox(const vx_write_desc* wd, const void* obj, const char* path, vx_error* err) {
    return vx_vox_write_file(wd, (const vx_vox_scene*)obj, path, err);
}
static vx_result w_probes(const vx_write_desc* wd, const void* obj, const char* path, vx_error* err) {
    return vx_probe_write_file(wd, (const vx_probe_set*)obj, path, err);
}
static vx_result w_atomic(const vx_write_desc* wd, const void* obj, const char* path, vx_error* err) {
    const vx_buf* b = (const vx_buf*)obj;
    return vx_file_write_atomic(path, wd->alloc, b->data, b->size, err);
}
#ifdef VX_HAVE_GLB
static vx_result w_glb(const vx_write_desc* wd, const void* obj, const char* path, vx_error* err) {
    return vx_conv_svo_to_glb_file(&(vx_conv_export_desc){.write = wd, .all = true}, (const vx_svo_scene*)obj, path, NULL,
                                   err);
}
#endif
#ifdef VX_HAVE_VDB
static vx_result w_vdb(const vx_write_desc* wd, const void* obj, const char* path, vx_error* err) {
    return vx_conv_svo_to_vdb_file(&(vx_conv_export_desc){.write = wd, .all = true}, (const vx_svo_scene*)obj, path, NULL,
                                   err);
}
static vx_result w_vdb_models(const vx_write_desc* wd, const void* obj, const char* path, vx_error* err) {
    return vx_conv_svo_to_vdb_file(&(vx_conv_export_desc){.write = wd, .all = true, .vdb_models = true},
                                   (const vx_svo_scene*)obj, path, NULL, err);
}
#endif

static void file_loop(const char* what, file_writer w, const void* obj, const char* name) {
    char dir[128], path[192];
    snprintf(dir, sizeof dir, "%s/out", tmpdir);
    snprintf(path, sizeof path, "%s/%s", dir, name);
    mkdir(dir, 0700);
    file_op op = {.write = w, .obj = obj};
    /* OpenVDB writes a random UUID into every header (magic, version, library
     * version, offsets flag: 21 bytes, then 36 characters) */
    if (strstr(name, ".vdb")) op.skip_at = 21, op.skip_n = 36;
    oom_loop(what, op_write_file, &(op_ctx){.obj = &op, .path = path});
    remove(path);
    rmdir(dir);
}

/* ---- tests ----------------------------------------------------------------------------- */

static void test_vox_and_svo(void) {
    vx_buf v = make_vox();
    REQUIRE(!v.failed);
    op_ctx vin = {.d = v.data, .n = v.size};
    oom_loop("vox read", op_vox_read, &vin);
    oom_loop("vox read + convert", op_vox_convert, &vin);

    /* the reference scene and file, with the default allocator */
    vx_error e;
    vx_vox_scene vs;
    REQUIRE(vx_vox_read(NULL, v.data, v.size, &vs, &e) == VX_OK);
    oom_loop("vox write (memory)", op_vox_write, &(op_ctx){.obj = &vs});
    file_loop("vox write (file)", w_vox, &vs, "scene.vox");
    vx_svo_scene s;
    vx_result r = vx_conv_vox(&(vx_conv_vox_desc){0}, &vs, &s, NULL, &e);
    vx_vox_scene_free(&vs);
    vx_buf_free(&v);
    REQUIRE(r == VX_OK);
    CHECK(s.model_count == 2 && s.instance_count == 3);
    uint8_t* svo = NULL;
    size_t svo_n = 0;
    r = vx_svo_write(&s, NULL, &svo, &svo_n, &e);
    CHECK(r == VX_OK);
    if (r == VX_OK) {
        oom_loop("svo write (memory)", op_svo_write, &(op_ctx){.obj = &s});
        oom_loop("vox export (svo -> vox)", op_vox_export, &(op_ctx){.obj = &s});
        oom_loop("svo read", op_svo_read, &(op_ctx){.d = svo, .n = svo_n});
        char path[128];
        snprintf(path, sizeof path, "%s/scene.svo", tmpdir);
        write_file(path, svo, svo_n);
        oom_loop("svo read (file)", op_svo_read, &(op_ctx){.path = path});
        remove(path);
        file_loop("svo write (file)", w_svo, &s, "scene.svo");
        vx_buf b = {.data = svo, .size = svo_n};
        file_loop("file write atomic", w_atomic, &b, "bytes.bin");
#ifdef VX_HAVE_GLB
        file_loop("svo_info --to-glb", w_glb, &s, "scene.glb");
#endif
#ifdef VX_HAVE_VDB
        file_loop("svo_info --to-vdb", w_vdb, &s, "scene.vdb");
        file_loop("svo_info --to-vdb --vdb-models", w_vdb_models, &s, "models.vdb");
#endif
    }
    vx_free(NULL, svo);
    vx_svo_scene_free(&s);
}

/* The export tests' scene: one RGBA8 model (count cells at keys, coloured
 * rgba) under `instances` identity instances on no layer. */
static void rgba_model_scene(vx_svo_scene* s, const uint32_t size[3], size_t count, const uint64_t* keys, const uint32_t* rgba,
                             uint32_t instances) {
    vx_svo_scene_init(s, NULL);
    s->models = (vx_svo_model*)vx_calloc(NULL, 1, sizeof *s->models);
    s->instances = (vx_svo_instance*)vx_calloc(NULL, instances, sizeof *s->instances);
    REQUIRE(s->models && s->instances);
    s->model_count = 1, s->instance_count = instances;
    vx_svo_voxels v = {.size = {size[0], size[1], size[2]}, .count = count, .keys = keys, .attrs = VX_ATTR_RGBA8, .rgba = rgba};
    REQUIRE(vx_svo_build_model(&(vx_svo_build_desc){0}, &v, &s->models[0], NULL, NULL) == VX_OK);
    for (uint32_t i = 0; i < instances; i++) {
        vx_svo_instance* in = &s->instances[i];
        in->xform[0] = in->xform[5] = in->xform[10] = 1;
        in->layer = UINT32_MAX;
    }
}

/* The export of a model over 256 cells a side: 300x3x3 in two pieces, two
 * instances (groups sharing the pieces) over two frames, RGBA8 colours. */
static void test_vox_export_split(void) {
    uint64_t keys[6];
    uint32_t rgba[6];
    for (uint32_t k = 0; k < 6; k++) keys[k] = vx_svo_morton(k < 3 ? k : 293 + k, k % 3, 2 - k % 3), rgba[k] = 0xFF000000u | (k * 0x102030u);
    vx_svo_scene s;
    rgba_model_scene(&s, (const uint32_t[3]){300, 3, 3}, 6, keys, rgba, 2);
    static const double x1[12] = {0, -1, 0, 10, 1, 0, 0, 0, 0, 0, 1, 0};
    memcpy(s.instances[1].xform, x1, sizeof x1);
    REQUIRE(vx_svo_scene_alloc_frames(&s, 2, NULL) == VX_OK);
    s.frame_instances[1].xform[3] += 4;
    oom_loop("vox export, split (svo -> vox)", op_vox_export, &(op_ctx){.obj = &s});
    vx_svo_scene_free(&s);
}

/* The export of 7^3 = 343 colours, quantized (--quantize). */
static void test_vox_export_quantize(void) {
    uint64_t keys[343];
    uint32_t rgba[343];
    for (uint32_t k = 0; k < 343; k++)
        keys[k] = vx_svo_morton(k % 7, k / 7 % 7, k / 49), rgba[k] = 0xFF000000u | (k % 7 * 40) | (k / 7 % 7 * 40) << 8 | (k / 49 * 40) << 16;
    vx_svo_scene s;
    rgba_model_scene(&s, (const uint32_t[3]){7, 7, 7}, 343, keys, rgba, 1);
    oom_loop("vox export, quantized (svo -> vox)", op_vox_export_quantize, &(op_ctx){.obj = &s});
    vx_svo_scene_free(&s);
}

static void test_svo_seeds(void) {
    /* the .svo fuzz seeds: palette and colour attributes, materials */
    int found = 0;
    for (int i = 0; i < 4; i++) {
        char path[4096], what[32];
        snprintf(path, sizeof path, "%s/tests/fuzz/svo_seeds/seed%d.svo", VX_SOURCE_DIR, i);
        if (access(path, R_OK) != 0) continue;
        found++;
        snprintf(what, sizeof what, "svo read seed%d (file)", i);
        oom_loop(what, op_svo_read, &(op_ctx){.path = path});
    }
    if (!found) SKIP("no seeds in tests/fuzz/svo_seeds");
}

static void test_probes(void) {
    for (int i = 0; i < 2; i++) {
        char path[4096], what[40];
        snprintf(path, sizeof path, "%s/tests/probes/fuzz_seeds/seed%d.probes", VX_SOURCE_DIR, i);
        uint8_t* d = NULL;
        size_t n = 0;
        vx_error e;
        if (vx_file_read(path, NULL, 0, &d, &n, &e) != VX_OK) SKIP("%s: %s", path, e.msg);
        snprintf(what, sizeof what, "probes read seed%d", i);
        oom_loop(what, op_probes_read, &(op_ctx){.d = d, .n = n});
        snprintf(what, sizeof what, "probes read seed%d (file)", i);
        oom_loop(what, op_probes_read, &(op_ctx){.path = path});
        vx_probe_set ps;
        if (vx_probe_read(NULL, d, n, &ps, &e) == VX_OK) {
            snprintf(what, sizeof what, "probes write seed%d", i);
            oom_loop(what, op_probes_write, &(op_ctx){.obj = &ps});
            snprintf(what, sizeof what, "probes write seed%d (file)", i);
            file_loop(what, w_probes, &ps, "set.probes");
            vx_probe_set_free(&ps);
        } else {
            CHECKF(0, "%s: %s", path, e.msg);
        }
        vx_free(NULL, d);
    }
}

int main(void) {
    snprintf(tmpdir, sizeof tmpdir, "/tmp/vx_alloc_fail_XXXXXX");
    if (!mkdtemp(tmpdir)) return 1;
    RUN(test_vox_and_svo);
    RUN(test_vox_export_split);
    RUN(test_vox_export_quantize);
    RUN(test_svo_seeds);
    RUN(test_probes);
    rmdir(tmpdir);
    fprintf(stderr, "%ld injection points (transient) in all\n", points_total);
    return vx_test_finish();
}
