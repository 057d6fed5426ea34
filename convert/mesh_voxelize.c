/* convert/mesh_voxelize.c - triangle voxelization by bricks.
 *
 * Exactness: a triangle meets the closed cell [i,i+1]x[j,j+1]x[k,k+1] iff
 * its part inside the column [i,i+1]x[j,j+1] (a convex polygon, found by
 * clipping against two slabs) spans a d-interval meeting [k,k+1]. So the
 * cells are enumerated by clipping strip by strip and column by column
 * (Sutherland-Hodgman with closed half-spaces; a clipped coordinate is set
 * exactly to the slab plane, the others interpolated from the nearer
 * endpoint), which is exact up to the rounding of the clip points
 * and handles zero-area triangles the same way. The half-open cells of
 * convert/mesh.h then drop a cell whose part of the triangle lies wholly
 * on one of its max faces (tri_cells). The clip of the column polygon
 * against the cell's d-slab also gives the area and centroid used to
 * weight and sample the attributes.
 */
#define _GNU_SOURCE /* sched_getaffinity: the cores this process may use */
#include "convert/mesh_internal.h"

#include <limits.h>
#include <math.h>
#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define BRICK 64
#define BRICK_CELLS (BRICK * BRICK * BRICK)
#define MAXP 16

/* ---- grid ------------------------------------------------------------------------ */

/* a - b rounded up: the double just above fl(a - b) when the subtraction
 * rounded down (two-sum error term), so that exact(a - b) <= the result. */
static double sub_up(double a, double b) {
    double s = a - b, bb = s - a, e = (a - (s - bb)) + (-b - bb);
    return e > 0 ? nextafter(s, INFINITY) : s;
}

vx_result vx_conv_mesh_grid_make(const float* pos, size_t tri_count, uint32_t res, vx_conv_mesh_grid* out,
                                 vx_error* err) {
    if (!out || (!pos && tri_count)) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "mesh grid: NULL argument");
    if (res == 0) res = 256;
    if (res > VX_CONV_MESH_RES_MAX)
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "mesh grid: res %u is more than %u", res, VX_CONV_MESH_RES_MAX);
    if (tri_count == 0) return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "mesh has no triangles");
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < tri_count * 9; i++) {
        double v = pos[i];
        if (!isfinite(v))
            return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "triangle %zu: vertex %zu has a NaN or infinite coordinate",
                           i / 9, (i % 9) / 3);
        int a = (int)(i % 3);
        if (v < lo[a]) lo[a] = v;
        if (v > hi[a]) hi[a] = v;
    }
    /* extents rounded up, h rounded up so that res * h >= L exactly (fma gives
     * the sign of the exact residual): the mesh's max faces then lie inside
     * the grid in exact arithmetic too, not an ulp beyond its last cell */
    double e[3], L = 0;
    for (int a = 0; a < 3; a++) {
        e[a] = sub_up(hi[a], lo[a]);
        L = fmax(L, e[a]);
    }
    double h = L > 0 ? L / res : 1.0;
    if (L > 0 && fma(h, (double)res, -L) < 0) h = nextafter(h, INFINITY);
    if (!(h > 0) || !isfinite(h)) return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "mesh bounds are degenerate");
    for (int a = 0; a < 3; a++) {
        /* the fewest cells n with n * h >= extent (exactly) */
        double c = ceil(e[a] / h);
        if (c < 1) c = 1;
        while (c > 1 && fma(c - 1, h, -e[a]) >= 0) c--;
        while (fma(c, h, -e[a]) < 0) c++;
        if (c > VX_CONV_MESH_RES_MAX) c = VX_CONV_MESH_RES_MAX;
        out->size[a] = (uint32_t)c;
        out->min[a] = lo[a];
    }
    out->h = h;
    return VX_OK;
}

/* ---- clipping ---------------------------------------------------------------------- */

/* The point of edge a-b on the plane p[axis] = val, interpolated from the
 * endpoint nearer the plane (the same for a-b as for b-a); exact for a
 * coordinate that is constant along the edge or changes by as much as
 * p[axis] does (a diagonal edge y == z meets y = 64 at z = 64 exactly). */
static inline void clip_point(const double* a, const double* b, int axis, double val, double* out) {
    if (fabs(b[axis] - val) < fabs(a[axis] - val)) {
        const double* t = a;
        a = b;
        b = t;
    }
    double da = b[axis] - a[axis], s = val - a[axis], t = s / da;
    for (int k = 0; k < 3; k++) {
        double dk = b[k] - a[k];
        out[k] = dk == 0 ? a[k] : dk == da ? a[k] + s : dk == -da ? a[k] - s : a[k] + t * dk;
    }
    out[axis] = val;
}

/* Keeps the part of polygon in[n] with lo <= p[axis] <= hi. */
static int clip_slab(const double (*in)[3], int n, int axis, double lo, double hi, double (*out)[3]) {
    double tmp[MAXP][3];
    int m = 0;
    for (int i = 0; i < n; i++) { /* p[axis] >= lo */
        const double* a = in[i];
        const double* b = in[(i + 1) % n];
        bool ia = a[axis] >= lo, ib = b[axis] >= lo;
        if (ia) memcpy(tmp[m++], a, sizeof tmp[0]);
        if (ia != ib) clip_point(a, b, axis, lo, tmp[m++]);
    }
    int r = 0;
    for (int i = 0; i < m; i++) { /* p[axis] <= hi */
        const double* a = tmp[i];
        const double* b = tmp[(i + 1) % m];
        bool ia = a[axis] <= hi, ib = b[axis] <= hi;
        if (ia) memcpy(out[r++], a, sizeof tmp[0]);
        if (ia != ib) clip_point(a, b, axis, hi, out[r++]);
    }
    return r;
}

static void poly_range(const double (*p)[3], int n, int axis, double* lo, double* hi) {
    double a = p[0][axis], b = a;
    for (int i = 1; i < n; i++) {
        double v = p[i][axis];
        a = v < a ? v : a;
        b = v > b ? v : b;
    }
    *lo = a;
    *hi = b;
}

static void poly_box(const double (*p)[3], int n, double mn[3], double mx[3]) {
    for (int k = 0; k < 3; k++) mn[k] = mx[k] = p[0][k];
    for (int i = 1; i < n; i++)
        for (int k = 0; k < 3; k++) {
            double v = p[i][k];
            mn[k] = v < mn[k] ? v : mn[k];
            mx[k] = v > mx[k] ? v : mx[k];
        }
}

/* Cells i meeting [lo, hi], clamped to [cmin, cmax]. last == ALL_CLOSED:
 * closed cells [i, i+1] (a superset, for binning); otherwise half-open
 * cells [i, i+1) except the closed cell [last, last + 1] (the grid's last
 * cell; NO_LAST when it is not in [cmin, cmax]). */
#define ALL_CLOSED INT_MIN
#define NO_LAST INT_MAX
static bool cell_range(double lo, double hi, int cmin, int cmax, int last, int* a, int* b) {
    double fa = last == ALL_CLOSED ? ceil(lo) - 1 : floor(lo), fb = floor(hi);
    if (last != ALL_CLOSED && lo == (double)last + 1) fa = last;
    if (fa < cmin) fa = cmin;
    if (fb > cmax) fb = cmax;
    if (fa > fb) return false;
    *a = (int)fa;
    *b = (int)fb;
    return true;
}

/* The axis the cells are stacked along: the dominant normal axis (few cells
 * per column), or for a zero-area triangle the axis of its longest extent. */
static int stack_axis(const double* v) {
    double e1[3], e2[3], n[3];
    for (int k = 0; k < 3; k++) {
        e1[k] = v[3 + k] - v[k];
        e2[k] = v[6 + k] - v[k];
    }
    n[0] = fabs(e1[1] * e2[2] - e1[2] * e2[1]);
    n[1] = fabs(e1[2] * e2[0] - e1[0] * e2[2]);
    n[2] = fabs(e1[0] * e2[1] - e1[1] * e2[0]);
    if (n[0] + n[1] + n[2] > 0) return n[0] >= n[1] && n[0] >= n[2] ? 0 : (n[1] >= n[2] ? 1 : 2);
    double ext[3];
    for (int k = 0; k < 3; k++)
        ext[k] = fmax(fmax(v[k], v[3 + k]), v[6 + k]) - fmin(fmin(v[k], v[3 + k]), v[6 + k]);
    return ext[0] >= ext[1] && ext[0] >= ext[2] ? 0 : (ext[1] >= ext[2] ? 1 : 2);
}

typedef void (*cell_fn)(void* user, const int c[3], const double (*poly)[3], int n);

/* Does polygon p[n] (inside the closed cell box) keep a point off the max
 * face of the cell at index c along axis (p[axis] < c + 1)? The grid's last
 * cell is closed: always. */
static bool off_max(const double (*p)[3], int n, int axis, int c, int last) {
    if (c == last) return true;
    for (int i = 0; i < n; i++)
        if (p[i][axis] < c + 1) return true;
    return false;
}

/* Calls fn for every cell in [cmin, cmax] (inclusive, per axis) whose box
 * meets triangle v (unit-cell coordinates). last == NULL: closed boxes
 * [c, c+1] (a superset, for binning); otherwise the rule of convert/mesh.h:
 * half-open boxes [c, c+1) per axis, closed at the top along axis a when
 * c == last[a] (the grid's last cell; NO_LAST when outside [cmin, cmax]).
 * With want_poly, poly is the part of the triangle inside the closed box.
 *
 * The half-open test: the triangle's part P inside the closed box is convex,
 * so it misses the half-open box iff it lies within one max face, i.e. iff
 * min over P of p[a] == c[a] + 1 for some axis a. Along the stack axis the
 * cell range does this; along u and w the clipped polygons are checked:
 * a whole column polygon on a max face is skipped, and a cell's part can
 * only lie on a max face where the cell's d-slab meets the column polygon
 * in one plane (a convex polygon's part in a slab of positive thickness
 * is no thinner than the polygon itself). */
