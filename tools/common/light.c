/* tools/common/light.c - the --light syntax and light / sky descriptions. */
#include "tools/common/light.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "tools/common/tool.h"

static const double deg = 3.14159265358979323846 / 180.0;

const char vx_tool_light_syntax[] =
    "                       point:X,Y,Z:R,G,B[:RANGE[:RADIUS]]\n"
    "                       spot:X,Y,Z:DX,DY,DZ:R,G,B:INNER,OUTER[:RANGE[:RADIUS]]  (cone angles in degrees)\n"
    "                       sun:DX,DY,DZ:R,G,B[:ANGULAR_DIAMETER]  (towards the sun; degrees, 0.53 = the sun)\n"
    "                       sphere:X,Y,Z:R,G,B:RADIUS  (R,G,B: radiance of the surface)\n"
    "                       rect:X,Y,Z:NX,NY,NZ:TX,TY,TZ:R,G,B:W,H  (emits along N; W along T)\n"
    "                       R,G,B: intensity per sr for point and spot, irradiance for sun;\n"
    "                       positions in world units, RANGE 0 = none, RADIUS 0 = a point\n";

static bool fail(char* why, size_t n, const char* msg) {
    if (why && n) snprintf(why, n, "%s", msg);
    return false;
}

const char vx_tool_sky_syntax[] =
    "                       R,G,B  (uniform radiance)\n"
    "                       gradient:ZR,ZG,ZB:HR,HG,HB:GR,GG,GB  (zenith, horizon, ground: linear from the\n"
    "                       horizon to the zenith in the direction's z, the ground below)\n"
    "                       map:FILE[:INTENSITY[:ROTATION]]  (an HDR environment map read through\n"
    "                       OpenImageIO: equirectangular, top row +z; ROTATION degrees about +z)\n";

bool vx_tool_parse_sky(const char* spec, bool allow_default, vx_sky* k, char* why, size_t wn) {
    /* the syntax is the library's (svo.h vx_sky_parse), shared with the
     * Python module and svo_view's `sky` command */
    vx_error err = {0};
    if (vx_sky_parse(spec, k, &err)) return fail(why, wn, err.msg);
    /* nothing to store or replace: the option is left out for the default */
    if (k->type == VX_SKY_DEFAULT && !allow_default)
        return fail(why, wn, "'default' is the renderer's own sky: leave --sky out");
    return true;
}

bool vx_tool_parse_light(const char* spec, vx_light* l, char* why, size_t wn) {
    char buf[512];
    memset(l, 0, sizeof *l);
    if (!spec || strlen(spec) >= sizeof buf) return fail(why, wn, "too long");
    snprintf(buf, sizeof buf, "%s", spec);
    char* part[8] = {0};
    int n = 0;
    /* strsep-like split that keeps empty fields, so "point::1,1,1" is an error, not a shift */
    for (char *p = buf, *c;; p = c + 1) {
        if (n == 8) return fail(why, wn, "too many ':' fields");
        part[n++] = p;
        if (!(c = strchr(p, ':'))) break;
        *c = 0;
    }
    l->intensity = 1;
    const char* t = part[0];
    double ang[2], ad = 0;
    if (!strcmp(t, "point")) {
        l->type = VX_LIGHT_POINT;
        if (n < 3 || n > 5) return fail(why, wn, "point:X,Y,Z:R,G,B[:RANGE[:RADIUS]]");
        if (!vx_tool_parse_vec(part[1], l->position, 3) || !vx_tool_parse_vec(part[2], l->color, 3) ||
            (n > 3 && !vx_tool_parse_vec(part[3], &l->range, 1)) || (n > 4 && !vx_tool_parse_vec(part[4], &l->radius, 1)))
            return fail(why, wn, "point:X,Y,Z:R,G,B[:RANGE[:RADIUS]]: a field is not numbers");
        return true;
    }
    if (!strcmp(t, "spot")) {
        l->type = VX_LIGHT_SPOT;
        if (n < 5 || n > 7) return fail(why, wn, "spot:X,Y,Z:DX,DY,DZ:R,G,B:INNER,OUTER[:RANGE[:RADIUS]]");
        if (!vx_tool_parse_vec(part[1], l->position, 3) || !vx_tool_parse_vec(part[2], l->direction, 3) ||
            !vx_tool_parse_vec(part[3], l->color, 3) || !vx_tool_parse_vec(part[4], ang, 2) ||
            (n > 5 && !vx_tool_parse_vec(part[5], &l->range, 1)) || (n > 6 && !vx_tool_parse_vec(part[6], &l->radius, 1)))
            return fail(why, wn, "spot:X,Y,Z:DX,DY,DZ:R,G,B:INNER,OUTER[:RANGE[:RADIUS]]: a field is not numbers");
        l->inner_cone = ang[0] * deg, l->outer_cone = ang[1] * deg;
        return true;
    }
    if (!strcmp(t, "sun")) {
        l->type = VX_LIGHT_DIRECTIONAL;
        if (n < 3 || n > 4) return fail(why, wn, "sun:DX,DY,DZ:R,G,B[:ANGULAR_DIAMETER]");
        if (!vx_tool_parse_vec(part[1], l->direction, 3) || !vx_tool_parse_vec(part[2], l->color, 3) ||
            (n > 3 && !vx_tool_parse_vec(part[3], &ad, 1)))
            return fail(why, wn, "sun:DX,DY,DZ:R,G,B[:ANGULAR_DIAMETER]: a field is not numbers");
        l->angular_diameter = ad * deg;
        return true;
    }
    if (!strcmp(t, "sphere")) {
        l->type = VX_LIGHT_SPHERE;
        if (n != 4 || !vx_tool_parse_vec(part[1], l->position, 3) || !vx_tool_parse_vec(part[2], l->color, 3) ||
            !vx_tool_parse_vec(part[3], &l->radius, 1))
            return fail(why, wn, "sphere:X,Y,Z:R,G,B:RADIUS");
        return true;
    }
    if (!strcmp(t, "rect")) {
        l->type = VX_LIGHT_RECT;
        if (n != 6 || !vx_tool_parse_vec(part[1], l->position, 3) || !vx_tool_parse_vec(part[2], l->direction, 3) ||
            !vx_tool_parse_vec(part[3], l->tangent, 3) || !vx_tool_parse_vec(part[4], l->color, 3) ||
            !vx_tool_parse_vec(part[5], l->size, 2))
            return fail(why, wn, "rect:X,Y,Z:NX,NY,NZ:TX,TY,TZ:R,G,B:W,H");
        return true;
    }
    return fail(why, wn, "unknown light type (point, spot, sun, sphere, rect)");
}

