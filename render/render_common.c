/* render/render_common.c - camera, transforms and scene checks shared by the
 * GPU tracer and the CPU reference (both must generate the same rays). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "render/trace.h"

static const char* const mode_names[VX_RENDER_MODE_NUM] = {"color", "albedo", "normal", "depth", "instance",
                                                           "iterations"};

const char* vx_render_mode_name(vx_render_mode m) { return (unsigned)m < VX_RENDER_MODE_NUM ? mode_names[m] : "?"; }

bool vx_render_mode_parse(const char* s, vx_render_mode* out) {
    for (int i = 0; i < VX_RENDER_MODE_NUM; i++)
        if (strcmp(s, mode_names[i]) == 0) {
            *out = (vx_render_mode)i;
            return true;
        }
    return false;
}

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static void cross3(const double a[3], const double b[3], double o[3]) {
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}
static bool norm3(double v[3]) {
    double l = sqrt(dot3(v, v));
    if (!(l > 0) || !isfinite(l)) return false;
    v[0] /= l, v[1] /= l, v[2] /= l;
    return true;
}

void vx__affine_apply(const double m[12], const double p[3], double o[3]) {
    for (int r = 0; r < 3; r++) o[r] = m[4 * r] * p[0] + m[4 * r + 1] * p[1] + m[4 * r + 2] * p[2] + m[4 * r + 3];
}


bool vx__affine_inverse(const double m[12], double o[12]) {
    double a = m[0], b = m[1], c = m[2], d = m[4], e = m[5], f = m[6], g = m[8], h = m[9], i = m[10];
    double A = e * i - f * h, B = -(d * i - f * g), C = d * h - e * g;
    double det = a * A + b * B + c * C;
    if (!(fabs(det) > 1e-300) || !isfinite(det)) return false;
    double inv[9] = {A / det, -(b * i - c * h) / det, (b * f - c * e) / det,
                     B / det, (a * i - c * g) / det,  -(a * f - c * d) / det,
                     C / det, -(a * h - b * g) / det, (a * e - b * d) / det};
    for (int r = 0; r < 3; r++) {
        o[4 * r + 0] = inv[3 * r + 0];
        o[4 * r + 1] = inv[3 * r + 1];
        o[4 * r + 2] = inv[3 * r + 2];
        o[4 * r + 3] = -(inv[3 * r] * m[3] + inv[3 * r + 1] * m[7] + inv[3 * r + 2] * m[11]);
    }
    for (int k = 0; k < 12; k++)
        if (!isfinite(o[k])) return false;
    return true;
}

vx_result vx__check_scene(const vx_svo_scene* s, vx_error* err) {
    for (uint32_t i = 0; i < s->instance_count; i++) {
        const vx_svo_instance* in = &s->instances[i];
        if (in->model >= s->model_count)
            return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "instance %u refers to model %u of %u", i, in->model,
                           s->model_count);
        if (!vx_svo_instance_drawn(s, i)) continue;
        const vx_svo_model* m = &s->models[in->model];
        if (m->depth > VX_RENDER_MAX_DEPTH)
            return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET,
                           "model %u has %u octree levels; the tracer supports at most %u (split it into instances)",
                           in->model, m->depth, VX_RENDER_MAX_DEPTH);
        if (m->root != VX_SVO_ROOT_LEAF && m->root >= m->node_count)
            return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "model %u: root %u outside %u node words", in->model,
                           m->root, m->node_count);
        double w[12], inv[12];
        vx_svo_instance_world(s, in, w);
        if (!vx__affine_inverse(w, inv))
            return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "instance %u has a singular or non-finite transform",
                           i);
    }
    return VX_OK;
}

vx_result vx_render_desc_validate(const vx_render_desc* d, vx_error* err) {
    if (!d) return VX_OK;
    if (d->width > 16384 || d->height > 16384)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "image size %ux%u exceeds 16384", d->width, d->height);
    if ((unsigned)d->mode >= VX_RENDER_MODE_NUM)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "unknown mode %d", (int)d->mode);
    if (d->spp > 1024) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "spp %u exceeds 1024", d->spp);
    const vx_render_camera* c = &d->camera;
    if (!(c->fov >= 0 && c->fov < 180))
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "fov %g outside (0, 180) degrees", c->fov);
    for (int k = 0; k < 3; k++)
        if (!isfinite(c->eye[k]) || !isfinite(c->target[k]) || !isfinite(c->up[k]) || !isfinite(d->light_dir[k]))
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "camera or light has a non-finite coordinate");
    if (c->set && c->eye[0] == c->target[0] && c->eye[1] == c->target[1] && c->eye[2] == c->target[2])
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "camera eye and target are the same point");
    if (!(c->ortho_height >= 0) || !isfinite(c->ortho_height))
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "ortho height must be positive");
    if (!(d->ambient >= 0 && d->ambient <= 1))
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "ambient %g outside [0, 1]", d->ambient);
    if (d->beam > 64) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "beam block %u exceeds 64 pixels", d->beam);
    if (!(d->lod_pixels >= 0) || !isfinite(d->lod_pixels))
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "lod pixels must be positive");
    return VX_OK;
}

vx_render_desc vx_render_desc_defaults(void) {
    vx_render_desc d = {.width = 640, .height = 480, .spp = 1, .lod_pixels = 1, .ambient = 0.3,
                        .light_dir = {0.35, -0.45, 0.82}};
    d.camera.fov = 45;
    return d;
}

void vx__frame_rect(const vx__frame* f, const double lo[3], const double hi[3], uint32_t rect[4]) {
    rect[0] = rect[1] = 0, rect[2] = f->width, rect[3] = f->height;
    double eye[3], rx2 = dot3(f->rx, f->rx), uy2 = dot3(f->uy, f->uy), diag = 0;
    for (int k = 0; k < 3; k++) {
        eye[k] = f->ref[k] - (f->ortho ? 0 : f->fwd[k] * f->t_start);
        diag += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    }
    if (!(rx2 > 0 && uy2 > 0) || !(diag >= 0)) return;
    diag = sqrt(diag);
    /* u, v as trace.comp defines them: a ray's direction (perspective) or
     * origin (orthographic) is fwd + u rx + v uy, resp. ref + u rx + v uy */
    double umin = INFINITY, umax = -INFINITY, vmin = INFINITY, vmax = -INFINITY;
    int behind = 0;
    bool near = false;
    double cz[8];
    for (int c = 0; c < 8; c++) {
        double p[3] = {(c & 1) ? hi[0] : lo[0], (c & 2) ? hi[1] : lo[1], (c & 4) ? hi[2] : lo[2]};
        double v[3] = {p[0] - eye[0], p[1] - eye[1], p[2] - eye[2]};
        double z = dot3(v, f->fwd), len = sqrt(dot3(v, v));
        double a = dot3(v, f->rx) / rx2, b = dot3(v, f->uy) / uy2;
        /* margins far above the float rays' rounding (about 1e-7 relative) */
        double eps = 1e-4 * (f->ortho ? diag + len : len);
        cz[c] = z;
        if (z < -eps) {
            behind++;
            if (!f->ortho) continue;
        } else if (!f->ortho) {
            if (z <= eps) {
                near = true; /* the box reaches the eye's plane */
                continue;
            }
            a /= z, b /= z;
        }
        umin = fmin(umin, a), umax = fmax(umax, a), vmin = fmin(vmin, b), vmax = fmax(vmax, b);
    }
    if (behind == 8) {
        /* rays run forward from the eye's plane (t >= 0): nothing to meet */
        rect[0] = rect[1] = rect[2] = rect[3] = 0;
        return;
    }
    if ((behind || near) && !f->ortho) {
        /* The box crosses the eye's plane (a camera inside the scene, whose
         * BVH nodes vx__frame_tiles projects). Where the eye lies at a
         * distance d outside it: the box cut at z = zc (its corners beyond
         * and its edges' crossings of that plane projected), zc = d / (2
         * sqrt(1 + 4 |rx|^2 + 4 |uy|^2)). A point seen under |u|, |v| <= 2
         * with z < zc lies within zc sqrt(...) = d / 2 of the eye; so the part
         * before the cut, at least d away, lies outside every pixel's ray
         * (|u|, |v| <= 1 + a sample's half pixel). Nearer: every pixel. */
        double dist2 = 0, cen2 = 0;
        for (int k = 0; k < 3; k++) {
            double e = eye[k] < lo[k] ? lo[k] - eye[k] : (eye[k] > hi[k] ? eye[k] - hi[k] : 0);
            double m = 0.5 * (lo[k] + hi[k]) - eye[k];
            dist2 += e * e, cen2 += m * m;
        }
        double dist = sqrt(dist2);
        if (!(dist > 1e-4 * (diag + sqrt(cen2)))) return;
        double zc = 0.5 * dist / sqrt(1 + 4 * rx2 + 4 * uy2);
        umin = vmin = INFINITY, umax = vmax = -INFINITY;
        for (int c = 0; c < 8; c++) {
            double p[3] = {(c & 1) ? hi[0] : lo[0], (c & 2) ? hi[1] : lo[1], (c & 4) ? hi[2] : lo[2]};
            double v[3] = {p[0] - eye[0], p[1] - eye[1], p[2] - eye[2]};
            if (cz[c] >= zc) {
                double a = dot3(v, f->rx) / rx2 / cz[c], b = dot3(v, f->uy) / uy2 / cz[c];
                umin = fmin(umin, a), umax = fmax(umax, a), vmin = fmin(vmin, b), vmax = fmax(vmax, b);
            }
            for (int k = 0; k < 3; k++) {
                int c2 = c | (1 << k); /* the edge from c along axis k */
                if (c2 == c || (cz[c] >= zc) == (cz[c2] >= zc)) continue;
                double q[3] = {p[0], p[1], p[2]};
                q[k] = (c2 & (1 << k)) ? hi[k] : lo[k];
                double s = (zc - cz[c]) / (cz[c2] - cz[c]), w[3];
                for (int j = 0; j < 3; j++) w[j] = p[j] + s * (q[j] - p[j]) - eye[j];
                double a = dot3(w, f->rx) / rx2 / zc, b = dot3(w, f->uy) / uy2 / zc;
                umin = fmin(umin, a), umax = fmax(umax, a), vmin = fmin(vmin, b), vmax = fmax(vmax, b);
            }
        }
        if (!(umin <= umax)) {
            rect[0] = rect[1] = rect[2] = rect[3] = 0;
            return;
        }
        /* the crossings' rounding: the cut's points are at z = zc exactly
         * in exact arithmetic; widen by their relative error */
        double wu = 1e-6 * (fabs(umin) + fabs(umax)), wv = 1e-6 * (fabs(vmin) + fabs(vmax));
        umin -= wu, umax += wu, vmin -= wv, vmax += wv;
        umin = fmax(umin, -4), umax = fmin(umax, 4), vmin = fmax(vmin, -4), vmax = fmin(vmax, 4);
    }
    /* pixel centres: u = ((x + 0.5) / W) * 2 - 1, v = 1 - ((y + 0.5) / H) * 2 */
    double W = f->width, H = f->height;
    double x0 = floor((umin + 1) * 0.5 * W - 0.5) - 2, x1 = ceil((umax + 1) * 0.5 * W - 0.5) + 3;
    double y0 = floor((1 - vmax) * 0.5 * H - 0.5) - 2, y1 = ceil((1 - vmin) * 0.5 * H - 0.5) + 3;
    x0 = fmax(x0, 0), y0 = fmax(y0, 0), x1 = fmin(x1, W), y1 = fmin(y1, H);
    if (!(x0 < x1 && y0 < y1)) {
        rect[0] = rect[1] = rect[2] = rect[3] = 0;
        return;
    }
    rect[0] = (uint32_t)x0, rect[1] = (uint32_t)y0, rect[2] = (uint32_t)x1, rect[3] = (uint32_t)y1;
}

