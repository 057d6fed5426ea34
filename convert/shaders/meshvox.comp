#version 450
/* convert/shaders/meshvox.comp - the brick voxelizer of convert/mesh_voxelize.c
 * on the GPU, one thread per (brick, triangle) pair, in the same double
 * arithmetic: MODE 0 counts each pair's cells, MODE 1 writes one record per
 * (cell, triangle): the cell's key and the triangle's weighted attribute
 * contributions, summed per cell in triangle order by meshreduce.comp.
 *
 * Exactness: every operation is the C code's, in the same order, and every
 * variable that takes part is `precise` (SPIR-V NoContraction), so no
 * multiply-add is fused where the C build (x86-64, no FMA) rounds twice.
 * Double literals carry lf: a float literal like 1e-7 is another number.
 * Float divisions the C code makes are done in double and rounded to float
 * (the same result: a double quotient of two floats rounds innocuously);
 * 255ths and the sRGB table come from the CPU. */
/* one workgroup per pair, its 16 invocations taking the strips of cells
 * along u (at most 64 in a brick) in turn: short loops per strip (llvmpipe
 * stops an invocation's loop after some tens of thousands of iterations:
 * one invocation per pair lost the cells of big triangles) and the big
 * triangles of a brick spread over 16 threads instead of one */
/* Two pairs share a workgroup of 32 (one subgroup on NVIDIA): with 16
 * invocations a group the other half of every warp idled. A pair's 16
 * invocations and their (pair, strip) slots are as before. On an H200 at
 * 1024^3 (DamagedHelmet) 16 lanes a pair took emit 11.8 ms, 8 lanes 14.6,
 * 4 lanes 21.8 (the big triangles' strips run in turn); mesh_gpu.c dispatches
 * pair_count * LANES / 32 groups. */
#define LANES 16u /* invocations a pair */
layout(local_size_x = 32) in;

layout(push_constant) uniform Push {
    uint pair_count;
    uint attrs;     /* 1 colour, 2 normals, 4 materials (anything set: attributes), 8 materials
                     * sampled per cell (with 4: records carry metallic, roughness, emission) */
    uint first;     /* pairs of this dispatch start here */
    uint mode;      /* 0 count, 1 emit: a push constant, not a specialisation, so that both
                     * passes run one compiled enumeration (they must agree cell for cell) */
    ivec4 size;     /* grid cells per axis */
} pc;

layout(std430, binding = 0) readonly buffer G { double g[]; };        /* 9 per triangle: grid coordinates */
layout(std430, binding = 1) readonly buffer Pairs { uvec2 pairs[]; }; /* triangle, brick rank */
layout(std430, binding = 2) readonly buffer Bricks { uvec4 bricks[]; }; /* origin cell */
layout(std430, binding = 3) buffer Counts { uint counts[]; };          /* pc.mode 0 out, pc.mode 1: offsets in */
layout(std430, binding = 4) writeonly buffer Keys { uvec2 keys[]; };
/* n.w: the weight; mat: the MATL id, or with attrs 8 the glTF material
 * index (meshreduce.comp makes the id from the cell's averages); pm, pr,
 * pe0 and RecX's two floats: the weighted metallic, roughness and emission
 * RGB (attrs 8 only: without it the record is the 48 bytes it was) */
struct Rec { vec4 c; vec4 n; uint mat; float pm, pr, pe0; };
layout(std430, binding = 5) writeonly buffer Recs { Rec recs[]; };
layout(std430, binding = 6) readonly buffer TriMat { uint trimat[]; };
struct Mat { vec4 base; int image; uint wrap_s, wrap_t, id; };
layout(std430, binding = 7) readonly buffer Mats { Mat mats[]; };
layout(std430, binding = 8) readonly buffer Images { uvec4 images[]; }; /* texel offset, width, height */
layout(std430, binding = 9) readonly buffer Texels { uint texels[]; };
layout(std430, binding = 10) readonly buffer UV { float uv[]; };
layout(std430, binding = 11) readonly buffer Col { float colr[]; };
layout(std430, binding = 13) writeonly buffer Vals { uint vals[]; };   /* the records' own indices, for the sort */
layout(std430, binding = 12) readonly buffer Tables { float srgb_to_lin[256]; float a255[256]; uint has_uv, has_color, mat_count, pad; };
/* attrs 8: per glTF material its effective metallic, roughness and emission
 * factors and the textures sampled per cell (setup_tri_sampling's; image -1:
 * not sampled), per triangle the uv of those textures, per record the
 * emission's G and B */
