#version 450
#extension GL_KHR_shader_subgroup_vote : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_basic : require
/* convert/shaders/meshbuild.comp - each region's octree built on the GPU
 * from its sorted cells (Morton order, tuples interned by meshintern.comp):
 * the node pool that the CPU builder's streaming pass (svo/svo_build.c,
 * pass 3) makes, word for word, so that the CPU keeps only the
 * representatives and the block layout (vx__svo_build_pool).
 *
 * Items are the children of the level being built: cells at level 0, then
 * each level's parents. Item: i0 = (key lo, key hi, region | leaf << 31,
 * ref), i1 = (last cell, label lo, label hi, 0); ref is the tuple id of a
 * leaf, the node slot of a node; the label is a leaf's hash of its tuple
 * id or a node's hash of its content over its children's labels (equal
 * subtrees, equal labels: the structural hash).
 * Node slot: n0 = (valid | leaf << 8, region, order, canonical slot),
 * n1 = (hash lo, hash hi, pool position, table slot), n2/n3 = the children
 * in octant order over valid (tuple id of a leaf child, node slot of a
 * node child); a parent that collapsed keeps valid 0 in its slot.
 * order = last cell << 5 | level: the CPU builder appends nodes in that
 * order (post-order; a node is finalized when the cell after its last one
 * arrives, lower levels first) and keeps the first of equal nodes, so the
 * canonical node of a class is the one of least order, and pool positions
 * are the prefix sums of the canonical nodes' sizes in order.
 *   MODE 0 (init, per cell): the level-0 items.
 *   MODE 1 (flag, per item of level pc.level): a region's only item at its
 *           depth is its root (rout); else pos[i] = 1 where i starts a group
 *           of siblings.
 *   MODE 2 (start, after pos's exclusive scan): start[parent] = first child.
 *   MODE 27 (one invocation): the parents' count P = pos[items]; more
 *           than the host's bound (pc.level, 0 above the last level) or
 *           beyond the node slots (pc.mask) sets the failure flag (the CPU
 *           builds) and P = 0.
 *   MODE 3 (parent, per parent): the uniform collapse, or node slot
 *           base + parent with its content and hash; the parent item.
 *   MODE 28 (one invocation): the parents become the items, base += P.
 * The counts live on the device (lay, bound to the level state: [0] =
 * (items, base), [1] = (P, failed), [2] = (levels built, 0)), so that every
 * level is recorded into one submission: the host dispatches each level
 * at a bound of its count and the invocations beyond it return.
 *   MODE 4 (insert, per node slot): the hash table (first slot claimed per
 *           (hash, region); the least order there).
 *   MODE 5 (owner): the slot's node of least order writes itself there.
 *   MODE 6 (canon): canonical slot; pos[q] = 1 for canonical nodes.
 *   MODE 7 (verify): each node against its canonical one, children through
 *           their canonical slots; any difference (a hash collision) sets
 *           misc[0] and the host builds on the CPU instead.
 *   MODE 8 (compact, after pos's scan): keys/vals = (order, slot) of the
 *           canonical nodes, for the radix sort by order.
 *   MODE 9 (sizes, per sorted node): pos[s] = its pool words.
 *   MODE 10 (place, after the scan): pool positions; each region's first.
 *   MODE 11 (emit): the pool words; MODE 12 (roots, per region).
 * With attributes (pc.attrs) each node's representative is computed with
 * its parent (MODE 3, vx__svo_rec_mean in the same float arithmetic:
 * divisions and the square root in double, rounded once) and interned per
 * region with the cells' tuples (a table of (tuple, region)):
 *   MODE 13 (per cell tuple): its slot and id; MODE 14 (per canonical node):
 *   its representative's slot, found or claimed; MODE 15: claimed slots get
 *   new ids (counted per region); MODE 16 (one invocation): each region's
 *   first new tuple; MODE 17: the representative ids (into the region's
 *   tuples, then its new ones), the new tuples written to ext.
 * The attribute runs of the block layout (svo_build.c, run_intern), per
 * node in pool order (sorted index i): its run is its children's tuple ids
 * over valid (a node child's representative). The CPU layout stores a run
 * at its first occurrence and points later equal runs there; a uniform run
 * (n copies of v, n < 8) instead takes the longest uniform run of v stored
 * before it. Stored uniform lengths of v only grow, so that is the first
 * occurrence of (v, M), M the longest uniform run of v at or before i: with
 * first(run) = its least node, target = first of the exact run, or for a
 * uniform run first(v, M) over M = the largest L with first(v, L) <= i.
 * Node i stores its run iff target == i; run starts are the prefix sums of
 * the stored lengths.
 *   MODE 18 (per node): the run table (first slot claimed per run and
 *           region; the least node there). MODE 19: target, pos[i] = the
 *           records stored, each region's first node. MODE 20 (after the
 *           scan): pool word 2 = the target's first record (region-relative),
 *           the stored runs' ids written to rids; each region's first record.
 *   MODE 30 (per node, after MODE 20, pos still its scan; pc.level = R): the
 *           model's attribute records themselves, so that the host copies
 *           them instead of looking every record's tuple up (a random read
 *           a record: at 4096^3 85 M of them took the CPU most of a second):
 *           each stored run's tuples by channel into itin (rgba) and itout
 *           (normal) as plain words and start (material, two 16-bit halves a
 *           word, or-ed into a zeroed buffer), at the records' global
 *           indices; per region r, misc[4 + 7R + 4r] = ~(the least global
 *           record holding the root's representative, as the CPU's search
 *           finds it) by atomicMax (0: none, the host appends it) and
 *           [+1..+3] that representative's rgba, normal, material.
 * The blocks (svo_build.c, layout_nodes): in pool order each node's block
 * is [far words][a descriptor per node child][its run's first record]; a
 * node without node children (a lone record) reuses the last copy of its
 * block while it is less than limit - 64 words back; a child beyond the
 * near-pointer limit gets a far word (a fixpoint: each far word moves the
 * descriptors). Each node's block depends only on earlier nodes (its
 * position, its children's blocks, earlier copies), so the decisions form
 * a triangular system with one solution, the sequential layout's; the GPU
 * iterates it (Jacobi: positions as prefix sums of the sizes, then every
 * node's decision from them) until an iteration changes nothing, which is
 * then that solution (else the CPU lays the blocks out).
 *   MODE 21 (per node): block size guessed (no far word, no reuse); a lone
 *           record's sort key (its run's global first record), else none.
 *   MODE 23: pos[i] = size (for the scan). MODE 24 (per node with node
 *           children): its far words and block from the positions.
 *   MODE 25 (per group of lone records with one key, sorted): reuse or a
 *           new copy, in pool order. misc[1]: something changed.
 *   MODE 29 (one invocation, after each iteration): an iteration that
 *           changed nothing sets misc[2] (settled: modes 24 and 25 then
 *           return, and the positions scanned again are the same);
 *           misc[3] counts the iterations computed.
 *   MODE 26 (per node with a block): its words. MODE 22 (per region):
 *           pc.level 0 clears its counts, 1 writes the root descriptor. */
