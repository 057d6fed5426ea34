/* render/gpu_dispatch.c - command recording, submission and GPU timing. */
#include <stdlib.h>
#include <string.h>

#include "render/render_internal.h"

vx_result vx__cmd_begin(vx_gpu* g, vx_error* err) {
    VX__VK(vkResetCommandBuffer(g->cmd, 0), "vkResetCommandBuffer");
    VkCommandBufferBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
                                   .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};
    VX__VK(vkBeginCommandBuffer(g->cmd, &bi), "vkBeginCommandBuffer");
    return VX_OK;
}

void vx__gpu_submit_held(vx_gpu* g) {
    if (g->held_submit) g->held_submit(g->held_user);
}

vx_result vx__cmd_submit_wait(vx_gpu* g, vx_error* err) {
    VX__VK(vkEndCommandBuffer(g->cmd), "vkEndCommandBuffer");
    vx__gpu_submit_held(g); /* frames recorded before this work run before it */
    VkSubmitInfo si = {.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO, .commandBufferCount = 1, .pCommandBuffers = &g->cmd};
    VX__VK(vkResetFences(g->device, 1, &g->fence), "vkResetFences");
    VX__VK(vkQueueSubmit(g->queue, 1, &si, g->fence), "vkQueueSubmit");
    /* generous: a software device may take a long time for a large frame */
    VX__VK(vkWaitForFences(g->device, 1, &g->fence, VK_TRUE, UINT64_C(600) * 1000000000u), "vkWaitForFences");
    return VX_OK;
}

static int cmp_double(const void* a, const void* b) {
    double x = *(const double*)a, y = *(const double*)b;
    return (x > y) - (x < y);
}

/* The timestamp pool (gpu_device.c) holds 64 queries, two per run: runs go
 * in submissions of at most VX__RUNS_PER_SUBMIT, so any repeat count is timed;
 * *seconds is the median run (wall time per run without timestamps). */
#define VX__RUNS_PER_SUBMIT 32u

/* Points set's bindings at d's buffers, each binding with the descriptor type
 * pipeline p declared it with (the trace shaders: binding 0 the uniform frame
 * block; images where p has a sampler or storage image). */
static void write_set(vx_gpu* g, VkDescriptorSet set, const vx__pipeline* p, const vx__dispatch_desc* d) {
    VkDescriptorBufferInfo infos[VX_GPU_MAX_BINDINGS];
    VkDescriptorImageInfo images[VX_GPU_MAX_BINDINGS];
    VkWriteDescriptorSet w[VX_GPU_MAX_BINDINGS];
    for (uint32_t i = 0; i < d->buffer_count; i++) {
        VkDescriptorType t = p->bindings[i];
        bool image = t == VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER || t == VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
        infos[i] = (VkDescriptorBufferInfo){.buffer = d->buffers[i]->buf, .offset = 0, .range = VK_WHOLE_SIZE};
        images[i] = (VkDescriptorImageInfo){.sampler = d->buffers[i]->sampler, .imageView = d->buffers[i]->view,
                                            .imageLayout = VK_IMAGE_LAYOUT_GENERAL};
        w[i] = (VkWriteDescriptorSet){.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
                                      .dstSet = set,
                                      .dstBinding = i,
                                      .descriptorCount = 1,
                                      .descriptorType = t,
                                      .pBufferInfo = image ? NULL : &infos[i],
                                      .pImageInfo = image ? &images[i] : NULL};
    }
    vkUpdateDescriptorSets(g->device, d->buffer_count, w, 0, NULL);
}

