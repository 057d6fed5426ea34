/* svo/svo_sky.c - the sky as text (svo.h vx_sky_parse, vx_sky_format): the
 * --sky syntax, here so that the tools, the Python module and svo_view read
 * and write one form. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "svo/svo.h"

/* The rotation is degrees on the command line, radians in vx_sky: the
 * parse multiplies by this constant, the format looks for the degrees that
 * give the radians back through the same product. */
static const double deg = 3.14159265358979323846 / 180.0;


static vx_result bad(vx_sky* k, vx_error* err, const char* msg) {
    memset(k, 0, sizeof *k);
    return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "%s", msg);
}

vx_result vx_sky_parse(const char* spec, vx_sky* k, vx_error* err) {
    if (!k) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "sky: NULL");
    memset(k, 0, sizeof *k); /* one stored form: what the type does not use is zero */
    char buf[512];
    if (!spec) return bad(k, err, "sky: NULL text");
    if (strlen(spec) >= sizeof buf) return bad(k, err, "sky: the text is too long");
    snprintf(buf, sizeof buf, "%s", spec);
    /* split at every ':', empty fields kept, so "map::2" is an error, not a shift */
    char* part[5] = {0};
    int n = 0;
    for (char *p = buf, *c;; p = c + 1) {
        if (n == 5) return bad(k, err, "sky: too many ':' fields");
        part[n++] = p;
        if (!(c = strchr(p, ':'))) break;
        *c = 0;
    }
    if (!strcmp(part[0], "default")) {
        if (n != 1) return bad(k, err, "sky: 'default' takes no fields");
        return VX_OK;
    }
    if (!strcmp(part[0], "gradient")) {
        k->type = VX_SKY_GRADIENT;
        if (n != 4 || !vx_parse_doubles(part[1], k->color, 3) || !vx_parse_doubles(part[2], k->horizon, 3) ||
            !vx_parse_doubles(part[3], k->ground, 3))
            return bad(k, err, "sky: expected gradient:ZR,ZG,ZB:HR,HG,HB:GR,GG,GB (zenith, horizon, ground: three numbers each)");
    } else if (!strcmp(part[0], "map")) {
        k->type = VX_SKY_ENVMAP;
        k->intensity = 1;
        double rot = 0;
        if (n < 2 || n > 4 || !part[1][0] || (n > 2 && !vx_parse_doubles(part[2], &k->intensity, 1)) ||
            (n > 3 && !vx_parse_doubles(part[3], &rot, 1)))
            return bad(k, err, "sky: expected map:FILE[:INTENSITY[:ROTATION]] (a file name, then numbers)");
        if (strlen(part[1]) > VX_SKY_PATH_MAX) return bad(k, err, "sky: the map's path is over 255 bytes");
        snprintf(k->path, sizeof k->path, "%s", part[1]);
        k->rotation = rot * deg;
    } else {
        k->type = VX_SKY_CONSTANT;
        if (n != 1 || !vx_parse_doubles(part[0], k->color, 3))
            return bad(k, err, "sky: expected R,G,B, gradient:..., map:... or default");
    }
    vx_result r = vx_sky_validate(k, err);
    if (r) memset(k, 0, sizeof *k);
    return r;
}

/* The shortest %g text of v that strtod reads back to v (17 digits always
 * do); where that has an exponent, the plain decimal when it is at most two
 * characters longer ("1000", "0.00001", not "1e+03", "1e-05"). */
static void shortest(double v, char t[32]) {
    for (int p = 1; p <= 17; p++) {
        snprintf(t, 32, "%.*g", p, v);
        if (strtod(t, NULL) == v) break;
    }
    if (!strchr(t, 'e') || !(fabs(v) < 1e9)) return;
    char f[48];
    for (int d = 0; d <= 12; d++) {
        snprintf(f, sizeof f, "%.*f", d, v);
        if (strtod(f, NULL) != v) continue;
        size_t fl = strlen(f);
        if (fl <= strlen(t) + 2 && fl < 32) memcpy(t, f, fl + 1);
        return;
    }
}

/* The degrees whose product with deg is rad, written shortest: the quotient
 * and its neighbours a few ulps away, the shortest text of those that give
 * rad back; the quotient when none does. */
static void degrees(double rad, char t[32]) {
    double q = rad / deg, c = q;
    for (int i = 0; i < 4; i++) c = nextafter(c, -INFINITY);
    shortest(q, t);
    bool found = false;
    for (int i = 0; i < 9; i++, c = nextafter(c, INFINITY)) {
        if (c * deg != rad || signbit(c) != signbit(rad)) continue;
        char u[32];
        shortest(c, u);
        if (!found || strlen(u) < strlen(t)) snprintf(t, 32, "%s", u);
        found = true;
    }
}

vx_result vx_sky_format(const vx_sky* k, char* out, size_t n, vx_error* err) {
    if (!out || !n) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "sky: no room for the text");
    out[0] = 0;
    vx_result r = vx_sky_validate(k, err);
    if (r) return r;
    if (k->type == VX_SKY_ENVMAP && strchr(k->path, ':'))
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "sky: the map's path '%.200s' holds ':', which the text form cannot say",
                       k->path);
    char t[VX_SKY_SPEC_MAX], a[32], b[32];
    int w = 0;
    const double* c[3] = {k->color, k->horizon, k->ground};
    switch (k->type) {
        case VX_SKY_CONSTANT:
        case VX_SKY_GRADIENT:
            w = snprintf(t, sizeof t, "%s", k->type == VX_SKY_GRADIENT ? "gradient" : "");
            for (int v = 0; v < (k->type == VX_SKY_GRADIENT ? 3 : 1); v++)
                for (int i = 0; i < 3 && w >= 0 && (size_t)w < sizeof t; i++) {
                    shortest(c[v][i], a);
                    const char* sep = i ? "," : k->type == VX_SKY_GRADIENT ? ":" : "";
                    int m = snprintf(t + w, sizeof t - (size_t)w, "%s%s", sep, a);
                    w = m < 0 ? m : w + m;
                }
            break;
        case VX_SKY_ENVMAP: {
            /* intensity 1 and rotation +0 are what the parse gives when left out */
            bool rot = k->rotation != 0 || signbit(k->rotation), in = rot || k->intensity != 1;
            shortest(k->intensity, a);
            degrees(k->rotation, b);
            w = snprintf(t, sizeof t, "map:%s%s%s%s%s", k->path, in ? ":" : "", in ? a : "", rot ? ":" : "", rot ? b : "");
            break;
        }
        default: w = snprintf(t, sizeof t, "default"); break;
    }
    if (w < 0 || (size_t)w >= sizeof t || (size_t)w >= n)
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "sky: the text needs %d bytes, %zu given", w + 1, n);
    memcpy(out, t, (size_t)w + 1);
    return VX_OK;
}
