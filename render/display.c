/* render/display.c - the pass pipeline's image to display bytes on the GPU (see display.h). */
#include "render/display.h"

#include <string.h>

#include "render/gpu.h"
#include "display.comp.h"

struct vx_display {
    vx_gpu* g;
    VkDescriptorPool pool;
    VkDescriptorSet set;
    VkDescriptorSetLayout set_layout; /* the layout `set` was allocated with */
    vx__buffer overlay;                /* host-visible: the CPU draws into it */
    uint32_t ow, oh;
    vx__buffer out;                    /* the display bytes */
    vx__buffer dummy;                  /* bound as the overlay when there is none */
};

typedef struct push_block {
    uint32_t n, bgra, overlay, row;
} push_block;

vx_result vx_display_create(vx_gpu* g, vx_display** out, vx_error* err) {
    if (!g || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    vx_display* d = vx_calloc(&g->alloc, 1, sizeof *d);
    if (!d) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    d->g = g;
    VkDescriptorPoolSize size = {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 3};
    VkDescriptorPoolCreateInfo pci = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO,
                                      .flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT,
                                      .maxSets = 1,
                                      .poolSizeCount = 1,
                                      .pPoolSizes = &size};
    VkResult vr = vkCreateDescriptorPool(g->device, &pci, NULL, &d->pool);
    vx_result r = vr != VK_SUCCESS ? vx__vk_fail(err, vr, "vkCreateDescriptorPool") : VX_OK;
    if (!r) r = vx__buffer_create(g, 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, "display dummy", &d->dummy, err);
    if (r) {
        vx_display_destroy(d);
        return r;
    }
    *out = d;
    return VX_OK;
}

void vx_display_destroy(vx_display* d) {
    if (!d) return;
    vx_gpu* g = d->g;
    vkDeviceWaitIdle(g->device);
    if (d->pool) vkDestroyDescriptorPool(g->device, d->pool, NULL);
    vx__buffer_destroy(g, &d->overlay);
    vx__buffer_destroy(g, &d->out);
    vx__buffer_destroy(g, &d->dummy);
    vx_allocator a = g->alloc;
    vx_free(&a, d);
}

uint8_t* vx_display_overlay(vx_display* d, uint32_t w, uint32_t h, vx_error* err) {
    if (!d || !w || !h) {
        vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "no display or an empty frame");
        return NULL;
    }
    VkDeviceSize bytes = (VkDeviceSize)w * h * 4;
    if (d->overlay.size < bytes) {
        vkDeviceWaitIdle(d->g->device); /* a frame may still read the old one */
        vx__buffer_destroy(d->g, &d->overlay);
        if (vx__buffer_create(d->g, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true, "display overlay", &d->overlay, err))
            return NULL;
        if (!d->overlay.map) {
            vx_fail(err, VX_ERR_GPU, VX_NO_OFFSET, "the overlay buffer is not host visible");
            vx__buffer_destroy(d->g, &d->overlay);
            return NULL;
        }
    }
    d->ow = w, d->oh = h;
    memset(d->overlay.map, 0, (size_t)bytes);
    return d->overlay.map;
}

