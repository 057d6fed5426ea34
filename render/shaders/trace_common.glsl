// render/shaders/trace_common.glsl - the scene's bindings 0-6 (and 9 in the
// PRECISE variant) and the traversal: BVH over instances, then each model's
// octree in the manner of Laine & Karras. Included by trace.comp and
// probe.comp; layouts must match render/render_internal.h.
#ifdef PRECISE
#define REAL double
#define RVEC2 dvec2
#define RVEC3 dvec3
#else
#define REAL float
#define RVEC2 vec2
#define RVEC3 vec3
#endif

layout(constant_id = 0) const int MODE = 0;          // vx_render_mode
layout(constant_id = 1) const bool HAS_COLOR = true; // some model has attributes
layout(constant_id = 2) const bool USE_BVH = true;   // more than one instance
layout(constant_id = 3) const bool LOD = false;
layout(constant_id = 4) const bool WRITE_HITS = false;
// Float variant, deep models (issue 18; see trace_model): 0 none (the plain
// loop), 1 some model is exact (Model flag 2: a hit's t from its cube's entry
// planes), 2 also some model has Model.rebase > 0 (the hi/lo origin and the
// walk in two frames). The pipeline sets it (render_scene.c does for
// trace.comp) from the scene's deepest model, so that kernels of shallow
// scenes keep the plain loop and those of 9-10 level models pay only at hits.
layout(constant_id = 8) const int DEEP = 0;
const bool REBASE = DEEP >= 2;
#if defined(TRACE_GRID) && !defined(PRECISE)
// grid_walk.glsl's GRID (declared here, where inst_at and model_at read its bit 4, GRID_UNION)
layout(constant_id = 13) const uint GRID = 0u;
#endif
#if defined(TRACE_GRID_UBO) && !defined(PRECISE)
// trace.comp's kernel of one instance walks the union of a converter's regions (grid_walk.glsl): its
// instance and model records (index 0xFFFFFFFF) are the frame block's, a hit's instance and model insts'
// and models' (render_scene.c grid_union)
const bool GRID_UNION = (GRID & 16u) != 0u && !USE_BVH;
#else
const bool GRID_UNION = false;
#endif
// Some model may hold a far pointer (render_scene.c sets it off where none
// can: the far bit's test on every push cost 2-5% on the H200, issue 21).
layout(constant_id = 9) const bool FAR = true;
// The scene is in the compact layout (render/compact.h, issue 18): bindings
// 1-3 are then its geometry slots, attribute words and palette + CModel
// records (compact_gpu.c), the walk reads slots (trace_model's node load and
// push), and a hit's colour is decoded from its cell's attribute index;
// Hit.attr is then the material id where the layout carries the models'
// ids (CModel flag 8), else the palette index (the per-record tables are per
// id or palette index, vx__render_scene_attr_material; compact_attr.glsl
// ca_table_index). Float variant only.
// COMPACT_FORM (vx__render_scene_compact_form): 0 plain, 1 compact, 2
// compact with the brick dictionary (else the index words' path is dead).
#ifdef PRECISE
const uint COMPACT_FORM = 0u;
#else
layout(constant_id = 10) const uint COMPACT_FORM = 0u;
#endif
const bool COMPACT = COMPACT_FORM != 0u;
// The push's child bits in the GPU form (desc_gpu_form below): from one
// shift of the descriptor (MASKS false: 3-6.5% more primary rays on the
// H200 than main's masks on the file's form), or tested in place with the
// child's bit (true: 1.5-3% faster than the shift where FAR is on). The
// rebased walk's colour kernel (REBASE, MODE 0: two walks, primary and
// shadow rays) turns each descriptor it loads back into the file's form and
// runs main's masks on it (FILE_FORM): reading the GPU form, that kernel of
// terrain4096 (DEEP 2, FAR) got 96 registers on the H200 (its stack arrays
// in registers; 56-64 with them forced into local memory) against 48 with
// the turn, and traced 0.51-0.57 of the file form's primary + shadow rays
// (0.88 at 56 registers).
// The rebased walk's other kernels (the depth kernel, one walk) read the GPU
// form as it is: the same registers, terrain4096's close-up 1.3% more
// primary rays than with the turn, its oblique and overview within 1%
// (issue 21, fifteenth and seventeenth sittings: docs/PERFORMANCE.md).
// NODES_FILE (set by gpu_pipeline.c for every pipeline from the device,
// gpu.h's nodes_file): the node buffer holds the file's form (CPU devices:
// lavapipe traced 0.55-0.75 of main's rate with any of the GPU form's loops,
// even main's loop with only the turn at the load, sixteenth sitting), and
// every path below is then main's: FILE_FORM without the turn at the load,
// the desc_* readers on the file's masks.
layout(constant_id = 100) const bool NODES_FILE = false;
#ifdef PRECISE
const bool FILE_FORM = NODES_FILE;
#else
const bool FILE_FORM = (REBASE && MODE == 0) || NODES_FILE; // MODE 0: MODE_COLOR below
#endif
// the loop's descriptors are the file's but the buffer's the GPU form
const bool TURN_LOAD = FILE_FORM && !NODES_FILE;
const bool MASKS = FAR || FILE_FORM;

const int MODE_COLOR = 0, MODE_ALBEDO = 1, MODE_NORMAL = 2, MODE_DEPTH = 3, MODE_INSTANCE = 4, MODE_ITER = 5;
// trace.comp's colour kernel (primary and shadow rays) marks an unloaded
// node by desc 0 rather than by a flag (a node word is never 0): 1-4% faster
// there on the H200, 2-4% slower in the depth kernel (issue 21). Other
// kernels that include this file keep the flag.
#ifdef TRACE_SENTINEL
const bool SENT = MODE == MODE_COLOR;
#else
const bool SENT = false;
#endif
const int S_MAX = 23;
const uint ROOT_EMPTY = 0xFFFFFFFFu, ROOT_LEAF = 0xFFFFFFFEu, NO_HIT = 0xFFFFFFFFu;
const uint MAX_ITER = 100000u;

// flags: 1 has colours; 2 exact (DEEP kernels): a hit's t computed from its
// cube's entry planes, with the origin kept as hi/lo where DEEP is 2 (trace_model)
// box: the extent in units of 2^max(depth - 10, 0) cells, rounded up, minus
// one, 10 bits per axis (render_internal.h)
struct Model { uint node_off, color_off, depth, root, root_attr, flags, rebase, box; };
#include "compact_attr.glsl"

// lo.xyz: the translations' rounding errors (r0.w + lo.x is the model-space
// x of the frame reference to about 2^-48 relative)
struct Inst { vec4 r0, r1, r2; uint model; float cell; uint id; float pad; vec4 lo; };
struct BNode { vec4 lo; vec4 hi; };
#ifdef TRACE_PATH
// A start below the root (vx__gpu_path): info.x the depth dx of node X,
// .y X's word (model-relative), .z the model; cube: X's cube ([1,2] units
// of the model cube: corner xyz, side w); nodes: X's ancestors, the root
// first
struct PathRec { uvec4 info; vec4 cube; uvec4 nodes[6]; };
const int PATHS = 64;
// The starts on (render_scene.c: off on CPU devices, where lavapipe (Mesa
// 22.3), which runs every instruction of the kernel masked for every ray,
// traced 0.45-0.65 of the rays per CPU second with them, the start's code
// never taken included; issue 21's fourteenth sitting)
layout(constant_id = 7) const bool PATH_START = true;
#endif

layout(std140, binding = 0) uniform Frame {
    vec4 fwd;   // w: t_start
    vec4 rx;    // w: ortho
    vec4 uy;    // w: lod footprint per unit distance
    vec4 light; // w: ambient
    vec4 misc;  // x: lod footprint at distance 0, y: lod pixels
    uvec4 dims; // width, height, spp, instance count
    uvec4 dims2;
    vec4 grid_lo;
#ifdef PRECISE
    dvec4 pfwd; // w: t_start
    dvec4 prx;
    dvec4 puy;
#endif
#if defined(TRACE_INST_UBO) && !defined(PRECISE)
    // a scene of one instance (!USE_BVH; vx__gpu_frame): instance 0's record
    // and its model's, read through inst_at and model_at. lavapipe loads a
    // storage buffer's word lane by lane even at a constant index (per
    // 8-lane group, 8 scalar loads and their bounds tests), a uniform
    // block's once: 19 words a ray (issue 21's eleventh sitting)
    layout(offset = 224) Inst inst0;
    Model model0;
#endif
#ifdef TRACE_CULL
    // trace.comp: the pixels [rect.x, rect.z) x [rect.y, rect.w) that the
    // trace pass covers (vx__gpu_frame.rect)
    layout(offset = 336) uvec4 rect;
#endif
#ifdef TRACE_TILES
    // trace.comp, several instances: the primary rays' BVH start per screen
    // tile (vx__frame_tiles), 16 bits each, 0xFFFF none; tile_info.x the
    // tiles' shift, .y tiles a row (vx__gpu_frame.tiles)
    layout(offset = 352) uvec4 tile_info;
    layout(offset = 368) uvec4 tiles[128];
#endif
#ifdef TRACE_PATH
    // trace.comp, one instance: the primary rays' starts below the root
    // (trace_model), per screen tile the index of one (tiles, 0xFFFF none)
    layout(offset = 2480) PathRec paths[PATHS]; // after trace_compact.comp's cmodel0 (vx__gpu_frame)
#endif
#ifdef TRACE_GRID_UBO
    // trace.comp, one instance: its model's grid (grid_walk.glsl): grid0 its word address (NO_HIT: none), its
    // cells' box (the grid's header) as floats, so that a ray loads neither (vx__gpu_frame.gbox_lo, grid0,
    // gbox_hi; std140 packs a vec3 and the word after it in one 16 bytes)
    layout(offset = 10672) vec3 gbox_lo;
    uint grid0;
    vec3 gbox_hi;
    uint gunion; // the union of regions' cube table (GRID_UNION)
#endif
} F;
layout(std430, binding = 1) readonly buffer Nodes { uint nodes[]; };
layout(std430, binding = 2) readonly buffer Colors { uint colors[]; };
layout(std430, binding = 3) readonly buffer Models { Model models[]; };
layout(std430, binding = 4) readonly buffer Insts { Inst insts[]; };
layout(std430, binding = 5) readonly buffer Bvh { BNode bvh[]; };
layout(std430, binding = 6) readonly buffer BvhItems { uint items[]; };
#ifndef PRECISE
// the compact layout's views of bindings 1-3 (COMPACT)
layout(std430, binding = 1) readonly buffer CGeom { uvec2 cslots[]; };
layout(std430, binding = 2) readonly buffer CAttr { uint cattr[]; };
layout(std430, binding = 3) readonly buffer CModels { uint cpalette[256]; CModel cmodels[]; };
#define CA_SLOT(i) cslots[i]
#define CA_ATTR(i) cattr[i]
#define CA_PAL(i) cpalette[i]
#define CA_PAGES 0u
#define CA_DICT (COMPACT_FORM == 2u)
#define CA_UNI true
#include "compact_attr.glsl"
#endif
// Model mi's record in either layout (COMPACT: from its CModel, with no
// node or colour offsets: the kernels that read those fields read the plain
// layout only). Kernels read models[] through this.
Model model_at(uint mi) {
#ifndef PRECISE
#ifdef TRACE_INST_UBO
    if (!USE_BVH && !COMPACT && (!GRID_UNION || mi == 0xFFFFFFFFu)) return F.model0;
#endif
    if (COMPACT) {
        CModel c = cmodels[mi];
        return Model(0u, 0u, c.depth, c.root, 0u, c.flags, c.rebase, c.box);
    }
#endif
    return models[mi];
}
// Instance i's record (TRACE_INST_UBO: from the frame block in a scene of
// one instance; kernels without it read insts[] as they did)
#ifdef TRACE_INST_UBO
Inst inst_at(uint i) {
#ifndef PRECISE
    if (!USE_BVH && (!GRID_UNION || i == 0xFFFFFFFFu)) return F.inst0;
#endif
    return insts[i];
}
#define INST_AT(i) inst_at(i)
#else
#define INST_AT(i) insts[i]
#endif
#ifdef PRECISE
// model-from-world rows (world relative to the frame reference), 3 per instance
layout(std430, binding = 9) readonly buffer PInsts { dvec4 pinst[]; };
#endif