bool vx__frame_cull(const vx__frame* f, const double lo[3], const double hi[3], bool cull, uint32_t rect[4],
                    uint32_t groups[3], uint32_t miss_groups[3], uint64_t* traced) {
    uint32_t W = f->width, H = f->height;
    if (cull) vx__frame_rect(f, lo, hi, rect);
    else rect[0] = rect[1] = 0, rect[2] = W, rect[3] = H;
    uint32_t rw = rect[2] - rect[0], rh = rect[3] - rect[1];
    *traced = (uint64_t)rw * rh;
    groups[0] = (rw + 7) / 8, groups[1] = (rh + 7) / 8, groups[2] = 1;
    uint64_t mg = ((uint64_t)W * H - *traced + 63) / 64;
    uint32_t mgx = mg < 65535 ? (uint32_t)mg : 65535u;
    if (!mgx) mgx = 1;
    miss_groups[0] = mgx, miss_groups[1] = (uint32_t)((mg + mgx - 1) / mgx), miss_groups[2] = 1;
    return *traced != (uint64_t)W * H;
}

/* The tiles [o[0], o[2]) x [o[1], o[3]) of 2^s pixels that node n's
 * rectangle meets (none: all 0). */
static void tile_span(const vx__frame* f, const vx_bvh* bvh, uint32_t n, uint32_t s, uint32_t o[4]) {
    const vx_bvh_node* b = &bvh->nodes[n];
    double lo[3] = {b->lo[0], b->lo[1], b->lo[2]}, hi[3] = {b->hi[0], b->hi[1], b->hi[2]};
    uint32_t r[4];
    vx__frame_rect(f, lo, hi, r);
    if (r[0] < r[2] && r[1] < r[3])
        o[0] = r[0] >> s, o[1] = r[1] >> s, o[2] = ((r[2] - 1) >> s) + 1, o[3] = ((r[3] - 1) >> s) + 1;
    else
        o[0] = o[1] = o[2] = o[3] = 0;
}

