/* tests/consumer/consumer.c - a program outside voxkit, built against an
 * installed voxkit (tests/consumer/run.sh: once through find_package(voxkit),
 * once through pkg-config) with nothing but the public headers and
 * libvoxkit.
 *
 * Usage: consumer WORKDIR [IN.vox [IN.glb [IN.vdb]]] ("-" skips one)
 * Converts IN.vox (or, without one, a .vox it writes itself with
 * vx_vox_write_file) to an .svo scene and checks every model's voxel count
 * against the distinct cells of the .vox model it came from, decodes every
 * model, writes the scene to WORKDIR and reads it back. IN.glb and IN.vdb,
 * where given and this libvoxkit has the readers, are converted too (the C++
 * shims through the shared library). Where the library has formats/image.h,
 * a PNG and an EXR are written to WORKDIR and read back, the same values:
 * OpenImageIO is a module that libvoxkit loads from voxkit/ beside itself
 * (formats/image.c), which only an installed library's run can show. Prints
 * one line per input and exits 0 when every check holds.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <voxkit/convert/convert.h>
#include <voxkit/formats/vox.h>
#include <voxkit/svo/svo.h>
#include <voxkit/version.h>

#if defined(__has_include)
#if __has_include(<voxkit/convert/mesh.h>)
#include <voxkit/convert/mesh.h>
#define HAVE_MESH 1
#endif
#if __has_include(<voxkit/convert/volume.h>)
#include <voxkit/convert/volume.h>
#define HAVE_VDB 1
#endif
#if __has_include(<voxkit/formats/image.h>)
#include <voxkit/formats/image.h>
#define HAVE_IMAGE 1
#endif
#endif

static int failures;

#define EXPECT(cond, ...)                                                   \
    do {                                                                    \
        if (!(cond)) {                                                      \
            fprintf(stderr, "consumer: check failed: %s: ", #cond);         \
            fprintf(stderr, __VA_ARGS__);                                   \
            fprintf(stderr, "\n");                                          \
            failures++;                                                     \
        }                                                                   \
    } while (0)

static bool count_cell(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    (void)x, (void)y, (void)z, (void)attr;
    ++*(uint64_t*)user;
    return true;
}

/* Cells decoded over all models, checked against each model's count. */
static uint64_t decoded_voxels(const vx_svo_scene* s, const char* what) {
    uint64_t total = 0;
    for (uint32_t i = 0; i < s->model_count; i++) {
        uint64_t n = 0;
        vx_error err = {0};
        vx_result r = vx_svo_decode_model(&s->models[i], count_cell, &n, &err);
        EXPECT(r == VX_OK, "%s model %u: %s", what, i, err.msg);
        EXPECT(n == s->models[i].voxel_count, "%s model %u: %llu decoded, voxel_count %llu", what, i,
               (unsigned long long)n, (unsigned long long)s->models[i].voxel_count);
        total += n;
    }
    return total;
}

/* Distinct cells of a .vox model (its XYZI chunk may repeat a cell). */
static uint64_t vox_distinct(const vx_vox_model* m) {
    size_t cells = (size_t)m->size[0] * m->size[1] * m->size[2];
    uint8_t* seen = calloc(cells ? cells : 1, 1);
    if (!seen) return 0;
    uint64_t n = 0;
    for (uint32_t v = 0; v < m->voxel_count; v++) {
        const uint8_t* p = m->xyzi + 4 * (size_t)v;
        size_t k = ((size_t)p[2] * m->size[1] + p[1]) * m->size[0] + p[0];
        if (!seen[k]) seen[k] = 1, n++;
    }
    free(seen);
    return n;
}

/* A one-model scene of its own: a ball of radius 6 in a 16^3 model, colours
 * by height. */
