/* The image files of builds without OpenImageIO (formats/image_pnm.c):
 * .pfm/.ppm/.pgm written byte for byte as the formats specify (header, PFM's
 * bottom-up rows, little-endian floats), read back to the same bits, and
 * every malformed or unsupported input refused with a message, no output. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdint.h>
#include <unistd.h>

#include "formats/image.h"
#include "tests/test.h"

static char dir[256];

static char* path_of(const char* name) {
    static char p[512];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    return p;
}

static size_t slurp(const char* path, uint8_t* buf, size_t cap) {
    FILE* f = fopen(path, "rb");
    if (!f) return 0;
    size_t n = fread(buf, 1, cap, f);
    fclose(f);
    return n;
}

static void spill(const char* path, const void* d, size_t n) {
    FILE* f = fopen(path, "wb");
    fwrite(d, 1, n, f);
    fclose(f);
}

static void test_pfm_round_trip(void) {
    /* 3 x 2 RGB with the values floats hide bits in: -0, NaN, inf, denormals */
    float px[18] = {0.0f, -0.0f, 1.0f, NAN, INFINITY, -INFINITY, 1e-40f, 0.5f, 3.25f,
                    -1.0f, 65504.0f, 1e30f, 0.1f, 0.2f, 0.3f, 7.0f, 8.0f, 9.0f};
    vx_error e = {0};
    const char* p = path_of("a.pfm");
    REQUIRE(vx_image_write(p, &(vx_image_desc){3, 2, 3, VX_IMAGE_F32, px}, &e) == VX_OK);
    uint8_t raw[256];
    size_t n = slurp(p, raw, sizeof raw);
    const char* head = "PF\n3 2\n-1.0\n";
    size_t hn = strlen(head);
    REQUIRE(n == hn + sizeof px);
    CHECK(!memcmp(raw, head, hn));
    /* the file's first row is the image's last (row 1: px[9..17]), little-endian */
    uint32_t bits;
    memcpy(&bits, &px[9], 4);
    CHECK(raw[hn] == (bits & 0xFF) && raw[hn + 3] == bits >> 24);
    CHECK(!memcmp(raw + hn, px + 9, 36) && !memcmp(raw + hn + 36, px, 36));
    uint32_t w, h, c;
    float* back = NULL;
    REQUIRE(vx_image_read(p, VX_IMAGE_F32, 0, &w, &h, &c, (void**)&back, &e) == VX_OK);
    CHECK(w == 3 && h == 2 && c == 3);
    CHECK(!memcmp(back, px, sizeof px)); /* the same bits, NaN and -0 included */
    vx_free(NULL, back);

    float g[4] = {1, 2, 3, 4};
    p = path_of("g.pfm");
    REQUIRE(vx_image_write(p, &(vx_image_desc){2, 2, 1, VX_IMAGE_F32, g}, &e) == VX_OK);
    n = slurp(p, raw, sizeof raw);
    CHECK(n == strlen("Pf\n2 2\n-1.0\n") + 16 && !memcmp(raw, "Pf\n2 2\n-1.0\n", 12));
    REQUIRE(vx_image_read(p, VX_IMAGE_F32, 0, &w, &h, &c, (void**)&back, &e) == VX_OK);
    CHECK(w == 2 && h == 2 && c == 1 && !memcmp(back, g, sizeof g));
    vx_free(NULL, back);
}

static void test_pixmaps(void) {
    uint8_t rgb[2 * 2 * 3] = {0, 1, 2, 3, 4, 5, 250, 251, 252, 253, 254, 255};
    vx_error e = {0};
    const char* p = path_of("a.ppm");
    REQUIRE(vx_image_write(p, &(vx_image_desc){2, 2, 3, VX_IMAGE_U8, rgb}, &e) == VX_OK);
    uint8_t raw[64];
    size_t n = slurp(p, raw, sizeof raw);
    REQUIRE(n == 11 + 12);
    CHECK(!memcmp(raw, "P6\n2 2\n255\n", 11) && !memcmp(raw + 11, rgb, 12)); /* top row first */
    uint32_t w, h, c;
    uint8_t* back = NULL;
    REQUIRE(vx_image_read(p, VX_IMAGE_U8, 0, &w, &h, &c, (void**)&back, &e) == VX_OK);
    CHECK(w == 2 && h == 2 && c == 3 && !memcmp(back, rgb, 12));
    vx_free(NULL, back);
    float* f = NULL;
    REQUIRE(vx_image_read(p, VX_IMAGE_F32, 0, &w, &h, &c, (void**)&f, &e) == VX_OK);
    CHECK(f[1] == 1 / 255.0f && f[11] == 1.0f);
    vx_free(NULL, f);
    /* comments and any whitespace between header tokens, as the format allows */
    const char* text = "P5 # a comment\n2\t1 # more\n255\n\x07\x09";
    spill(path_of("c.pgm"), text, strlen(text));
    REQUIRE(vx_image_read(path_of("c.pgm"), VX_IMAGE_U8, 0, &w, &h, &c, (void**)&back, &e) == VX_OK);
    CHECK(w == 2 && h == 1 && c == 1 && back[0] == 7 && back[1] == 9);
    vx_free(NULL, back);
}

