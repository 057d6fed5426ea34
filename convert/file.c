/* convert/file.c - input files to svo scenes by extension (convert/file.h). */
#include "convert/file.h"

#include <ctype.h>
#include <string.h>

#ifdef VX_HAVE_MESH
#include "convert/mesh.h"
#endif
#ifdef VX_HAVE_VDB
#include "convert/volume.h"
#endif

vx_conv_file_desc vx_conv_file_defaults(void) {
    vx_conv_file_desc d = {0};
    d.res = 256;
    return d;
}

const char* vx_conv_file_kind(const char* path) {
    static const char* const kinds[] = {".vox", ".gltf", ".glb", ".vdb", ".svo"};
    if (!path) return NULL;
    const char* slash = strrchr(path, '/');
    const char* dot = strrchr(path, '.');
    if (!dot || (slash && dot < slash)) return NULL;
    for (size_t k = 0; k < sizeof kinds / sizeof kinds[0]; k++) {
        size_t i = 0;
        while (kinds[k][i] && tolower((unsigned char)dot[i]) == kinds[k][i]) i++;
        if (!kinds[k][i] && !dot[i]) return kinds[k];
    }
    return NULL;
}

vx_result vx_conv_file(const vx_conv_file_desc* desc, const char* path, vx_svo_scene* out, vx_conv_stats* stats,
                       vx_error* err) {
    vx_conv_file_desc d = desc ? *desc : vx_conv_file_defaults();
    if (!d.res) d.res = 256;
    const vx_allocator* A = d.alloc;
    if (!path || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "no path or no output scene");
    const char* kind = vx_conv_file_kind(path);
    vx_conv_stats st = {0};
    double t0 = vx_time_now();
    vx_result r;
    if (!kind || (!strcmp(kind, ".svo") && !d.allow_svo)) {
        const char* dot = strrchr(path, '.');
        return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET,
                       "unknown input type '%s' (expected %s.vox, .gltf, .glb or .vdb)", dot ? dot : "",
                       d.allow_svo ? ".svo, " : "");
    }
    if (!strcmp(kind, ".svo")) {
        r = vx_svo_read_file(&(vx_svo_read_desc){.alloc = A}, path, out, err);
        st.seconds_read = vx_time_now() - t0;
        st.peak_bytes = vx_peak_rss();
    } else if (!strcmp(kind, ".vox")) {
        vx_vox_scene vs;
        vx_vox_read_desc rd = {.alloc = A, .logger = d.logger, .frame = d.frame, .keep_hidden = d.keep_hidden,
                               .all_frames = !d.one_frame};
        r = vx_vox_read_file(&rd, path, &vs, err);
        double tread = vx_time_now() - t0;
        if (r == VX_OK) {
            r = vx_conv_vox(&(vx_conv_vox_desc){.build = d.build, .alloc = A, .keep_unused = d.keep_unused}, &vs, out,
                            &st, err);
            vx_vox_scene_free(&vs);
        }
        st.seconds_read = tread;
    } else if (!strcmp(kind, ".vdb")) {
#ifdef VX_HAVE_VDB
        vx_conv_vdb_desc vd = {.build = d.build, .alloc = A, .logger = d.logger, .grid = d.grid, .solid = d.solid,
                               .threshold_set = d.threshold_set, .threshold = d.threshold, .density = d.density,
                               .color_grid = d.color_grid};
        r = vx_conv_vdb_file(&vd, path, out, &st, err);
#else
        r = vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "this build has no OpenVDB support");
#endif
    } else { /* .gltf, .glb */
#ifdef VX_HAVE_MESH
        vx_conv_mesh_desc md = vx_conv_mesh_desc_from_file(&d);
        r = vx_conv_mesh_file(&md, path, out, &st, err);
#else
        r = vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "this build has no glTF support");
#endif
    }
    if (r == VX_OK && stats) *stats = st;
    return r;
}
