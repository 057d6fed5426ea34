// cones/shaders/cone_common.glsl - the radiance volume of voxel cone tracing
// (cones/cones.h): its bindings, quadrilinear reads and the cone march.
// Included after trace_common.glsl and passes_common.glsl (bindings 0-19, 19
// the sky by direction);
// layouts must match cones/cones.c.
//
// Volume: level l's voxel (x, y, z) holds ENTRIES entries (1 isotropic; 6
// anisotropic: what a viewer on the +x, -x, +y, -y, +z, -z side sees), each
// premultiplied radiance RGB and opacity A as four halfs: texel CP.atl[l] +
// (x, y, z) + (0, 0, e * CP.atlas.w) of the atlas (below). vol[] only takes
// a level's copy for vx_cone_gi_read_level (filter.comp STAGE 5), at
// ((z * dy + y) * dx + x) * ENTRIES + e.
layout(std430, binding = 20) buffer Vol { uvec2 vol[]; };
// Per listed voxel and side (6 per voxel, 5 vec4 each): the visible surface
// (voxelize.comp): 0 xyz mean hit point relative to the volume origin, w
// opacity from that side; 1 xyz normal, w share of the side's rays that see
// a lit surface (not an interior); 2 albedo; 3 emitted radiance; 4 gathered
// indirect radiance (bounces > 1).
layout(std430, binding = 21) buffer Rec { vec4 rec[]; };
layout(std430, binding = 22) readonly buffer ConeP {
    vec4 origin;     // xyz: the volume's world corner relative to the frame reference, w: level-0 voxel side
    uvec4 info;      // x: levels, y: entries per voxel, z: samples per face side, w: 0
    vec4 cone;       // x: tan(half angle), y: offset (voxels), z: step share of the diameter, w: AO distance (voxels; 0: all)
    uvec4 ctl;       // x: cones, y: output (1: AO), z: add the gathered light (inject), w: first entry of
                     // the environment BRDF table in cmat[] (SPEC)
    vec4 spec;       // x: the sun's 1 - cos(angular radius) (SHADOWS), y: the specular cone's tan(half
                     // angle) per GGX alpha, z: its largest tan(half angle), w: 0
    uvec4 dims[16];  // per level: xyz voxels, w: first voxel
    vec4 dirs[32];   // cone directions around +z (tangent space), w: weight
    vec4 atlas;      // xyz: 1 / the atlas's size (texels), w: its z stride per entry
    uvec4 atl[16];   // per level: its corner in the atlas (texels)
} CP;
// The atlas that holds the volume (cones/cones.c layout_volume): every
// level, each entry's copy stacked in z, with a zero voxel around each
// level; written and read texel by texel as an image (voxelize, inject,
// filter), sampled by the cones with the hardware's trilinear filter (zero
// outside). An image, not a buffer: a storage buffer's range stops at 4 GB
// (maxStorageBufferRange), and the anisotropic volume at res 512 is 9 GB.
layout(binding = 24) uniform sampler3D vol_tex;
layout(binding = 25, rgba16f) uniform image3D vol_img;
// list[0]: voxels listed, then their level-0 indices
layout(std430, binding = 23) buffer List { uint list[]; };

// bits 0-3: entries per voxel (1 isotropic, 6 anisotropic); the gi pass's
// features: bit 4 specular cones (some attribute record is metal), bit 5
// cone soft shadows (the gi image brings the direct light too)
layout(constant_id = 6) const uint CONE_SPEC = 1u;
const uint ENTRIES = CONE_SPEC & 15u;
const bool SPEC = (CONE_SPEC & 16u) != 0u, SHADOWS = (CONE_SPEC & 32u) != 0u;

ivec3 vol_texel(uint l, uvec3 c, uint e) { return ivec3(CP.atl[l].xyz + c) + ivec3(0, 0, int(e) * int(CP.atlas.w)); }
vec4 vol_get(uint l, uvec3 c, uint e) { return imageLoad(vol_img, vol_texel(l, c, e)); }
void vol_put(uint l, uvec3 c, uint e, vec4 v) { imageStore(vol_img, vol_texel(l, c, e), v); }

// A voxel's index in the whole pyramid (its occupancy bit, filter.comp).
uint vol_index(uint l, uvec3 c) {
    uvec4 d = CP.dims[l];
    return d.w + (c.z * d.y + c.y) * d.x + c.x;
}

