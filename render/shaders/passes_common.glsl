// render/shaders/passes_common.glsl - the bindings and helpers shared by the
// pass shaders of render/pipeline.c (gbuffer, direct, ao, resolve, post).
// Included after trace_common.glsl (bindings 0-6: frame and scene). Layouts
// must match render/pipeline.c.
//
// G-buffer, one entry per pixel:
//   gb0: hit point xyz (world, relative to the frame reference) and depth as
//        float bits; depth is +inf on a miss, and xyz then the ray's direction
//   gb1: x attribute colour RGBA8, y instance slot (NO_HIT on a miss),
//        z entry face axis | 4 if the model-space normal is negative,
//        w attribute record (NO_HIT without one): the material id
//   gb2: two entries per pixel, sample 0 only, when ids are wanted: the
//        layout of trace.comp's hits (instance id, cell; depth, iterations)
layout(std430, binding = 7) buffer GB0 { uvec4 gb0[]; };
layout(std430, binding = 8) buffer GB1 { uvec4 gb1[]; };
layout(std430, binding = 9) buffer GB2 { uvec4 gb2[]; };
layout(std430, binding = 10) buffer Direct { vec4 direct_img[]; };
layout(std430, binding = 11) buffer Ao { float ao_img[]; };
layout(std430, binding = 12) buffer Gi { vec4 gi_img[]; };
layout(std430, binding = 13) buffer Acc { vec4 acc_img[]; };
// per attribute record the emission's terms (svo/svo.h vx_material_emitted_terms): radiance = colour * w + xyz
layout(std430, binding = 14) readonly buffer Emit { vec4 emit_attr[]; };
layout(std430, binding = 15) buffer Out2 { vec4 out2_img[]; };
// Lights (svo/svo.h vx_light), PC.u1.z of them, the PC.u1.w directional
// ones first (render/pipeline.c packs them):
//   a: xyz position (centre), w type (0 directional, 1 point, 2 spot, 3 sphere, 4 rect)
//   b: xyz direction (directional: towards the light; spot: where it points;
//      rect: its emitting normal), w window radius R (0: none): the light is
//      scaled by (1 - (d/R)^4)^2 and is 0 from R on; glTF's range, or the
//      cut-off radius of pipeline.h (what the culling bounds)
//   c: rgb colour times intensity (directional: irradiance; point, spot:
//      intensity per sr; sphere, rect: radiance), w source size: directional
//      1 - cos(half the angular diameter); point, spot, sphere: radius
//   d: x cone scale, y cone offset (spot: clamp(cos * x + y)^2, glTF's smooth edge)
//   e: xyz rect: half the first edge (tangent * size[0] / 2)
//   f: xyz rect: half the second edge (normal x tangent * size[1] / 2)
struct Light { vec4 a, b, c, d, e, f; };
layout(std430, binding = 16) readonly buffer Lights { Light lights[]; };
// Light culling (cull.comp): cl[0] entries written, cl[1] entries needed when
// the list overflowed (0 otherwise), then per cluster its count (cl[4 + c])
// and the offset of its list in lidx (cl[4 + C + c]), then (tiled) the view
// depth range of each tile as float bits (cl[4 + 2C + 2t], cl[4 + 2C + 2t + 1]).
layout(std430, binding = 17) buffer Cull { uint cl[]; };
layout(std430, binding = 18) buffer LightIdx { uint lidx[]; };
// The sky by direction (render/pipeline.c, when PC.f2.w > 0): sky.glsl's four
// vec4 (floats 0-15), then E(n) / pi, the sky's light on a white diffuse
// surface of normal n, at SKY_IRR_W x SKY_IRR_H normals (azimuth steps from
// +x towards +y, polar angles from +z to -z, poles included; rgb each), then
// the environment map's texels.
layout(std430, binding = 19) readonly buffer Sky { float skyf[]; };
const uint SKY_IRR_W = 32u, SKY_IRR_H = 17u, SKY_ENV_AT = 16u + 3u * SKY_IRR_W * SKY_IRR_H;

layout(push_constant) uniform Push {
    vec4 f0;  // x: lens radius, y: focus distance, z: ao radius, w: 2^exposure
    vec4 f1;  // xyz: sun irradiance (radiometric light), w: aa edge threshold
    vec4 f2;  // xyz: sky radiance (radiometric light), w: 1: the sky by direction (binding 19) instead
    uvec4 u0; // x: sample, y: samples, z: ao rays, w: seed
    uvec4 u1; // x: first ao ray of this dispatch, y: ao rays in this dispatch, z: lights, w: directional lights
    vec4 f3;  // light grid: x depth origin zb, y near, z (slices - 1) / ln(far / near), w list capacity (uint bits)
    uvec4 u2; // light grid: x tiles across, y tiles down, z depth slices, w tile size in pixels
#ifdef DISPLAY_OUT
    uvec4 u3; // the display image the last pass writes (display_out.glsl)
#endif
} PC;

const float PI = 3.14159265358979;

#define SKY_TEXEL(i) skyf[SKY_ENV_AT + (i)]
#include "sky.glsl"

vec4 sky_param(uint k) { return vec4(skyf[4u * k], skyf[4u * k + 1u], skyf[4u * k + 2u], skyf[4u * k + 3u]); }

// The frame's sky radiance towards unit d: uniform, or by direction.
vec3 frame_sky(vec3 d) {
    if (PC.f2.w <= 0.0) return PC.f2.xyz;
    return sky_eval(sky_param(0u), sky_param(1u), sky_param(2u), sky_param(3u), d);
}

