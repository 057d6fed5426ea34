#version 450
// render/shaders/trace_compact.comp - primary (+ shadow) rays through the
// compact layout (render/compact.h, issue 18): the same BVH over instances
// and the same Laine-Karras walk as trace.comp (float variant, with its
// exact t and its two-frame walk of deep models, without the beam or LOD),
// reading the geometry DAG instead of the .svo node words: one 64-bit
// slot load per node (its descriptor and its children's block together, as
// trace.comp's descriptor word), none for a brick's level-1 octants. The
// walk's decisions depend only on geometry, so its cells and depths are
// trace.comp's; the colour comes after the scene's walk, once for the
// nearest hit, from the cell's attribute index (a second descent, from the
// model's start table's level-K cube or the root, summing leaf cubes and
// ranks or brick popcounts: no rank work in the walk's loop) and the
// attribute block that holds it. Layouts: render/compact.h (geometry,
// attributes), render/compact_gpu.c (CModel), render/render_internal.h (Frame,
// Inst, BVH: bindings 0, 4-6 are the render scene's).
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(constant_id = 0) const int MODE = 0;          // vx_render_mode
layout(constant_id = 1) const bool HAS_COLOR = true; // some model has attributes
layout(constant_id = 2) const bool USE_BVH = true;   // more than one instance
layout(constant_id = 4) const bool WRITE_HITS = false;
// as trace.comp's: 1 some model is exact (CModel flag 2: a hit's t from its
// cube's entry planes), 2 also some model has CModel.rebase > 0 (the hi/lo
// origin and the walk in two frames), else 0
layout(constant_id = 8) const int DEEP = 0;
const bool REBASE = DEEP >= 2;
// pages of the paged layout (render/compact.h, compact_gpu.c), 0: the whole
// layout is resident and none of the paging code is compiled in
layout(constant_id = 9) const uint PAGES = 0u;
// One sample a pixel (F.dims.z <= 1), as trace.comp's: the samples' loop
// then has the constant trip count 1 and the compiler drops it; the
// albedo kernels then take 40 registers (48 with the loop on deep models):
// 3-5% more albedo rays/s on the H200 on eph_monu1 and eph_menger, within
// 1% on the deep helmet and terrain, whose depth kernel (37 registers)
// lost up to 4% (docs/PERFORMANCE.md issue 18, twelfth step) until the
// model's record came from the frame block (model_at; thirteenth step)
layout(constant_id = 6) const bool ONE_SAMPLE = false;
// some model's start table has entries whose cells hold one value
// (compact_gpu.c tab_uniform), or some model's cells all hold one value
// (CModel flag 4), else their tests are compiled out
layout(constant_id = 7) const bool UNIFORM = false;
// the scene has the brick dictionary (render/compact.h VX_COMPACT_INDEXED
// nodes); without it the index word's path is compiled out of the walk
layout(constant_id = 5) const bool DICT = false;
// the attribute words in parts of 2^ATTR_SHIFT words (bindings 2, 11-17)
// where they exceed one storage buffer's range (maxStorageBufferRange, 4 GB
// on NVIDIA: the helmet at 32768^3 has about 6 GB); 0: one buffer, and the
// part selection is compiled out (render/compact_gpu.c)
layout(constant_id = 10) const uint ATTR_SHIFT = 0u;
// The screen cull's second pass (compact_gpu.c dispatch), as trace.comp's:
// the pixels outside F.rect, their misses written without a ray.
layout(constant_id = 11) const bool MISS_PASS = false;
// The primary rays' starts below the root (F.paths: render_scene.c
// vx__render_scene_paths over compact_gpu.c's listed tops), as trace.comp's
// (trace_model below); off on CPU devices (lavapipe), as trace.comp's
layout(constant_id = 12) const bool PATH_START = false;
// some model has level-3 records (CModel.rec3; compact_gpu.c records_on):
// the colour of a hit inside a brick from the walk's path (PATH_COLOR)
layout(constant_id = 3) const bool RECORDS = false;
// Set by gpu_pipeline.c for every pipeline (VX__SPEC_NODES_FILE): the device
// is a CPU (lavapipe), where the walk's stack is a ladder of selects (LADDER).
layout(constant_id = 100) const bool NODES_FILE = false;
// The walk's stack as a ladder of selects at constant indices on CPU devices
// in DEEP 0-1 (STK_PUT / STK_GET of stack_ladder.glsl, one text with
// trace.comp's; issue 21's seventeenth sitting): lavapipe then keeps it in
// registers instead of writing and reading an array lane by lane: the compact kernel 1.2-1.4x
// faster there (albedo; docs/PERFORMANCE.md issue 18, sixteenth step). On the
// H200 the same ladder cost 11-23% (48 registers in the albedo kernels
// instead of 40, the stack's 96 bytes of local memory an L1 hit a pop): GPUs
// keep the array. (A ternary, not &&: glslang made a spec-constant && of
// these a value that does not dominate its uses.)
const bool LADDER = DEEP < (NODES_FILE ? 2 : 0);
const int PATHS = 64;
const uint NO_PATH = 0xFFFFu;
const uint PW = (PAGES + 31u) / 32u;
// the state buffer's words: request count, request list, request bitmap,
// mean colours, then a use bit per pool unit (the host knows each unit's page)
const uint P_LIST = 1u, P_REQ = 1u + PAGES, P_REP = 1u + PAGES + PW, P_USE = 1u + 2u * PAGES + PW;
const uint NOT_RESIDENT = 0x80000000u;
// The iteration guard (MAX_ITER) and count only where hits are written (the
// count is in them) or the iteration mode shows it; else the advance
// compares the crossing times as !(tc > tc_max), so that a NaN time steps
// every axis and the ray still leaves the root (trace.comp's colour
// kernel's form): 2.5-4% more rays/s in the depth mode, 0-2% in albedo on
// the H200 (docs/PERFORMANCE.md issue 18, sixth step).
const bool GUARD = WRITE_HITS || MODE == 5;
// The depth kernel marks an unloaded node by desc 0 (a node's, a brick's
// and an octant's descriptors are never 0) rather than by a flag: 1-2% more
// rays/s there on the H200, where the other kernels keep the flag
// (docs/PERFORMANCE.md issue 18, ninth step; trace.comp's kernels the
// other way round, trace_common.glsl SENT).
const bool SENT = MODE == 3;
// A hit's t is read by the depth mode, the colour mode (its shadow ray), the
// hits and the choice of the nearest of several instances; elsewhere the
// one model's hit needs no t, and an exact model's entry-plane t (the stack's
// oa and d, about 25 operations) is left out where the hit cube is one cell:
// 2% more albedo rays/s on the helmet's close-up on the H200
// (docs/PERFORMANCE.md issue 18, thirteenth step)
const bool NEED_T = USE_BVH || WRITE_HITS || MODE == 0 || MODE == 3;
// The push from level 3 into a brick loads the brick's slot and makes its
// level-2 descriptor (brick_desc, some 15 operations), so that the loop top
// loads slots of level 3 and above only and computes no brick descriptor
// (before, it computed one at every load and chose): in the kernels of DEEP
// 0 on the H200 2.1% more albedo rays/s on eph_monu1's close-up and up to
// 4.7% more in the depth mode (eph_menger's albedo -0.3% to -0.8%); the DEEP
// 1 kernels' albedo lost 2.8-11% with it (the helmet at 512, the terrain), so
// they keep the load's choice (docs/PERFORMANCE.md issue 18, fifteenth step).
const bool PUSH_BRICK = DEEP == 0;
// The lean walk (trace_common.glsl LEAN, trace.comp's kernels' since issue
// 21's twenty-first sitting), in the part that pays here: in a primary walk
// (not any_hit) no test of the ray's end at a push. The model's box holds
// every cell, so a push past the box's exit (the ray's end with one
// instance) finds none; a paged layout's coarse hit (a page's cube) may lie
// outside the box, so PAGES keeps the test. This walk already had two of
// trace.comp's lean parts (no iteration guard but with the hits or the heat
// map, every push storing its parent). On the H200 (docs/PERFORMANCE.md
// issue 18, branch lean3) the test's removal gives the DEEP 0 albedo
// kernels 1.5-3.3% (eph_monu1's close-up 0.869 -> 0.898 of trace.comp's
// rays/s) and their depth kernels 2-5%, but the DEEP 1 albedo kernels (the
// helmet, the terrain) lost 5%: the driver then gave them 32 registers and
// spilled; and the other lean parts lost
// in every albedo kernel: scale_exp2 from scale at the loop's top (-2%)
// and the pixel's index formed before the walk (-4% on eph_monu1's
// close-up). So DEEP 0 only, and the DEEP 0 walk's decisions are
// trace.comp's lean walk's (test_compact_gpu). (A macro: glslang makes a
// const bool of && between specialization constants a value that does
// not dominate its uses.)
#define LEAN (MODE != MODE_ITER && !WRITE_HITS && !USE_BVH && DEEP == 0 && PAGES == 0u && !NODES_FILE)

