// render/shaders/pass_bodies.glsl - the per-pixel work of the gbuffer,
// direct and resolve passes as functions, so that each pass's shader
// (gbuffer.comp, direct.comp, resolve.comp) and the merged frame.comp run
// the same code: merged, the values stay in registers instead of going
// through the G-buffer. Included after trace_common.glsl and
// passes_common.glsl; the including shader declares DOF, PHYS, FLAGS, SHOW.

// The G-buffer entry of pixel px for sample s (see passes_common.glsl).
void gbuffer_pixel(uvec2 px, uint s, out uvec4 g0, out uvec4 g1, out uvec4 ids0, out uvec4 ids1) {
    uint W = F.dims.x, H = F.dims.y;
    bool ortho = F.rx.w != 0.0;
    float t_start = F.fwd.w;
    vec2 off = vec2(0.0);
    if (s > 0u) off = fract(vec2(0.5) + float(s) * vec2(0.7548776662466927, 0.5698402909980532)) - 0.5;
    float u = ((float(px.x) + 0.5 + off.x) / float(W)) * 2.0 - 1.0;
    float v = 1.0 - ((float(px.y) + 0.5 + off.y) / float(H)) * 2.0;
    vec3 o, d;
    float t_off;
    if (ortho) {
        o = u * F.rx.xyz + v * F.uy.xyz;
        d = F.fwd.xyz;
        t_off = t_start;
    } else {
        vec3 du = F.fwd.xyz + u * F.rx.xyz + v * F.uy.xyz;
        float len = length(du);
        d = du / len;
        o = t_start * (u * F.rx.xyz + v * F.uy.xyz);
        t_off = t_start * len;
        if (DOF) {
            // eye at -t_start * fwd relative to the reference point
            vec3 eye = -t_start * F.fwd.xyz;
            vec3 focus_pt = eye + d * (PC.f0.y / dot(d, F.fwd.xyz));
            float r = PC.f0.x * sqrt(pass_rnd(px, 7u, 0u)), phi = 2.0 * PI * pass_rnd(px, 7u, 1u);
            vec3 lens = eye + r * cos(phi) * normalize(F.rx.xyz) + r * sin(phi) * normalize(F.uy.xyz);
            d = normalize(focus_pt - lens);
            float tp = t_start / dot(d, F.fwd.xyz); // to the reference plane
            o = lens + d * tp;
            t_off = tp;
        }
    }
    g_iter = 0u;
    Hit h;
    h.t = 3.0e38;
    h.inst = NO_HIT;
    h.color = 0xFFFFFFFFu;
    h.attr = NO_HIT;
    bool hit = trace_scene(o, d, 0.0, false, h);
    if (hit) {
        WPREC vec3 p = o + d * h.t; // (WALK_PRECISE kernels: as the walk, not contracted)
        float depth = float(t_off + h.t);
        g0 = uvec4(floatBitsToUint(p.x), floatBitsToUint(p.y), floatBitsToUint(p.z), floatBitsToUint(depth));
        uint face = uint(h.axis) | (h.nsign < 0.0 ? 4u : 0u);
        g1 = uvec4(h.color, h.inst, face, h.attr);
    } else {
        g0 = uvec4(floatBitsToUint(d.x), floatBitsToUint(d.y), floatBitsToUint(d.z), 0x7F800000u); // a miss: the ray's direction (the sky it sees)
        g1 = uvec4(0u, NO_HIT, 0u, NO_HIT);
    }
    ids0 = uvec4(hit ? insts[h.inst].id : NO_HIT, h.cell);
    ids1 = uvec4(floatBitsToUint(hit ? float(t_off + h.t) : 0.0), g_iter, 0u, 0u);
}

// ---- lights ---------------------------------------------------------------------
// LIGHTS (pipeline.c): bits 0-1 the culling (0 every light, 1 tiled, 2
// clustered), bits 2-7 how many lights per pixel get a shadow ray (the
// strongest by unshadowed irradiance; the rest are added unshadowed), bit 8
// emission records are bound (emit_attr: emissive surfaces are known).
layout(constant_id = 7) const uint LIGHTS = 0u;
const uint CULLING = LIGHTS & 3u, SHADOWED = (LIGHTS >> 2) & 63u;
const bool EMIT_KNOWN = (LIGHTS & 256u) != 0u;
// The radiance a surface of albedo alb emits by its record's terms k (svo/svo.h vx_material_emitted_terms):
// the albedo times the emission, or the material's own emission colour.
vec3 emitted(vec3 alb, vec4 k) { return alb * k.w + k.xyz; }
bool emits(vec4 k) { return k.w > 0.0 || k.x > 0.0 || k.y > 0.0 || k.z > 0.0; }

// ---- metal seen directly ----------------------------------------------------------
// METAL: some attribute record is metal (radiometric model only): LIGHTS bit 9
// in the direct pass, FLAGS bit 64 in resolve, both in the merged kernel. The
// includer defines MAT_BINDING (direct.comp, resolve.comp, frame.comp) for
// the records' materials (render/pipeline.c, bound only then): per record
// vec4(1 metal / 0 not, roughness, metalness, specular), then the GGX lobe's
// directional albedo table (MAT_ENV_N x MAT_ENV_N (A, B, 0, 0): cos of the
// view angle across, roughness down, texel centres at (i + 0.5) / N; the
// albedo is f0 A + B): the records are the first mats.length() - N^2.
// Without METAL no code below runs and the passes keep their SPIR-V path.
const bool METAL = (((LIGHTS >> 9) | (FLAGS >> 6)) & 1u) != 0u;
const uint MAT_ENV_N = 32u;
#ifdef MAT_BINDING
layout(std430, binding = MAT_BINDING) readonly buffer Mats { vec4 mats[]; };
#endif