struct SMat { vec4 f; vec4 g; ivec4 mr; ivec4 em; }; /* f: metal, rough, emit R, G; g.x emit B; mr: VX__MESH_SAMPLE_*, image, wraps; em: image, wraps */
layout(std430, binding = 14) readonly buffer SMats { SMat smats[]; };
layout(std430, binding = 15) readonly buffer UVMR { float uv_mr[]; };
layout(std430, binding = 16) readonly buffer UVEM { float uv_em[]; };
layout(std430, binding = 17) writeonly buffer RecX { vec2 recx[]; };

#define NO_LAST 0x7fffffff
/* The polygons, in one private array (as small as it can be: llvmpipe's
 * per-invocation stack is small): a clip by a slab adds at most 2 vertices,
 * so TRI (3) at 0, P1 (5) at 3, P2 (7) at 8, P3 (9) at 15, and TMP, the
 * half-clipped polygon of clip_slab (at most 10), at 24. The values come
 * from precise expressions. */
#define P1 3
#define P2 8
#define P3 15
#define TMP 24
dvec3 PB[34];

uint cell_count;
uint rec_base;
uint brick_rank;
/* the current triangle's attributes (setup_tri_attrs) */
dvec3 V[3];
vec3 nrm;
double d00, d01, d11, den;
vec4 base;
float tuv[6];
float tcol[12];
int img;
uint ws, wt, tmat, tmi;
/* attrs 8: the triangle's factors and the textures that vary them */
float smetal, srough;
vec3 semit;
int ssamp, mr_img, em_img;
uint mr_ws, mr_wt, em_ws, em_wt;
float tuv_mr[6], tuv_em[6];

precise dvec3 clip_point(dvec3 a_in, dvec3 b_in, int axis, double val) {
    precise dvec3 a = a_in, b = b_in;
    precise double x0 = b[axis] - val, x1 = a[axis] - val;
    if (abs(x0) < abs(x1)) {
        a = b_in;
        b = a_in;
    }
    precise double da = b[axis] - a[axis];
    precise double s = val - a[axis];
    precise double t = s / da;
    precise dvec3 o;
    for (int k = 0; k < 3; k++) {
        precise double dk = b[k] - a[k];
        precise double r;
        if (dk == 0) r = a[k];
        else if (dk == da) r = a[k] + s;
        else if (dk == -da) r = a[k] - s;
        else r = a[k] + t * dk;
        o[k] = r;
    }
    o[axis] = val;
    return o;
}

/* PB[src .. src+n) clipped to lo <= p[axis] <= hi into PB[dst ..) */
int clip_slab(int src, int n, int axis, double lo, double hi, int dst) {
    int m = 0;
    for (int i = 0; i < n; i++) {
        dvec3 a = PB[src + i], b = PB[src + (i + 1) % n];
        bool ia = a[axis] >= lo, ib = b[axis] >= lo;
        if (ia) PB[TMP + m++] = a;
        if (ia != ib) PB[TMP + m++] = clip_point(a, b, axis, lo);
    }
    int r = 0;
    for (int i = 0; i < m; i++) {
        dvec3 a = PB[TMP + i], b = PB[TMP + (i + 1) % m];
        bool ia = a[axis] <= hi, ib = b[axis] <= hi;
        if (ia) PB[dst + r++] = a;
        if (ia != ib) PB[dst + r++] = clip_point(a, b, axis, hi);
    }
    return r;
}

void poly_range(int src, int n, int axis, out double lo, out double hi) {
    double a = PB[src][axis], b = a;
    for (int i = 1; i < n; i++) {
        double v = PB[src + i][axis];
        a = v < a ? v : a;
        b = v > b ? v : b;
    }
    lo = a;
    hi = b;
}

bool cell_range(double lo, double hi, int cmin, int cmax, int last, out int a, out int b) {
    double fa = floor(lo), fb = floor(hi);
    if (lo == double(last) + 1.0lf) fa = double(last);
    if (fa < double(cmin)) fa = double(cmin);
    if (fb > double(cmax)) fb = double(cmax);
    a = 0;
    b = -1;
    if (fa > fb) return false;
    a = int(fa);
    b = int(fb);
    return true;
}