struct Hit {
    REAL t;       // world distance from the ray origin
    uint inst;    // instance slot, NO_HIT for none
    uvec3 cell;
    int axis;     // entry face axis
    float nsign;  // model-space normal = nsign * e_axis
    uint color;
    uint attr;    // index into colors[] of the hit's attribute, NO_HIT without
};

uint g_iter = 0u;
// An instance slot trace_scene passes over (NO_HIT: none): the glass walks'
// look for other instances' voxels inside a glass box (probes/shaders/
// path_common.glsl glass_walk, pass_bodies.glsl glass_pass_walk), where a ray
// from inside the glass would meet the glass itself at once. Kernels that
// never set it test a constant.
uint g_skip_inst = NO_HIT;
#ifdef TRACE_PATH
// The start below the root (F.paths) the next model walk may take: a
// primary ray's (trace.comp), 0xFFFF none
uint g_path = 0xFFFFu;
#endif
// The iteration guard (MAX_ITER) and count. trace.comp's colour kernel
// (primary and shadow rays) has neither where it writes no hits: 1-5% more
// pixels/s on the H200 (issue 21); its advance then compares the crossing
// times as !(tc > tc_max), so that a NaN time steps every axis and the ray
// still leaves the root. Other kernels that include this file keep both.
// The lean walk (TRACE_LEAN: trace.comp's kernels and the pass pipeline's
// G-buffer, gbuffer.comp and frame.comp; GPU form, no hits or ids, no LOD,
// DEEP 0 or 1): the primary depth kernel's loop fits 32
// registers on the H200 (64 warps per SM) where main's took 39 (50 warps),
// 2-3% more primary rays/s (issue 21, twentieth sitting); the colour kernel
// (primary and shadow rays) went from 45 (DEEP 0; 46 DEEP 1) to 40
// registers (42 to 50 warps), 2.6-6% more pixels/s, gbuffer.comp from 48 to
// 40, frame.comp stayed at 40 with 4-6% less time (lean2, twenty-first
// sitting). Its parts: no iteration guard (GUARD below), scale_exp2 taken
// from scale at the loop's top rather than carried around it, every push
// storing its parent (no hh); and in a primary walk (not any_hit) no test of
// the ray's end at a push (the model's box holds every cell, so a push past
// the box's exit finds none; t1 is h.t's initial 3e38 with one instance;
// only a ray leaving the box within rounding of a cell edge on its face, a
// tie, might be decided otherwise than main's walk decides it); trace.comp
// forms the pixel's index before the walk. Each alone kept the depth kernel
// at 36-39 registers and cost 1-6%; the cells, depths and colours are main's
// (render_bench: 0 px differ; svo_render's images byte for byte). trace.comp's
// BVH kernels (several instances; TRACE_LEAN_BVH) too, but for the ray-end
// test at a push (below: there t1 is the nearest hit so far, and without the
// test a tie between two instances' faces went the other way,
// test_many_instances): registers as main's (48 depth, 64 colour), 2-4.7%
// more primary rays/s on the H200's multi-instance oblique and close-up
// (issue 21, ray8). DEEP 1 (exact models): the same loop; the hit's t comes
// from its cube's entry planes after it, as before. The compact layout's
// G-buffer (COMPACT) too (issue 18, lean3: 0-3.5% less time a frame on the
// H200), so that both layouts' G-buffers make the same decisions by
// construction; trace_compact.comp keeps only its DEEP 0 push, the part
// that paid there (its LEAN).
// (the choice by the preprocessor: glslang 12 wrote invalid SPIR-V, an
// undefined id, for a const bool combined with the spec constants here)
// trace.comp's rebased walk (DEEP 2) too (TRACE_LEAN_DEEP2): scale_exp2 is
// 2^(scale - S_MAX) in both of its frames, and the rebased frame's ray end
// is the model frame's, scaled. terrain4096's depth kernel 56 -> 48
// registers, 5.7-7.3% more primary rays/s on the H200 (issue 21, ray8). But
// not in the colour kernel (MODE_COLOR: primary and shadow rays): with the
// lean walk its registers stayed at 48 and it traced 0.8-1% fewer pixels/s
// on terrain4096; with the full walk 1.0-1.2% more than with the lean one
// on its close-up and oblique (its overview 0.6-1.8% fewer, within that
// view's spread), the same pixels (issue 21, deep3). (LEAN_DEEP_MAX a const int of its own:
// folded into LEAN's expression, glslang wrote an undefined id again)
#if defined(TRACE_LEAN_DEEP2) && defined(TRACE_LEAN_DEEP2_COLOR)
const int LEAN_DEEP_MAX = 2; // the G-buffer kernels (MODE_COLOR without shadow rays: gbuffer.comp, frame.comp)
#elif defined(TRACE_LEAN_DEEP2)
const int LEAN_DEEP_MAX = MODE == MODE_COLOR ? 1 : 2;
#else
const int LEAN_DEEP_MAX = 1;
#endif
#if defined(TRACE_LEAN) && !defined(PRECISE) && defined(TRACE_LEAN_BVH)
const bool LEAN = MODE != MODE_ITER && !WRITE_HITS && !LOD && DEEP <= LEAN_DEEP_MAX && !NODES_FILE;
#elif defined(TRACE_LEAN) && !defined(PRECISE)
// (the G-buffer's BVH kernels: not measured with the lean walk)
const bool LEAN = MODE != MODE_ITER && !WRITE_HITS && !USE_BVH && !LOD && DEEP <= 1 && !NODES_FILE;
#else
const bool LEAN = false;
#endif
#ifdef TRACE_NOGUARD
const bool GUARD = (MODE != MODE_COLOR || WRITE_HITS) && !LEAN;
#else
const bool GUARD = !LEAN; // (the iteration count is the hits' and ids', which LEAN excludes)
#endif

#ifdef TRACE_BEAM
// Beam optimization (trace.comp and beam.comp, float variant only): beam.comp
// finds per block of BEAM x BEAM pixels the first distance at which any ray
// of the block could meet a non-empty node; trace.comp's primary rays then
// start their octree walk at g_tskip (world t) with unchanged coefficients,
// so the cells and depths are those of the walk from the ray's start.
layout(constant_id = 5) const uint BEAM = 0u; // block side in pixels; 0: off
float g_tskip = 0.0;
#endif

bool sign_neg(float x) { return (floatBitsToUint(x) >> 31) != 0u; }

// CELL_HITS (probe.comp's bake kernels, float variant): a hit is found in a cell-level leaf in every
// layout. The plain layout's leaves can be whole cubes of cells (a subtree of one colour), the compact
// layout's geometry is cut by other rules (its 4^3 bricks hold single cells; colours do not split it),
// so the same solid cube is one leaf in one layout and a subtree in the other; where a ray meets it
// within float rounding of an edge (the walk's crossing times lose 2^(depth - 23) of a cell), the
// leaf's hit and the subtree's walk picked different cells, faces or distances (issue 18: svo_bake
// --load models against --load whole, 1,840 of 105.6 M .probes bytes on the H200). With CELL_HITS a
// leaf above the cell level is walked as a node whose children are all leaves (no loads), down to the
// cell, and no push tests the child's exit (as the DEEP and compact walks), so both layouts' walks make
// the same float operations on the same cubes from the first solid cube down, and agree bit for bit.
// (a macro, not a constant: without it the other kernels' SPIR-V is main's, byte for byte)
#if defined(CELL_HITS) && !defined(PRECISE)
#define CELL_WALK
#endif
#ifdef PRECISE
bool sign_neg(double x) { return (unpackDouble2x32(x).y >> 31) != 0u; }
#endif

// WALK_PRECISE (the kernels of cmake/shaders.cmake's VX_WALK_PRECISE_KERNELS, which says why; probe.comp's render
// kernel through PT_PRECISE): every float operation of the walk precise (no contraction into fused multiply-adds:
// the NVIDIA compiler contracted the walk's crossing times differently in two variants of that kernel, issue 21,
// and in the plain and the compact layout's pipelines of one kernel, issue 18); elsewhere the walk is as it was
#ifdef WALK_PRECISE
#define WPREC precise
#else
#define WPREC
#endif