layout(local_size_x = 256) in;
layout(constant_id = 0) const uint MODE = 0;
/* attrs: 1 rgba, 2 normal, 4 material; smask, lmask: the bits kept of every table's first slot and of the
 * structural hash (all but in tests, vx_conv_mesh_gpu_set_hash: forced collisions) */
layout(push_constant) uniform Push { uint n, level, base, mask, attrs, smask, lmask; } pc;

layout(std430, binding = 0) readonly buffer OKeys { uvec2 okeys[]; }; /* (local | brick << 18, brick >> 14) */
layout(std430, binding = 1) readonly buffer Ids { uint ids[]; };      /* global tuple id per cell */
layout(std430, binding = 2) readonly buffer BInfo { uvec4 binfo[]; }; /* per brick: region-local Morton lo, hi, region */
layout(std430, binding = 3) readonly buffer RInfo { uvec4 rinfo[]; }; /* per region: depth, first tuple id */
layout(std430, binding = 4) buffer ROut { uvec4 rout[]; };             /* per region: root ref, root leaf, plain, collapsed */
layout(std430, binding = 5) buffer ItemsIn { uvec4 itin[]; };
layout(std430, binding = 6) buffer ItemsOut { uvec4 itout[]; };
layout(std430, binding = 7) buffer Pos { uint pos[]; };
layout(std430, binding = 8) buffer Start { uint start[]; };
layout(std430, binding = 9) buffer Nodes { uvec4 nodes[]; };
layout(std430, binding = 10) buffer Table { uvec2 tab[]; }; /* (slot claimed by / canonical slot, least order) */
/* [0]: a node differs from its canonical one; [1]: a block layout iteration changed something; [2]: the layout
 * settled, [3]: its iterations (MODE 29);
 * [4 + r]: region r's cells; [4 + R + 6 r]: their box (MODE 0); [4 + 7 R + 4 r]: its root record (MODE 30) */
layout(std430, binding = 11) buffer Misc { uint misc[]; };
layout(std430, binding = 12) buffer Keys { uvec2 keys[]; };
layout(std430, binding = 13) buffer Vals { uint vals[]; };
layout(std430, binding = 14) buffer Pool { uint pool[]; };
layout(std430, binding = 15) buffer RBase { uint rbase[]; }; /* per region: its first pool word (0xFFFFFFFF: no node) */
layout(std430, binding = 16) buffer NRep { uvec4 nrep[]; };   /* per node slot: its representative (rgba, normal, material), id */
layout(std430, binding = 17) readonly buffer UTab { uvec4 utab[]; }; /* per tuple id: rgba, normal, material, region */
layout(std430, binding = 18) buffer TTab { uvec2 ttab[]; };   /* tuple table: (code, id); code < pc.base: a cell tuple, else a node */
layout(std430, binding = 19) buffer RNew { uint rnew[]; };    /* per region: new tuples; [R + r]: their first index in ext */
layout(std430, binding = 20) buffer Ext { uvec4 ext[]; }; /* the new tuples, region by region (MODE 30 reads them) */
layout(std430, binding = 21) buffer RTab { uvec2 rtab[]; };    /* attribute runs: (claimed by node, least node) */
layout(std430, binding = 22) buffer RNode { uvec2 rnode[]; };  /* per node in pool order: its run's slot, target node */
layout(std430, binding = 23) writeonly buffer RIds { uint rids[]; }; /* the stored runs' tuple ids, region by region */
/* per region r: [2r] (first node in pool order, first record, last node, the root's representative),
 * [2r + 1] (its laid-out words' first index, their count, far pointers, descriptor words) */
