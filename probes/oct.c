/* probes/oct.c - octahedral mapping, texel geometry and half floats. */
#include <math.h>
#include <string.h>

#include "probes/probes.h"

static double sgn(double v) { return v < 0 ? -1.0 : 1.0; }

void vx_probe_oct_encode(const double d[3], double uv[2]) {
    double l1 = fabs(d[0]) + fabs(d[1]) + fabs(d[2]);
    double u = d[0] / l1, v = d[1] / l1;
    if (d[2] < 0) {
        double fu = (1 - fabs(v)) * sgn(u), fv = (1 - fabs(u)) * sgn(v);
        u = fu, v = fv;
    }
    uv[0] = u, uv[1] = v;
}

/* The unnormalised point on the octahedron |x|+|y|+|z| = 1; the map from the
 * square is linear on each triangle between the axes and the diamond. */
static void oct_point(double u, double v, double p[3]) {
    double z = 1 - fabs(u) - fabs(v);
    if (z < 0) {
        double x = (1 - fabs(v)) * sgn(u), y = (1 - fabs(u)) * sgn(v);
        u = x, v = y;
    }
    p[0] = u, p[1] = v, p[2] = z;
}

void vx_probe_oct_decode(const double uv[2], double d[3]) {
    double p[3];
    oct_point(uv[0], uv[1], p);
    double l = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    for (int k = 0; k < 3; k++) d[k] = p[k] / l;
}

static uint32_t snorm16(double v) {
    double c = v < -1 ? -1 : (v > 1 ? 1 : v);
    long q = lrint(c * 32767.0);
    return (uint32_t)(uint16_t)(int16_t)q;
}

uint32_t vx_probe_oct_pack16(const double d[3]) {
    double uv[2];
    vx_probe_oct_encode(d, uv);
    return snorm16(uv[0]) | (snorm16(uv[1]) << 16);
}

void vx_probe_oct_unpack16(uint32_t v, double d[3]) {
    int16_t a = (int16_t)(uint16_t)(v & 0xFFFFu), b = (int16_t)(uint16_t)(v >> 16);
    double uv[2] = {fmax(-1.0, a / 32767.0), fmax(-1.0, b / 32767.0)};
    vx_probe_oct_decode(uv, d);
}

void vx_probe_texel_dir(uint32_t n, uint32_t i, uint32_t j, double d[3]) {
    double uv[2] = {(2.0 * i + 1) / n - 1, (2.0 * j + 1) / n - 1};
    vx_probe_oct_decode(uv, d);
}

/* Solid angle of the flat triangle abc seen from the origin (Van Oosterom
 * and Strackee 1983): exact for any triangle not through the origin. */
static double tri_solid_angle(const double a[3], const double b[3], const double c[3]) {
    double la = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    double lb = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
    double lc = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    double bxc[3] = {b[1] * c[2] - b[2] * c[1], b[2] * c[0] - b[0] * c[2], b[0] * c[1] - b[1] * c[0]};
    double num = fabs(a[0] * bxc[0] + a[1] * bxc[1] + a[2] * bxc[2]);
    double ab = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    double ac = a[0] * c[0] + a[1] * c[1] + a[2] * c[2];
    double bc = b[0] * c[0] + b[1] * c[1] + b[2] * c[2];
    double den = la * lb * lc + ab * lc + ac * lb + bc * la;
    return 2 * atan2(num, den);
}

double vx_probe_texel_solid_angle(uint32_t n, uint32_t i, uint32_t j) {
    double u0 = 2.0 * i / n - 1, u1 = 2.0 * (i + 1) / n - 1;
    double v0 = 2.0 * j / n - 1, v1 = 2.0 * (j + 1) / n - 1;
    /* For even n the axes are texel edges and the diamond |u|+|v| = 1 runs
     * along texel diagonals; splitting along the diagonal parallel to the
     * quadrant's diamond edge leaves two triangles on which the map is linear,
     * so their images are flat triangles of the octahedron. */
    double cu = 0.5 * (u0 + u1), cv = 0.5 * (v0 + v1);
    double p00[3], p10[3], p01[3], p11[3];
    oct_point(u0, v0, p00);
    oct_point(u1, v0, p10);
    oct_point(u0, v1, p01);
    oct_point(u1, v1, p11);
    if ((cu > 0) == (cv > 0)) /* diamond edge along (1,-1): split 01-10 */
        return tri_solid_angle(p00, p10, p01) + tri_solid_angle(p10, p11, p01);
    return tri_solid_angle(p00, p10, p11) + tri_solid_angle(p00, p11, p01);
}

void vx_probe_border_src(uint32_t n, uint32_t bi, uint32_t bj, uint32_t* si, uint32_t* sj) {
    /* Interior coordinates, -1 or n on the border. Crossing the edge u = +-1
     * at v lands at -v on the same edge (and likewise for v); a corner is the
     * opposite corner. */
    int64_t i = (int64_t)bi - 1, j = (int64_t)bj - 1, N = n;
    bool bu = i < 0 || i >= N, bv = j < 0 || j >= N;
    if (bu && bv) {
        i = i < 0 ? N - 1 : 0;
        j = j < 0 ? N - 1 : 0;
    } else if (bu) {
        i = i < 0 ? 0 : N - 1;
        j = N - 1 - j;
    } else if (bv) {
        j = j < 0 ? 0 : N - 1;
        i = N - 1 - i;
    }
    *si = (uint32_t)i, *sj = (uint32_t)j;
}

uint16_t vx_probe_half(float f) {
    uint32_t x;
    memcpy(&x, &f, 4);
    uint32_t sign = (x >> 16) & 0x8000u;
    uint32_t mant = x & 0x7FFFFFu;
    int32_t e = (int32_t)((x >> 23) & 0xFF);
    if (e == 0xFF) return (uint16_t)(sign | 0x7C00u | (mant ? 0x200u : 0));
    int32_t he = e - 127 + 15;
    if (he >= 0x1F) return (uint16_t)(sign | 0x7C00u);
    if (he <= 0) {
        if (he < -10) return (uint16_t)sign;
        mant |= 0x800000u;
        uint32_t shift = (uint32_t)(14 - he);
        uint32_t hm = mant >> shift, rem = mant & ((1u << shift) - 1), half = 1u << (shift - 1);
        if (rem > half || (rem == half && (hm & 1))) hm++;
        return (uint16_t)(sign | hm);
    }
    uint32_t hm = mant >> 13, rem = mant & 0x1FFFu;
    uint32_t h = sign | ((uint32_t)he << 10) | hm;
    if (rem > 0x1000u || (rem == 0x1000u && (hm & 1))) h++; /* may carry into the exponent: still correct */
    return (uint16_t)h;
}

float vx_probe_half_to_float(uint16_t h) {
    uint32_t sign = (uint32_t)(h & 0x8000u) << 16;
    uint32_t e = (h >> 10) & 0x1F, m = h & 0x3FFu;
    uint32_t x;
    if (e == 0) {
        if (!m) {
            x = sign;
        } else {
            float f = ldexpf((float)m, -24);
            return sign ? -f : f;
        }
    } else if (e == 0x1F) {
        x = sign | 0x7F800000u | (m << 13);
    } else {
        x = sign | ((e - 15 + 127) << 23) | (m << 13);
    }
    float f;
    memcpy(&f, &x, 4);
    return f;
}
