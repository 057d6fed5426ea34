/* tests/glb/test_glb_sky.c - svo_info --to-glb writes the scene's sky as
 * voxkit's record in the scene's extras (convert/export_glb.c,
 * formats/glb.h scene_extras) and voxkit reads it back (formats/gltf.h
 * vx_gltf_mesh.sky, convert/mesh.c).
 *  - round trip: a box scene with a constant, a gradient and an envmap sky
 *    -> .glb (vx_conv_svo_to_glb_file, svo_info's export) -> our glTF reader
 *    and vox2svo's conversion (also with y_up): the sky field for field,
 *    doubles exact (-0 included);
 *  - an envmap's relative path is rebased when the .glb goes to another
 *    folder (and back by vox2svo's vx_sky_rebase); absolute paths stay;
 *  - a DEFAULT sky writes no scene extras (the JSON holds no "extras"), and
 *    a sky changes the JSON only: the BIN chunk is the same;
 *  - malformed records are VX_ERR_BAD_FORMAT naming "scene 0 extras
 *    voxkit_sky"; punctual_only ignores them; the writer refuses scene
 *    extras that are not a JSON object. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "convert/convert.h"
#include "convert/export.h"
#include "convert/mesh.h"
#include "formats/glb.h"
#include "formats/gltf.h"
#include "svo/svo.h"
#include "tests/glb/box_gltf.h"
#include "tests/test.h"

static const vx_sky SKIES[] = {
    {.type = VX_SKY_CONSTANT, .color = {0.1, 1.0 / 3.0, 12345.678901234567}},
    {.type = VX_SKY_GRADIENT, .color = {0.2, 0.4, 0.9}, .horizon = {1e-300, 0.7, 1e29}, .ground = {0.3, 0.2, 0.1}},
    {.type = VX_SKY_ENVMAP, .intensity = 2.0 / 3.0, .rotation = -0.0, .path = "maps/sky \"noon\".pfm"},
    {.type = VX_SKY_ENVMAP, .intensity = 0.5, .rotation = -2.718281828459045, .path = "/abs/sky.exr"},
};
enum { NSKIES = sizeof SKIES / sizeof SKIES[0] };

/* ---- helpers ---------------------------------------------------------------------- */

static char TMP[256]; /* a folder of our own */

static void tmp_path(char* buf, size_t n, const char* name) { snprintf(buf, n, "%s/%s", TMP, name); }


/* A .gltf (text): a box 0..4 on each axis, its scene's extras `extras`
 * (JSON text, or NULL for none). malloc'ed. */
static char* gltf_text(const char* extras) {
    char b64[BOX_GLTF_B64];
    box_gltf_positions(b64);
    size_t n = strlen(b64) + (extras ? strlen(extras) : 0) + 1024;
    char* s = malloc(n);
    if (!s) return NULL;
    snprintf(s, n,
             "{\"asset\":{\"version\":\"2.0\"},"
             "\"buffers\":[{\"byteLength\":%zu,\"uri\":\"data:application/octet-stream;base64,%s\"}],"
             "\"bufferViews\":[{\"buffer\":0,\"byteLength\":%zu}],"
             "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":36,\"type\":\"VEC3\","
             "\"min\":[0,0,0],\"max\":[4,4,4]}],"
             "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}}]}],"
             "\"nodes\":[{\"mesh\":0}],\"scenes\":[{\"nodes\":[0]%s%s}],\"scene\":0}",
             (size_t)BOX_GLTF_BYTES, b64, (size_t)BOX_GLTF_BYTES, extras ? ",\"extras\":" : "", extras ? extras : "");
    return s;
}

/* vox2svo's conversion of a glTF file (at 8 cells a side) */
static vx_result convert(const char* path, bool y_up, vx_svo_scene* out, vx_error* err) {
    return vx_conv_mesh_file(&(vx_conv_mesh_desc){.res = 8, .y_up = y_up}, path, out, NULL, err);
}

/* The box as a scene (no sky). */
static vx_result box_scene(vx_svo_scene* out) {
    char path[512];
    tmp_path(path, sizeof path, "box.gltf");
    char* text = gltf_text(NULL);
    bool ok = text && write_text(path, text);
    free(text);
    if (!ok) return VX_ERR_IO;
    vx_error err = {0};
    vx_result r = convert(path, false, out, &err);
    if (r) fprintf(stderr, "  convert: %s\n", err.msg);
    remove(path);
    return r;
}

