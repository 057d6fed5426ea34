#version 450
// probes/shaders/probe_beam.comp - the beam pass of the bake's camera rays (render/shaders/beam.comp's
// walk for a probe's texel blocks): one invocation per block of BLK x BLK texels of a probe's
// octahedral map finds a distance S before which no ray from the probe through the block can meet a
// non-empty node; probe.comp's bake then starts the block's camera rays' octree walk there (g_tskip:
// the walk's coefficients unchanged, so the same hits as from the probe, bit for bit).
//
// The block's directions: oct_decode maps each of the four triangles of a quadrant of the map
// (|u| + |v| <= 1 and >= 1) affinely onto a face of the octahedron |x| + |y| + |z| = 1, so the block's
// part in each triangle is a convex polygon there, and a direction's angle to the block's centre
// direction dc is quasi-convex on it (its sublevel sets are convex cones): the largest angle is at a
// polygon vertex, a block corner or a point where a block edge crosses the fold |u| + |v| = 1 (blocks
// never cross u = 0 or v = 0: BLK divides res / 2). Every ray of the block then lies within chord
// r1 = max |d - dc| of dc, and its point at distance s within r1 s of the probe's o + s dc: the tube
// of beam.comp with radius 0 + r1 s.
#extension GL_GOOGLE_include_directive : require

#include "beam_body.glsl" // beam.comp: trace_common.glsl (BEAM_PASS), beam_model, beam_s[] (binding 10)

layout(push_constant) uniform Push {
    uint res, blk, first, count; // map side, block side in texels, the batch's first probe, its probes
} PB;
layout(std430, binding = 9) readonly buffer Probes { vec4 probes[]; }; // xyz: position - reference, w: state

float sgn_b(float v) { return v < 0.0 ? -1.0 : 1.0; }
vec3 oct_dir(vec2 uv) { // probes/shaders/path_common.glsl's oct_decode
    vec3 p = vec3(uv, 1.0 - abs(uv.x) - abs(uv.y));
    if (p.z < 0.0) p.xy = vec2((1.0 - abs(uv.y)) * sgn_b(uv.x), (1.0 - abs(uv.x)) * sgn_b(uv.y));
    return normalize(p);
}

void main() {
    uint nb = PB.res / PB.blk, blocks = nb * nb;
    uint b = gl_GlobalInvocationID.x, slot = gl_GlobalInvocationID.y;
    if (b >= blocks || slot >= PB.count) return;
    uint at = slot * blocks + b;
    vec4 pr = probes[PB.first + slot];
    if (pr.w == 2.0) { // disabled: its texels are not traced
        beam_s[at] = 0.0;
        return;
    }
    uint bx = b % nb, by = b / nb;
    // the block's edges in the map's [-1, 1] coordinates (texel edges: every jittered sample inside)
    vec2 lo = vec2(float(bx * PB.blk), float(by * PB.blk)) * 2.0 / float(PB.res) - 1.0;
    vec2 hi = vec2(float((bx + 1u) * PB.blk), float((by + 1u) * PB.blk)) * 2.0 / float(PB.res) - 1.0;
    vec3 dc = oct_dir(0.5 * (lo + hi));
    float r1 = 0.0;
    for (int k = 0; k < 4; k++) r1 = max(r1, length(oct_dir(vec2((k & 1) != 0 ? hi.x : lo.x, (k >> 1) != 0 ? hi.y : lo.y)) - dc));
    // where the edges cross the fold su u + sv v = 1 (the block lies in one quadrant)
    vec2 mid = 0.5 * (lo + hi), s = vec2(sgn_b(mid.x), sgn_b(mid.y));
    for (int k = 0; k < 2; k++) {
        float u = k == 0 ? lo.x : hi.x, v = s.y * (1.0 - s.x * u); // edge u = const
        if (v >= lo.y && v <= hi.y) r1 = max(r1, length(oct_dir(vec2(u, v)) - dc));
        v = k == 0 ? lo.y : hi.y;
        u = s.x * (1.0 - s.y * v); // edge v = const
        if (u >= lo.x && u <= hi.x) r1 = max(r1, length(oct_dir(vec2(u, v)) - dc));
    }
    g_dir = dc;
    g_ra = 0.0;
    g_rb = r1 * 1.001 + 1e-6; // the directions' rounding (normalize) besides beam_model's own padding
    Hit h;
    h.t = 3.0e38;
    h.inst = NO_HIT;
    trace_scene(pr.xyz, g_dir, 0.0, false, h);
    beam_s[at] = h.t;
}