// A metal pixel's BRDF (probes/pathtrace.c bsdf_of, bsdf_eval): a Lambert
// lobe kd / pi, kd = (1 - metalness)(1 - 0.08 specular) colour, plus GGX
// with alpha = max(rough^2, 1e-3), Smith height-correlated G2 and Schlick's
// Fresnel from f0 = mix(0.08 specular, colour, metalness). wo: unit,
// towards the eye.
struct Metal { vec3 kd, f0, wo; float a2, rough; };

// The eye's direction from a G-buffer point p (relative to the frame
// reference): the pinhole's (with dof the lens point is not kept).
vec3 view_to_eye(vec3 p) {
    if (F.rx.w != 0.0) return -F.fwd.xyz;
    return normalize(-(p + F.fwd.w * F.fwd.xyz)); // the eye at -t_start * fwd
}

// Whether the G-buffer entry's record is metal, and its lobe.
bool metal_of(uvec4 g0, uvec4 g1, out Metal M) {
    M.kd = vec3(0.0), M.f0 = vec3(0.0), M.wo = vec3(0.0, 0.0, 1.0), M.a2 = 1.0, M.rough = 1.0;
#ifdef MAT_BINDING
    if (g1.y == NO_HIT || g1.w >= uint(mats.length()) - MAT_ENV_N * MAT_ENV_N) return false; // (callers test METAL)
    vec4 m = mats[g1.w];
    if (m.x != 1.0) return false;
    vec3 alb = HAS_COLOR ? unpack_rgb(g1.x) : vec3(1.0);
    float f0d = 0.08 * m.w, alpha = max(m.y * m.y, 1e-3);
    M.kd = (1.0 - m.z) * (1.0 - f0d) * alb;
    M.f0 = (1.0 - m.z) * f0d + m.z * alb;
    M.a2 = alpha * alpha, M.rough = m.y;
    M.wo = view_to_eye(uintBitsToFloat(g0.xyz));
    return true;
#else
    return false;
#endif
}

float ggx_lambda(float a2, float z) {
    float z2 = z * z;
    if (z2 >= 1.0) return 0.0;
    return 0.5 * (-1.0 + sqrt(1.0 + a2 * (1.0 - z2) / z2));
}

// The specular lobe's directional albedo f0 A + B towards the eye (cos nv
// from the normal): the table after the records (render/pipeline.h
// vx_ggx_albedo_table), bilinear between its texel centres.
vec3 metal_albedo(Metal M, float nv) {
#ifdef MAT_BINDING
    const float N = float(MAT_ENV_N);
    uint base = uint(mats.length()) - MAT_ENV_N * MAT_ENV_N;
    vec2 g = vec2(nv, M.rough) * N - 0.5;
    vec2 c = clamp(floor(g), vec2(0.0), vec2(N - 2.0));
    vec2 f = clamp(g - c, vec2(0.0), vec2(1.0));
    uint b = base + uint(c.y) * MAT_ENV_N + uint(c.x);
    vec2 ab = mix(mix(mats[b].xy, mats[b + 1u].xy, f.x), mix(mats[b + MAT_ENV_N].xy, mats[b + MAT_ENV_N + 1u].xy, f.x), f.y);
    return M.f0 * ab.x + ab.y;
#else
    return vec3(0.0);
#endif
}

// f(wo, wi) of the lobe at unit normal n towards unit wi: what multiplies a
// light's irradiance (which holds n.wi) into the radiance it reflects to the
// eye. The specular part is 0 below either horizon; the Lambert part stays
// (the irradiance already is 0 there, or a source's clipped share).
vec3 metal_brdf(Metal M, vec3 n, vec3 wi) {
    vec3 f = M.kd / PI;
    float no = dot(n, M.wo), ni = dot(n, wi);
    if (no <= 0.0 || ni <= 0.0) return f;
    vec3 h = normalize(M.wo + wi);
    float z = dot(n, h), c = z * z * (M.a2 - 1.0) + 1.0;
    float d = M.a2 / (PI * c * c);
    float g2 = 1.0 / (1.0 + ggx_lambda(M.a2, no) + ggx_lambda(M.a2, ni));
    float s5 = pow(1.0 - max(dot(wi, h), 0.0), 5.0);
    return f + (M.f0 + (1.0 - M.f0) * s5) * (d * g2 / (4.0 * no * ni));
}

// ---- glass seen directly: constants --------------------------------------------
// GLASS: some attribute record is glass with transmission > 0 (radiometric
// model, the direct pass present): LIGHTS bit 10 in the direct pass, FLAGS
// bit 128 in resolve, both in the merged kernel; its record in the material
// table (MAT_BINDING) is vec4(2, roughness, ior, transmission). GLASS_SKY
// (LIGHTS bit 11): the frame has the sky term (resolve's HAS_SKY), which the
// direct pass then adds at the surface seen through the glass. Without
// GLASS no glass code runs (the SPIR-V path of a scene without glass).
// GLASS_GI (LIGHTS bit 12): the frame has a gi pass, which gives a glass
// pixel's glass lobe whole (what the glass reflects and what it transmits:
// the surface behind it with its direct light, emission and indirect light,
// by the method's own transport; the path tracer's paths go on through the
// glass as in the reference); the direct pass then gives only the glass's
// Lambert share (1 - transmission) and resolve adds the gi image as it is.
// Without a gi pass the direct pass gives the whole glass radiance.
const bool GLASS = (((LIGHTS >> 10) | (FLAGS >> 7)) & 1u) != 0u;
const bool GLASS_SKY = (LIGHTS & 2048u) != 0u;
const bool GLASS_GI = (LIGHTS & 4096u) != 0u;
// The limit on glass bodies a pixel's transmitted ray enters (the first
// included; the surface met after the last is shaded as opaque). The steps a
// walk takes in one body (with total internal reflections) before it is
// given up (no light): cell_leaf.glsl glass_walk_steps, the path tracer's.
const uint GLASS_BODIES = 4u;
#include "dielectric.glsl" // fresnel_dielectric, the path tracer's (probes/shaders/path_common.glsl)
#include "cell_leaf.glsl"  // model_cell_leaf, glass_walk_steps (the path tracer's)