static int write_own_vox(const char* path) {
    vx_vox_scene s;
    memset(&s, 0, sizeof s);
    s.version = 150;
    s.model_count = 1;
    s.models = calloc(1, sizeof *s.models);
    s.instance_count = 1;
    s.instances = calloc(1, sizeof *s.instances);
    if (!s.models || !s.instances) return 1;
    vx_vox_model* m = &s.models[0];
    m->size[0] = m->size[1] = m->size[2] = 16;
    m->xyzi = malloc(4 * 16 * 16 * 16);
    if (!m->xyzi) return 1;
    for (int z = 0; z < 16; z++)
        for (int y = 0; y < 16; y++)
            for (int x = 0; x < 16; x++) {
                int dx = 2 * x - 15, dy = 2 * y - 15, dz = 2 * z - 15;
                if (dx * dx + dy * dy + dz * dz > 4 * 36) continue;
                uint8_t* p = m->xyzi + 4 * (size_t)m->voxel_count++;
                p[0] = (uint8_t)x, p[1] = (uint8_t)y, p[2] = (uint8_t)z, p[3] = (uint8_t)(1 + z);
            }
    const int32_t id[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    memcpy(s.instances[0].rot, id, sizeof id);
    s.instances[0].layer = -1;
    memcpy(s.palette, vx_vox_default_palette, sizeof s.palette);
    vx_error err = {0};
    vx_result r = vx_vox_write_file(NULL, &s, path, &err);
    vx_vox_scene_free(&s);
    if (r != VX_OK) {
        fprintf(stderr, "consumer: %s: %s\n", path, err.msg);
        return 1;
    }
    return 0;
}

static void check_vox(const char* in, const char* workdir) {
    vx_vox_scene vox;
    vx_error err = {0};
    if (vx_vox_read_file(NULL, in, &vox, &err) != VX_OK) {
        EXPECT(0, "%s: %s", in, err.msg);
        return;
    }
    vx_svo_scene svo;
    vx_conv_vox_desc desc = {.keep_unused = true}; /* one svo model per vox model, same order */
    vx_conv_stats stats;
    if (vx_conv_vox(&desc, &vox, &svo, &stats, &err) != VX_OK) {
        EXPECT(0, "%s: %s", in, err.msg);
        vx_vox_scene_free(&vox);
        return;
    }
    EXPECT(svo.model_count == vox.model_count, "%u svo models, %u vox models", svo.model_count, vox.model_count);
    EXPECT(svo.instance_count == vox.instance_count, "%u svo instances, %u vox instances", svo.instance_count,
           vox.instance_count);
    uint64_t stored = 0;
    for (uint32_t i = 0; i < svo.model_count && i < vox.model_count; i++) {
        uint64_t want = vox_distinct(&vox.models[i]);
        EXPECT(svo.models[i].voxel_count == want, "%s model %u: %llu voxels, the .vox model has %llu", in, i,
               (unsigned long long)svo.models[i].voxel_count, (unsigned long long)want);
        stored += want;
    }
    uint64_t decoded = decoded_voxels(&svo, in);

    char path[4096];
    snprintf(path, sizeof path, "%s/consumer.svo", workdir);
    EXPECT(vx_svo_write_file(NULL, &svo, path, &err) == VX_OK, "%s: %s", path, err.msg);
    vx_svo_scene back;
    if (vx_svo_read_file(NULL, path, &back, &err) == VX_OK) {
        EXPECT(vx_svo_validate_scene(&back, &err) == VX_OK, "%s: %s", path, err.msg);
        EXPECT(decoded_voxels(&back, path) == decoded, "%s: voxel count changed in the round trip", path);
        vx_svo_scene_free(&back);
    } else {
        EXPECT(0, "%s: %s", path, err.msg);
    }
    printf("%s: %u models, %u instances, %llu voxels (the .vox models store %llu)\n", in, svo.model_count,
           svo.instance_count, (unsigned long long)decoded, (unsigned long long)stored);
    vx_svo_scene_free(&svo);
    vx_vox_scene_free(&vox);
}

#ifdef HAVE_IMAGE
/* A 5x3 image of `type` (RGB) written to WORKDIR/image.EXT and read back: the same values. */
static void check_image(const char* workdir, const char* ext, vx_image_type type) {
    char path[4096];
    snprintf(path, sizeof path, "%s/image.%s", workdir, ext);
    enum { W = 5, H = 3, C = 3 };
    uint8_t u8[W * H * C];
    float f32[W * H * C];
    for (int i = 0; i < W * H * C; i++) u8[i] = (uint8_t)(i * 17 + 3), f32[i] = 0.25f * (float)i - 1.5f;
    vx_error err = {0};
    vx_image_desc d = {.width = W, .height = H, .channels = C, .type = type};
    d.pixels = type == VX_IMAGE_F32 ? (const void*)f32 : (const void*)u8;
    if (vx_image_write(path, &d, &err) != VX_OK) {
        if (strstr(err.msg, "built without OpenImageIO")) {
            printf("%s: this libvoxkit has no OpenImageIO, skipped\n", path);
        } else {
            EXPECT(0, "%s: %s", path, err.msg);
        }
        return;
    }
    uint32_t w = 0, h = 0, c = 0;
    void* px = NULL;
    if (vx_image_read(path, type, 0, &w, &h, &c, &px, &err) != VX_OK) {
        EXPECT(0, "%s: read back: %s", path, err.msg);
        return;
    }
    EXPECT(w == W && h == H && c == C, "%s: read back %ux%ux%u", path, w, h, c);
    size_t bytes = (size_t)W * H * C * (type == VX_IMAGE_F32 ? sizeof(float) : 1);
    if (w == W && h == H && c == C) EXPECT(memcmp(px, d.pixels, bytes) == 0, "%s: other values read back", path);
    printf("%s: written and read back through the library\n", path);
    vx_free(NULL, px);
}
#endif

int main(int argc, char** argv) {
    if (argc < 2) {
        fprintf(stderr, "usage: consumer WORKDIR [IN.vox [IN.glb [IN.vdb]]]\n");
        return 2;
    }
    const char* workdir = argv[1];
    printf("voxkit %s (headers %s, VX_VERSION %d)\n", vx_version(), VX_VERSION_STRING, VX_VERSION);
    EXPECT(strcmp(vx_version(), VX_VERSION_STRING) == 0, "library %s, headers %s", vx_version(), VX_VERSION_STRING);
    EXPECT(VX_VERSION == VX_VERSION_MAJOR * 10000 + VX_VERSION_MINOR * 100 + VX_VERSION_PATCH, "VX_VERSION %d",
           VX_VERSION);

    char own[4096];
    const char* vox = argc > 2 && strcmp(argv[2], "-") != 0 ? argv[2] : NULL;
    if (!vox) {
        snprintf(own, sizeof own, "%s/own.vox", workdir);
        if (write_own_vox(own) != 0) return 1;
        vox = own;
    }
    check_vox(vox, workdir);

    const char* glb = argc > 3 && strcmp(argv[3], "-") != 0 ? argv[3] : NULL;
    const char* vdb = argc > 4 && strcmp(argv[4], "-") != 0 ? argv[4] : NULL;
#ifdef HAVE_MESH
    if (glb) {
        vx_error err = {0};
        vx_svo_scene s;
        vx_conv_mesh_desc d = {.res = 32, .threads = 2};
        if (vx_conv_mesh_file(&d, glb, &s, NULL, &err) == VX_OK) {
            uint64_t n = decoded_voxels(&s, glb);
            EXPECT(n > 0, "%s: no voxels", glb);
            printf("%s: %u models, %llu voxels at --res 32\n", glb, s.model_count, (unsigned long long)n);
            vx_svo_scene_free(&s);
        } else {
            EXPECT(0, "%s: %s", glb, err.msg);
        }
    }
#else
    if (glb) printf("%s: this libvoxkit has no glTF reader, skipped\n", glb);
#endif
#ifdef HAVE_VDB
    if (vdb) {
        vx_error err = {0};
        vx_svo_scene s;
        vx_conv_vdb_desc d = {0};
        if (vx_conv_vdb_file(&d, vdb, &s, NULL, &err) == VX_OK) {
            uint64_t n = decoded_voxels(&s, vdb);
            EXPECT(n > 0, "%s: no voxels", vdb);
            printf("%s: %u models, %llu voxels\n", vdb, s.model_count, (unsigned long long)n);
            vx_svo_scene_free(&s);
        } else {
            EXPECT(0, "%s: %s", vdb, err.msg);
        }
    }
#else
    if (vdb) printf("%s: this libvoxkit has no OpenVDB reader, skipped\n", vdb);
#endif
#ifdef HAVE_IMAGE
    check_image(workdir, "png", VX_IMAGE_U8);
    check_image(workdir, "exr", VX_IMAGE_F32);
#endif
    if (failures) fprintf(stderr, "consumer: %d checks failed\n", failures);
    return failures ? 1 : 0;
}