static vx_result export_glb(const vx_svo_scene* s, const char* svo_path, const char* path) {
    vx_error err = {0};
    vx_result r = vx_conv_svo_to_glb_file(&(vx_conv_export_desc){.svo_path = svo_path}, s, path, NULL, &err);
    if (r) fprintf(stderr, "  export: %s\n", err.msg);
    return r;
}

static bool same_bits(double a, double b) { return memcmp(&a, &b, sizeof a) == 0; }

/* Two skies the same, field for field, every double's bits. */
static bool same_sky(const vx_sky* got, const vx_sky* want, char* why, size_t n) {
    const char* bad = got->type != want->type ? "type" : NULL;
    for (int k = 0; k < 3 && !bad; k++) {
        if (!same_bits(got->color[k], want->color[k])) bad = "color";
        else if (!same_bits(got->horizon[k], want->horizon[k])) bad = "horizon";
        else if (!same_bits(got->ground[k], want->ground[k])) bad = "ground";
    }
    if (!bad && !same_bits(got->intensity, want->intensity)) bad = "intensity";
    if (!bad && !same_bits(got->rotation, want->rotation)) bad = "rotation";
    if (!bad && strcmp(got->path, want->path) != 0) bad = "path";
    if (bad)
        snprintf(why, n, "%s: type %d/%d color %.17g/%.17g intensity %.17g/%.17g rotation %.17g/%.17g path '%.80s'/'%.80s'",
                 bad, (int)got->type, (int)want->type, got->color[0], want->color[0], got->intensity, want->intensity,
                 got->rotation, want->rotation, got->path, want->path);
    return !bad;
}

/* The JSON chunk of a .glb (malloc'ed, terminated) and its BIN chunk's bytes. */
static char* glb_json(const char* path, uint8_t** bin, size_t* bin_size) {
    size_t size = 0;
    uint8_t* b = (uint8_t*)vx_test_slurp(path, &size);
    if (!b || size < 20) return free(b), NULL;
    uint32_t jl;
    memcpy(&jl, b + 12, 4);
    if (jl > size - 20) return free(b), NULL;
    char* j = malloc(jl + 1);
    if (j) memcpy(j, b + 20, jl), j[jl] = 0;
    if (bin) {
        *bin_size = size - 20 - jl;
        *bin = malloc(*bin_size ? *bin_size : 1);
        if (*bin) memcpy(*bin, b + 20 + jl, *bin_size);
    }
    free(b);
    return j;
}

/* ---- tests ------------------------------------------------------------------------ */

/* Each sky -> .glb -> our reader and vox2svo's conversion (+Z up and y_up):
 * the same sky. */
static void test_sky_round_trip(void) {
    vx_svo_scene s;
    REQUIRE(box_scene(&s) == VX_OK);
    char svo[512], glb[512];
    tmp_path(svo, sizeof svo, "scene.svo"); /* the .glb beside it: paths unchanged */
    tmp_path(glb, sizeof glb, "sky.glb");
    for (int i = 0; i < NSKIES; i++) {
        s.sky = SKIES[i];
        if (export_glb(&s, svo, glb) != VX_OK) {
            CHECKF(0, "sky %d: export", i);
            continue;
        }
        char* json = glb_json(glb, NULL, NULL);
        CHECKF(json && strstr(json, "\"voxkit_sky\""), "sky %d: no voxkit_sky in the JSON", i);
        free(json);
        char why[512];
        vx_gltf_mesh m;
        vx_error err = {0};
        vx_result r = vx_gltf_read_file(NULL, glb, &m, &err);
        CHECKF(r == VX_OK, "sky %d: read: %s", i, err.msg);
        if (r == VX_OK) {
            CHECKF(same_sky(&m.sky, &SKIES[i], why, sizeof why), "sky %d read back: %s", i, why);
            vx_gltf_mesh_free(&m);
        }
        /* punctual_only: the file as other readers see it, no sky */
        r = vx_gltf_read_file(&(vx_gltf_read_desc){.punctual_only = true}, glb, &m, &err);
        CHECKF(r == VX_OK && m.sky.type == VX_SKY_DEFAULT, "sky %d punctual_only: %d type %d", i, (int)r,
               (int)m.sky.type);
        if (r == VX_OK) vx_gltf_mesh_free(&m);
        for (int y_up = 0; y_up < 2; y_up++) {
            vx_svo_scene t;
            r = convert(glb, y_up, &t, &err);
            CHECKF(r == VX_OK, "sky %d: convert: %s", i, err.msg);
            if (r) continue;
            CHECKF(same_sky(&t.sky, &SKIES[i], why, sizeof why), "sky %d converted (y_up %d): %s", i, y_up, why);
            vx_svo_scene_free(&t);
        }
    }
    vx_svo_scene_free(&s);
    remove(glb);
}

