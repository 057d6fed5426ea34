// render/shaders/compact_attr.glsl - the compact layout's model record and
// the shared reads of it (render/compact.h): a brick's descriptors, a
// cell's attribute index (a descent from the model's root) and the decode
// of its attribute block. Included by trace_compact.comp (the single-shader
// frame) and trace_common.glsl (every kernel that traces, where its COMPACT
// constant is set), which say where the layout lives:
//   CA_SLOT(i)  the geometry's 64-bit slot i (uvec2)
//   CA_ATTR(i)  attribute word i
//   CA_PAL(i)   palette entry i (RGBA)
//   CA_PAGES    the paged layout's page count (0: the whole layout)
//   CA_DICT     false: no node has VX_COMPACT_INDEXED (the index words' code is dead)
//   CA_UNI      false: no start-table entry is CA_TAB_UNIFORM (its tests are dead)
// render/compact_gpu.c writes CModel (cmodel_gpu). Included twice: first
// without CA_SLOT (the record, before the buffers that hold it), then with
// the macros defined (the functions, after the buffers).
#ifndef CA_SLOT

// flags: 1 has colours, 2 exact; kind: 1 palette indices, 2 RGBA; box as
// trace.comp's Model.box; rank_base: the word of slot 0's rank (the rank of
// slot s of level >= 5 is word rank_base + s of the geometry, levels 3-4
// keep theirs in bits 16..31 of word 0; the paged layout has a rank word
// per slot of level >= 3, a page its own base, in its header);
// rebase as trace.comp's Model.rebase; page_up: the page level + 1 for a
// paged model (its nodes of that level have their children's slots in the
// top, pages below), else 0
// pool_base, unit_log2: the pool's first slot and its unit (a page at slot P
// is in unit (P - pool_base) >> unit_log2)
// tab_word, tab_k: the model's start table in the attribute words (its
// first word), and its level K (0: none; render/compact_gpu.c): entry
// (x | y << D | z << 2D) of a level-K cube (D = depth - K) is its node's
// slot and the cells before it, or CA_TAB_FULL and the index of its first
// cell inside a full leaf cube
// value: the colour of every cell where flags has 4 (a model of one value), else 0
// rec3: the whole layout: level-3 slot s's record (vx__compact_level3_records)
// is slot rec3 + s of the geometry, 0 none (cell_index_path)
// flags 8 (CA_MATERIAL, the passes' records of the whole layout only, which
// has no pool): the model's material ids, coded as its colours (RGBA width,
// its block) in the attribute words from pool_base (render/compact_gpu.c,
// where a material channel names materials other than diffuse;
// ca_table_index)
struct CModel { uint root, depth, flags, box, attr_base, block_log2, kind, rank_base, rebase, page_up, pool_base, unit_log2, tab_word, tab_k, value, rec3; };
#else
// bit 0 of each byte of w: the byte is not zero; packed into 4 bits
uint bytes_set(uint w) {
    // bit 7 of each byte: the byte is not zero; the product moves bits 7, 15,
    // 23, 31 to 28..31 without carries (fewer operations than or-folding
    // the bytes: 1-3% of the H200's rays/s, docs/PERFORMANCE.md issue 18)
    uint x = (((w & 0x7F7F7F7Fu) + 0x7F7F7F7Fu) | w) & 0x80808080u;
    return (x * 0x00204081u) >> 28;
}

// A brick's level-2 descriptor (trace.comp form, valid << 8): its level-1
// octants that hold cells, none a leaf.
uint brick_desc(uvec2 b) { return (bytes_set(b.x) | (bytes_set(b.y) << 4)) << 8; }
// Octant o of a brick as a level-1 descriptor: its cells, all leaves.
uint brick_octant(uvec2 b, uint o) {
    uint v = ((o < 4u ? b.x : b.y) >> (8u * (o & 3u))) & 0xFFu;
    return (v << 8) | v;
}

