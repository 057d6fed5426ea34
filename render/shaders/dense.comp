#version 450
// render/shaders/dense.comp - the benchmark baseline: the same primary rays
// through a dense occupancy bit grid with a plain 3D-DDA (Amanatides & Woo).
layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(std140, binding = 0) uniform Frame {
    vec4 fwd;
    vec4 rx;
    vec4 uy;
    vec4 light;
    vec4 misc;
    uvec4 dims;
    uvec4 dims2;   // grid nx, ny, nz
    vec4 grid_lo;  // xyz: lower corner relative to the frame reference, w: cell size
} F;
layout(std430, binding = 1) readonly buffer Bits { uint bits[]; };
layout(std430, binding = 2) writeonly buffer Pixels { vec4 pixels[]; };

bool cell_set(ivec3 c) {
    uint i = (uint(c.z) * F.dims2.y + uint(c.y)) * F.dims2.x + uint(c.x);
    return ((bits[i >> 5] >> (i & 31u)) & 1u) != 0u;
}

void main() {
    uvec2 px = gl_GlobalInvocationID.xy;
    uint W = F.dims.x, H = F.dims.y;
    if (px.x >= W || px.y >= H) return;
    float u = ((float(px.x) + 0.5) / float(W)) * 2.0 - 1.0;
    float v = 1.0 - ((float(px.y) + 0.5) / float(H)) * 2.0;
    vec3 o, d;
    float t_off;
    float t_start = F.fwd.w;
    if (F.rx.w != 0.0) {
        o = u * F.rx.xyz + v * F.uy.xyz;
        d = F.fwd.xyz;
        t_off = t_start;
    } else {
        vec3 du = F.fwd.xyz + u * F.rx.xyz + v * F.uy.xyz;
        float len = length(du);
        d = du / len;
        o = t_start * (u * F.rx.xyz + v * F.uy.xyz);
        t_off = t_start * len;
    }
    float cs = F.grid_lo.w;
    vec3 g = (o - F.grid_lo.xyz) / cs;
    vec3 gd = d / cs;
    vec3 n = vec3(F.dims2.xyz);
    vec3 inv;
    for (int i = 0; i < 3; i++) inv[i] = abs(gd[i]) < 1e-30 ? 1e30 : 1.0 / gd[i];
    vec3 a = (vec3(0.0) - g) * inv, b = (n - g) * inv;
    vec3 tn = min(a, b), tf = max(a, b);
    float t0 = max(max(max(tn.x, tn.y), tn.z), 0.0);
    float t1 = min(min(tf.x, tf.y), tf.z);
    float result = uintBitsToFloat(0x7F800000u);
    if (t0 < t1) {
        vec3 p = g + gd * t0;
        ivec3 c = clamp(ivec3(floor(p)), ivec3(0), ivec3(F.dims2.xyz) - 1);
        ivec3 stp = ivec3(sign(gd));
        vec3 tdel = abs(inv);
        vec3 nb = vec3(c) + max(vec3(stp), vec3(0.0));
        vec3 tmx = (nb - g) * inv;
        for (int i = 0; i < 3; i++) if (stp[i] == 0) tmx[i] = 3e38;
        float t = t0;
        for (uint it = 0u; it < 100000u; it++) {
            if (cell_set(c)) { result = t_off + t; break; }
            if (tmx.x <= tmx.y && tmx.x <= tmx.z) { c.x += stp.x; t = tmx.x; tmx.x += tdel.x; if (c.x < 0 || c.x >= int(F.dims2.x)) break; }
            else if (tmx.y <= tmx.z) { c.y += stp.y; t = tmx.y; tmx.y += tdel.y; if (c.y < 0 || c.y >= int(F.dims2.y)) break; }
            else { c.z += stp.z; t = tmx.z; tmx.z += tdel.z; if (c.z < 0 || c.z >= int(F.dims2.z)) break; }
        }
    }
    pixels[px.y * W + px.x] = vec4(result, result, result, 1.0);
}