/* A .glb in another folder than the .svo names the same map; vox2svo's
 * rebase gives the path back next to the .svo. */
static void test_envmap_other_folder(void) {
    vx_svo_scene s;
    REQUIRE(box_scene(&s) == VX_OK);
    char a[512], b[512], map[600], svo[600], glb[600];
    tmp_path(a, sizeof a, "a");
    tmp_path(b, sizeof b, "b");
    REQUIRE(mkdir(a, 0700) == 0 && mkdir(b, 0700) == 0);
    snprintf(map, sizeof map, "%s/sky.pfm", a);
    snprintf(svo, sizeof svo, "%s/scene.svo", a);
    snprintf(glb, sizeof glb, "%s/scene.glb", b);
    REQUIRE(write_text(map, "PF\n1 1\n-1\n"));
    s.sky = (vx_sky){.type = VX_SKY_ENVMAP, .intensity = 1, .path = "sky.pfm"};
    if (export_glb(&s, svo, glb) == VX_OK) {
        vx_gltf_mesh m;
        vx_error err = {0};
        vx_result r = vx_gltf_read_file(NULL, glb, &m, &err);
        CHECKF(r == VX_OK, "read: %s", err.msg);
        if (r == VX_OK) {
            CHECKF(strcmp(m.sky.path, "../a/sky.pfm") == 0, "path '%s'", m.sky.path);
            char seen[1200];
            CHECK(vx_sky_path(&m.sky, glb, seen, sizeof seen) && access(seen, R_OK) == 0);
            /* vox2svo writing next to the map again: the first path */
            char out[600];
            snprintf(out, sizeof out, "%s/again.svo", a);
            vx_sky k = m.sky;
            CHECKF(vx_sky_rebase(&k, glb, out, &err) == VX_OK && strcmp(k.path, "sky.pfm") == 0, "'%s' %s", k.path,
                   err.msg);
            vx_gltf_mesh_free(&m);
        }
    } else {
        CHECK(0);
    }
    /* leading "./" and "../" are taken off the canonical folder first */
    vx_sky k = {.type = VX_SKY_ENVMAP, .intensity = 1, .path = "./sky.pfm"};
    vx_error e = {0};
    CHECKF(vx_sky_rebase(&k, svo, glb, &e) == VX_OK && strcmp(k.path, "../a/sky.pfm") == 0, "'%s' %s", k.path, e.msg);
    k = (vx_sky){.type = VX_SKY_ENVMAP, .intensity = 1, .path = "../b/deep/sky.pfm"};
    CHECKF(vx_sky_rebase(&k, svo, glb, &e) == VX_OK && strcmp(k.path, "deep/sky.pfm") == 0, "'%s' %s", k.path, e.msg);
    k = (vx_sky){.type = VX_SKY_CONSTANT, .color = {1, 1, 1}}; /* no map: untouched */
    CHECK(vx_sky_rebase(&k, svo, "/nonexistent/x.glb", &e) == VX_OK);
    /* an absolute path is left as it is */
    s.sky = (vx_sky){.type = VX_SKY_ENVMAP, .intensity = 1};
    REQUIRE(strlen(map) < sizeof s.sky.path);
    memcpy(s.sky.path, map, strlen(map) + 1);
    if (export_glb(&s, svo, glb) == VX_OK) {
        vx_gltf_mesh m;
        vx_error err = {0};
        if (vx_gltf_read_file(NULL, glb, &m, &err) == VX_OK) {
            CHECKF(strcmp(m.sky.path, map) == 0, "path '%s'", m.sky.path);
            vx_gltf_mesh_free(&m);
        } else {
            CHECKF(0, "read: %s", err.msg);
        }
    } else {
        CHECK(0);
    }
    /* a folder that does not exist cannot be resolved: an error, no file */
    char nowhere[600];
    snprintf(nowhere, sizeof nowhere, "%s/missing/scene.svo", TMP);
    s.sky = (vx_sky){.type = VX_SKY_ENVMAP, .intensity = 1, .path = "sky.pfm"};
    remove(glb);
    vx_error err = {0};
    vx_result r = vx_conv_svo_to_glb_file(&(vx_conv_export_desc){.svo_path = nowhere}, &s, glb, NULL, &err);
    CHECKF(r == VX_ERR_IO && strstr(err.msg, "missing"), "%d '%s'", (int)r, err.msg);
    CHECK(access(glb, F_OK) != 0);
    vx_svo_scene_free(&s);
    remove(map);
    rmdir(a);
    rmdir(b);
}