static void tri_cells(const double* v, const int cmin[3], const int cmax[3], const int* last, bool want_poly,
                      cell_fn fn, void* user) {
    int d = stack_axis(v), u = (d + 1) % 3, w = (d + 2) % 3;
    int lu = last ? last[u] : ALL_CLOSED, lw = last ? last[w] : ALL_CLOSED, ld = last ? last[d] : ALL_CLOSED;
    double tri[3][3], p1[MAXP][3], p2[MAXP][3], p3[MAXP][3];
    memcpy(tri, v, sizeof tri);
    double lo, hi;
    int ua, ub, wa, wb, da, db, c[3];
    /* fast path: the whole triangle inside one cell interior */
    int fc[3];
    bool inside = true;
    for (int k = 0; k < 3 && inside; k++) {
        poly_range((const double(*)[3])tri, 3, k, &lo, &hi);
        double f = floor(lo);
        fc[k] = (int)f;
        inside = lo > f && hi < f + 1 && f >= cmin[k] && f <= cmax[k];
    }
    if (inside) {
        fn(user, fc, (const double(*)[3])tri, 3);
        return;
    }
    poly_range((const double(*)[3])tri, 3, u, &lo, &hi);
    if (!cell_range(lo, hi, cmin[u], cmax[u], lu, &ua, &ub)) return;
    for (int iu = ua; iu <= ub; iu++) {
        int n1 = clip_slab((const double(*)[3])tri, 3, u, iu, iu + 1, p1);
        if (n1 == 0) continue;
        poly_range((const double(*)[3])p1, n1, w, &lo, &hi);
        if (!cell_range(lo, hi, cmin[w], cmax[w], lw, &wa, &wb)) continue;
        for (int iw = wa; iw <= wb; iw++) {
            int n2 = clip_slab((const double(*)[3])p1, n1, w, iw, iw + 1, p2);
            if (n2 == 0) continue;
            double mn[3], mx[3];
            poly_box((const double(*)[3])p2, n2, mn, mx);
            bool check = false; /* does the column polygon touch a max face of u or w? */
            if (last) {
                if ((iu != lu && mn[u] >= iu + 1) || (iw != lw && mn[w] >= iw + 1))
                    continue; /* all of it on u = iu + 1 or on w = iw + 1 */
                check = (iu != lu && mx[u] >= iu + 1) || (iw != lw && mx[w] >= iw + 1);
            }
            lo = mn[d];
            hi = mx[d];
            if (!cell_range(lo, hi, cmin[d], cmax[d], ld, &da, &db)) continue;
            c[u] = iu;
            c[w] = iw;
            for (int id = da; id <= db; id++) {
                c[d] = id;
                /* the part in the cell can lie wholly on a max face of u or w
                 * only where the d-slab meets the column polygon in a single
                 * plane: at d = hi = id, or d = lo = id + 1 in the last cell */
                bool edge = check && ((double)id == hi || (id == ld && lo == id + 1.0));
                if (!want_poly && !edge) {
                    fn(user, c, NULL, 0);
                    continue;
                }
                int n3 = clip_slab((const double(*)[3])p2, n2, d, id, id + 1, p3);
                if (n3 == 0) { /* rounding: keep the cell the range test found, with a point */
                    memcpy(p3[0], p2[0], sizeof p3[0]);
                    n3 = 1;
                }
                if (edge && (!off_max((const double(*)[3])p3, n3, u, iu, lu) ||
                             !off_max((const double(*)[3])p3, n3, w, iw, lw)))
                    continue; /* only the cell's max face is touched */
                fn(user, c, want_poly ? (const double(*)[3])p3 : NULL, want_poly ? n3 : 0);
            }
        }
    }
}

/* ---- colour --------------------------------------------------------------------------- */

static float srgb_to_lin[256];
static float srgb_threshold[256]; /* linear value half-way between sRGB codes k and k+1; [255] = 2 */
static float unit8[256];           /* k / 255.0f: the same float as the division, without one per texel */
static uint8_t srgb_guess[4097];   /* code at the start of each 1/4096 step of linear values */
static pthread_once_t tables_once = PTHREAD_ONCE_INIT;

static double srgb_decode(double s) { return s <= 0.04045 ? s / 12.92 : pow((s + 0.055) / 1.055, 2.4); }
static void init_tables(void) {
    for (int i = 0; i < 256; i++) srgb_to_lin[i] = (float)srgb_decode(i / 255.0);
    for (int i = 0; i < 256; i++) unit8[i] = i / 255.0f;
    for (int i = 0; i < 255; i++) srgb_threshold[i] = (float)srgb_decode((i + 0.5) / 255.0);
    srgb_threshold[255] = 2.0f;
    int c = 0;
    for (int i = 0; i <= 4096; i++) {
        while (srgb_threshold[c] < i / 4096.0f) c++;
        srgb_guess[i] = (uint8_t)c;
    }
}
/* The sRGB code nearest in sRGB space (the number of half-way thresholds
 * below v): a table guess, then at most a few steps up. */
static uint32_t lin_to_srgb8(float v) {
    if (!(v > 0)) return 0;
    if (v >= 1) return 255;
    uint32_t c = srgb_guess[(int)(v * 4096.0f)];
    while (srgb_threshold[c] < v) c++;
    return c;
}
void vx__mesh_color_tables(float thr[256], uint32_t guess[4097], float lin[256], float a255[256]) {
    pthread_once(&tables_once, init_tables);
    for (int i = 0; i < 256; i++) {
        thr[i] = srgb_threshold[i];
        lin[i] = srgb_to_lin[i];
        a255[i] = i / 255.0f;
    }
    for (int i = 0; i <= 4096; i++) guess[i] = srgb_guess[i];
}

static uint32_t unorm8(float v) {
    if (!(v > 0)) return 0;
    if (v >= 1) return 255;
    return (uint32_t)lrintf(v * 255.0f);
}

static int64_t wrap_coord(int64_t x, int64_t n, int mode) {
    /* inside the image every mode is x; the 64-bit divisions below were the
     * most of a sample (four coordinates a sample, up to three samples a
     * piece with per-cell materials) */
    if (x >= 0 && x < n) return x;
    if (mode == VX_GLTF_WRAP_CLAMP) return x < 0 ? 0 : (x >= n ? n - 1 : x);
    if (mode == VX_GLTF_WRAP_MIRROR) {
        int64_t m = ((x % (2 * n)) + 2 * n) % (2 * n);
        return m >= n ? 2 * n - 1 - m : m;
    }
    return ((x % n) + n) % n;
}

/* The four texels and bilinear weights of a sample at (s, t) of a w x h
 * image with the wrap modes: byte offsets into its RGBA. Images of one size
 * and wraps sampled at one (s, t) share it (texel_fetch). */
typedef struct texel_foot {
    size_t off[4];
    float wgt[4];
} texel_foot;

static void texel_footprint(uint32_t w, uint32_t h, int ws, int wt, double s, double t, texel_foot* f) {
    if (!(fabs(s) < 1e9)) s = 0; /* also NaN */
    if (!(fabs(t) < 1e9)) t = 0;
    double x = s * w - 0.5, y = t * h - 0.5;
    double fx = floor(x), fy = floor(y);
    float ax = (float)(x - fx), ay = (float)(y - fy);
    int64_t x0 = (int64_t)fx, y0 = (int64_t)fy;
    int64_t xs[2] = {wrap_coord(x0, w, ws), wrap_coord(x0 + 1, w, ws)};
    int64_t ys[2] = {wrap_coord(y0, h, wt), wrap_coord(y0 + 1, h, wt)};
    f->wgt[0] = (1 - ax) * (1 - ay), f->wgt[1] = ax * (1 - ay), f->wgt[2] = (1 - ax) * ay, f->wgt[3] = ax * ay;
    for (int k = 0; k < 4; k++) f->off[k] = ((size_t)ys[k >> 1] * w + (size_t)xs[k & 1]) * 4;
}

/* The bilinear sample of im over footprint f: RGB sRGB-decoded when srgb
 * (colour), else bytes / 255 as alpha always is (glTF's metallic-roughness
 * texture is linear). */
static void texel_fetch(const vx_gltf_image* im, const texel_foot* f, bool srgb, float out[4]) {
    const float* rgb = srgb ? srgb_to_lin : unit8;
    for (int c = 0; c < 4; c++) out[c] = 0;
    for (int k = 0; k < 4; k++) {
        const uint8_t* p = im->rgba + f->off[k];
        out[0] += f->wgt[k] * rgb[p[0]];
        out[1] += f->wgt[k] * rgb[p[1]];
        out[2] += f->wgt[k] * rgb[p[2]];
        out[3] += f->wgt[k] * unit8[p[3]];
    }
}

static uint32_t oct_encode(double x, double y, double z) {
    double l = fabs(x) + fabs(y) + fabs(z);
    if (!(l > 0)) { x = 0; y = 0; z = 1; l = 1; }
    double px = x / l, py = y / l;
    if (z < 0) {
        double ox = (1 - fabs(py)) * (px >= 0 ? 1 : -1), oy = (1 - fabs(px)) * (py >= 0 ? 1 : -1);
        px = ox;
        py = oy;
    }
    int32_t sx = (int32_t)lrint(fmax(-1, fmin(1, px)) * 32767), sy = (int32_t)lrint(fmax(-1, fmin(1, py)) * 32767);
    return (uint32_t)(uint16_t)(int16_t)sx | ((uint32_t)(uint16_t)(int16_t)sy << 16);
}

/* ---- the job ----------------------------------------------------------------------- */

typedef struct acc {
    float c[4], w, n[3];
    float mw;     /* the largest clipped area seen, and its material (id; index with sampled materials) */
    uint16_t mat;
    uint32_t mi;
    float pm, pr, pe[3]; /* with sampled materials: weighted sums of metallic, roughness, emission RGB */
} acc;

typedef struct brick_out {
    size_t count;
    uint32_t* local; /* local Morton keys, sorted */
    uint32_t* rgba;
    uint32_t* normal;
    uint16_t* material;
} brick_out;