vx_result vx_display_record(vx_display* d, void* cmd_handle, const vx_display_desc* desc, uint64_t* out_buffer,
                            vx_error* err) {
    if (!d || !cmd_handle || !desc || !desc->fr)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    vx_gpu* g = d->g;
    VkCommandBuffer cmd = (VkCommandBuffer)cmd_handle;
    uint32_t fw = 0, fh = 0;
    vx__buffer* src = vx__frame_renderer_image(desc->fr, &fw, &fh);
    if (!src) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "the frame renderer has rendered no frame");
    if (fw != desc->width || fh != desc->height)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "display of %ux%u, the last frame is %ux%u", desc->width,
                       desc->height, fw, fh);
    if (desc->overlay && (d->ow != fw || d->oh != fh))
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "the overlay is %ux%u, the frame %ux%u", d->ow, d->oh, fw, fh);
    uint64_t n = (uint64_t)fw * fh;
    vx_result r = VX_OK;
    if (d->out.size < n * 4) {
        vkDeviceWaitIdle(g->device);
        vx__buffer_destroy(g, &d->out);
        r = vx__buffer_create(g, n * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT, false,
                              "display bytes", &d->out, err);
        if (r) return r;
    }
    vx_gpu_compute_pipeline_desc pd = {.spirv = vx__display_spv_arr, .spirv_size = sizeof vx__display_spv_arr,
                                       .push_constant_size = sizeof(push_block), .binding_count = 3,
                                       .label = "display"};
    for (int i = 0; i < 3; i++) pd.bindings[i] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    vx__pipeline* p;
    if ((r = vx__pipeline_get(g, 0xD15B1A70u, &pd, &p, err))) return r;
    /* the set follows the pipeline's layout (a cached pipeline may have been made again) */
    if (!d->set || d->set_layout != p->dsl) {
        if (d->set) vkFreeDescriptorSets(g->device, d->pool, 1, &d->set), d->set = VK_NULL_HANDLE;
        VkDescriptorSetAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO,
                                          .descriptorPool = d->pool,
                                          .descriptorSetCount = 1,
                                          .pSetLayouts = &p->dsl};
        VX__VK(vkAllocateDescriptorSets(g->device, &ai, &d->set), "vkAllocateDescriptorSets");
        d->set_layout = p->dsl;
    }
    const vx__buffer* ov = desc->overlay ? &d->overlay : &d->dummy;
    VkDescriptorBufferInfo bi[3] = {{src->buf, 0, n * 16}, {ov->buf, 0, desc->overlay ? n * 4 : VK_WHOLE_SIZE},
                                    {d->out.buf, 0, n * 4}};
    VkWriteDescriptorSet w[3];
    for (int i = 0; i < 3; i++)
        w[i] = (VkWriteDescriptorSet){.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
                                      .dstSet = d->set,
                                      .dstBinding = (uint32_t)i,
                                      .descriptorCount = 1,
                                      .descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                                      .pBufferInfo = &bi[i]};
    vkUpdateDescriptorSets(g->device, 3, w, 0, NULL);
    /* the frame's passes ran in earlier submissions on this queue; the overlay was written by the host */
    VkMemoryBarrier mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
                          .srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_HOST_WRITE_BIT,
                          .dstAccessMask = VK_ACCESS_SHADER_READ_BIT};
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_HOST_BIT,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 1, &mb, 0, NULL, 0, NULL);
    uint64_t groups = (n + 255) / 256;
    uint32_t row = groups < 65535 ? (uint32_t)groups : 65535u;
    push_block pc = {.n = (uint32_t)n, .bgra = desc->bgra, .overlay = desc->overlay, .row = row};
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p->pipe);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p->layout, 0, 1, &d->set, 0, NULL);
    vkCmdPushConstants(cmd, p->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof pc, &pc);
    vkCmdDispatch(cmd, row, (uint32_t)((groups + row - 1) / row), 1);
    VkMemoryBarrier tb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
                          .srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT,
                          .dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT};
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &tb, 0, NULL, 0,
                         NULL);
    *out_buffer = (uint64_t)(uintptr_t)d->out.buf;
    return VX_OK;
}

vx_result vx_display_run(vx_display* d, const vx_display_desc* desc, uint8_t* bytes, double* seconds, vx_error* err) {
    if (!d || !desc) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    vx_gpu* g = d->g;
    double t0 = vx_time_now();
    uint64_t buf;
    vx_result r = vx__cmd_begin(g, err);
    if (!r) r = vx_display_record(d, g->cmd, desc, &buf, err);
    if (r) {
        vkEndCommandBuffer(g->cmd);
        return r;
    }
    if ((r = vx__cmd_submit_wait(g, err))) return r;
    if (seconds) *seconds = vx_time_now() - t0;
    if (bytes) r = vx__buffer_download(g, &d->out, bytes, (VkDeviceSize)desc->width * desc->height * 4, err);
    return r;
}