int stack_axis() {
    precise dvec3 e1 = V[1] - V[0], e2 = V[2] - V[0];
    precise double n0 = abs(e1[1] * e2[2] - e1[2] * e2[1]);
    precise double n1 = abs(e1[2] * e2[0] - e1[0] * e2[2]);
    precise double n2 = abs(e1[0] * e2[1] - e1[1] * e2[0]);
    precise double ns = n0 + n1 + n2;
    if (ns > 0) return n0 >= n1 && n0 >= n2 ? 0 : (n1 >= n2 ? 1 : 2);
    precise double ext[3];
    for (int k = 0; k < 3; k++) ext[k] = max(max(V[0][k], V[1][k]), V[2][k]) - min(min(V[0][k], V[1][k]), V[2][k]);
    return ext[0] >= ext[1] && ext[0] >= ext[2] ? 0 : (ext[1] >= ext[2] ? 1 : 2);
}

bool off_max(int n, int axis, int c, int last) {
    if (c == last) return true;
    for (int i = 0; i < n; i++)
        if (PB[P3 + i][axis] < double(c + 1)) return true;
    return false;
}

/* ---- attributes --------------------------------------------------------------- */

/* x mod n for an integer-valued double x (|x| < 2^53): the floor quotient,
 * corrected by one where x / n rounded across an integer; all exact */
double mod_exact(double x, double n) {
    double q = floor(x / n);
    precise double r = x - q * n;
    if (r < 0) r += n;
    else if (r >= n) r -= n;
    return r;
}

/* x mod n in [0, n) (GLSL's % is undefined for negative operands) */
int mod_int(int x, int n) { return x >= 0 ? x % n : n - 1 - (-x - 1) % n; }

int wrap_coord(double x, uint n_u, uint mode) {
    if (abs(x) < 1073741824.0lf) { /* the usual case, in exact integers */
        int xi = int(x), ni = int(n_u);
        if (mode == 1u) return xi < 0 ? 0 : (xi >= ni ? ni - 1 : xi);
        if (mode == 2u) {
            int m = mod_int(xi, 2 * ni);
            return m >= ni ? 2 * ni - 1 - m : m;
        }
        return mod_int(xi, ni);
    }
    double n = double(n_u);
    if (mode == 1u) return int(x < 0 ? 0 : (x >= n ? n - 1 : x));
    if (mode == 2u) {
        double m = mod_exact(x, 2 * n);
        return int(m >= n ? 2 * n - 1 - m : m);
    }
    return int(mod_exact(x, n));
}

/* Bilinear sample of image im_i at (s, t): RGB sRGB-decoded when srgb
 * (colour, emission), else bytes / 255 (metallic-roughness is linear) */
vec4 sample_texture(double s_in, double t_in, int im_i, uint ws, uint wt, bool srgb) {
    precise double s = s_in, t = t_in;
    if (!(abs(s) < 1e9lf)) s = 0;
    if (!(abs(t) < 1e9lf)) t = 0;
    uvec4 im = images[im_i];
    precise double x = s * double(im.y) - 0.5lf, y = t * double(im.z) - 0.5lf;
    double fx = floor(x), fy = floor(y);
    precise double dxf = x - fx, dyf = y - fy;
    precise float ax = float(dxf), ay = float(dyf);
    int xs0 = wrap_coord(fx, im.y, ws), xs1 = wrap_coord(fx + 1, im.y, ws);
    int ys0 = wrap_coord(fy, im.z, wt), ys1 = wrap_coord(fy + 1, im.z, wt);
    precise float w0 = (1 - ax) * (1 - ay), w1 = ax * (1 - ay), w2 = (1 - ax) * ay, w3 = ax * ay;
    precise vec4 o = vec4(0);
    for (int k = 0; k < 4; k++) {
        int xx = (k & 1) != 0 ? xs1 : xs0, yy = (k >> 1) != 0 ? ys1 : ys0;
        uint p = texels[im.x + uint(yy) * im.y + uint(xx)];
        float wk = k == 0 ? w0 : k == 1 ? w1 : k == 2 ? w2 : w3;
        o[0] += wk * (srgb ? srgb_to_lin[p & 255u] : a255[p & 255u]);
        o[1] += wk * (srgb ? srgb_to_lin[(p >> 8) & 255u] : a255[(p >> 8) & 255u]);
        o[2] += wk * (srgb ? srgb_to_lin[(p >> 16) & 255u] : a255[(p >> 16) & 255u]);
        o[3] += wk * a255[p >> 24];
    }
    return o;
}