// The child of the root cube where the walk starts (and restarts): the octants whose mid-planes
// the ray has crossed by tmin (idx, pos); T is the type of the crossing times. Under WALK_PRECISE
// the crossing times are computed once, precise; otherwise per axis, as the kernels always did.
#ifdef WALK_PRECISE
#define WALK_FIRST_CHILD(T) { \
    precise T tmid = 1.5 * coef - bias; \
    if (tmid.x > tmin) { idx ^= 1; pos.x = 1.5; } \
    if (tmid.y > tmin) { idx ^= 2; pos.y = 1.5; } \
    if (tmid.z > tmin) { idx ^= 4; pos.z = 1.5; } }
#else
#define WALK_FIRST_CHILD(T) \
    if (1.5 * coef.x - bias.x > tmin) { idx ^= 1; pos.x = 1.5; } \
    if (1.5 * coef.y - bias.y > tmin) { idx ^= 2; pos.y = 1.5; } \
    if (1.5 * coef.z - bias.z > tmin) { idx ^= 4; pos.z = 1.5; }
#endif

// 1/d without infinities: a zero (or denormal) component becomes +-1e30 with
// its sign, so that (plane - o) * inv is never 0 * inf = NaN and a ray lying
// in a slab plane counts as displaced towards the sign of its component.
RVEC3 safe_inv(RVEC3 d) {
    WPREC RVEC3 r;
    for (int i = 0; i < 3; i++)
        r[i] = abs(d[i]) < 1e-30 ? (sign_neg(d[i]) ? -1e30 : 1e30) : 1.0 / d[i];
    return r;
}

// Ray/box slab test: (t entry, t exit).
RVEC2 box_t(RVEC3 o, RVEC3 rd_inv, RVEC3 lo, RVEC3 hi) {
    WPREC RVEC3 a = (lo - o) * rd_inv, b = (hi - o) * rd_inv;
    RVEC3 tn = min(a, b), tf = max(a, b);
    return RVEC2(max(max(tn.x, tn.y), tn.z), min(min(tf.x, tf.y), tf.z));
}

// The GPU form of a descriptor (issue 21): the plain layout's node buffer
// holds every descriptor with its low byte the INNER mask (valid and not
// leaf), where the file's holds the leaf mask (render_scene.c's upload
// transforms them: vx__render_desc_gpu). Bits 8-31 are the file's (valid
// mask, far bit, pointer). So child c (its bit cbit = 1 << c) is valid where
// desc & (cbit << 8), inner where desc & cbit, a leaf where valid and not
// inner, and its block entry counts the inner bits below cbit: in the walk
// one shift, desc << (7 - c), puts c's valid bit at 15, its inner bit at 7
// and the inner children below it in bits 0-6 (the paper's child_masks,
// with the octant order of the file's blocks). Every GLSL reader of the
// plain node buffer reads descriptors through these; a descriptor built in
// the file's form (the compact layout's slots, compact_attr.glsl) is turned
// into this form with desc_gpu_form where the walk reads it.
// With NODES_FILE the buffer holds the file's form and these read its
// masks (main's expressions).
uint desc_gpu_form(uint d) { return (d & 0xFFFFFF00u) | ((d >> 8) & ~d & 0xFFu); }
bool desc_valid(uint desc, uint cbit) { return (desc & (cbit << 8)) != 0u; }
bool desc_inner(uint desc, uint cbit) { return (NODES_FILE ? (desc >> 8) & ~desc & cbit : desc & cbit) != 0u; }
bool desc_is_leaf(uint desc, uint cbit) {
    return NODES_FILE ? (desc & cbit) != 0u : (desc & ((cbit << 8) | cbit)) == (cbit << 8);
}
uint desc_inner_count(uint desc) { return uint(bitCount((NODES_FILE ? (desc >> 8) & ~desc : desc) & 0xFFu)); }
uint desc_inner_below(uint desc, uint cbit) {
    return uint(bitCount((NODES_FILE ? (desc >> 8) & ~desc : desc) & (cbit - 1u)));
}

// The node index of inner child cbit (1 << octant) of node `parent` with
// descriptor desc (GPU form; absolute indices; far pointers are
// model-relative, nbase the model's first node): the children's block, then
// the inner children below cbit.
uint child_node(uint parent, uint desc, uint cbit, uint nbase) {
    uint blk = parent - (desc >> 17);
    if (FAR && (desc & 0x10000u) != 0u) blk = nbase + nodes[blk];
    return blk + desc_inner_below(desc, cbit);
}
// The same for a descriptor in the file's form (trace_model's FILE_FORM).
uint child_node_file(uint parent, uint desc, uint cbit, uint nbase) {
    uint blk = parent - (desc >> 17);
    if (FAR && (desc & 0x10000u) != 0u) blk = nbase + nodes[blk];
    return blk + uint(bitCount((desc >> 8) & ~desc & (cbit - 1u)));
}

#ifndef PRECISE
#include "entry_tau.glsl"

// three floats from the walk's stack slots i, i+1, i+2
#define SLOTS3(i) vec3(intBitsToFloat(stk_node[i]), intBitsToFloat(stk_node[(i) + 1]), intBitsToFloat(stk_node[(i) + 2]))
#endif

#ifdef TRACE_STACK_SELECTS
// The walk's stack as a ladder of selects (trace.comp, float variant): on CPU
// devices (NODES_FILE) every access to stk_node is at a constant index, so
// the compiler keeps the array in registers. The ladder covers every index
// the walk can push: a model of depth D pushes at S_MAX - D + 1 to S_MAX - 1,
// in the rebased walk too (a depth-k frame's entries sit k below their frame
// scale, i.e. at the model frame's); so DEEP 0 (depth <= VX_RENDER_EXACT_DEPTH
// 8) from S_MAX - 7, DEEP 1 (<= VX_RENDER_REBASE_DEPTH 10) from S_MAX - 9, and
// DEEP 2 from S_MAX - 20, for VX_RENDER_MAX_DEPTH 21: the float variant traces
// models past VX_RENDER_PRECISE_DEPTH 16 where it is forced
// (vx__render_scene_force_precise, render_bench --variant float). A DEEP 2
// ladder sized for 16 levels (S_MAX - 15 up) dropped the pushes of models of
// 17-21 levels and popped to the wrong nodes, on lavapipe too (test_deep_octrees'
// float record 381 -> 17141 of 69120 pixels off the reference, not asserted;
// the H200 with VX_GPU_NODE_FORM=file showed it as beam-against-none
// differences) (issue 21, eighteenth sitting). The exact models' slots 0-5
// (DEEP 1) and the rebased walk's past S_MAX are at constant indices.
// lavapipe (Mesa 22.3) writes a per-lane index of an array in memory lane by
// lane, each lane a load, a select that LLVM makes a branch on the lane's
// mask, and a store, and reads it lane by lane: on an AVX2 CPU a third of the
// depth kernel's time. The ladder (DEEP 0: 7 selects a push, 6 a pop) cost
// 1.5-1.8x fewer CPU seconds a ray on an AVX2 CPU, 1.02-1.22x with AVX-512
// (masked stores) (issue 21, seventeenth sitting). GPUs (NODES_FILE false)
// keep the array in memory. test_render_gpu's test_stack_levels (depths 7 to
// 21) fails with a ladder one level short.
const bool STK_REG = NODES_FILE;
const int STK_LO = S_MAX - (DEEP == 0 ? 7 : DEEP == 1 ? 9 : 20);
// STK_PUT / STK_GET: stack_ladder.glsl (one text with trace_compact.comp's);
// the two switches keep this walk's SPIR-V as it was (slots 3 up, all guarded)
#define STK_LADDER_DEEP
#define STK_LADDER_GUARD_ALL
#include "stack_ladder.glsl"
#endif

// Traces model space ray o + t d (t in world units, d not normalised)
// through model mi over [t0, t1]. Returns true and fills h on a hit. o_lo is
// the rounding error of o (float variant; the rebased walk reads it).
//
// Rebased walk (float variant, REBASE and Model.rebase = k > 0): in the
// [1,2] cube a float keeps 23 - depth bits below a cell, and the crossing
// times pos * coef - bias lose as many to the cancellation against bias
// (|bias| ~ 1.5 |coef|), so at depth 16 a cell decision and the depth were
// off by up to 2^-7 of a cell (issue 18). When the walk descends into a node
// N at depth k, it moves into N's frame: N becomes the [1,2] cube, the
// origin the point of the ray at N's entry t_r (computed from the origin kept
// as a hi/lo pair, exact products and sums, so the new origin is right to
// 2^-24 of N), t' = (t - t_r) 2^k. Below N the walk then keeps 23 - (depth - k)
// bits; above, 23 - k bits of a depth-k node. When the walk leaves N (a pop
// past N's cube) it goes back to the model frame at N's level, stepping out
// of N through the faces the rebased walk found. The stack entries of the
// rebased walk sit k below their scale, below those of the model frame's
// levels; the state for going back lives in the stack array's slots past
// S_MAX (local memory, touched once per node of depth k). k is
// depth - VX_RENDER_FRAME_LEVELS (render/render.h): the lower frame as deep as
// its precision allows, so that its nodes are wide and a ray rarely moves
// between frames. Exact models (Model flag 2, deeper than
// VX_RENDER_EXACT_DEPTH, rebased or not) also take a hit's t from its cube's
// entry planes against the frame's origin, not from the walk's crossing
// times (after the loop).
// The hit child cs's attribute record in the plain layout (parent: its
// node's block, desc: its descriptor; the records' word follows the block's
// inner children): one text for the hit after the loop and the cell walk's
// leaf above the cell level (CELL_WALK), so they cannot drift. A macro, not a
// function, so that both sites compile to the SPIR-V they had.
#define HIT_ATTR_REC                                                                                     \
    {                                                                                                    \
        uint valid = (desc >> 8) & 0xFFu;                                                                \
        uint blk = parent - (desc >> 17);                                                                \
        if (FAR && (desc & 0x10000u) != 0u) blk = nbase + nodes[blk];                                    \
        uint a = nodes[blk + (FILE_FORM ? uint(bitCount(valid & ~(desc & 0xFFu))) : desc_inner_count(desc))]; \
        attr_rec = a + uint(bitCount(valid & ((1u << cs) - 1u)));                                        \
        have_attr = true;                                                                                \
    }

