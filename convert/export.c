/* convert/export.c - the exports a build lacks (convert/export.h): without
 * tinygltf there is no .glb writer, without OpenVDB no .vdb writer; the
 * functions stay, so that programs link against every build, and say why
 * they cannot write. */
#include "convert/export.h"

#ifndef VX_HAVE_GLB
const char* vx_conv_glb_light_approx(const vx_light* l) {
    (void)l;
    return NULL;
}

vx_result vx_conv_svo_to_glb_file(const vx_conv_export_desc* desc, const vx_svo_scene* s, const char* path,
                                  vx_conv_glb_stats* stats, vx_error* err) {
    (void)desc, (void)s, (void)stats;
    return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET,
                   "%s: this voxkit was built without tinygltf (libtinygltf-dev): no .glb export", path ? path : "");
}
#endif

#ifndef VX_HAVE_VDB
vx_result vx_conv_svo_to_vdb_file(const vx_conv_export_desc* desc, const vx_svo_scene* s, const char* path,
                                  vx_conv_vdb_stats* stats, vx_error* err) {
    (void)desc, (void)s, (void)stats;
    return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET,
                   "%s: this voxkit was built without OpenVDB (libopenvdb-dev): no .vdb export", path ? path : "");
}
#endif