typedef struct job {
    const vx_conv_mesh_desc* desc;
    const vx_gltf_mesh* mesh;
    const vx_conv_mesh_grid* grid;
    const vx_allocator* alloc;
    uint32_t attrs;
    bool color, normals, materials;
    bool sampling;           /* some material samples metallic-roughness or emission per cell */
    vx__mesh_mats mats;      /* the material ids (j->materials) */
    double* g;               /* grid coordinates, 9 per triangle */
    uint64_t* pairs;         /* brick Morton << 32 | triangle, sorted by brick */
    size_t pair_count;
    uint32_t nb[3];          /* bricks per axis */
    uint64_t* vote[3];       /* solid: parity per axis, bit x + n0 (y + n1 z) */
    /* current region */
    const size_t* brick_first; /* pair index of each brick of the region; [brick_count] = end */
    size_t brick_count;
    brick_out* outs;
    atomic_size_t done;       /* its bricks voxelized */
    size_t done_before;       /* bricks of this share's regions before it, for the progress */
    struct worker* workers;         /* one per thread (vx_run_jobs' thread index) */
    atomic_int failed; /* vx_result */
    atomic_bool cancel;
    /* all regions */
    size_t* bstart;        /* pair index where each brick starts; [total_bricks] = pair_count */
    size_t total_bricks;
    size_t* rstart;        /* brick index where each region starts; [region_count] = total_bricks */
    size_t region_count;
    size_t* mine;          /* the regions this share converts, ascending (all of them for one share) */
    size_t mine_count;
    size_t mine_bricks;    /* their bricks: the progress total */
    unsigned rb;           /* region = 2^rb bricks per side */
    uint32_t R;
    atomic_size_t bricks_done;
    pthread_mutex_t lock;
    vx_error first_err;    /* the first failure of a region worker */
    vx__mesh_sink sink;
    void* user;
} job;

static uint32_t mort6[BRICK][3]; /* local Morton bits of x, y, z in a brick */
static void init_mort6(void) {
    for (uint32_t i = 0; i < BRICK; i++)
        for (int a = 0; a < 3; a++) {
            uint32_t m = 0;
            for (int b = 0; b < 6; b++) m |= ((i >> b) & 1u) << (3 * b + a);
            mort6[i][a] = m;
        }
}
static pthread_once_t mort_once = PTHREAD_ONCE_INIT;

typedef struct region_buf {
    uint64_t* keys;
    uint32_t *rgba, *nrm;
    uint16_t* mat;
    size_t kcap, rcap, ncap, mcap;
} region_buf;

typedef struct worker {
    job* j;
    region_buf buf;
    uint64_t* bits; /* BRICK_CELLS bits of the current brick */
    /* When attributes: the brick's touched cells' sums, packed in the order
     * the cells were first hit (acc[slot[m]] is cell m's where its bit is
     * set): room for BRICK_CELLS, but only as many pages touched as cells a
     * brick has (indexed by cell, 64-byte sums faulted in 16 MiB a worker:
     * 8 k of DamagedHelmet's 44 k page faults at 256; docs/PERFORMANCE.md
     * section 3). */
    acc* acc;
    uint32_t* slot;
    uint32_t acc_count;
    uint32_t* fin_rgba;
    uint32_t* fin_nrm;
    uint16_t* fin_mat;
    /* current triangle */
    const double* v; /* local coordinates */
    float uv[6], col[12], base[4], nrm[3];
    uint16_t mat;
    const vx_gltf_image* img;
    int ws, wt;
    double d00, d01, d11, den;
    /* j->sampling: the triangle's material index, its factors per piece
     * (vx__mesh_mat's; a triangle without material: 0, 1, 0) and the
     * textures it samples them from */
    uint32_t mi;
    uint8_t samp; /* VX__MESH_SAMPLE_*: a channel not sampled is its factor (a uniform texture folded in) */
    float metal, rough, emit[3];
    const vx_gltf_image *mr_img, *em_img;
    int mr_ws, mr_wt, em_ws, em_wt;
    bool mr_shares, em_shares; /* sampled over the colour's footprint (hit_attr) */
    float uv_mr[6], uv_em[6];
} worker;

static void hit_geom(void* user, const int c[3], const double (*poly)[3], int n) {
    (void)poly;
    (void)n;
    worker* w = (worker*)user;
    uint32_t m = mort6[c[0]][0] | mort6[c[1]][1] | mort6[c[2]][2];
    w->bits[m >> 6] |= 1ull << (m & 63);
}

static void hit_attr(void* user, const int c[3], const double (*p)[3], int n) {
    worker* w = (worker*)user;
    uint32_t m = mort6[c[0]][0] | mort6[c[1]][1] | mort6[c[2]][2];
    acc* a;
    if (!(w->bits[m >> 6] & (1ull << (m & 63)))) {
        w->bits[m >> 6] |= 1ull << (m & 63);
        w->slot[m] = w->acc_count;
        a = &w->acc[w->acc_count++];
        memset(a, 0, sizeof *a);
    } else {
        a = &w->acc[w->slot[m]];
    }
    /* area and centroid of the clipped polygon (fan from p[0]) */
    double area = 0, cen[3] = {0, 0, 0};
    for (int i = 1; i + 1 < n; i++) {
        double e1[3], e2[3];
        for (int k = 0; k < 3; k++) {
            e1[k] = p[i][k] - p[0][k];
            e2[k] = p[i + 1][k] - p[0][k];
        }
        double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2], cz = e1[0] * e2[1] - e1[1] * e2[0];
        double ar = 0.5 * sqrt(cx * cx + cy * cy + cz * cz);
        area += ar;
        for (int k = 0; k < 3; k++) cen[k] += ar * (p[0][k] + p[i][k] + p[i + 1][k]) / 3.0;
    }
    if (area > 0) {
        for (int k = 0; k < 3; k++) cen[k] /= area;
    } else {
        for (int k = 0; k < 3; k++) {
            cen[k] = 0;
            for (int i = 0; i < n; i++) cen[k] += p[i][k];
            cen[k] /= n;
        }
    }
    /* zero-area pieces still count a little, so a cell touched only by an
     * edge or a degenerate triangle gets that triangle's attributes */
    float wgt = (float)(area + 1e-7);
    double b0 = 1.0 / 3, b1 = 1.0 / 3, b2 = 1.0 / 3; /* the centroid's barycentrics, where sampled */
    if ((w->j->color || w->j->sampling) && w->den > 0) {
        const double* v = w->v;
        double v2[3], d20 = 0, d21 = 0;
        for (int k = 0; k < 3; k++) v2[k] = cen[k] - v[k];
        for (int k = 0; k < 3; k++) {
            d20 += v2[k] * (v[3 + k] - v[k]);
            d21 += v2[k] * (v[6 + k] - v[k]);
        }
        b1 = (w->d11 * d20 - w->d01 * d21) / w->den;
        b2 = (w->d00 * d21 - w->d01 * d20) / w->den;
        b0 = 1 - b1 - b2;
    }
    /* the colour's footprint, shared by the metallic-roughness and emissive
     * textures where they are sampled at the same uv with the same size and
     * wraps (setup_tri_sampling: DamagedHelmet's three 2048^2 images) */
    texel_foot fc, fo;
    if (w->j->color) {
        float col[4];
        for (int k = 0; k < 4; k++)
            col[k] = w->base[k] * (float)(b0 * w->col[k] + b1 * w->col[4 + k] + b2 * w->col[8 + k]);
        if (w->img) {
            float t[4];
            texel_footprint(w->img->width, w->img->height, w->ws, w->wt, b0 * w->uv[0] + b1 * w->uv[2] + b2 * w->uv[4],
                            b0 * w->uv[1] + b1 * w->uv[3] + b2 * w->uv[5], &fc);
            texel_fetch(w->img, &fc, true, t);
            for (int k = 0; k < 4; k++) col[k] *= t[k];
        }
        for (int k = 0; k < 4; k++) a->c[k] += wgt * col[k];
    }
    if (w->j->sampling) { /* metallic, roughness and emission at the same point, weighted the same */
        float pm = w->metal, pr = w->rough, pe[3] = {w->emit[0], w->emit[1], w->emit[2]}, t[4];
        if (w->mr_img) {
            const texel_foot* f = &fc;
            if (!w->mr_shares) {
                texel_footprint(w->mr_img->width, w->mr_img->height, w->mr_ws, w->mr_wt,
                                b0 * w->uv_mr[0] + b1 * w->uv_mr[2] + b2 * w->uv_mr[4],
                                b0 * w->uv_mr[1] + b1 * w->uv_mr[3] + b2 * w->uv_mr[5], &fo);
                f = &fo;
            }
            texel_fetch(w->mr_img, f, false, t);
            if (w->samp & VX__MESH_SAMPLE_METAL) pm *= t[2]; /* glTF: metalness in B, roughness in G */
            if (w->samp & VX__MESH_SAMPLE_ROUGH) pr *= t[1];
        }
        if (w->em_img) {
            const texel_foot* f = &fc;
            if (!w->em_shares) {
                texel_footprint(w->em_img->width, w->em_img->height, w->em_ws, w->em_wt,
                                b0 * w->uv_em[0] + b1 * w->uv_em[2] + b2 * w->uv_em[4],
                                b0 * w->uv_em[1] + b1 * w->uv_em[3] + b2 * w->uv_em[5], &fo);
                f = &fo;
            }
            texel_fetch(w->em_img, f, true, t);
            for (int k = 0; k < 3; k++) pe[k] *= t[k];
        }
        a->pm += wgt * pm;
        a->pr += wgt * pr;
        for (int k = 0; k < 3; k++) a->pe[k] += wgt * pe[k];
    }
    for (int k = 0; k < 3; k++) a->n[k] += wgt * w->nrm[k];
    a->w += wgt;
    /* the material of the triangle with the largest piece in the cell */
    if (wgt > a->mw) a->mw = wgt, a->mat = w->mat, a->mi = w->mi;
}

/* Whether texture b is sampled over texture a's footprints: the same size,
 * wraps and corner uvs (bit for bit, so the same (s, t) everywhere). */
static bool same_footprint(const vx_gltf_image* a, int aws, int awt, const float auv[6], const vx_gltf_image* b, int bws,
                           int bwt, const float buv[6]) {
    return a->width == b->width && a->height == b->height && aws == bws && awt == bwt && memcmp(auv, buv, 6 * sizeof *auv) == 0;
}

/* The triangle's metallic, roughness and emission factors and the
 * textures that vary them (vx__mesh_mats decides which do). */
