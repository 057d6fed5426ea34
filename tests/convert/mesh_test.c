/* tests/convert/mesh_test.c - the mesh voxelizer against a brute-force
 * reference: every cell of the grid tested against every triangle with the
 * separating-axis test (Akenine-Moeller: 13 axes, projections of all 8 box
 * corners and 3 vertices, double precision) - a code path independent of
 * the voxelizer's slab clipping. Only the grid definition
 * (vx_conv_mesh_grid_make and g = (p - min) / h) is shared, because it is
 * the specification. The cells are half-open (convert/mesh.h): the
 * reference shrinks each box's max faces by an infinitesimal eps (closed
 * box [c, c+1-eps]; the grid's last cell keeps its max face), carried
 * symbolically as (value, eps coefficient) pairs. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "convert/mesh.h"
#include "convert/mesh_internal.h"
#include "formats/gltf.h"
#include "tests/test.h"

/* ---- reference ----------------------------------------------------------------- */

static void cross3(const double* a, const double* b, double* o) {
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

/* Triangle t vs the box at lo: [lo, lo+1) per axis, or [lo, lo+1] along
 * axis a when closed[a] (the grid's last cell); closed == NULL: closed box.
 * Corner k projects to p0 - eps p1 on an axis; they intersect iff no axis
 * separates them for every small enough eps > 0. */
static bool sat_overlap(const double* t, const double* lo, const bool* closed) {
    double e[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, f[3][3], axes[13][3];
    int na = 0;
    for (int k = 0; k < 3; k++)
        for (int c = 0; c < 3; c++) f[k][c] = t[3 * ((k + 1) % 3) + c] - t[3 * k + c];
    for (int k = 0; k < 3; k++) memcpy(axes[na++], e[k], sizeof axes[0]);
    cross3(f[0], f[1], axes[na++]);
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) cross3(e[a], f[b], axes[na++]);
    for (int x = 0; x < na; x++) {
        const double* A = axes[x];
        double tmin = INFINITY, tmax = -INFINITY;
        for (int v = 0; v < 3; v++) {
            double p = A[0] * t[3 * v] + A[1] * t[3 * v + 1] + A[2] * t[3 * v + 2];
            tmin = fmin(tmin, p);
            tmax = fmax(tmax, p);
        }
        /* box extremes, lexicographic in (p0, -eps p1) */
        double b0 = INFINITY, b1 = 0, B0 = -INFINITY, B1 = 0;
        for (int c = 0; c < 8; c++) {
            double p0 = 0, p1 = 0;
            for (int k = 0; k < 3; k++) {
                int bit = (c >> k) & 1;
                p0 += A[k] * (lo[k] + bit);
                if (bit && closed && !closed[k]) p1 += A[k];
            }
            if (p0 < b0 || (p0 == b0 && p1 > b1)) { b0 = p0; b1 = p1; }
            if (p0 > B0 || (p0 == B0 && p1 < B1)) { B0 = p0; B1 = p1; }
        }
        if (tmax < b0 || (tmax == b0 && b1 < 0)) return false;
        if (tmin > B0 || (tmin == B0 && B1 > 0)) return false;
    }
    return true;
}

static size_t cell_index(const vx_conv_mesh_grid* g, uint32_t x, uint32_t y, uint32_t z) {
    return x + (size_t)g->size[0] * (y + (size_t)g->size[1] * z);
}

/* Bitmap of the reference cells. Every cell of the grid is visited for every
 * triangle; the SAT's three box axes come first so that separated cells cost
 * one comparison. */
static uint8_t* reference(const vx_gltf_mesh* m, const vx_conv_mesh_grid* g) {
    size_t n = (size_t)g->size[0] * g->size[1] * g->size[2];
    uint8_t* bits = (uint8_t*)calloc(n, 1);
    for (size_t t = 0; t < m->tri_count; t++) {
        double v[9], lo[3], hi[3];
        for (int k = 0; k < 9; k++) v[k] = ((double)m->pos[9 * t + k] - g->min[k % 3]) / g->h;
        for (int a = 0; a < 3; a++) {
            lo[a] = fmin(fmin(v[a], v[3 + a]), v[6 + a]);
            hi[a] = fmax(fmax(v[a], v[3 + a]), v[6 + a]);
        }
        for (uint32_t z = 0; z < g->size[2]; z++) {
            if (z + 1.0 < lo[2] || z > hi[2]) continue;
            for (uint32_t y = 0; y < g->size[1]; y++) {
                if (y + 1.0 < lo[1] || y > hi[1]) continue;
                for (uint32_t x = 0; x < g->size[0]; x++) {
                    if (x + 1.0 < lo[0] || x > hi[0]) continue;
                    double c[3] = {x, y, z};
                    bool closed[3] = {x + 1 == g->size[0], y + 1 == g->size[1], z + 1 == g->size[2]};
                    if (sat_overlap(v, c, closed)) bits[cell_index(g, x, y, z)] = 1;
                }
            }
        }
    }
    return bits;
}

/* Voxelizes with desc and compares with the reference; returns mismatches. */
static size_t compare(const vx_gltf_mesh* m, vx_conv_mesh_desc desc, size_t* cells_out) {
    vx_conv_mesh_grid g;
    uint32_t* xyz = NULL;
    size_t count = 0;
    vx_error err = {0};
    vx_result r = vx_conv_mesh_cells(&desc, m, &g, &xyz, NULL, &count, &err);
    CHECKF(r == VX_OK, "%s", err.msg);
    if (r) return SIZE_MAX;
    uint8_t* ref = reference(m, &g);
    size_t n = (size_t)g.size[0] * g.size[1] * g.size[2];
    uint8_t* got = (uint8_t*)calloc(n, 1);
    size_t bad = 0, shown = 0;
    for (size_t i = 0; i < count; i++) {
        uint32_t x = xyz[3 * i], y = xyz[3 * i + 1], z = xyz[3 * i + 2];
        if (x >= g.size[0] || y >= g.size[1] || z >= g.size[2]) { bad++; continue; }
        size_t c = cell_index(&g, x, y, z);
        if (got[c]) bad++; /* duplicate */
        got[c] = 1;
    }
    for (size_t c = 0; c < n; c++)
        if (got[c] != ref[c]) {
            if (shown++ < 5)
                fprintf(stderr, "  cell %zu %zu %zu: voxelizer %d reference %d\n", c % g.size[0],
                        (c / g.size[0]) % g.size[1], c / ((size_t)g.size[0] * g.size[1]), got[c], ref[c]);
            bad++;
        }
    if (cells_out) *cells_out = count;
    free(ref);
    free(got);
    free(xyz);
    return bad;
}

/* ---- meshes ---------------------------------------------------------------------- */

static vx_gltf_mesh soup(const float* pos, size_t tris) {
    vx_gltf_mesh m;
    memset(&m, 0, sizeof m);
    m.tri_count = tris;
    m.pos = (float*)pos;
    return m;
}

static void quad(float* out, const float* a, const float* b, const float* c, const float* d) {
    const float* v[6] = {a, b, c, a, c, d};
    for (int i = 0; i < 6; i++) memcpy(out + 3 * i, v[i], 12);
}

/* 12 triangles of the box [lo, hi]; skip: a triangle index left out (hole), -1 none */
static size_t box(float* out, const float* lo, const float* hi, int skip) {
    float c[8][3];
    for (int i = 0; i < 8; i++)
        for (int a = 0; a < 3; a++) c[i][a] = (i >> a) & 1 ? hi[a] : lo[a];
    static const int f[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
    float tmp[36 * 3];
    for (int i = 0; i < 6; i++) quad(tmp + 18 * i, c[f[i][0]], c[f[i][1]], c[f[i][2]], c[f[i][3]]);
    size_t n = 0;
    for (int t = 0; t < 12; t++) {
        if (t == skip) continue;
        memcpy(out + 9 * n, tmp + 9 * t, 36);
        n++;
    }
    return n;
}

static uint64_t rng_s = 0x243F6A8885A308D3ull;
static double rnd(void) {
    rng_s ^= rng_s << 13;
    rng_s ^= rng_s >> 7;
    rng_s ^= rng_s << 17;
    return (double)(rng_s >> 11) / 9007199254740992.0;
}

/* ---- tests ------------------------------------------------------------------------- */

static void load(const char* rel, vx_gltf_mesh* m, bool* ok) {
    *ok = false;
    const char* p = vx_test_corpus(rel);
    if (!p) return;
    vx_error err = {0};
    vx_result r = vx_gltf_read_file(&(vx_gltf_read_desc){0}, p, m, &err);
    CHECKF(r == VX_OK, "%s: %s", rel, err.msg);
    *ok = r == VX_OK;
}

static void test_corpus_box(void) {
    vx_gltf_mesh m;
    bool ok;
    load("gltf/tinygltf_box01.glb", &m, &ok);
    if (!ok) SKIP("corpus gltf/tinygltf_box01.glb not found");
    CHECK(m.tri_count == 12);
    for (uint32_t res = 16; res <= 128; res *= 2) {
        size_t cells = 0, bad = compare(&m, (vx_conv_mesh_desc){.res = res}, &cells);
        CHECKF(bad == 0, "box01 res %u: %zu mismatches of %zu cells", res, bad, cells);
        CHECK(cells > 0);
    }
    vx_gltf_mesh_free(&m);
}

static void test_corpus_duck(void) {
    vx_gltf_mesh m;
    bool ok;
    load("gltf/julian_Duck.glb", &m, &ok);
    if (!ok) SKIP("corpus gltf/julian_Duck.glb not found");
    CHECK(m.tri_count == 4212);
    CHECK(m.uv != NULL);
    static const uint32_t res[] = {16, 27, 48};
    for (int i = 0; i < 3; i++) {
        size_t cells = 0, bad = compare(&m, (vx_conv_mesh_desc){.res = res[i]}, &cells);
        CHECKF(bad == 0, "duck res %u: %zu mismatches of %zu cells", res[i], bad, cells);
    }
    vx_gltf_mesh_free(&m);
}

/* Faces exactly on cell boundaries set one layer: the cells on their +
 * side (half-open cells), or the last cell at the grid's max bound. */
static void test_boundary_faces(void) {
    float pos[9 * 40];
    float lo[3] = {0, 0, 0}, hi[3] = {8, 8, 8};
    size_t n = box(pos, lo, hi, -1);
    /* an inner quad on the plane x = 3 (a cell boundary at res 8), y,z in [2, 5] */
    float a[3] = {3, 2, 2}, b[3] = {3, 5, 2}, c[3] = {3, 5, 5}, d[3] = {3, 2, 5};
    quad(pos + 9 * n, a, b, c, d);
    n += 2;
    vx_gltf_mesh m = soup(pos, n);
    size_t cells = 0;
    CHECK(compare(&m, (vx_conv_mesh_desc){.res = 8}, &cells) == 0);
    /* hand count: the box shell fills the 8^3 grid's outer layer (the min
     * faces set layer 0, the max faces lie on the grid's max bound and set
     * its last layer); the inner quad sets x = 3 for y, z in [2, 5] (cells
     * [2, 3) .. [5, 6) meet the closed quad; [1, 2) does not) */
    uint32_t* xyz = NULL;
    size_t count = 0;
    REQUIRE(vx_conv_mesh_cells(&(vx_conv_mesh_desc){.res = 8}, &m, NULL, &xyz, NULL, &count, NULL) == VX_OK);
    size_t shell = 8 * 8 * 8 - 6 * 6 * 6, inner = 0;
    for (size_t i = 0; i < count; i++) {
        uint32_t x = xyz[3 * i], y = xyz[3 * i + 1], z = xyz[3 * i + 2];
        bool on_shell = x == 0 || y == 0 || z == 0 || x == 7 || y == 7 || z == 7;
        if (!on_shell) inner++;
        if (!on_shell) CHECK(x == 3 && y >= 2 && y <= 5 && z >= 2 && z <= 5);
    }
    CHECK(count == shell + inner);
    CHECK(inner == 4 * 4); /* one layer, x = 3 */
    free(xyz);
    /* the same at other resolutions and with the box off the origin */
    for (uint32_t res = 16; res <= 64; res *= 2) {
        float lo2[3] = {-4, 2, 6}, hi2[3] = {12, 10, 10};
        size_t k = box(pos, lo2, hi2, -1);
        float p[4][3] = {{-4, 6, 6}, {12, 6, 6}, {12, 6, 10}, {-4, 6, 10}}; /* plane y = 6 */
        quad(pos + 9 * k, p[0], p[1], p[2], p[3]);
        vx_gltf_mesh m2 = soup(pos, k + 2);
        CHECKF(compare(&m2, (vx_conv_mesh_desc){.res = res}, NULL) == 0, "res %u", res);
    }
}

/* A bottle of our own: a profile (r, y) revolved in segs segments, float
 * positions. Flat bottom at y0 (the grid's lower bound), wall, a flat
 * shoulder step at y_step (normal +y), neck, flat cap at y1 (the upper
 * bound); radii scale with the height y1 - y0 (0.26044 gives the held-out
 * bottle's 0.0544 units). */
static size_t bottle(float* out, int segs, double y0, double y1, double y_step) {
    double s = (y1 - y0) / 0.260440678, R = 0.05445001 * s;
    const double prof[][2] = {{0, y0},          {0.05 * s, y0},  {R, y0 + 0.005 * s}, {R, y_step}, {0.03 * s, y_step},
                              {0.02 * s, y_step + 0.02 * s}, {0.02 * s, y1}, {0, y1}};
    const int np = (int)(sizeof prof / sizeof prof[0]);
    size_t n = 0;
    for (int i = 0; i < segs; i++) {
        double a0 = 6.283185307179586 * i / segs, a1 = 6.283185307179586 * (i + 1) / segs;
        for (int j = 0; j + 1 < np; j++) {
            float p[4][3];
            for (int k = 0; k < 4; k++) {
                double r = prof[j + (k >> 1)][0], a = k & 1 ? a1 : a0;
                p[k][0] = (float)(r * cos(a));
                p[k][1] = (float)prof[j + (k >> 1)][1];
                p[k][2] = (float)(r * sin(a));
            }
            const float* t[2][3] = {{p[0], p[1], p[3]}, {p[0], p[3], p[2]}};
            for (int q = 0; q < 2; q++) {
                if (prof[j + q][0] == 0) continue; /* on the axis: a fan */
                for (int v = 0; v < 3; v++) memcpy(out + 9 * n + 3 * v, t[q][v], 12);
                n++;
            }
        }
    }
    return n;
}

/* Is the square of cells (x, z) wholly between radii f0 and f1 (fractions
 * of the bottle's height) of the bottle's axis? */
static bool square_in_ring(const vx_conv_mesh_grid* g, uint32_t x, uint32_t z, double f0, double f1, double height) {
    for (int c = 0; c < 4; c++) {
        double px = g->min[0] + (x + (c & 1)) * g->h, pz = g->min[2] + (z + (c >> 1)) * g->h;
        double r = sqrt(px * px + pz * pz) / height * 0.260440678;
        if (r <= f0 || r >= f1) return false;
    }
    return true;
}

/* Each flat face sets exactly one layer: squares wholly inside the bottom
 * disc, the step ring and the cap are set in their layer, not in the next. */
static void check_layers(const vx_gltf_mesh* m, uint32_t res, uint32_t k_step, double height) {
    vx_conv_mesh_grid g;
    uint32_t* xyz = NULL;
    size_t count = 0;
    REQUIRE(vx_conv_mesh_cells(&(vx_conv_mesh_desc){.res = res}, m, &g, &xyz, NULL, &count, NULL) == VX_OK);
    uint8_t* got = (uint8_t*)calloc((size_t)g.size[0] * g.size[1] * g.size[2], 1);
    for (size_t i = 0; i < count; i++) got[cell_index(&g, xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2])] = 1;
    struct { uint32_t on, off; double r0, r1; } faces[3] = {
        {0, 1, 0, 0.0498}, {k_step, k_step - 1, 0.0301, 0.054}, {res - 1, res - 2, 0, 0.0199}};
    for (int f = 0; f < 3; f++) {
        if (f == 1 && !k_step) continue;
        size_t inside = 0, on = 0, off = 0;
        for (uint32_t z = 0; z < g.size[2]; z++)
            for (uint32_t x = 0; x < g.size[0]; x++) {
                if (!square_in_ring(&g, x, z, faces[f].r0, faces[f].r1, height)) continue;
                inside++;
                on += got[cell_index(&g, x, faces[f].on, z)];
                off += got[cell_index(&g, x, faces[f].off, z)];
            }
        CHECKF(inside > 4 && on == inside && off == 0, "res %u face %d: %zu squares, %zu set in layer %u, %zu in layer %u",
               res, f, inside, on, faces[f].on, off, faces[f].off);
    }
    free(got);
    free(xyz);
}

/* The held-out bottle's case: flat faces on the grid's lower and upper
 * bounds, cell size not exact in binary (0.260440678 / 96). Exact against
 * the reference, and the bounds are exact in exact arithmetic too: before,
 * h = L / 96 rounded down put the cap 1e-14 cells beyond the last layer,
 * and its 146 cells were set where an exact test leaves them empty. Then
 * the same bottle 24 units tall (h = 1/4 exactly) with its shoulder step on
 * the interior boundary y = 60: one layer there too. */
static void test_bottle(void) {
    enum { SEGS = 48 };
    static float pos[9 * 2 * 8 * SEGS];
    vx_gltf_mesh m = soup(pos, bottle(pos, SEGS, -0.130220339, 0.130220339, 0.0123));
    vx_conv_mesh_grid g;
    REQUIRE(vx_conv_mesh_grid_make(m.pos, m.tri_count, 96, &g, NULL) == VX_OK);
    CHECK(g.size[1] == 96 && g.size[0] == 41 && g.size[2] == 41);
    CHECK(g.min[1] == (double)-0.130220339f); /* the origin is the float minimum itself */
    /* exact bounds: the cap (y1 - y0, an exact difference of floats) lies within 96 cells */
    double L = (double)0.130220339f - (double)-0.130220339f, W = 2 * (double)(float)(0.05445001);
    CHECKF(fma(96.0, g.h, -L) >= 0, "96 h = %.17g < L = %.17g", 96 * g.h, L);
    CHECK(fma(95.0, g.h, -L) < 0);
    CHECK(fma(40.0, g.h, -W) < 0 && fma(41.0, g.h, -W) >= 0);
    static const uint32_t res[] = {96, 37, 100};
    for (int i = 0; i < 3; i++) {
        size_t cells = 0, bad = compare(&m, (vx_conv_mesh_desc){.res = res[i]}, &cells);
        CHECKF(bad == 0, "bottle res %u: %zu mismatches of %zu cells", res[i], bad, cells);
        check_layers(&m, res[i], 0, 0.260440678);
    }
    /* 24 units tall, step at y = -12 + 60 / 4 */
    m = soup(pos, bottle(pos, SEGS, -12, 12, 3));
    REQUIRE(vx_conv_mesh_grid_make(m.pos, m.tri_count, 96, &g, NULL) == VX_OK);
    REQUIRE(g.h == 0.25 && g.size[1] == 96);
    size_t cells = 0, bad = compare(&m, (vx_conv_mesh_desc){.res = 96}, &cells);
    CHECKF(bad == 0, "bottle 24 units: %zu mismatches of %zu cells", bad, cells);
    check_layers(&m, 96, 60, 24);
}

/* Slivers and zero-area triangles (segments, points). */
static void test_slivers_degenerate(void) {
    float pos[9 * 64];
    size_t n = 0;
    for (int i = 0; i < 20; i++) { /* thin slivers */
        float a[3], b[3], c[3];
        for (int k = 0; k < 3; k++) {
            a[k] = (float)(rnd() * 10);
            b[k] = (float)(rnd() * 10);
            c[k] = a[k] + (b[k] - a[k]) * 0.5f + (float)(rnd() * 1e-4);
        }
        memcpy(pos + 9 * n, a, 12);
        memcpy(pos + 9 * n + 3, b, 12);
        memcpy(pos + 9 * n + 6, c, 12);
        n++;
    }
    /* exactly collinear (a segment), and a point on a grid corner; bounds [0, 10] */
    float seg[9] = {1, 1, 1, 9, 5, 3, 5, 3, 2};
    float pt[9] = {5, 5, 5, 5, 5, 5, 5, 5, 5};
    float span[9] = {0, 0, 0, 10, 10, 10, 0, 0, 0}; /* fixes the bounds */
    memcpy(pos + 9 * n++, seg, 36);
    memcpy(pos + 9 * n++, pt, 36);
    memcpy(pos + 9 * n++, span, 36);
    vx_gltf_mesh m = soup(pos, n);
    for (uint32_t res = 16; res <= 128; res *= 2) {
        size_t cells = 0, bad = compare(&m, (vx_conv_mesh_desc){.res = res}, &cells);
        CHECKF(bad == 0, "slivers res %u: %zu mismatches of %zu", res, bad, cells);
    }
    /* the point alone: at res 10 it sits on the corner shared by 8 cells
     * and sets one of them, the one it is the min corner of */
    float only[27] = {5, 5, 5, 5, 5, 5, 5, 5, 5, 0, 0, 0, 0, 0, 0, 0, 0, 0, 10, 10, 10, 10, 10, 10, 10, 10, 10};
    vx_gltf_mesh p = soup(only, 3);
    uint32_t* xyz = NULL;
    size_t count = 0;
    REQUIRE(vx_conv_mesh_cells(&(vx_conv_mesh_desc){.res = 10}, &p, NULL, &xyz, NULL, &count, NULL) == VX_OK);
    size_t corner = 0;
    for (size_t i = 0; i < count; i++)
        corner += xyz[3 * i] >= 4 && xyz[3 * i] <= 5 && xyz[3 * i + 1] >= 4 && xyz[3 * i + 1] <= 5 &&
                  xyz[3 * i + 2] >= 4 && xyz[3 * i + 2] <= 5;
    CHECK(corner == 1);
    CHECK(count == 3); /* and the two points fixing the bounds: cells 0 0 0 and 9 9 9 (closed last cell) */
    for (size_t i = 0; i < count; i++)
        if (xyz[3 * i] >= 4 && xyz[3 * i] <= 5 && xyz[3 * i + 1] >= 4 && xyz[3 * i + 1] <= 5) {
            CHECK(xyz[3 * i] == 5 && xyz[3 * i + 1] == 5 && xyz[3 * i + 2] == 5);
        }
    free(xyz);
}

/* One triangle spanning the grid, across bricks and (region = 64) models;
 * random soups. */
static void test_large_and_random(void) {
    float big[9] = {0, 0, 0, 100, 7.3f, 31.1f, 13.7f, 100, 100};
    vx_gltf_mesh m = soup(big, 1);
    for (uint32_t res = 16; res <= 128; res *= 2) {
        size_t cells = 0;
        CHECKF(compare(&m, (vx_conv_mesh_desc){.res = res, .region = 64, .threads = 2}, &cells) == 0, "res %u", res);
    }
    float pos[9 * 300];
    for (int i = 0; i < 9 * 300; i++) pos[i] = (float)(rnd() * 50 - 25);
    for (int i = 0; i < 300; i++) /* small triangles near each first vertex */
        for (int k = 3; k < 9; k++) pos[9 * i + k] = pos[9 * i + k % 3] + (float)(rnd() * 6 - 3);
    m = soup(pos, 300);
    static const uint32_t res[] = {16, 33, 100, 128};
    for (int i = 0; i < 4; i++)
        CHECKF(compare(&m, (vx_conv_mesh_desc){.res = res[i], .threads = 1 + (uint32_t)i % 2}, NULL) == 0, "res %u",
               res[i]);
}

/* The binning on several threads (triangle ranges in parts, each worker
 * into a fixed slice, a full slice binned again on the caller's thread)
 * gives the one-thread pairs, brick and region boundaries exactly; and the
 * cells of a soup large enough to be split agree with the brute force. */
static void test_parallel_binning(void) {
    enum { N = 4000 };
    static float pos[9 * N];
    for (int i = 0; i < 9 * N; i++) pos[i] = (float)(rnd() * 50 - 25);
    for (int i = 0; i < N; i++) /* small triangles, and every 50th one large (many bricks: slices overflow) */
        for (int k = 3; k < 9; k++) pos[9 * i + k] = pos[9 * i + k % 3] + (float)(rnd() * (i % 50 ? 4 : 60) - (i % 50 ? 2 : 30));
    vx_gltf_mesh m = soup(pos, N);
    static const uint32_t res[] = {64, 700, 4000};
    for (int q = 0; q < 3; q++) {
        vx_conv_mesh_grid g;
        vx_error err = {0};
        CHECK(vx_conv_mesh_grid_make(m.pos, m.tri_count, res[q], &g, &err) == VX_OK);
        vx__mesh_bins a, b;
        memset(&a, 0, sizeof a);
        memset(&b, 0, sizeof b);
        vx_conv_mesh_desc d1 = {.res = res[q], .threads = 1}, d8 = {.res = res[q], .threads = 8};
        CHECK(vx__mesh_bin(&d1, &m, &g, &a, &err) == VX_OK);
        CHECK(vx__mesh_bin(&d8, &m, &g, &b, &err) == VX_OK);
        CHECKF(a.pair_count == b.pair_count && a.pair_count >= N && !memcmp(a.pairs, b.pairs, a.pair_count * 8), "res %u: %zu pairs against %zu",
               res[q], b.pair_count, a.pair_count);
        CHECKF(a.total_bricks == b.total_bricks && a.region_count == b.region_count &&
                   !memcmp(a.bstart, b.bstart, (a.total_bricks + 1) * sizeof *a.bstart) &&
                   !memcmp(a.rstart, b.rstart, (a.region_count + 1) * sizeof *a.rstart),
               "res %u: bricks or regions differ", res[q]);
        if (q == 2) CHECKF(a.pair_count > 8 * (size_t)N, "res %u: %zu pairs: no slice overflowed", res[q], a.pair_count);
        vx__mesh_bins_free(NULL, &a);
        vx__mesh_bins_free(NULL, &b);
    }
    for (int i = 0; i < N; i++) /* the large ones small again, for the brute force */
        if (i % 50 == 0)
            for (int k = 3; k < 9; k++) pos[9 * i + k] = pos[9 * i + k % 3] + (float)(rnd() * 4 - 2);
    CHECK(compare(&m, (vx_conv_mesh_desc){.res = 100, .threads = 4}, NULL) == 0);
}

/* The largest res is taken, one more refused (VX_ERR_LIMIT) in the
 * library's words: the desc field, not a tool's flag (STYLE.md Part 3). */
static void test_res_limit(void) {
    float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    vx_gltf_mesh m = soup(pos, 1);
    vx_conv_mesh_grid g;
    vx_error err = {0};
    CHECK(vx_conv_mesh_grid_make(m.pos, m.tri_count, VX_CONV_MESH_RES_MAX, &g, &err) == VX_OK);
    CHECKF(g.size[0] == VX_CONV_MESH_RES_MAX && g.size[1] == VX_CONV_MESH_RES_MAX && g.size[2] == 1, "%u x %u x %u", g.size[0], g.size[1],
           g.size[2]);
    CHECK(vx_conv_mesh_grid_make(m.pos, m.tri_count, VX_CONV_MESH_RES_MAX + 1, &g, &err) == VX_ERR_LIMIT);
    CHECKF(strstr(err.msg, "res 65537") && !strstr(err.msg, "--"), "%s", err.msg);
}

static void test_nan(void) {
    float pos[18] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 1, NAN, 0, 0, 1, 1};
    vx_gltf_mesh m = soup(pos, 2);
    uint32_t* xyz = NULL;
    size_t count = 0;
    vx_error err = {0};
    CHECK(vx_conv_mesh_cells(&(vx_conv_mesh_desc){.res = 16}, &m, NULL, &xyz, NULL, &count, &err) == VX_ERR_BAD_FORMAT);
    CHECK(strstr(err.msg, "NaN") != NULL);
    pos[4] = INFINITY;
    pos[13] = 0;
    CHECK(vx_conv_mesh_cells(&(vx_conv_mesh_desc){.res = 16}, &m, NULL, &xyz, NULL, &count, &err) == VX_ERR_BAD_FORMAT);
}

