// render/shaders/passes_common.glsl - the bindings and helpers shared by the
// pass shaders of render/pipeline.c (gbuffer, direct, ao, resolve, post).
// Included after trace_common.glsl (bindings 0-6: frame and scene). Layouts
// must match render/pipeline.c.
//
// G-buffer, one entry per pixel:
//   gb0: hit point xyz (world, relative to the frame reference) and depth as
//        float bits; depth is +inf on a miss
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
layout(std430, binding = 14) readonly buffer Emit { float emit_attr[]; };
layout(std430, binding = 15) buffer Out2 { vec4 out2_img[]; };
// Lights (render/pipeline.h vx_light), PC.u1.z of them:
//   a: xyz position (point, spot), w type (0 directional, 1 point, 2 spot)
//   b: xyz direction (directional: towards the light; spot: where it points), w range (0: none)
//   c: rgb colour times intensity (directional: irradiance; point, spot: intensity per sr)
//   d: x cone scale, y cone offset (spot: clamp(cos * x + y)^2, glTF's smooth edge)
struct Light { vec4 a, b, c, d; };
layout(std430, binding = 16) readonly buffer Lights { Light lights[]; };

layout(push_constant) uniform Push {
    vec4 f0;  // x: lens radius, y: focus distance, z: ao radius, w: 2^exposure
    vec4 f1;  // xyz: sun irradiance (radiometric light), w: aa edge threshold
    vec4 f2;  // xyz: sky radiance (radiometric light), w: 0
    uvec4 u0; // x: sample, y: samples, z: ao rays, w: seed
    uvec4 u1; // x: first ao ray of this dispatch, y: ao rays in this dispatch, z: lights
} PC;

const float PI = 3.14159265358979;

// The world normal of a G-buffer entry: instance row of the entry axis times
// the sign, normalised (as trace.comp computes it).
vec3 gb_normal(uvec4 g1) {
    Inst I = insts[g1.y];
    uint axis = g1.z & 3u;
    float nsign = (g1.z & 4u) != 0u ? -1.0 : 1.0;
    vec4 row = axis == 0u ? I.r0 : (axis == 1u ? I.r1 : I.r2);
    return normalize(row.xyz * nsign);
}

// A point just off the surface for secondary rays (as trace.comp's shadow ray).
vec3 gb_offset_point(vec3 p, vec3 nw, uint slot) {
    float cell = insts[slot].cell;
    return p + nw * (cell * 1e-3 + 4e-6 * max(max(abs(p.x), abs(p.y)), abs(p.z)));
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

// Cosine-weighted direction around unit n (Duff et al.'s orthonormal basis).
vec3 pass_cosine_dir(vec3 n, float u1, float u2) {
    float sg = n.z < 0.0 ? -1.0 : 1.0;
    float a = -1.0 / (sg + n.z), b = n.x * n.y * a;
    vec3 t = vec3(1.0 + sg * n.x * n.x * a, sg * b, -sg * n.x);
    vec3 bt = vec3(b, sg + n.y * n.y * a, -n.y);
    float r = sqrt(u1), phi = 2.0 * PI * u2;
    return normalize(r * cos(phi) * t + r * sin(phi) * bt + sqrt(max(0.0, 1.0 - u1)) * n);
}

bool pass_pixel(out uvec2 px, out uint i) {
    px = gl_GlobalInvocationID.xy;
    i = px.y * F.dims.x + px.x;
    return px.x < F.dims.x && px.y < F.dims.y;
}
