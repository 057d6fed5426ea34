/* render/node_order.h - a model's node words re-laid out for the trace
 * kernels' caches (issue 21; internal to render/, plain C, no Vulkan).
 *
 * The .svo file holds a model's blocks in the builder's creation order, a
 * post-order: the block of a node's children is written when its subtree is
 * done, so the first child's block sits behind all its later siblings'
 * subtrees, and a walk that pushes from a node to its children lands in a
 * cache line far from the parent's. vx__node_order writes the same octree
 * (the same descriptors' masks, attribute words and so the same colour
 * records, svo/svo.h's format with backward pointers and far slots) with
 * the blocks in treelets: from a treelet's root block, blocks breadth-first
 * until the treelet holds `words` words (a block is never split), then each
 * block left at the treelet's frontier roots its own treelet, depth-first.
 * A DAG-shared block is placed once, after every block that points to it (a
 * block joins a treelet when its last parent is placed), so pointers still
 * go backwards. Unreachable words are dropped. */
#ifndef VX_RENDER_NODE_ORDER_H
#define VX_RENDER_NODE_ORDER_H

#include <stdbool.h>
#include <stdint.h>

#include "svo/svo.h"

typedef struct vx__node_order_desc {
    uint32_t words; /* treelet size in words (0: 32, one 128-byte line); 1 gives a plain depth-first order */
    /* 0: none; else a treelet of at most align words that would cross a
     * multiple of align words starts at the next one, and the words' count
     * is a multiple of it (gaps of zero words; the model's first word must
     * be placed at a multiple of align for lines to match) */
    uint32_t align;
    uint32_t limit; /* largest near pointer (0: 32767, the descriptor's 15 bits; tests lower it to force far slots) */
} vx__node_order_desc;

/* The words of model m in treelet order: *out (count *out_count, allocated
 * with alloc, the caller frees) and the root descriptor's index *out_root.
 * Returns false, with *out NULL, where m has no descriptor to reorder (an
 * empty or leaf root), is out of memory, or where its words do not form the
 * tree svo/svo.h describes (a pointer out of range or not backwards, a block
 * reached with two lengths); the caller then keeps the file's words. */
bool vx__node_order(const vx_svo_model* m, const vx__node_order_desc* desc, const vx_allocator* alloc, uint32_t** out,
                    uint32_t* out_count, uint32_t* out_root);

#endif