// Whether attribute record attr is glass that transmits (the path tracer's
// is_glass), and its record vec4(2, roughness, ior, transmission).
bool glass_of(uint attr, out vec4 m) {
    m = vec4(0.0);
#ifdef MAT_BINDING
    if (attr == NO_HIT || attr >= uint(mats.length()) - MAT_ENV_N * MAT_ENV_N) return false; // (callers test GLASS)
    m = mats[attr];
    return m.x == 2.0 && m.w > 0.0;
#else
    return false;
#endif
}

// The light's window: (1 - (d/R)^4)^2 below R, 0 from R on; R = 0: none.
float light_window(float dist, float R) {
    if (R <= 0.0) return 1.0;
    float q = dist / R;
    q *= q;
    float w = clamp(1.0 - q * q, 0.0, 1.0);
    return w * w;
}

// Irradiance of a sphere of radius r at distance dist (centre direction at
// cos ct from the normal), per unit radiance: pi sin^2(s) ct while the sphere
// is above the horizon, and the exact integral of the horizon-clipped cap
// otherwise (Snyder 1996, "Area light sources for real-time graphics"; the
// test checks both against a quadrature); pi inside the sphere.
float sphere_irradiance(float ct, float dist, float r) {
    if (dist <= r) return PI;
    float s2 = (r / dist) * (r / dist);
    if (ct > 0.0 && ct * ct >= s2) return PI * s2 * ct;
    if (ct <= -sqrt(s2)) return 0.0;
    float st = sqrt(max(0.0, 1.0 - ct * ct));
    float x = sqrt(max(0.0, 1.0 / s2 - 1.0));
    float y = clamp(-x * ct / max(st, 1e-20), -1.0, 1.0);
    float q = st * sqrt(max(0.0, 1.0 - y * y));
    return max(0.0, (ct * acos(y) - x * q) * s2 + atan(q, x));
}

// The projected solid angle of a quad (corners q0..q3 relative to the
// shading point) above the plane of unit normal n: the quad clipped to
// n.w >= 0, then Lambert's polygon formula 1/2 sum gamma_i n.(w_i x w_j)/|..|
// with gamma_i the angle between consecutive corners (atan2, so that small
// angles keep their precision).
float quad_projected_angle(vec3 q0, vec3 q1, vec3 q2, vec3 q3, vec3 n) {
    vec3 q[4] = vec3[4](q0, q1, q2, q3);
    vec3 w[5];
    uint m = 0u;
    for (uint i = 0u; i < 4u; i++) {
        vec3 a = q[i], b = q[(i + 1u) & 3u];
        float da = dot(a, n), db = dot(b, n);
        if (da >= 0.0) w[m++] = a;
        if ((da >= 0.0) != (db >= 0.0) && m < 5u) w[m++] = a + (b - a) * (da / (da - db));
    }
    float sum = 0.0;
    for (uint i = 0u; i < m; i++) {
        vec3 a = normalize(w[i]), b = normalize(w[i + 1u == m ? 0u : i + 1u]);
        vec3 c = cross(a, b);
        float lc = length(c);
        float g = atan(lc, dot(a, b));
        sum += dot(n, c) * (lc > 1e-20 ? g / lc : 1.0);
    }
    return m >= 3u ? 0.5 * abs(sum) : 0.0;
}

// Light k at the shading point ps (normal nw): its unshadowed irradiance e
// and a shadow ray (direction sd, length st; st = 0: nothing to trace) to a
// point of its source (seeded per pixel, sample and light: soft shadows of
// area lights, point radii and the sun's disc converge over samples).
// Returns false when the light adds nothing. Point and spot: E = c n.l / d^2
// (d^2 kept above (cell/100)^2 so that a light on the surface stays finite)
// times the window and, for a spot, its cone factor; directional: c n.l.
// A sphere that stands for emissive voxels (L.d.z, VX_LIGHT_FROM_VOXELS)
// adds nothing to an emissive surface inside it: that surface is one of the
// voxels it stands for (or of the next cluster of the same lamp), which
// shows its own emission; lit by the sphere it would also count the light
// its neighbours send along the surface, which the path tracer (sampling
// the voxels themselves) finds to be none.
bool light_eval(uint k, vec3 ps, vec3 nw, float cell, bool emissive, uvec2 px, out vec3 e, out vec3 sd, out float st) {
    Light L = lights[k];
    uint type = uint(L.a.w);
    e = vec3(0.0), sd = nw, st = 0.0;
    if (type == 0u) {
        float ndl = dot(nw, L.b.xyz);
        if (ndl <= 0.0) return false;
        e = L.c.xyz * ndl;
        sd = L.c.w > 0.0 ? cone_dir(L.b.xyz, L.c.w, pass_rnd(px, 13u, 2u * k), pass_rnd(px, 13u, 2u * k + 1u))
                         : L.b.xyz;
        st = 3.0e38;
        return true;
    }
    vec3 v = L.a.xyz - ps;
    float d2 = dot(v, v), dist = sqrt(d2);
    float f = light_window(dist, L.b.w);
    if (f <= 0.0) return false;
    vec3 l = dist > 0.0 ? v / dist : nw;
    float r = L.c.w;
    if (emissive && L.d.z > 0.0 && dist <= r + 0.01 * cell) return false;
    if (type == 4u) {
        vec3 c = v, U = L.e.xyz, V = L.f.xyz;
        if (dot(-v, L.b.xyz) <= 0.0) return false; // behind the one-sided rectangle
        f *= quad_projected_angle(c - U - V, c + U - V, c + U + V, c - U + V, nw);
        vec3 q = c + (2.0 * pass_rnd(px, 13u, 2u * k) - 1.0) * U + (2.0 * pass_rnd(px, 13u, 2u * k + 1u) - 1.0) * V;
        float lq = length(q);
        sd = lq > 0.0 ? q / lq : nw, st = lq * 0.9999;
    } else {
        if (type == 3u) {
            f *= sphere_irradiance(dot(nw, l), dist, r);
        } else {
            float ndl = dot(nw, l);
            if (ndl <= 0.0) return false;
            f *= ndl / max(d2, 1e-4 * cell * cell);
            if (type == 2u) {
                float a = clamp(dot(-l, L.b.xyz) * L.d.x + L.d.y, 0.0, 1.0);
                f *= a * a;
            }
        }
        sd = l, st = dist * 0.9999;
        if (r > 0.0) { // a point of the source's sphere: a direction in the cone it subtends
            if (dist <= r) {
                st = 0.0; // inside the source: nothing in between
            } else {
                float s2 = (r / dist) * (r / dist);
                sd = cone_dir(l, s2 / (1.0 + sqrt(1.0 - s2)), pass_rnd(px, 13u, 2u * k),
                                   pass_rnd(px, 13u, 2u * k + 1u));
                float b = dot(sd, v), disc = b * b - (d2 - r * r);
                st = (b - sqrt(max(disc, 0.0))) * 0.9999;
            }
        }
    }
    if (!(f > 0.0)) return false;
    e = L.c.xyz * f;
    return true;
}

