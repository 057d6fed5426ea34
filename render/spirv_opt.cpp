// render/spirv_opt.cpp - the SPIRV-Tools shim behind render/spirv_opt.h.
// Exceptions never cross into C: the call is wrapped.
#include <spirv-tools/optimizer.hpp>

#include <cstdlib>
#include <cstring>
#include <string>
#include <unordered_map>
#include <vector>

extern "C" {
#include "render/spirv_opt.h"
}

extern "C" bool vx__spirv_can_specialise(void) { return true; }

extern "C" vx_result vx__spirv_specialise(const uint32_t* code, size_t words, const uint32_t* ids,
                                          const uint32_t* values, uint32_t count, uint32_t** out,
                                          size_t* out_words, vx_error* err) {
    try {
        std::unordered_map<uint32_t, std::vector<uint32_t>> set;
        for (uint32_t i = 0; i < count; i++) set[ids[i]] = {values[i]};
        std::string msg;
        spvtools::Optimizer opt(SPV_ENV_VULKAN_1_2);
        opt.SetMessageConsumer([&msg](spv_message_level_t level, const char*, const spv_position_t&, const char* m) {
            if (level <= SPV_MSG_ERROR && msg.empty()) msg = m ? m : "?";
        });
        // the values, then every constant frozen (ops on constants folded); then what they switch off, twice:
        // a branch removed can leave a function without callers, whose removal leaves more dead code
        opt.RegisterPass(spvtools::CreateSetSpecConstantDefaultValuePass(set))
            .RegisterPass(spvtools::CreateFreezeSpecConstantValuePass())
            .RegisterPass(spvtools::CreateFoldSpecConstantOpAndCompositePass());
        for (int pass = 0; pass < 2; pass++)
            opt.RegisterPass(spvtools::CreateDeadBranchElimPass())
                .RegisterPass(spvtools::CreateAggressiveDCEPass())
                .RegisterPass(spvtools::CreateEliminateDeadFunctionsPass());
        spvtools::OptimizerOptions o;
        o.set_run_validator(false); // our own modules, checked by spirv-val at build time (test_spirv_valid)
        std::vector<uint32_t> result;
        if (!opt.Run(code, words, &result, o))
            return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "SPIR-V specialisation failed: %s", msg.c_str());
        uint32_t* buf = static_cast<uint32_t*>(std::malloc(result.size() * sizeof(uint32_t)));
        if (!buf) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "SPIR-V specialisation: out of memory");
        std::memcpy(buf, result.data(), result.size() * sizeof(uint32_t));
        *out = buf;
        *out_words = result.size();
        return VX_OK;
    } catch (const std::exception& e) {
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "SPIR-V specialisation: %s", e.what());
    } catch (...) {
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "SPIR-V specialisation failed");
    }
}