/* --solid on a box with a hole (one triangle missing) inside a larger grid:
 * the result is the surface plus every cell whose centre is inside the box
 * (the hole breaks the parity along one axis only). */
static void test_solid_hole(void) {
    float pos[9 * 16];
    float lo[3] = {2.25f, 3.25f, 1.75f}, hi[3] = {9.75f, 8.25f, 6.25f};
    for (int skip = -1; skip < 12; skip += 5) {
        size_t n = box(pos, lo, hi, skip);
        /* two tiny triangles in opposite corners extend the bounds to [0, 12]^3 */
        float far[18] = {0, 0, 0, 0.1f, 0, 0, 0, 0.1f, 0, 12, 12, 12, 11.9f, 12, 12, 12, 11.9f, 12};
        memcpy(pos + 9 * n, far, 72);
        n += 2;
        vx_gltf_mesh m = soup(pos, n);
        uint32_t* xyz = NULL;
        size_t count = 0;
        vx_conv_mesh_grid g;
        REQUIRE(vx_conv_mesh_cells(&(vx_conv_mesh_desc){.res = 12, .solid = true}, &m, &g, &xyz, NULL, &count, NULL) ==
                VX_OK);
        uint8_t* got = (uint8_t*)calloc(12 * 12 * 12, 1);
        for (size_t i = 0; i < count; i++) got[cell_index(&g, xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2])] = 1;
        /* surface cells (reference) plus the cells whose centre is inside the box */
        uint8_t* ref_far = reference(&m, &g);
        size_t bad = 0;
        for (uint32_t z = 0; z < 12; z++)
            for (uint32_t y = 0; y < 12; y++)
                for (uint32_t x = 0; x < 12; x++) {
                    bool in_box = x >= 2 && x <= 9 && y >= 3 && y <= 7 && z >= 2 && z <= 5;
                    size_t c = cell_index(&g, x, y, z);
                    bool want = in_box || ref_far[c];
                    if (got[c] != want && bad < 10) fprintf(stderr, "  cell %u %u %u: got %d want %d\n", x, y, z, got[c], want);
                    bad += got[c] != want;
                }
        CHECKF(bad == 0, "solid box (hole %d): %zu cells differ", skip, bad);
        free(ref_far);
        free(got);
        free(xyz);
    }
}