// The light grid cell of a point p (relative to the frame reference); the
// grid's outer tiles and slices reach to infinity, so every point has one.
uint grid_cell(vec3 p, uvec2 px) {
    vec3 vw = grid_view(p);
    uint tx = grid_tile(vw, true), ty = grid_tile(vw, false);
    uint k = CULLING == 2u ? grid_slice(vw.z - PC.f3.x) : 0u;
    return (k * PC.u2.y + ty) * PC.u2.x + tx;
}

// Irradiance from the frame's lights at a G-buffer entry: every light
// (brute force) or the lights of its grid cell, plus the directional ones;
// the SHADOWED strongest get a ray-traced shadow. A metal pixel (mt): each
// light's irradiance times the BRDF towards its shadow ray's point (a
// sampled point of an area source, converging over samples), the radiance
// it reflects to the eye; its strongest by that radiance get the shadows.
vec3 lights_pixel(uvec2 px, uvec4 g0, uvec4 g1, vec3 nw, bool mt, Metal M) {
    vec3 p = uintBitsToFloat(g0.xyz);
    vec3 ps = gb_offset_point(p, nw, g1.y);
    float cell = insts[g1.y].cell;
    bool emissive = EMIT_KNOWN && g1.w < uint(emit_attr.length()) && emits(emit_attr[g1.w]); // records past the table: none
    vec3 e = vec3(0.0);
    const uint K = SHADOWED > 0u ? SHADOWED : 1u;
    vec3 ke[K], kd[K];
    float kt[K], kw[K];
    uint kn = 0u;
    uint first = 0u, end = PC.u1.z, ndir = PC.u1.w;
    uint off = 0u;
    if (CULLING != 0u) {
        uint c = grid_cell(p, px), C = PC.u2.x * PC.u2.y * PC.u2.z;
        uint cap = floatBitsToUint(PC.f3.w);
        off = cl[4u + C + c];
        first = 0u;
        end = ndir + min(cl[4u + c], off < cap ? cap - off : 0u);
    }
    for (uint j = first; j < end; j++) {
        uint k = CULLING == 0u || j < ndir ? j : lidx[off + j - ndir];
        vec3 le, sd;
        float st;
        if (!light_eval(k, ps, nw, cell, emissive, px, le, sd, st)) continue;
        if (mt) le *= metal_brdf(M, nw, sd);
        if (SHADOWED == 0u || st <= 0.0) {
            e += le;
            continue;
        }
        float w = dot(le, vec3(0.2126, 0.7152, 0.0722));
        uint slot = kn;
        if (kn < SHADOWED) {
            kn++;
        } else {
            // the weakest of the shadowed: replaced when this light is stronger
            slot = 0u;
            for (uint i = 1u; i < SHADOWED; i++)
                if (kw[i] < kw[slot]) slot = i;
            if (w <= kw[slot]) {
                e += le;
                continue;
            }
            e += ke[slot];
        }
        ke[slot] = le, kd[slot] = sd, kt[slot] = st, kw[slot] = w;
    }
    for (uint i = 0u; i < kn; i++) {
        Hit sh;
        sh.t = kt[i];
        sh.inst = NO_HIT;
        if (!trace_scene(ps, kd[i], 0.0, true, sh)) e += ke[i];
    }
    return e;
}

// The sun's visibility (0 or 1) from a G-buffer entry of normal nw, ndl = max(n.l, 0): a shadow ray (or the
// sun's depth map) where ndl > 0 and there is a sun.
float sun_visibility(uvec4 g0, uvec4 g1, vec3 nw, float ndl) {
    float vis = 0.0;
    bool sun = !PHYS || PC.f1.x > 0.0 || PC.f1.y > 0.0 || PC.f1.z > 0.0; // no sun ray without a sun
    if (ndl > 0.0 && sun) {
        vec3 ps = gb_offset_point(uintBitsToFloat(g0.xyz), nw, g1.y);
        Hit sh;
        sh.t = 3.0e38;
        sh.inst = NO_HIT;
#ifdef SMAP_BINDING
        // the sun's depth map (smap_lookup.glsl; the frame block carries its frame): a tmax, or no walk.
        // The G-buffer keeps no hit cell, so the rule for a ray from the one cube that gave m1 is off
        if (SMAP) sh.t = smap_tmax(ps, F.light.xyz, F.grid_lo, F.dims2.x, F.dims2.y, NO_HIT, uvec3(0u), false);
        if (sh.t < 0.0) vis = sh.t == -2.0 ? 0.0 : 1.0;
        else
#endif
        vis = trace_scene(ps, F.light.xyz, 0.0, true, sh) ? 0.0 : 1.0;
    }
    return vis;
}