const int MODE_COLOR = 0, MODE_ALBEDO = 1, MODE_NORMAL = 2, MODE_DEPTH = 3, MODE_INSTANCE = 4, MODE_ITER = 5;
// The colour of a hit inside a brick from the walk's path (the whole layout,
// no rebasing: compact_attr.glsl cell_index_path, the model's level-3
// records), where a colour is made (a macro: glslang makes a const bool of
// && between specialization constants a value that does not dominate its uses)
#define PATH_COLOR (RECORDS && PAGES == 0u && !REBASE && HAS_COLOR && (MODE == MODE_COLOR || MODE == MODE_ALBEDO))
const int S_MAX = 23;
const uint ROOT_EMPTY = 0xFFFFFFFFu, ROOT_LEAF = 0xFFFFFFFEu, NO_HIT = 0xFFFFFFFFu;
const uint MAX_ITER = 100000u;

#include "compact_attr.glsl"
struct Inst { vec4 r0, r1, r2; uint model; float cell; uint id; float pad; vec4 lo; };
struct BNode { vec4 lo; vec4 hi; };
// A start below the root (vx__gpu_path): info.x the depth dx of node X,
// .y X's slot, .z the model; cube: X's cube ([1,2] units of the model
// cube: corner xyz, side w); nodes: the slots of X's ancestors, the root first
struct PathRec { uvec4 info; vec4 cube; uvec4 nodes[6]; };

layout(std140, binding = 0) uniform Frame {
    vec4 fwd;   // w: t_start
    vec4 rx;    // w: ortho
    vec4 uy;
    vec4 light; // w: ambient
    vec4 misc;
    uvec4 dims; // width, height, spp, instance count
    uvec4 dims2;
    vec4 grid_lo;
    // a scene of one instance (USE_BVH off): its record (vx__render_scene_tables,
    // as trace.comp's) and, the whole layout resident, its model's in
    // cmodel0 (compact_gpu.c dispatch): inst_at, model_at
    layout(offset = 224) Inst inst0;
    // the pixels [rect.x, rect.z) x [rect.y, rect.w) that the trace pass
    // covers (vx__gpu_frame.rect, the screen cull: screen_cull.glsl)
    layout(offset = 336) uvec4 rect;
    // the screen tiles (vx__frame_tile_grid): tile_info.x the shift, .y
    // tiles a row; per tile 16 bits, the index of its start (paths) or
    // NO_PATH (vx__gpu_frame.tiles)
    layout(offset = 352) uvec4 tile_info;
    layout(offset = 368) uvec4 tiles[128];
    layout(offset = 2416) CModel cmodel0;
    layout(offset = 2480) PathRec paths[PATHS];
} F;
layout(std430, binding = 1) readonly buffer Geom { uvec2 slots[]; };
layout(std430, binding = 2) readonly buffer Attr { uint attr[]; };
layout(std430, binding = 3) readonly buffer CModels { CModel models[]; };
layout(std430, binding = 4) readonly buffer Insts { Inst insts[]; };
layout(std430, binding = 5) readonly buffer Bvh { BNode bvh[]; };
layout(std430, binding = 6) readonly buffer BvhItems { uint items[]; };
layout(std430, binding = 7) writeonly buffer Pixels { vec4 pixels[]; };
layout(std430, binding = 8) writeonly buffer Hits { uvec4 hits[]; }; // 2 per pixel
layout(std430, binding = 9) readonly buffer Palette { uint palette[]; };
layout(std430, binding = 10) buffer PageState { uint pstate[]; };
layout(std430, binding = 11) readonly buffer Attr1 { uint attr1[]; };
layout(std430, binding = 12) readonly buffer Attr2 { uint attr2[]; };
layout(std430, binding = 13) readonly buffer Attr3 { uint attr3[]; };
layout(std430, binding = 14) readonly buffer Attr4 { uint attr4[]; };
layout(std430, binding = 15) readonly buffer Attr5 { uint attr5[]; };
layout(std430, binding = 16) readonly buffer Attr6 { uint attr6[]; };
layout(std430, binding = 17) readonly buffer Attr7 { uint attr7[]; };
uint attr_word(uint i) {
    if (ATTR_SHIFT == 0u) return attr[i];
    uint o = i & ((1u << ATTR_SHIFT) - 1u);
    switch (i >> ATTR_SHIFT) {
    case 0u: return attr[o];
    case 1u: return attr1[o];
    case 2u: return attr2[o];
    case 3u: return attr3[o];
    case 4u: return attr4[o];
    case 5u: return attr5[o];
    case 6u: return attr6[o];
    default: return attr7[o];
    }
}
#define CA_SLOT(i) slots[i]
#define CA_ATTR(i) attr_word(i)
#define CA_PAL(i) palette[i]
#define CA_PAGES PAGES
#define CA_DICT DICT
#define CA_UNI UNIFORM
#include "compact_attr.glsl"

