/* tools/common/conv.c */
#include "tools/common/conv.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tools/common/tool.h"
#ifdef VX_HAVE_MESH
#include "convert/mesh.h"
#endif
#ifdef VX_HAVE_VDB
#include "convert/volume.h"
#endif

vx_tool_conv vx_tool_conv_defaults(void) {
    vx_tool_conv c = {0};
    c.res = 256;
    return c;
}

static const char* value(int argc, char** argv, int* i, void (*usage)(int)) {
    if (*i + 1 >= argc) vx_tool_usage_error(usage, "option %s needs an argument", argv[*i]);
    return argv[++*i];
}

bool vx_tool_conv_option(int argc, char** argv, int* i, vx_tool_conv* c, void (*usage)(int)) {
    const char* a = argv[*i];
    if (!strcmp(a, "--frame")) {
        if (!vx_tool_parse_u32(value(argc, argv, i, usage), &c->frame))
            vx_tool_usage_error(usage, "bad --frame value '%s'", argv[*i]);
    } else if (!strcmp(a, "--keep-hidden")) c->keep_hidden = true;
    else if (!strcmp(a, "--keep-unused")) c->keep_unused = true;
    else if (!strcmp(a, "--no-collapse")) c->no_collapse = true;
    else if (!strcmp(a, "--no-dag")) c->no_dag = true;
    else if (!strcmp(a, "--res")) {
        if (!vx_tool_parse_u32(value(argc, argv, i, usage), &c->res) || c->res < 1 || c->res > 65536)
            vx_tool_usage_error(usage, "bad --res value '%s' (1 to 65536)", argv[*i]);
    } else if (!strcmp(a, "--scene")) {
        if (!vx_tool_parse_u32(value(argc, argv, i, usage), &c->scene))
            vx_tool_usage_error(usage, "bad --scene value '%s'", argv[*i]);
        c->scene_set = true;
    } else if (!strcmp(a, "--solid")) c->solid = true;
    else if (!strcmp(a, "--normals")) c->normals = true;
    else if (!strcmp(a, "--grid")) c->grid = value(argc, argv, i, usage);
    else if (!strcmp(a, "--threshold")) {
        if (!vx_tool_parse_double(value(argc, argv, i, usage), &c->threshold))
            vx_tool_usage_error(usage, "bad --threshold value '%s'", argv[*i]);
        c->threshold_set = true;
    } else if (!strcmp(a, "--density")) c->density = true;
    else if (!strcmp(a, "--color")) c->color = value(argc, argv, i, usage);
    else if (!strcmp(a, "--max-memory")) {
        if (!vx_tool_parse_bytes(value(argc, argv, i, usage), &c->max_memory) || !c->max_memory)
            vx_tool_usage_error(usage, "bad --max-memory value '%s' (bytes, e.g. 512M or 4G)", argv[*i]);
    }
    else return false;
    return true;
}

static uint64_t file_size(const char* path) {
    FILE* f = fopen(path, "rb");
    if (!f) return 0;
    long n = fseek(f, 0, SEEK_END) == 0 ? ftell(f) : -1;
    fclose(f);
    return n > 0 ? (uint64_t)n : 0;
}

vx_result vx_tool_conv_load(const char* path, const vx_tool_conv* c, bool allow_svo, const vx_logger* log,
                            vx_progress progress, vx_svo_scene* out, vx_tool_loaded* info, vx_error* err) {
    vx_tool_loaded li = {0};
    const char* ext = vx_tool_ext(path);
    vx_svo_build_desc build = {.no_collapse = c->no_collapse, .no_dag = c->no_dag, .progress = progress};
    const vx_allocator* A = c->alloc;
    double t0 = vx_time_now();
    vx_result r;
    li.in_bytes = file_size(path);
    if (allow_svo && !strcmp(ext, "svo")) {
        li.kind = ".svo";
        r = vx_svo_read_file(&(vx_svo_read_desc){.alloc = A}, path, out, err);
        li.seconds_read = vx_time_now() - t0;
    } else if (!strcmp(ext, "vox")) {
        li.kind = ".vox";
        vx_vox_scene vs;
        vx_vox_read_desc rd = {.alloc = A, .logger = log, .frame = c->frame, .keep_hidden = c->keep_hidden};
        r = vx_vox_read_file(&rd, path, &vs, err);
        li.seconds_read = vx_time_now() - t0;
        if (r == VX_OK) {
            vx_conv_vox_desc cd = {.build = build, .alloc = A, .keep_unused = c->keep_unused};
            r = vx_conv_vox(&cd, &vs, out, &li.stats, err);
            vx_vox_scene_free(&vs);
        }
    } else if (!strcmp(ext, "gltf") || !strcmp(ext, "glb")) {
        li.kind = !strcmp(ext, "glb") ? ".glb" : ".gltf";
#ifdef VX_HAVE_MESH
        vx_conv_mesh_desc md = {.build = build, .alloc = A, .logger = log, .res = c->res, .scene_set = c->scene_set,
                                .scene = c->scene, .solid = c->solid, .normals = c->normals};
        r = vx_conv_mesh_file(&md, path, out, &li.stats, err);
        li.seconds_read = li.stats.seconds_read;
#else
        r = vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "this build has no glTF support");
#endif
    } else if (!strcmp(ext, "vdb")) {
        li.kind = ".vdb";
#ifdef VX_HAVE_VDB
        vx_conv_vdb_desc vd = {.build = build, .alloc = A, .logger = log, .grid = c->grid, .solid = c->solid,
                               .threshold_set = c->threshold_set, .threshold = c->threshold, .density = c->density,
                               .color_grid = c->color};
        r = vx_conv_vdb_file(&vd, path, out, &li.stats, err);
        li.seconds_read = li.stats.seconds_read;
#else
        r = vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "this build has no OpenVDB support");
#endif
    } else {
        r = vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "unknown input type '.%s' (expected %s.vox, .gltf, .glb or .vdb)",
                    ext, allow_svo ? ".svo, " : "");
    }
    li.seconds_total = vx_time_now() - t0;
    if (r == VX_OK && info) *info = li;
    return r;
}
