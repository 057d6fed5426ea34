/* render/spirv_opt_none.c - render/spirv_opt.h in builds without SPIRV-Tools: no specialisation on the host
 * (pipelines are made from the modules as built, with their constants given to the driver). */
#include "render/spirv_opt.h"

bool vx__spirv_can_specialise(void) { return false; }

vx_result vx__spirv_specialise(const uint32_t* code, size_t words, const uint32_t* ids, const uint32_t* values,
                               uint32_t count, uint32_t** out, size_t* out_words, vx_error* err) {
    (void)code, (void)words, (void)ids, (void)values, (void)count, (void)out, (void)out_words;
    return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "this build has no SPIR-V specialiser (SPIRV-Tools)");
}
