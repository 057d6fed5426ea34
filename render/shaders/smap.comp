#version 450
// render/shaders/smap.comp - the directional light's conservative depth map
// (render/shadow_map.c): per texel of the light's orthographic view, the
// largest light-space coordinate s (distance along the unit light
// direction, towards the light) of any octree node whose projection touches
// the texel. A shadow ray from p meets geometry only where s <= that
// maximum, so trace.comp ends its walk there.
//
// Two modes (push constant): 0 clears the texels, 1 adds the nodes. Each
// node is a cube of the model's cells [c, c + 2^level]^3; its instance's
// row maps model cells to (u, v) in texels and s in world units, so the
// box's projection is exactly the centre's image plus/minus |P| times the
// half side. The rectangle and s are widened by `margin` (world units, in
// the header), which covers the float rounding here and in the tracer's
// walk (shadow_map.c says why it suffices).
layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

struct Node { uint x, y, z, level; };
// pu, pv: texel coordinates from model cells; ps: s in world units;
// range: first node of the instance's model, its count, the instance's first
// work item (exclusive prefix of the counts), unused
struct SInst { vec4 pu, pv, ps; uvec4 range; };

layout(std430, binding = 0) readonly buffer Nodes { Node nodes[]; };
layout(std430, binding = 1) readonly buffer Insts { SInst si[]; };
// header (16 words, shadow_map.c writes it) then side * side texels
layout(std430, binding = 2) buffer Map { uint smap[]; };

layout(push_constant) uniform P {
    uint mode;   // 0 clear, 1 add nodes
    uint count;  // texels (mode 0) or work items (mode 1)
    uint insts;  // entries in si
    uint side;
    float margin_tex; // the margin in texels
    float margin;     // in world units
} pc;

const uint HDR = 16u;

// s as a uint whose order is the float order (0 is below every s: empty)
uint ordered(float f) {
    uint b = floatBitsToUint(f);
    return (b & 0x80000000u) != 0u ? ~b : (b | 0x80000000u);
}

void main() {
    uint id = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u;
    if (id >= pc.count) return;
    if (pc.mode == 0u) {
        smap[HDR + id] = 0u;
        return;
    }
    // the instance whose work items hold id (the last with range.z <= id)
    uint lo = 0u, hi = pc.insts;
    while (hi - lo > 1u) {
        uint mid = (lo + hi) / 2u;
        if (si[mid].range.z <= id) lo = mid; else hi = mid;
    }
    SInst I = si[lo];
    Node n = nodes[I.range.x + (id - I.range.z)];
    float h = 0.5 * exp2(float(n.level));
    vec3 c = vec3(n.x, n.y, n.z) + h;
    float u = dot(I.pu.xyz, c) + I.pu.w, v = dot(I.pv.xyz, c) + I.pv.w, s = dot(I.ps.xyz, c) + I.ps.w;
    float hu = dot(abs(I.pu.xyz), vec3(h)) + pc.margin_tex;
    float hv = dot(abs(I.pv.xyz), vec3(h)) + pc.margin_tex;
    float smax = s + dot(abs(I.ps.xyz), vec3(h)) + pc.margin;
    int side = int(pc.side);
    int u0 = int(clamp(floor(u - hu), 0.0, float(side - 1)));
    int u1 = int(clamp(floor(u + hu), 0.0, float(side - 1)));
    int v0 = int(clamp(floor(v - hv), 0.0, float(side - 1)));
    int v1 = int(clamp(floor(v + hv), 0.0, float(side - 1)));
    uint w = ordered(smax);
    for (int y = v0; y <= v1; y++)
        for (int x = u0; x <= u1; x++) atomicMax(smap[HDR + uint(y * side + x)], w);
}
