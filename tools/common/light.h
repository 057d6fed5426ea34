/* tools/common/light.h - lights on the command line: the --light syntax
 * (svo_render, svo_view) and one line per light or sky for printing
 * (svo_info, vox2svo). The lights themselves are svo/svo.h's vx_light. */
#ifndef VX_TOOL_LIGHT_H
#define VX_TOOL_LIGHT_H

#include <stdbool.h>
#include <stddef.h>

#include "svo/svo.h"

/* The --light syntax, for --help (one line per type, indented by 23). */
extern const char vx_tool_light_syntax[];

/* Parses one --light spec into *out (intensity 1, colour R,G,B; angles in
 * degrees on the command line, radians in vx_light). false with why filled
 * when malformed; the light is then also checked with vx_light_validate by
 * the caller. */
bool vx_tool_parse_light(const char* spec, vx_light* out, char* why, size_t why_size);

/* The --sky syntax, for --help (indented by 23). */
extern const char vx_tool_sky_syntax[];
/* Parses a --sky spec: R,G,B (constant), gradient:ZENITH:HORIZON:GROUND
 * (R,G,B each) or map:FILE[:INTENSITY[:ROTATION]] (degrees on the command
 * line, radians in vx_sky); svo/svo.h vx_sky_parse, which also checks it
 * with vx_sky_validate. "default" (the renderer's own sky) only where
 * allow_default (vox2svo: store none, dropping the input's); elsewhere the
 * option left out says it. false with why filled when malformed or invalid. */
bool vx_tool_parse_sky(const char* spec, bool allow_default, vx_sky* out, char* why, size_t why_size);

/* "point (1 2 3) colour 1 1 1 x 10, range 5" and the like. */
void vx_tool_light_str(const vx_light* l, char* buf, size_t n);
/* "gradient zenith ... horizon ... ground ..." / "environment map PATH x I" / "default". */
void vx_tool_sky_str(const vx_sky* s, char* buf, size_t n);

#endif
