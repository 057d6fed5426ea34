/* tests/probes/closed_form.h - the pieces the glass tests' closed forms share
 * (test_glass_direct.c, test_glass_thick.c), written here from the formulas,
 * not taken from the renderers (they are the independent path):
 * the pinhole's pixel-centre ray and unpolarised Fresnel reflectance. */
#ifndef VX_TESTS_PROBES_CLOSED_FORM_H
#define VX_TESTS_PROBES_CLOSED_FORM_H

#include <math.h>
#include <stdint.h>

#include "render/render.h"

static inline double cf_dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* Unpolarised Fresnel reflectance (cosi > 0, eta = n_t / n_i). */
static inline double cf_fresnel(double cosi, double eta) {
    double s2t = (1 - cosi * cosi) / (eta * eta);
    if (s2t >= 1) return 1;
    double ct = sqrt(1 - s2t);
    double rs = (cosi - eta * ct) / (cosi + eta * ct), rp = (eta * cosi - ct) / (eta * cosi + ct);
    return 0.5 * (rs * rs + rp * rp);
}

/* Pixel (px, py)'s centre ray of b's camera (render/render.h's pinhole: u
 * across, v up, the half height tan(fov / 2)), unit direction into d. */
static inline void cf_pixel_ray(const vx_render_desc* b, uint32_t px, uint32_t py, double d[3]) {
    const double* e = b->camera.eye;
    double f[3], r[3], u[3], up[3] = {b->camera.up[0], b->camera.up[1], b->camera.up[2]};
    for (int k = 0; k < 3; k++) f[k] = b->camera.target[k] - e[k];
    double lf = sqrt(cf_dot3(f, f));
    for (int k = 0; k < 3; k++) f[k] /= lf;
    r[0] = f[1] * up[2] - f[2] * up[1], r[1] = f[2] * up[0] - f[0] * up[2], r[2] = f[0] * up[1] - f[1] * up[0];
    double lr = sqrt(cf_dot3(r, r));
    for (int k = 0; k < 3; k++) r[k] /= lr;
    u[0] = r[1] * f[2] - r[2] * f[1], u[1] = r[2] * f[0] - r[0] * f[2], u[2] = r[0] * f[1] - r[1] * f[0];
    double hh = tan(0.5 * b->camera.fov * 3.14159265358979323846 / 180), hw = hh * (double)b->width / b->height;
    double su = ((px + 0.5) / b->width) * 2 - 1, sv = 1 - ((py + 0.5) / b->height) * 2;
    for (int k = 0; k < 3; k++) d[k] = f[k] + su * hw * r[k] + sv * hh * u[k];
    double ld = sqrt(cf_dot3(d, d));
    for (int k = 0; k < 3; k++) d[k] /= ld;
}

#endif
