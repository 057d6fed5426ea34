// inst_grid.glsl - the instances' grid walk (issue 18, many instances): where
// every drawn instance is a translated model on one grid of 2^k-cell cubes
// (the regions `mpirun vox2svo` makes of a mesh), render_scene.c
// (inst_grid_build) writes the grid after the BVH's items, and the rays walk
// its cells in order (a 3D DDA) instead of the BVH: each cell costs a
// comparison and a load where a BVH node costs two box tests, and the walk
// stops at the first cell past the nearest hit, so no instance beyond it is
// entered.
//
// items[n] (n = F.dims.w, the instance count): INST_GRID_MAGIC or anything
// else (no grid); items[n + 1]: log2 of the cell side R in model units (bits
// 0-7) and kq (bits 8-15); n + 2..4: the grid's lower cell in instance 0's
// model space (q0, signed); n + 5..7: the cells per axis; then one word a
// cell (x fastest): the instance slot + 1, 0 for none; then two words an
// instance: its model's cells' box (the BVH's instance boxes), lo and hi - 1
// in units of R / 2^kq, 10 bits an axis. The walk runs in instance 0's model
// space, where instance i's model is the cube [q_i R, q_i R + R); an instance
// is traced where the ray meets its cells' box (widened by a margin far
// above the walk's rounding), as the BVH would.
//
// Exactness: each instance is traced as the BVH walk traces it (the whole
// [t0, h.t], its own box test), so only the set of instances entered could
// differ. Float rounding may order two crossings that lie within an ulp of
// each other wrongly (a ray through a cell's edge or corner); wherever the
// ray crosses a face within INST_GRID_TOL of another face with a cell behind
// it, the walk hands the ray to the BVH (which then traces every instance
// the ray meets; the hits found so far stay), so a cell the ray enters by
// less than the rounding is never skipped.
//
// Needs, before the include: trace_instance, Hit, insts[], items[], F.
const uint INST_GRID_MAGIC = 0x47524944u; // "GRID"
const float INST_GRID_TOL = 1.0 / 4096.0; // of a cell

const uint INST_GRID_BAIL = 0xFFFFFFFFu;

// Whether p (a position in cell c, [0,1]^3) lies within INST_GRID_TOL of a
// face of c, other than along the axis in skip, that has a cell of the grid
// behind it.
bool inst_grid_near(ivec3 c, vec3 p, bvec3 skip, ivec3 dims) {
    bvec3 lo = lessThan(p, vec3(INST_GRID_TOL)), hi = greaterThan(p, vec3(1.0 - INST_GRID_TOL));
    bvec3 nl = bvec3(lo.x && c.x > 0, lo.y && c.y > 0, lo.z && c.z > 0);
    bvec3 nh = bvec3(hi.x && c.x + 1 < dims.x, hi.y && c.y + 1 < dims.y, hi.z && c.z + 1 < dims.z);
    bvec3 nr = bvec3(!skip.x && (nl.x || nh.x), !skip.y && (nl.y || nh.y), !skip.z && (nl.z || nh.z));
    return any(nr);
}

// The grid walk's state between the instances it hands out.
struct GridWalk {
    vec3 p, g, ginv;   // the origin and direction in grid cells from the grid's corner, 1/g
    ivec3 c, st, dims; // the current cell, the steps' signs, cells per axis
    uint base, boxes;  // items[] index of the cells and of the instances' boxes
    float bq;          // a box unit in cells
    bool pending;      // the current cell is still to be looked at
    bool walking;      // false once the walk has left the grid or passed the nearest hit
};