static void setup_tri_sampling(worker* w, uint32_t mi, size_t t) {
    const vx_gltf_mesh* mesh = w->j->mesh;
    w->mr_img = w->em_img = NULL;
    w->mr_shares = w->em_shares = false;
    w->samp = 0;
    w->metal = 0, w->rough = 1;
    w->emit[0] = w->emit[1] = w->emit[2] = 0;
    if (mi >= w->j->mats.count) return;
    const vx__mesh_mat* p = &w->j->mats.m[mi];
    const vx_gltf_material* g = &mesh->materials[mi];
    w->metal = p->metal, w->rough = p->rough;
    memcpy(w->emit, p->emit, sizeof w->emit);
    w->samp = p->sample;
    if (p->sample & (VX__MESH_SAMPLE_METAL | VX__MESH_SAMPLE_ROUGH)) {
        w->mr_img = &mesh->images[g->metal_rough.image];
        w->mr_ws = g->metal_rough.wrap_s, w->mr_wt = g->metal_rough.wrap_t;
        memcpy(w->uv_mr, mesh->uv_mr + 6 * t, sizeof w->uv_mr);
    }
    if (p->sample & VX__MESH_SAMPLE_EMIT) {
        w->em_img = &mesh->images[g->emissive_tex.image];
        w->em_ws = g->emissive_tex.wrap_s, w->em_wt = g->emissive_tex.wrap_t;
        memcpy(w->uv_em, mesh->uv_emissive + 6 * t, sizeof w->uv_em);
    }
}

static void setup_tri_attrs(worker* w, size_t t) {
    const vx_gltf_mesh* mesh = w->j->mesh;
    const double* v = w->v;
    double e1[3], e2[3];
    for (int k = 0; k < 3; k++) {
        e1[k] = v[3 + k] - v[k];
        e2[k] = v[6 + k] - v[k];
    }
    double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int k = 0; k < 3; k++) w->nrm[k] = l > 0 ? (float)(n[k] / l) : 0.f;
    w->d00 = e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2];
    w->d11 = e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2];
    w->d01 = e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2];
    w->den = w->d00 * w->d11 - w->d01 * w->d01;
    if (!(w->den > 1e-30 * w->d00 * w->d11)) w->den = 0;
    uint32_t mi = mesh->material ? mesh->material[t] : UINT32_MAX;
    static const float no_emit[3] = {0, 0, 0};
    w->mat = w->j->materials ? vx__mesh_mats_id(&w->j->mats, mi, 0, 0, no_emit) : 0;
    w->mi = mi;
    if (w->j->sampling) setup_tri_sampling(w, mi, t);
    if (!w->j->color) return;
    w->img = NULL;
    for (int k = 0; k < 4; k++) w->base[k] = 1.f;
    if (mi < mesh->material_count) {
        const vx_gltf_material* m = &mesh->materials[mi];
        memcpy(w->base, m->base_color, sizeof w->base);
        if (m->image >= 0 && (uint32_t)m->image < mesh->image_count && mesh->images[m->image].rgba && mesh->uv) {
            w->img = &mesh->images[m->image];
            w->ws = m->wrap_s;
            w->wt = m->wrap_t;
        }
    }
    if (w->img) memcpy(w->uv, mesh->uv + 6 * t, sizeof w->uv);
    if (mesh->color) memcpy(w->col, mesh->color + 12 * t, sizeof w->col);
    else for (int k = 0; k < 12; k++) w->col[k] = 1.f;
    if (w->j->sampling && w->img) {
        w->mr_shares = w->mr_img && same_footprint(w->img, w->ws, w->wt, w->uv, w->mr_img, w->mr_ws, w->mr_wt, w->uv_mr);
        w->em_shares = w->em_img && same_footprint(w->img, w->ws, w->wt, w->uv, w->em_img, w->em_ws, w->em_wt, w->uv_em);
    }
}

static bool majority(uint64_t* const vote[3], const uint32_t n[3], uint32_t x, uint32_t y, uint32_t z) {
    uint64_t i = x + (uint64_t)n[0] * (y + (uint64_t)n[1] * z);
    uint64_t m = 1ull << (i & 63);
    int v = !!(vote[0][i >> 6] & m) + !!(vote[1][i >> 6] & m) + !!(vote[2][i >> 6] & m);
    return v >= 2;
}

/* The solid fill of a brick at org (cells up to cmax per axis): the cells
 * that are not surface (bits) and inside by the votes, into inner. */
static void solid_inner(uint64_t* const vote[3], const uint32_t n[3], const uint32_t org[3], const int cmax[3],
                        const uint64_t* bits, uint64_t* inner) {
    memset(inner, 0, BRICK_CELLS / 8);
    for (int z = 0; z <= cmax[2]; z++)
        for (int y = 0; y <= cmax[1]; y++)
            for (int x = 0; x <= cmax[0]; x++) {
                uint32_t m = mort6[x][0] | mort6[y][1] | mort6[z][2];
                if (bits[m >> 6] & (1ull << (m & 63))) continue;
                if (majority(vote, n, org[0] + x, org[1] + y, org[2] + z)) inner[m >> 6] |= 1ull << (m & 63);
            }
}

/* The interior cells' attributes (fin_* hold the surface cells' finished
 * ones): the nearest surface cell before them in their x row, else the
 * brick's first surface cell (Morton order), else opaque white / +z. */
static void solid_attrs(const int cmax[3], const uint64_t* bits, const uint64_t* inner, uint32_t* fin_rgba, uint32_t* fin_nrm,
                        uint16_t* fin_mat) {
    uint32_t first_rgba = 0xFFFFFFFFu, first_nrm = oct_encode(0, 0, 1);
    uint16_t first_mat = 0;
    for (size_t i = 0; i < BRICK_CELLS / 64; i++)
        if (bits[i]) {
            uint32_t m = (uint32_t)(i * 64 + (size_t)__builtin_ctzll(bits[i]));
            first_rgba = fin_rgba[m], first_nrm = fin_nrm[m], first_mat = fin_mat[m];
            break;
        }
    for (int z = 0; z <= cmax[2]; z++)
        for (int y = 0; y <= cmax[1]; y++) {
            uint32_t cr = first_rgba, cn = first_nrm;
            uint16_t cm = first_mat;
            for (int x = 0; x <= cmax[0]; x++) {
                uint32_t m = mort6[x][0] | mort6[y][1] | mort6[z][2];
                if (bits[m >> 6] & (1ull << (m & 63))) {
                    cr = fin_rgba[m];
                    cn = fin_nrm[m];
                    cm = fin_mat[m];
                } else if (inner[m >> 6] & (1ull << (m & 63))) {
                    fin_rgba[m] = cr;
                    fin_nrm[m] = cn;
                    fin_mat[m] = cm;
                }
            }
        }
}

/* A brick's origin and last cells in the grid (do_brick's; last: NO_LAST
 * unless the grid's last cell along that axis is in the brick). */
static void brick_extent(uint64_t bm, const uint32_t size[3], uint32_t org[3], int cmax[3], int last[3]) {
    uint32_t bx, by, bz;
    vx_svo_demorton(bm, &bx, &by, &bz);
    org[0] = bx * BRICK, org[1] = by * BRICK, org[2] = bz * BRICK;
    for (int a = 0; a < 3; a++) {
        uint32_t left = size[a] - org[a];
        cmax[a] = (int)(left < BRICK ? left : BRICK) - 1;
        last[a] = left <= BRICK ? cmax[a] : NO_LAST;
    }
}

/* A surface cell's material id: its largest piece's material, with the
 * levels of its averages where that material samples them. */
static uint16_t cell_material(const job* j, const acc* a) {
    if (!j->sampling) return a->mat;
    float w = a->w > 0 ? a->w : 1.f;
    float e[3] = {a->pe[0] / w, a->pe[1] / w, a->pe[2] / w};
    return vx__mesh_mats_id(&j->mats, a->mi, a->pm / w, a->pr / w, e);
}

static uint32_t finish_rgba(const acc* a) {
    float c[4];
    for (int k = 0; k < 4; k++) c[k] = a->w > 0 ? a->c[k] / a->w : 1.f;
    return lin_to_srgb8(c[0]) | lin_to_srgb8(c[1]) << 8 | lin_to_srgb8(c[2]) << 16 | unorm8(c[3]) << 24;
}

