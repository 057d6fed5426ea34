/* tools/vox2svo/demo.h - the built-in demo scene. */
#ifndef VX_TOOL_DEMO_H
#define VX_TOOL_DEMO_H
#include "formats/vox.h"
/* Fills out with the demo scene (freed with vx_vox_scene_free). */
vx_result vx_demo_scene(const vx_allocator* a, vx_vox_scene* out);
#endif