// A scene of one instance reads its instance's and its model's records from
// the frame block (uniform, as trace.comp's TRACE_INST_UBO) rather than
// from the buffers: on the H200 the instance 0.2-3% more rays/s on every
// view in both modes, the model another 3% on the helmet's and eph_menger's
// close-ups in albedo (eph_monu1's -0.7%) and 4-5% in the deep scenes' depth
// mode (docs/PERFORMANCE.md issue 18, thirteenth step).
CModel model_at(uint mi) {
    if (!USE_BVH && PAGES == 0u) return F.cmodel0;
    return models[mi];
}
Inst inst_at(uint i) {
    if (!USE_BVH) return F.inst0;
    return insts[i];
}
struct Hit {
    float t;
    uint inst;
    uvec3 cell;
    int axis;
    float nsign;
    uint color;
    uint page; // a page not resident whose cube was hit (coarse), else NO_HIT
    // PATH_COLOR: a hit inside a brick of a model with level-3 records: its
    // level-3 and level-4 ancestors (NO_HIT: none) and the brick
    uint n3, n4;
    uvec2 brick;
};

// The ray needs page p (not resident): its bit in the frame's requests, and
// the page in the list once (the first ray to set the bit appends it).
void page_request(uint p) {
    uint w = P_REQ + (p >> 5), b = 1u << (p & 31u);
    if ((pstate[w] & b) != 0u) return;
    if ((atomicOr(pstate[w], b) & b) == 0u) {
        uint i = atomicAdd(pstate[0], 1u);
        if (i < PAGES) pstate[P_LIST + i] = p;
    }
}
// The ray entered the resident page in pool unit u (the host's LRU): a read
// first, the common case.
void page_use(uint u) {
    uint w = P_USE + (u >> 5), b = 1u << (u & 31u);
    if ((pstate[w] & b) == 0u) atomicOr(pstate[w], b);
}

uint g_iter = 0u;
// the start below the root the next model walk may take (F.paths): the
// primary ray's, NO_PATH none (shadow rays, several instances)
uint g_path = NO_PATH;

bool sign_neg(float x) { return (floatBitsToUint(x) >> 31) != 0u; }

vec3 safe_inv(vec3 d) {
    vec3 r;
    for (int i = 0; i < 3; i++) r[i] = abs(d[i]) < 1e-30 ? (sign_neg(d[i]) ? -1e30 : 1e30) : 1.0 / d[i];
    return r;
}

vec2 box_t(vec3 o, vec3 rd_inv, vec3 lo, vec3 hi) {
    vec3 a = (lo - o) * rd_inv, b = (hi - o) * rd_inv;
    vec3 tn = min(a, b), tf = max(a, b);
    return vec2(max(max(tn.x, tn.y), tn.z), min(min(tf.x, tf.y), tf.z));
}

#include "entry_tau.glsl" // trace_common.glsl's

#define SLOTS3(i) vec3(intBitsToFloat(stk_node[i]), intBitsToFloat(stk_node[(i) + 1]), intBitsToFloat(stk_node[(i) + 2]))
// LADDER: the stack's pushed scales, S_MAX - 7 (DEEP 0: models of up to 8
// levels push from levels 8 to 2) or S_MAX - 9 (DEEP 1: up to 10) to
// S_MAX - 1, each at a constant index (stack_ladder.glsl without its
// switches: slots 14 up, 16 up unguarded)
const int STK_LO = S_MAX - (DEEP == 0 ? 7 : 9);
#include "stack_ladder.glsl"

