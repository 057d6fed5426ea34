#version 450
/* convert/shaders/meshreduce.comp - one voxel per run of equal keys in the
 * sorted records: MODE 0 flags the first record of each run, MODE 1 (after
 * the flags' exclusive scan) sums the run's records in their order, which is
 * the CPU's triangle order (a stable sort of records written in (brick,
 * triangle) order), with the CPU's float additions, and finishes the cell
 * as convert/mesh_voxelize.c's finish_rgba and oct_encode do; with
 * materials sampled per cell (Tables.sampled) the material id too, as its
 * cell_material and vx__mesh_mats_id (convert/mesh_material.c) do. */
layout(local_size_x = 256) in;
layout(constant_id = 0) const uint MODE = 0;
layout(push_constant) uniform Push { uint n; } pc;

layout(std430, binding = 0) readonly buffer Keys { uvec2 keys[]; };
layout(std430, binding = 1) readonly buffer Vals { uint vals[]; };
struct Rec { vec4 c; vec4 n; uint mat; float pm, pr, pe0; }; /* meshvox.comp's */
layout(std430, binding = 2) readonly buffer Recs { Rec recs[]; };
layout(std430, binding = 3) buffer Pos { uint pos[]; };
layout(std430, binding = 4) writeonly buffer OKeys { uvec2 okeys[]; };
layout(std430, binding = 5) writeonly buffer ORgba { uint orgba[]; };
layout(std430, binding = 6) writeonly buffer ONrm { uint onrm[]; };
layout(std430, binding = 7) writeonly buffer OMat { uint omat[]; };
layout(std430, binding = 8) readonly buffer Tables { float thr[256]; uint guess[4097]; uint attrs, sampled, levels, mat_count; };
/* sampled: per glTF material its vx__mesh_mat (f: metal, rough, emit_max,
 * trans; u: base, block, sample, special; e: emit, 0); per record its
 * emission's G, B */
struct Plan { vec4 f; uvec4 u; vec4 e; };
layout(std430, binding = 9) readonly buffer Plans { Plan plans[]; };
layout(std430, binding = 10) readonly buffer RecX { vec2 recx[]; };

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

/* mesh_material.c's level_of: v / f in [0, 1] to the nearest of levels
 * steps (lrint: ties to even) */
uint level_of(float v, float f, uint L) {
    precise double q = f > 0 ? double(v) / double(f) : 0.0lf;
    if (!(q > 0)) return 0u;
    if (q >= 1) return L - 1u;
    precise double s = q * double(L - 1u);
    return uint(roundEven(s));
}

/* vx__mesh_mats_id: the id of a cell whose largest piece is of material mi;
 * a sampled emission quantizes each channel whose factor is above 0, ke
 * their levels' mixed-radix number (R first) */
uint mats_id(uint mi, float metal, float rough, vec3 emit) {
    if (mi >= mat_count || plans[mi].u.x == 0u) return 0u;
    vec4 f = plans[mi].f;
    uvec4 u = plans[mi].u;
    if (u.z == 0u) return u.w != 0u ? u.x : 0u;
    uint L = levels, km = 0u, kr = 0u, ke = 0u, Le = 1u;
    uint Lr = (u.z & 2u) != 0u ? L : 1u;
    bool lit = f.z > 0, metallic = f.x > 0;
    if ((u.z & 1u) != 0u) {
        km = level_of(metal, f.x, L);
        metallic = km > 0u;
    }
    if ((u.z & 2u) != 0u) kr = level_of(rough, f.y, L);
    if ((u.z & 4u) != 0u) {
        vec4 e = plans[mi].e;
        lit = false;
        for (int c = 0; c < 3; c++)
            if (e[c] > 0) {
                uint k = level_of(emit[c], e[c], L);
                ke = ke * L + k;
                Le *= L;
                lit = lit || k > 0u;
            }
    }
    if (!metallic && !lit && !(f.w > 0)) return 0u; /* diffuse: no record */
    return (u.x + (km * Lr + kr) * Le + ke) & 0xFFFFu;
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
    precise float pm = 0, pr = 0;
    precise vec3 pe = vec3(0);
    uint mat = 0u;
    for (uint j = i; j < pc.n && keys[j] == k; j++) {
        Rec r = recs[vals[j]];
        if (sampled != 0u) {
            vec2 x = recx[vals[j]];
            pm += r.pm;
            pr += r.pr;
            pe[0] += r.pe0;
            pe[1] += x.x;
            pe[2] += x.y;
        }
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
    if (sampled != 0u) { /* mat is the glTF index: cell_material */
        float ww = w > 0 ? w : 1.0;
        mat = mats_id(mat, fdiv(pm, ww), fdiv(pr, ww), vec3(fdiv(pe[0], ww), fdiv(pe[1], ww), fdiv(pe[2], ww)));
    }
    omat[o] = mat;
}