// Trilinear read of level l at q (level-0 voxel units from the volume
// origin; voxel centres of level l at (i + 1/2) 2^l); outside is empty. One
// hardware-filtered fetch per entry read from the atlas: voxel i of level l
// is texel atl + i, so the point is texel coordinate atl + q / 2^l; it is
// clamped to half a voxel beyond the level, where the filter reads only the
// zero voxels around it (and the value outside is zero anyway), so a read
// never reaches another level. Anisotropic: the three sides facing the
// cone, weighted by d^2 (sum 1).
vec4 vol_trilinear(uint l, vec3 q, vec3 d) {
    vec3 g = clamp(q / exp2(float(l)), vec3(-0.5), vec3(CP.dims[l].xyz) + 0.5) + vec3(CP.atl[l].xyz);
    if (ENTRIES == 1u) return textureLod(vol_tex, g * CP.atlas.xyz, 0.0);
    vec3 w = d * d;
    float zs = CP.atlas.w;
    // a cone going +x sees the voxel's -x side (entry 1)
    vec4 sx = textureLod(vol_tex, (g + vec3(0.0, 0.0, zs * (d.x > 0.0 ? 1.0 : 0.0))) * CP.atlas.xyz, 0.0);
    vec4 sy = textureLod(vol_tex, (g + vec3(0.0, 0.0, zs * (d.y > 0.0 ? 3.0 : 2.0))) * CP.atlas.xyz, 0.0);
    vec4 sz = textureLod(vol_tex, (g + vec3(0.0, 0.0, zs * (d.z > 0.0 ? 5.0 : 4.0))) * CP.atlas.xyz, 0.0);
    return w.x * sx + w.y * sy + w.z * sz;
}

// Quadrilinear: trilinear in the two levels around lev, linear between.
vec4 vol_sample(float lev, vec3 q, vec3 d) {
    float top = float(CP.info.x - 1u);
    lev = clamp(lev, 0.0, top);
    uint l0 = uint(floor(lev));
    float f = lev - float(l0);
    vec4 a = vol_trilinear(l0, q, d);
    if (f <= 0.0 || l0 + 1u >= CP.info.x) return a;
    return mix(a, vol_trilinear(l0 + 1u, q, d), f);
}

// Marches one cone from q (level-0 voxel units) along unit d with half-angle
// tangent tanh: front-to-back compositing of the volume, the sky behind what
// is left. Returns the radiance arriving along the cone; occ receives the
// opacity met within the AO distance.
// Near the surface the cone is kept narrower than the sample's height above
// the surface's tangent plane (q0 = q - n * offset): a voxel of level l
// reaches 1.5 2^l from its centre in a trilinear read, and the two levels
// of a quadrilinear one are at most twice the diameter, so a diameter of at
// most a third of the height never reads the voxels that hold the surface
// itself (without it, grazing cones of a plane see the plane: 15% of an
// open sky lost isotropic, 60% anisotropic, whose filtered plane is opaque
// seen from above at every level).
vec3 cone_march(vec3 q, vec3 d, float tanh, float h0, float dn, vec3 sky, out float occ) {
    vec3 C = vec3(0.0);
    float A = 0.0;
    occ = 0.0;
    vec3 hi = vec3(CP.dims[0].xyz);
    float share = CP.cone.z, aod = CP.cone.w;
    float t = 0.5;
    bool blocked = false;
    // a step of `share` diameters: the diameter grows by a factor of at least
    // 1 + share min(2 tanh, cos / 3) a step, so the loop ends well within the
    // bound (a cone of 1 degree crosses 512 voxels in about 400 steps)
    for (uint it = 0u; it < 4096u; it++) {
        float dia = max(1.0, min(2.0 * t * tanh, (h0 + t * dn) / 3.0));
        vec3 p = q + d * t;
        if (any(lessThan(p, vec3(-0.5 * dia))) || any(greaterThan(p, hi + 0.5 * dia))) break;
        vec4 s = vol_sample(log2(dia), p, d);
        if (s.a > 1e-6) {
            // opacity of a step of share * dia through a voxel of side dia
            float a = 1.0 - pow(max(1.0 - min(s.a, 1.0), 0.0), share);
            C += (1.0 - A) * s.rgb * (a / s.a);
            if (aod <= 0.0 || t <= aod) occ += (1.0 - occ) * a;
            A += (1.0 - A) * a;
            if (A >= 0.995) {
                blocked = true;
                break;
            }
        }
        t += share * dia;
    }
    if (blocked) return C / A; // all of it hit: what was hit, without a sliver of sky
    return C + (1.0 - A) * sky;
}

