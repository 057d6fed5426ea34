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
        vec3 p = o + d * h.t;
        float depth = float(t_off + h.t);
        g0 = uvec4(floatBitsToUint(p.x), floatBitsToUint(p.y), floatBitsToUint(p.z), floatBitsToUint(depth));
        uint face = uint(h.axis) | (h.nsign < 0.0 ? 4u : 0u);
        g1 = uvec4(h.color, h.inst, face, h.attr);
    } else {
        g0 = uvec4(0u, 0u, 0u, 0x7F800000u);
        g1 = uvec4(0u, NO_HIT, 0u, NO_HIT);
    }
    ids0 = uvec4(hit ? insts[h.inst].id : NO_HIT, h.cell);
    ids1 = uvec4(floatBitsToUint(hit ? float(t_off + h.t) : 0.0), g_iter, 0u, 0u);
}

// Irradiance from the frame's lights (render/pipeline.h) at a G-buffer
// entry, each with a ray-traced shadow: directional E = c n.l; point and spot
// E = c n.l / d^2 times glTF's range window (1 - (d/range)^4)^2 and, for a
// spot, its cone factor. d^2 is kept above (cell/100)^2 so that a light on
// the surface gives a finite value.
vec3 lights_pixel(uvec4 g0, uvec4 g1, vec3 nw) {
    vec3 p = uintBitsToFloat(g0.xyz);
    vec3 ps = gb_offset_point(p, nw, g1.y);
    float cell = insts[g1.y].cell;
    vec3 e = vec3(0.0);
    for (uint k = 0u; k < PC.u1.z; k++) {
        Light L = lights[k];
        uint type = uint(L.a.w);
        vec3 l;
        float dist, f = 1.0;
        if (type == 0u) {
            l = L.b.xyz;
            dist = 3.0e38;
        } else {
            vec3 v = L.a.xyz - ps;
            float d2 = max(dot(v, v), 1e-4 * cell * cell);
            dist = sqrt(dot(v, v));
            l = dist > 0.0 ? v / dist : nw;
            f = 1.0 / d2;
            if (L.b.w > 0.0) {
                float q = dist / L.b.w;
                f *= pow(clamp(1.0 - q * q * q * q, 0.0, 1.0), 2.0);
            }
            if (type == 2u) {
                float a = clamp(dot(-l, L.b.xyz) * L.d.x + L.d.y, 0.0, 1.0);
                f *= a * a;
            }
        }
        float ndl = dot(nw, l);
        if (ndl <= 0.0 || f <= 0.0) continue;
        Hit sh;
        sh.t = type == 0u ? 3.0e38 : dist * 0.9999;
        sh.inst = NO_HIT;
        if (trace_scene(ps, l, 0.0, true, sh)) continue;
        e += L.c.xyz * (ndl * f);
    }
    return e;
}

// What the direct pass delivers for a G-buffer entry: in the colour model
// (1 - ambient) * n.l * visibility, in the radiometric one (PHYS) sun
// irradiance * n.l * visibility.
vec4 direct_pixel(uvec4 g0, uvec4 g1) {
    if (g1.y == NO_HIT) return vec4(0.0);
    vec3 nw = gb_normal(g1);
    float ndl = max(dot(nw, F.light.xyz), 0.0);
    float vis = 0.0;
    bool sun = !PHYS || PC.f1.x > 0.0 || PC.f1.y > 0.0 || PC.f1.z > 0.0; // no sun ray without a sun
    if (ndl > 0.0 && sun) {
        vec3 ps = gb_offset_point(uintBitsToFloat(g0.xyz), nw, g1.y);
        Hit sh;
        sh.t = 3.0e38;
        sh.inst = NO_HIT;
        vis = trace_scene(ps, F.light.xyz, 0.0, true, sh) ? 0.0 : 1.0;
    }
    if (!PHYS) {
        float amb = F.light.w;
        return vec4(vec3((1.0 - amb) * ndl * vis), 1.0);
    }
    vec3 e = PC.f1.xyz * ndl * vis;
    if (PC.u1.z > 0u) e += lights_pixel(g0, g1, nw);
    return vec4(e, 1.0);
}

// Ambient occlusion rays first .. first+count-1 of a G-buffer entry: how many
// of them hit within PC.f0.z (ray k's direction depends on k alone).
float ao_blocked(uvec2 px, uvec4 g0, uvec4 g1, uint first, uint count) {
    vec3 nw = gb_normal(g1);
    vec3 ps = gb_offset_point(uintBitsToFloat(g0.xyz), nw, g1.y);
    float blocked = 0.0;
    for (uint k = first; k < first + count; k++) {
        vec3 dir = pass_cosine_dir(nw, pass_rnd(px, 11u, 2u * k), pass_rnd(px, 11u, 2u * k + 1u));
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
        if (!hit) return PHYS ? vec4(PC.f2.xyz, 0.0) : vec4(0.62, 0.75, 0.92, 0.0);
        if (!PHYS) {
            float amb = F.light.w;
            float e = HAS_DIRECT ? dir.x : 0.0;
            if (HAS_AO) amb *= ao;
            return vec4(alb * (amb + e), 1.0);
        }
        vec3 rad = vec3(0.0);
        if (HAS_EMIT && g1.w != NO_HIT) rad += alb * emit_attr[g1.w];
        if (HAS_DIRECT) rad += alb / PI * dir.xyz;
        if (HAS_GI) rad += gi.xyz * (HAS_AO ? ao : 1.0);
        if (HAS_SKY) rad += alb * PC.f2.xyz * (HAS_AO ? ao : 1.0); // sky radiance times its visibility
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