/* Voxelizes brick b of the current region into j->outs[b]. */
static vx_result do_brick(worker* w, size_t first, size_t end, brick_out* o) {
    job* j = w->j;
    uint32_t org[3];
    int cmin[3] = {0, 0, 0}, cmax[3], last[3];
    brick_extent(j->pairs[first] >> 32, j->grid->size, org, cmax, last);
    bool attrs = j->attrs != 0;
    memset(w->bits, 0, BRICK_CELLS / 8);
    w->acc_count = 0;
    for (size_t p = first; p < end; p++) {
        size_t t = (size_t)(j->pairs[p] & 0xFFFFFFFFu);
        if (t == 0xFFFFFFFFu) continue; /* solid filler: a brick with no triangle */
        double v[9];
        for (int k = 0; k < 9; k++) v[k] = j->g[9 * t + k] - org[k % 3];
        w->v = v;
        if (attrs) setup_tri_attrs(w, t);
        tri_cells(v, cmin, cmax, last, attrs, attrs ? hit_attr : hit_geom, w);
    }
    /* solid: interior cells, marked in a second bitmap half (after the surface bits) */
    bool solid = j->vote[0] != NULL;
    uint64_t* inner = w->bits + BRICK_CELLS / 64;
    size_t count = 0;
    if (solid) solid_inner(j->vote, j->grid->size, org, cmax, w->bits, inner);
    for (size_t i = 0; i < BRICK_CELLS / 64; i++)
        count += (size_t)__builtin_popcountll(w->bits[i]) + (solid ? (size_t)__builtin_popcountll(inner[i]) : 0);
    o->count = count;
    if (count == 0) return VX_OK;
    o->local = (uint32_t*)vx_alloc(j->alloc, count * 4);
    if (j->attrs & VX_ATTR_RGBA8) o->rgba = (uint32_t*)vx_alloc(j->alloc, count * 4);
    if (j->attrs & VX_ATTR_NORMAL) o->normal = (uint32_t*)vx_alloc(j->alloc, count * 4);
    if (j->materials) o->material = (uint16_t*)vx_alloc(j->alloc, count * 2);
    if (!o->local || ((j->attrs & VX_ATTR_RGBA8) && !o->rgba) || ((j->attrs & VX_ATTR_NORMAL) && !o->normal) ||
        (j->materials && !o->material))
        return VX_ERR_NOMEM;
    if (solid && attrs) {
        /* final surface attributes, then interior cells copy the nearest
         * surface cell before them in their x row (else the brick's first) */
        for (size_t i = 0; i < BRICK_CELLS / 64; i++)
            for (uint64_t word = w->bits[i]; word; word &= word - 1) {
                uint32_t m = (uint32_t)(i * 64 + (size_t)__builtin_ctzll(word));
                const acc* a = &w->acc[w->slot[m]];
                w->fin_rgba[m] = finish_rgba(a);
                w->fin_nrm[m] = oct_encode(a->n[0], a->n[1], a->n[2]);
                w->fin_mat[m] = cell_material(j, a);
            }
        solid_attrs(cmax, w->bits, inner, w->fin_rgba, w->fin_nrm, w->fin_mat);
    }
    size_t k = 0;
    for (size_t i = 0; i < BRICK_CELLS / 64; i++) {
        uint64_t word = w->bits[i] | (solid ? inner[i] : 0);
        for (; word; word &= word - 1) {
            uint32_t m = (uint32_t)(i * 64 + (size_t)__builtin_ctzll(word));
            o->local[k] = m;
            if (attrs && solid) {
                if (o->rgba) o->rgba[k] = w->fin_rgba[m];
                if (o->normal) o->normal[k] = w->fin_nrm[m];
                if (o->material) o->material[k] = w->fin_mat[m];
            } else if (attrs) {
                const acc* a = &w->acc[w->slot[m]];
                if (o->rgba) o->rgba[k] = finish_rgba(a);
                if (o->normal) o->normal[k] = oct_encode(a->n[0], a->n[1], a->n[2]);
                if (o->material) o->material[k] = cell_material(j, a);
            }
            k++;
        }
    }
    return VX_OK;
}

static void worker_free(worker* w, const vx_allocator* a) {
    vx_free(a, w->buf.keys);
    vx_free(a, w->buf.rgba);
    vx_free(a, w->buf.nrm);
    vx_free(a, w->buf.mat);
    vx_free(a, w->bits);
    vx_free(a, w->acc);
    vx_free(a, w->slot);
    vx_free(a, w->fin_rgba);
    vx_free(a, w->fin_nrm);
    vx_free(a, w->fin_mat);
}

static bool worker_init(worker* w, job* j) {
    memset(w, 0, sizeof *w);
    w->j = j;
    w->bits = (uint64_t*)vx_alloc(j->alloc, BRICK_CELLS / 4); /* surface + interior bitmaps */
    if (!w->bits) return false;
    if (j->attrs) {
        w->acc = (acc*)vx_alloc(j->alloc, sizeof(acc) * BRICK_CELLS);
        w->slot = (uint32_t*)vx_alloc(j->alloc, sizeof(uint32_t) * BRICK_CELLS);
        if (!w->acc || !w->slot) return false;
        if (j->vote[0]) {
            w->fin_rgba = (uint32_t*)vx_alloc(j->alloc, 4 * BRICK_CELLS);
            w->fin_nrm = (uint32_t*)vx_alloc(j->alloc, 4 * BRICK_CELLS);
            w->fin_mat = (uint16_t*)vx_alloc(j->alloc, 2 * BRICK_CELLS);
            if (!w->fin_rgba || !w->fin_nrm || !w->fin_mat) return false;
        }
    }
    return true;
}

/* Brick b of the current region (vx_run_jobs); the caller's thread (0)
 * reports the progress. */
static void brick_job(void* ctx, unsigned thread, uint32_t b) {
    job* j = (job*)ctx;
    if (atomic_load(&j->failed) || atomic_load(&j->cancel)) return;
    vx_result r = do_brick(&j->workers[thread], j->brick_first[b], j->brick_first[b + 1], &j->outs[b]);
    if (r) {
        int z = 0;
        atomic_compare_exchange_strong(&j->failed, &z, (int)r);
        return;
    }
    size_t done = atomic_fetch_add(&j->done, 1) + 1;
    atomic_fetch_add(&j->bricks_done, 1);
    if (thread == 0 && !vx_progress_report(&j->desc->build.progress, "voxelize", j->done_before + done, j->mine_bricks))
        atomic_store(&j->cancel, true);
}

/* ---- sorting and binning ----------------------------------------------------------------- */

/* Stable LSD radix sort of v by bits [lo, hi) of each value. */
static bool radix_sort(const vx_allocator* a, uint64_t* v, size_t n, unsigned lo, unsigned hi) {
    if (n < 2 || hi <= lo) return true;
    uint64_t* tmp = (uint64_t*)vx_alloc(a, n * sizeof *tmp);
    if (!tmp) return false;
    uint64_t *src = v, *dst = tmp;
    for (unsigned s = lo; s < hi; s += 11) {
        size_t cnt[2048] = {0};
        for (size_t i = 0; i < n; i++) cnt[(src[i] >> s) & 2047]++;
        size_t sum = 0;
        for (int i = 0; i < 2048; i++) {
            size_t c = cnt[i];
            cnt[i] = sum;
            sum += c;
        }
        for (size_t i = 0; i < n; i++) dst[cnt[(src[i] >> s) & 2047]++] = src[i];
        uint64_t* t = src;
        src = dst;
        dst = t;
    }
    if (src != v) memcpy(v, src, n * sizeof *v);
    vx_free(a, tmp);
    return true;
}

/* One thread's share of the binning: the pairs of triangles [t0, t1) in
 * triangle order, in its own array (concatenated in part order afterwards,
 * so the pairs are the one-thread loop's). A part on a worker thread writes
 * into a slice of an array the caller allocated (fixed: the worker never
 * allocates, so it takes no malloc arena of its own: arenas left by short
 * threads were handed to the octree builders' threads later, cold, and
 * cost them more than the binning saved); a full slice stops the part
 * (full), and the caller bins it again with a growing array. */
typedef struct bin_ctx {
    job* j;
    uint32_t tri;
    size_t t0, t1;
    uint64_t* pairs;
    size_t count, cap;
    bool nomem, fixed, full;
} bin_ctx;

static void bin_hit(void* user, const int c[3], const double (*poly)[3], int n) {
    (void)poly;
    (void)n;
    bin_ctx* b = (bin_ctx*)user;
    if (b->nomem || b->full) return;
    if (b->fixed && b->count == b->cap) {
        b->full = true;
        return;
    }
    if (!b->fixed && !vx_grow(b->j->alloc, (void**)&b->pairs, &b->cap, b->count + 1, sizeof(uint64_t))) {
        b->nomem = true;
        return;
    }
    b->pairs[b->count++] = vx_svo_morton((uint32_t)c[0], (uint32_t)c[1], (uint32_t)c[2]) << 32 | b->tri;
}

/* Part k of the binning (ctx: the parts; vx_run_jobs). */
static void bin_part(void* ctx, unsigned thread, uint32_t k) {
    (void)thread;
    bin_ctx* b = (bin_ctx*)ctx + k;
    int cmin[3] = {0, 0, 0}, cmax[3] = {(int)b->j->nb[0] - 1, (int)b->j->nb[1] - 1, (int)b->j->nb[2] - 1};
    for (size_t t = b->t0; t < b->t1 && !b->nomem && !b->full; t++) {
        double v[9];
        for (int q = 0; q < 9; q++) v[q] = b->j->g[9 * t + q] / BRICK;
        b->tri = (uint32_t)t;
        tri_cells(v, cmin, cmax, NULL, false, bin_hit, b);
    }
}

/* ---- solid: parity along each axis --------------------------------------------------- */

typedef struct crossing {
    uint64_t ray; /* ray index << 32 | float bits of the crossing coordinate (sortable: >= 0) */
} crossing;

static bool edge_top_left(double dx, double dy) { return dy < 0 || (dy == 0 && dx > 0); }