static double srgb_encode(double l) { return l <= 0.0031308 ? 12.92 * l : 1.055 * pow(l, 1 / 2.4) - 0.055; }

/* A uniform material colour comes out as its sRGB encoding in every cell;
 * texture and vertex colour multiply in linear space. */
static void test_colors(void) {
    float pos[9 * 12];
    float lo[3] = {0, 0, 0}, hi[3] = {3, 2, 1};
    size_t n = box(pos, lo, hi, -1);
    uint32_t mat[12] = {0};
    vx_gltf_material mtl = {.base_color = {0.5f, 0.25f, 1.0f, 0.75f}, .image = -1, .roughness = 1, .ior = 1.5f};
    vx_gltf_mesh m = soup(pos, n);
    m.material = mat;
    m.material_count = 1;
    m.materials = &mtl;
    uint32_t *xyz = NULL, *rgba = NULL;
    size_t count = 0;
    REQUIRE(vx_conv_mesh_cells(&(vx_conv_mesh_desc){.res = 24}, &m, NULL, &xyz, &rgba, &count, NULL) == VX_OK);
    REQUIRE(rgba != NULL);
    uint32_t want = (uint32_t)lrint(srgb_encode(0.5) * 255) | (uint32_t)lrint(srgb_encode(0.25) * 255) << 8 |
                    255u << 16 | (uint32_t)lrint(0.75 * 255) << 24;
    size_t bad = 0;
    for (size_t i = 0; i < count; i++) bad += rgba[i] != want;
    CHECKF(bad == 0, "%zu of %zu cells not %08x (first %08x)", bad, count, want, rgba[0]);
    free(xyz);
    free(rgba);
    /* a 1x1 texture (sRGB 200 100 50) times vertex colour 0.5 grey (linear) */
    uint8_t texel[4] = {200, 100, 50, 255};
    vx_gltf_image img = {1, 1, texel};
    vx_gltf_material tm = {.base_color = {1, 1, 1, 1}, .image = 0, .wrap_s = VX_GLTF_WRAP_REPEAT, .wrap_t = VX_GLTF_WRAP_CLAMP, .roughness = 1, .ior = 1.5f};
    float uv[6 * 12], col[12 * 12];
    for (int i = 0; i < 6 * 12; i++) uv[i] = (float)(rnd() * 4 - 2);
    for (int i = 0; i < 12 * 12; i++) col[i] = (i % 4 == 3) ? 1.f : 0.5f;
    m.materials = &tm;
    m.images = &img;
    m.image_count = 1;
    m.uv = uv;
    m.color = col;
    REQUIRE(vx_conv_mesh_cells(&(vx_conv_mesh_desc){.res = 24}, &m, NULL, &xyz, &rgba, &count, NULL) == VX_OK);
    double lin[3] = {pow((200 / 255.0 + 0.055) / 1.055, 2.4), pow((100 / 255.0 + 0.055) / 1.055, 2.4),
                     pow((50 / 255.0 + 0.055) / 1.055, 2.4)};
    uint32_t want2 = 0xFF000000u;
    for (int k = 0; k < 3; k++) want2 |= (uint32_t)lrint(srgb_encode(0.5 * lin[k]) * 255) << (8 * k);
    bad = 0;
    for (size_t i = 0; i < count; i++) {
        int d = 0;
        for (int k = 0; k < 4; k++) d += abs((int)((rgba[i] >> (8 * k)) & 255) - (int)((want2 >> (8 * k)) & 255));
        bad += d > 1; /* float accumulation may move one code */
    }
    CHECKF(bad == 0, "%zu of %zu textured cells not %08x (first %08x)", bad, count, want2, rgba[0]);
    free(xyz);
    free(rgba);
    /* no material, no colours: geometry only */
    vx_gltf_mesh g = soup(pos, n);
    REQUIRE(vx_conv_mesh_cells(&(vx_conv_mesh_desc){.res = 8}, &g, NULL, &xyz, &rgba, &count, NULL) == VX_OK);
    CHECK(rgba == NULL);
    free(xyz);
}