// The radiometric direct light at a G-buffer entry: the sun's irradiance *
// n.l * visibility plus the lights'; for a metal record (mt) each source's
// irradiance times the BRDF towards it (the radiance it reflects along M.wo).
vec3 direct_light(uvec2 px, uvec4 g0, uvec4 g1, vec3 nw, bool mt, Metal M) {
    float ndl = max(dot(nw, F.light.xyz), 0.0);
    vec3 e = PC.f1.xyz * ndl * sun_visibility(g0, g1, nw, ndl);
    if (mt) e *= metal_brdf(M, nw, F.light.xyz);
    if (PC.u1.z > 0u) e += lights_pixel(px, g0, g1, nw, mt, M);
    return e;
}

// ---- glass seen directly ------------------------------------------------------------
// The cell of instance slot inst that holds point q (relative to the frame reference).
uvec3 glass_cell(uint inst, vec3 q) {
    Inst I = insts[inst];
    vec3 m = vec3(dot(I.r0.xyz, q) + I.r0.w, dot(I.r1.xyz, q) + I.r1.w, dot(I.r2.xyz, q) + I.r2.w);
    return uvec3(max(floor(m), vec3(0.0)));
}

// The direction refracted into the side opposite unit wo (on the side of
// unit normal n), eta = n_other / n_this, below the critical angle (the path
// tracer's dielectric with the macro normal).
vec3 glass_refract(vec3 wo, vec3 n, float eta) {
    float c = dot(wo, n), e = 1.0 / eta, k2 = 1.0 - e * e * (1.0 - c * c);
    return normalize(-e * wo + (e * c - sqrt(max(0.0, k2))) * n);
}

// Inside a glass body at p (in instance slot inst) along unit d: box by box
// to the face where the glass ends (the path tracer's glass_walk, made
// deterministic): a box is the octree leaf that holds the current cell (a
// uniform glass block at once, cell_leaf.glsl; else the cell); across a
// face into a glass cell the walk goes on; at an outer face the ray
// refracts out with weight 1 - F (thr), or, past the critical angle,
// reflects and walks on. Exits are measured along the straight stretch from
// its start p (t: how far the walk is along it), so the exit from the glass
// does not depend on the boxes taken on the way (the compact layout walks
// cell by cell and gives the same bits). The share F reflected back inside
// below the critical angle comes back as a ray of its own (ro, rd: from just
// inside the exit face; rthr its weight, 0 where nothing reflects), which
// glass_lobe follows as it follows the first reflection. WALK_ABSORBED:
// glass_walk_steps steps. WALK_OUT: o and d the ray that left. WALK_STOP: an opaque voxel
// across a face of the glass (a glass block on a floor, a voxel set in
// glass; the path tracer's walk stops there too), or with several instances
// another instance's voxel inside the glass box: o the point on its face,
// s1 its G-buffer-like record (the voxel's colour and record, the instance
// and axis whose normal faces into the glass).
const uint WALK_ABSORBED = 0u, WALK_OUT = 1u, WALK_STOP = 2u;
uint glass_pass_walk(uint inst, vec3 p, float ior, inout vec3 d, inout vec3 thr, out vec3 o, out uvec4 s1, out vec3 ro,
                     out vec3 rd, out vec3 rthr) {
    ro = p, rd = d, rthr = vec3(0.0);
    uvec3 c = glass_cell(inst, p);
    uint lv;
    if (model_cell_leaf(insts[inst].model, c, lv) == NO_HIT) lv = 0u;
    o = p;
    float t = 0.0;
    uint limit = glass_walk_steps(insts[inst].model);
    for (uint step = 0u; step < limit; step++) {
        Inst I = insts[inst];
        // the leaf's box [lo, hi), within the model's cube
        vec3 lo = vec3(c & ~uvec3((1u << lv) - 1u));
        vec3 hi = min(lo + exp2(float(lv)), vec3(exp2(float(model_at(I.model).depth))));
        vec3 om = vec3(dot(I.r0.xyz, p) + I.r0.w, dot(I.r1.xyz, p) + I.r1.w, dot(I.r2.xyz, p) + I.r2.w);
        vec3 dm = vec3(dot(I.r0.xyz, d), dot(I.r1.xyz, d), dot(I.r2.xyz, d));
        float te = 3.0e38;
        int ax = -1;
        for (int a = 0; a < 3; a++) {
            if (dm[a] == 0.0) continue;
            float ta = ((dm[a] > 0.0 ? hi[a] : lo[a]) - om[a]) / dm[a];
            if (ta < te) {
                te = ta;
                ax = a;
            }
        }
        if (ax < 0) return WALK_ABSORBED;
        te = max(te, t);
        // another instance's voxel inside the box (a box of one cell: met at its faces, below)
        if (USE_BVH && lv > 0u && te > t) {
            Hit g;
            vec4 gm;
            if (other_instance_hit(inst, p + d * t, d, te - t, g) && !glass_of(g.attr, gm)) {
                o = p + d * (t + g.t);
                s1 = uvec4(g.color, g.inst, uint(g.axis) | (g.nsign < 0.0 ? 4u : 0u), g.attr);
                return WALK_STOP;
            }
        }
        vec4 row = ax == 0 ? I.r0 : (ax == 1 ? I.r1 : I.r2);
        vec3 nf = normalize(row.xyz) * (dm[ax] > 0.0 ? 1.0 : -1.0); // the exit face's outward normal
        vec3 q = p + d * te;
        float eps = 1e-3 * I.cell + 4e-6 * max(max(abs(q.x), abs(q.y)), abs(q.z));
        vec3 qi = q + d * eps;
        // the neighbour across the face: looked up in the instance's own model first (a glass cell there is
        // what the ray below would meet, without its BVH and set-up, the path tracer's order), outside the box
        vec3 mq = floor(vec3(dot(I.r0.xyz, qi) + I.r0.w, dot(I.r1.xyz, qi) + I.r1.w, dot(I.r2.xyz, qi) + I.r2.w));
        uint nl;
        vec4 nm;
        if (all(greaterThanEqual(mq, vec3(0.0))) && all(lessThan(mq, vec3(exp2(float(model_at(I.model).depth))))) &&
            !(all(greaterThanEqual(mq, lo)) && all(lessThan(mq, hi))) &&
            glass_of(model_cell_leaf(I.model, uvec3(mq), nl), nm)) {
            c = uvec3(mq);
            lv = nl;
            t = te + eps;
            continue;
        }
        // else a ray: a ray starting inside a voxel meets it at once
        Hit g;
        g.t = eps;
        g.inst = NO_HIT;
        g.color = 0xFFFFFFFFu;
        g.attr = NO_HIT;
        g_iter = 0u;
        if (trace_scene(qi, d, 0.0, false, g)) {
            vec4 gm;
            if (!glass_of(g.attr, gm)) { // an opaque voxel against the glass: its face, seen from inside
                o = q;
                s1 = uvec4(g.color, inst, uint(ax) | (dm[ax] > 0.0 ? 4u : 0u), g.attr);
                return WALK_STOP;
            }
            inst = g.inst;
            c = glass_cell(inst, qi);
            if (model_cell_leaf(insts[inst].model, c, lv) == NO_HIT) lv = 0u;
            t = te + eps;
            continue;
        }
        float fr = fresnel_dielectric(dot(d, nf), 1.0 / ior);
        if (fr >= 1.0) { // total internal reflection: a new stretch from just inside the face
            d = reflect(d, nf);
            p = q - nf * eps;
            t = 0.0;
            continue;
        }
        rthr = thr * fr, rd = reflect(d, nf), ro = q - nf * eps; // the share reflected back inside
        thr *= 1.0 - fr;
        d = glass_refract(-d, -nf, 1.0 / ior);
        o = q + nf * eps;
        return WALK_OUT;
    }
    return WALK_ABSORBED;
}

