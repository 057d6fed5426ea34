#version 450
// render/shaders/beam.comp - the beam pass of the primary rays (Laine &
// Karras 2010, section 6.1, made conservative): one invocation per block of
// BEAM x BEAM pixels finds a distance S before which no ray of the block can
// meet a non-empty node; trace.comp's primary rays of the block start their
// octree walk there. Float variant only; not used with LOD (a LOD ray stops
// at an inner node, which the beam does not bound).
//
// The block's rays leave the eye e along unit directions d within chord r1
// of the centre direction dc (|d - dc| <= r1, taken at the block's corners:
// the directions through a rectangle of the image plane lie within the
// largest corner angle), so the point at eye distance s of any of them lies
// within r1 s of e + s dc: inside the tube of radius r1 s around the centre
// ray. (Orthographic: parallel rays, a tube of constant radius.) The walk
// below takes the first s at which that tube meets a leaf, or a non-empty
// node no wider than the tube, each box grown by the tube's radius in every
// axis (a cube around the ball: conservative). Rounding is covered by a
// padded radius and by trace.comp starting slightly before S.
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

#define TRACE_BEAM
#define BEAM_PASS
#include "trace_common.glsl"

// binding 7-9: trace.comp's pixels, hits and (float64 variant) instances
layout(std430, binding = 10) writeonly buffer BeamOut { float beam_s[]; };

// the tube, world units: radius g_ra + g_rb t along o + t g_dir
vec3 g_dir;
float g_ra, g_rb;
// Iterations of the walk left for this block; past them the walk stops
// conservatively (a long walk costs more than the rays would save), and the
// size, in tube radii, of the nodes it stops at. Chosen on the H100 (issue
// 21): 64 and 4 beat 256 and 2 on every bench view.
#ifndef BEAM_ITER
#define BEAM_ITER 64
#endif
#ifndef BEAM_STOP
#define BEAM_STOP 4.0
#endif
int g_budget = BEAM_ITER;

// The tube (radius ra + rb t around o + t d) against boxes: per axis,
// (d + rb) t >= lo - ra - o and (d - rb) t <= hi + ra - o, each a lower or an
// upper bound on t by the sign of its factor (d + rb >= d - rb; a zero factor
// counts as +1e-30 resp. -1e-30, as safe_inv does: then the bound is +-huge,
// right in sign). Set up once per model; a box then costs two FMAs per face.
struct Tube { vec3 inv1, inv2, b1, b2; };

Tube tube_setup(vec3 o, vec3 d, float ra, float rb) {
    Tube T;
    vec3 a1 = d + rb, a2 = d - rb;
    for (int k = 0; k < 3; k++) {
        T.inv1[k] = 1.0 / (a1[k] >= 0.0 ? max(a1[k], 1e-30) : min(a1[k], -1e-30));
        T.inv2[k] = 1.0 / (a2[k] > 0.0 ? max(a2[k], 1e-30) : min(a2[k], -1e-30));
    }
    T.b1 = (o + ra) * T.inv1;
    T.b2 = (o - ra) * T.inv2;
    return T;
}

// Entry and exit t of the tube into [lo, hi] grown by its radius.
vec2 tube_box(Tube T, vec3 lo, vec3 hi) {
    vec3 t1 = lo * T.inv1 - T.b1, t2 = hi * T.inv2 - T.b2;
    vec3 tin = max(mix(vec3(-3.0e38), t1, greaterThan(T.inv1, vec3(0.0))), mix(vec3(-3.0e38), t2, lessThan(T.inv2, vec3(0.0))));
    vec3 tout = min(mix(vec3(3.0e38), t1, lessThan(T.inv1, vec3(0.0))), mix(vec3(3.0e38), t2, greaterThan(T.inv2, vec3(0.0))));
    return vec2(max(max(tin.x, tin.y), tin.z), min(min(tout.x, tout.y), tout.z));
}

vec2 scene_box(vec3 o, vec3 dinv, vec3 lo, vec3 hi) { return tube_box(tube_setup(o, g_dir, g_ra, g_rb), lo, hi); }

// Bit i of the result is bit i ^ mirror of the 8-bit mask m.
uint mirror_mask(uint m, uint mirror) {
    if ((mirror & 1u) != 0u) m = ((m & 0x55u) << 1) | ((m >> 1) & 0x55u);
    if ((mirror & 2u) != 0u) m = ((m & 0x33u) << 2) | ((m >> 2) & 0x33u);
    if ((mirror & 4u) != 0u) m = ((m & 0x0Fu) << 4) | ((m >> 4) & 0x0Fu);
    return m;
}

// The model walk (beam_walk.glsl, a template shared with the bake's beam
// pass over the compact layout, probes/shaders/probe_beam.comp) over the
// plain layout's node words: a node is its index (nbase: the model's first).
#define BW_NAME beam_model
#define BW_MODEL Model
#define BW_MODELS models
#define BW_NODE uint
#define BW_ROOT uint nbase = m.node_off; uint node = nbase + m.root, desc = nodes[node];
#define BW_IS_LEAF(desc, cbit) desc_is_leaf(desc, cbit)
#define BW_CHILD node = child_node(node, desc, cbit, nbase); desc = nodes[node];
#include "beam_walk.glsl"
void main() {
    uint W = F.dims.x, H = F.dims.y;
    uint bw = (W + BEAM - 1u) / BEAM, bh = (H + BEAM - 1u) / BEAM;
    uvec2 b = gl_GlobalInvocationID.xy;
    if (b.x >= bw || b.y >= bh) return;
    // the block's corners at pixel edges (any sample offset lies inside)
    float x0 = float(b.x * BEAM), x1 = float(min(b.x * BEAM + BEAM, W));
    float y0 = float(b.y * BEAM), y1 = float(min(b.y * BEAM + BEAM, H));
    vec2 u01 = vec2(x0, x1) / float(W) * 2.0 - 1.0, v01 = 1.0 - vec2(y0, y1) / float(H) * 2.0;
    float uc = 0.5 * (u01.x + u01.y), vc = 0.5 * (v01.x + v01.y);
    float t_start = F.fwd.w;
    vec3 o;
    float t0, t_off;
    g_ra = 0.0;
    g_rb = 0.0;
    if (F.rx.w != 0.0) {
        o = uc * F.rx.xyz + vc * F.uy.xyz;
        g_dir = F.fwd.xyz;
        t_off = t_start;
        t0 = 0.0;
        for (int k = 0; k < 4; k++) {
            vec3 q = u01[k & 1] * F.rx.xyz + v01[k >> 1] * F.uy.xyz;
            g_ra = max(g_ra, length(q - o));
        }
    } else {
        vec3 du = F.fwd.xyz + uc * F.rx.xyz + vc * F.uy.xyz;
        float len = length(du);
        g_dir = du / len;
        o = t_start * (uc * F.rx.xyz + vc * F.uy.xyz);
        t_off = t_start * len;
        t0 = -t_off; // from the eye: every ray of the block starts after it
        float r1 = 0.0;
        for (int k = 0; k < 4; k++)
            r1 = max(r1, length(normalize(F.fwd.xyz + u01[k & 1] * F.rx.xyz + v01[k >> 1] * F.uy.xyz) - g_dir));
        g_rb = r1;
        g_ra = r1 * t_off; // radius r1 s at eye distance s = t + t_off
    }
    Hit h;
    h.t = 3.0e38;
    h.inst = NO_HIT;
    trace_scene(o, g_dir, t0, false, h);
    // eye distance (orthographic: t from the image plane plus t_start)
    beam_s[b.y * bw + b.x] = h.t < 3.0e38 ? h.t + t_off : 3.0e38;
}