/* setup_tri_sampling: a triangle without material is metal 0, rough 1, no emission */
void setup_tri_sampling(uint mi, uint t) {
    smetal = 0;
    srough = 1;
    semit = vec3(0);
    ssamp = 0;
    mr_img = -1;
    em_img = -1;
    if (mi >= mat_count) return;
    SMat sm = smats[mi];
    smetal = sm.f.x;
    srough = sm.f.y;
    semit = vec3(sm.f.z, sm.f.w, sm.g.x);
    ssamp = sm.mr.x;
    mr_img = sm.mr.y;
    mr_ws = uint(sm.mr.z);
    mr_wt = uint(sm.mr.w);
    em_img = sm.em.x;
    em_ws = uint(sm.em.y);
    em_wt = uint(sm.em.z);
    if (mr_img >= 0)
        for (int k = 0; k < 6; k++) tuv_mr[k] = uv_mr[6 * t + k];
    if (em_img >= 0)
        for (int k = 0; k < 6; k++) tuv_em[k] = uv_em[6 * t + k];
}

void setup_tri_attrs(uint t) {
    precise dvec3 e1 = V[1] - V[0], e2 = V[2] - V[0];
    precise double n0 = e1[1] * e2[2] - e1[2] * e2[1], n1 = e1[2] * e2[0] - e1[0] * e2[2],
                   n2 = e1[0] * e2[1] - e1[1] * e2[0];
    precise double l = sqrt(n0 * n0 + n1 * n1 + n2 * n2);
    if (l > 0) {
        precise double q0 = n0 / l, q1 = n1 / l, q2 = n2 / l;
        precise vec3 nv = vec3(float(q0), float(q1), float(q2));
        nrm = nv;
    } else
        nrm = vec3(0);
    precise double a00 = e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2];
    precise double a11 = e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2];
    precise double a01 = e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2];
    precise double dn = a00 * a11 - a01 * a01;
    precise double lim = 1e-30lf * a00 * a11;
    if (!(dn > lim)) dn = 0;
    d00 = a00;
    d11 = a11;
    d01 = a01;
    den = dn;
    uint mi = trimat[t];
    tmat = (pc.attrs & 4u) != 0 && mi < mat_count ? mats[mi].id : 0u;
    tmi = mi;
    if ((pc.attrs & 8u) != 0u) setup_tri_sampling(mi, t);
    if ((pc.attrs & 1u) == 0) return;
    img = -1;
    base = vec4(1);
    if (mi < mat_count) {
        base = mats[mi].base;
        img = mats[mi].image; /* -1 unless sampled (an image with texels, and uv) */
        ws = mats[mi].wrap_s;
        wt = mats[mi].wrap_t;
    }
    if (img >= 0)
        for (int k = 0; k < 6; k++) tuv[k] = uv[6 * t + k];
    if (has_color != 0u)
        for (int k = 0; k < 12; k++) tcol[k] = colr[12 * t + k];
    else
        for (int k = 0; k < 12; k++) tcol[k] = 1.0;
}