/* Every glTF file of the corpus loads and voxelizes, or fails with the
 * documented error (the Draco box). */
static void test_corpus_all(void) {
    static const char* files[] = {"gltf/aleph_white-claw-can.glb", "gltf/julian_Duck.glb",
                                  "gltf/khronos_Avocado_glTF/Avocado.gltf", "gltf/khronos_DamagedHelmet.glb",
                                  "gltf/mjurczyk_shuttle.glb", "gltf/rtxgi_cornell.glb", "gltf/rtxgi_furnace.glb",
                                  "gltf/rtxgi_tunnel.glb", "gltf/rtxgi_two-rooms.glb", "gltf/tinygltf_box01.glb",
                                  "gltf/tinygltf_Cube/Cube.gltf",
                                  "gltf/tinygltf_CubeImageUriSpaces/CubeImageUriSpaces.gltf",
                                  "gltf/tinygltf_CubeImageUriSpaces/CubeImageUriMultipleSpaces.gltf"};
    int found = 0;
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
        const char* p = vx_test_corpus(files[i]);
        if (!p) continue;
        found++;
        vx_gltf_mesh m;
        vx_error err = {0};
        vx_result r = vx_gltf_read_file(&(vx_gltf_read_desc){0}, p, &m, &err);
        CHECKF(r == VX_OK, "%s: %s", files[i], err.msg);
        if (r) continue;
        CHECKF(m.tri_count > 0, "%s", files[i]);
        uint32_t *xyz = NULL, *rgba = NULL;
        size_t count = 0;
        r = vx_conv_mesh_cells(&(vx_conv_mesh_desc){.res = 32}, &m, NULL, &xyz, &rgba, &count, &err);
        CHECKF(r == VX_OK && count > 0, "%s: %s", files[i], err.msg);
        fprintf(stderr, "  %s: %zu triangles, %u materials, %u images, %zu cells at res 32, %s\n", files[i],
                m.tri_count, m.material_count, m.image_count, count, rgba ? "colours" : "geometry only");
        free(xyz);
        free(rgba);
        vx_gltf_mesh_free(&m);
    }
    const char* draco = vx_test_corpus("gltf/aleph_Box.glb");
    if (draco) {
        found++;
        vx_gltf_mesh m;
        vx_error err = {0};
        CHECK(vx_gltf_read_file(&(vx_gltf_read_desc){0}, draco, &m, &err) == VX_ERR_UNSUPPORTED);
        CHECKF(strstr(err.msg, "KHR_draco_mesh_compression") != NULL, "%s", err.msg);
    }
    if (!found) SKIP("no glTF corpus");
}