layout(std430, binding = 24) buffer RFirst { uvec4 rfirst[]; };
/* per node in pool order: its block's words, and for a lone record the node whose copy it reuses (itself
 * when it writes one): the decisions; positions always follow from them (block_at) */
layout(std430, binding = 25) buffer Lay { uvec2 lay[]; };

uint fmix(uint h) {
    h ^= h >> 16;
    h *= 0x85EBCA6Bu;
    h ^= h >> 13;
    h *= 0xC2B2AE35u;
    h ^= h >> 16;
    return h;
}
/* A 64-bit hash as two 32-bit lanes, each mixed with the other. */
uvec2 hmix(uvec2 h, uvec2 w) {
    uint a = fmix(h.x ^ (w.x * 0x9E3779B1u) ^ ((h.y << 7) | (h.y >> 25)));
    uint b = fmix(h.y ^ (w.y * 0x27D4EB2Fu) ^ (a + 0x165667B1u) ^ (w.x >> 3));
    return uvec2(a, b);
}
uvec2 leaf_label(uint rid) { return hmix(uvec2(0x5BD1E995u, 0x1B873593u), uvec2(rid, rid ^ 0xA5A5A5A5u)); }

uvec2 key_up(uvec2 k) { return uvec2((k.x >> 3) | (k.y << 29), k.y >> 3); }

uint node_at(uint q, uint o) { return o < 4u ? nodes[4u * q + 2u][o] : nodes[4u * q + 3u][o - 4u]; }

/* ---- the representative: vx__svo_rec_mean (svo/svo_build.c) in the same arithmetic ---- */

/* float division correctly rounded (double, then rounded: exact for floats) */
float fdiv(float a, float b) { return float(double(a) / double(b)); }

vec3 oct_decode(uint v) {
    precise float u = fdiv(float(int(v << 16) >> 16), 32767.0); /* the int16 halves */
    precise float w = fdiv(float(int(v) >> 16), 32767.0);
    if (u < -1.0) u = -1.0;
    if (w < -1.0) w = -1.0;
    precise float z = (1.0 - abs(u)) - abs(w);
    if (z < 0.0) {
        precise float ou = u;
        u = (1.0 - abs(w)) * (ou >= 0.0 ? 1.0 : -1.0);
        w = (1.0 - abs(ou)) * (w >= 0.0 ? 1.0 : -1.0);
    }
    precise float l2 = (u * u + w * w) + z * z;
    float len = float(sqrt(double(l2)));
    if (len > 0.0) {
        u = fdiv(u, len);
        w = fdiv(w, len);
        z = fdiv(z, len);
    }
    return vec3(u, w, z);
}

uint snorm16(float f) {
    if (!(f >= -1.0)) f = -1.0;
    if (f > 1.0) f = 1.0;
    precise float x = f * 32767.0;
    double a = floor(abs(double(x)) + 0.5lf); /* lroundf: half away from zero */
    int q = x < 0.0 ? -int(a) : int(a);
    return uint(q) & 0xFFFFu;
}

uint oct_encode(vec3 n) {
    precise float s = (abs(n.x) + abs(n.y)) + abs(n.z);
    if (!(s > 0.0)) return 0u;
    precise float u = fdiv(n.x, s), w = fdiv(n.y, s);
    if (n.z < 0.0) {
        precise float ou = u;
        u = (1.0 - abs(w)) * (ou >= 0.0 ? 1.0 : -1.0);
        w = (1.0 - abs(ou)) * (w >= 0.0 ? 1.0 : -1.0);
    }
    return snorm16(u) | (snorm16(w) << 16);
}

uint most_frequent(uint v[8], uint n) {
    uint best = 0u, bestn = 0u;
    for (uint i = 0u; i < n; i++) {
        uint k = 0u;
        for (uint j = 0u; j < n; j++) k += v[j] == v[i] ? 1u : 0u;
        if (k > bestn || (k == bestn && v[i] < best)) best = v[i], bestn = k;
    }
    return best;
}

/* n (1..8) children's tuples (rgba, normal, material) */
uvec3 rec_mean(uvec3 c[8], uint n) {
    bool same = true;
    for (uint i = 1u; i < n; i++) same = same && c[i] == c[0];
    if (same) return c[0];
    uvec3 r = uvec3(0u);
    if ((pc.attrs & 4u) != 0u) {
        uint v[8];
        for (uint i = 0u; i < 8u; i++) v[i] = i < n ? c[i].z : 0u;
        r.z = most_frequent(v, n);
    }
    if ((pc.attrs & 1u) != 0u) {
        uint o = 0u;
        for (uint ch = 0u; ch < 4u; ch++) {
            uint sum = 0u;
            for (uint i = 0u; i < n; i++) sum += (c[i].x >> (8u * ch)) & 0xFFu;
            o |= ((sum + n / 2u) / n) << (8u * ch);
        }
        r.x = o;
    }
    if ((pc.attrs & 2u) != 0u) {
        precise vec3 m = vec3(0.0);
        for (uint i = 0u; i < n; i++) {
            vec3 d = oct_decode(c[i].y);
            m.x = m.x + d.x;
            m.y = m.y + d.y;
            m.z = m.z + d.z;
        }
        r.y = oct_encode(m);
    }
    return r;
}

