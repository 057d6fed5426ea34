// render/shaders/pass_grid.glsl - included before trace_common.glsl by the pass kernels that trace (gbuffer,
// direct, ao, frame): models with a grid walk it as in trace.comp (grid_walk.glsl: the GRID constant, id 13;
// render/pipeline.c binds the grids at 24, past the passes' own 7-23), and a hit's record is always looked
// up (the passes read its materials and glass, which trace.comp's depth kernels do not).
#define TRACE_GRID
#define GRID_BINDING 24
#define GRID_RECORD_ALWAYS