/* Textures: the Cube's base colour is decoded, sampled through uv */
static void test_scene_select(void) {
    const char* p = vx_test_corpus("gltf/julian_Duck.glb");
    if (!p) SKIP("no Duck");
    vx_gltf_mesh m;
    vx_error err = {0};
    CHECK(vx_gltf_read_file(&(vx_gltf_read_desc){.scene_set = true, .scene = 7}, p, &m, &err) == VX_ERR_INVALID_ARG);
    REQUIRE(vx_gltf_read_file(&(vx_gltf_read_desc){.scene_set = true, .scene = 0}, p, &m, &err) == VX_OK);
    CHECK(m.image_count == 1 && m.images[0].rgba != NULL && m.images[0].width > 0);
    vx_gltf_mesh_free(&m);
    REQUIRE(vx_gltf_read_file(&(vx_gltf_read_desc){.no_images = true}, p, &m, &err) == VX_OK);
    CHECK(m.uv == NULL);
    vx_gltf_mesh_free(&m);
}

/* KHR_texture_transform: the reader hands out uv' = T R S uv (glTF's
 * offset, counter-clockwise rotation and scale) from the texCoord set the
 * extension names; a malformed transform is an error naming the material. */
static const char* kTriGltf =
    "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
    "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"TEXCOORD_0\":1,\"TEXCOORD_1\":2},"
    "\"material\":0}]}],"
    "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0%s}}}],"
    "\"textures\":[{\"source\":0}],"
    "\"images\":[{\"uri\":\"data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAIAAAACCAYAAABytg0kAAAAEklEQVR4nGP4z8DwHwy"
    "BNBgAAEnICff5q7YNAAAAAElFTkSuQmCC\"}],"
    "\"buffers\":[{\"byteLength\":84,\"uri\":\"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAA"
    "AAAAAAAAgD8AAAAAAAAAAAAAAAAAAIA/AAAAAAAAAAAAAIA/AAAAPwAAAD8AAEA/AAAAPwAAAD8AAEA/\"}],"
    "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":36},{\"buffer\":0,\"byteOffset\":36,"
    "\"byteLength\":24},{\"buffer\":0,\"byteOffset\":60,\"byteLength\":24}],"
    "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\",\"min\":[0,0,0],"
    "\"max\":[1,1,0]},{\"bufferView\":1,\"componentType\":5126,\"count\":3,\"type\":\"VEC2\"},"
    "{\"bufferView\":2,\"componentType\":5126,\"count\":3,\"type\":\"VEC2\"}]}";

static vx_result read_tri(const char* ext, vx_gltf_mesh* m, vx_error* err) {
    char json[4096];
    snprintf(json, sizeof json, kTriGltf, ext);
    return vx_gltf_read(&(vx_gltf_read_desc){0}, json, strlen(json), ".", m, err);
}

/* An image whose data URI has a media type tinygltf does not decode (webp):
 * the mesh is read, the image left out, and one warning names the image and
 * its media type, not tinygltf's "File not found : data:image/webp;base64,..."
 * and "Failed to load external 'uri'" */
typedef struct warn_log {
    char text[512];
} warn_log;
static void keep_warning(void* user, vx_log_level level, const char* id, const char* msg) {
    warn_log* w = user;
    if (level == VX_LOG_WARN) snprintf(w->text + strlen(w->text), sizeof w->text - strlen(w->text), "[%s] %s\n", id, msg);
}
/* Reads the glTF text json into m, its warnings into w. */
static vx_result read_logged(const char* json, vx_gltf_mesh* m, warn_log* w, vx_error* err) {
    w->text[0] = 0;
    vx_logger lg = {keep_warning, w};
    return vx_gltf_read(&(vx_gltf_read_desc){.logger = &lg}, json, strlen(json), ".", m, err);
}
static void test_unknown_image_media_type(void) {
    char json[4096];
    snprintf(json, sizeof json, kTriGltf, "");
    const char* png = strstr(json, "data:image/png;base64,");
    REQUIRE(png != NULL);
    const char* end = strchr(png, '"');
    REQUIRE(end != NULL);
    char webp[4096];
    snprintf(webp, sizeof webp, "%.*sdata:image/webp;base64,UklGRhwAAABXRUJQVlA4TA8AAAAv%s", (int)(png - json), json, end);
    warn_log w;
    vx_gltf_mesh m;
    vx_error err = {0};
    vx_result r = read_logged(webp, &m, &w, &err);
    CHECKF(r == VX_OK, "%s", err.msg);
    if (r) return;
    fprintf(stderr, "  warning: %s", w.text);
    CHECK(m.tri_count == 1);
    CHECKF(strstr(w.text, "image 0 (a data URI of media type 'image/webp'): missing or not a PNG/JPEG") &&
               !strstr(w.text, "File not found") && !strstr(w.text, "base64") && !strstr(w.text, "external"),
           "%s", w.text);
    vx_gltf_mesh_free(&m);
}

/* An emissiveTexture that is decoded keeps the factor (the voxelizer
 * multiplies it by the texels, formats/gltf.h) with the texture named; one
 * that is not decoded (no_images; an unreadable image) leaves the emission
 * out with the warning gltf.emissive_texture, not its factor over the whole
 * material (the corpus's DamagedHelmet converted into a white lamp);
 * without the texture the factor stays. */
static void test_emissive_texture(void) {
    static const char* with =
        "},\"metallicFactor\":0},\"emissiveFactor\":[1,0.5,1],\"emissiveTexture\":{\"index\":0,\"texCoord\":1},"
        "\"extras\":{\"a\":{\"b\":0";
    static const char* without = "},\"metallicFactor\":0},\"emissiveFactor\":[1,0.5,1],\"extras\":{\"a\":{\"b\":0";
    for (int i = 0; i < 3; i++) {
        char json[4096];
        snprintf(json, sizeof json, kTriGltf, i == 2 ? without : with);
        warn_log w = {{0}};
        vx_logger lg = {keep_warning, &w};
        vx_gltf_mesh m;
        vx_error err = {0};
        vx_result r = vx_gltf_read(&(vx_gltf_read_desc){.logger = &lg, .no_images = i == 1}, json, strlen(json), ".", &m,
                                   &err);
        CHECKF(r == VX_OK, "%s", err.msg);
        if (r) continue;
        REQUIRE(m.material_count == 1);
        const float* e = m.materials[0].emissive;
        bool warned = strstr(w.text, "[gltf.emissive_texture] material 0") != NULL;
        if (i == 0) /* decoded: the factor, the texture, its own uv set (TEXCOORD_1: 0.5 0.5, 0.75 0.5, 0.5 0.75) */
            CHECKF(e[0] == 1 && e[1] == 0.5f && e[2] == 1 && !warned && m.materials[0].emissive_tex.image == 0 &&
                       m.uv_emissive && m.uv_emissive[0] == 0.5f && m.uv_emissive[2] == 0.75f && m.uv_emissive[5] == 0.75f,
                   "decoded: %g %g %g, image %d, '%s'", e[0], e[1], e[2], m.materials[0].emissive_tex.image, w.text);
        else if (i == 1)
            CHECKF(e[0] == 0 && e[1] == 0 && e[2] == 0 && warned && m.materials[0].emissive_tex.image == -1,
                   "not decoded: %g %g %g, '%s'", e[0], e[1], e[2], w.text);
        else
            CHECKF(e[0] == 1 && e[1] == 0.5f && e[2] == 1 && !warned && !m.uv_emissive, "without: %g %g %g, '%s'", e[0],
                   e[1], e[2], w.text);
        vx_gltf_mesh_free(&m);
    }
}

static void test_texture_transform(void) {
    static const double uv0[6] = {0, 0, 1, 0, 0, 1}, uv1[6] = {0.5, 0.5, 0.75, 0.5, 0.5, 0.75};
    struct {
        const char* ext;
        double off[2], rot, sc[2];
        const double* src;
    } cases[] = {
        {"", {0, 0}, 0, {1, 1}, uv0},
        {",\"extensions\":{\"KHR_texture_transform\":{\"offset\":[0.25,0.5],\"rotation\":0.3,\"scale\":[2,3]}}",
         {0.25, 0.5}, 0.3, {2, 3}, uv0},
        {",\"extensions\":{\"KHR_texture_transform\":{\"scale\":[-1,0.5],\"texCoord\":1}}", {0, 0}, 0, {-1, 0.5}, uv1},
        {",\"texCoord\":1", {0, 0}, 0, {1, 1}, uv1},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        vx_gltf_mesh m;
        vx_error err = {0};
        vx_result r = read_tri(cases[i].ext, &m, &err);
        if (r) fprintf(stderr, "  case %zu: %s\n", i, err.msg);
        REQUIRE(r == VX_OK);
        REQUIRE(m.tri_count == 1 && m.uv != NULL && m.image_count == 1 && m.images[0].rgba != NULL);
        double worst = 0;
        double c = cos(cases[i].rot), s = sin(cases[i].rot);
        for (int v = 0; v < 3; v++) {
            double u = cases[i].src[2 * v], w = cases[i].src[2 * v + 1];
            double su = cases[i].sc[0] * u, sw = cases[i].sc[1] * w;
            double eu = c * su + s * sw + cases[i].off[0], ew = -s * su + c * sw + cases[i].off[1];
            worst = fmax(worst, fmax(fabs(m.uv[2 * v] - eu), fabs(m.uv[2 * v + 1] - ew)));
        }
        CHECKF(worst < 1e-6, "case %zu: uv off by %g", i, worst);
        vx_gltf_mesh_free(&m);
    }
    const char* bad[] = {",\"extensions\":{\"KHR_texture_transform\":{\"offset\":[1]}}",
                         ",\"extensions\":{\"KHR_texture_transform\":{\"rotation\":\"x\"}}",
                         ",\"extensions\":{\"KHR_texture_transform\":{\"texCoord\":-1}}"};
    for (int i = 0; i < 3; i++) {
        vx_gltf_mesh m;
        vx_error err = {0};
        CHECK(read_tri(bad[i], &m, &err) == VX_ERR_BAD_FORMAT);
        CHECKF(strstr(err.msg, "material 0: KHR_texture_transform") != NULL, "message: %s", err.msg);
    }
}

/* Sparse accessors (glTF 2.0 3.6.2.3): positions with one element replaced,
 * texture coordinates with no buffer view (zeros) and one element set; a
 * replacement index out of range is an error. */
static const char* kSparseGltf =
    "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
    "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"TEXCOORD_0\":1},\"material\":0}]}],"
    "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}}}],"
    "\"textures\":[{\"source\":0}],"
    "\"images\":[{\"uri\":\"data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAIAAAACCAYAAABytg0kAAAAEklEQVR4nGP4z8DwHwy"
    "BNBgAAEnICff5q7YNAAAAAElFTkSuQmCC\"}],"
    "\"buffers\":[{\"byteLength\":116,\"uri\":\"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAA"
    "AAAAAAAAgD8AAAAAAAAAAAAAAAAAAIA/AAAAAAAAAAAAAIA/AAAAPwAAAD8AAEA/AAAAPwAAAD8AAEA/AgAAAAAAAAAAAABAAAAAAAEAAAAAAAA/"
    "AACAPgUAAAA=\"}],"
    "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":36},{\"buffer\":0,\"byteOffset\":84,"
    "\"byteLength\":1},{\"buffer\":0,\"byteOffset\":88,\"byteLength\":12},{\"buffer\":0,\"byteOffset\":%d,"
    "\"byteLength\":1},{\"buffer\":0,\"byteOffset\":104,\"byteLength\":8}],"
    "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\",\"min\":[0,0,0],"
    "\"max\":[1,2,0],\"sparse\":{\"count\":1,\"indices\":{\"bufferView\":1,\"componentType\":5121},"
    "\"values\":{\"bufferView\":2}}},"
    "{\"componentType\":5126,\"count\":3,\"type\":\"VEC2\",\"sparse\":{\"count\":1,"
    "\"indices\":{\"bufferView\":3,\"componentType\":5121},\"values\":{\"bufferView\":4}}}]}";

static void test_sparse(void) {
    char json[4096];
    snprintf(json, sizeof json, kSparseGltf, 100);
    vx_gltf_mesh m;
    vx_error err = {0};
    vx_result r = vx_gltf_read(&(vx_gltf_read_desc){0}, json, strlen(json), ".", &m, &err);
    if (r) fprintf(stderr, "  %s\n", err.msg);
    REQUIRE(r == VX_OK);
    REQUIRE(m.tri_count == 1 && m.uv != NULL);
    static const float want_pos[9] = {0, 0, 0, 1, 0, 0, 0, 2, 0}, want_uv[6] = {0, 0, 0.5f, 0.25f, 0, 0};
    CHECK(!memcmp(m.pos, want_pos, sizeof want_pos));
    CHECK(!memcmp(m.uv, want_uv, sizeof want_uv));
    vx_gltf_mesh_free(&m);
    snprintf(json, sizeof json, kSparseGltf, 112); /* replacement index 5 of 3 elements */
    CHECK(vx_gltf_read(&(vx_gltf_read_desc){0}, json, strlen(json), ".", &m, &err) == VX_ERR_BAD_FORMAT);
    CHECKF(strstr(err.msg, "sparse accessor 1: index 5") != NULL, "message: %s", err.msg);
}

/* What the reader does not implement is named, not misread: a glTF 1.0 file
 * (asset.version, or a version 1 .glb container) and a minVersion above 2.0
 * are VX_ERR_UNSUPPORTED naming the version (tinygltf read a 1.0 file as an
 * empty 2.0 one: "no triangles"); a primitive compressed with
 * KHR_draco_mesh_compression that the file uses without requiring it and
 * without an uncompressed fallback names the extension (tinygltf said
 * "accessor[0] invalid bufferView"); with a fallback it is read. */
static const char* kVersionGltf =
    "{\"asset\":{%s},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],%s"
    "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}%s}]}],"
    "\"buffers\":[{\"byteLength\":36,\"uri\":\"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAA"
    "AAAAAAAAgD8AAAAA\"}],"
    "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":36}],"
    "\"accessors\":[{%s\"componentType\":5126,\"count\":3,\"type\":\"VEC3\",\"min\":[0,0,0],\"max\":[1,1,0]}]}";

