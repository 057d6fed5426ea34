#version 450
// render/shaders/cull.comp - light culling for the direct pass
// (render/pipeline.c), built on the GPU every frame: each light's window
// sphere (centre, radius R: pipeline.h's cut-off) is inserted into the cells
// of the light grid it touches (passes_common.glsl: screen tiles times
// exponential depth slices, "clustered"; or one cell per tile spanning the
// view depths of the tile's G-buffer hits, "tiled"). Light-centric, in four
// or five dispatches:
//   STEP 0 clear   one invocation per cell: count 0 (tiled: empty depth range)
//   STEP 1 depth   tiled only, one invocation per pixel: the tile's depth range
//   STEP 2 count   32 invocations per light: count the cells it touches
//   STEP 3 scan    one workgroup: each cell's list offset (exclusive sum), count 0
//   STEP 4 fill    32 invocations per light: append its index to those cells
// (32 per light, each taking every 32nd cell of the light's box, so that a
// light that covers the screen costs no more than a few small ones.)
// Directional lights (the first PC.u1.w) are in no list: every pixel takes
// them. Lists past the capacity (PC.f3.w) are dropped and cl[1] says how
// many entries were needed (the most over the frame's samples); pipeline.c
// then grows the list and renders the frame again.
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 256, local_size_y = 1, local_size_z = 1) in;

#include "trace_common.glsl"
#include "passes_common.glsl"

layout(constant_id = 5) const uint STEP = 0u;
layout(constant_id = 6) const bool TILED = false;

shared uint s_sum[256];
shared uint s_zmin, s_zmax;

uint cells() { return PC.u2.x * PC.u2.y * PC.u2.z; }

// The view depth (minus zb) of a G-buffer hit, clamped at 0 so that its
// float bits order as the values do.
float hit_depth(vec3 p) { return max(grid_view(p).z - PC.f3.x, 0.0); }

// Whether the light sphere (view centre c, radius r) touches the cell
// (tx, ty) between view depths z0 and z1 (minus zb): the sphere against the
// cell's bounding box in view coordinates, open-ended at the grid's edges.
bool touches(vec3 c, float r, uint tx, uint ty, float z0, float z1) {
    const float BIG = 1e30;
    float T = float(PC.u2.w), W = float(F.dims.x), H = float(F.dims.y);
    float ulo = tx == 0u ? -BIG : 2.0 * float(tx) * T / W - 1.0;
    float uhi = tx + 1u >= PC.u2.x ? BIG : 2.0 * float(tx + 1u) * T / W - 1.0;
    float vhi = ty == 0u ? BIG : 1.0 - 2.0 * float(ty) * T / H;
    float vlo = ty + 1u >= PC.u2.y ? -BIG : 1.0 - 2.0 * float(ty + 1u) * T / H;
    float sx = length(F.rx.xyz), sy = length(F.uy.xyz);
    float za = z0 + PC.f3.x, zb = z1 + PC.f3.x; // view depths
    vec3 lo, hi;
    if (F.rx.w != 0.0) {
        lo.xy = vec2(ulo * sx, vlo * sy), hi.xy = vec2(uhi * sx, vhi * sy);
    } else {
        za = max(za, 0.0), zb = max(zb, 0.0);
        lo.xy = min(vec2(ulo * sx, vlo * sy) * za, vec2(ulo * sx, vlo * sy) * zb);
        hi.xy = max(vec2(uhi * sx, vhi * sy) * za, vec2(uhi * sx, vhi * sy) * zb);
    }
    lo.z = za, hi.z = zb;
    vec3 d = max(max(lo - c, c - hi), vec3(0.0));
    return dot(d, d) <= r * r;
}

