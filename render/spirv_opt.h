/* render/spirv_opt.h - a compute module specialised on the host: its
 * specialisation constants set to a pipeline's values and frozen, and the code
 * they switch off removed (SPIRV-Tools' optimizer; render/spirv_opt.cpp is the
 * C++ shim). Internal to vx_render (render/gpu_pipeline.c).
 *
 * Why: Mesa 22.3's lavapipe translates the whole module to NIR and inlines every
 * function before it folds the constants, so a kernel's start-up grows with all
 * the features the module can do, not with the ones a pipeline uses. The merged
 * frame kernel took 2.5 s to make on this machine's lavapipe, the same kernel
 * specialised on the host 0.05 s, with the same pixels (docs/PERFORMANCE.md
 * section 13). Only passes that keep the module's meaning run (constants,
 * dead branches, dead code, dead functions): no inlining, no arithmetic
 * rewritten (NoContraction decorations stay with the instructions they mark). */
#ifndef VX_RENDER_SPIRV_OPT_H
#define VX_RENDER_SPIRV_OPT_H

#include <stddef.h>
#include <stdint.h>

#include "svo/core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* True when this build has the specialiser (SPIRV-Tools found at configure time). */
bool vx__spirv_can_specialise(void);

/* Sets the constants ids[i] to values[i] (their 32-bit patterns; a bool is
 * true when nonzero), freezes every other constant at its default (as a
 * pipeline without that entry would see it) and removes the code they switch
 * off. *out (malloc'ed, the caller frees) holds *out_words words. Fails with
 * VX_ERR_UNSUPPORTED in builds without the specialiser, VX_ERR_BAD_FORMAT when
 * the optimizer rejects the module (err names its message). */
vx_result vx__spirv_specialise(const uint32_t* code, size_t words, const uint32_t* ids, const uint32_t* values,
                               uint32_t count, uint32_t** out, size_t* out_words, vx_error* err);

#ifdef __cplusplus
}
#endif
#endif