vx_result vx__dispatch(vx_gpu* g, const vx__dispatch_desc* d, double* seconds, vx_error* err) {
    uint32_t repeat = d->repeat ? d->repeat : 1;
    /* one set per stage: the main pipeline's and the optional first stage's */
    uint32_t nsets = d->pre_pipeline ? 2u : 1u;
    VkDescriptorPoolSize sizes[4] = {{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 2 * VX_GPU_MAX_BINDINGS},
                                     {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 2 * VX_GPU_MAX_BINDINGS},
                                     {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 2 * VX_GPU_MAX_BINDINGS},
                                     {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 2 * VX_GPU_MAX_BINDINGS}};
    VkDescriptorPoolCreateInfo pci = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO,
                                      .maxSets = 2,
                                      .poolSizeCount = 4,
                                      .pPoolSizes = sizes};
    bool timed = g->has_timestamps && seconds;
    double* runs = NULL;
    if (timed) {
        runs = vx_alloc(&g->alloc, (size_t)repeat * sizeof *runs);
        if (!runs) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u run times", repeat);
    }
    VkDescriptorPool pool;
    VkResult vr = vkCreateDescriptorPool(g->device, &pci, NULL, &pool);
    if (vr != VK_SUCCESS) {
        vx_free(&g->alloc, runs);
        return vx__vk_fail(err, vr, "vkCreateDescriptorPool");
    }
    vx_result r = VX_OK;
    vx__pipeline* stage[2] = {d->pipeline, d->pre_pipeline};
    VkDescriptorSet sets[2];
    for (uint32_t s = 0; s < nsets; s++) {
        VkDescriptorSetAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO,
                                          .descriptorPool = pool,
                                          .descriptorSetCount = 1,
                                          .pSetLayouts = &stage[s]->dsl};
        vr = vkAllocateDescriptorSets(g->device, &ai, &sets[s]);
        if (vr != VK_SUCCESS) {
            r = vx__vk_fail(err, vr, "vkAllocateDescriptorSets");
            goto done;
        }
        write_set(g, sets[s], stage[s], d);
    }
    VkDescriptorSet set = sets[0];
    double wall = 0;
    for (uint32_t done_runs = 0; done_runs < repeat;) {
        uint32_t n = repeat - done_runs < VX__RUNS_PER_SUBMIT ? repeat - done_runs : VX__RUNS_PER_SUBMIT;
        if ((r = vx__cmd_begin(g, err))) goto done;
        if (g->begin_label && d->label) {
            VkDebugUtilsLabelEXT l = {.sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_LABEL_EXT, .pLabelName = d->label};
            g->begin_label(g->cmd, &l);
        }
        if (g->has_timestamps) vkCmdResetQueryPool(g->cmd, g->timestamps, 0, 2 * n);
        vkCmdBindPipeline(g->cmd, VK_PIPELINE_BIND_POINT_COMPUTE, d->pipeline->pipe);
        vkCmdBindDescriptorSets(g->cmd, VK_PIPELINE_BIND_POINT_COMPUTE, d->pipeline->layout, 0, 1, &set, 0, NULL);
        if (d->push && d->push_size)
            vkCmdPushConstants(g->cmd, d->pipeline->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, d->push_size, d->push);
        for (uint32_t k = 0; k < n; k++) {
            if (g->has_timestamps) vkCmdWriteTimestamp(g->cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, g->timestamps, 2 * k);
            if (d->pre_pipeline) {
                vkCmdBindPipeline(g->cmd, VK_PIPELINE_BIND_POINT_COMPUTE, d->pre_pipeline->pipe);
                vkCmdBindDescriptorSets(g->cmd, VK_PIPELINE_BIND_POINT_COMPUTE, d->pre_pipeline->layout, 0, 1, &sets[1], 0,
                                        NULL);
                vkCmdDispatch(g->cmd, d->pre_groups[0], d->pre_groups[1], d->pre_groups[2]);
                VkMemoryBarrier pb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
                                      .srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT,
                                      .dstAccessMask = VK_ACCESS_SHADER_READ_BIT};
                vkCmdPipelineBarrier(g->cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0,
                                     1, &pb, 0, NULL, 0, NULL);
                vkCmdBindPipeline(g->cmd, VK_PIPELINE_BIND_POINT_COMPUTE, d->pipeline->pipe);
                vkCmdBindDescriptorSets(g->cmd, VK_PIPELINE_BIND_POINT_COMPUTE, d->pipeline->layout, 0, 1, &set, 0, NULL);
            }
            vkCmdDispatch(g->cmd, d->groups[0], d->groups[1], d->groups[2]);
            if (g->has_timestamps)
                vkCmdWriteTimestamp(g->cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, g->timestamps, 2 * k + 1);
            VkMemoryBarrier mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
                                  .srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT,
                                  .dstAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT |
                                                   VK_ACCESS_HOST_READ_BIT};
            vkCmdPipelineBarrier(g->cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                                 VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT |
                                     VK_PIPELINE_STAGE_HOST_BIT,
                                 0, 1, &mb, 0, NULL, 0, NULL);
        }
        if (g->end_label && d->label) g->end_label(g->cmd);
        double t0 = vx_time_now();
        if ((r = vx__cmd_submit_wait(g, err))) goto done;
        wall += vx_time_now() - t0;
        if (timed) {
            uint64_t ts[2 * VX__RUNS_PER_SUBMIT];
            vr = vkGetQueryPoolResults(g->device, g->timestamps, 0, 2 * n, sizeof ts, ts, sizeof ts[0],
                                       VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT);
            if (vr != VK_SUCCESS) {
                r = vx__vk_fail(err, vr, "vkGetQueryPoolResults");
                goto done;
            }
            for (uint32_t k = 0; k < n; k++)
                runs[done_runs + k] = (double)(ts[2 * k + 1] - ts[2 * k]) * g->props.limits.timestampPeriod * 1e-9;
        }
        done_runs += n;
    }
    if (seconds) *seconds = wall / repeat;
    if (timed) {
        qsort(runs, repeat, sizeof runs[0], cmp_double);
        *seconds = runs[repeat / 2];
    }