// Starts the walk along o + t d from t0: 0 where the ray misses the grid
// before tmax, INST_GRID_BAIL where it enters the grid near an edge (the
// BVH then), else 1.
uint grid_start(vec3 o, vec3 d, float t0, float tmax, out GridWalk w) {
    uint n = F.dims.w;
    uint hdr = items[n + 1u];
    float R = exp2(float(hdr & 0xFFu));
    w.bq = exp2(-float((hdr >> 8) & 0xFFu));
    ivec3 q0 = ivec3(items[n + 2u], items[n + 3u], items[n + 4u]);
    w.dims = ivec3(items[n + 5u], items[n + 6u], items[n + 7u]);
    w.base = n + 8u, w.boxes = w.base + uint(w.dims.x * w.dims.y * w.dims.z);
    Inst I = insts[0];
    // instance 0's model space in grid cells, from the grid's corner
    w.p = (vec3(dot(I.r0.xyz, o) + I.r0.w, dot(I.r1.xyz, o) + I.r1.w, dot(I.r2.xyz, o) + I.r2.w)) / R - vec3(q0);
    w.g = vec3(dot(I.r0.xyz, d), dot(I.r1.xyz, d), dot(I.r2.xyz, d)) / R;
    w.ginv = safe_inv(w.g);
    w.pending = true;
    w.walking = true;
    vec2 tb = box_t(w.p, w.ginv, vec3(0.0), vec3(w.dims));
    float t = max(tb.x, t0);
    if (!(t <= min(tb.y, tmax))) return 0u;
    w.st = ivec3(w.g.x > 0.0 ? 1 : -1, w.g.y > 0.0 ? 1 : -1, w.g.z > 0.0 ? 1 : -1);
    vec3 e = w.p + w.g * t;
    w.c = clamp(ivec3(floor(e)), ivec3(0), w.dims - 1);
    return inst_grid_near(w.c, e - vec3(w.c), bvec3(false), w.dims) ? INST_GRID_BAIL : 1u;
}

// The next instance to trace (its slot + 1), 0 when the walk is done: the
// instances of the cells along the ray, in order, whose cells' box the ray
// meets in [t0, tmax] (tmax: the nearest hit so far). INST_GRID_BAIL where
// the ray crosses a face near an edge or a corner of the grid, where the
// float crossing times may order two cells wrongly or skip one: the caller
// then walks the BVH (about one ray in a thousand).
uint grid_next(inout GridWalk w, float t0, float tmax) {
    for (int it = 0; it < 3 * 4096; it++) {
        if (w.pending) {
            w.pending = false;
            uint ci = uint((w.c.z * w.dims.y + w.c.y) * w.dims.x + w.c.x);
            uint slot = items[w.base + ci];
            if (slot == 0u) continue;
            // the ray against the instance's cells' box (widened by the margin)
            uint bl = items[w.boxes + 2u * (slot - 1u)], bh = items[w.boxes + 2u * (slot - 1u) + 1u];
            vec3 cc = vec3(w.c);
            vec3 blo = cc + vec3(uvec3(bl, bl >> 10, bl >> 20) & 1023u) * w.bq - INST_GRID_TOL;
            vec3 bhi = cc + vec3((uvec3(bh, bh >> 10, bh >> 20) & 1023u) + 1u) * w.bq + INST_GRID_TOL;
            vec2 tc = box_t(w.p, w.ginv, blo, bhi);
            if (tc.x <= tc.y && tc.y >= t0 && tc.x <= tmax) return slot;
            continue;
        }
        if (!w.walking) return 0u;
        // the next cell: the crossing times of the cell's exit planes, from
        // the origin (no accumulated error)
        vec3 up = vec3(greaterThan(w.st, ivec3(0)));
        vec3 tn = (vec3(w.c) + up - w.p) * w.ginv;
        tn = mix(tn, vec3(3.0e38), equal(w.g, vec3(0.0)));
        float tm = min(min(tn.x, tn.y), tn.z);
        // the axis crossed (one, on a tie: then the point is near an edge)
        bvec3 m = tn.x == tm ? bvec3(true, false, false) : (tn.y == tm ? bvec3(false, true, false) : bvec3(false, false, true));
        ivec3 cn = w.c + w.st * ivec3(m);
        // every later cell starts past the nearest hit, or the grid ends
        if (!(tm <= tmax) || any(lessThan(cn, ivec3(0))) || any(greaterThanEqual(cn, w.dims))) {
            w.walking = false;
            return 0u;
        }
        if (inst_grid_near(w.c, w.p + w.g * tm - vec3(w.c), m, w.dims)) return INST_GRID_BAIL;
        w.c = cn;
        w.pending = true;
    }
    return 0u;
}