/* hit_attr: the record of this triangle's part PB[src .. src+n) of cell c */
void emit(ivec3 c, int src, int n) {
    uint ri = rec_base + cell_count;
    cell_count++;
    uint local = 0;
    for (int b = 0; b < 6; b++)
        local |= ((uint(c.x) >> b) & 1u) << (3 * b) | ((uint(c.y) >> b) & 1u) << (3 * b + 1) |
                 ((uint(c.z) >> b) & 1u) << (3 * b + 2);
    keys[ri] = uvec2(local | brick_rank << 18, brick_rank >> 14);
    vals[ri] = ri;
    if (pc.attrs == 0u) return;
    precise double area = 0;
    precise dvec3 cen = dvec3(0);
    for (int i = 1; i + 1 < n; i++) {
        precise dvec3 e1 = PB[src + i] - PB[src], e2 = PB[src + i + 1] - PB[src];
        precise double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2],
                       cz = e1[0] * e2[1] - e1[1] * e2[0];
        precise double ar = 0.5lf * sqrt(cx * cx + cy * cy + cz * cz);
        area += ar;
        for (int k = 0; k < 3; k++) {
            precise double sum = PB[src][k] + PB[src + i][k] + PB[src + i + 1][k];
            precise double term = ar * sum / 3.0lf;
            cen[k] += term;
        }
    }
    if (area > 0) {
        for (int k = 0; k < 3; k++) cen[k] /= area;
    } else {
        for (int k = 0; k < 3; k++) {
            cen[k] = 0;
            for (int i = 0; i < n; i++) cen[k] += PB[src + i][k];
            cen[k] /= double(n);
        }
    }
    precise double wd = area + 1e-7lf;
    precise float wgt = float(wd);
    precise vec4 col = vec4(0);
    bool samp = (pc.attrs & 8u) != 0u;
    /* the centroid's barycentrics where sampled; a degenerate triangle's
     * are 1/3 each (hit_attr's: not 1 - 1/3 - 1/3, which is another double) */
    precise double b0 = 1.0lf / 3.0lf, b1 = 1.0lf / 3.0lf, b2 = 1.0lf / 3.0lf;
    if (((pc.attrs & 1u) != 0u || samp) && den > 0) {
        precise dvec3 v2 = cen - V[0];
        precise double d20 = 0, d21 = 0;
        for (int k = 0; k < 3; k++) {
            d20 += v2[k] * (V[1][k] - V[0][k]);
            d21 += v2[k] * (V[2][k] - V[0][k]);
        }
        b1 = (d11 * d20 - d01 * d21) / den;
        b2 = (d00 * d21 - d01 * d20) / den;
        b0 = 1 - b1 - b2;
    }
    if ((pc.attrs & 1u) != 0u) {
        for (int k = 0; k < 4; k++) {
            precise double mix3 = b0 * double(tcol[k]) + b1 * double(tcol[4 + k]) + b2 * double(tcol[8 + k]);
            precise float m = float(mix3);
            col[k] = base[k] * m;
        }
        if (img >= 0) {
            precise double s = b0 * double(tuv[0]) + b1 * double(tuv[2]) + b2 * double(tuv[4]);
            precise double t = b0 * double(tuv[1]) + b1 * double(tuv[3]) + b2 * double(tuv[5]);
            precise vec4 tx = sample_texture(s, t, img, ws, wt, true);
            for (int k = 0; k < 4; k++) col[k] *= tx[k];
        }
        for (int k = 0; k < 4; k++) col[k] = wgt * col[k];
    }
    precise vec3 nw;
    for (int k = 0; k < 3; k++) nw[k] = wgt * nrm[k];
    recs[ri].c = col;
    recs[ri].n = vec4(nw, wgt);
    recs[ri].mat = samp ? tmi : tmat;
    if (samp) { /* metallic, roughness and emission at the same point, weighted the same */
        precise float pm = smetal, pr = srough;
        precise vec3 pe = semit;
        if (mr_img >= 0) {
            precise double s = b0 * double(tuv_mr[0]) + b1 * double(tuv_mr[2]) + b2 * double(tuv_mr[4]);
            precise double t = b0 * double(tuv_mr[1]) + b1 * double(tuv_mr[3]) + b2 * double(tuv_mr[5]);
            precise vec4 tx = sample_texture(s, t, mr_img, mr_ws, mr_wt, false);
            if ((ssamp & 1) != 0) pm *= tx[2]; /* glTF: metalness in B, roughness in G */
            if ((ssamp & 2) != 0) pr *= tx[1];
        }
        if (em_img >= 0) {
            precise double s = b0 * double(tuv_em[0]) + b1 * double(tuv_em[2]) + b2 * double(tuv_em[4]);
            precise double t = b0 * double(tuv_em[1]) + b1 * double(tuv_em[3]) + b2 * double(tuv_em[5]);
            precise vec4 tx = sample_texture(s, t, em_img, em_ws, em_wt, true);
            for (int k = 0; k < 3; k++) pe[k] *= tx[k];
        }
        precise float wm = wgt * pm, wr = wgt * pr;
        precise vec3 we;
        for (int k = 0; k < 3; k++) we[k] = wgt * pe[k];
        recs[ri].pm = wm;
        recs[ri].pr = wr;
        recs[ri].pe0 = we[0];
        recx[ri] = vec2(we[1], we[2]);
    }
}

void hit(ivec3 c, int src, int n) {
    if (pc.mode == 0u) cell_count++;
    else emit(c, src, n);
}