uint thash(uvec3 t, uint r) { return fmix(fmix(fmix(t.x ^ 0x9E3779B1u) ^ t.y) ^ (t.z + r * 0x85EBCA77u)); }
uvec4 tuple_of(uint code) { /* (tuple, region) of a table code */
    if (code < pc.base) return utab[code];
    uint q = code - pc.base;
    return uvec4(nrep[q].xyz, nodes[4u * q].y);
}

/* ---- the attribute runs ---- */

/* Node i's (pool order) run: its children's tuple ids over valid; its region. */
uint run_of(uint i, out uint v[8], out uint r) {
    uint q = vals[i];
    uvec4 n0 = nodes[4u * q];
    r = n0.y;
    uint at = nodes[4u * q + 1u].z, b = rbase[r];
    uint valid = n0.x & 0xFFu, leaf = n0.x >> 8, k = 0u;
    for (uint o = 0u; o < 8u; o++) v[o] = 0u;
    for (uint o = 0u; o < 8u; o++) {
        if ((valid >> o & 1u) == 0u) continue;
        uint ref = pool[at + 3u + k];
        v[k] = (leaf >> o & 1u) != 0u ? ref : pool[b + ref + 1u];
        k++;
    }
    return k;
}
/* Tuple id (region-relative) t of region r: the region's cell tuples, then
 * its new representatives (MODE 17's numbering); R regions. */
uvec4 tuple_of(uint r, uint t, uint R) {
    uint nc = rinfo[r].z;
    return t < nc ? utab[rinfo[r].y + t] : ext[rnew[R + r] + (t - nc)];
}
uint run_hash(uint v[8], uint n, uint r) {
    uint h = fmix(n * 0x9E3779B1u ^ r * 0x85EBCA77u);
    for (uint k = 0u; k < n; k++) h = fmix(h ^ (v[k] * 0x27D4EB2Fu + k));
    return h;
}
bool run_is(uint c, uint v[8], uint n, uint r) {
    uint w[8], rc;
    if (run_of(c, w, rc) != n || rc != r) return false;
    for (uint k = 0u; k < n; k++)
        if (w[k] != v[k]) return false;
    return true;
}
/* The least node whose run is L copies of v in region r (0xFFFFFFFF: none). */
uint uniform_first(uint v, uint L, uint r) {
    uint w[8];
    for (uint k = 0u; k < 8u; k++) w[k] = v;
    uint j = run_hash(w, L, r) & pc.smask & pc.mask;
    for (;;) {
        uint cur = rtab[j].x;
        if (cur == 0xFFFFFFFFu) return 0xFFFFFFFFu;
        if (run_is(cur, w, L, r)) return rtab[j].y;
        j = (j + 1u) & pc.mask;
    }
}

/* ---- the blocks ---- */

uint desc_make(uint ptr, bool far, uint hdr) { return (ptr << 17) | (far ? 0x10000u : 0u) | ((hdr & 0xFFu) << 8) | (hdr >> 8); }
/* Node k's block position (region-relative) under the current decisions
 * and the positions scanned from them: after its far words, or a lone
 * record's copy. */
uint block_at(uint k) {
    uvec2 l = lay[k];
    uint q = vals[k], hdr = nodes[4u * q].x, nn = bitCount((hdr & 0xFFu) & ~(hdr >> 8));
    uint base = pos[rfirst[2u * nodes[4u * q].y].x];
    if (nn == 0u) return pos[l.x != 0u ? k : l.y] - base;
    return pos[k] - base + (l.x - nn - 1u);
}
/* The node children of node slot q: their blocks' positions cb and headers cd, in octant order. */
uint node_kids(uint q, out uint cb[8], out uint cd[8]) {
    uint hdr = nodes[4u * q].x, valid = hdr & 0xFFu, leaf = hdr >> 8, j = 0u, nn = 0u;
    for (uint o = 0u; o < 8u; o++) cb[o] = 0u, cd[o] = 0u;
    for (uint o = 0u; o < 8u; o++) {
        if ((valid >> o & 1u) == 0u) continue;
        if ((leaf >> o & 1u) == 0u) {
            uint c = nodes[4u * node_at(q, j)].w; /* the canonical slot */
            cb[nn] = block_at(nodes[4u * c + 1u].w);
            cd[nn] = nodes[4u * c].x;
            nn++;
        }
        j++;
    }
    return nn;
}
/* layout_nodes' far-slot fixpoint for a block at cur: far[k] as bits. */
uint far_slots(uint cur, uint cb[8], uint nn, out uint nfar) {
    uint fb = 0u;
    nfar = 0u;
    for (int it = 0; it < 10; it++) {
        uint cnt = 0u;
        fb = 0u;
        for (uint k = 0u; k < nn; k++)
            if ((cur + nfar + k) - cb[k] > pc.mask) fb |= 1u << k, cnt++;
        if (cnt == nfar) break;
        nfar = cnt;
    }
    return fb;
}

