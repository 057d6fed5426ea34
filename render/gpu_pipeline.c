/* render/gpu_pipeline.c - compute pipelines described by structs, created
 * once per (shader, specialisation) key and cached in the vx_gpu. The SPIR-V
 * is compiled at build time by glslangValidator and embedded here. */
#include <stdint.h>
#include <string.h>

#include "render/render_internal.h"

#include "trace.comp.h"
#include "dense.comp.h"
#include "trace_precise.comp.h"

const uint32_t* vx__spirv_trace(size_t* bytes) {
    *bytes = sizeof vx__trace_spv_arr;
    return vx__trace_spv_arr;
}
const uint32_t* vx__spirv_trace_precise(size_t* bytes) {
    *bytes = sizeof vx__trace_precise_spv_arr;
    return vx__trace_precise_spv_arr;
}
const uint32_t* vx__spirv_dense(size_t* bytes) {
    *bytes = sizeof vx__dense_spv_arr;
    return vx__dense_spv_arr;
}

#ifndef NDEBUG
/* Debug-only checks of a pipeline desc (programmer errors, not input). */
static vx_result validate_desc(const vx_gpu_compute_pipeline_desc* d, vx_error* err) {
    if (!d->spirv || d->spirv_size < 20 || d->spirv_size % 4)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "pipeline '%s': bad SPIR-V size %zu", d->label,
                       d->spirv_size);
    if (d->spirv[0] != 0x07230203u)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "pipeline '%s': not SPIR-V (magic %08x)", d->label,
                       d->spirv[0]);
    if (d->binding_count > VX_GPU_MAX_BINDINGS || d->spec_count > 8)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "pipeline '%s': too many bindings or constants",
                       d->label);
    return VX_OK;
}
#endif

static vx_result create_pipeline(vx_gpu* g, const vx_gpu_compute_pipeline_desc* d, vx__pipeline* p, vx_error* err) {
    VkDescriptorSetLayoutBinding b[VX_GPU_MAX_BINDINGS];
    for (uint32_t i = 0; i < d->binding_count; i++)
        b[i] = (VkDescriptorSetLayoutBinding){.binding = i,
                                              .descriptorType = d->bindings[i],
                                              .descriptorCount = 1,
                                              .stageFlags = VK_SHADER_STAGE_COMPUTE_BIT};
    VkDescriptorSetLayoutCreateInfo dl = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO,
                                          .bindingCount = d->binding_count,
                                          .pBindings = b};
    VX__VK(vkCreateDescriptorSetLayout(g->device, &dl, NULL, &p->dsl), "vkCreateDescriptorSetLayout");
    VkPushConstantRange pc = {.stageFlags = VK_SHADER_STAGE_COMPUTE_BIT, .size = d->push_constant_size};
    VkPipelineLayoutCreateInfo pl = {.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO,
                                     .setLayoutCount = 1,
                                     .pSetLayouts = &p->dsl,
                                     .pushConstantRangeCount = d->push_constant_size ? 1u : 0u,
                                     .pPushConstantRanges = &pc};
    VX__VK(vkCreatePipelineLayout(g->device, &pl, NULL, &p->layout), "vkCreatePipelineLayout");
    VkShaderModuleCreateInfo sm = {.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO,
                                   .codeSize = d->spirv_size,
                                   .pCode = d->spirv};
    VkShaderModule mod;
    VX__VK(vkCreateShaderModule(g->device, &sm, NULL, &mod), "vkCreateShaderModule");
    VkSpecializationMapEntry me[8];
    for (uint32_t i = 0; i < d->spec_count; i++)
        me[i] = (VkSpecializationMapEntry){.constantID = i, .offset = 4 * i, .size = 4};
    VkSpecializationInfo si = {.mapEntryCount = d->spec_count,
                               .pMapEntries = me,
                               .dataSize = 4u * d->spec_count,
                               .pData = d->spec};
    VkComputePipelineCreateInfo ci = {.sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO,
                                      .stage = {.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
                                                .stage = VK_SHADER_STAGE_COMPUTE_BIT,
                                                .module = mod,
                                                .pName = d->entry ? d->entry : "main",
                                                .pSpecializationInfo = d->spec_count ? &si : NULL},
                                      .layout = p->layout};
    VkResult r = vkCreateComputePipelines(g->device, VK_NULL_HANDLE, 1, &ci, NULL, &p->pipe);
    vkDestroyShaderModule(g->device, mod, NULL);
    if (r != VK_SUCCESS) return vx__vk_fail(err, r, "vkCreateComputePipelines");
    vx__gpu_name(g, VK_OBJECT_TYPE_PIPELINE, (uint64_t)p->pipe, d->label);
    return VX_OK;
}

static void destroy_pipeline(vx_gpu* g, vx__pipeline* p) {
    if (p->pipe) vkDestroyPipeline(g->device, p->pipe, NULL);
    if (p->layout) vkDestroyPipelineLayout(g->device, p->layout, NULL);
    if (p->dsl) vkDestroyDescriptorSetLayout(g->device, p->dsl, NULL);
    memset(p, 0, sizeof *p);
}

vx_result vx__pipeline_get(vx_gpu* g, uint64_t key, const vx_gpu_compute_pipeline_desc* d, vx__pipeline** out,
                           vx_error* err) {
    for (uint32_t i = 0; i < g->pipeline_count; i++)
        if (g->pipelines[i].key == key) {
            *out = &g->pipelines[i];
            return VX_OK;
        }
#ifndef NDEBUG
    vx_result vr = validate_desc(d, err);
    if (vr) return vr;
#endif
    if (g->pipeline_count == VX_GPU_MAX_PIPELINES) {
        /* evict the oldest; the device is idle between frames */
        destroy_pipeline(g, &g->pipelines[0]);
        memmove(&g->pipelines[0], &g->pipelines[1], sizeof g->pipelines[0] * (VX_GPU_MAX_PIPELINES - 1));
        g->pipeline_count--;
    }
    vx__pipeline* p = &g->pipelines[g->pipeline_count];
    memset(p, 0, sizeof *p);
    vx_result r = create_pipeline(g, d, p, err);
    if (r) {
        destroy_pipeline(g, p);
        return r;
    }
    p->key = key;
    g->pipeline_count++;
    *out = p;
    return VX_OK;
}

void vx__pipelines_destroy(vx_gpu* g) {
    for (uint32_t i = g->pipeline_count; i-- > 0;) destroy_pipeline(g, &g->pipelines[i]);
    g->pipeline_count = 0;
}