// Geometry word w (a select, not a dynamic component index: issue 21, the
// NVIDIA compiler's code for those never finished on some pixels).
uint ca_word(uint w) {
    uvec2 p = CA_SLOT(w >> 1);
    return (w & 1u) != 0u ? p.y : p.x;
}
// A level-3 node whose word 0 has bit 31 (CA_INDEXED: a scene built with
// the brick dictionary) has its bricks' index words in its children's
// block (render/compact.h): the brick's dictionary slot in the low
// CA_BRICK_BITS bits, the cells of the block up to it, less one, above.
const uint CA_INDEXED = 0x80000000u, CA_BRICK_BITS = 23u, CA_BRICK_MASK = (1u << CA_BRICK_BITS) - 1u;
// The slot of child k (block order) of a level-lvl node with word 0 desc whose children's block is blk.
uint ca_child(int lvl, uint desc, uint blk, uint k) {
    return CA_DICT && lvl == 3 && (desc & CA_INDEXED) != 0u ? ca_word(blk + k) & CA_BRICK_MASK : blk + k;
}

// The n bits (n <= 32) at bit pos of the attribute words from word. Both
// words are loaded without a branch (the second is the first again where
// the field does not straddle: its bits then land at or above 32 - sh >= n,
// which the extraction drops), so their loads issue together.
uint attr_bits(uint word, uint pos, uint n) {
    uint w = word + (pos >> 5), sh = pos & 31u;
    uint hi = CA_ATTR(sh + n > 32u ? w + 1u : w);
    return bitfieldExtract((CA_ATTR(w) >> sh) | ((hi << 1) << (31u - sh)), 0, int(n));
}
// The width-bit value k (width 8 or 32) of a payload's values from word:
// byte or word aligned, so one load and one extraction.
uint attr_value(uint word, uint k, uint width) {
    uint pos = k * width;
    return bitfieldExtract(CA_ATTR(word + (pos >> 5)), int(pos & 31u), int(width));
}

uint part1by2(uint x) {
    x &= 0x3FFu;
    x = (x | (x << 16)) & 0x030000FFu;
    x = (x | (x << 8)) & 0x0300F00Fu;
    x = (x | (x << 4)) & 0x030C30C3u;
    x = (x | (x << 2)) & 0x09249249u;
    return x;
}
uint morton(uvec3 c) { return part1by2(c.x) | (part1by2(c.y) << 1) | (part1by2(c.z) << 2); }
// morton(c & 3u): a brick's cell from the low 2 bits of each coordinate
uint morton2(uvec3 c) {
    return (c.x & 1u) | ((c.y & 1u) << 1) | ((c.z & 1u) << 2) | ((c.x & 2u) << 2) | ((c.y & 2u) << 3) | ((c.z & 2u) << 4);
}

// The cells in the children before child cbit of a level-lvl node (lvl >=
// 3) with descriptor desc and children's block blk, k of them not leaves:
// its leaf cubes before, and the rank of slot k - 1 of the block (the
// whole layout: a rank word at levels >= 6, word 0's bits 16..31 at 4-5;
// the paged layout: a rank word at levels >= 4; at level 3 the brick's
// index word, or the popcounts of the bricks before, which have no rank).
uint cells_before(uint rank_base, int lvl, uint desc, uint blk, uint k, uint cbit) {
    // rank_base: the word of slot 0's rank
    uint leaves = uint(bitCount(desc & 0xFFu & (cbit - 1u)));
    // (a leaf cube of level 11 or more would pass 2^32 cells: the builder refuses it)
    uint r = lvl <= 11 ? leaves << (3u * uint(lvl - 1)) : 0u;
    if (k == 0u) return r;
    if (lvl > (CA_PAGES == 0u ? 5 : 3)) {
        r += ca_word(rank_base + blk + k - 1u);
    } else if (lvl > 3) {
        // word 0's bits 16..31 (level 3: 16..30, bit 31 is CA_INDEXED)
        r += (CA_SLOT(blk + k - 1u).x >> 16) & (lvl == 4 ? 0x7FFFu : 0xFFFFu);
    } else if (CA_DICT && (desc & CA_INDEXED) != 0u) {
        r += (ca_word(blk + k - 1u) >> CA_BRICK_BITS) + 1u;
    } else {
        // bricks have no rank: the cells of the bricks before (the push
        // reads brick k's cache line anyway)
        for (uint i = 0u; i < k; i++) {
            uvec2 b = CA_SLOT(blk + i);
            r += uint(bitCount(b.x)) + uint(bitCount(b.y));
        }
    }
    return r;
}
// a start table's entry inside a full leaf cube (CModel.tab_k), and one
// whose cells all hold one value (CA_TAB_UNIFORM | a palette model's
// palette index; its second word the colour)
const uint CA_TAB_FULL = 0xFFFFFFFFu, CA_TAB_UNIFORM = 0xFFFFFE00u;
// cell_index's attribute base for a cell of a uniform cube (CA_UNIFORM |
// the palette index): the index it returns is then the colour itself
// (decode_color; decode_value gives the palette index or the colour)
const uint CA_UNIFORM = 0xFFFFFF00u;
// The attribute index of set cell c (vx_compact_lookup): a descent from the
// root, or from the node of its level-K cube in the model's start table
// (CModel.tab_k), after the hit (measured faster on the H200 than a
// running count in the walk, docs/PERFORMANCE.md issue 18).
// In a resident page the index is from the page's first cell, and
// attr_base becomes the page's attribute region.
// The cells before child cbit of a level-3 node nd (k of its children
// before cbit are bricks) whose previous slot's rank is prev: its leaf cubes
// before, and the bricks before child k, or where fewer come after it, the
// node's cells (its rank less prev) less its leaf cubes and the bricks from
// k on: one loop of at most 4 brick loads.
uint bricks_before(uvec2 nd, uint k, uint cbit, uint prev) {
    uint nb = uint(bitCount((nd.x >> 8) & ~nd.x & 0xFFu));
    bool back = 2u * k > nb;
    uint a = back ? k : 0u, cnt = back ? nb - k : k, sum = 0u;
    for (uint i = 0u; i < cnt; i++) {
        uvec2 b = CA_SLOT(nd.y + a + i);
        sum += uint(bitCount(b.x)) + uint(bitCount(b.y));
    }
    uint own = ((nd.x >> 16) & 0x7FFFu) - prev - (uint(bitCount(nd.x & 0xFFu)) << 6);
    return (uint(bitCount(nd.x & 0xFFu & (cbit - 1u))) << 6) + (back ? own - sum : sum);
}