/* DEFAULT writes no scene extras; a sky changes the JSON only. */
static void test_default_sky_no_extras(void) {
    vx_svo_scene s;
    REQUIRE(box_scene(&s) == VX_OK);
    char glb[512];
    tmp_path(glb, sizeof glb, "default.glb");
    uint8_t *bin0 = NULL, *bin1 = NULL;
    size_t n0 = 0, n1 = 0;
    char *j0 = NULL, *j1 = NULL;
    if (export_glb(&s, NULL, glb) == VX_OK) j0 = glb_json(glb, &bin0, &n0);
    s.sky = SKIES[1];
    if (export_glb(&s, NULL, glb) == VX_OK) j1 = glb_json(glb, &bin1, &n1);
    REQUIRE(j0 && j1 && bin0 && bin1);
    CHECKF(!strstr(j0, "voxkit_sky") && !strstr(j0, "\"extras\""), "%s", j0);
    CHECK(strstr(j1, "\"extras\"") && strstr(j1, "voxkit_sky"));
    CHECK(n0 == n1 && memcmp(bin0, bin1, n0) == 0);
    vx_gltf_mesh m;
    vx_error err = {0};
    vx_result r = vx_gltf_read_file(NULL, glb, &m, &err);
    if (r == VX_OK) vx_gltf_mesh_free(&m);
    free(j0), free(j1), free(bin0), free(bin1);
    vx_svo_scene_free(&s);
    remove(glb);
}

/* Malformed records are refused naming the record; punctual_only reads
 * the file as other readers do. */