static void refused_write(const char* name, vx_image_desc d, const char* words) {
    vx_error e = {0};
    CHECKF(vx_image_write(path_of(name), &d, &e) != VX_OK, "%s written", name);
    CHECKF(strstr(e.msg, name) && strstr(e.msg, words), "%s: message '%s'", name, e.msg);
    CHECKF(access(path_of(name), F_OK) != 0, "%s: a file was left", name);
}

static void refused_read(const char* name, const void* d, size_t n, const char* words) {
    spill(path_of(name), d, n);
    vx_error e = {0};
    uint32_t w, h, c;
    void* px = (void*)1;
    CHECKF(vx_image_read(path_of(name), VX_IMAGE_F32, 64, &w, &h, &c, &px, &e) != VX_OK, "%s read", name);
    CHECKF(px == NULL, "%s: pixels returned", name);
    CHECKF(strstr(e.msg, name) && strstr(e.msg, words), "%s: message '%s'", name, e.msg);
}

static void test_refused(void) {
    float f4[16] = {0};
    uint8_t u[16] = {0};
#ifndef VX_TEST_OIIO
    refused_write("x.png", (vx_image_desc){2, 2, 3, VX_IMAGE_U8, u}, "OpenImageIO");
#endif
    refused_write("x.pfm", (vx_image_desc){2, 2, 4, VX_IMAGE_F32, f4}, "4 channels");
    refused_write("y.ppm", (vx_image_desc){2, 2, 3, VX_IMAGE_F32, f4}, ".pfm");
    refused_write("z.pfm", (vx_image_desc){2, 2, 1, VX_IMAGE_U8, u}, ".ppm");
    refused_write("w.pgm", (vx_image_desc){2, 2, 3, VX_IMAGE_U8, u}, "3 channels");

    const char trunc[] = "PF\n2 2\n-1.0\n0123456789";
    refused_read("t.pfm", trunc, sizeof trunc - 1, "bytes of pixels");
    const char big[] = "PF\n2 2\n1.0\n0123456789abcdef0123456789abcdef0123456789abcdef";
    refused_read("b.pfm", big, sizeof big - 1, "little-endian");
    const char magic[] = "P3\n1 1\n255\n1 2 3";
    refused_read("m.ppm", magic, sizeof magic - 1, "magic");
    const char wide[] = "P5\n65 1\n255\n";
    refused_read("d.pgm", wide, sizeof wide - 1, "limits");
    const char deep[] = "P5\n1 1\n65535\n\0\0";
    refused_read("e.pgm", deep, sizeof deep - 1, "8-bit");
    const char huge[] = "P5\n99999999999 1\n255\n";
    refused_read("f.pgm", huge, sizeof huge - 1, "header");
    refused_read("g.pgm", "P5\n", 3, "header");
    refused_read("h.pgm", "", 0, "");
}

/* With OpenImageIO: the same float pixels through its EXR writer and reader
 * (an independent implementation) and through ours as .pfm agree bit for bit. */
static void test_against_exr(void) {
#ifdef VX_TEST_OIIO
    enum { W = 17, H = 5 };
    float px[W * H * 3];
    for (int i = 0; i < W * H * 3; i++) px[i] = (float)(i * 0.37 - 3.0) / (float)(1 + i % 7);
    vx_error e = {0};
    REQUIRE(vx_image_write(path_of("s.exr"), &(vx_image_desc){W, H, 3, VX_IMAGE_F32, px}, &e) == VX_OK);
    REQUIRE(vx_image_write(path_of("s.pfm"), &(vx_image_desc){W, H, 3, VX_IMAGE_F32, px}, &e) == VX_OK);
    uint32_t w1, h1, c1, w2, h2, c2;
    float *a = NULL, *b = NULL;
    REQUIRE(vx_image_read(path_of("s.exr"), VX_IMAGE_F32, 0, &w1, &h1, &c1, (void**)&a, &e) == VX_OK);
    REQUIRE(vx_image_read(path_of("s.pfm"), VX_IMAGE_F32, 0, &w2, &h2, &c2, (void**)&b, &e) == VX_OK);
    CHECK(w1 == W && h1 == H && c1 == 3 && w2 == W && h2 == H && c2 == 3);
    CHECK(!memcmp(a, b, sizeof px) && !memcmp(a, px, sizeof px));
    vx_free(NULL, a);
    vx_free(NULL, b);
#else
    SKIP("built without OpenImageIO");
#endif
}

int main(void) {
    snprintf(dir, sizeof dir, "/tmp/vx_test_image_pnm.%d", (int)getpid());
    char cmd[300];
    snprintf(cmd, sizeof cmd, "mkdir -p %s", dir);
    if (system(cmd) != 0) return 1;
    RUN(test_pfm_round_trip);
    RUN(test_pixmaps);
    RUN(test_refused);
    RUN(test_against_exr);
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    if (system(cmd) != 0) return 1;
    return vx_test_finish();
}
