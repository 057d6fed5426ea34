/* tools/vox2svo/demo.h - the built-in demo scene. */
#ifndef VX_TOOL_DEMO_H
#define VX_TOOL_DEMO_H
#include "formats/vox.h"
/* Fills out with the demo scene (freed with vx_vox_scene_free). */
vx_result vx_demo_scene(const vx_allocator* a, vx_vox_scene* out);
/* The demo scene animated over `frames` frames (frame_instances; < 2: the
 * still scene): the tower moves, four trees turn. */
vx_result vx_demo_animation(const vx_allocator* a, uint32_t frames, vx_vox_scene* out);
#endif