// E(n) / pi of the frame's sky at unit normal n (the table, bilinear; a
// uniform sky: its radiance).
vec3 frame_sky_irradiance(vec3 n) {
    if (PC.f2.w <= 0.0) return PC.f2.xyz;
    float u = (n.x == 0.0 && n.y == 0.0) ? 0.0 : atan(n.y, n.x) / (2.0 * PI);
    u = (u - floor(u)) * float(SKY_IRR_W);
    float v = acos(clamp(n.z, -1.0, 1.0)) / PI * float(SKY_IRR_H - 1u);
    uint x0 = min(uint(u), SKY_IRR_W - 1u), x1 = (x0 + 1u) % SKY_IRR_W;
    uint y0 = min(uint(v), SKY_IRR_H - 2u), y1 = y0 + 1u;
    float ax = clamp(u - float(x0), 0.0, 1.0), ay = clamp(v - float(y0), 0.0, 1.0);
    vec3 e[4];
    uint at[4] = uint[4](y0 * SKY_IRR_W + x0, y0 * SKY_IRR_W + x1, y1 * SKY_IRR_W + x0, y1 * SKY_IRR_W + x1);
    for (uint k = 0u; k < 4u; k++) e[k] = vec3(skyf[16u + 3u * at[k]], skyf[17u + 3u * at[k]], skyf[18u + 3u * at[k]]);
    return mix(mix(e[0], e[1], ax), mix(e[2], e[3], ax), ay);
}

// The world normal of a G-buffer entry: instance row of the entry axis times
// the sign, normalised (as trace.comp computes it).
vec3 gb_normal(uvec4 g1) {
    Inst I = insts[g1.y];
    uint axis = g1.z & 3u;
    float nsign = (g1.z & 4u) != 0u ? -1.0 : 1.0;
    vec4 row = axis == 0u ? I.r0 : (axis == 1u ? I.r1 : I.r2);
    return normalize(row.xyz * nsign);
}

// A point just off the surface for secondary rays (as trace.comp's shadow ray). In the WALK_PRECISE kernels
// (cmake/shaders.cmake) not contracted either: the shadow and AO rays start there in the separate passes and
// in the merged kernel, which the NVIDIA compiler contracts each on its own.
vec3 gb_offset_point(vec3 p, vec3 nw, uint slot) {
    float cell = insts[slot].cell;
#ifdef WALK_PRECISE
    precise vec3 q = p + nw * (cell * 1e-3 + 4e-6 * max(max(abs(p.x), abs(p.y)), abs(p.z)));
    return q;
#else
    return p + nw * (cell * 1e-3 + 4e-6 * max(max(abs(p.x), abs(p.y)), abs(p.z)));
#endif
}

// Counter-based random numbers keyed by (pixel, sample, stream).
uvec4 pass_pcg4d(uvec4 v) {
    v = v * 1664525u + 1013904223u;
    v.x += v.y * v.w; v.y += v.z * v.x; v.z += v.x * v.y; v.w += v.y * v.z;
    v ^= v >> 16u;
    v.x += v.y * v.w; v.y += v.z * v.x; v.z += v.x * v.y; v.w += v.y * v.z;
    return v;
}
float pass_rnd(uvec2 px, uint stream, uint k) {
    uvec4 h = pass_pcg4d(uvec4(px.x, px.y, PC.u0.x * 977u + stream, PC.u0.w ^ (k * 0x9E3779B9u)));
    return float(h.x >> 8) * (1.0 / 16777216.0);
}

#include "sampling.glsl"

// ---- the light grid (render/pipeline.c, cull.comp) ------------------------------
// Tiles of PC.u2.w pixels (PC.u2.x across, PC.u2.y down) times PC.u2.z
// depth slices; slice 0 ends at the view depth near (PC.f3.y, measured from
// the depth origin zb = PC.f3.x), slice k >= 1 spans near * e^((k-1)/s) to
// near * e^(k/s) with s = PC.f3.z, exponential in depth. The outer tiles
// and the first and last slices reach to infinity: every point has a cell.

// View coordinates of a point (relative to the frame reference): along the
// image's right and up (unit) and the view depth (from the eye plane).
vec3 grid_view(vec3 p) {
    return vec3(dot(p, normalize(F.rx.xyz)), dot(p, normalize(F.uy.xyz)), dot(p, F.fwd.xyz) + F.fwd.w);
}

// The screen coordinate (u or v in [-1, 1] on the image) of a view point.
float grid_screen(vec3 vw, bool across) {
    float s = across ? length(F.rx.xyz) : length(F.uy.xyz);
    float c = across ? vw.x : vw.y;
    return F.rx.w != 0.0 ? c / s : c / (max(vw.z, 1e-30) * s);
}

// The tile column (across) or row of a screen coordinate, clamped to the grid.
uint grid_tile_of(float uv, bool across) {
    float n = across ? float(PC.u2.x) : float(PC.u2.y);
    float px = across ? (uv + 1.0) * 0.5 * float(F.dims.x) : (1.0 - uv) * 0.5 * float(F.dims.y);
    return uint(clamp(floor(px / float(PC.u2.w)), 0.0, n - 1.0));
}
uint grid_tile(vec3 vw, bool across) { return grid_tile_of(grid_screen(vw, across), across); }

// The depth slice of s = view depth - zb.
uint grid_slice(float s) {
    if (!(s > PC.f3.y)) return 0u;
    return uint(clamp(1.0 + floor(log(s / PC.f3.y) * PC.f3.z), 1.0, float(PC.u2.z - 1u)));
}

bool pass_pixel(out uvec2 px, out uint i) {
    px = gl_GlobalInvocationID.xy;
    i = px.y * F.dims.x + px.x;
    return px.x < F.dims.x && px.y < F.dims.y;
}