// Diffuse light at a surface point q (level-0 voxel units, already off the
// surface) with unit normal n: sum over the cones of weight * radiance (the
// irradiance over pi); ao receives the weighted unoccluded share. rot turns
// the cone set around n (per sample). What a cone leaves unoccluded sees the
// uniform sky, or (PC.f2.w > 0) the sky by direction along the cone's axis
// (passes_common.glsl frame_sky: a point sample of the cone's solid angle).
vec3 cone_gather(vec3 q, vec3 n, float rot, vec3 sky, out float ao) {
    vec3 t, bt;
    basis(n, t, bt);
    float c = cos(rot), s = sin(rot);
    vec3 L = vec3(0.0);
    ao = 0.0;
    for (uint k = 0u; k < CP.ctl.x; k++) {
        vec4 dl = CP.dirs[k];
        vec2 xy = vec2(c * dl.x - s * dl.y, s * dl.x + c * dl.y);
        vec3 d = normalize(xy.x * t + xy.y * bt + dl.z * n);
        float occ;
        vec3 sk = PC.f2.w > 0.0 ? frame_sky(d) : sky;
        L += dl.w * cone_march(q, d, CP.cone.x, CP.cone.y, max(dot(d, n), 0.0), sk, occ);
        ao += dl.w * (1.0 - occ);
    }
    return L;
}

// ---- specular cones (SPEC) -------------------------------------------------------
// Per attribute record one vec4 (kind: 1 metal, roughness, metalness,
// specular weight; probes/shaders/path_common.glsl's bsdf_of), then the
// environment BRDF table from CP.ctl.w: ENV_N x ENV_N entries (A, B, 0, 0),
// x the cosine of the view angle, y the roughness, both at (i + 1/2) / ENV_N,
// such that the directional albedo of the path tracer's GGX lobe (Smith
// height-correlated masking, Schlick Fresnel) is f0 A + B (cones/cones.c
// env_table). The binding is passes_common.glsl's 15 (unused by the cone
// shaders otherwise).
#define cmat out2_img
const uint ENV_N = 32u;

vec2 env_brdf(float nv, float rough) {
    vec2 g = vec2(nv, rough) * float(ENV_N) - 0.5;
    vec2 f0 = clamp(floor(g), vec2(0.0), vec2(float(ENV_N) - 2.0));
    vec2 f = clamp(g - f0, vec2(0.0), vec2(1.0));
    uint b = CP.ctl.w + uint(f0.y) * ENV_N + uint(f0.x);
    vec2 a = mix(cmat[b].xy, cmat[b + 1u].xy, f.x), c = mix(cmat[b + ENV_N].xy, cmat[b + ENV_N + 1u].xy, f.x);
    return mix(a, c, f.y);
}

// Cone occlusion along unit d from q (as cone_march, no light): the
// transmittance (1 - composited opacity) within t_max level-0 voxels.
float cone_transmit(vec3 q, vec3 d, float tanh, float h0, float dn, float t_max) {
    float A = 0.0;
    vec3 hi = vec3(CP.dims[0].xyz);
    float share = CP.cone.z;
    float t = 0.5;
    for (uint it = 0u; it < 4096u && t < t_max; it++) {
        float dia = max(1.0, min(2.0 * t * tanh, (h0 + t * dn) / 3.0));
        vec3 p = q + d * t;
        if (any(lessThan(p, vec3(-0.5 * dia))) || any(greaterThan(p, hi + 0.5 * dia))) break;
        float a = vol_sample(log2(dia), p, d).a;
        if (a > 1e-6) {
            // the last step only as far as t_max
            float len = min(share * dia, t_max - t) / dia;
            A += (1.0 - A) * (1.0 - pow(max(1.0 - min(a, 1.0), 0.0), len));
            if (A >= 0.995) return 0.0;
        }
        t += share * dia;
    }
    return 1.0 - A;
}
