// cones/shaders/cone_common.glsl - the radiance volume of voxel cone tracing
// (cones/cones.h): its bindings, quadrilinear reads and the cone march.
// Included after trace_common.glsl and passes_common.glsl (bindings 0-19, 19
// the sky by direction);
// layouts must match cones/cones.c.
//
// Volume: level l's voxel (x, y, z) holds ENTRIES entries (1 isotropic; 6
// anisotropic: what a viewer on the +x, -x, +y, -y, +z, -z side sees), each
// premultiplied radiance RGB and opacity A as four halfs, at
// vol[(CP.dims[l].w + (z * dy + y) * dx + x) * ENTRIES + e].
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
    uvec4 ctl;       // x: cones, y: output (1: AO), z: add the gathered light (inject), w: 0
    uvec4 dims[16];  // per level: xyz voxels, w: first voxel
    vec4 dirs[32];   // cone directions around +z (tangent space), w: weight
} CP;
// list[0]: voxels listed, then their level-0 indices
layout(std430, binding = 23) buffer List { uint list[]; };

layout(constant_id = 6) const uint ENTRIES = 1u; // 1 isotropic, 6 anisotropic

vec4 vol_load(uint idx) {
    uvec2 v = vol[idx];
    return vec4(unpackHalf2x16(v.x), unpackHalf2x16(v.y));
}
void vol_store(uint idx, vec4 c) { vol[idx] = uvec2(packHalf2x16(c.xy), packHalf2x16(c.zw)); }

uint vol_index(uint l, uvec3 c) {
    uvec4 d = CP.dims[l];
    return d.w + (c.z * d.y + c.y) * d.x + c.x;
}

// The value a cone going along d reads from voxel c of level l: the entry
// itself, or the three sides facing the cone weighted by d^2 (sum 1).
vec4 vol_voxel(uint l, ivec3 c, vec3 d) {
    uvec3 n = CP.dims[l].xyz;
    if (any(lessThan(c, ivec3(0))) || any(greaterThanEqual(uvec3(c), n))) return vec4(0.0);
    uint i = vol_index(l, uvec3(c)) * ENTRIES;
    if (ENTRIES == 1u) return vol_load(i);
    vec3 w = d * d;
    // a cone going +x sees the voxel's -x side (entry 1)
    return w.x * vol_load(i + (d.x > 0.0 ? 1u : 0u)) + w.y * vol_load(i + (d.y > 0.0 ? 3u : 2u)) +
           w.z * vol_load(i + (d.z > 0.0 ? 5u : 4u));
}

// Trilinear read of level l at q (level-0 voxel units from the volume
// origin; voxel centres of level l at (i + 1/2) 2^l); outside is empty.
vec4 vol_trilinear(uint l, vec3 q, vec3 d) {
    vec3 g = q / exp2(float(l)) - 0.5;
    vec3 f0 = floor(g);
    vec3 f = g - f0;
    ivec3 b = ivec3(f0);
    vec4 s = vec4(0.0);
    for (int k = 0; k < 8; k++) {
        ivec3 o = ivec3(k & 1, (k >> 1) & 1, (k >> 2) & 1);
        vec3 w3 = mix(1.0 - f, f, vec3(o));
        float w = w3.x * w3.y * w3.z;
        if (w > 0.0) s += w * vol_voxel(l, b + o, d);
    }
    return s;
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