static void test_versions_and_draco(void) {
    const char* draco_used = "\"extensionsUsed\":[\"KHR_draco_mesh_compression\"],";
    const char* draco_prim =
        ",\"extensions\":{\"KHR_draco_mesh_compression\":{\"bufferView\":0,\"attributes\":{\"POSITION\":0}}}";
    struct {
        const char *asset, *used, *prim, *view;
        vx_result want;
        const char* msg;
    } cases[] = {
        {"\"version\":\"2.0\"", "", "", "\"bufferView\":0,", VX_OK, NULL},
        {"\"version\":\"2.1\"", "", "", "\"bufferView\":0,", VX_OK, NULL},
        {"\"version\":\"1.0\"", "", "", "\"bufferView\":0,", VX_ERR_UNSUPPORTED, "glTF version 1.0 is not supported"},
        {"\"version\":\"3.0\"", "", "", "\"bufferView\":0,", VX_ERR_UNSUPPORTED, "glTF version 3.0 is not supported"},
        {"\"version\":\"2.0\",\"minVersion\":\"2.1\"", "", "", "\"bufferView\":0,", VX_ERR_UNSUPPORTED,
         "glTF minVersion 2.1 is not supported"},
        {"\"version\":\"2.0\"", draco_used, draco_prim, "", VX_ERR_UNSUPPORTED,
         "mesh 0 primitive 0: KHR_draco_mesh_compression"},
        {"\"version\":\"2.0\"", draco_used, draco_prim, "\"bufferView\":0,", VX_OK, NULL},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char json[4096];
        snprintf(json, sizeof json, kVersionGltf, cases[i].asset, cases[i].used, cases[i].prim, cases[i].view);
        vx_gltf_mesh m;
        vx_error err = {0};
        vx_result r = vx_gltf_read(&(vx_gltf_read_desc){0}, json, strlen(json), ".", &m, &err);
        CHECKF(r == cases[i].want, "case %zu: result %d (%s)", i, (int)r, err.msg);
        if (r == VX_OK) {
            CHECKF(m.tri_count == 1, "case %zu: %zu triangles", i, m.tri_count);
            vx_gltf_mesh_free(&m);
        } else if (cases[i].msg) {
            CHECKF(strstr(err.msg, cases[i].msg) != NULL, "case %zu: message: %s", i, err.msg);
        }
    }
    /* a .glb container of version 1 (glTF 1.0's KHR_binary_glTF): 20-byte
     * header, then a JSON scene chunk of content format 0 */
    static const char json1[] = "{\"asset\":{\"version\":\"1.0\"}}   ";
    unsigned char glb[20 + sizeof json1 - 1];
    uint32_t hdr[5] = {0x46546C67u, 1u, (uint32_t)sizeof glb, (uint32_t)(sizeof json1 - 1), 0u};
    for (int k = 0; k < 5; k++)
        for (int b = 0; b < 4; b++) glb[4 * k + b] = (unsigned char)(hdr[k] >> (8 * b));
    memcpy(glb + 20, json1, sizeof json1 - 1);
    vx_gltf_mesh m;
    vx_error err = {0};
    CHECK(vx_gltf_read(&(vx_gltf_read_desc){0}, glb, sizeof glb, ".", &m, &err) == VX_ERR_UNSUPPORTED);
    CHECKF(strstr(err.msg, "binary glTF version 1 is not supported") != NULL, "message: %s", err.msg);
}