/* The parity votes along axis ax (solid_votes), into j->vote[ax]. */
static vx_result solid_axis(job* j, int ax, vx_error* err) {
    const uint32_t* n = j->grid->size;
    size_t T = j->mesh->tri_count;
    int u = (ax + 1) % 3, w = (ax + 2) % 3;
    uint64_t* list = NULL;
    size_t cnt = 0, cap = 0;
    for (size_t t = 0; t < T; t++) {
        const double* v = j->g + 9 * t;
        double p[3][2], A[3];
        for (int k = 0; k < 3; k++) {
            p[k][0] = v[3 * k + u];
            p[k][1] = v[3 * k + w];
            A[k] = v[3 * k + ax];
        }
        double area = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]);
        if (area == 0 || !isfinite(area)) continue; /* edge-on: no crossing */
        if (area < 0) { /* make it counter-clockwise */
            double s0 = p[1][0], s1 = p[1][1], sa = A[1];
            p[1][0] = p[2][0]; p[1][1] = p[2][1]; A[1] = A[2];
            p[2][0] = s0; p[2][1] = s1; A[2] = sa;
            area = -area;
        }
        double ulo = fmin(fmin(p[0][0], p[1][0]), p[2][0]), uhi = fmax(fmax(p[0][0], p[1][0]), p[2][0]);
        double wlo = fmin(fmin(p[0][1], p[1][1]), p[2][1]), whi = fmax(fmax(p[0][1], p[1][1]), p[2][1]);
        double ja = fmax(ceil(ulo - 0.5), 0), jb = fmin(floor(uhi - 0.5), (double)n[u] - 1);
        double ka = fmax(ceil(wlo - 0.5), 0), kb = fmin(floor(whi - 0.5), (double)n[w] - 1);
        for (double kk = ka; kk <= kb; kk++)
            for (double jj = ja; jj <= jb; jj++) {
                double q0 = jj + 0.5, q1 = kk + 0.5, e[3];
                bool in = true;
                for (int k = 0; k < 3 && in; k++) {
                    const double* a0 = p[(k + 1) % 3];
                    const double* a1 = p[(k + 2) % 3];
                    double dx = a1[0] - a0[0], dy = a1[1] - a0[1];
                    e[k] = dx * (q1 - a0[1]) - dy * (q0 - a0[0]);
                    in = e[k] > 0 || (e[k] == 0 && edge_top_left(dx, dy));
                }
                if (!in) continue;
                double s = e[0] + e[1] + e[2];
                double at = s > 0 ? (e[0] * A[0] + e[1] * A[1] + e[2] * A[2]) / s : A[0];
                float af = (float)fmax(at, 0);
                uint32_t bitsf;
                memcpy(&bitsf, &af, 4);
                if (!vx_grow(j->alloc, (void**)&list, &cap, cnt + 1, sizeof *list)) {
                    vx_free(j->alloc, list);
                    return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "solid fill: ray crossings");
                }
                uint64_t ray = (uint64_t)jj + (uint64_t)n[u] * (uint64_t)kk;
                list[cnt++] = ray << 32 | bitsf;
            }
    }
    if (!radix_sort(j->alloc, list, cnt, 0, 64)) {
        vx_free(j->alloc, list);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "solid fill: sorting crossings");
    }
    /* walk each ray: a cell centre is inside when an odd number of crossings lie before it */
    for (size_t i = 0; i < cnt;) {
        uint64_t ray = list[i] >> 32;
        size_t e = i;
        while (e < cnt && (list[e] >> 32) == ray) e++;
        uint32_t ju = (uint32_t)(ray % n[u]), kw = (uint32_t)(ray / n[u]);
        size_t c = i;
        bool inside = false;
        for (uint32_t x = 0; x < n[ax]; x++) {
            float centre = (float)x + 0.5f;
            while (c < e) {
                float f;
                uint32_t fb = (uint32_t)list[c];
                memcpy(&f, &fb, 4);
                if (f >= centre) break;
                inside = !inside;
                c++;
            }
            if (c == e && !inside) break;
            if (inside) {
                uint32_t xyz[3];
                xyz[ax] = x;
                xyz[u] = ju;
                xyz[w] = kw;
                uint64_t idx = xyz[0] + (uint64_t)n[0] * (xyz[1] + (uint64_t)n[1] * xyz[2]);
                j->vote[ax][idx >> 6] |= 1ull << (idx & 63);
            }
        }
        i = e;
    }
    vx_free(j->alloc, list);
    return VX_OK;
}

/* The three axes on three threads (each its own crossings and bitmap). */
typedef struct votes_job {
    job* j;
    vx_result r[3];
    vx_error e[3];
} votes_job;
static void votes_axis(void* ctx, unsigned thread, uint32_t ax) {
    (void)thread;
    votes_job* v = (votes_job*)ctx;
    v->r[ax] = solid_axis(v->j, (int)ax, &v->e[ax]);
}

static vx_result solid_votes(job* j, vx_error* err) {
    const uint32_t* n = j->grid->size;
    uint64_t cells = (uint64_t)n[0] * n[1] * n[2];
    if (cells > (1ull << 31))
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET,
                       "solid fill: a grid of %ux%ux%u cells is more than 2^31 (a lower res)", n[0], n[1], n[2]);
    size_t words = (size_t)((cells + 63) / 64);
    for (int a = 0; a < 3; a++) {
        j->vote[a] = (uint64_t*)vx_calloc(j->alloc, words, 8);
        if (!j->vote[a]) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "solid fill: %zu bytes", words * 8);
    }
    votes_job v = {j, {VX_OK, VX_OK, VX_OK}, {{0}}};
    vx_run_jobs(j->desc->threads == 1 ? 1 : 3, 3, votes_axis, &v);
    for (int ax = 0; ax < 3; ax++)
        if (v.r[ax]) {
            if (err) *err = v.e[ax];
            return v.r[ax];
        }
    return VX_OK;
}

/* ---- driver -------------------------------------------------------------------------- */

uint32_t vx__mesh_attrs(const vx_conv_mesh_desc* desc, const vx_gltf_mesh* mesh) {
    uint32_t attrs = 0;
    bool has_color = mesh->material_count > 0 || mesh->color != NULL;
    if (mesh->material) {
        bool any_mat = false;
        for (size_t t = 0; t < mesh->tri_count && !any_mat; t++) any_mat = mesh->material[t] != UINT32_MAX;
        has_color = any_mat || mesh->color != NULL;
    }
    if (!desc->no_color && has_color) attrs |= VX_ATTR_RGBA8;
    if (desc->normals) attrs |= VX_ATTR_NORMAL;
    /* a material channel only when some triangle's material can need a record
     * (a plan that cannot be made: the voxelizer's own attempt reports why) */
    vx__mesh_mats mp;
    if (vx__mesh_mats_make(mesh, desc->alloc, &mp, NULL) != VX_OK) {
        if (mesh->material) attrs |= VX_ATTR_MATERIAL;
    } else {
        if (mp.any_special) attrs |= VX_ATTR_MATERIAL;
        vx__mesh_mats_free(desc->alloc, &mp);
    }
    return attrs;
}

/* ---- shares (convert/mesh.h, vx_conv_mesh_share) -------------------------------------- */

typedef struct region_cost {
    size_t bricks, index;
} region_cost;

static int cost_cmp(const void* pa, const void* pb) {
    const region_cost *a = (const region_cost*)pa, *b = (const region_cost*)pb;
    if (a->bricks != b->bricks) return a->bricks > b->bricks ? -1 : 1; /* costly first */
    return a->index < b->index ? -1 : a->index > b->index;
}
static int index_cmp(const void* pa, const void* pb) {
    size_t a = *(const size_t*)pa, b = *(const size_t*)pb;
    return a < b ? -1 : a > b;
}

/* A binary heap of the shares by (load, share) in two parallel arrays: ties
 * go to the lowest share, so every process computes the same assignment. */
static bool heap_less(const uint64_t* load, const uint32_t* sh, size_t a, size_t b) {
    return load[a] != load[b] ? load[a] < load[b] : sh[a] < sh[b];
}
static void heap_down(uint64_t* load, uint32_t* sh, size_t n, size_t i) {
    for (;;) {
        size_t l = 2 * i + 1, m = i;
        if (l < n && heap_less(load, sh, l, m)) m = l;
        if (l + 1 < n && heap_less(load, sh, l + 1, m)) m = l + 1;
        if (m == i) return;
        uint64_t tl = load[i];
        uint32_t ts = sh[i];
        load[i] = load[m], sh[i] = sh[m];
        load[m] = tl, sh[m] = ts;
        i = m;
    }
}

/* The regions of share `share` of `shares` (convert/mesh_internal.h): longest processing time first
 * (regions by their number of surface bricks, the most first, each to the
 * share with the least bricks so far), a function of the binning alone, so
 * every process computes the same partition without talking to the others.
 * Bricks are a fair measure of a region's cost: voxelizing and building
 * both follow the surface it holds. One share keeps every region. */
vx_result vx__mesh_share_regions(const size_t* rstart, size_t n, uint32_t share, uint32_t shares, const vx_allocator* a,
                                 size_t** out, size_t* count, size_t* bricks, vx_error* err) {
    size_t* mine = (size_t*)vx_alloc(a, (n ? n : 1) * sizeof *mine);
    *out = mine;
    *count = *bricks = 0;
    if (!mine) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "%zu regions", n);
    if (shares <= 1) {
        for (size_t i = 0; i < n; i++) mine[i] = i;
        *count = n;
        *bricks = rstart[n] - rstart[0];
        return VX_OK;
    }
    region_cost* c = (region_cost*)vx_alloc(a, (n ? n : 1) * sizeof *c);
    uint64_t* load = (uint64_t*)vx_calloc(a, shares, sizeof *load);
    uint32_t* sh = (uint32_t*)vx_alloc(a, (size_t)shares * sizeof *sh);
    if (!c || !load || !sh) {
        vx_free(a, c), vx_free(a, load), vx_free(a, sh);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "%zu regions over %u shares", n, shares);
    }
    for (size_t i = 0; i < n; i++) c[i] = (region_cost){rstart[i + 1] - rstart[i], i};
    qsort(c, n, sizeof *c, cost_cmp);
    for (uint32_t s = 0; s < shares; s++) sh[s] = s; /* all loads 0: already a heap */
    for (size_t i = 0; i < n; i++) {
        if (sh[0] == share) {
            mine[(*count)++] = c[i].index;
            *bricks += c[i].bricks;
        }
        load[0] += c[i].bricks;
        heap_down(load, sh, shares, 0);
    }
    qsort(mine, *count, sizeof *mine, index_cmp); /* Morton order, as one process goes */
    vx_free(a, c), vx_free(a, load), vx_free(a, sh);
    return VX_OK;
}

static vx_result assign_regions(job* j, uint32_t share, uint32_t shares, vx_error* err) {
    return vx__mesh_share_regions(j->rstart, j->region_count, share, shares, j->alloc, &j->mine, &j->mine_count,
                                  &j->mine_bricks, err);
}

static void job_free(job* j) {
    vx_free(j->alloc, j->mine);
    vx_free(j->alloc, j->g);
    vx_free(j->alloc, j->pairs);
    for (int a = 0; a < 3; a++) vx_free(j->alloc, j->vote[a]);
    vx__mesh_mats_free(j->alloc, &j->mats);
}


/* Concatenates the bricks of region ri (Morton order) and hands them to the
 * sink; frees the brick outputs either way. */
