/* tests/fuzz/gltf_fuzz.c - glTF reader (tinygltf shim) then a tiny
 * voxelization of whatever loaded: read -> voxelize -> free. External files
 * are refused so a mutated URI cannot reach the file system. */
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
    vx_gltf_mesh_free(&m);
    return 0;
}