/* A scene far from the origin (georeferenced: a node translation of 6e6,
 * where floats are 0.5 apart) voxelizes to the same cells as the same scene
 * at the origin: positions are kept relative to vx_gltf_mesh.origin (they
 * were rounded to world floats, and the triangle lost cells), and the
 * origin plus the grid's min is the world position of the grid. */
static const char* kFarGltf =
    "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],"
    "\"nodes\":[{\"mesh\":0,\"translation\":[%s]}],"
    "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}}]}],"
    "\"buffers\":[{\"byteLength\":36,\"uri\":\"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAA"
    "AAAAAAAAgD8AAAAA\"}],"
    "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":36}],"
    "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\",\"min\":[0,0,0],"
    "\"max\":[1,1,0]}]}";

static int cell_cmp(const void* a, const void* b) {
    return memcmp(a, b, 3 * sizeof(uint32_t));
}

static void test_far_origin(void) {
    const char* at[2] = {"0.25,0.5,0.125", "6000000.25,0.5,-6000000.125"};
    vx_gltf_mesh m[2];
    vx_conv_mesh_grid g[2];
    uint32_t* xyz[2] = {NULL, NULL};
    size_t n[2] = {0, 0};
    for (int i = 0; i < 2; i++) {
        char json[2048];
        snprintf(json, sizeof json, kFarGltf, at[i]);
        vx_error err = {0};
        warn_log w;
        vx_result r = read_logged(json, &m[i], &w, &err);
        if (r) fprintf(stderr, "  %s\n", err.msg);
        REQUIRE(r == VX_OK && m[i].tri_count == 1);
        CHECKF(w.text[0] == 0, "no precision warning at %s: %s", at[i], w.text); /* rounding 2^-29 of the extent */
        r = vx_conv_mesh_cells(&(vx_conv_mesh_desc){.res = 64}, &m[i], &g[i], &xyz[i], NULL, &n[i], &err);
        REQUIRE(r == VX_OK);
        qsort(xyz[i], n[i], 3 * sizeof(uint32_t), cell_cmp);
    }
    CHECK(m[0].origin[0] == 0 && m[0].origin[1] == 0 && m[0].origin[2] == 0);
    CHECKF(m[1].origin[0] == 5999616 && m[1].origin[1] == 0 && m[1].origin[2] == -5999616, "origin %g %g %g",
           m[1].origin[0], m[1].origin[1], m[1].origin[2]);
    CHECKF(n[0] == n[1] && n[0] > 0 && !memcmp(xyz[0], xyz[1], n[0] * 3 * sizeof(uint32_t)),
           "%zu cells near the origin, %zu far", n[0], n[1]);
    CHECK(g[0].h == g[1].h);
    CHECKF(fabs(m[1].origin[0] + g[1].min[0] - 6000000.25) < 1e-6 &&
               fabs(m[1].origin[2] + g[1].min[2] - (-6000000.125)) < 1e-6,
           "grid at %.9g %.9g", m[1].origin[0] + g[1].min[0], m[1].origin[2] + g[1].min[2]);
    for (int i = 0; i < 2; i++) {
        vx_free(NULL, xyz[i]);
        vx_gltf_mesh_free(&m[i]);
    }
}

/* Rounding that loses a scene's shape is a warning, gltf.position_precision
 * (gltf.h): a unit triangle translated to 1e30 (on x every vertex the same
 * double; on every axis: one point) or to 1e14 (steps of 1/64), and a file whose float vertices sit at 1e9
 * (floats 64 apart) for a 128-unit triangle; not a triangle at 6e6 (steps of
 * 2^-29 of it: test_far_origin), one of 1e-6 near 0 or one at 250. */