void vx__frame_tile_grid(const vx__frame* f, uint32_t* shift, uint32_t* nx, uint32_t* ny) {
    uint32_t W = f->width, H = f->height, s = 3;
    while (((W + (1u << s) - 1) >> s) > VX__TILES_X || ((H + (1u << s) - 1) >> s) > VX__TILES_X) s++;
    *shift = s, *nx = (W + (1u << s) - 1) >> s, *ny = (H + (1u << s) - 1) >> s;
}

void vx__frame_tiles(const vx__frame* f, const vx_bvh* bvh, uint16_t tiles[VX__TILES_X * VX__TILES_X],
                     uint32_t* shift, uint32_t* nx) {
    uint32_t W = f->width, H = f->height, s, tx, ty;
    vx__frame_tile_grid(f, &s, &tx, &ty);
    *shift = s, *nx = tx;
    memset(tiles, 0, sizeof(uint16_t) * VX__TILES_X * VX__TILES_X);
    if (!bvh || !bvh->node_count || !W || !H) return;
    /* every tile starts at the root, or nowhere outside its rectangle */
    uint32_t root[4];
    tile_span(f, bvh, 0, s, root);
    for (uint32_t y = 0; y < ty; y++)
        for (uint32_t x = 0; x < tx; x++)
            tiles[y * tx + x] = (x >= root[0] && x < root[2] && y >= root[1] && y < root[3]) ? 0 : VX__TILE_NONE;
    /* top down: a node's tiles (those that hold its index, within its span)
     * move to the one child whose rectangle meets them, or to none; a depth
     * past the stack leaves them at the node (an ancestor: still exact) */
    struct {
        uint32_t node, span[4];
    } st[64];
    int sp = 0;
    st[sp].node = 0, memcpy(st[sp].span, root, sizeof root), sp++;
    while (sp > 0) {
        sp--;
        uint32_t n = st[sp].node, sn[4];
        memcpy(sn, st[sp].span, sizeof sn);
        const vx_bvh_node* b = &bvh->nodes[n];
        if (b->count || b->first + 1 >= bvh->node_count || b->first + 1 >= VX__TILE_NONE) continue;
        uint32_t sa[4], sb[4];
        tile_span(f, bvh, b->first, s, sa);
        tile_span(f, bvh, b->first + 1, s, sb);
        bool any_a = false, any_b = false;
        for (uint32_t y = sn[1]; y < sn[3]; y++)
            for (uint32_t x = sn[0]; x < sn[2]; x++) {
                uint16_t* t = &tiles[y * tx + x];
                if (*t != n) continue;
                bool a = x >= sa[0] && x < sa[2] && y >= sa[1] && y < sa[3];
                bool c = x >= sb[0] && x < sb[2] && y >= sb[1] && y < sb[3];
                if (a && c) continue;
                *t = a ? (uint16_t)b->first : c ? (uint16_t)(b->first + 1) : (uint16_t)VX__TILE_NONE;
                any_a |= a, any_b |= c;
            }
        if (any_a && sp < 64) st[sp].node = b->first, memcpy(st[sp].span, sa, sizeof sa), sp++;
        if (any_b && sp < 64) st[sp].node = b->first + 1, memcpy(st[sp].span, sb, sizeof sb), sp++;
    }
}