done:
    vkDestroyDescriptorPool(g->device, pool, NULL);
    vx_free(&g->alloc, runs);
    return r;
}

/* ---- vx__seq: several dispatches, one submission (gpu.h) ---- */

/* After every command of a sequence: its writes before every later read or write (shaders, indirect group
 * counts, copies, the host after the wait). */
static void seq_barrier(vx_gpu* g) {
    VkMemoryBarrier mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
                          .srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                          .dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                                           VK_ACCESS_UNIFORM_READ_BIT | VK_ACCESS_INDIRECT_COMMAND_READ_BIT |
                                           VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT |
                                           VK_ACCESS_HOST_READ_BIT};
    vkCmdPipelineBarrier(g->cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT |
                             VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_HOST_BIT,
                         0, 1, &mb, 0, NULL, 0, NULL);
}

vx_result vx__seq_begin(vx_gpu* g, vx__seq* s, vx_error* err) {
    *s = (vx__seq){0};
    VkDescriptorPoolSize sizes[4] = {{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VX__SEQ_MAX * VX_GPU_MAX_BINDINGS},
                                     {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, VX__SEQ_MAX * VX_GPU_MAX_BINDINGS},
                                     {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VX__SEQ_MAX * VX_GPU_MAX_BINDINGS},
                                     {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VX__SEQ_MAX * VX_GPU_MAX_BINDINGS}};
    VkDescriptorPoolCreateInfo pci = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO,
                                      .maxSets = VX__SEQ_MAX,
                                      .poolSizeCount = 4,
                                      .pPoolSizes = sizes};
    VX__VK(vkCreateDescriptorPool(g->device, &pci, NULL, &s->pool), "vkCreateDescriptorPool");
    vx_result r = vx__cmd_begin(g, err);
    if (r) {
        vkDestroyDescriptorPool(g->device, s->pool, NULL);
        s->pool = VK_NULL_HANDLE;
        return r;
    }
    if (g->has_timestamps) {
        vkCmdResetQueryPool(g->cmd, g->timestamps, 0, VX__SEQ_MAX + 1);
        vkCmdWriteTimestamp(g->cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, g->timestamps, 0);
    }
    return VX_OK;
}