static void test_bad_sky(void) {
    static const char* const BAD[] = {
        "{\"voxkit_sky\":{\"type\":\"sunset\",\"color\":[1,1,1]}}",                /* unknown type */
        "{\"voxkit_sky\":{\"type\":\"constant\",\"color\":[1,1]}}",                /* 2-element colour */
        "{\"voxkit_sky\":{\"type\":\"constant\",\"color\":[1,-0.5,1]}}",           /* negative */
        "{\"voxkit_sky\":{\"type\":\"gradient\",\"color\":[1,1,1],\"horizon\":[1,1,1]}}", /* no ground */
        "{\"voxkit_sky\":{\"type\":\"constant\",\"color\":[1,\"1\",1]}}",          /* not a number */
        "{\"voxkit_sky\":{\"type\":\"constant\",\"color\":[1,1,1e300]}}",          /* over 1e30 */
        "{\"voxkit_sky\":{\"type\":\"envmap\",\"path\":\"\",\"intensity\":1,\"rotation\":0}}", /* empty path */
        "{\"voxkit_sky\":{\"type\":\"envmap\",\"path\":7,\"intensity\":1,\"rotation\":0}}",    /* not a string */
        "{\"voxkit_sky\":{\"type\":\"envmap\",\"path\":\"a\\u0000b\",\"intensity\":1,\"rotation\":0}}", /* NUL */
        "{\"voxkit_sky\":{\"type\":\"envmap\",\"path\":\"s.exr\",\"intensity\":-1,\"rotation\":0}}",   /* negative */
        "{\"voxkit_sky\":{\"type\":\"envmap\",\"path\":\"s.exr\",\"rotation\":0}}",                     /* no intensity */
        "{\"voxkit_sky\":{\"type\":\"envmap\",\"path\":\"s.exr\",\"intensity\":1,\"rotation\":1e7}}",  /* rotation */
        "{\"voxkit_sky\":\"constant\"}",                                                              /* not an object */
        "{\"voxkit_sky\":{\"type\":\"envmap\",\"path\":\"LONG\",\"intensity\":1,\"rotation\":0}}",     /* too long */
    };
    enum { NBAD = sizeof BAD / sizeof BAD[0] };
    char path[512];
    tmp_path(path, sizeof path, "bad.gltf");
    for (int i = 0; i < NBAD; i++) {
        char extras[1024];
        snprintf(extras, sizeof extras, "%s", BAD[i]);
        char* at = strstr(extras, "LONG");
        if (at) { /* a path of VX_SKY_PATH_MAX + 1 bytes */
            char tail[256];
            snprintf(tail, sizeof tail, "%s", at + 4);
            memset(at, 'x', VX_SKY_PATH_MAX + 1);
            snprintf(at + VX_SKY_PATH_MAX + 1, sizeof extras - (size_t)(at - extras) - VX_SKY_PATH_MAX - 1, "%s", tail);
        }
        char* text = gltf_text(extras);
        REQUIRE(text && write_text(path, text));
        free(text);
        vx_gltf_mesh m;
        vx_error err = {0};
        vx_result r = vx_gltf_read_file(NULL, path, &m, &err);
        CHECKF(r == VX_ERR_BAD_FORMAT && strstr(err.msg, "scene 0 extras voxkit_sky"), "case %d: %d '%s'", i, (int)r,
               err.msg);
        if (r == VX_OK) vx_gltf_mesh_free(&m);
        /* vox2svo's conversion says the same */
        vx_svo_scene s;
        r = convert(path, false, &s, &err);
        CHECKF(r == VX_ERR_BAD_FORMAT && strstr(err.msg, "voxkit_sky"), "case %d convert: %d '%s'", i, (int)r, err.msg);
        if (r == VX_OK) vx_svo_scene_free(&s);
        r = vx_gltf_read_file(&(vx_gltf_read_desc){.punctual_only = true}, path, &m, &err);
        CHECKF(r == VX_OK && m.sky.type == VX_SKY_DEFAULT, "case %d punctual_only: %d '%s'", i, (int)r, err.msg);
        if (r == VX_OK) vx_gltf_mesh_free(&m);
    }
    /* other extras, and members a type does not use, are ignored */
    char* text = gltf_text("{\"author\":\"x\",\"voxkit_sky\":{\"type\":\"constant\",\"color\":[0.5,0.25,2],"
                           "\"path\":\"ignored\",\"note\":[1]}}");
    REQUIRE(text && write_text(path, text));
    free(text);
    vx_gltf_mesh m;
    vx_error err = {0};
    vx_result r = vx_gltf_read_file(NULL, path, &m, &err);
    CHECKF(r == VX_OK, "%s", err.msg);
    if (r == VX_OK) {
        vx_sky want = {.type = VX_SKY_CONSTANT, .color = {0.5, 0.25, 2}};
        char why[512];
        CHECKF(same_sky(&m.sky, &want, why, sizeof why), "%s", why);
        vx_gltf_mesh_free(&m);
    }
    remove(path);
}

/* The writer's scene_extras: a JSON object, or refused before any file. */
static void test_writer_scene_extras(void) {
    char path[512];
    tmp_path(path, sizeof path, "extras.glb");
    static const char* const BAD[] = {"[1, 2]", "{\"voxkit_sky\": ", "7"};
    for (int i = 0; i < 3; i++) {
        vx_glb_scene gs = {.scene_extras = BAD[i]};
        vx_error err = {0};
        vx_result r = vx_glb_write_file(NULL, &gs, path, &err);
        CHECKF(r == VX_ERR_INVALID_ARG && strstr(err.msg, "scene_extras"), "case %d: %d '%s'", i, (int)r, err.msg);
        CHECK(access(path, F_OK) != 0);
    }
    vx_glb_scene gs = {.scene_extras = "{\"k\":[1,2.5]}"};
    vx_error err = {0};
    CHECKF(vx_glb_write_file(NULL, &gs, path, &err) == VX_OK, "%s", err.msg);
    char* json = glb_json(path, NULL, NULL);
    CHECKF(json && strstr(json, "\"extras\":{\"k\":[1,2.5]}"), "%s", json ? json : "(none)");
    free(json);
    remove(path);
}

int main(void) {
    const char* d = getenv("TMPDIR");
    snprintf(TMP, sizeof TMP, "%s/test_glb_sky_%ld", d && *d ? d : "/tmp", (long)getpid());
    if (mkdir(TMP, 0700) != 0) {
        fprintf(stderr, "cannot make %s\n", TMP);
        return 1;
    }
    RUN(test_sky_round_trip);
    RUN(test_envmap_other_folder);
    RUN(test_default_sky_no_extras);
    RUN(test_bad_sky);
    RUN(test_writer_scene_extras);
    rmdir(TMP);
    return vx_test_finish();
}
