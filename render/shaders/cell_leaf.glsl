// render/shaders/cell_leaf.glsl - the octree leaf that holds a cell, for the glass walks (the passes'
// pass_bodies.glsl glass_pass_walk, the path tracer's and the photons' probes/shaders/path_common.glsl
// glass_walk). Include after trace_common.glsl.

// The walks' step limit (render/trace.h vx__glass_walk_steps: the one rule for the CPU path tracer and
// every kernel): 12 sides of the cube of the model where the walk starts, at least 512.
uint glass_walk_steps(uint mi) {
    uint side = 1u << min(model_at(mi).depth, 21u);
    return max(12u * side, 512u);
}

// The first voxel along a + s d, s in [0, len), of an instance other than inst (g: its hit, t from a): inside
// a glass box the walks (path_common.glsl glass_walk, pass_bodies.glsl glass_pass_walk) look this way for a
// model placed overlapping the glass, which the glass's own model says nothing of; a ray from inside the glass
// would meet the glass itself at once, so inst is passed over (trace_common.glsl g_skip_inst).
bool other_instance_hit(uint inst, vec3 a, vec3 d, float len, out Hit g) {
    g.t = len;
    g.inst = NO_HIT;
    g.color = 0xFFFFFFFFu;
    g.attr = NO_HIT;
    g_iter = 0u;
    g_skip_inst = inst;
    bool met = trace_scene(a, d, 0.0, false, g);
    g_skip_inst = NO_HIT;
    return met;
}

#include "model_cell_leaf.glsl" // model_cell_leaf