uint cell_index(CModel m, uvec3 c, out uint attr_base) {
    attr_base = m.attr_base;
    if (m.root == ROOT_LEAF) return morton(c);
    uint n = m.root, base = 0u, rank_base = m.rank_base;
    int L = int(m.depth);
    // each level's octant from the cell's bits, the brick's cell by morton2:
    // the whole Morton code (a part1by2 per axis) only where a leaf cube
    // holds the cell (0.4-2.7% of the H200's albedo rays/s on the close-ups,
    // docs/PERFORMANCE.md issue 18, ninth step)
    uint K = m.tab_k;
    if (CA_PAGES == 0u && K != 0u) {
        // the table's entry of the cell's level-K cube (D = depth - K bits a side)
        uint D = m.depth - K;
        uvec3 r = c >> K;
        uint e = m.tab_word + 2u * (r.x | (r.y << D) | (r.z << (2u * D)));
        n = CA_ATTR(e);
        base = CA_ATTR(e + 1u);
        if (n == CA_TAB_FULL) return base + morton(c & ((1u << K) - 1u));
        if (CA_UNI && (n & 0xFFFFFF00u) == CA_TAB_UNIFORM) {
            attr_base = CA_UNIFORM | (n & 0xFFu);
            return base;
        }
        L = int(K);
    }
    // the rank of the level-3 node's previous slot in its block (the level-4
    // step reads it), so that its own cells are known at level 3
    uint prev = 0u;
    bool have_prev = false;
    for (; L >= 3; L--) {
        uvec2 nd = CA_SLOT(n);
        if (CA_PAGES > 0u && uint(L) + 1u == m.page_up && ((nd.x >> 8) & ~nd.x & 0xFFu) != 0u) {
            // a page root (resident: the ray hit a cell inside): its header
            // precedes its first block
            uvec2 hd = CA_SLOT(nd.y - 2u);
            attr_base = hd.x, rank_base = hd.y, base = 0u;
        }
        uint s = uint(L - 1);
        uint o = ((c.x >> s) & 1u) | (((c.y >> s) & 1u) << 1) | (((c.z >> s) & 1u) << 2);
        uint cbit = 1u << o, k = uint(bitCount((nd.x >> 8) & ~nd.x & (cbit - 1u)));
        if (CA_PAGES == 0u && L == 4) {
            // cells_before's level-4 form, the rank kept
            prev = k > 0u ? (CA_SLOT(nd.y + k - 1u).x >> 16) & 0x7FFFu : 0u;
            have_prev = true;
            base += (uint(bitCount(nd.x & 0xFFu & (cbit - 1u))) << 9) + prev;
        } else if (CA_PAGES == 0u && L == 3 && have_prev && !(CA_DICT && (nd.x & CA_INDEXED) != 0u)) {
            // level 3 after a ranked slot: the bricks' popcounts
            base += bricks_before(nd, k, cbit, prev);
        } else {
            base += cells_before(rank_base, L, nd.x, nd.y, k, cbit);
        }
        if ((nd.x & cbit) != 0u) return base + morton(c & ((1u << s) - 1u));
        n = ca_child(L, nd.x, nd.y, k);
    }
    // L is 2 here, or the depth of a model of 1 or 2 levels (c below 2^L)
    uint bit = morton2(c);
    uvec2 b = CA_SLOT(n);
    uint below = bit < 32u ? uint(bitCount(b.x & ((1u << bit) - 1u)))
                           : uint(bitCount(b.x)) + uint(bitCount(b.y & ((1u << (bit - 32u)) - 1u)));
    return base + below;
}

