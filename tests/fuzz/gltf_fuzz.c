/* tests/fuzz/gltf_fuzz.c - glTF reader (tinygltf shim) then a tiny
 * voxelization of whatever loaded: read -> voxelize -> free. External files
 * are refused so a mutated URI cannot reach the file system. A mesh with
 * materials or lights is also converted into a scene, so that the
 * materials' plan (textures sampled per cell, their levels and ids, the MATL
 * records: convert/mesh_material.c, mesh.c) and the lights (voxkit's extras
 * record included: add_lights) run on every mutated factor, texture and
 * light. */
#include <stdlib.h>

#include "convert/mesh.h"
#include "formats/gltf.h"

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    vx_gltf_read_desc rd = {.no_external = true, .max_triangles = 1u << 18, .max_image_pixels = 1u << 20};
    vx_gltf_mesh m;
    if (vx_gltf_read(&rd, data, size, NULL, &m, NULL) != VX_OK) return 0;
    uint32_t *xyz = NULL, *rgba = NULL;
    size_t count = 0;
    if (vx_conv_mesh_cells(&(vx_conv_mesh_desc){.res = 12, .threads = 1}, &m, NULL, &xyz, &rgba, &count, NULL) ==
        VX_OK) {
        free(xyz);
        free(rgba);
    }
    if (m.material_count || m.light_count) {
        vx_svo_scene s;
        if (vx_conv_mesh(&(vx_conv_mesh_desc){.res = 12, .threads = 1}, &m, &s, NULL, NULL) == VX_OK)
            vx_svo_scene_free(&s);
    }
    vx_gltf_mesh_free(&m);
    return 0;
}
