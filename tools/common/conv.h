/* tools/common/conv.h - the converter options every tool that reads scenes
 * accepts (vox2svo, svo_view), and loading any supported input into an svo
 * scene by its extension. */
#ifndef VX_TOOL_CONV_H
#define VX_TOOL_CONV_H

#include <stdbool.h>
#include <stdint.h>

#include "convert/convert.h"
#include "convert/file.h"

typedef struct vx_tool_conv {
    /* .vox */
    bool frame_set; /* --frame: that one frame; default: every frame of an animation */
    uint32_t frame;
    bool keep_hidden;
    bool keep_unused; /* also store models no instance places */
    /* octree builder */
    bool no_collapse, no_dag;
    /* .gltf / .glb */
    uint32_t res; /* 256 by default (vx_tool_conv_defaults) */
    uint32_t region; /* cells per side of one model; 0: the converter's choice */
    bool scene_set;
    uint32_t scene;
    bool solid, normals; /* solid: level sets too */
    bool y_up;           /* keep glTF's +Y up axis */
    /* .vdb */
    const char* grid;
    bool threshold_set;
    double threshold;
    bool density;
    const char* color;
    /* memory: --max-memory (0: no limit); the tool makes the budget and sets
     * alloc to it before vx_tool_conv_load (NULL: malloc) */
    uint64_t max_memory;
    const vx_allocator* alloc;
    /* meshes: another voxelizer (vox2svo --gpu sets the GPU's; NULL: the CPU's) */
    const struct vx_conv_mesh_backend* mesh_backend;
} vx_tool_conv;

vx_tool_conv vx_tool_conv_defaults(void);

/* If argv[*i] is a converter option, takes it (and its value, advancing *i)
 * and returns true; a missing or malformed value is a usage error:
 * vx_tool_usage_error(usage, ...). */
bool vx_tool_conv_option(int argc, char** argv, int* i, vx_tool_conv* c, void (*usage)(int status));

/* Whether IN names a frame sequence: a .vdb name with a run of # or a
 * printf number (smoke_####.vdb, smoke_%04d.vdb), or a list file (.txt, one
 * .vdb path per line); vx_tool_conv_load converts it into one animation. */
bool vx_tool_conv_is_sequence(const char* path);

/* What vx_tool_conv_load read. */
typedef struct vx_tool_loaded {
    const char* kind;      /* ".vox", ".glb", ".gltf", ".vdb", ".svo" */
    uint64_t in_bytes;     /* size of the input file */
    double seconds_read;   /* reading and parsing the input */
    double seconds_total;  /* the whole load */
    vx_conv_stats stats;   /* converters only */
} vx_tool_loaded;

/* The library's options for c (what vx_tool_conv_load passes to vx_conv_file). */
vx_conv_file_desc vx_tool_conv_file_desc(const vx_tool_conv* c, bool allow_svo, const vx_logger* log,
                                         vx_progress progress);

/* Reads path by its extension: .vox, .gltf/.glb, .vdb (converted with c),
 * and .svo when allow_svo. info may be NULL. */
vx_result vx_tool_conv_load(const char* path, const vx_tool_conv* c, bool allow_svo, const vx_logger* log,
                            vx_progress progress, vx_svo_scene* out, vx_tool_loaded* info, vx_error* err);

#endif
