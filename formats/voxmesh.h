/* formats/voxmesh.h - the surface of a set of voxels as axis-aligned quads
 * (greedy meshing), for mesh exports (svo_info --to-glb).
 *
 * A voxel is a unit cell [x, x+1] x [y, y+1] x [z, z+1] with a colour. A
 * face of a cell is exposed when the cell on its other side is not in the
 * set (cells outside 0..2^21-1 count as empty). Every exposed face is
 * covered by exactly one quad and no other face is. The space is cut into
 * bricks of 64^3 cells, meshed independently (on every core for large
 * sets; the output does not depend on the thread count): within a brick the
 * quads of one plane and direction are greedy: each unused face, in
 * row-major order, starts a quad that grows along u while the colour (and
 * the material id, where given) holds,
 * then along v while the whole row segment matches. Quads do not cross
 * brick boundaries. The naive mesh (one quad per exposed face) is
 * vx_voxmesh.faces quads.
 *
 * Axes: a quad with normal axis a spans u along axis (a+1)%3 and v along
 * axis (a+2)%3, so u x v points to +a: corners (u0,v0) (u1,v0) (u1,v1)
 * (u0,v1) run counter-clockwise seen from the +a side.
 *
 *   vx_voxmesh m;
 *   vx_voxmesh_build(NULL, xyz, rgba, n, &m, &err);
 *   ... m.quads[i] ...
 *   vx_voxmesh_free(&m);
 */
#ifndef VX_VOXMESH_H
#define VX_VOXMESH_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "svo/core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Largest cell coordinate + 1 (the .svo limit, 2^21 cells per side). */
#define VX_VOXMESH_MAX_COORD (1u << 21)

typedef struct vx_voxmesh_quad {
    uint8_t axis;      /* 0 x, 1 y, 2 z: the axis the face's normal lies on */
    bool positive;     /* normal +axis (the cell is at plane - 1) or -axis (cell at plane) */
    uint32_t plane;    /* coordinate of the face's plane along axis, 0..2^21 */
    uint32_t u0, u1;   /* extent along axis (axis+1)%3, u0 < u1 */
    uint32_t v0, v1;   /* extent along axis (axis+2)%3, v0 < v1 */
    uint32_t rgba;     /* colour of the cells behind the quad (as given) */
    uint32_t material; /* material id of those cells (as given; 0 without ids) */
} vx_voxmesh_quad;

typedef struct vx_voxmesh {
    size_t quad_count;
    vx_voxmesh_quad* quads; /* by brick (in the order of each brick's first cell in the
                               input), then by axis, direction, plane, v0, u0 */
    uint64_t faces;         /* exposed unit faces (the quads' total area) */
    const vx_allocator* alloc;
} vx_voxmesh;

/* Meshes count cells given as xyz[3i..3i+2] (each < VX_VOXMESH_MAX_COORD)
 * with colours rgba[i] (may be NULL: one colour). A cell given twice is
 * VX_ERR_INVALID_ARG. */
vx_result vx_voxmesh_build(const vx_allocator* alloc, const uint32_t* xyz, const uint32_t* rgba, size_t count,
                           vx_voxmesh* out, vx_error* err);
/* The same with a material id per cell (material[i]; NULL: as
 * vx_voxmesh_build): a quad then covers cells of one colour and one id, so
 * an export can draw each id's faces with its own material. */
vx_result vx_voxmesh_build_material(const vx_allocator* alloc, const uint32_t* xyz, const uint32_t* rgba,
                                    const uint32_t* material, size_t count, vx_voxmesh* out, vx_error* err);
void vx_voxmesh_free(vx_voxmesh* m);

#ifdef __cplusplus
}
#endif
#endif /* VX_VOXMESH_H */