// The start table's entry of cell c's level-K cube (CModel.tab_k) and the
// levels K..5 below it (cell_index_table, cell_index_path): true where that
// gives the index (base: in a full leaf cube, or a uniform cube's value, its
// attr_base set), else false, n the level-4 node's slot (the level-3 node's
// for K = 3) and base the cells before it.
bool table_to_level4(CModel m, uvec3 c, out uint n, out uint base, inout uint attr_base) {
    uint K = m.tab_k, D = m.depth - K;
    uvec3 r = c >> K;
    uint e = m.tab_word + 2u * (r.x | (r.y << D) | (r.z << (2u * D)));
    n = CA_ATTR(e);
    base = CA_ATTR(e + 1u);
    if (n == CA_TAB_FULL) {
        base += morton(c & ((1u << K) - 1u));
        return true;
    }
    if (CA_UNI && (n & 0xFFFFFF00u) == CA_TAB_UNIFORM) {
        attr_base = CA_UNIFORM | (n & 0xFFu);
        return true;
    }
    for (int L = int(K); L >= 5; L--) {
        uvec2 nd = CA_SLOT(n);
        uint s = uint(L - 1);
        uint o = ((c.x >> s) & 1u) | (((c.y >> s) & 1u) << 1) | (((c.z >> s) & 1u) << 2);
        uint cbit = 1u << o, k = uint(bitCount((nd.x >> 8) & ~nd.x & (cbit - 1u)));
        base += cells_before(m.rank_base, L, nd.x, nd.y, k, cbit);
        if ((nd.x & cbit) != 0u) {
            base += morton(c & ((1u << s) - 1u));
            return true;
        }
        n = nd.y + k;
    }
    return false;
}

// cell_index for the whole layout (no pages) where the model's start table
// is of level K >= 4: the levels above 4 in a loop, levels 4 and 3 after it
// in straight code (cell_index tests a step's level for their forms):
// +2.5% of the H200's albedo rays/s on the helmet's close-up (levels 4, 3
// and the brick below its table), the other views within 0.3%
// (docs/PERFORMANCE.md issue 18, twelfth step). Other models: cell_index.
uint cell_index_table(CModel m, uvec3 c, out uint attr_base) {
    attr_base = m.attr_base;
    if (m.root == ROOT_LEAF || m.tab_k < 4u) return cell_index(m, c, attr_base);
    uint n, base;
    if (table_to_level4(m, c, n, base, attr_base)) return base;
    // level 4: the rank of the level-3 node's previous slot kept
    uvec2 nd = CA_SLOT(n);
    uint o = ((c.x >> 3u) & 1u) | (((c.y >> 3u) & 1u) << 1) | (((c.z >> 3u) & 1u) << 2);
    uint cbit = 1u << o, k = uint(bitCount((nd.x >> 8) & ~nd.x & (cbit - 1u)));
    uint prev = k > 0u ? (CA_SLOT(nd.y + k - 1u).x >> 16) & 0x7FFFu : 0u;
    base += (uint(bitCount(nd.x & 0xFFu & (cbit - 1u))) << 9) + prev;
    if ((nd.x & cbit) != 0u) return base + morton(c & 7u);
    n = nd.y + k;
    // level 3
    nd = CA_SLOT(n);
    o = ((c.x >> 2u) & 1u) | (((c.y >> 2u) & 1u) << 1) | (((c.z >> 2u) & 1u) << 2);
    cbit = 1u << o, k = uint(bitCount((nd.x >> 8) & ~nd.x & (cbit - 1u)));
    if (CA_DICT && (nd.x & CA_INDEXED) != 0u) {
        base += cells_before(m.rank_base, 3, nd.x, nd.y, k, cbit);
    } else {
        base += bricks_before(nd, k, cbit, prev);
    }
    if ((nd.x & cbit) != 0u) return base + morton(c & 3u);
    n = ca_child(3, nd.x, nd.y, k);
    uint bit = morton2(c);
    uvec2 b = CA_SLOT(n);
    uint below = bit < 32u ? uint(bitCount(b.x & ((1u << bit) - 1u)))
                           : uint(bitCount(b.x)) + uint(bitCount(b.y & ((1u << (bit - 32u)) - 1u)));
    return base + below;
}