// Count (fill = false) or append light k to every cell it touches; this
// invocation takes the cells lane, lane + 32, ... of the light's box.
void insert(uint k, uint lane, bool fill) {
    Light L = lights[k];
    float r = L.b.w * (1.0 + 1e-4) + 1e-6 * length(L.a.xyz); // conservative against rounding
    if (!(r > 0.0)) return;
    vec3 c = grid_view(L.a.xyz);
    bool ortho = F.rx.w != 0.0;
    if (!ortho && c.z + r <= 0.0) return; // behind the eye
    uint C = cells(), cap = floatBitsToUint(PC.f3.w);
    // the tiles of the sphere's screen bounds: the box [c - r, c + r] in x/z (or y/z)
    uint t0[2], t1[2];
    for (int a = 0; a < 2; a++) {
        bool across = a == 0;
        float x = across ? c.x : c.y, s = across ? length(F.rx.xyz) : length(F.uy.xyz);
        float lo, hi;
        if (ortho) {
            lo = (x - r) / s, hi = (x + r) / s;
        } else if (c.z - r <= 1e-6 * r) {
            lo = -1e30, hi = 1e30; // reaches the eye plane: every tile
        } else {
            lo = min((x - r) / (c.z - r), (x - r) / (c.z + r)) / s;
            hi = max((x + r) / (c.z - r), (x + r) / (c.z + r)) / s;
        }
        uint ta = grid_tile_of(clamp(lo, -1e6, 1e6), across), tb = grid_tile_of(clamp(hi, -1e6, 1e6), across);
        t0[a] = min(ta, tb), t1[a] = max(ta, tb);
    }
    uint k0 = 0u, k1 = 0u;
    if (!TILED) k0 = grid_slice(c.z - r - PC.f3.x), k1 = grid_slice(c.z + r - PC.f3.x);
    float near = PC.f3.y, inv = 1.0 / PC.f3.z;
    uint nx = t1[0] - t0[0] + 1u, ny = t1[1] - t0[1] + 1u, n = nx * ny * (k1 - k0 + 1u);
    for (uint i = lane; i < n; i += 32u) {
        uint tx = t0[0] + i % nx, ty = t0[1] + (i / nx) % ny, ks = k0 + i / (nx * ny);
        float z0 = ks == 0u ? -1e30 : near * exp(float(ks - 1u) * inv);
        float z1 = ks + 1u >= PC.u2.z ? 1e30 : near * exp(float(ks) * inv);
        uint cell = (ks * PC.u2.y + ty) * PC.u2.x + tx;
        if (TILED) {
            z0 = uintBitsToFloat(cl[4u + 2u * C + 2u * cell]);
            z1 = uintBitsToFloat(cl[4u + 2u * C + 2u * cell + 1u]);
            if (z0 > z1) continue; // no hit in the tile
            z0 *= 1.0 - 1e-5, z1 *= 1.0 + 1e-5;
        }
        if (!touches(c, r, tx, ty, z0, z1)) continue;
        if (!fill) {
            atomicAdd(cl[4u + cell], 1u);
            continue;
        }
        uint at = cl[4u + C + cell] + atomicAdd(cl[4u + cell], 1u);
        if (at < cap) lidx[at] = k;
    }
}

void main() {
    uint C = cells(), id = gl_GlobalInvocationID.x;
    if (STEP == 0u) {
        if (id == 0u && PC.u0.x == 0u) cl[0] = 0u, cl[1] = 0u; // cl[1] keeps the largest need over the samples
        if (id >= C) return;
        cl[4u + id] = 0u;
        if (TILED) cl[4u + 2u * C + 2u * id] = 0x7F7FFFFFu, cl[4u + 2u * C + 2u * id + 1u] = 0u;
    } else if (STEP == 1u) {
        // one workgroup per tile (pipeline.c: tiles of 16 x 16 pixels)
        uint W = F.dims.x, n = W * F.dims.y;
        if (gl_LocalInvocationIndex == 0u) s_zmin = 0x7F7FFFFFu, s_zmax = 0u;
        barrier();
        uint T = PC.u2.w, tx = gl_WorkGroupID.x, ty = gl_WorkGroupID.y, tile = ty * PC.u2.x + tx;
        uint x = tx * T + gl_LocalInvocationIndex % T, y = ty * T + gl_LocalInvocationIndex / T;
        if (x < W && y < F.dims.y) {
            uint i = y * W + x;
            if (gb1[i].y != NO_HIT) {
                vec3 p = uintBitsToFloat(gb0[i].xyz);
                vec3 vw = grid_view(p);
                uint t = grid_tile(vw, false) * PC.u2.x + grid_tile(vw, true);
                uint z = floatBitsToUint(hit_depth(p));
                if (t == tile) {
                    atomicMin(s_zmin, z);
                    atomicMax(s_zmax, z);
                } else { // a jittered or lens ray whose hit lies in another tile
                    atomicMin(cl[4u + 2u * C + 2u * t], z);
                    atomicMax(cl[4u + 2u * C + 2u * t + 1u], z);
                }
            }
        }
        barrier();
        if (gl_LocalInvocationIndex == 0u && s_zmin <= s_zmax) {
            atomicMin(cl[4u + 2u * C + 2u * tile], s_zmin);
            atomicMax(cl[4u + 2u * C + 2u * tile + 1u], s_zmax);
        }
    } else if (STEP == 2u || STEP == 4u) {
        uint wg = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
        uint k = PC.u1.w + wg * 8u + gl_LocalInvocationIndex / 32u;
        if (k < PC.u1.z) insert(k, gl_LocalInvocationIndex % 32u, STEP == 4u);
    } else {
        // one workgroup: 256 contiguous chunks, their sums scanned in shared memory
        uint t = gl_LocalInvocationIndex, per = (C + 255u) / 256u;
        uint a = min(t * per, C), b = min(a + per, C), sum = 0u;
        for (uint c = a; c < b; c++) sum += cl[4u + c];
        s_sum[t] = sum;
        barrier();
        for (uint o = 1u; o < 256u; o <<= 1) {
            uint v = t >= o ? s_sum[t - o] : 0u;
            barrier();
            s_sum[t] += v;
            barrier();
        }
        uint run = s_sum[t] - sum; // exclusive
        for (uint c = a; c < b; c++) {
            uint n = cl[4u + c];
            cl[4u + C + c] = run;
            cl[4u + c] = 0u;
            run += n;
        }
        if (t == 255u) {
            uint cap = floatBitsToUint(PC.f3.w);
            cl[0] = min(s_sum[255], cap);
            if (s_sum[255] > cap) cl[1] = max(cl[1], s_sum[255]);
        }
    }
}