// The radiance an opaque G-buffer-like entry (s0, s1: a point met by a ray
// through glass) sends back along unit wo: its direct light (the sun and the
// lights, shadowed as direct_pixel's, the Lambert BRDF or metal's towards
// wo), its emission and, with the sky term, the sky's light on it
// (unoccluded: the ao pass knows the pixels' surfaces only).
vec3 glass_seen_surface(uvec2 px, uvec4 s0, uvec4 s1, vec3 wo) {
    vec3 nw = gb_normal(s1);
    vec3 alb = HAS_COLOR ? unpack_rgb(s1.x) : vec3(1.0);
    Metal M;
    bool mt = METAL && metal_of(s0, s1, M);
    if (mt) M.wo = wo;
    vec3 e = direct_light(px, s0, s1, nw, mt, M);
    vec3 rad = mt ? e : alb / PI * e;
    if (EMIT_KNOWN && s1.w < uint(emit_attr.length())) rad += emitted(alb, emit_attr[s1.w]);
    if (GLASS_SKY) {
        if (mt) rad += M.kd * frame_sky_irradiance(nw) + frame_sky(reflect(-wo, nw)) * metal_albedo(M, max(dot(nw, wo), 0.0));
        else rad += alb * frame_sky_irradiance(nw);
    }
#ifdef GLASS_SEEN_GI
    rad += GLASS_SEEN_GI(s0, s1); // the includer's indirect light there (a gi method's kernel: cone.comp)
#endif
    return rad;
}

