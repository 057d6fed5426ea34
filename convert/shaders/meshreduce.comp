#version 450
/* convert/shaders/meshreduce.comp - one voxel per run of equal keys in the
 * sorted records: MODE 0 flags the first record of each run, MODE 1 (after
 * the flags' exclusive scan) sums the run's records in their order, which is
 * the CPU's triangle order (a stable sort of records written in (brick,
 * triangle) order), with the CPU's float additions, and finishes the cell
 * as convert/mesh_voxelize.c's finish_rgba and oct_encode do. */
layout(local_size_x = 256) in;
layout(constant_id = 0) const uint MODE = 0;
layout(push_constant) uniform Push { uint n; } pc;

layout(std430, binding = 0) readonly buffer Keys { uvec2 keys[]; };
layout(std430, binding = 1) readonly buffer Vals { uint vals[]; };
struct Rec { vec4 c; vec4 n; uint mat; uint pad0, pad1, pad2; };
layout(std430, binding = 2) readonly buffer Recs { Rec recs[]; };
layout(std430, binding = 3) buffer Pos { uint pos[]; };
layout(std430, binding = 4) writeonly buffer OKeys { uvec2 okeys[]; };
layout(std430, binding = 5) writeonly buffer ORgba { uint orgba[]; };
layout(std430, binding = 6) writeonly buffer ONrm { uint onrm[]; };
layout(std430, binding = 7) writeonly buffer OMat { uint omat[]; };
layout(std430, binding = 8) readonly buffer Tables { float thr[256]; uint guess[4097]; uint attrs; };

uint lin_to_srgb8(float v) {
    if (!(v > 0)) return 0u;
    if (v >= 1) return 255u;
    precise float s = v * 4096.0;
    uint c = guess[int(s)];
    while (thr[c] < v) c++;
    return c;
}
uint unorm8(float v) {
    if (!(v > 0)) return 0u;
    if (v >= 1) return 255u;
    precise float s = v * 255.0;
    return uint(roundEven(s));
}

uint oct_encode(double x_in, double y_in, double z_in) {
    precise double x = x_in, y = y_in, z = z_in;
    precise double l = abs(x) + abs(y) + abs(z);
    if (!(l > 0)) {
        x = 0;
        y = 0;
        z = 1;
        l = 1;
    }
    precise double px = x / l, py = y / l;
    if (z < 0) {
        precise double ox = (1 - abs(py)) * (px >= 0 ? 1.0lf : -1.0lf), oy = (1 - abs(px)) * (py >= 0 ? 1.0lf : -1.0lf);
        px = ox;
        py = oy;
    }
    precise double qx = max(-1.0lf, min(1.0lf, px)) * 32767.0lf, qy = max(-1.0lf, min(1.0lf, py)) * 32767.0lf;
    int sx = int(roundEven(qx)), sy = int(roundEven(qy));
    return (uint(sx) & 0xFFFFu) | ((uint(sy) & 0xFFFFu) << 16);
}

float fdiv(float a, float b) {
    precise double q = double(a) / double(b);
    return float(q);
}

void main() {
    uint i = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 256u + gl_LocalInvocationID.x;
    if (i >= pc.n) return;
    uvec2 k = keys[i];
    bool head = i == 0u || keys[i - 1u] != k;
    if (MODE == 0u) {
        pos[i] = head ? 1u : 0u;
        return;
    }
    if (!head) return;
    uint o = pos[i];
    okeys[o] = k;
    if (attrs == 0u) return;
    precise vec4 c = vec4(0);
    precise vec3 nn = vec3(0);
    precise float w = 0, mw = 0;
    uint mat = 0u;
    for (uint j = i; j < pc.n && keys[j] == k; j++) {
        Rec r = recs[vals[j]];
        for (int q = 0; q < 4; q++) c[q] += r.c[q];
        for (int q = 0; q < 3; q++) nn[q] += r.n[q];
        w += r.n.w;
        if (r.n.w > mw) {
            mw = r.n.w;
            mat = r.mat;
        }
    }
    float f[4];
    for (int q = 0; q < 4; q++) f[q] = w > 0 ? fdiv(c[q], w) : 1.0;
    orgba[o] = lin_to_srgb8(f[0]) | lin_to_srgb8(f[1]) << 8 | lin_to_srgb8(f[2]) << 16 | unorm8(f[3]) << 24;
    onrm[o] = oct_encode(double(nn.x), double(nn.y), double(nn.z));
    omat[o] = mat;
}