/* The centre (c may be NULL) and half diagonal of the box [lo, hi], 1 for an
 * empty or degenerate box: the default framing's measure. */
static void box_centre_radius(const double lo[3], const double hi[3], double c[3], double* rad) {
    double r = 0;
    for (int k = 0; k < 3; k++) {
        if (c) c[k] = 0.5 * (lo[k] + hi[k]);
        r += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    }
    r = 0.5 * sqrt(r);
    *rad = r > 0 ? r : 1;
}

void vx_render_camera_default(const double lo[3], const double hi[3], const vx_render_desc* desc, vx_render_camera* out) {
    const vx_render_desc D = vx_render_desc_defaults();
    vx_render_camera cam = desc ? desc->camera : (vx_render_camera){0};
    double fov = (cam.fov > 0 ? cam.fov : D.camera.fov) * 3.14159265358979323846 / 180.0;
    double c[3], rad;
    box_centre_radius(lo, hi, c, &rad);
    double dir[3] = {0.45, -1.0, 0.65};
    norm3(dir);
    double dist = cam.ortho ? 3 * rad : rad / sin(0.5 * fov) * 1.05;
    for (int k = 0; k < 3; k++) cam.eye[k] = c[k] + dir[k] * dist, cam.target[k] = c[k];
    /* vx__frame_setup's half height for a set camera without one is rad * 1.05
     * of the frame's own bounds: the box's, stated (2 x is exact) */
    if (cam.ortho && !(cam.ortho_height > 0)) cam.ortho_height = 2 * (rad * 1.05);
    cam.set = true;
    *out = cam;
}