vx_result vx__seq_dispatch(vx_gpu* g, vx__seq* s, const vx__dispatch_desc* d, const vx__buffer* indirect,
                           VkDeviceSize offset, vx_error* err) {
    if (s->count >= VX__SEQ_MAX)
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "more than %d dispatches in one submission", VX__SEQ_MAX);
    VkDescriptorSetAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO,
                                      .descriptorPool = s->pool,
                                      .descriptorSetCount = 1,
                                      .pSetLayouts = &d->pipeline->dsl};
    VkDescriptorSet set;
    VX__VK(vkAllocateDescriptorSets(g->device, &ai, &set), "vkAllocateDescriptorSets");
    write_set(g, set, d->pipeline, d);
    if (g->begin_label && d->label) {
        VkDebugUtilsLabelEXT l = {.sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_LABEL_EXT, .pLabelName = d->label};
        g->begin_label(g->cmd, &l);
    }
    vkCmdBindPipeline(g->cmd, VK_PIPELINE_BIND_POINT_COMPUTE, d->pipeline->pipe);
    vkCmdBindDescriptorSets(g->cmd, VK_PIPELINE_BIND_POINT_COMPUTE, d->pipeline->layout, 0, 1, &set, 0, NULL);
    if (d->push && d->push_size)
        vkCmdPushConstants(g->cmd, d->pipeline->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, d->push_size, d->push);
    if (indirect) vkCmdDispatchIndirect(g->cmd, indirect->buf, offset);
    else vkCmdDispatch(g->cmd, d->groups[0], d->groups[1], d->groups[2]);
    bool beside = s->beside;
    s->beside = false;
    s->query[s->count] = 0;
    if (g->has_timestamps && !beside) {
        s->query[s->count] = ++s->queries;
        vkCmdWriteTimestamp(g->cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, g->timestamps, s->queries);
    }
    if (g->end_label && d->label) g->end_label(g->cmd);
    if (!beside) seq_barrier(g);
    s->count++, s->commands++;
    return VX_OK;
}

void vx__seq_copy(vx_gpu* g, vx__seq* s, const vx__buffer* src, VkDeviceSize src_offset, const vx__buffer* dst,
                  VkDeviceSize dst_offset, VkDeviceSize size) {
    VkBufferCopy c = {.srcOffset = src_offset, .dstOffset = dst_offset, .size = size};
    vkCmdCopyBuffer(g->cmd, src->buf, dst->buf, 1, &c);
    seq_barrier(g);
    s->commands++;
}

void vx__seq_fill(vx_gpu* g, vx__seq* s, const vx__buffer* dst, VkDeviceSize offset, VkDeviceSize size, uint32_t word) {
    vkCmdFillBuffer(g->cmd, dst->buf, offset, size, word);
    seq_barrier(g);
    s->commands++;
}

void vx__seq_abandon(vx_gpu* g, vx__seq* s) {
    if (!s->pool) return;
    vkEndCommandBuffer(g->cmd);
    vkDestroyDescriptorPool(g->device, s->pool, NULL);
    s->pool = VK_NULL_HANDLE;
}

vx_result vx__seq_submit(vx_gpu* g, vx__seq* s, vx_error* err) {
    double t0 = vx_time_now();
    vx_result r = vx__cmd_submit_wait(g, err);
    double wall = vx_time_now() - t0;
    vkDestroyDescriptorPool(g->device, s->pool, NULL);
    s->pool = VK_NULL_HANDLE;
    if (r) return r;
    for (uint32_t k = 0; k < s->count; k++) s->seconds[k] = wall / s->count;
    if (g->has_timestamps && s->queries) {
        uint64_t ts[VX__SEQ_MAX + 1];
        VkResult vr = vkGetQueryPoolResults(g->device, g->timestamps, 0, s->queries + 1, sizeof ts, ts, sizeof ts[0],
                                            VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT);
        if (vr != VK_SUCCESS) return vx__vk_fail(err, vr, "vkGetQueryPoolResults");
        uint64_t prev = ts[0];
        for (uint32_t k = 0; k < s->count; k++) {
            uint32_t q = s->query[k];
            s->seconds[k] = q ? (double)(ts[q] - prev) * g->props.limits.timestampPeriod * 1e-9 : 0.0;
            if (q) prev = ts[q];
        }
    }
    return VX_OK;
}