bool trace_model(uint mi, RVEC3 o, vec3 o_lo, RVEC3 d, REAL t0, REAL t1, bool any_hit, float lod_a, float lod_b, inout Hit h) {
    Model m = model_at(mi);
    if (m.root == ROOT_EMPTY) return false;
    REAL side = REAL(exp2(float(m.depth)));
    // Advance to the model's box first so that the [1,2] coordinates keep
    // the model's precision even when the origin is far away. The box is the
    // model's extent (Model.box, rounded up to 2^(depth - 10) cells), often
    // smaller than the 2^depth cube: rays that meet only the cube's empty
    // rest are culled here, the others start and end the walk on the box.
    uint bsh = m.depth > 10u ? m.depth - 10u : 0u;
    uvec3 bq = (uvec3(m.box, m.box >> 10, m.box >> 20) & 1023u) + 1u;
    RVEC2 tb = box_t(o, safe_inv(d), RVEC3(0.0), RVEC3(bq << bsh));
    REAL te = max(tb.x, t0);
    REAL tx = min(tb.y, t1);
    if (!(te < tx)) return false;
#ifdef PRECISE
    RVEC3 oa = o + d * te;
    REAL sc = 1.0 / side;
    RVEC3 ol = clamp(1.0 + oa * sc, RVEC3(1.0), RVEC3(2.0));
#else
    WPREC vec3 oa, ol, ol_lo = vec3(0.0), oa_lo = vec3(0.0);
    float sc = 1.0 / side;
    bool exact = DEEP >= 1 && (m.flags & 2u) != 0u;
    if (REBASE && exact) {
        // oa + oa_lo: o + o_lo + d te with the product's and the sum's
        // rounding errors kept (fma gives the product's exactly)
        precise vec3 pr = d * te;
        precise vec3 pe = fma(d, vec3(te), -pr);
        precise vec3 oas = o + pr;
        precise vec3 bb = oas - o;
        precise vec3 se = (o - (oas - bb)) + (pr - bb);
        precise vec3 oal = o_lo + (pe + se);
        precise vec3 ols = clamp(1.0 + oas * sc, vec3(1.0), vec3(2.0));
        // ol - 1 and oa * sc - (ol - 1) are exact (Sterbenz; sc a power of 2)
        precise vec3 oll = (oas * sc - (ols - 1.0)) + oal * sc;
        oa = oas, oa_lo = oal, ol = ols, ol_lo = oll;
    } else {
        oa = o + d * te;
        ol = clamp(1.0 + oa * sc, vec3(1.0), vec3(2.0));
    }
#endif
    WPREC RVEC3 dl = d * sc;
    WPREC REAL L = length(dl);
    dl /= L;
    WPREC REAL tl1 = (tx - te) * L;

    // Tiny components would make the coefficients overflow; replace them
    // with +-2^-23 keeping the sign (so -0 stays "negative"). In double,
    // +-2^-40: the ray then drifts at most 2^-39 over the cube (2^-18 of a
    // depth-21 cell) and |coef * pos| stays below 2^42, far from overflow.
#ifdef PRECISE
    const double eps = 1.0LF / 1099511627776.0LF;
#else
    const float eps = exp2(-float(S_MAX));
#endif
    if (abs(dl.x) < eps) dl.x = sign_neg(dl.x) ? -eps : eps;
    if (abs(dl.y) < eps) dl.y = sign_neg(dl.y) ? -eps : eps;
    if (abs(dl.z) < eps) dl.z = sign_neg(dl.z) ? -eps : eps;
    WPREC RVEC3 coef = 1.0 / -abs(dl);
    WPREC RVEC3 bias = coef * ol;
    int oct = 7;
    if (dl.x > 0.0) { oct ^= 1; bias.x = 3.0 * coef.x - bias.x; }
    if (dl.y > 0.0) { oct ^= 2; bias.y = 3.0 * coef.y - bias.y; }
    if (dl.z > 0.0) { oct ^= 4; bias.z = 3.0 * coef.z - bias.z; }
#ifndef PRECISE
    // the rebased walk: koff = k while in a depth-k node's frame, else 0;
    // rb_scale the scale of a depth-k cube in the model frame (-100 while
    // rebased: no second rebase)
    int koff = 0;
    int rb_scale = (REBASE && m.rebase > 0u) ? S_MAX - int(m.rebase) : -100;
#endif

    WPREC REAL tmin = max(max(2.0 * coef.x - bias.x, 2.0 * coef.y - bias.y), 2.0 * coef.z - bias.z);
    WPREC REAL tmax = min(min(coef.x - bias.x, coef.y - bias.y), coef.z - bias.z);
    WPREC REAL hh = tmax;
    tmin = max(tmin, 0.0);
    tmax = min(tmax, tl1);
#ifdef TRACE_BEAM
    if (BEAM > 1u) {
        // no cell before g_tskip holds anything (beam.comp): start there
        tmin = max(tmin, (g_tskip - te) * L);
        if (!(tmin <= tmax)) return false;
    }
#endif
#ifdef PRECISE
    const int RB_SLOTS = 0;
#else
    // the rebased walk's stack slots past S_MAX: mirrored origin hi and lo,
    // the walk's start, N's cube, N's parent, the ray's end in the model
    // frame, |dl|, the model frame's bias, t_r. State the loop needs only at
    // a rebase, on the way back or after the loop lives here rather than in
    // registers (they bound the kernel's occupancy).
#ifdef TRACE_PATH
    // (+ the primary ray's start below N, trace_model's TRACE_PATH block: X,
    // the scale of X's children and K's corner in N's frame)
    const int RB_SLOTS = 33;
#else
    const int RB_SLOTS = 28;
#endif
    const int RB_OHI = S_MAX, RB_OLO = S_MAX + 3, RB_T0 = S_MAX + 6, RB_POS = S_MAX + 7, RB_PARENT = S_MAX + 10,
              RB_TMAX = S_MAX + 11, RB_ADL = S_MAX + 12, RB_BIAS = S_MAX + 15, RB_TBASE = S_MAX + 18,
              RB_OALO = S_MAX + 19, RB_JX = S_MAX + 28, RB_JS = S_MAX + 29, RB_JPOS = S_MAX + 30;
    // exact models: the box entry point oa and the direction d for the hit's
    // t, kept in memory rather than in registers across the loop: in slots
    // 0-5 where DEEP is 1 (its models, at most VX_RENDER_REBASE_DEPTH deep,
    // push no deeper than stk_node[S_MAX - 10])
    const int OA = REBASE ? S_MAX + 22 : 0, DM = OA + 3;
#endif

    WPREC RVEC3 pos = RVEC3(1.0);
    int scale = S_MAX - 1;
    WPREC REAL scale_exp2 = 0.5;
    bool hit = false;
    uint attr_rec = 0u;
    bool have_attr = false;

    int stk_node[S_MAX + (REBASE ? RB_SLOTS : 0)];
#ifdef CELL_WALK
    // inside a leaf above the cell level (its cube all solid): the nodes' descriptor (every child valid,
    // none inner; the file's form: the low byte the leaf mask) and no loads
    bool virt = false;
    const uint FULL_DESC = FILE_FORM ? 0xFFFFu : 0xFF00u;
    if (false) { // (a root leaf is walked as a full node below)
#else
    if (m.root == ROOT_LEAF) {
#endif
        if (tmin <= tmax) {
            hit = true;
            scale = S_MAX;
            scale_exp2 = 1.0;
            attr_rec = m.root_attr;
            have_attr = true;
        }
    } else {
        // Without contours a child's span ends at min(ray end, its cube's
        // exit) (a cube's exit is never later than its parent's, in float
        // too: pos * coef - bias is monotonic in pos), so the stack holds
        // parents only and tmax stays the ray's end.
        uint nbase = m.node_off; // node indices below are absolute (far pointers are model-relative)
        uint parent = nbase + m.root;
        int oct7 = oct ^ 7;
        uint desc = 0u;
        bool loaded = false;
#ifdef CELL_WALK
        if (m.root == ROOT_LEAF) {
            // a root leaf: the model's cube walked as a full node (its record is the hit's)
            virt = true, desc = FULL_DESC, loaded = true, parent = 0u;
            attr_rec = m.root_attr, have_attr = true;
        }
#endif
#ifndef PRECISE
        // COMPACT: the slot of the node at parent (level >= 2; a level-1
        // node is an octant of its brick, parent the brick's slot), and the
        // level of the node at scale s: s + lvl_off - koff
        uvec2 cnd = uvec2(0u);
        int lvl_off = int(m.depth) - (S_MAX - 1);
#endif
        int idx = 0;
        WALK_FIRST_CHILD(RVEC3)
#if defined(TRACE_PATH) && !defined(PRECISE)
        // (the switch's state, below: declared here for the path start, and
        // below in the other kernels, whose SPIR-V stays as it was)
        int pending = 0, rb_step = 0;
        uint rb_cbit = 0u;
#endif
#ifdef TRACE_PATH
        // A primary ray whose walk starts at a point well inside the cube
        // of K, a child of node X (F.paths[g_path], the host's guess for
        // the ray's screen tile), descends from the root to X without an
        // advance: every push's child is the one holding the start (tmin is
        // 0 here: the walk's [1,2] ray starts at ol). Its state at X's loop
        // top is then known: X, K's mirrored corner and octant, X's
        // ancestors on the stack (hh, the root's exit, only makes the next
        // push store its entry where the walk might not, the same value).
        // 2^-16 of the model cube between the start and K's faces keeps
        // every decision of the skipped pushes (crossing times of the
        // mid-planes and the exits against tmin; rounding errors below
        // 2^-20 of |coef|) the walk's, so the steps from X on are the
        // walk's, bit for bit; a start on the root cube's entry face (the
        // mirrored 2) needs none on that side, its planes being K's and
        // its ancestors' far sides. Not with LOD (a push may stop), the
        // beam (tmin moved), the compact layout or the float64 variant.
        if (PATH_START && g_path != 0xFFFFu && !USE_BVH && !LOD && !COMPACT && BEAM <= 1u && tmin == 0.0 && tmin <= tmax &&
            mi == F.paths[g_path].info.z) {
            const float dlt = 1.0 / 65536.0;
            vec3 cc = F.paths[g_path].cube.xyz;
            float cw = F.paths[g_path].cube.w;
            // mirrored (exact: 3 - x for x in [1, 2]): the start, X's corner
            // and that of K, the child of X holding the start
            bvec3 keep = bvec3((oct & 1) != 0, (oct & 2) != 0, (oct & 4) != 0);
            vec3 om = mix(3.0 - ol, ol, keep);
            vec3 px = mix(3.0 - cw - cc, cc, keep);
            cw *= 0.5;
            vec3 pk = mix(px, px + cw, greaterThanEqual(om, px + cw));
            vec3 top = mix(pk + (cw - dlt), vec3(3.0), equal(pk + cw, vec3(2.0)));
            if (all(greaterThan(om, pk + dlt)) && all(lessThan(om, top))) {
                int dx = int(F.paths[g_path].info.x);
                for (int j = 0; j < dx; j++) stk_node[S_MAX - 1 - j] = int(nbase + F.paths[g_path].nodes[j >> 2][j & 3]);
                parent = nbase + F.paths[g_path].info.y;
                scale = S_MAX - 1 - dx;
                scale_exp2 = cw;
                pos = pk;
                ivec3 sh = floatBitsToInt(pos) >> scale;
                idx = (sh.x & 1) | ((sh.y & 1) << 1) | ((sh.z & 1) << 2);
#ifndef PRECISE
                if (REBASE && scale < rb_scale) {
                    // X at depth k or below (in the frame of its depth-k
                    // ancestor N): the walk would push to N in the model
                    // frame and switch into N's frame there (pending 1).
                    // Start at that switch instead, so that it runs before
                    // the loop (its code, the same arithmetic, from N's
                    // corner pos and N's parent), and continue below N as
                    // above: X, K's corner in N's frame (exact: pk and N's
                    // corner lie on K's grid, the scale a power of 2). The
                    // start is 2^-16 of the model cube inside K, 2^(k-16)
                    // of N's, far above the rebased frame's rounding (the
                    // hi/lo origin's few 2^-23 of N's cube), so the pushes
                    // skipped below N hold the start too. N's word sits in
                    // its slot as a parent (depth k's: X's when dx == k),
                    // where N's walk would store it.
                    int k = S_MAX - rb_scale;
                    stk_node[S_MAX - 1 - dx] = int(parent);
                    stk_node[RB_JX] = int(parent), stk_node[RB_JS] = scale + k;
                    vec3 pn = intBitsToFloat((floatBitsToInt(pk) >> rb_scale) << rb_scale); // N's corner
                    vec3 pj = 1.0 + (pk - pn) * intBitsToFloat((127 + k) << 23);
                    stk_node[RB_JPOS] = floatBitsToInt(pj.x), stk_node[RB_JPOS + 1] = floatBitsToInt(pj.y);
                    stk_node[RB_JPOS + 2] = floatBitsToInt(pj.z);
                    parent = uint(stk_node[S_MAX - k]); // N's parent, at depth k - 1
                    pos = pn;
                    scale_exp2 = intBitsToFloat((127 - k) << 23);
                    scale = S_MAX; // past the loop, to the switch
                    pending = 1, rb_cbit = 0u;
                }
#endif
            }
        }
#endif
#ifndef PRECISE
        if (exact) {
            stk_node[OA] = floatBitsToInt(oa.x), stk_node[OA + 1] = floatBitsToInt(oa.y);
            stk_node[OA + 2] = floatBitsToInt(oa.z);
            stk_node[DM] = floatBitsToInt(d.x), stk_node[DM + 1] = floatBitsToInt(d.y);
            stk_node[DM + 2] = floatBitsToInt(d.z);
        }
        if (REBASE && exact) {
            stk_node[RB_OALO] = floatBitsToInt(oa_lo.x), stk_node[RB_OALO + 1] = floatBitsToInt(oa_lo.y);
            stk_node[RB_OALO + 2] = floatBitsToInt(oa_lo.z);
        }
        if (REBASE && rb_scale > 0) {
            // mirrored origin (3 - ol on mirrored axes, exact) and its error
            vec3 olm = ol, olm_lo = ol_lo;
            if ((oct & 1) == 0) { olm.x = 3.0 - ol.x; olm_lo.x = -ol_lo.x; }
            if ((oct & 2) == 0) { olm.y = 3.0 - ol.y; olm_lo.y = -ol_lo.y; }
            if ((oct & 4) == 0) { olm.z = 3.0 - ol.z; olm_lo.z = -ol_lo.z; }
            stk_node[RB_OHI] = floatBitsToInt(olm.x), stk_node[RB_OHI + 1] = floatBitsToInt(olm.y);
            stk_node[RB_OHI + 2] = floatBitsToInt(olm.z);
            stk_node[RB_OLO] = floatBitsToInt(olm_lo.x), stk_node[RB_OLO + 1] = floatBitsToInt(olm_lo.y);
            stk_node[RB_OLO + 2] = floatBitsToInt(olm_lo.z);
            stk_node[RB_T0] = floatBitsToInt(tmin);
            vec3 adl = abs(dl);
            stk_node[RB_ADL] = floatBitsToInt(adl.x), stk_node[RB_ADL + 1] = floatBitsToInt(adl.y);
            stk_node[RB_ADL + 2] = floatBitsToInt(adl.z);
        }
        // the two-frame walk's switches run outside the walk's loop, so that
        // their code and registers stay out of it: 1 into the depth-k child
        // rb_cbit of parent (0: the path start's N, trace.comp), 2 out of N
        // through the faces rb_step
#ifndef TRACE_PATH
        int pending = 0, rb_step = 0;
        uint rb_cbit = 0u;
#endif
        while (true) {
#endif
        while (scale < S_MAX) {
            if (GUARD) g_iter++;
#ifndef PRECISE
            if (LEAN) scale_exp2 = uintBitsToFloat(uint(scale - S_MAX + 127) << 23); // not carried
#endif
            if (SENT ? desc == 0u : !loaded) {
#ifndef PRECISE
                if (COMPACT) {
                    // a level-1 node is loaded only as a depth-1 model's root: a push
                    // below a brick's level 2 takes the octant from cnd (no load)
                    int lvl = scale + lvl_off - koff;
                    cnd = cslots[parent];
                    desc = lvl >= 3 ? cnd.x : (lvl == 2 ? brick_desc(cnd) : brick_octant(cnd, 0u));
                    if (!FILE_FORM) desc = desc_gpu_form(desc);
                } else
#endif
                {
                    desc = nodes[parent];
                    if (TURN_LOAD) desc = desc_gpu_form(desc); // its own inverse: back to the file's form
                }
                loaded = true;
            }
            WPREC RVEC3 tc = pos * coef - bias;
            WPREC REAL tc_max = min(min(tc.x, tc.y), tc.z);
            int cs = idx ^ oct7; // real octant: mirrored axes flipped
            // no test of the ray's end (a primary ray in the model's box; not with
            // several instances, where h.t is another instance's hit: the test
            // decides a tie between two instances' faces as main's walk does)
            bool lean = LEAN && !any_hit && !USE_BVH;
#ifdef PRECISE
            // the mask form below made the NVIDIA compiler give the float64
            // depth kernel 80 registers instead of 64 (20% slower on the H100)
            uint valid = (desc >> 8) & 0xFFu;
            uint inner = (FILE_FORM ? valid & ~desc : desc) & 0xFFu; // the inner mask (NODES_FILE: from the file's)
            if (((valid >> cs) & 1u) != 0u && tmin <= tmax) {
#else
            // desc (GPU form) shifted by 7 - cs (= idx ^ oct): child cs's
            // valid bit at 15, its inner bit at 7, the inner children below
            // it in bits 0-6 (the paper's child_masks); MASKS: the bits
            // tested in place instead (cbit)
            uint cbit = 1u << cs;
            uint cm = desc << uint(idx ^ oct);
            bool push = (MASKS ? desc & (cbit << 8) : cm & 0x8000u) != 0u && tmin <= tmax;
            if (lean) push = (MASKS ? desc & (cbit << 8) : cm & 0x8000u) != 0u;
            if (push) {
#endif
                WPREC REAL tv_max = lean ? tc_max : min(tmax, tc_max);
                WPREC REAL half_ = scale_exp2 * 0.5;
                WPREC RVEC3 tcen = half_ * coef + tc;
                // The DEEP kernels skip the test against the child's exit
                // (tmin lies in the child by construction, as in the ESVO
                // loop; tmin <= tmax is tested): 2-5% faster there on the
                // H200, 1-2% slower in the plain kernel, which keeps it. The
                // compact walk skips it in DEEP 0 too, as trace_compact.comp's
                // (docs/PERFORMANCE.md issue 18, sixteenth and seventeenth steps).
#ifdef CELL_WALK
                if (true) {
#else
                if (DEEP >= 1 || COMPACT || tmin <= tv_max) {
#endif
#ifdef PRECISE
                    bool is_leaf = ((inner >> cs) & 1u) == 0u;
#else
                    bool is_leaf = FILE_FORM ? (desc & cbit) != 0u : (MASKS ? desc & cbit : cm & 0x80u) == 0u;
#endif
                    bool stop = is_leaf;
                    if (LOD && !stop) {
                        // world footprint of a pixel at this distance, in [1,2] units
#ifdef PRECISE
                        REAL tw = te + tmin / L;
                        stop = (lod_a + lod_b * tw) * L >= scale_exp2;
#else
                        float us = intBitsToFloat((127 - koff) << 23); // 2^-koff
                        float tbase = REBASE && koff != 0 ? intBitsToFloat(stk_node[RB_TBASE]) : 0.0;
                        WPREC float tw = te + (tbase + tmin * us) / L;
#ifdef WALK_PRECISE
                        precise float lw = (lod_a + lod_b * tw) * L, lc = scale_exp2 * us;
                        stop = lw >= lc;
#else
                        stop = (lod_a + lod_b * tw) * L >= scale_exp2 * us;
#endif
#endif
                    }
#ifdef CELL_WALK
                    if (stop && scale - koff > S_MAX - int(m.depth)) {
                        // a leaf above the cell level: walked as a full node. Its attribute
                        // record is the hit's (the plain layout's; found here, before the
                        // descriptor is the full node's)
                        if (!virt && HAS_COLOR && !any_hit && !COMPACT && (m.flags & 1u) != 0u) {
                            HIT_ATTR_REC
                        }
                        virt = true;
                        stop = false;
                    }
#endif
                    if (stop) {
                        // the attribute record is found after the loop
                        hit = true;
                        break;
                    }
#ifndef PRECISE
                    if (REBASE && scale == rb_scale) {
                        // into node N at depth k: after the loop
                        pending = 1, rb_cbit = cbit;
                        break;
                    }
#endif
                    // push
#ifdef PRECISE
                    if (tc_max < hh) stk_node[scale] = int(parent);
#else
                    bool store = LEAN ? true : tc_max < hh;
                    if (store) {
#ifdef TRACE_STACK_SELECTS
                        if (STK_REG) STK_PUT(scale - koff, int(parent))
                        else
#endif
                        stk_node[scale - koff] = int(parent);
                    }
#endif
                    hh = tc_max;
#ifdef PRECISE
                    uint blk = parent - (desc >> 17);
                    if (FAR && (desc & 0x10000u) != 0u) blk = nbase + nodes[blk];
                    parent = blk + uint(bitCount(inner & ((1u << cs) - 1u)));
#else
                    bool keep = false; // COMPACT below level 2: the octant's descriptor, no load
#ifdef CELL_WALK
                    if (virt) {
                        desc = FULL_DESC, keep = true;
                    } else
#endif
                    if (COMPACT) {
                        // the child's slot is in the block cnd.y (level >= 3); below a
                        // brick's level 2 the child is octant cs of the brick in cnd
                        // (level 3: through the brick's index word)
                        int plvl = scale + lvl_off - koff;
                        uint below = FILE_FORM ? (desc >> 8) & ~desc & (cbit - 1u) : (MASKS ? desc & (cbit - 1u) : cm & 0x7Fu);
                        if (plvl >= 3) parent = ca_child(plvl, desc, cnd.y, uint(bitCount(below)));
                        else desc = FILE_FORM ? brick_octant(cnd, uint(cs)) : desc_gpu_form(brick_octant(cnd, uint(cs))), keep = true;
                    } else if (FILE_FORM) {
                        parent = child_node_file(parent, desc, cbit, nbase);
                    } else {
                        uint blk = parent - (desc >> 17);
                        if (FAR && (desc & 0x10000u) != 0u) blk = nbase + nodes[blk];
                        parent = blk + uint(bitCount(MASKS ? desc & (cbit - 1u) : cm & 0x7Fu));
                    }
#endif
                    idx = 0;
                    scale--;
                    scale_exp2 = half_;
                    if (tcen.x > tmin) { idx ^= 1; pos.x += scale_exp2; }
                    if (tcen.y > tmin) { idx ^= 2; pos.y += scale_exp2; }
                    if (tcen.z > tmin) { idx ^= 4; pos.z += scale_exp2; }
#ifdef PRECISE
                    loaded = false; if (SENT) desc = 0u;
#else
                    loaded = keep; if (SENT && !keep) desc = 0u;
#endif
                    continue;
                }
            }
            // advance; the iteration guard is checked here only: pushes are
            // bounded by the depth, and a ray past the guard is a miss below
            if (GUARD && g_iter > MAX_ITER) break;
            int step = 0;
            if (GUARD ? tc.x <= tc_max : !(tc.x > tc_max)) { step ^= 1; pos.x -= scale_exp2; }
            if (GUARD ? tc.y <= tc_max : !(tc.y > tc_max)) { step ^= 2; pos.y -= scale_exp2; }
            if (GUARD ? tc.z <= tc_max : !(tc.z > tc_max)) { step ^= 4; pos.z -= scale_exp2; }
            tmin = tc_max;
            idx ^= step;
            if ((idx & step) != 0) {
                // pop: the highest differing position bit is the common ancestor's level
#ifdef PRECISE
                // the path bits are the integer offsets of pos from 1 in units
                // of 2^-23 (exact; negative once the ray leaves the root, whose
                // sign bit then differs, so findMSB >= S_MAX)
                ivec3 ip = ivec3((pos - 1.0) * 8388608.0);
                ivec3 iq = ip + (1 << scale);
                uint diff = 0u;
                if ((step & 1) != 0) diff |= uint(ip.x ^ iq.x);
                if ((step & 2) != 0) diff |= uint(ip.y ^ iq.y);
                if ((step & 4) != 0) diff |= uint(ip.z ^ iq.z);
                scale = findMSB(diff);
                if (scale >= S_MAX) break;
                scale_exp2 = double(1 << scale) / 8388608.0;
                parent = uint(stk_node[scale]);
                ivec3 sh = ip >> scale;
                pos = 1.0 + dvec3(sh << scale) / 8388608.0;
                idx = (sh.x & 1) | ((sh.y & 1) << 1) | ((sh.z & 1) << 2);
                hh = 0.0;
                loaded = false; if (SENT) desc = 0u;
#else
                uint diff = 0u;
                if ((step & 1) != 0) diff |= floatBitsToUint(pos.x) ^ floatBitsToUint(pos.x + scale_exp2);
                if ((step & 2) != 0) diff |= floatBitsToUint(pos.y) ^ floatBitsToUint(pos.y + scale_exp2);
                if ((step & 4) != 0) diff |= floatBitsToUint(pos.z) ^ floatBitsToUint(pos.z + scale_exp2);
                scale = findMSB(diff);
                if (REBASE && scale >= S_MAX && koff != 0) {
                    // out of the rebased node N: after the loop
                    pending = 2, rb_step = step;
                    break;
                }
                if (scale >= S_MAX) break;
                scale_exp2 = uintBitsToFloat(uint(scale - S_MAX + 127) << 23);
#ifdef TRACE_STACK_SELECTS
                if (STK_REG) STK_GET(scale - koff, parent)
                else
#endif
                parent = uint(stk_node[scale - koff]);
                ivec3 sh = floatBitsToInt(pos) >> scale;
                pos = intBitsToFloat(sh << scale);
                idx = (sh.x & 1) | ((sh.y & 1) << 1) | ((sh.z & 1) << 2);
                hh = 0.0;
                loaded = false; if (SENT) desc = 0u;
#endif
            }
        }
#ifndef PRECISE
            if (!REBASE || pending == 0) break;
            if (pending == 1) {
                // into node N at depth k (the cube pos): rebase
                vec3 tc = pos * coef - bias;
                stk_node[RB_POS] = floatBitsToInt(pos.x), stk_node[RB_POS + 1] = floatBitsToInt(pos.y);
                stk_node[RB_POS + 2] = floatBitsToInt(pos.z);
                stk_node[RB_PARENT] = int(parent);
                stk_node[RB_TMAX] = floatBitsToInt(tmax);
                stk_node[RB_BIAS] = floatBitsToInt(bias.x), stk_node[RB_BIAS + 1] = floatBitsToInt(bias.y);
                stk_node[RB_BIAS + 2] = floatBitsToInt(bias.z);
                // t_r: N's entry; q: the mirrored ray point at t_r
                // relative to N's corner, (olm + olm_lo - pos) - |dl| t_r
                // with the rounding errors of the product and sum kept
                vec3 tent = scale_exp2 * coef + tc;
                float tr = max(max(tent.x, tent.y), tent.z);
                vec3 olm = SLOTS3(RB_OHI);
                vec3 olm_lo = SLOTS3(RB_OLO);
                precise vec3 adl = SLOTS3(RB_ADL);
                precise vec3 pr = adl * tr;
                precise vec3 pe = fma(adl, vec3(tr), -pr);
                precise vec3 a = olm - pos; // exact: both in [1,2]
                precise vec3 sq = a - pr;
                precise vec3 bb = sq - a;
                precise vec3 se = (a - (sq - bb)) - (pr + bb);
                precise vec3 q = sq + ((se - pe) + olm_lo);
#ifdef TRACE_PATH
                int k = S_MAX - rb_scale; // (scale at a push's switch; past the loop for the path start's)
#else
                int k = S_MAX - scale;
#endif
                float sk = intBitsToFloat((127 + k) << 23); // 2^k
                vec3 qn = 1.0 + q * sk;
                bias = coef * qn;
                float t0n = (intBitsToFloat(stk_node[RB_T0]) - tr) * sk;
                float entn = max(max(2.0 * coef.x - bias.x, 2.0 * coef.y - bias.y), 2.0 * coef.z - bias.z);
                tmin = max(entn, t0n);
                tmax = (tmax - tr) * sk;
                hh = min(min(coef.x - bias.x, coef.y - bias.y), coef.z - bias.z);
                stk_node[RB_TBASE] = floatBitsToInt(tr);
                koff = k;
                rb_scale = -100;
                // N (level >= 3 in COMPACT): its slot is in the block cnd.y
                // (desc in the file's form where FILE_FORM, else the GPU form)
#ifdef TRACE_PATH
                if (rb_cbit == 0u) {
                    // the path start's N: on at X, K's corner in N's frame
                    parent = uint(stk_node[RB_JX]);
                    scale = stk_node[RB_JS];
                    scale_exp2 = intBitsToFloat((scale - S_MAX + 127) << 23);
                    pos = SLOTS3(RB_JPOS);
                    ivec3 sh = floatBitsToInt(pos) >> scale;
                    idx = (sh.x & 1) | ((sh.y & 1) << 1) | ((sh.z & 1) << 2);
                } else
#endif
                {
#ifdef CELL_WALK
                    if (virt)
                        ; // N lies in a leaf: a full node (parent unused)
                    else
#endif
                    if (FILE_FORM)
                        parent = COMPACT ? cnd.y + uint(bitCount((desc >> 8) & ~desc & (rb_cbit - 1u)))
                                         : child_node_file(parent, desc, rb_cbit, nbase);
                    else
                        parent = COMPACT ? cnd.y + uint(bitCount(desc & (rb_cbit - 1u))) : child_node(parent, desc, rb_cbit, nbase);
                    idx = 0;
                    scale = S_MAX - 1;
                    scale_exp2 = 0.5;
                    pos = vec3(1.0);
                    WALK_FIRST_CHILD(vec3)
                }
                loaded = false; if (SENT) desc = 0u;
#ifdef CELL_WALK
                if (virt) desc = FULL_DESC, loaded = true;
#endif
                pending = 0;
                continue;
            }
            // out of N through the faces step: back to the model frame at
            // N's level, the same step there
            int step = rb_step;
            pending = 0;
            uint diff;
            float us = intBitsToFloat((127 - koff) << 23); // 2^-k
            tmin = intBitsToFloat(stk_node[RB_TBASE]) + tmin * us;
            tmax = intBitsToFloat(stk_node[RB_TMAX]);
            pos = SLOTS3(RB_POS);
            parent = uint(stk_node[RB_PARENT]);
            scale = S_MAX - koff;
            scale_exp2 = us;
            ivec3 nb = (floatBitsToInt(pos) >> scale) & 1;
            idx = nb.x | (nb.y << 1) | (nb.z << 2);
            bias = SLOTS3(RB_BIAS);
            rb_scale = scale;
            koff = 0;
            hh = 0.0;
            loaded = false; if (SENT) desc = 0u;
            diff = 0u;
            if ((step & 1) != 0) { diff |= floatBitsToUint(pos.x) ^ floatBitsToUint(pos.x - us); pos.x -= us; }
            if ((step & 2) != 0) { diff |= floatBitsToUint(pos.y) ^ floatBitsToUint(pos.y - us); pos.y -= us; }
            if ((step & 4) != 0) { diff |= floatBitsToUint(pos.z) ^ floatBitsToUint(pos.z - us); pos.z -= us; }
            idx ^= step;
            if ((idx & step) == 0) {
                // into a sibling N' of N
#ifdef TRACE_PATH
                // (trace.comp) where N' is an inner child the loop's next step would push into
                // it and leave the loop again to switch into its frame (pending 1): take that
                // step here, the same decisions on the same values (N''s valid and leaf bits,
                // tmin <= tmax unless lean), and go to the switch without re-entering the loop
                if (!LOD && !COMPACT) {
                    uint dp = nodes[parent];
                    if (TURN_LOAD) dp = desc_gpu_form(dp);
                    desc = dp, loaded = true;
                    int cs = idx ^ oct7;
                    uint cbit = 1u << cs;
                    uint cm = dp << uint(idx ^ oct);
                    bool lean = LEAN && !any_hit && !USE_BVH;
                    bool push = (MASKS ? dp & (cbit << 8) : cm & 0x8000u) != 0u && (lean || tmin <= tmax);
                    bool is_leaf = FILE_FORM ? (dp & cbit) != 0u : (MASKS ? dp & cbit : cm & 0x80u) == 0u;
                    if (push && !is_leaf) {
                        if (GUARD) g_iter++;
                        pending = 1, rb_cbit = cbit;
                        scale = S_MAX; // past the loop, to the switch
                    }
                }
#endif
                continue;
            }
            scale = findMSB(diff);
            if (scale >= S_MAX) break;
            scale_exp2 = uintBitsToFloat(uint(scale - S_MAX + 127) << 23);
#ifdef TRACE_STACK_SELECTS
            if (STK_REG) STK_GET(scale, parent)
            else
#endif
            parent = uint(stk_node[scale]);
            ivec3 sh = floatBitsToInt(pos) >> scale;
            pos = intBitsToFloat(sh << scale);
            idx = (sh.x & 1) | ((sh.y & 1) << 1) | ((sh.z & 1) << 2);
            hh = 0.0;
            loaded = false; if (SENT) desc = 0u;
        }
#endif
        if (scale >= S_MAX || g_iter > MAX_ITER) hit = false;
#ifdef CELL_WALK
        if (virt) {
            // the record found at the leaf (or the root leaf's)
        } else
#endif
        if (hit && !any_hit && HAS_COLOR && !COMPACT && (m.flags & 1u) != 0u) {
            // the hit child's attribute record (after the loop: code in the
            // loop runs masked on every step on SIMD CPUs such as lavapipe;
            // shadow rays, any_hit, need none)
            int cs = idx ^ oct7;
            HIT_ATTR_REC
        }
    }
    if (!hit) return false;
#ifdef PRECISE
    REAL troot = tmin;
#else
    float us = intBitsToFloat((127 - koff) << 23); // 2^-k in a rebased frame, else 1
    float tbase = REBASE && koff != 0 ? intBitsToFloat(stk_node[RB_TBASE]) : 0.0; // t_r
    WPREC float troot = tbase + tmin * us;        // model frame [1,2] units
#endif
    WPREC REAL t = te + troot / L;
#ifdef PRECISE
    const bool exact = false;
#endif
    if (!exact || any_hit) {
        if (!(t <= h.t)) return false;
        if (any_hit) { h.t = t; return true; }
    }

    // entry face: the cube's entry planes in mirrored space are its max corners
    // No vector is indexed by a variable below: with per-pixel hits in the
    // depth mode the NVIDIA compiler (driver 580, H100) turned the dynamic
    // component accesses (c[axis] = ..., d[axis], p[axis]) into code that
    // never finished for some pixels of a 1920x1080 frame (issue 21);
    // explicit selects compute the same cell.
    // An axis the ray runs along (|dl| at eps: -coef at 1 / eps) crosses none of the cube's planes, so it is
    // never the entry's, as in the CPU reference (render/cpu_trace.c: -inf): axis-parallel rays through cell
    // centres had tent of the parallel axis first and took its face's normal (test_render_gpu
    // test_axis_rays_on_edges' normals, stop 87)
    WPREC RVEC3 tent = (pos + scale_exp2) * coef - bias;
    bvec3 par = greaterThanEqual(-coef, RVEC3(1.0 / eps));
    int axis = par.x ? (par.y ? 2 : 1) : 0; // the first axis the ray crosses (d is not 0)
    REAL ta = axis == 0 ? tent.x : (axis == 1 ? tent.y : tent.z);
    if (!par.y && tent.y > ta) { axis = 1; ta = tent.y; }
    if (!par.z && tent.z > ta) axis = 2;
    // unmirror the leaf cube and find the cell holding the hit point
    WPREC RVEC3 lo, c;
    WPREC REAL sz;
#ifndef PRECISE
    if (REBASE && koff != 0) {
        // in N's frame: the leaf's cube in the model's [1,2] cube (exact:
        // multiples of 2^-depth), the hit point's offsets in the leaf from
        // the crossing times, x(t) - pos = (tc - t) |dl| (mirrored)
        vec3 adl = SLOTS3(RB_ADL);
        WPREC vec3 offm = ((pos * coef - bias) - tmin) * adl;
        vec3 pn = SLOTS3(RB_POS);
        WPREC vec3 posr = pn + (pos - 1.0) * us;
        WPREC float ser = scale_exp2 * us;
        if ((oct & 1) == 0) { posr.x = 3.0 - ser - posr.x; offm.x = scale_exp2 - offm.x; }
        if ((oct & 2) == 0) { posr.y = 3.0 - ser - posr.y; offm.y = scale_exp2 - offm.y; }
        if ((oct & 4) == 0) { posr.z = 3.0 - ser - posr.z; offm.z = scale_exp2 - offm.z; }
        lo = (posr - 1.0) * side;
        sz = ser * side;
        c = lo + clamp(floor(offm * (side * us)), vec3(0.0), vec3(sz - 1.0));
        t = te + entry_tau(SLOTS3(OA), SLOTS3(RB_OALO), SLOTS3(DM), lo, sz);
    } else
#endif
    {
        if ((oct & 1) == 0) pos.x = 3.0 - scale_exp2 - pos.x;
        if ((oct & 2) == 0) pos.y = 3.0 - scale_exp2 - pos.y;
        if ((oct & 4) == 0) pos.z = 3.0 - scale_exp2 - pos.z;
        lo = (pos - 1.0) * side;
        sz = scale_exp2 * side;
        REAL tau = troot / L;
#ifndef PRECISE
        if (exact) tau = entry_tau(SLOTS3(OA), REBASE ? SLOTS3(RB_OALO) : vec3(0.0), SLOTS3(DM), lo, sz), t = te + tau;
#endif
        WPREC RVEC3 p = oa + d * tau;
        c = clamp(floor(p), lo, lo + sz - 1.0);
    }
    if (exact && !(t <= h.t)) return false;
    // the entry axis is decided by the ray direction, not by rounding (but
    // a ray that starts in the leaf keeps the cell holding its start)
    REAL da = axis == 0 ? d.x : (axis == 1 ? d.y : d.z);
    REAL la = axis == 0 ? lo.x : (axis == 1 ? lo.y : lo.z);
    WPREC REAL ca = (da > 0.0 || (da == 0.0 && !sign_neg(da))) ? la : la + sz - 1.0;
    if (!(troot <= 0.0 && te <= t0)) {
        if (axis == 0) c.x = ca;
        else if (axis == 1) c.y = ca;
        else c.z = ca;
    }
    h.t = t;
    h.cell = uvec3(c);
    h.axis = axis;
    h.nsign = sign_neg(da) ? 1.0 : -1.0;
    h.color = 0xFFFFFFFFu;
    h.attr = NO_HIT;
    if (HAS_COLOR && have_attr && !COMPACT && (m.flags & 1u) != 0u) {
        h.attr = m.color_off + attr_rec;
        h.color = colors[h.attr];
    }
#ifndef PRECISE
    if (COMPACT && HAS_COLOR && !any_hit && (m.flags & 1u) != 0u) {
        // the cell's attribute index (a descent from the root) and its block
        CModel cm = cmodels[mi];
        uint ab;
        // two statements: as one call's arguments, ab would be read before
        // cell_index sets it (GLSL evaluates them left to right)
        uint ci = cell_index(cm, h.cell, ab);
        uint v = decode_value(cm, ab, ci);
        // the record's index into the per-record tables (emission, materials):
        // a compact scene's tables are per material id or palette index
        // (render_scene.c vx__render_scene_attr_material)
        h.color = cm.kind == 1u ? cpalette[v & 0xFFu] : v;
        h.attr = ca_table_index(cm, ci, v);
    }
#endif
    return true;
}

#if defined(TRACE_GRID) && !defined(PRECISE)
// trace.comp and the pass kernels that trace: models with a grid walk it (grid_walk.glsl; GRID, id 13, 0: none
// has one)
#define GRID_WALK
#include "grid_walk.glsl"
#endif

#ifdef BEAM_PASS
// beam.comp: the tube's box test and model walk replace the ray's
vec2 scene_box(vec3 o, vec3 dinv, vec3 lo, vec3 hi);
bool beam_model(uint mi, vec3 o, vec3 d, float scale, float t0, inout Hit h);
#else
#define scene_box box_t
#endif

bool trace_instance(uint i, RVEC3 o, RVEC3 d, REAL t0, bool any_hit, inout Hit h) {
    Inst I = INST_AT(i);
#ifdef PRECISE
    dvec4 r0 = pinst[3u * i], r1 = pinst[3u * i + 1u], r2 = pinst[3u * i + 2u];
#else
    vec4 r0 = I.r0, r1 = I.r1, r2 = I.r2;
#endif
    WPREC RVEC3 om = RVEC3(dot(r0.xyz, o) + r0.w, dot(r1.xyz, o) + r1.w, dot(r2.xyz, o) + r2.w);
    WPREC RVEC3 dm = RVEC3(dot(r0.xyz, d), dot(r1.xyz, d), dot(r2.xyz, d));
    // precise: its ops form the two-sum's error term, which exact algebra
    // makes 0; not precise, the NVIDIA compiler (driver 580) folded it to 0
    // and the origin's rounding was lost (issue 18: 380 of 110,592 depth-16
    // close-up pixels off on the H200)
    precise vec3 om_lo = vec3(0.0);
#ifndef PRECISE
    if (REBASE) {
        // the translation's and the sum's rounding errors (two-sum)
        precise vec3 dt = vec3(dot(r0.xyz, o), dot(r1.xyz, o), dot(r2.xyz, o));
        precise vec3 w = vec3(r0.w, r1.w, r2.w);
        precise vec3 s = dt + w;
        precise vec3 bb = s - dt;
        om = s;
        om_lo = ((dt - (s - bb)) + (w - bb)) + I.lo.xyz;
    }
#endif
#ifdef BEAM_PASS
    // a world distance r is at most |M|_F r in the model (Frobenius bound)
    float scale = sqrt(dot(r0.xyz, r0.xyz) + dot(r1.xyz, r1.xyz) + dot(r2.xyz, r2.xyz));
    if (beam_model(I.model, om, dm, scale, t0, h)) {
#else
    float lod_b = F.uy.w, lod_a = F.misc.x;
#ifdef GRID_WALK
    uint groot = GRID != 0u && !LOD ? grid_address(I.model) : NO_HIT;
    if (GRID_ALL || groot != NO_HIT ? trace_model_grid(I.model, groot, om, om_lo, dm, t0, h.t, any_hit, h)
                        : trace_model(I.model, om, om_lo, dm, t0, h.t, any_hit, lod_a, lod_b, h)) {
#else
    if (trace_model(I.model, om, om_lo, dm, t0, h.t, any_hit, lod_a, lod_b, h)) {
#endif
#endif
        if (!GRID_UNION) h.inst = i; // (the union's walk set its hit's instance)
        return true;
    }
    return false;
}

// A far child on the walk's stack: its words (first << 3 | count: the host
// keeps node and item indices below 2^29, leaves at most 4 items) and its
// box's entry t from the test that pushed it, so that a pop neither loads
// nor tests its box again (the same t, the same decision).
#ifdef PRECISE
#define BVH_ENTRY uvec3
#define BVH_ENTRY_MAKE(w, t) uvec3(w, unpackDouble2x32(t))
#define BVH_ENTRY_T(e) packDouble2x32(e.yz)
#else
#define BVH_ENTRY uvec2
#define BVH_ENTRY_MAKE(w, t) uvec2(w, floatBitsToUint(t))
#define BVH_ENTRY_T(e) uintBitsToFloat(e.y)
#endif
// The walk to the next leaf (first, count: its items; done: none left).
// node_first, node_count: node's own words (its children or items), taken
// from the load that tested its box rather than loaded again (a storage
// buffer's load is 8 lane-by-lane loads with their bounds tests on lavapipe).
#define BVH_NEXT_LEAF \
    while (true) {                                                                          \
        if (pop_next) {                                                                     \
            /* pop, skipping nodes now beyond the nearest hit */                            \
            pop_next = false;                                                               \
            bool next = false;                                                              \
            while (sp > 0) {                                                                \
                BVH_ENTRY c = stack[--sp];                                                  \
                if (BVH_ENTRY_T(c) <= h.t) {                                                \
                    node_first = c.x >> 3u;                                                 \
                    node_count = c.x & 7u;                                                  \
                    next = true;                                                            \
                    break;                                                                  \
                }                                                                           \
            }                                                                               \
            if (!next) { done = true; break; }                                              \
        }                                                                                   \
        count = node_count;                                                                 \
        first = node_first;                                                                 \
        if (count > 0u) { pop_next = true; break; }                                         \
        BNode a = bvh[first], b = bvh[first + 1u];                                          \
        RVEC2 ta = scene_box(o, dinv, RVEC3(a.lo.xyz), RVEC3(a.hi.xyz));                    \
        RVEC2 tb = scene_box(o, dinv, RVEC3(b.lo.xyz), RVEC3(b.hi.xyz));                    \
        bool ha = ta.x <= ta.y && ta.y >= t0 && ta.x <= h.t;                                \
        bool hb = tb.x <= tb.y && tb.y >= t0 && tb.x <= h.t;                                \
        if (ha && hb) {                                                                     \
            /* nearest first; the far one waits on the stack */                             \
            bool an = ta.x <= tb.x;                                                         \
            uvec2 aw = uvec2(floatBitsToUint(a.lo).w, floatBitsToUint(a.hi).w);             \
            uvec2 bw = uvec2(floatBitsToUint(b.lo).w, floatBitsToUint(b.hi).w);             \
            uvec2 fw = an ? bw : aw;                                                        \
            if (sp < 64) stack[sp++] = BVH_ENTRY_MAKE((fw.x << 3u) | fw.y, an ? tb.x : ta.x); \
            node_first = an ? aw.x : bw.x;                                                  \
            node_count = an ? aw.y : bw.y;                                                  \
        } else if (ha) {                                                                    \
            node_first = floatBitsToUint(a.lo).w;                                           \
            node_count = floatBitsToUint(a.hi).w;                                           \
        } else if (hb) {                                                                    \
            node_first = floatBitsToUint(b.lo).w;                                           \
            node_count = floatBitsToUint(b.hi).w;                                           \
        } else {                                                                            \
            pop_next = true;                                                                \
        }                                                                                   \
    }

#ifdef TRACE_TILES
// The BVH node the next trace_scene starts from (its subtree holds every
// leaf the ray can meet: the primary ray's tile's, vx__frame_tiles), the
// root for every other ray
uint g_start = 0u;
#endif
// Nearest hit (or any hit) along o + t d, t in [t0, h.t].
bool trace_scene(RVEC3 o, RVEC3 d, REAL t0, bool any_hit, inout Hit h) {
    bool found = false;
    if (!USE_BVH) {
        if (F.dims.w > 0u) found = trace_instance(GRID_UNION ? 0xFFFFFFFFu : 0u, o, d, t0, any_hit, h);
        return found;
    }
    if (F.dims.w == 0u) return false;
    RVEC3 dinv = safe_inv(d);
    BVH_ENTRY stack[64];
    int sp = 0;
#ifdef TRACE_TILES
    uint node = g_start;
#else
    uint node = 0u;
#endif
    BNode rn = bvh[node];
    RVEC2 rt = scene_box(o, dinv, RVEC3(rn.lo.xyz), RVEC3(rn.hi.xyz));
    if (!(rt.x <= rt.y && rt.y >= t0 && rt.x <= h.t)) return false;
    uint node_first = floatBitsToUint(rn.lo).w, node_count = floatBitsToUint(rn.hi).w;
    // The walk to the next leaf is a loop of its own, and the leaf's
    // instances are traced outside it: SIMD CPUs (lavapipe) run a loop's
    // every branch masked, so the octree walk runs once per leaf visit
    // rather than once per BVH step.
    bool pop_next = false;
#ifdef TRACE_FLAT_ITEMS
    // the leaf's items [first, first + count) one per iteration of the outer
    // loop (k the next), so that the octree walk sits one loop deep rather
    // than two: lavapipe pays for every level of loop around it (issue 21's
    // eleventh sitting). The same instances in the same order.
    uint first = 0u, count = 0u, k = 0u;
    while (true) {
        bool done = false;
        if (k >= count) {
            k = 0u;
            BVH_NEXT_LEAF
        }
        if (done) break;
        uint it = items[first + k];
        k++;
        if (it != g_skip_inst && trace_instance(it, o, d, t0, any_hit, h)) {
            found = true;
            if (any_hit) return true;
        }
    }
#else
    while (true) {
        uint first = 0u, count = 0u;
        bool done = false;
        BVH_NEXT_LEAF
        if (done) break;
        for (uint k = 0u; k < count; k++) {
            if (items[first + k] != g_skip_inst && trace_instance(items[first + k], o, d, t0, any_hit, h)) {
                found = true;
                if (any_hit) return true;
            }
        }
    }
#endif
    return found;
}

vec3 unpack_rgb(uint c) {
    return vec3(float(c & 0xFFu), float((c >> 8) & 0xFFu), float((c >> 16) & 0xFFu)) / 255.0;
}

vec3 inst_color(uint id) {
    uint h = id * 2654435761u + 0x9E3779B9u;
    h ^= h >> 15; h *= 0x85EBCA6Bu; h ^= h >> 13;
    return vec3(float(h & 0xFFu), float((h >> 8) & 0xFFu), float((h >> 16) & 0xFFu)) / 255.0 * 0.8 + 0.2;
}

vec3 heat(uint it) {
    float x = clamp(float(it) / 256.0, 0.0, 1.0);
    return clamp(vec3(3.0 * x, 3.0 * x - 1.0, 3.0 * x - 2.0), 0.0, 1.0);
}