static vx_result region_emit(job* j, size_t ri, brick_out* outs, region_buf* rb, vx_error* err) {
    size_t b0 = j->rstart[ri], nbk = j->rstart[ri + 1] - b0, total = 0, k = 0;
    vx_result r = VX_OK;
    for (size_t b = 0; b < nbk; b++) total += outs[b].count;
    if (total > 0 && (!vx_grow(j->alloc, (void**)&rb->keys, &rb->kcap, total, 8) ||
                      (j->color && !vx_grow(j->alloc, (void**)&rb->rgba, &rb->rcap, total, 4)) ||
                      (j->normals && !vx_grow(j->alloc, (void**)&rb->nrm, &rb->ncap, total, 4)) ||
                      (j->materials && !vx_grow(j->alloc, (void**)&rb->mat, &rb->mcap, total, 2))))
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "region of %zu voxels", total);
    uint64_t region = (j->pairs[j->bstart[b0]] >> 32) >> (3 * j->rb);
    for (size_t b = 0; b < nbk; b++) {
        brick_out* o = &outs[b];
        if (!r && o->count) {
            uint64_t bm = (j->pairs[j->bstart[b0 + b]] >> 32) & ((1ull << (3 * j->rb)) - 1);
            for (size_t i = 0; i < o->count; i++) rb->keys[k + i] = bm << 18 | o->local[i];
            if (j->color) memcpy(rb->rgba + k, o->rgba, o->count * 4);
            if (j->normals) memcpy(rb->nrm + k, o->normal, o->count * 4);
            if (j->materials) memcpy(rb->mat + k, o->material, o->count * 2);
            k += o->count;
        }
        vx_free(j->alloc, o->local);
        vx_free(j->alloc, o->rgba);
        vx_free(j->alloc, o->normal);
        vx_free(j->alloc, o->material);
        memset(o, 0, sizeof *o);
    }
    if (r || total == 0) return r;
    vx__mesh_region reg;
    vx__mesh_region_place(&reg, region, j->R, j->grid->size, ri, j->region_count);
    reg.count = total;
    reg.keys = rb->keys;
    reg.rgba = j->color ? rb->rgba : NULL;
    reg.normal = j->normals ? rb->nrm : NULL;
    reg.material = j->materials ? rb->mat : NULL;
    reg.attrs = j->attrs;
    return j->sink(j->user, &reg, err);
}

static void record_failure(job* j, vx_result r, const vx_error* e) {
    pthread_mutex_lock(&j->lock);
    int z = 0;
    if (atomic_compare_exchange_strong(&j->failed, &z, (int)r)) j->first_err = *e;
    pthread_mutex_unlock(&j->lock);
}

/* Whole regions per thread (voxelize, then the sink builds the model), so
 * the octree builds of different regions run in parallel too: region
 * mine[k] on a vx_run_jobs thread. The calling thread (0) alone reports
 * progress. */
static void region_job(void* ctx, unsigned thread, uint32_t k) {
    job* j = (job*)ctx;
    worker* w = &j->workers[thread];
    bool is_main = thread == 0;
    {
        if (atomic_load(&j->failed) || atomic_load(&j->cancel)) return;
        size_t ri = j->mine[k];
        size_t b0 = j->rstart[ri], nbk = j->rstart[ri + 1] - b0;
        vx_error e = {0};
        brick_out* outs = (brick_out*)vx_calloc(j->alloc, nbk, sizeof *outs);
        vx_result r = outs ? VX_OK : vx_fail(&e, VX_ERR_NOMEM, VX_NO_OFFSET, "region bricks");
        for (size_t b = 0; b < nbk && !r; b++) {
            if (atomic_load(&j->failed) || atomic_load(&j->cancel)) break;
            r = do_brick(w, j->bstart[b0 + b], j->bstart[b0 + b + 1], &outs[b]);
            if (r) vx_fail(&e, r, VX_NO_OFFSET, "voxelizer: out of memory");
            size_t done = atomic_fetch_add(&j->bricks_done, 1) + 1;
            if (is_main && !vx_progress_report(&j->desc->build.progress, "voxelize", done, j->mine_bricks))
                atomic_store(&j->cancel, true);
        }
        if (outs) {
            if (!r && !atomic_load(&j->cancel) && !atomic_load(&j->failed)) r = region_emit(j, ri, outs, &w->buf, &e);
            else
                for (size_t b = 0; b < nbk; b++) {
                    vx_free(j->alloc, outs[b].local);
                    vx_free(j->alloc, outs[b].rgba);
                    vx_free(j->alloc, outs[b].normal);
                    vx_free(j->alloc, outs[b].material);
                }
            vx_free(j->alloc, outs);
        }
        if (r) record_failure(j, r, &e);
    }
}

/* Everything before the bricks are voxelized: the region size, grid
 * coordinates, solid votes (desc->solid), the (brick, triangle) pairs in
 * brick order and the brick and region boundaries. j is initialised first,
 * so the caller frees it (job_end) whatever this returns. */
static vx_result job_begin(job* j, const vx_conv_mesh_desc* desc, const vx_gltf_mesh* mesh,
                           const vx_conv_mesh_grid* grid, uint32_t attrs, vx__mesh_sink sink, void* user,
                           vx_error* err) {
    pthread_once(&tables_once, init_tables);
    pthread_once(&mort_once, init_mort6);
    memset(j, 0, sizeof *j);
    pthread_mutex_init(&j->lock, NULL);
    uint32_t R = desc->region;
    if (R == 0) {
        /* one model up to 512 cells; beyond, at least 8 regions (so that
         * octree builds run in parallel) of at most 2048 cells */
        uint32_t side = grid->size[0];
        if (grid->size[1] > side) side = grid->size[1];
        if (grid->size[2] > side) side = grid->size[2];
        R = BRICK;
        while (R < side) R *= 2;
        if (R > 512) R /= 2;
        if (R > 2048) R = 2048;
    }
    if (R < BRICK || (R & (R - 1)) || R > (1u << 21))
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "region %u: not a power of two in 64..2^21", R);
    if (mesh->tri_count > UINT32_MAX - 1)
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "%zu triangles is too many", mesh->tri_count);
    j->desc = desc;
    j->mesh = mesh;
    j->grid = grid;
    j->alloc = desc->alloc;
    j->attrs = attrs;
    j->color = (attrs & VX_ATTR_RGBA8) != 0;
    j->normals = (attrs & VX_ATTR_NORMAL) != 0;
    j->materials = (attrs & VX_ATTR_MATERIAL) != 0;
    vx_result mr = j->materials ? vx__mesh_mats_make(mesh, desc->alloc, &j->mats, err) : VX_OK;
    if (mr) return mr;
    j->sampling = j->mats.sampled;
    j->sink = sink;
    j->user = user;
    j->R = R;
    while (((uint32_t)BRICK << j->rb) < R) j->rb++;
    atomic_init(&j->done, 0);
    atomic_init(&j->failed, 0);
    atomic_init(&j->cancel, false);
    atomic_init(&j->bricks_done, 0);
    size_t T = mesh->tri_count, n9;
    vx_result r = VX_OK;
    if (!vx_mul_size(T, 9 * sizeof(double), &n9) || !(j->g = (double*)vx_alloc(j->alloc, n9))) {
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "%zu triangles", T);
        return r;
    }
    for (size_t i = 0; i < 9 * T; i++) {
        double p = mesh->pos[i];
        if (!isfinite(p)) {
            r = vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "triangle %zu: vertex %zu has a NaN or infinite coordinate",
                        i / 9, (i % 9) / 3);
            return r;
        }
        j->g[i] = (p - grid->min[i % 3]) / grid->h;
    }
    if (desc->solid && (r = solid_votes(j, err))) return r;
    /* bin triangles into bricks */
    for (int a = 0; a < 3; a++) j->nb[a] = (grid->size[a] + BRICK - 1) / BRICK;
    {
        /* triangles in contiguous parts, on the cores for large meshes (the
         * clipping is most of the binning: 2-6 ms at 1024^3 for 15 k
         * triangles on one core, ahead of everything the GPU path does) */
        unsigned threads = desc->threads;
        if (threads == 0) {
            cpu_set_t set;
            long nc = sched_getaffinity(0, sizeof set, &set) == 0 ? CPU_COUNT(&set) : sysconf(_SC_NPROCESSORS_ONLN);
            threads = nc > 0 ? (unsigned)nc : 1;
        }
        if (threads > VX_MAX_THREADS) threads = VX_MAX_THREADS;
        /* parts of at least 1024 triangles, up to 4 a thread (parts of 256 measured no better on the H200) */
        unsigned nparts = (unsigned)(T / 1024 < 4u * threads ? T / 1024 : 4u * threads);
        if (threads < 2 || nparts < 2) nparts = 1;
        bin_ctx parts1[1], *parts = nparts > 1 ? (bin_ctx*)vx_calloc(j->alloc, nparts, sizeof *parts) : parts1;
        /* the workers' slices: 8 pairs a triangle (DamagedHelmet has 2 at 1024^3, 6 at 4096^3) */
        size_t slice_total = nparts > 1 ? 8 * T + 1024 * (size_t)nparts : 0;
        uint64_t* slices = slice_total ? (uint64_t*)vx_alloc(j->alloc, slice_total * sizeof *slices) : NULL;
        if (!parts || (slice_total && !slices)) {
            if (parts != parts1) vx_free(j->alloc, parts);
            return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "binning %zu triangles", T);
        }
        size_t at = 0;
        for (unsigned k = 0; k < nparts; k++) {
            size_t t0 = T * k / nparts, t1 = T * (k + 1) / nparts, cap = 8 * (t1 - t0) + 1024;
            parts[k] = (bin_ctx){j, 0, t0, t1, slices ? slices + at : NULL, 0, slices ? cap : 0, false, slices != NULL, false};
            at += cap;
        }
        vx_run_jobs(nparts > 1 ? threads : 1, nparts, bin_part, parts);
        for (unsigned k = 0; k < nparts; k++)
            if (parts[k].full) { /* more pairs than its slice: again, here, growing */
                parts[k] = (bin_ctx){j, 0, parts[k].t0, parts[k].t1, NULL, 0, 0, false, false, false};
                bin_part(parts, 0, k);
            }
        bool nomem = false;
        size_t total = 0;
        for (unsigned k = 0; k < nparts; k++) nomem |= parts[k].nomem, total += parts[k].count;
        bin_ctx b = {j, 0, 0, 0, NULL, 0, 0, nomem, false, false};
        if (!nomem && total) { /* the parts in triangle order */
            if (nparts == 1) {
                b.pairs = parts[0].pairs, b.count = parts[0].count, b.cap = parts[0].cap;
                parts[0].pairs = NULL;
            } else if (!vx_grow(j->alloc, (void**)&b.pairs, &b.cap, total, sizeof(uint64_t))) {
                b.nomem = true;
            } else {
                for (unsigned k = 0; k < nparts; k++) {
                    if (parts[k].count) memcpy(b.pairs + b.count, parts[k].pairs, parts[k].count * sizeof(uint64_t));
                    b.count += parts[k].count;
                }
            }
        }
        for (unsigned k = 0; k < nparts; k++)
            if (!parts[k].fixed) vx_free(j->alloc, parts[k].pairs);
        vx_free(j->alloc, slices);
        if (parts != parts1) vx_free(j->alloc, parts);
        /* solid: bricks with no triangle can still be inside; one filler pair each */
        if (desc->solid)
            for (uint32_t z = 0; z < j->nb[2] && !b.nomem; z++)
                for (uint32_t y = 0; y < j->nb[1] && !b.nomem; y++)
                    for (uint32_t x = 0; x < j->nb[0] && !b.nomem; x++) {
                        b.tri = 0xFFFFFFFFu;
                        int c[3] = {(int)x, (int)y, (int)z};
                        bin_hit(&b, c, NULL, 0);
                    }
        j->pairs = b.pairs;
        j->pair_count = b.count;
        if (b.nomem || !radix_sort(j->alloc, j->pairs, j->pair_count, 32, 64)) {
            r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "binning %zu triangles", T);
            return r;
        }
    }
    /* brick and region boundaries */
    {
        size_t bcap = 0, rcap = 0;
        for (size_t i = 0; i <= j->pair_count && !r; i++) {
            bool end = i == j->pair_count;
            bool new_brick = end || i == 0 || (j->pairs[i] >> 32) != (j->pairs[i - 1] >> 32);
            if (!new_brick) continue;
            bool new_region = end || i == 0 || (j->pairs[i] >> 32 >> (3 * j->rb)) != (j->pairs[i - 1] >> 32 >> (3 * j->rb));
            if (!vx_grow(j->alloc, (void**)&j->bstart, &bcap, j->total_bricks + 1, sizeof(size_t)) ||
                (new_region && !vx_grow(j->alloc, (void**)&j->rstart, &rcap, j->region_count + 1, sizeof(size_t)))) {
                r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "brick lists");
                break;
            }
            j->bstart[j->total_bricks] = i;
            if (new_region) j->rstart[j->region_count] = j->total_bricks;
            if (end) break;
            j->total_bricks++;
            if (new_region) j->region_count++;
        }
        if (r) return r;
    }
    return VX_OK;
}