// The attribute index of cell c of a model with level-3 records (CModel.rec3)
// and a start table of level K >= 3, where the walk hit it inside brick brk
// below level-3 node n3 and level-4 node n4 (the walk's stack): the table's
// entry, the levels K..5 as cell_index_table's, then in loads that wait on
// none of those nor on each other: n3's record (its cells before the brick's
// octant), n4's slot (its leaf cubes before n3's octant, its children's
// block) and the slot before n3 (the cells of n4's children before n3: its
// rank, where n3 is not the block's first). cell_index_table's descent below
// the table is a chain of dependent loads (level 4's slot, then level 3's and
// the rank, then the bricks before): the helmet's close-up at 512 0.857 ->
// 0.886 of trace.comp's albedo rays/s on the H200 with its table of level 3
// (docs/PERFORMANCE.md issue 18, branch ck11).
uint cell_index_path(CModel m, uvec3 c, uint n3, uint n4, uvec2 brk, out uint attr_base) {
    attr_base = m.attr_base;
    // (a table of level 3 holds level 4's cells in its entry: no level-4 loads)
    bool k4 = m.tab_k >= 4u;
    uvec2 rec = CA_SLOT(m.rec3 + n3), s4 = k4 ? CA_SLOT(n4) : uvec2(0u), sp = k4 ? CA_SLOT(max(n3, 1u) - 1u) : uvec2(0u);
    uint n, base;
    if (table_to_level4(m, c, n, base, attr_base)) return base; // (a uniform cube)
    if (k4) {
        uint o4 = ((c.x >> 3u) & 1u) | (((c.y >> 3u) & 1u) << 1) | (((c.z >> 3u) & 1u) << 2);
        base += (uint(bitCount(s4.x & 0xFFu & ((1u << o4) - 1u))) << 9) + (n3 != s4.y ? (sp.x >> 16) & 0x7FFFu : 0u);
    }
    // the record's 9-bit field o3 - 1 of its 64 bits
    uint o3 = ((c.x >> 2u) & 1u) | (((c.y >> 2u) & 1u) << 1) | (((c.z >> 2u) & 1u) << 2), p = 9u * (o3 - 1u);
    uint f = p < 32u ? (rec.x >> p) | (p > 23u ? rec.y << (32u - p) : 0u) : rec.y >> (p - 32u);
    uint before3 = o3 == 0u ? 0u : f & 0x1FFu;
    uint bit = morton2(c);
    uint below = bit < 32u ? uint(bitCount(brk.x & ((1u << bit) - 1u)))
                           : uint(bitCount(brk.x)) + uint(bitCount(brk.y & ((1u << (bit - 32u)) - 1u)));
    return base + before3 + below;
}