// trace.comp's trace_model (trace_common.glsl, float variant, DEEP 0-2, no
// LOD or beam) over the compact geometry: the same walk, the same two-frame
// walk of models deeper than VX_RENDER_REBASE_DEPTH (CModel.rebase = k: in
// the frame of a depth-k node below it), the same exact t; only the node
// loads and pushes read slots (node_load, the pushes below).
bool trace_model(uint mi, vec3 o, vec3 o_lo, vec3 d, float t0, float t1, bool any_hit, inout Hit h) {
    // the depth kernels of DEEP 0 (eph_monu1, eph_menger) walk with the
    // record from the buffer: 0.909 -> 0.929 of trace.comp's rays/s on
    // eph_monu1's close-up, 0.922 -> 0.936 on eph_menger's (H200), where their
    // albedo kernels are faster with it from the frame block (eph_menger's
    // close-up 0.990 against 0.968) and the deep scenes' kernels are the same
    // either way (docs/PERFORMANCE.md issue 18, thirteenth step)
    CModel m;
    if (DEEP >= 1 || MODE != MODE_DEPTH) m = model_at(mi);
    else m = models[mi];
    if (m.root == ROOT_EMPTY) return false;
    float side = exp2(float(m.depth));
    uint bsh = m.depth > 10u ? m.depth - 10u : 0u;
    uvec3 bq = (uvec3(m.box, m.box >> 10, m.box >> 20) & 1023u) + 1u;
    vec2 tb = box_t(o, safe_inv(d), vec3(0.0), vec3(bq << bsh));
    float te = max(tb.x, t0);
    float tx = min(tb.y, t1);
    if (!(te < tx)) return false;
    vec3 oa, ol, ol_lo = vec3(0.0), oa_lo = vec3(0.0);
    float sc = 1.0 / side;
    bool exact = DEEP >= 1 && (m.flags & 2u) != 0u;
    if (REBASE && exact) {
        precise vec3 pr = d * te;
        precise vec3 pe = fma(d, vec3(te), -pr);
        precise vec3 oas = o + pr;
        precise vec3 bb = oas - o;
        precise vec3 se = (o - (oas - bb)) + (pr - bb);
        precise vec3 oal = o_lo + (pe + se);
        precise vec3 ols = clamp(1.0 + oas * sc, vec3(1.0), vec3(2.0));
        precise vec3 oll = (oas * sc - (ols - 1.0)) + oal * sc;
        oa = oas, oa_lo = oal, ol = ols, ol_lo = oll;
    } else {
        oa = o + d * te;
        ol = clamp(1.0 + oa * sc, vec3(1.0), vec3(2.0));
    }
    vec3 dl = d * sc;
    float L = length(dl);
    dl /= L;
    float tl1 = (tx - te) * L;
    const float eps = exp2(-float(S_MAX));
    if (abs(dl.x) < eps) dl.x = sign_neg(dl.x) ? -eps : eps;
    if (abs(dl.y) < eps) dl.y = sign_neg(dl.y) ? -eps : eps;
    if (abs(dl.z) < eps) dl.z = sign_neg(dl.z) ? -eps : eps;
    vec3 coef = 1.0 / -abs(dl);
    vec3 bias = coef * ol;
    int oct = 7;
    if (dl.x > 0.0) { oct ^= 1; bias.x = 3.0 * coef.x - bias.x; }
    if (dl.y > 0.0) { oct ^= 2; bias.y = 3.0 * coef.y - bias.y; }
    if (dl.z > 0.0) { oct ^= 4; bias.z = 3.0 * coef.z - bias.z; }
    // koff = k while in a depth-k node's frame, else 0; rb_scale the scale
    // of a depth-k cube in the model frame (-100 while rebased)
    int koff = 0;
    int rb_scale = (REBASE && m.rebase > 0u) ? S_MAX - int(m.rebase) : -100;
    float tmin = max(max(2.0 * coef.x - bias.x, 2.0 * coef.y - bias.y), 2.0 * coef.z - bias.z);
    float tmax = min(min(coef.x - bias.x, coef.y - bias.y), coef.z - bias.z);
    tmin = max(tmin, 0.0);
    tmax = min(tmax, tl1);
    // stack slots past S_MAX as trace_common.glsl's (the rebased walk's state)
    const int RB_SLOTS = 28;
    const int RB_OHI = S_MAX, RB_OLO = S_MAX + 3, RB_T0 = S_MAX + 6, RB_POS = S_MAX + 7, RB_PARENT = S_MAX + 10,
              RB_TMAX = S_MAX + 11, RB_ADL = S_MAX + 12, RB_BIAS = S_MAX + 15, RB_TBASE = S_MAX + 18,
              RB_OALO = S_MAX + 19;
    const int OA = REBASE ? S_MAX + 22 : 0, DM = OA + 3;

    vec3 pos = vec3(1.0);
    int scale = S_MAX - 1;
    float scale_exp2 = 0.5;
    bool hit = false;
    uint coarse = NO_HIT;
    int stk_node[S_MAX + (REBASE ? RB_SLOTS : 0)];
    uint hit_n3 = NO_HIT, hit_n4 = NO_HIT; // PATH_COLOR (below)
    uvec2 hit_brick = uvec2(0u);
    if (m.root == ROOT_LEAF) {
        if (tmin <= tmax) {
            hit = true;
            scale = S_MAX;
            scale_exp2 = 1.0;
        }
    } else {
        uint parent = m.root;
        int oct7 = oct ^ 7;
        uint desc = 0u;
        uvec2 nd = uvec2(0u); // the slot of the node at parent (level >= 2)
        bool loaded = false;
        // the level of the node at scale s is s + lvl_off (- koff while rebased)
        int lvl_off = int(m.depth) - (S_MAX - 1);
        // the level tests on the scale (scale - koff against the scales of
        // levels 3 and 2), not on scale + lvl_off: SPIR-V's int add may
        // wrap, so the compiler cannot fold the add a step into the compare
        int s3 = 3 - lvl_off, s2 = 2 - lvl_off;
        int idx = 0;
        if (1.5 * coef.x - bias.x > tmin) { idx ^= 1; pos.x = 1.5; }
        if (1.5 * coef.y - bias.y > tmin) { idx ^= 2; pos.y = 1.5; }
        if (1.5 * coef.z - bias.z > tmin) { idx ^= 4; pos.z = 1.5; }
        // A primary ray whose walk starts at a point well inside the cube
        // of K, a child of node X (F.paths[g_path], the host's guess for the
        // ray's screen tile), descends from the root to X without an advance,
        // as in trace.comp's trace_model (trace_common.glsl, whose argument
        // this is): every push takes the child holding the start (tmin is 0:
        // the walk's [1,2] ray starts at ol), and 2^-16 of the model cube
        // between the start and K's faces keeps each skipped decision the
        // walk's. The walk's state at X's loop top is then X's slot (not
        // loaded: the loop top loads it, as after a pop), K's mirrored corner
        // and octant, and X's ancestors' slots on the stack; the steps from X
        // on are the walk's, bit for bit, and so are the cell and the colour
        // (the colour's descent starts from the cell, not from the walk).
        // X is of level 3 or more (a slot with a descriptor) and, paged, no
        // deeper than the page level's parent (compact_gpu.c path_lists).
        if (PATH_START && g_path != NO_PATH && !USE_BVH && tmin == 0.0 && tmin <= tmax && mi == F.paths[g_path].info.z) {
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
                if (LADDER) {
                    for (int j = 0; j < S_MAX - STK_LO; j++)
                        if (j < dx) stk_node[S_MAX - 1 - j] = int(F.paths[g_path].nodes[j >> 2][j & 3]);
                } else
                    for (int j = 0; j < dx; j++) stk_node[S_MAX - 1 - j] = int(F.paths[g_path].nodes[j >> 2][j & 3]);
                parent = F.paths[g_path].info.y;
                scale = S_MAX - 1 - dx;
                scale_exp2 = cw;
                pos = pk;
                ivec3 sh = floatBitsToInt(pos) >> scale;
                idx = (sh.x & 1) | ((sh.y & 1) << 1) | ((sh.z & 1) << 2);
            }
        }
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
        int pending = 0, rb_step = 0;
        uint rb_cbit = 0u;
        while (true) {
        while (scale < S_MAX) {
            if (GUARD) g_iter++;
            int lvl = scale + lvl_off - koff;
            bool ge3 = scale - koff >= s3, eq2 = scale - koff == s2; // lvl >= 3, lvl == 2
            if (SENT ? desc == 0u : !loaded) {
                // level 1 only as the root of a depth-1 model: a push into a
                // level-1 node takes its descriptor from the brick in nd, and
                // a pop never lands on one (its children are cells)
                nd = slots[parent];
                if (PUSH_BRICK) {
                    // a brick only as a model's root or after a pop to it
                    if (ge3) desc = nd.x;
                    else desc = eq2 ? brick_desc(nd) : brick_octant(nd, 0u);
                } else {
                    // the brick's descriptor computed before the choice (at every
                    // load), not in a branch of it: 0.3-4.6% more albedo rays/s on the
                    // H200 (docs/PERFORMANCE.md issue 18, ninth step)
                    uint d2 = brick_desc(nd);
                    desc = ge3 ? nd.x : (eq2 ? d2 : brick_octant(nd, 0u));
                }
                loaded = true;
            }
            vec3 tc = pos * coef - bias;
            float tc_max = min(min(tc.x, tc.y), tc.z);
            int cs = idx ^ oct7;
            uint cbit = 1u << cs;
            bool valid = (desc & (cbit << 8)) != 0u;
            if (valid && ((LEAN && !any_hit) || tmin <= tmax)) {
                float half_ = scale_exp2 * 0.5;
                vec3 tcen = half_ * coef + tc;
                // No test of tmin against the child's exit (min(tmax, tc_max))
                // before the push, in every kernel (tmin lies in the child by
                // construction, as in the ESVO loop; tmin <= tmax is tested):
                // the DEEP kernels never had it, and without it the DEEP 0
                // kernels give 3-5% more albedo rays/s on the H200 (eph_monu1's
                // close-up 0.881 -> 0.922 of trace.comp's, eph_menger's 0.953 ->
                // 0.984), where trace.comp's DEEP 0 kernel keeps it (it measured
                // -0.6% to -2.6% without; docs/PERFORMANCE.md issue 18, sixteenth step)
                {
                    if ((desc & cbit) != 0u) {
                        hit = true;
                        break;
                    }
                    uvec2 ch = uvec2(0u);
                    if (PAGES > 0u && uint(lvl) == m.page_up) {
                        // the child is of the page level: a page root when it
                        // has children; not resident, its cube is the hit.
                        // (The push below keeps this slot: no second load.)
                        ch = slots[nd.y + uint(bitCount((desc >> 8) & ~desc & (cbit - 1u)))];
                        if ((ch.y & NOT_RESIDENT) != 0u) {
                            coarse = ch.y & ~NOT_RESIDENT;
                            page_request(coarse);
                            hit = true;
                            break;
                        }
                        if (((ch.x >> 8) & ~ch.x & 0xFFu) != 0u) page_use((ch.y - 2u - m.pool_base) >> m.unit_log2);
                    }
                    if (REBASE && scale == rb_scale) {
                        // into node N at depth k: after the loop
                        pending = 1, rb_cbit = cbit;
                        break;
                    }
                    // push: the child's slot is in the block nd.y (level >=
                    // 3), or, below a brick's level 2, the child is octant cs
                    // of the brick in nd (no load)
                    // every push writes its entry: without Laine and Karras'
                    // test (skip it where the child's exit is the parent's,
                    // whose entry is then never read) the walk needs no hh
                    // (ckern3)
                    if (LADDER) STK_PUT(scale, int(parent))
                    else stk_node[scale - koff] = int(parent);
                    // PUSH_BRICK: from level 3 the child is a brick, loaded here
                    bool to2 = PUSH_BRICK && scale - koff == s3;
                    loaded = eq2 || to2;
                    if (ge3) {
                        // (level 3 of the whole layout: through the brick's index word)
                        parent = ca_child(lvl, desc, nd.y, uint(bitCount((desc >> 8) & ~desc & (cbit - 1u))));
                        if (to2) {
                            nd = slots[parent];
                            desc = brick_desc(nd);
                        }
                    } else desc = brick_octant(nd, uint(cs));
                    if (SENT && !loaded) desc = 0u;
                    if (PAGES > 0u && uint(lvl) == m.page_up) {
                        nd = ch;
                        desc = ch.x;
                        loaded = true;
                    }
                    idx = 0;
                    scale--;
                    scale_exp2 = half_;
                    if (tcen.x > tmin) { idx ^= 1; pos.x += scale_exp2; }
                    if (tcen.y > tmin) { idx ^= 2; pos.y += scale_exp2; }
                    if (tcen.z > tmin) { idx ^= 4; pos.z += scale_exp2; }
                    continue;
                }
            }
            if (GUARD && g_iter > MAX_ITER) break;
            int step = 0;
            if (GUARD ? tc.x <= tc_max : !(tc.x > tc_max)) { step ^= 1; pos.x -= scale_exp2; }
            if (GUARD ? tc.y <= tc_max : !(tc.y > tc_max)) { step ^= 2; pos.y -= scale_exp2; }
            if (GUARD ? tc.z <= tc_max : !(tc.z > tc_max)) { step ^= 4; pos.z -= scale_exp2; }
            tmin = tc_max;
            idx ^= step;
            if ((idx & step) != 0) {
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
                if (LADDER) STK_GET(scale, parent)
                else parent = uint(stk_node[scale - koff]);
                ivec3 sh = floatBitsToInt(pos) >> scale;
                pos = intBitsToFloat(sh << scale);
                idx = (sh.x & 1) | ((sh.y & 1) << 1) | ((sh.z & 1) << 2);
                loaded = false; if (SENT) desc = 0u;
            }
        }
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
                vec3 tent = scale_exp2 * coef + tc;
                float tr = max(max(tent.x, tent.y), tent.z);
                vec3 olm = SLOTS3(RB_OHI);
                vec3 olm_lo = SLOTS3(RB_OLO);
                precise vec3 adl = SLOTS3(RB_ADL);
                precise vec3 pr = adl * tr;
                precise vec3 pe = fma(adl, vec3(tr), -pr);
                precise vec3 a = olm - pos;
                precise vec3 sq = a - pr;
                precise vec3 bb = sq - a;
                precise vec3 se = (a - (sq - bb)) - (pr + bb);
                precise vec3 q = sq + ((se - pe) + olm_lo);
                int k = S_MAX - scale;
                float sk = intBitsToFloat((127 + k) << 23); // 2^k
                vec3 qn = 1.0 + q * sk;
                bias = coef * qn;
                float t0n = (intBitsToFloat(stk_node[RB_T0]) - tr) * sk;
                float entn = max(max(2.0 * coef.x - bias.x, 2.0 * coef.y - bias.y), 2.0 * coef.z - bias.z);
                tmin = max(entn, t0n);
                tmax = (tmax - tr) * sk;
                stk_node[RB_TBASE] = floatBitsToInt(tr);
                koff = k;
                rb_scale = -100;
                // N is a node of level depth - k >= 3: its slot is in the block nd.y
                parent = nd.y + uint(bitCount((desc >> 8) & ~desc & (rb_cbit - 1u)));
                idx = 0;
                scale = S_MAX - 1;
                scale_exp2 = 0.5;
                pos = vec3(1.0);
                if (1.5 * coef.x - bias.x > tmin) { idx ^= 1; pos.x = 1.5; }
                if (1.5 * coef.y - bias.y > tmin) { idx ^= 2; pos.y = 1.5; }
                if (1.5 * coef.z - bias.z > tmin) { idx ^= 4; pos.z = 1.5; }
                loaded = false; if (SENT) desc = 0u;
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
            loaded = false; if (SENT) desc = 0u;
            diff = 0u;
            if ((step & 1) != 0) { diff |= floatBitsToUint(pos.x) ^ floatBitsToUint(pos.x - us); pos.x -= us; }
            if ((step & 2) != 0) { diff |= floatBitsToUint(pos.y) ^ floatBitsToUint(pos.y - us); pos.y -= us; }
            if ((step & 4) != 0) { diff |= floatBitsToUint(pos.z) ^ floatBitsToUint(pos.z - us); pos.z -= us; }
            idx ^= step;
            if ((idx & step) == 0) continue; // into a sibling of N
            scale = findMSB(diff);
            if (scale >= S_MAX) break;
            scale_exp2 = uintBitsToFloat(uint(scale - S_MAX + 127) << 23);
            parent = uint(stk_node[scale]);
            ivec3 sh = floatBitsToInt(pos) >> scale;
            pos = intBitsToFloat(sh << scale);
            idx = (sh.x & 1) | ((sh.y & 1) << 1) | ((sh.z & 1) << 2);
            loaded = false; if (SENT) desc = 0u;
        }
        if (scale >= S_MAX || (GUARD && g_iter > MAX_ITER)) hit = false;
        // a hit inside a brick (below level 2: nd is the brick) of a model
        // with level-3 records: every push wrote its stack entry, so the
        // entries of levels 3 and 4 are the hit's ancestors
        if (PATH_COLOR && hit && scale < s2 && m.rec3 != 0u) {
            uint a3 = 0u, a4 = 0u;
            if (LADDER) {
                STK_GET(s3, a3)
                STK_GET(s3 + 1, a4)
            } else {
                a3 = uint(stk_node[s3]);
                a4 = uint(stk_node[s3 + 1]);
            }
            hit_n3 = a3, hit_n4 = a4, hit_brick = nd;
        }
    }
    if (!hit) return false;
    if (UNIFORM && !NEED_T && MODE == MODE_ALBEDO && (m.flags & 4u) != 0u) {
        // a model whose cells all hold one value needs no cell (its colour
        // is m.value) and here no t
        h.t = te, h.cell = uvec3(0u), h.axis = 0, h.nsign = 1.0, h.color = 0xFFFFFFFFu, h.page = coarse;
        return true;
    }
    float us = intBitsToFloat((127 - koff) << 23); // 2^-k in a rebased frame, else 1
    float tbase = REBASE && koff != 0 ? intBitsToFloat(stk_node[RB_TBASE]) : 0.0; // t_r
    float troot = tbase + tmin * us;              // model frame [1,2] units
    float t = te + troot / L;
    if (NEED_T && (!exact || any_hit)) {
        if (!(t <= h.t)) return false;
        if (any_hit) { h.t = t; return true; }
    }
    // an axis the ray runs along (|dl| at eps) is never the entry's: trace_common.glsl's rule (stop 87)
    vec3 tent = (pos + scale_exp2) * coef - bias;
    bvec3 par = greaterThanEqual(-coef, vec3(1.0 / eps));
    int axis = par.x ? (par.y ? 2 : 1) : 0;
    float ta = axis == 0 ? tent.x : (axis == 1 ? tent.y : tent.z);
    if (!par.y && tent.y > ta) { axis = 1; ta = tent.y; }
    if (!par.z && tent.z > ta) axis = 2;
    vec3 lo, c;
    float sz;
    if (REBASE && koff != 0) {
        vec3 adl = SLOTS3(RB_ADL);
        vec3 offm = ((pos * coef - bias) - tmin) * adl;
        vec3 pn = SLOTS3(RB_POS);
        vec3 posr = pn + (pos - 1.0) * us;
        float ser = scale_exp2 * us;
        if ((oct & 1) == 0) { posr.x = 3.0 - ser - posr.x; offm.x = scale_exp2 - offm.x; }
        if ((oct & 2) == 0) { posr.y = 3.0 - ser - posr.y; offm.y = scale_exp2 - offm.y; }
        if ((oct & 4) == 0) { posr.z = 3.0 - ser - posr.z; offm.z = scale_exp2 - offm.z; }
        lo = (posr - 1.0) * side;
        sz = ser * side;
        c = lo + clamp(floor(offm * (side * us)), vec3(0.0), vec3(sz - 1.0));
        if (NEED_T) t = te + entry_tau(SLOTS3(OA), SLOTS3(RB_OALO), SLOTS3(DM), lo, sz);
    } else {
        if ((oct & 1) == 0) pos.x = 3.0 - scale_exp2 - pos.x;
        if ((oct & 2) == 0) pos.y = 3.0 - scale_exp2 - pos.y;
        if ((oct & 4) == 0) pos.z = 3.0 - scale_exp2 - pos.z;
        lo = (pos - 1.0) * side;
        sz = scale_exp2 * side;
        float tau = troot / L;
        if (exact && (NEED_T || sz != 1.0)) tau = entry_tau(SLOTS3(OA), REBASE ? SLOTS3(RB_OALO) : vec3(0.0), SLOTS3(DM), lo, sz), t = te + tau;
        // a cube of one cell is the cell (the point, floor and clamp give
        // lo, and the entry axis' rule below too): most hits, whose colour
        // needs the cell where trace.comp's needs none (0.2-2.3% of the H200's
        // albedo rays/s, docs/PERFORMANCE.md issue 18, ninth step)
        if (sz == 1.0) {
            c = lo;
        } else {
            vec3 p = oa + d * tau;
            c = clamp(floor(p), lo, lo + sz - 1.0);
        }
    }
    if (NEED_T && exact && !(t <= h.t)) return false;
    float da = axis == 0 ? d.x : (axis == 1 ? d.y : d.z);
    float la = axis == 0 ? lo.x : (axis == 1 ? lo.y : lo.z);
    float ca = (da > 0.0 || (da == 0.0 && !sign_neg(da))) ? la : la + sz - 1.0;
    if (sz != 1.0 && !(troot <= 0.0 && te <= t0)) {
        if (axis == 0) c.x = ca;
        else if (axis == 1) c.y = ca;
        else c.z = ca;
    }
    h.t = t;
    h.cell = uvec3(c);
    h.axis = axis;
    h.nsign = sign_neg(da) ? 1.0 : -1.0;
    h.color = 0xFFFFFFFFu;
    h.page = coarse;
    h.n3 = hit_n3, h.n4 = hit_n4, h.brick = hit_brick;
    return true; // the colour: once for the scene's nearest hit (main)
}