/* tri_cells with last != NULL (the brick pass) */
void tri_cells(ivec3 cmin, ivec3 cmax, ivec3 last, bool want_poly, int strip) {
    int d = stack_axis(), u = (d + 1) % 3, w = (d + 2) % 3;
    int lu = last[u], lw = last[w], ld = last[d];
    for (int k = 0; k < 3; k++) PB[k] = V[k];
    double lo, hi;
    int ua, ub, wa, wb, da, db;
    ivec3 c, fc;
    bool inside = true;
    for (int k = 0; k < 3 && inside; k++) {
        poly_range(0, 3, k, lo, hi);
        double f = floor(lo);
        fc[k] = int(f);
        inside = lo > f && hi < f + 1 && f >= double(cmin[k]) && f <= double(cmax[k]);
    }
    if (inside) {
        if (strip == 0) hit(fc, 0, 3);
        return;
    }
    poly_range(0, 3, u, lo, hi);
    if (!cell_range(lo, hi, cmin[u], cmax[u], lu, ua, ub)) return;
    for (int iu = ua + strip; iu <= ub && iu == ua + strip; iu++) {
        int n1 = clip_slab(0, 3, u, double(iu), double(iu + 1), P1);
        if (n1 == 0) continue;
        poly_range(P1, n1, w, lo, hi);
        if (!cell_range(lo, hi, cmin[w], cmax[w], lw, wa, wb)) continue;
        for (int iw = wa; iw <= wb; iw++) {
            int n2 = clip_slab(P1, n1, w, double(iw), double(iw + 1), P2);
            if (n2 == 0) continue;
            dvec3 mn = PB[P2], mx = PB[P2];
            for (int i = 1; i < n2; i++) {
                mn = min(mn, PB[P2 + i]);
                mx = max(mx, PB[P2 + i]);
            }
            if ((iu != lu && mn[u] >= double(iu + 1)) || (iw != lw && mn[w] >= double(iw + 1))) continue;
            bool check = (iu != lu && mx[u] >= double(iu + 1)) || (iw != lw && mx[w] >= double(iw + 1));
            lo = mn[d];
            hi = mx[d];
            if (!cell_range(lo, hi, cmin[d], cmax[d], ld, da, db)) continue;
            c[u] = iu;
            c[w] = iw;
            for (int id = da; id <= db; id++) {
                c[d] = id;
                bool edge = check && (double(id) == hi || (id == ld && lo == double(id) + 1.0lf));
                if (!want_poly && !edge) {
                    hit(c, P3, 0);
                    continue;
                }
                int n3 = clip_slab(P2, n2, d, double(id), double(id + 1), P3);
                if (n3 == 0) {
                    PB[P3] = PB[P2];
                    n3 = 1;
                }
                if (edge && (!off_max(n3, u, iu, lu) || !off_max(n3, w, iw, lw))) continue;
                hit(c, P3, n3);
            }
        }
    }
}

void main() {
    uint p = pc.first + (32u / LANES) * (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) + gl_LocalInvocationID.x / LANES;
    if (p >= pc.pair_count) return;
    uvec2 pr = pairs[p];
    uint t = pr.x;
    brick_rank = pr.y;
    ivec3 org = ivec3(bricks[brick_rank].xyz);
    ivec3 cmin = ivec3(0), cmax, last;
    for (int a = 0; a < 3; a++) {
        int left = pc.size[a] - org[a];
        cmax[a] = (left < 64 ? left : 64) - 1;
        last[a] = left <= 64 ? cmax[a] : NO_LAST;
    }
    for (int k = 0; k < 3; k++) {
        precise dvec3 gv = dvec3(g[9 * t + 3 * k], g[9 * t + 3 * k + 1], g[9 * t + 3 * k + 2]);
        precise dvec3 vk = gv - dvec3(org);
        V[k] = vk;
    }
    bool attrs = pc.attrs != 0u;
    if (pc.mode == 1u && attrs) setup_tri_attrs(t);
    for (int strip = int(gl_LocalInvocationID.x % LANES); strip < 64; strip += int(LANES)) {
        uint slot = p * 64u + uint(strip); /* counts: per (pair, strip), in the CPU's enumeration order */
        cell_count = 0;
        rec_base = pc.mode == 1u ? counts[slot] : 0u;
        tri_cells(cmin, cmax, last, pc.mode == 1u && attrs, strip);
        if (pc.mode == 0u) {
            counts[slot] = cell_count;
            /* an upper bound of all pieces / 256, which cannot wrap: the host
             * refuses a total the 32-bit prefix sum would wrap */
            if (cell_count > 0u) atomicAdd(counts[pc.pair_count * 64u + 1u], (cell_count + 255u) >> 8);
        }
    }
}