vx_result vx__frame_setup(const double lo[3], const double hi[3], const vx_render_desc* desc_in, vx__frame* f,
                          vx_error* err) {
    const vx_render_desc D = vx_render_desc_defaults(); /* what a zero field means */
    vx_render_desc d = desc_in ? *desc_in : (vx_render_desc){0};
    vx_result r = vx_render_desc_validate(&d, err);
    if (r) return r;
    memset(f, 0, sizeof *f);
    f->width = d.width ? d.width : D.width;
    f->height = d.height ? d.height : D.height;
    f->spp = d.spp ? d.spp : D.spp;
    f->mode = d.mode;
    f->ortho = d.camera.ortho;
    f->lod = d.lod;
    f->beam = d.beam; /* 0 and 1: off */
    f->lod_pixels = d.lod_pixels > 0 ? d.lod_pixels : D.lod_pixels;
    f->ambient = d.ambient > 0 ? d.ambient : D.ambient;
    double fov = (d.camera.fov > 0 ? d.camera.fov : D.camera.fov) * 3.14159265358979323846 / 180.0;
    double rad;
    box_centre_radius(lo, hi, NULL, &rad);
    if (!d.camera.set) vx_render_camera_default(lo, hi, &d, &d.camera);
    double up[3] = {d.camera.up[0], d.camera.up[1], d.camera.up[2]};
    if (up[0] == 0 && up[1] == 0 && up[2] == 0) up[2] = 1;
    double eye[3], target[3];
    memcpy(eye, d.camera.eye, sizeof eye);
    memcpy(target, d.camera.target, sizeof target);
    double fwd[3] = {target[0] - eye[0], target[1] - eye[1], target[2] - eye[2]};
    if (!norm3(fwd)) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "camera direction is degenerate");
    double right[3], upv[3];
    cross3(fwd, up, right);
    if (!norm3(right)) {
        double alt[3] = {0, 1, 0};
        if (fabs(fwd[1]) > 0.9) alt[1] = 0, alt[0] = 1;
        cross3(fwd, alt, right);
        norm3(right);
    }
    cross3(right, fwd, upv);
    double aspect = (double)f->width / f->height;
    double half_h;
    if (f->ortho) {
        half_h = d.camera.ortho_height > 0 ? 0.5 * d.camera.ortho_height : rad * 1.05;
        f->pixel_size = 2 * half_h / f->height;
    } else {
        half_h = tan(0.5 * fov);
        f->pixel_angle = 2 * half_h / f->height;
    }
    for (int k = 0; k < 3; k++) {
        f->fwd[k] = fwd[k];
        f->rx[k] = right[k] * half_h * aspect;
        f->uy[k] = upv[k] * half_h;
    }
    /* The reference plane sits just before every corner of the scene bounds,
     * so no geometry lies between the eye and the plane. */
    double tmin = INFINITY;
    for (int cidx = 0; cidx < 8; cidx++) {
        double p[3] = {(cidx & 1) ? hi[0] : lo[0], (cidx & 2) ? hi[1] : lo[1], (cidx & 4) ? hi[2] : lo[2]};
        double v[3] = {p[0] - eye[0], p[1] - eye[1], p[2] - eye[2]};
        tmin = fmin(tmin, dot3(v, fwd));
    }
    f->t_start = tmin > 0 ? tmin * (1 - 1e-7) - 1e-3 * rad : 0;
    if (f->t_start < 0) f->t_start = 0;
    for (int k = 0; k < 3; k++) f->ref[k] = eye[k] + fwd[k] * f->t_start;
    double ld[3] = {d.light_dir[0], d.light_dir[1], d.light_dir[2]};
    if (ld[0] == 0 && ld[1] == 0 && ld[2] == 0) memcpy(ld, D.light_dir, sizeof ld);
    if (!norm3(ld)) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "light direction is degenerate");
    memcpy(f->light, ld, sizeof ld);
    return VX_OK;
}