void vx_tool_light_str(const vx_light* l, char* b, size_t n) {
    static const char* names[VX_LIGHT_TYPE_COUNT] = {"sun", "point", "spot", "sphere", "rect"};
    const char* name = (unsigned)l->type < VX_LIGHT_TYPE_COUNT ? names[l->type] : "?";
    const double *p = l->position, *d = l->direction, *c = l->color;
    int k = 0;
    if (l->type == VX_LIGHT_DIRECTIONAL)
        k = snprintf(b, n, "%s towards (%g %g %g), colour %g %g %g x %g, angular diameter %g deg", name, d[0], d[1], d[2], c[0],
                     c[1], c[2], l->intensity, l->angular_diameter / deg);
    else
        k = snprintf(b, n, "%s at (%g %g %g), colour %g %g %g x %g", name, p[0], p[1], p[2], c[0], c[1], c[2], l->intensity);
    if (k < 0 || (size_t)k >= n) return;
    b += k, n -= (size_t)k;
    if (l->type == VX_LIGHT_SPOT)
        k = snprintf(b, n, ", towards (%g %g %g), cone %g..%g deg", d[0], d[1], d[2], l->inner_cone / deg, l->outer_cone / deg);
    else if (l->type == VX_LIGHT_RECT)
        k = snprintf(b, n, ", normal (%g %g %g), tangent (%g %g %g), size %g x %g", d[0], d[1], d[2], l->tangent[0], l->tangent[1],
                     l->tangent[2], l->size[0], l->size[1]);
    else
        k = 0;
    if (k < 0 || (size_t)k >= n) return;
    b += k, n -= (size_t)k;
    if (l->range > 0) {
        k = snprintf(b, n, ", range %g", l->range);
        if (k < 0 || (size_t)k >= n) return;
        b += k, n -= (size_t)k;
    }
    if (l->radius > 0) {
        k = snprintf(b, n, ", radius %g", l->radius);
        if (k < 0 || (size_t)k >= n) return;
        b += k, n -= (size_t)k;
    }
    if (l->flags & VX_LIGHT_FROM_VOXELS) snprintf(b, n, " (emissive voxels)");
}

void vx_tool_sky_str(const vx_sky* s, char* b, size_t n) {
    const double *c = s->color, *h = s->horizon, *g = s->ground;
    switch (s->type) {
    case VX_SKY_CONSTANT: snprintf(b, n, "constant %g %g %g", c[0], c[1], c[2]); break;
    case VX_SKY_GRADIENT:
        snprintf(b, n, "gradient zenith %g %g %g, horizon %g %g %g, ground %g %g %g", c[0], c[1], c[2], h[0], h[1], h[2], g[0],
                 g[1], g[2]);
        break;
    case VX_SKY_ENVMAP:
        snprintf(b, n, "environment map \"%s\" x %g, turned %g deg about +z", s->path, s->intensity, s->rotation / deg);
        break;
    default: snprintf(b, n, "default (the renderer's)"); break;
    }
}
