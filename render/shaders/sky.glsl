// render/shaders/sky.glsl - the sky's radiance by direction: the one GLSL
// definition of svo/svo_light.c vx_sky_radiance (in float), included by the
// path tracer (probes/shaders/probe.comp) and the pass pipeline
// (passes_common.glsl). The C side packs a sky with vx__sky_pack
// (render/pipeline.c) into four vec4:
//   zen: rgb the constant sky, or the gradient's zenith
//   hor: rgb the gradient's horizon, w the kind: 0 uniform (zen), 1 gradient, 2 map
//   gnd: rgb the gradient's ground, w the map's intensity
//   map: x rotation (radians about +z), y width, z height
// The includer defines SKY_TEXEL(i): float i of the environment map's
// texels (RGB per texel, row-major, row 0 at +z).

#ifndef PT_PREC
#define PT_PREC
#endif
PT_PREC vec3 sky_eval(vec4 zen, vec4 hor, vec4 gnd, vec4 map, vec3 d) {
    uint kind = uint(hor.w);
    if (kind == 1u) return d.z >= 0.0 ? mix(hor.xyz, zen.xyz, min(d.z, 1.0)) : gnd.xyz;
    if (kind != 2u) return zen.xyz;
    float phi = (d.x == 0.0 && d.y == 0.0) ? 0.0 : atan(d.y, d.x); // atan2(0, 0) = 0, as in C
    PT_PREC float u = (phi - map.x) / (2.0 * 3.14159265358979), v = acos(clamp(d.z, -1.0, 1.0)) / 3.14159265358979;
    u -= floor(u);
    uint w = uint(map.y), h = uint(map.z);
#ifdef PATH_PRECISE
    precise float xf = max(u, 0.0) * map.y, yf = max(v, 0.0) * map.z;
    uint x = min(uint(xf), w - 1u), y = min(uint(yf), h - 1u);
#else
    uint x = min(uint(max(u, 0.0) * map.y), w - 1u), y = min(uint(max(v, 0.0) * map.z), h - 1u);
#endif
    uint i = 3u * (y * w + x);
    return vec3(SKY_TEXEL(i), SKY_TEXEL(i + 1u), SKY_TEXEL(i + 2u)) * gnd.w;
}