vx_result vx__gpu_float_range(const double lo[3], const double hi[3], vx_error* err) {
    /* the kernels' coordinates are relative to the frame's reference point
     * (vx__frame), so the bounds' distance from 0 reaches them only through
     * the double differences the host takes: what floats must hold is the
     * scene's size; what doubles must hold is the scene at its place */
    const double big = 0x1p56, small = 0x1p-56, reach = 0x1p52;
    double mag = 0, side = 0;
    for (int k = 0; k < 3; k++) {
        if (!(lo[k] <= hi[k])) return VX_OK; /* empty */
        mag = fmax(mag, fmax(fabs(lo[k]), fabs(hi[k])));
        side = fmax(side, hi[k] - lo[k]);
    }
    if (side > big || (side > 0 && side < small)) /* side 0 at 0: an empty scene */
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET,
                       "scene bounds [%.3g %.3g %.3g] - [%.3g %.3g %.3g] past the GPU tracer's float range "
                       "(a side within 2^-56..2^56); the CPU reference traces it",
                       lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
    if (mag > side * reach)
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET,
                       "scene bounds [%.3g %.3g %.3g] - [%.3g %.3g %.3g] lie more than 2^52 times their size from "
                       "the origin, past the GPU tracer's float range: a double there cannot tell the scene's corners "
                       "apart (nor can the CPU reference's rays)",
                       lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
    return VX_OK;
}

double vx__frame_ray(const vx__frame* f, double u, double v, double P[3], double o[3], double d[3]) {
    double t_off;
    if (f->ortho) {
        for (int k = 0; k < 3; k++) P[k] = u * f->rx[k] + v * f->uy[k], d[k] = f->fwd[k];
        t_off = f->t_start;
    } else {
        double du[3], len = 0;
        for (int k = 0; k < 3; k++) du[k] = f->fwd[k] + u * f->rx[k] + v * f->uy[k], len += du[k] * du[k];
        len = sqrt(len);
        for (int k = 0; k < 3; k++) d[k] = du[k] / len, P[k] = f->t_start * (u * f->rx[k] + v * f->uy[k]);
        t_off = f->t_start * len;
    }
    for (int k = 0; k < 3; k++) o[k] = f->ref[k] + P[k];
    return t_off;
}

void vx__sample_offset(uint32_t i, double* ox, double* oy) {
    if (i == 0) {
        *ox = *oy = 0;
        return;
    }
    /* R2 sequence; the GPU computes the same in float */
    double x = 0.5 + i * 0.7548776662466927, y = 0.5 + i * 0.5698402909980532;
    *ox = x - floor(x) - 0.5;
    *oy = y - floor(y) - 0.5;
}

void vx__instance_color(uint32_t id, float rgb[3]) {
    uint32_t h = id * 2654435761u + 0x9E3779B9u;
    h ^= h >> 15;
    h *= 0x85EBCA6Bu;
    h ^= h >> 13;
    rgb[0] = (float)(h & 0xFFu) / 255.0f * 0.8f + 0.2f;
    rgb[1] = (float)((h >> 8) & 0xFFu) / 255.0f * 0.8f + 0.2f;
    rgb[2] = (float)((h >> 16) & 0xFFu) / 255.0f * 0.8f + 0.2f;
}

void vx__heat_color(uint32_t it, float rgb[3]) {
    float x = (float)it / 256.0f;
    if (x > 1) x = 1;
    float v[3] = {3 * x, 3 * x - 1, 3 * x - 2};
    for (int k = 0; k < 3; k++) rgb[k] = v[k] < 0 ? 0 : (v[k] > 1 ? 1 : v[k]);
}

void vx_render_image_free(vx_render_image* img) {
    if (!img) return;
    vx_free(img->alloc, img->pixels);
    vx_free(img->alloc, img->hits);
    memset(img, 0, sizeof *img);
}
