#include <dlfcn.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "tests/probes/probe_scenes.h"
#include "tests/test.h"
enum { N = 16, W = 40, H = 30 };
static uint8_t pane_cell(uint32_t x, uint32_t y, uint32_t z, uint32_t n) {
    (void)n;
    if (x >= 14 && y >= 8 && y <= 9 && z >= 1 && z <= 2) return 9;
    if (z == 0) return 3;
    if (y == N - 1) return 4;
    return 0;
}
int main(int argc, char** argv) {
    int spp = argc > 1 ? atoi(argv[1]) : 256, mode = argc > 2 ? atoi(argv[2]) : 0;
    unsigned seed = argc > 3 ? atoi(argv[3]) : 7;
    dlopen("libvulkan_lvp.so", RTLD_NOW | RTLD_NODELETE);
    vx_error err = {0};
    vx_gpu* gpu;
    if (vx_gpu_create(&(vx_gpu_desc){0}, &gpu, &err)) return 1;
    vx_svo_scene s;
    cells_scene(&s, N, pane_cell);
    s.palette[3] = 0xFF909090u, s.palette[4] = 0xFFC8C8C8u, s.palette[9] = 0xFFFFFFFFu;
    const char* const emit[] = {"_type", "_emit", "_emit", "4", "_flux", "1"};
    add_material(&s, 9, emit, 3);
    vx_render_scene* rs = NULL;
    vx_probe_set ps = {0};
    if (vx_render_scene_create(gpu, &s, &rs, &err)) return 2;
    vx_probe_bake_desc bd = {.grid = {4, 4, 4}, .res = 32, .spp = 64, .bounces = 1, .seed = 5, .no_sun = true, .black_sky = true};
    if (vx_probe_bake_gpu(rs, &s, &bd, &ps, &err)) return 3;
    vx_render_desc base = {.width = W, .height = H};
    base.camera.set = true;
    double eye[3] = {8, -10, 5}, at[3] = {8, 15, 5};
    memcpy(base.camera.eye, eye, sizeof eye), memcpy(base.camera.target, at, sizeof at);
    vx_probe_render_mode m = mode == 0 ? VX_PROBE_RENDER_LF_INDIRECT : mode == 1 ? VX_PROBE_RENDER_LIGHTFIELD : mode == 2 ? VX_PROBE_RENDER_INDIRECT : VX_PROBE_RENDER_PT_INDIRECT;
    vx_probe_render_desc rd = {.base = &base, .mode = m, .spp = spp, .seed = seed, .threads = 2, .pixel_centre = true};
    vx_render_image c = {0}, g = {0};
    if (vx_probe_render(&s, &ps, &rd, &c, &err)) { fprintf(stderr, "%s\n", err.msg); return 4; }
    if (vx_probe_render_gpu(rs, &s, &ps, &rd, &g, &err)) { fprintf(stderr, "%s\n", err.msg); return 5; }
    double sc = 0, sg = 0, C3[3] = {0}, G3[3] = {0};
    FILE* f = fopen("diff.txt", "w");
    for (int y = 0; y < H; y++) {
        for (int x = 0; x < W; x++) {
            double a = c.pixels[4 * (y * W + x)], b = g.pixels[4 * (y * W + x)];
            sc += a, sg += b; for (int k = 0; k < 3; k++) C3[k] += c.pixels[4 * (y * W + x) + k], G3[k] += g.pixels[4 * (y * W + x) + k];
            fprintf(f, "%d %d %.5f %.5f\n", x, y, a, b);
        }
    }
    fclose(f);
    printf("mode %d spp %d seed %u: CPU %.5f GPU %.5f ratio %.4f\n", mode, spp, seed, sc / (W * H), sg / (W * H), sg / sc);
    printf("CPU %.5f %.5f %.5f  GPU %.5f %.5f %.5f\n", C3[0]/(W*H), C3[1]/(W*H), C3[2]/(W*H), G3[0]/(W*H), G3[1]/(W*H), G3[2]/(W*H));
    printf("CPU %.5f %.5f %.5f  GPU %.5f %.5f %.5f\n", C3[0]/(W*H), C3[1]/(W*H), C3[2]/(W*H), G3[0]/(W*H), G3[1]/(W*H), G3[2]/(W*H));
    return 0;
}
