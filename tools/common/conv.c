/* tools/common/conv.c */
#include "tools/common/conv.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "convert/file.h"
#include "tools/common/tool.h"

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
        c->frame_set = true;
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
    else if (!strcmp(a, "--y-up")) c->y_up = true;
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
    vx_conv_file_desc d = {
        .build = {.no_collapse = c->no_collapse, .no_dag = c->no_dag, .progress = progress},
        .alloc = c->alloc,
        .logger = log,
        .allow_svo = allow_svo,
        .frame = c->frame,
        .one_frame = c->frame_set,
        .keep_hidden = c->keep_hidden,
        .keep_unused = c->keep_unused,
        .res = c->res,
        .scene_set = c->scene_set,
        .scene = c->scene,
        .normals = c->normals,
        .y_up = c->y_up,
        .solid = c->solid,
        .grid = c->grid,
        .threshold_set = c->threshold_set,
        .threshold = c->threshold,
        .density = c->density,
        .color_grid = c->color,
    };
    double t0 = vx_time_now();
    li.in_bytes = file_size(path);
    li.kind = vx_conv_file_kind(path);
    vx_result r = vx_conv_file(&d, path, out, &li.stats, err);
    li.seconds_read = li.stats.seconds_read;
    li.seconds_total = vx_time_now() - t0;
    if (r == VX_OK && info) *info = li;
    return r;
}