// The radiance a glass pixel (record m = vec4(2, rough, ior, transmission))
// sends to the eye: the path tracer's glass events (probes/pathtrace.c
// vx__path: a dielectric event is no bounce, so at bounces 0 a path goes on
// through glass and off it to the first surface that is not glass, which
// gets its direct light and emission) in expectation, with smooth directions
// (rough glass too: the macro normal's mirror and refraction). Where the path
// tracer draws one branch of each Fresnel split, this follows both: at a
// glass surface the reflected ray (weight F at its angle, the exact Fresnel)
// and the refracted one (1 - F, times the colour: the path tracer's tint at
// entry); inside, the walk (glass_pass_walk) to the exit face, where the ray
// leaves with 1 - F_out and the share F_out reflected back inside is
// followed in turn (past the critical angle the walk reflects whole). Each
// ray that leaves the glass is traced to the next surface, which
// glass_seen_surface shades (its direct light, emission, sky term), or to
// the sky on a miss; a further glass body met is split the same way (its
// transmission t weighting the glass lobe, 1 - t its Lambert share shaded as
// a diffuse surface) up to GLASS_BODIES entered along one ray, the surface
// met after that shaded as opaque. The pending rays wait on a small stack
// (GLASS_STACK; the refracted ray goes first, the reflected one waits); at
// most GLASS_RAYS rays are followed per pixel and none lighter than
// GLASS_MIN_WEIGHT (a slab of ior 1.5 seen head on: the reflection 4%, the
// light reflected twice inside 0.16%, three times 6e-5, dropped). The
// pixel's own transmission t weights what this returns; its Lambert share
// (1 - t) is glass_pixel's (and resolve's sky term).
const uint GLASS_RAYS = 8u, GLASS_STACK = 4u;
const float GLASS_MIN_WEIGHT = 1e-4;
const uint GLASS_OUT = 0u, GLASS_IN = 1u, GLASS_AT = 2u; // a ray in the open, inside glass, at a glass surface
vec3 glass_lobe(uvec2 px, uvec4 g0, uvec4 g1, vec4 m) {
    vec3 rad = vec3(0.0);
    // the ray followed: its state, start o, direction d, weight thr; inside glass (GLASS_IN) its instance slot and
    // ior; the glass bodies entered along it; at a glass surface (GLASS_AT) the surface s0, s1
    uint state = GLASS_AT, inst = g1.y, bodies = 0u;
    vec3 o = uintBitsToFloat(g0.xyz), d = -view_to_eye(o), thr = vec3(1.0);
    float ior = 1.0;
    uvec4 s0 = g0, s1 = g1;
    // the rays waiting: (start, direction, weight, instance | GLASS_IN << 31, ior, bodies)
    vec3 wo_[GLASS_STACK], wd_[GLASS_STACK], ww_[GLASS_STACK];
    uint wi_[GLASS_STACK], wb_[GLASS_STACK];
    float wr_[GLASS_STACK];
    uint nw = 0u;
    bool have = true;
    for (uint r = 0u; r < GLASS_RAYS; r++) {
        if (!have) {
            if (nw == 0u) break;
            nw--;
            o = wo_[nw], d = wd_[nw], thr = ww_[nw], ior = wr_[nw], bodies = wb_[nw];
            inst = wi_[nw] & 0x7FFFFFFFu, state = (wi_[nw] >> 31) != 0u ? GLASS_IN : GLASS_OUT;
        }
        have = false;
        if (max(max(thr.x, thr.y), thr.z) < GLASS_MIN_WEIGHT) continue;
        bool shade = false; // s0, s1 a surface seen along d, shaded with weight sw
        vec3 sw = thr;
        if (state == GLASS_IN) {
            vec3 q, ro, rd, rw;
            uint wk = glass_pass_walk(inst, o, ior, d, thr, q, s1, ro, rd, rw);
            if (wk == WALK_OUT && max(max(rw.x, rw.y), rw.z) >= GLASS_MIN_WEIGHT && nw < GLASS_STACK) {
                wo_[nw] = ro, wd_[nw] = rd, ww_[nw] = rw, wi_[nw] = inst | 0x80000000u, wr_[nw] = ior, wb_[nw] = bodies;
                nw++;
            }
            if (wk == WALK_ABSORBED) continue;
            o = q, state = GLASS_OUT, sw = thr;
            if (wk == WALK_STOP) {
                // a voxel set in the glass (or the floor a glass block stands on): shaded as a surface seen
                // through glass; its shadow rays start inside the glass, which they meet, so its direct light
                // is none, as in the path tracer, which samples no light inside glass
                s0 = uvec4(floatBitsToUint(q), 0u);
                shade = true;
            }
        }
        if (state == GLASS_OUT && !shade) {
            Hit h;
            h.t = 3.0e38;
            h.inst = NO_HIT;
            h.color = 0xFFFFFFFFu;
            h.attr = NO_HIT;
            g_iter = 0u;
            if (!trace_scene(o, d, 0.0, false, h)) {
                rad += thr * frame_sky(d);
                continue;
            }
            vec3 p = o + d * h.t;
            s0 = uvec4(floatBitsToUint(p.x), floatBitsToUint(p.y), floatBitsToUint(p.z), 0u);
            s1 = uvec4(h.color, h.inst, uint(h.axis) | (h.nsign < 0.0 ? 4u : 0u), h.attr);
            vec4 gm;
            state = bodies < GLASS_BODIES && glass_of(h.attr, gm) ? GLASS_AT : GLASS_OUT;
            shade = state == GLASS_OUT;
        }
        vec3 swo = -d; // towards where the ray came from
        if (state == GLASS_AT) {
            // a glass surface met from outside: its Lambert share shaded (not the pixel's own: glass_pixel's), its
            // glass lobe split into the reflected ray (waiting) and the refracted one (followed next)
            vec4 gm;
            glass_of(s1.w, gm);
            vec3 p = uintBitsToFloat(s0.xyz), n = gb_normal(s1);
            vec3 alb = HAS_COLOR ? unpack_rgb(s1.x) : vec3(1.0);
            sw = thr * (1.0 - gm.w);
            shade = r > 0u && gm.w < 1.0;
            inst = s1.y, ior = gm.z;
            thr *= gm.w;
            float c = dot(n, swo), fr = c > 0.0 ? fresnel_dielectric(c, ior) : 0.0;
            float eps = 1e-3 * insts[inst].cell + 4e-6 * max(max(abs(p.x), abs(p.y)), abs(p.z));
            if (c > 0.0 && nw < GLASS_STACK) {
                wo_[nw] = p + n * eps, wd_[nw] = reflect(d, n), ww_[nw] = thr * fr, wi_[nw] = inst, wr_[nw] = ior;
                wb_[nw] = bodies;
                nw++;
            }
            if (c > 0.0 && fr < 1.0) {
                thr *= (1.0 - fr) * alb;
                d = glass_refract(swo, n, ior);
                o = p - n * eps;
                state = GLASS_IN, bodies++, have = true;
            }
        }
        if (shade) rad += sw * glass_seen_surface(px, s0, s1, swo);
    }
    return rad;
}

// The direct pass's radiance of a glass pixel: the Lambert share's direct
// light, and the glass lobe where no gi pass gives it (GLASS_GI).
vec3 glass_pixel(uvec2 px, uvec4 g0, uvec4 g1, vec4 m) {
    vec3 rad = vec3(0.0);
    if (m.w < 1.0) {
        Metal M0;
        vec3 alb = HAS_COLOR ? unpack_rgb(g1.x) : vec3(1.0);
        rad = (1.0 - m.w) * alb / PI * direct_light(px, g0, g1, gb_normal(g1), false, M0);
    }
    if (GLASS_GI) return rad; // the glass lobe is the gi pass's (above)
    return rad + glass_lobe(px, g0, g1, m);
}

// What the direct pass delivers for a G-buffer entry: in the colour model
// (1 - ambient) * n.l * visibility, in the radiometric one (PHYS) sun
// irradiance * n.l * visibility plus the lights' irradiance; for a metal
// record (METAL) the radiance that light leaves towards the eye instead
// (each source's irradiance times the BRDF towards it: resolve adds it as it
// is, where a diffuse pixel's irradiance is multiplied by albedo / pi); for a
// glass record (GLASS) the radiance glass_pixel finds, also added as it is.
vec4 direct_pixel(uvec2 px, uvec4 g0, uvec4 g1) {
    if (g1.y == NO_HIT) return vec4(0.0);
    vec3 nw = gb_normal(g1);
    if (!PHYS) {
        float ndl = max(dot(nw, F.light.xyz), 0.0);
        float amb = F.light.w;
        return vec4(vec3((1.0 - amb) * ndl * sun_visibility(g0, g1, nw, ndl)), 1.0);
    }
    vec4 gm;
    if (GLASS && glass_of(g1.w, gm)) return vec4(glass_pixel(px, g0, g1, gm), 1.0);
    Metal M;
    bool mt = METAL && metal_of(g0, g1, M);
    return vec4(direct_light(px, g0, g1, nw, mt, M), 1.0);
}