static void job_end(job* j) {
    vx_free(j->alloc, j->bstart);
    vx_free(j->alloc, j->rstart);
    pthread_mutex_destroy(&j->lock);
    job_free(j);
}

vx_result vx__mesh_bin(const vx_conv_mesh_desc* desc, const vx_gltf_mesh* mesh, const vx_conv_mesh_grid* grid,
                       vx__mesh_bins* out, vx_error* err) {
    job j;
    vx_result r = job_begin(&j, desc, mesh, grid, 0, NULL, NULL, err);
    if (!r) {
        out->g = j.g;
        out->pairs = j.pairs;
        out->pair_count = j.pair_count;
        out->bstart = j.bstart;
        out->total_bricks = j.total_bricks;
        out->rstart = j.rstart;
        out->region_count = j.region_count;
        out->R = j.R;
        out->rb = j.rb;
        for (int a = 0; a < 3; a++) out->vote[a] = j.vote[a], j.vote[a] = NULL;
        j.g = NULL;
        j.pairs = NULL;
        j.bstart = NULL;
        j.rstart = NULL;
    }
    job_end(&j);
    return r;
}

void vx__mesh_bins_free(const vx_allocator* a, vx__mesh_bins* b) {
    vx_free(a, b->g);
    vx_free(a, b->pairs);
    vx_free(a, b->bstart);
    vx_free(a, b->rstart);
    for (int k = 0; k < 3; k++) vx_free(a, b->vote[k]);
    memset(b, 0, sizeof *b);
}

size_t vx__mesh_fill_scratch_size(void) { return BRICK_CELLS / 4 + (size_t)BRICK_CELLS * (4 + 4 + 2); }

size_t vx__mesh_fill_brick(const vx__mesh_bins* bins, const vx_conv_mesh_grid* grid, uint64_t bm, uint32_t attrs,
                           const uint32_t* local, const uint32_t* rgba, const uint32_t* nrm, const uint32_t* mat, size_t n,
                           void* scratch, uint32_t* out_local, uint32_t* out_rgba, uint32_t* out_nrm, uint16_t* out_mat) {
    pthread_once(&mort_once, init_mort6);
    uint64_t* bits = (uint64_t*)scratch; /* surface, then interior (do_brick's two halves) */
    uint64_t* inner = bits + BRICK_CELLS / 64;
    uint32_t* fin_rgba = (uint32_t*)(inner + BRICK_CELLS / 64);
    uint32_t* fin_nrm = fin_rgba + BRICK_CELLS;
    uint16_t* fin_mat = (uint16_t*)(fin_nrm + BRICK_CELLS);
    uint32_t org[3];
    int cmax[3], last[3];
    brick_extent(bm, grid->size, org, cmax, last);
    memset(bits, 0, BRICK_CELLS / 8);
    for (size_t i = 0; i < n; i++) {
        uint32_t m = local[i] & (BRICK_CELLS - 1);
        bits[m >> 6] |= 1ull << (m & 63);
        if (attrs) { /* every channel (the unused ones are only carried along) */
            fin_rgba[m] = rgba ? rgba[i] : 0;
            fin_nrm[m] = nrm ? nrm[i] : 0;
            fin_mat[m] = mat ? (uint16_t)mat[i] : 0;
        }
    }
    solid_inner(bins->vote, grid->size, org, cmax, bits, inner);
    if (attrs) solid_attrs(cmax, bits, inner, fin_rgba, fin_nrm, fin_mat);
    size_t k = 0;
    for (size_t i = 0; i < BRICK_CELLS / 64; i++)
        for (uint64_t word = bits[i] | inner[i]; word; word &= word - 1) {
            uint32_t m = (uint32_t)(i * 64 + (size_t)__builtin_ctzll(word));
            out_local[k] = m;
            if (out_rgba) out_rgba[k] = fin_rgba[m];
            if (out_nrm) out_nrm[k] = fin_nrm[m];
            if (out_mat) out_mat[k] = fin_mat[m];
            k++;
        }
    return k;
}

vx_result vx__mesh_voxelize(const vx_conv_mesh_desc* desc, const vx_gltf_mesh* mesh, const vx_conv_mesh_grid* grid,
                            uint32_t attrs, uint32_t share, uint32_t shares, vx__mesh_sink sink, void* user,
                            vx_error* err) {
    job j;
    vx_result r = job_begin(&j, desc, mesh, grid, attrs, sink, user, err);
    if (r) goto done;
    if (share >= (shares ? shares : 1)) {
        r = vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "share %u of %u", share, shares);
        goto done;
    }
    if ((r = assign_regions(&j, share, shares, err))) goto done;
    unsigned threads = desc->threads;
    if (threads == 0) {
        cpu_set_t set;
        long nc = sched_getaffinity(0, sizeof set, &set) == 0 ? CPU_COUNT(&set) : sysconf(_SC_NPROCESSORS_ONLN);
        threads = nc > 0 ? (unsigned)nc : 1;
    }
    if (threads > 64) threads = 64;
    worker ws[64];
    memset(ws, 0, sizeof ws);
    for (unsigned i = 0; i < threads && !r; i++)
        if (!worker_init(&ws[i], &j)) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "voxelizer buffers");
    j.workers = ws;
    if (!r && j.mine_count >= 2 * threads) {
        vx_run_jobs(threads, (uint32_t)j.mine_count, region_job, &j);
    } else {
        /* few regions: one at a time, its bricks spread over the threads */
        size_t base = 0; /* bricks of this share's regions before this one, for the progress */
        for (size_t k = 0; k < j.mine_count && !r; k++) {
            size_t ri = j.mine[k];
            size_t b0 = j.rstart[ri], nbk = j.rstart[ri + 1] - b0;
            j.brick_first = j.bstart + b0;
            j.brick_count = nbk;
            j.outs = (brick_out*)vx_calloc(j.alloc, nbk, sizeof *j.outs);
            if (!j.outs) {
                r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "region bricks");
                break;
            }
            atomic_store(&j.done, 0);
            j.done_before = base;
            vx_run_jobs(threads, (uint32_t)nbk, brick_job, &j);
            if (!atomic_load(&j.failed) && !atomic_load(&j.cancel)) {
                r = region_emit(&j, ri, j.outs, &ws[0].buf, err);
            } else {
                for (size_t b = 0; b < nbk; b++) {
                    vx_free(j.alloc, j.outs[b].local);
                    vx_free(j.alloc, j.outs[b].rgba);
                    vx_free(j.alloc, j.outs[b].normal);
                    vx_free(j.alloc, j.outs[b].material);
                }
                if (atomic_load(&j.failed)) r = vx_fail(err, (vx_result)atomic_load(&j.failed), VX_NO_OFFSET, "voxelizer: out of memory");
            }
            vx_free(j.alloc, j.outs);
            j.outs = NULL;
            base += nbk;
        }
    }
    if (!r && atomic_load(&j.cancel)) r = vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "cancelled");
    if (!r && atomic_load(&j.failed)) {
        r = (vx_result)atomic_load(&j.failed);
        if (err) *err = j.first_err;
    }
    for (unsigned i = 0; i < threads; i++) worker_free(&ws[i], j.alloc);
done:
    job_end(&j);
    return r;
}

void vx__mesh_region_place(vx__mesh_region* reg, uint64_t region, uint32_t R, const uint32_t grid_size[3], size_t index,
                           size_t region_count) {
    memset(reg, 0, sizeof *reg);
    uint32_t r[3];
    vx_svo_demorton(region, &r[0], &r[1], &r[2]);
    for (int a = 0; a < 3; a++) {
        reg->origin[a] = r[a] * R;
        uint32_t left = grid_size[a] - reg->origin[a];
        reg->size[a] = left < R ? left : R;
    }
    reg->index = index;
    reg->region_count = region_count;
}