// The stored value of attribute index i (vx__compact_value: the palette
// index of a palette model, else RGBA).
uint decode_value(CModel m, uint attr_base, uint i) {
    if (CA_UNI && attr_base >= CA_UNIFORM) return m.kind == 1u ? attr_base & 0xFFu : i; // a uniform cube's (cell_index)
    uint B = 1u << m.block_log2, width = m.kind == 1u ? 8u : 32u;
    uint blk = i >> m.block_log2, j = i & (B - 1u);
    uint g = CA_ATTR(attr_base + (blk >> 6));
    uint h = CA_ATTR(attr_base + (g & 0x7FFFFFFFu) + ((g >> 31) != 0u ? 0u : (blk & 63u)));
    uint code = h & 31u, p = attr_base + (h >> 5);
    uint v;
    if (code == 30u) {
        // a delta block: per channel the minimum and its residuals' width
        // (4 bits each), bit 16 the decorrelation (R - G, G, B - G)
        uint mn = CA_ATTR(p), wc = CA_ATTR(p + 1u);
        uint o1 = wc & 15u, o2 = o1 + ((wc >> 4) & 15u), o3 = o2 + ((wc >> 8) & 15u), n = o3 + ((wc >> 12) & 15u);
        // the value's residuals are adjacent (at most 32 bits): one extraction
        uint bits = attr_bits(p + 2u, j * n, n);
        // each residual in its byte, all four added to the minimum in one
        // add: the encoder's residuals are value - minimum per channel
        // (render/compact.c flush_block), so no byte carries into the next
        // (with the arithmetic recorrelation below: the helmet's close-up at
        // 512 0.871 -> 0.878 of trace.comp's albedo rays/s on the H200;
        // its residuals' load issued before the widths arrive lost,
        // docs/PERFORMANCE.md issue 18, branch cdec)
        uint x = bitfieldExtract(bits, 0, int(o1)) | (bitfieldExtract(bits, int(o1), int(o2 - o1)) << 8) |
                 (bitfieldExtract(bits, int(o2), int(o3 - o2)) << 16) | ((bits >> o3) << 24);
        v = mn + x;
        // recorrelate (R + G - 128, B + G - 128 mod 256) as arithmetic, no
        // select: K is 0 where the block is not decorrelated; R and B each
        // in a 16-bit lane, whose sum (at most 638) stays in the lane
        uint K = ((wc >> 16) & 1u) * 0x00010001u;
        uint t = (v & 0x00FF00FFu) + ((v >> 8) & 0xFFu) * K + (K << 7);
        v = (v & 0xFF00FF00u) | (t & 0x00FF00FFu);
    } else {
        // raw values (code 31: value j), or a palette of the block's values
        // and its indices (code bits each; 0: one value, which reads no
        // index: the terrain's blocks, 96%)
        uint k = code == 31u ? j : 0u, q = p;
        if (code - 1u < 29u) {
            k = attr_bits(p, j * code, code);
            q = p + ((B * code + 31u) >> 5);
        }
        v = attr_value(q, k, width);
    }
    return v;
}
// The index into the passes' per-record tables of attribute index i whose
// stored value (decode_value) is v: the material id where the model has its
// ids (CA_MATERIAL), else a palette model's palette index, else 0 (svo/svo.h
// vx_svo_attr_material's rule; the tables, render_scene.c
// vx__render_scene_attr_material, are per id then, else per palette index).
// attr_base: cell_index's (a model with ids has no uniform table entries).
const uint CA_MATERIAL = 8u;
uint ca_table_index(CModel m, uint i, uint v) {
    if ((m.flags & CA_MATERIAL) != 0u) {
        CModel q = m;
        q.kind = 2u;
        return decode_value(q, m.pool_base, i);
    }
    return m.kind == 1u ? v & 0xFFu : 0u;
}
// The colour of attribute index i (vx_compact_rgba).
uint decode_color(CModel m, uint attr_base, uint i) {
    if (CA_UNI && attr_base >= CA_UNIFORM) return i; // a uniform cube's colour (cell_index)
    uint v = decode_value(m, attr_base, i);
    return m.kind == 1u ? CA_PAL(v & 0xFFu) : v;
}
// Whether cell c (inside the model's cube) is set: a descent as cell_index's
// that checks each level's valid bits (no pages).
bool cell_set(CModel m, uvec3 c) {
    if (m.root == ROOT_EMPTY) return false;
    if (m.root == ROOT_LEAF) return true;
    uint n = m.root;
    int L = int(m.depth);
    // the rank of the level-3 node's previous slot in its block (the level-4
    // step reads it), so that its own cells are known at level 3
    uint prev = 0u;
    bool have_prev = false;
    for (; L >= 3; L--) {
        uvec2 nd = CA_SLOT(n);
        uint s = uint(L - 1);
        uint o = ((c.x >> s) & 1u) | (((c.y >> s) & 1u) << 1) | (((c.z >> s) & 1u) << 2), cbit = 1u << o;
        if ((nd.x & (cbit << 8)) == 0u) return false;
        if ((nd.x & cbit) != 0u) return true;
        n = ca_child(L, nd.x, nd.y, uint(bitCount((nd.x >> 8) & ~nd.x & (cbit - 1u))));
    }
    uint bit = morton(c & ((1u << uint(L)) - 1u));
    uvec2 b = CA_SLOT(n);
    return (((bit < 32u ? b.x : b.y) >> (bit & 31u)) & 1u) != 0u;
}
#endif