// Ambient occlusion rays first .. first+count-1 of a G-buffer entry: how many
// of them hit within PC.f0.z (ray k's direction depends on k alone).
float ao_blocked(uvec2 px, uvec4 g0, uvec4 g1, uint first, uint count) {
    vec3 nw = gb_normal(g1);
    vec3 ps = gb_offset_point(uintBitsToFloat(g0.xyz), nw, g1.y);
    float blocked = 0.0;
    for (uint k = first; k < first + count; k++) {
        vec3 dir = cosine_dir(nw, pass_rnd(px, 11u, 2u * k), pass_rnd(px, 11u, 2u * k + 1u));
        Hit h;
        h.t = PC.f0.z;
        h.inst = NO_HIT;
        if (trace_scene(ps, dir, 0.0, true, h)) blocked += 1.0;
    }
    return blocked;
}

const bool HAS_DIRECT = (FLAGS & 1u) != 0u, HAS_GI = (FLAGS & 2u) != 0u, HAS_AO = (FLAGS & 4u) != 0u;
const bool HAS_EMIT = (FLAGS & 8u) != 0u, HAS_SKY = (FLAGS & 32u) != 0u;

// The sample's colour (or the intermediate SHOW asks for) from its images.
vec4 resolve_pixel(uvec4 g0, uvec4 g1, vec4 dir, float ao, vec4 gi) {
    bool hit = g1.y != NO_HIT;
    vec3 alb = HAS_COLOR ? unpack_rgb(g1.x) : vec3(1.0);
    if (SHOW == 0u) {
        if (!hit) return PHYS ? vec4(frame_sky(uintBitsToFloat(g0.xyz)), 0.0) : vec4(0.62, 0.75, 0.92, 0.0);
        if (!PHYS) {
            float amb = F.light.w;
            float e = HAS_DIRECT ? dir.x : 0.0;
            if (HAS_AO) amb *= ao;
            return vec4(alb * (amb + e), 1.0);
        }
        vec3 rad = vec3(0.0);
        Metal M;
        bool mt = METAL && metal_of(g0, g1, M); // the direct pass gave its radiance
        vec4 gm;
        bool gl = GLASS && glass_of(g1.w, gm); // so it did for glass, the sky term included
        if (HAS_EMIT && g1.w < uint(emit_attr.length())) rad += emitted(alb, emit_attr[g1.w]);
        if (HAS_DIRECT) rad += mt || gl ? dir.xyz : alb / PI * dir.xyz;
        if (gl) {
            // glass with a gi pass: its image holds the glass lobe whole and the Lambert share's indirect
            // light, each weighted by its lobe's share (GLASS_GI above), added as it is (the ao image knows
            // the glass surface, not what is seen through it); without one the direct pass gave the glass
            // radiance and the sky term is the Lambert share's (1 - transmission, the path tracer's choice
            // of lobe)
            if (HAS_GI) rad += gi.xyz;
            if (HAS_SKY) rad += (1.0 - gm.w) * alb * frame_sky_irradiance(gb_normal(g1)) * (HAS_AO ? ao : 1.0);
            return vec4(rad, 1.0);
        }
        if (HAS_GI) rad += gi.xyz * (HAS_AO ? ao : 1.0);
        if (HAS_SKY && mt) {
            // metal: the sky's light on the Lambert lobe (kd), and the sky along the mirror direction times the
            // specular lobe's albedo (exact for a uniform unoccluded sky; the sky by direction is not filtered
            // by the lobe), both times the visibility
            vec3 n = gb_normal(g1);
            float nv = max(dot(n, M.wo), 0.0);
            vec3 sky_spec = frame_sky(reflect(-M.wo, n)) * metal_albedo(M, nv);
            rad += (M.kd * frame_sky_irradiance(n) + sky_spec) * (HAS_AO ? ao : 1.0);
        } else if (HAS_SKY) {
            rad += alb * frame_sky_irradiance(gb_normal(g1)) * (HAS_AO ? ao : 1.0); // the sky's light times its visibility
        }
        return vec4(rad, 1.0);
    }
    if (SHOW == 1u) return hit ? vec4(alb, 1.0) : vec4(0.0);
    if (SHOW == 2u) return hit ? vec4(gb_normal(g1), 1.0) : vec4(0.0);
    if (SHOW == 3u) {
        float t = uintBitsToFloat(g0.w);
        return vec4(t, t, t, hit ? 1.0 : 0.0);
    }
    if (SHOW == 4u) return HAS_DIRECT ? vec4(dir.xyz, hit ? 1.0 : 0.0) : vec4(0.0);
    if (SHOW == 5u) return HAS_GI ? vec4(gi.xyz, hit ? 1.0 : 0.0) : vec4(0.0);
    if (SHOW == 6u) {
        float a = HAS_AO ? ao : 1.0;
        return vec4(a, a, a, hit ? 1.0 : 0.0);
    }
    if (SHOW == 7u) return hit ? vec4(inst_color(insts[g1.y].id), 1.0) : vec4(0.0);
    float m = hit && g1.w != NO_HIT ? float(g1.w) : -1.0;
    return vec4(m, m, m, hit ? 1.0 : 0.0);
}

// Adds a sample's colour to the accumulation (trace.comp's summation order).
void accumulate(uint i, vec4 c) {
    uint s = PC.u0.x, n = max(PC.u0.y, 1u);
    vec4 a = s == 0u ? c : acc_img[i] + c;
    if (s + 1u == n) a = a / float(n);
    acc_img[i] = a;
}