bool trace_instance(uint i, vec3 o, vec3 d, float t0, bool any_hit, inout Hit h) {
    Inst I = inst_at(i);
    vec3 om = vec3(dot(I.r0.xyz, o) + I.r0.w, dot(I.r1.xyz, o) + I.r1.w, dot(I.r2.xyz, o) + I.r2.w);
    vec3 dm = vec3(dot(I.r0.xyz, d), dot(I.r1.xyz, d), dot(I.r2.xyz, d));
    // precise: its ops form the two-sum's error term, which exact algebra
    // makes 0; not precise, the NVIDIA compiler (driver 580) folded it to 0
    // and the origin's rounding was lost (issue 18: 380 of 110,592 depth-16
    // close-up pixels off on the H200)
    precise vec3 om_lo = vec3(0.0);
    if (REBASE) {
        // the translation's and the sum's rounding errors (two-sum), as trace.comp
        precise vec3 dt = vec3(dot(I.r0.xyz, o), dot(I.r1.xyz, o), dot(I.r2.xyz, o));
        precise vec3 w = vec3(I.r0.w, I.r1.w, I.r2.w);
        precise vec3 s = dt + w;
        precise vec3 bb = s - dt;
        om = s;
        om_lo = ((dt - (s - bb)) + (w - bb)) + I.lo.xyz;
    }
    if (trace_model(I.model, om, om_lo, dm, t0, h.t, any_hit, h)) {
        h.inst = i;
        return true;
    }
    return false;
}