static void test_position_precision(void) {
    static const struct {
        const char* translation;
        const char* scale;
        bool warn;
        const char* text;
    } cases[] = {
        {"1e30,0,0", "1,1,1", true, "lost to rounding"}, {"1e30,1e30,1e30", "1,1,1", true, "no extent"},
        {"1e14,0,0", "1,1,1", true, "lost to rounding"},
        {"0,0,0", "1e-6,1e-6,1e-6", false, ""},  {"250,0,0", "1,1,1", false, ""},
        {NULL, NULL, true, "lost to rounding"}, /* the float vertices at 1e9 */
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char tr[160], json[2048];
        snprintf(tr, sizeof tr, "%s],\"scale\":[%s", cases[i].translation ? cases[i].translation : "0,0,0",
                 cases[i].scale ? cases[i].scale : "1,1,1");
        snprintf(json, sizeof json, kFarGltf, tr);
        if (!cases[i].translation) { /* (1e9 0 0) (1e9 100 0) (1e9+128 0 0) as floats */
            char* b = strstr(json, "base64,");
            REQUIRE(b != NULL);
            memcpy(b + 7, "KGtuTgAAAAAAAAAAKGtuTgAAyEIAAAAAKmtuTgAAAAAAAAAA", 48);
        }
        warn_log w;
        vx_gltf_mesh m;
        vx_error err = {0};
        vx_result r = read_logged(json, &m, &w, &err);
        CHECKF(r == VX_OK, "case %zu: %s", i, err.msg);
        if (r) continue;
        bool warned = strstr(w.text, "[gltf.position_precision]") != NULL;
        CHECKF(warned == cases[i].warn && strstr(w.text, cases[i].text), "case %zu (%s): '%s'", i,
               cases[i].translation ? cases[i].translation : "floats at 1e9", w.text);
        vx_gltf_mesh_free(&m);
    }
}

/* An external URI that names a directory (here "." next to the file) is an
 * error naming it ("File not found : ."), not an allocation of the size a directory stream reports
 * (2^63 - 1: VX_ERR_NOMEM in Release, an AddressSanitizer abort). */
static void test_uri_directory(void) {
    static const char json[] =
        "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}}]}],"
        "\"buffers\":[{\"byteLength\":36,\"uri\":\".\"}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":36}],"
        "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\",\"min\":[0,0,0],"
        "\"max\":[1,1,0]}]}";
    vx_gltf_mesh m;
    vx_error err = {0};
    vx_result r = vx_gltf_read(&(vx_gltf_read_desc){0}, json, strlen(json), ".", &m, &err);
    CHECKF(r == VX_ERR_BAD_FORMAT, "result %d (%s)", (int)r, err.msg);
    CHECKF(strstr(err.msg, "not found") != NULL || strstr(err.msg, "not a regular file") != NULL, "message: %s",
           err.msg);
}

/* The id plan (mesh_internal.h, "materials"): a sampled emission is one
 * quantized channel per channel of its factor above 0, so its block is
 * levels^n (a white factor 6^3, (1 0.5 0) 6^2); the fallback to fewer levels
 * counts those blocks; and every id of a block is the id of its own record's
 * values (vx__mesh_mats_record then vx__mesh_mats_id give it back). */
static void test_mats_emission_blocks(void) {
    static uint8_t px[16] = {0, 0, 0, 255, 255, 128, 64, 255, 10, 20, 30, 255, 200, 0, 90, 255}; /* every channel varies */
    vx_gltf_image im = {2, 2, px};
    float uv[6] = {0};
    static vx_gltf_material mats[2048];
    static const struct {
        float e[3];
        bool mr;        /* also samples metallic and roughness */
        uint32_t count; /* materials */
        uint32_t levels, block;
    } cases[] = {
        {{1, 1, 1}, false, 1, 6, 216},
        {{1, 0.5f, 0}, false, 1, 6, 36},
        {{0, 0, 2}, false, 1, 6, 6},
        {{1, 1, 1}, true, 8, 6, 7776},     /* 62,208 ids */
        {{1, 1, 1}, true, 9, 4, 1024},     /* at 6 levels 69,984 */
        {{1, 1, 1}, true, 64, 3, 243},     /* at 4 levels 65,536 */
        {{1, 1, 1}, true, 270, 2, 32},     /* at 3 levels 65,610 */
        {{1, 1, 1}, true, 2048, 0, 0},     /* at 2 levels 65,536: VX_ERR_LIMIT */
        {{0.5f, 0, 0}, true, 2048, 3, 27}, /* only R sampled: 3^3 ids each, 55,296 */
    };
    for (size_t ci = 0; ci < sizeof cases / sizeof cases[0]; ci++) {
        for (uint32_t i = 0; i < cases[ci].count; i++) {
            vx_gltf_material* g = &mats[i];
            memset(g, 0, sizeof *g);
            for (int k = 0; k < 4; k++) g->base_color[k] = 1;
            g->image = -1, g->roughness = 1, g->ior = 1.5f, g->metallic = cases[ci].mr ? 1.f : 0.f;
            memcpy(g->emissive, cases[ci].e, sizeof g->emissive);
            g->metal_rough.image = cases[ci].mr ? 0 : -1;
            g->emissive_tex.image = 0;
        }
        vx_gltf_mesh m;
        memset(&m, 0, sizeof m);
        m.images = &im, m.image_count = 1, m.uv_mr = uv, m.uv_emissive = uv;
        m.materials = mats, m.material_count = cases[ci].count;
        vx__mesh_mats p;
        vx_error err = {0};
        vx_result r = vx__mesh_mats_make(&m, NULL, &p, &err);
        if (!cases[ci].levels) {
            CHECKF(r == VX_ERR_LIMIT && strstr(err.msg, "more than 65535"), "case %zu: %s", ci, r ? err.msg : "accepted");
            if (!r) vx__mesh_mats_free(NULL, &p);
            continue;
        }
        CHECKF(r == VX_OK, "case %zu: %s", ci, err.msg);
        if (r) continue;
        CHECKF(p.levels == cases[ci].levels && p.m[0].block == cases[ci].block && p.m[cases[ci].count - 1].base ==
                   1 + (cases[ci].count - 1) * cases[ci].block,
               "case %zu: %u levels, block %u", ci, p.levels, p.m[0].block);
        /* the first and last materials' ids round-trip through their records */
        size_t bad = 0, lit = 0;
        for (uint32_t mi = 0; mi < cases[ci].count; mi += cases[ci].count > 1 ? cases[ci].count - 1 : 1)
            for (uint32_t k = 0; k < p.m[mi].block; k++) {
                uint32_t id = p.m[mi].base + k, back_mi = UINT32_MAX;
                float v[4], rgb[3];
                if (!vx__mesh_mats_record(&p, id, &back_mi, v, rgb)) continue; /* diffuse: no cell names it */
                float mx = rgb[0] > rgb[1] ? rgb[0] : rgb[1];
                mx = mx > rgb[2] ? mx : rgb[2];
                bad += back_mi != mi || vx__mesh_mats_id(&p, mi, v[0], v[1], rgb) != id || v[2] != mx;
                for (int c = 0; c < 3; c++) bad += cases[ci].e[c] == 0 && rgb[c] != 0; /* a channel whose factor is 0 stays 0 */
                lit += mx > 0;
            }
        CHECKF(bad == 0 && lit > 0, "case %zu: %zu ids do not round-trip", ci, bad);
        vx__mesh_mats_free(NULL, &p);
    }
}

int main(void) {
    RUN(test_boundary_faces);
    RUN(test_bottle);
    RUN(test_slivers_degenerate);
    RUN(test_large_and_random);
    RUN(test_parallel_binning);
    RUN(test_res_limit);
    RUN(test_nan);
    RUN(test_solid_hole);
    RUN(test_colors);
    RUN(test_corpus_box);
    RUN(test_corpus_duck);
    RUN(test_corpus_all);
    RUN(test_scene_select);
    RUN(test_texture_transform);
    RUN(test_unknown_image_media_type);
    RUN(test_sparse);
    RUN(test_versions_and_draco);
    RUN(test_far_origin);
    RUN(test_position_precision);
    RUN(test_emissive_texture);
    RUN(test_mats_emission_blocks);
    RUN(test_uri_directory);
    return vx_test_finish();
}
