#version 450
// render/shaders/refit.comp - one level of the instance BVH refit on the GPU
// (render/render_scene.c): each node of the level gets the bounds of what it
// holds, a leaf the union of its instances' boxes, an interior node the union
// of its two children (the level below, refit by the dispatch before). The
// boxes are relative to the frame's reference point, rounded outward to
// float on the host, so the unions (min and max) are exact and every box
// contains the double-precision one. The tree's shape (first, count) stays.
layout(local_size_x = 64) in;

struct BNode { vec3 lo; uint first; vec3 hi; uint count; }; // render.h vx_bvh_node
layout(std430, binding = 0) buffer Bvh { BNode bvh[]; };
layout(std430, binding = 1) readonly buffer Items { uint items[]; };
layout(std430, binding = 2) readonly buffer Boxes { vec4 boxes[]; }; // per instance: lo, hi
layout(std430, binding = 3) readonly buffer Order { uint order[]; };  // vx_bvh_levels
layout(push_constant) uniform Push {
    uint first; // the level's first entry of order
    uint count; // its nodes
} pc;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    uint n = order[pc.first + i];
    uint first = bvh[n].first, count = bvh[n].count;
    vec3 lo, hi;
    if (count != 0u) {
        lo = vec3(1.0 / 0.0), hi = vec3(-1.0 / 0.0);
        for (uint k = first; k < first + count; k++) {
            uint it = items[k];
            lo = min(lo, boxes[2u * it].xyz), hi = max(hi, boxes[2u * it + 1u].xyz);
        }
    } else {
        lo = min(bvh[first].lo, bvh[first + 1u].lo), hi = max(bvh[first].hi, bvh[first + 1u].hi);
    }
    bvh[n].lo = lo;
    bvh[n].hi = hi;
}