void main() {
    uint i = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 256u + gl_LocalInvocationID.x;
    if (i >= pc.n) return;
    if (MODE == 0u) {
        uvec2 ok = okeys[i];
        uint brick = (ok.x >> 18) | (ok.y << 14);
        uvec4 bi = binfo[brick];
        uint rid = ids[i] - rinfo[bi.z].y;
        uvec2 key = uvec2((bi.x << 18) | (ok.x & 0x3FFFFu), (bi.y << 18) | (bi.x >> 14));
        uvec2 lab = leaf_label(rid);
        itout[2u * i] = uvec4(key, bi.z | 0x80000000u, rid);
        itout[2u * i + 1u] = uvec4(i, lab, 0u);
        atomicAdd(misc[4u + bi.z], 1u); /* the region's cells (the host may not download them) */
        /* and their box (the scene's bounds then need no pass over the models): per region at
         * misc[4 + R + 6 r] the largest ~x, ~y, ~z and x + 1, y + 1, z + 1 (R = pc.base), one
         * atomic per subgroup where its cells are of one region */
        uint c[3] = {0u, 0u, 0u};
        for (uint b = 0u; b < 21u; b++)
            for (uint a = 0u; a < 3u; a++) {
                uint p = 3u * b + a;
                c[a] |= (p < 32u ? (key.x >> p) & 1u : (key.y >> (p - 32u)) & 1u) << b;
            }
        uint e = 4u + pc.base + 6u * bi.z;
        if (subgroupAllEqual(bi.z)) {
            uint v[6] = {subgroupMax(~c[0]), subgroupMax(~c[1]), subgroupMax(~c[2]), subgroupMax(c[0] + 1u), subgroupMax(c[1] + 1u),
                         subgroupMax(c[2] + 1u)};
            if (subgroupElect())
                for (uint a = 0u; a < 6u; a++) atomicMax(misc[e + a], v[a]);
        } else {
            for (uint a = 0u; a < 3u; a++) atomicMax(misc[e + a], ~c[a]), atomicMax(misc[e + 3u + a], c[a] + 1u);
        }
    } else if (MODE == 27u) {
        uint P = pos[lay[0].x];
        bool bad = P > pc.level || lay[0].y + P > pc.mask;
        if (bad) lay[1].y = 1u, P = 0u;
        lay[1].x = P;
    } else if (MODE == 28u) {
        uint P = lay[1].x;
        lay[0] = uvec2(P, lay[0].y + P);
        if (P != 0u) lay[2].x += 1u;
    } else if (MODE == 1u) {
        if (i >= lay[0].x) return;
        uvec4 a = itin[2u * i];
        uint r = a.z & 0x7FFFFFFFu;
        if (rinfo[r].x <= pc.level) { /* the region's root */
            rout[r].xy = uvec2(a.w, a.z >> 31);
            pos[i] = 0u;
            return;
        }
        bool head = i == 0u;
        if (!head) {
            uvec4 p = itin[2u * i - 2u];
            head = (p.z & 0x7FFFFFFFu) != r || key_up(p.xy) != key_up(a.xy);
        }
        pos[i] = head ? 1u : 0u;
    } else if (MODE == 2u) {
        if (i >= lay[0].x) return;
        uvec4 a = itin[2u * i];
        uint r = a.z & 0x7FFFFFFFu;
        if (rinfo[r].x <= pc.level) return;
        bool head = i == 0u;
        if (!head) {
            uvec4 p = itin[2u * i - 2u];
            head = (p.z & 0x7FFFFFFFu) != r || key_up(p.xy) != key_up(a.xy);
        }
        if (head) start[pos[i]] = i;
    } else if (MODE == 3u) {
        /* lay[1].x parents; lay[0]: the items' count, the parents' first node slot; pc.level: the parents' level */
        if (i >= lay[1].x) return;
        uint nitems = lay[0].x, base = lay[0].y;
        uint s = start[i];
        uvec4 a0 = itin[2u * s];
        uint r = a0.z & 0x7FFFFFFFu;
        uvec2 pk = key_up(a0.xy);
        uint valid = 0u, leaf = 0u, last = 0u, first_rid = 0u;
        bool same = true;
        uint kid[8];
        uvec2 lab[8];
        uvec3 tup[8];
        uint nt = 0u;
        for (uint o = 0u; o < 8u; o++) kid[o] = 0u, lab[o] = uvec2(0u), tup[o] = uvec3(0u);
        for (uint j = s; j < nitems && j < s + 8u; j++) {
            uvec4 a = itin[2u * j];
            if ((a.z & 0x7FFFFFFFu) != r || key_up(a.xy) != pk) break;
            uvec4 b = itin[2u * j + 1u];
            uint o = a.x & 7u;
            valid |= 1u << o;
            if ((a.z >> 31) != 0u) {
                leaf |= 1u << o;
                if (j == s) first_rid = a.w;
                same = same && a.w == first_rid;
            }
            kid[o] = a.w;
            lab[o] = b.yz;
            last = b.x;
            if (pc.attrs != 0u) tup[nt++] = (a.z >> 31) != 0u ? utab[rinfo[r].y + a.w].xyz : nrep[a.w].xyz;
        }
        atomicAdd(rout[r].z, 1u);
        if (valid == 0xFFu && leaf == 0xFFu && same) { /* uniform: the parent is a leaf of that tuple */
            itout[2u * i] = uvec4(pk, r | 0x80000000u, first_rid);
            itout[2u * i + 1u] = uvec4(last, leaf_label(first_rid), 0u);
            nodes[4u * (base + i)] = uvec4(0u);
            return;
        }
        atomicAdd(rout[r].w, 1u);
        uint hdr = valid | leaf << 8;
        uvec2 h = hmix(uvec2(hdr * 0x9E3779B1u, r * 0x85EBCA77u + 1u), uvec2(hdr, r));
        uint c[8];
        uint n = 0u;
        for (uint o = 0u; o < 8u; o++) c[o] = 0u;
        for (uint o = 0u; o < 8u; o++)
            if ((valid >> o & 1u) != 0u) {
                h = hmix(h, lab[o] ^ uvec2(o, o << 16));
                c[n++] = kid[o];
            }
        h &= uvec2(pc.lmask);
        uint q = base + i;
        nodes[4u * q] = uvec4(hdr, r, last << 5 | pc.level, 0u);
        nodes[4u * q + 1u] = uvec4(h, 0u, 0u);
        nodes[4u * q + 2u] = uvec4(c[0], c[1], c[2], c[3]);
        nodes[4u * q + 3u] = uvec4(c[4], c[5], c[6], c[7]);
        itout[2u * i] = uvec4(pk, r, q);
        itout[2u * i + 1u] = uvec4(last, h, 0u);
        if (pc.attrs != 0u) nrep[q] = uvec4(rec_mean(tup, nt), 0u);
    } else if (MODE == 4u) {
        uvec4 n0 = nodes[4u * i];
        if ((n0.x & 0xFFu) == 0u) return;
        uvec2 h = nodes[4u * i + 1u].xy;
        uint j = fmix(h.x ^ n0.y) & pc.smask & pc.mask;
        for (;;) {
            uint cur = atomicCompSwap(tab[j].x, 0xFFFFFFFFu, i);
            if (cur == 0xFFFFFFFFu || (nodes[4u * cur + 1u].xy == h && nodes[4u * cur].y == n0.y)) break;
            j = (j + 1u) & pc.mask;
        }
        nodes[4u * i + 1u].w = j;
        atomicMin(tab[j].y, n0.z);
    } else if (MODE == 5u) {
        uvec4 n0 = nodes[4u * i];
        if ((n0.x & 0xFFu) == 0u) return;
        uint j = nodes[4u * i + 1u].w;
        if (tab[j].y == n0.z) tab[j].x = i;
    } else if (MODE == 6u) {
        uvec4 n0 = nodes[4u * i];
        if ((n0.x & 0xFFu) == 0u) {
            pos[i] = 0u;
            return;
        }
        uint c = tab[nodes[4u * i + 1u].w].x;
        nodes[4u * i].w = c;
        pos[i] = c == i ? 1u : 0u;
    } else if (MODE == 7u) {
        uvec4 n0 = nodes[4u * i];
        if ((n0.x & 0xFFu) == 0u) return;
        uint c = n0.w;
        uvec4 c0 = nodes[4u * c];
        bool ok = c0.x == n0.x && c0.y == n0.y && c0.w == c;
        uint valid = n0.x & 0xFFu, leaf = n0.x >> 8, k = 0u;
        for (uint o = 0u; o < 8u && ok; o++) {
            if ((valid >> o & 1u) == 0u) continue;
            uint a = node_at(i, k), b = node_at(c, k);
            if ((leaf >> o & 1u) != 0u) ok = a == b;
            else ok = nodes[4u * a].w == nodes[4u * b].w && (nodes[4u * a].x & 0xFFu) != 0u;
            k++;
        }
        if (!ok) atomicOr(misc[0], 1u);
    } else if (MODE == 8u) {
        uvec4 n0 = nodes[4u * i];
        if ((n0.x & 0xFFu) == 0u || n0.w != i) return;
        keys[pos[i]] = uvec2(n0.z, 0u);
        vals[pos[i]] = i;
    } else if (MODE == 9u) {
        pos[i] = 3u + bitCount(nodes[4u * vals[i]].x & 0xFFu);
    } else if (MODE == 10u) {
        uint q = vals[i];
        nodes[4u * q + 1u].z = pos[i];
        nodes[4u * q + 1u].w = i; /* its index in pool order (the table slot is no longer needed) */
        uint r = nodes[4u * q].y;
        if (i == 0u || nodes[4u * vals[i - 1u]].y != r) rbase[r] = pos[i];
    } else if (MODE == 11u) {
        uint q = vals[i];
        uvec4 n0 = nodes[4u * q];
        uint at = pos[i], b = rbase[n0.y];
        uint valid = n0.x & 0xFFu, leaf = n0.x >> 8, k = 0u;
        pool[at] = n0.x;
        pool[at + 1u] = nrep[q].w;
        pool[at + 2u] = 0xFFFFFFFFu;
        for (uint o = 0u; o < 8u; o++) {
            if ((valid >> o & 1u) == 0u) continue;
            uint a = node_at(q, k);
            pool[at + 3u + k] = (leaf >> o & 1u) != 0u ? a : nodes[4u * nodes[4u * a].w + 1u].z - b;
            k++;
        }
    } else if (MODE == 13u) { /* per cell tuple (pc.base of them): its slot, its id */
        uvec4 t = utab[i];
        uint j = thash(t.xyz, t.w) & pc.smask & pc.mask;
        for (;;) {
            uint cur = atomicCompSwap(ttab[j].x, 0xFFFFFFFFu, i);
            if (cur == 0xFFFFFFFFu) break;
            j = (j + 1u) & pc.mask;
        }
        ttab[j].y = i - rinfo[t.w].y;
    } else if (MODE == 14u) { /* per canonical node: its representative's slot, found or claimed */
        uvec4 n0 = nodes[4u * i];
        if ((n0.x & 0xFFu) == 0u || n0.w != i) return;
        uvec3 t = nrep[i].xyz;
        uint code = pc.base + i, j = thash(t, n0.y) & pc.smask & pc.mask;
        for (;;) {
            uint cur = atomicCompSwap(ttab[j].x, 0xFFFFFFFFu, code);
            if (cur == 0xFFFFFFFFu) break;
            uvec4 o = tuple_of(cur);
            if (o.xyz == t && o.w == n0.y) break;
            j = (j + 1u) & pc.mask;
        }
        nrep[i].w = j;
    } else if (MODE == 15u) { /* the slots that nodes claimed: new ids, counted per region */
        uvec4 n0 = nodes[4u * i];
        if ((n0.x & 0xFFu) == 0u || n0.w != i) return;
        uint j = nrep[i].w;
        if (ttab[j].x == pc.base + i) ttab[j].y = atomicAdd(rnew[n0.y], 1u) | 0x80000000u;
    } else if (MODE == 16u) { /* one invocation: each region's first new tuple in ext */
        uint sum = 0u;
        for (uint r = 0u; r < pc.level; r++) {
            rnew[pc.level + r] = sum;
            sum += rnew[r];
        }
        rnew[2u * pc.level] = sum;
    } else if (MODE == 17u) { /* representative ids; the new tuples written once */
        uvec4 n0 = nodes[4u * i];
        if ((n0.x & 0xFFu) == 0u || n0.w != i) return;
        uint j = nrep[i].w, t = ttab[j].y, id = t;
        if ((t & 0x80000000u) != 0u) {
            uint k = t & 0x7FFFFFFFu;
            id = rinfo[n0.y].z + k;
            if (ttab[j].x == pc.base + i) ext[rnew[pc.level + n0.y] + k] = uvec4(nrep[i].xyz, n0.y);
        }
        nrep[i].w = id;
    } else if (MODE == 18u) { /* per node in pool order: its run in the table */
        uint v[8], r;
        uint n = run_of(i, v, r), j = run_hash(v, n, r) & pc.smask & pc.mask;
        for (;;) {
            uint cur = atomicCompSwap(rtab[j].x, 0xFFFFFFFFu, i);
            if (cur == 0xFFFFFFFFu || run_is(cur, v, n, r)) break;
            j = (j + 1u) & pc.mask;
        }
        rnode[i].x = j;
        atomicMin(rtab[j].y, i);
    } else if (MODE == 19u) { /* the run's target; the records node i stores */
        uint v[8], r;
        uint n = run_of(i, v, r), t = rtab[rnode[i].x].y;
        bool uni = true;
        for (uint k = 1u; k < n; k++) uni = uni && v[k] == v[0];
        for (uint L = n + 1u; uni && L <= 8u; L++) { /* the longest uniform run of v so far */
            uint f = uniform_first(v[0], L, r);
            if (f < i) t = f;
        }
        rnode[i].y = t;
        pos[i] = t == i ? n : 0u;
        if (i == 0u || nodes[4u * vals[i - 1u]].y != r) rfirst[2u * r].x = i;
        if (i + 1u == pc.n || nodes[4u * vals[i + 1u]].y != r) rfirst[2u * r].z = i;
    } else if (MODE == 20u) { /* after pos's scan: the node's first record into pool word 2, the stored ids */
        uint q = vals[i], r = nodes[4u * q].y, f = rfirst[2u * r].x, t = rnode[i].y, base = pos[f];
        pool[nodes[4u * q + 1u].z + 2u] = pos[t] - base;
        if (i == f) rfirst[2u * r].y = base;
        if (t == i) {
            uint v[8], rr;
            uint n = run_of(i, v, rr);
            for (uint k = 0u; k < n; k++) rids[pos[i] + k] = v[k];
        }
    } else if (MODE == 30u) { /* the records' attributes (itin: rgba, itout: normal, start: material) */
        uint q = vals[i], r = nodes[4u * q].y, R = pc.level;
        uint q_root = vals[rfirst[2u * r].z], root = pool[nodes[4u * q_root + 1u].z + 1u];
        uint slot = 4u + 7u * R + 4u * r;
        if (i == rfirst[2u * r].x) { /* once a region: the root's representative */
            uvec4 tr = tuple_of(r, root, R);
            misc[slot + 1u] = tr.x;
            misc[slot + 2u] = tr.y;
            misc[slot + 3u] = tr.z & 0xFFFFu;
        }
        if (rnode[i].y != i) return; /* its run is stored elsewhere */
        uint v[8], rr;
        uint n = run_of(i, v, rr), at = pos[i];
        for (uint k = 0u; k < n; k++) {
            uvec4 t = tuple_of(r, v[k], R);
            uint g = at + k;
            if ((pc.attrs & 1u) != 0u) itin[g >> 2u][g & 3u] = t.x;
            if ((pc.attrs & 2u) != 0u) itout[g >> 2u][g & 3u] = t.y;
            if ((pc.attrs & 4u) != 0u) atomicOr(start[g >> 1u], (t.z & 0xFFFFu) << (16u * (g & 1u)));
            if (v[k] == root) atomicMax(misc[slot], ~g);
        }
    } else if (MODE == 21u) { /* the blocks' first guess; lone records keyed for the sort */
        uint q = vals[i], r = nodes[4u * q].y, hdr = nodes[4u * q].x;
        uint nn = bitCount((hdr & 0xFFu) & ~(hdr >> 8));
        lay[i] = uvec2(nn + 1u, nn == 0u ? i : 0u);
        keys[i] = uvec2(nn == 0u ? rfirst[2u * r].y + pool[nodes[4u * q + 1u].z + 2u] : 0xFFFFFFFFu, 0u);
        start[i] = i;
    } else if (MODE == 23u) {
        pos[i] = lay[i].x;
    } else if (MODE == 29u) {
        if (misc[2] == 0u) {
            misc[3] += 1u;
            if (misc[1] == 0u) misc[2] = 1u;
        }
    } else if (MODE == 24u) { /* a node with node children: its far words from the positions */
        if (misc[2] != 0u) return;
        uint q = vals[i], r = nodes[4u * q].y, cb[8], cd[8];
        uint nn = node_kids(q, cb, cd);
        if (nn == 0u) return;
        uint cur = pos[i] - pos[rfirst[2u * r].x], nfar;
        far_slots(cur, cb, nn, nfar);
        uvec2 nw = uvec2(nfar + nn + 1u, 0u);
        if (lay[i] != nw) {
            lay[i] = nw;
            misc[1] = 1u;
        }
    } else if (MODE == 25u) { /* a group of lone records with one run, in pool order: reuse or a new copy */
        if (misc[2] != 0u) return;
        uint key = keys[i].x;
        if (key == 0xFFFFFFFFu || (i > 0u && keys[i - 1u].x == key)) return;
        uint last = 0u, lk = 0u;
        bool any = false;
        for (uint t = i; t < pc.n && keys[t].x == key; t++) {
            uint k = start[t], p = pos[k];
            uvec2 nw;
            if (any && p - last + 64u < pc.mask) {
                nw = uvec2(0u, lk);
            } else {
                last = p, lk = k, any = true;
                nw = uvec2(1u, k);
            }
            if (lay[k] != nw) {
                lay[k] = nw;
                misc[1] = 1u;
            }
        }
    } else if (MODE == 26u) { /* the block's words: far words, descriptors, the run's first record */
        uvec2 l = lay[i];
        if (l.x == 0u) return;
        uint q = vals[i], r = nodes[4u * q].y, cb[8], cd[8];
        uint nn = node_kids(q, cb, cd), base = pos[rfirst[2u * r].x], cur = pos[i] - base, ob = base + 2u * r, nfar;
        uint fb = far_slots(cur, cb, nn, nfar), w = ob + cur, fi = 0u, bstart = cur + nfar;
        for (uint k = 0u; k < nn; k++)
            if ((fb >> k & 1u) != 0u) rids[w++] = cb[k];
        for (uint k = 0u; k < nn; k++) {
            uint at = bstart + k;
            rids[ob + at] = (fb >> k & 1u) != 0u ? desc_make(at - (cur + fi++), true, cd[k]) : desc_make(at - cb[k], false, cd[k]);
        }
        rids[ob + bstart + nn] = pool[nodes[4u * q + 1u].z + 2u];
        if (nfar != 0u) atomicAdd(rfirst[2u * r + 1u].z, nfar);
        if (nn != 0u) atomicAdd(rfirst[2u * r + 1u].w, nn); /* descriptor words */
    } else if (MODE == 22u) { /* per region: counts cleared (level 0), the root descriptor (level 1) */
        uint f = rfirst[2u * i].x;
        if (f == 0xFFFFFFFFu) return;
        if (pc.level == 0u) {
            rfirst[2u * i + 1u] = uvec4(0u);
            return;
        }
        uint last = rfirst[2u * i].z, base = pos[f], ob = base + 2u * i, W = pos[last] + lay[last].x - base, blk = block_at(last);
        uint q = vals[last], hdr = nodes[4u * q].x, far = rfirst[2u * i + 1u].z, nd = rfirst[2u * i + 1u].w + 1u;
        rfirst[2u * i].w = pool[nodes[4u * q + 1u].z + 1u]; /* the root's representative */
        if (W - blk > pc.mask) {
            rids[ob + W] = blk;
            rids[ob + W + 1u] = desc_make(1u, true, hdr);
            rfirst[2u * i + 1u] = uvec4(ob, W + 2u, far + 1u, nd);
        } else {
            rids[ob + W] = desc_make(W - blk, false, hdr);
            rfirst[2u * i + 1u] = uvec4(ob, W + 1u, far, nd);
        }
    } else if (MODE == 12u) {
        uvec4 ro = rout[i];
        if (ro.y == 0u && rbase[i] != 0xFFFFFFFFu) rout[i].x = nodes[4u * nodes[4u * ro.x].w + 1u].z - rbase[i];
    }
}