// trace.comp's BVH walk (trace_common.glsl trace_scene)
bool trace_scene(vec3 o, vec3 d, float t0, bool any_hit, inout Hit h) {
    bool found = false;
    if (!USE_BVH) {
        if (F.dims.w > 0u) found = trace_instance(0u, o, d, t0, any_hit, h);
        return found;
    }
    if (F.dims.w == 0u) return false;
    vec3 dinv = safe_inv(d);
    uint stack[64];
    int sp = 0;
    uint node = 0u;
    vec2 rt = box_t(o, dinv, bvh[0].lo.xyz, bvh[0].hi.xyz);
    if (!(rt.x <= rt.y && rt.y >= t0 && rt.x <= h.t)) return false;
    bool pop_next = false;
    while (true) {
        uint first = 0u, count = 0u;
        bool done = false;
        while (true) {
            if (pop_next) {
                pop_next = false;
                bool next = false;
                while (sp > 0) {
                    uint c = stack[--sp];
                    vec2 tc = box_t(o, dinv, bvh[c].lo.xyz, bvh[c].hi.xyz);
                    if (tc.x <= h.t) { node = c; next = true; break; }
                }
                if (!next) { done = true; break; }
            }
            BNode n = bvh[node];
            count = floatBitsToUint(n.hi.w);
            first = floatBitsToUint(n.lo.w);
            if (count > 0u) { pop_next = true; break; }
            BNode a = bvh[first], b = bvh[first + 1u];
            vec2 ta = box_t(o, dinv, a.lo.xyz, a.hi.xyz);
            vec2 tb = box_t(o, dinv, b.lo.xyz, b.hi.xyz);
            bool ha = ta.x <= ta.y && ta.y >= t0 && ta.x <= h.t;
            bool hb = tb.x <= tb.y && tb.y >= t0 && tb.x <= h.t;
            if (ha && hb) {
                uint nearc = ta.x <= tb.x ? first : first + 1u;
                uint farc = ta.x <= tb.x ? first + 1u : first;
                if (sp < 64) stack[sp++] = farc;
                node = nearc;
            } else if (ha) {
                node = first;
            } else if (hb) {
                node = first + 1u;
            } else {
                pop_next = true;
            }
        }
        if (done) break;
        for (uint k = 0u; k < count; k++) {
            if (trace_instance(items[first + k], o, d, t0, any_hit, h)) {
                found = true;
                if (any_hit) return true;
            }
        }
    }
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

void shade(uvec2 px) {
    uint W = F.dims.x, H = F.dims.y;
    uint spp = ONE_SAMPLE ? 1u : max(F.dims.z, 1u);
    // The camera ray, its t and the shading are precise (no contraction or
    // reassociation): trace.comp computes them with the same expressions and
    // must give the same bits (test_compact_gpu), but the NVIDIA compiler
    // (driver 580) contracted the two kernels' copies differently (issue 18:
    // up to 2,917 of 15,360 pixels differed on the H200). Once per pixel.
    precise vec4 acc = vec4(0.0);
    bool ortho = F.rx.w != 0.0;
    float t_start = F.fwd.w;
    for (uint s = 0u; s < spp; s++) {
        vec2 off = vec2(0.0);
        if (s > 0u) off = fract(vec2(0.5) + float(s) * vec2(0.7548776662466927, 0.5698402909980532)) - 0.5;
        precise float u = ((float(px.x) + 0.5 + off.x) / float(W)) * 2.0 - 1.0;
        precise float v = 1.0 - ((float(px.y) + 0.5 + off.y) / float(H)) * 2.0;
        precise vec3 o, d;
        precise float t_off;
        if (ortho) {
            o = u * F.rx.xyz + v * F.uy.xyz;
            d = F.fwd.xyz;
            t_off = t_start;
        } else {
            vec3 du = F.fwd.xyz + u * F.rx.xyz + v * F.uy.xyz;
            precise float len = length(du);
            d = du / len;
            o = t_start * (u * F.rx.xyz + v * F.uy.xyz);
            t_off = t_start * len;
        }
        g_iter = 0u;
        Hit h;
        h.t = 3.0e38;
        h.inst = NO_HIT;
        h.color = 0xFFFFFFFFu;
        h.cell = uvec3(0u);
        h.page = NO_HIT;
        // one instance: the start below the root for the pixel's screen
        // tile (vx__render_scene_paths), NO_PATH none
        if (PATH_START && !USE_BVH && !MISS_PASS) {
            uint ti = min((px.y >> F.tile_info.x) * F.tile_info.y + (px.x >> F.tile_info.x), 1023u);
            uint tile = (F.tiles[ti >> 3u][(ti >> 1u) & 3u] >> ((ti & 1u) * 16u)) & 0xFFFFu;
            g_path = tile < uint(PATHS) ? tile : NO_PATH;
        }
        bool hit = MISS_PASS ? false : trace_scene(o, d, 0.0, false, h);
        g_path = NO_PATH; // the shadow ray's walk from the root
        uint prim_iter = g_iter;
        if (hit && HAS_COLOR && (MODE == MODE_COLOR || MODE == MODE_ALBEDO)) {
            // after the scene's walk, not at each model's hit: once a pixel
            CModel m = model_at(inst_at(h.inst).model);
            if (PAGES > 0u && h.page != NO_HIT) {
                if ((m.flags & 1u) != 0u) h.color = pstate[P_REP + h.page];
            } else if (UNIFORM && (m.flags & 5u) == 5u) {
                h.color = m.value; // a model of one value: no descent, no decode
            } else if ((m.flags & 1u) != 0u) {
                uint ab;
                uint i;
                if (PATH_COLOR && h.n3 != NO_HIT) i = cell_index_path(m, h.cell, h.n3, h.n4, h.brick, ab);
                else i = PAGES == 0u ? cell_index_table(m, h.cell, ab) : cell_index(m, h.cell, ab);
                h.color = decode_color(m, ab, i);
            }
        }
        precise vec4 c = vec4(0.0);
        precise vec3 nw = vec3(0.0);
        if (hit) {
            Inst I = inst_at(h.inst);
            vec4 row = h.axis == 0 ? I.r0 : (h.axis == 1 ? I.r1 : I.r2);
            nw = normalize(row.xyz * h.nsign);
        }
        if (MODE == MODE_COLOR || MODE == MODE_ALBEDO) {
            if (!hit) c = vec4(0.62, 0.75, 0.92, 0.0);
            else {
                vec3 alb = HAS_COLOR ? unpack_rgb(h.color) : vec3(1.0);
                if (MODE == MODE_ALBEDO) c = vec4(alb, 1.0);
                else {
                    float amb = F.light.w;
                    precise float ndl = max(dot(nw, F.light.xyz), 0.0);
                    float vis = 0.0;
                    if (ndl > 0.0) {
                        precise vec3 p = o + d * h.t;
                        float cell = inst_at(h.inst).cell;
                        precise vec3 ps = p + nw * (cell * 1e-3 + 4e-6 * max(max(abs(p.x), abs(p.y)), abs(p.z)));
                        Hit sh;
                        sh.t = 3.0e38;
                        sh.inst = NO_HIT;
                        vis = trace_scene(ps, F.light.xyz, 0.0, true, sh) ? 0.0 : 1.0;
                    }
                    c = vec4(alb * (amb + (1.0 - amb) * ndl * vis), 1.0);
                }
            }
        } else if (MODE == MODE_NORMAL) {
            c = vec4(nw, hit ? 1.0 : 0.0);
        } else if (MODE == MODE_DEPTH) {
            precise float t = hit ? float(t_off + h.t) : uintBitsToFloat(0x7F800000u);
            c = vec4(t, t, t, hit ? 1.0 : 0.0);
        } else if (MODE == MODE_INSTANCE) {
            c = hit ? vec4(inst_color(insts[h.inst].id), 1.0) : vec4(0.0);
        } else {
            c = vec4(heat(g_iter), 1.0);
        }
        acc += c;
        if (WRITE_HITS && s == 0u) {
            uint base = 2u * (px.y * W + px.x);
            precise float t_hit = hit ? float(t_off + h.t) : 0.0;
            hits[base] = uvec4(hit ? insts[h.inst].id : NO_HIT, h.cell);
            uint hflags = PAGES > 0u && hit && h.page != NO_HIT ? 2u : 0u; // VX_RENDER_HIT_COARSE
            hits[base + 1u] = uvec4(floatBitsToUint(t_hit), prim_iter, hflags, 0u);
        }
    }
    pixels[px.y * W + px.x] = acc / float(spp);
}

#include "screen_cull.glsl"

void main() {
    if (MISS_PASS) {
        uvec2 px;
        if (cull_miss_pixel(F.rect, F.dims.x, F.dims.y, px)) shade(px);
        return;
    }
    uvec2 px = F.rect.xy + gl_GlobalInvocationID.xy;
    if (px.x < F.rect.z && px.y < F.rect.w) shade(px);
}
