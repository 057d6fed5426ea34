/* render/gpu_memory.c - buffers: device-local for scene data (staged uploads
 * when the memory is not host visible, as on discrete GPUs), host-visible and
 * persistently mapped for small per-frame tables. */
#define _GNU_SOURCE /* getcpu: the memory log's CPU and NUMA node */
#include <sched.h>
#include <stdio.h>
#include <string.h>

#include "render/render_internal.h"

/* VX_GPU_MEMORY_LOG's words for a memory type's flags. */
static void flag_names(VkMemoryPropertyFlags f, char* out, size_t n) {
    snprintf(out, n, "%s%s%s%s%s", f & VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT ? "device-local " : "",
             f & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT ? "host-visible " : "",
             f & VK_MEMORY_PROPERTY_HOST_COHERENT_BIT ? "coherent " : "",
             f & VK_MEMORY_PROPERTY_HOST_CACHED_BIT ? "cached " : "", f ? "" : "none ");
}

void vx__gpu_log_memory_types(vx_gpu* g) {
    if (!g->memory_log) return;
    for (uint32_t h = 0; h < g->memprops.memoryHeapCount; h++)
        vx_log(g->logger, VX_LOG_INFO, "gpu.memory", "heap %u: %.1f MiB%s", h, g->memprops.memoryHeaps[h].size / 1048576.0,
               g->memprops.memoryHeaps[h].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT ? " device-local" : "");
    for (uint32_t i = 0; i < g->memprops.memoryTypeCount; i++) {
        char f[96];
        flag_names(g->memprops.memoryTypes[i].propertyFlags, f, sizeof f);
        vx_log(g->logger, VX_LOG_INFO, "gpu.memory", "type %u: heap %u, %s", i, g->memprops.memoryTypes[i].heapIndex, f);
    }
}

static bool find_type(vx_gpu* g, uint32_t bits, VkMemoryPropertyFlags want, uint32_t* out) {
    for (uint32_t i = 0; i < g->memprops.memoryTypeCount; i++)
        if ((bits & (1u << i)) && (g->memprops.memoryTypes[i].propertyFlags & want) == want) {
            *out = i;
            return true;
        }
    return false;
}

vx_result vx__buffer_create(vx_gpu* g, VkDeviceSize size, VkBufferUsageFlags usage, bool host_visible,
                            const char* label, vx__buffer* out, vx_error* err) {
    memset(out, 0, sizeof *out);
    if (size == 0) size = 16; /* absent arrays still need a valid binding */
    size = (size + 15) & ~(VkDeviceSize)15;
    VkBufferCreateInfo bi = {.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO,
                             .size = size,
                             .usage = usage | VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                             .sharingMode = VK_SHARING_MODE_EXCLUSIVE};
    VX__VK(vkCreateBuffer(g->device, &bi, NULL, &out->buf), "vkCreateBuffer");
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(g->device, out->buf, &req);
    uint32_t type = 0;
    bool ok;
    if (host_visible) {
        ok = find_type(g, req.memoryTypeBits,
                       VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT |
                           VK_MEMORY_PROPERTY_HOST_CACHED_BIT,
                       &type) ||
             find_type(g, req.memoryTypeBits, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
                       &type);
    } else {
        ok = find_type(g, req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, &type) ||
             find_type(g, req.memoryTypeBits, 0, &type);
    }
    if (!ok) {
        vx__buffer_destroy(g, out);
        return vx_fail(err, VX_ERR_GPU, VX_NO_OFFSET, "no suitable memory type for buffer '%s'", label);
    }
    VkMemoryAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
                               .allocationSize = req.size,
                               .memoryTypeIndex = type};
    VkResult r = vkAllocateMemory(g->device, &ai, NULL, &out->mem);
    if (r == VK_SUCCESS) r = vkBindBufferMemory(g->device, out->buf, out->mem, 0);
    out->size = size;
    VkMemoryPropertyFlags flags = g->memprops.memoryTypes[type].propertyFlags;
    out->host_visible = (flags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) && (flags & VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    if (r == VK_SUCCESS && out->host_visible) r = vkMapMemory(g->device, out->mem, 0, VK_WHOLE_SIZE, 0, &out->map);
    if (g->memory_log) {
        char f[96];
        flag_names(flags, f, sizeof f);
        unsigned cpu = 0, node = 0;
        getcpu(&cpu, &node);
        vx_log(g->logger, VX_LOG_INFO, "gpu.memory", "'%s' %llu bytes: type %u (%sheap %u), map %p, cpu %u node %u%s", label,
               (unsigned long long)req.size, type, f, g->memprops.memoryTypes[type].heapIndex, out->map, cpu, node,
               r == VK_SUCCESS ? "" : " FAILED");
    }
    if (r != VK_SUCCESS) {
        vx__buffer_destroy(g, out);
        char what[96];
        snprintf(what, sizeof what, "allocating %llu bytes for '%s'", (unsigned long long)size, label);
        return vx__vk_fail(err, r, what);
    }
    vx__gpu_name(g, VK_OBJECT_TYPE_BUFFER, (uint64_t)out->buf, label);
    return VX_OK;
}

void vx__buffer_destroy(vx_gpu* g, vx__buffer* b) {
    if (!b) return;
    if (b->sampler) vkDestroySampler(g->device, b->sampler, NULL);
    if (b->view) vkDestroyImageView(g->device, b->view, NULL);
    if (b->image) vkDestroyImage(g->device, b->image, NULL);
    if (b->map) vkUnmapMemory(g->device, b->mem);
    if (b->buf) vkDestroyBuffer(g->device, b->buf, NULL);
    if (b->mem) vkFreeMemory(g->device, b->mem, NULL);
    memset(b, 0, sizeof *b);
}

static vx_result staged_copy(vx_gpu* g, vx__buffer* b, VkDeviceSize offset, void* data, VkDeviceSize size, bool up,
                              vx_error* err) {
    vx__buffer st;
    vx_result r = vx__buffer_create(g, size, 0, true, "staging", &st, err);
    if (r) return r;
    if (!st.map) {
        vx__buffer_destroy(g, &st);
        return vx_fail(err, VX_ERR_GPU, VX_NO_OFFSET, "staging buffer is not host visible");
    }
    if (up) memcpy(st.map, data, size);
    r = vx__cmd_begin(g, err);
    if (!r) {
        VkBufferCopy c = {.size = size};
        if (up) {
            c.dstOffset = offset;
            vkCmdCopyBuffer(g->cmd, st.buf, b->buf, 1, &c);
        } else {
            c.srcOffset = offset;
            vkCmdCopyBuffer(g->cmd, b->buf, st.buf, 1, &c);
        }
        r = vx__cmd_submit_wait(g, err);
    }
    if (!r && !up) memcpy(data, st.map, size);
    vx__buffer_destroy(g, &st);
    return r;
}

vx_result vx__buffer_upload(vx_gpu* g, vx__buffer* b, const void* data, VkDeviceSize size, vx_error* err) {
    return vx__buffer_upload_at(g, b, 0, data, size, err);
}

vx_result vx__buffer_upload_at(vx_gpu* g, vx__buffer* b, VkDeviceSize offset, const void* data, VkDeviceSize size,
                               vx_error* err) {
    if (size == 0) return VX_OK;
    if (offset > b->size || size > b->size - offset)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "upload past the buffer's end");
    if (b->map) {
        memcpy((uint8_t*)b->map + offset, data, size);
        return VX_OK;
    }
    return staged_copy(g, b, offset, (void*)data, size, true, err);
}

vx_result vx__buffer_download(vx_gpu* g, vx__buffer* b, void* data, VkDeviceSize size, vx_error* err) {
    return vx__buffer_download_at(g, b, 0, data, size, err);
}

vx_result vx__buffer_download_at(vx_gpu* g, vx__buffer* b, VkDeviceSize offset, void* data, VkDeviceSize size,
                                 vx_error* err) {
    if (size == 0) return VX_OK;
    if (offset > b->size || size > b->size - offset)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "download past the buffer's end");
    if (b->map) {
        memcpy(data, (const uint8_t*)b->map + offset, size);
        return VX_OK;
    }
    return staged_copy(g, b, offset, data, size, false, err);
}

vx_result vx__buffer_ensure(vx_gpu* g, vx__buffer* b, VkDeviceSize size, const char* label, vx_error* err) {
    if (b->buf && b->size >= size) return VX_OK;
    vx__buffer_destroy(g, b);
    return vx__buffer_create(g, size, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, label, b, err);
}

vx_result vx__image3d_create(vx_gpu* g, const uint32_t extent[3], const char* label, vx__buffer* out, vx_error* err) {
    memset(out, 0, sizeof *out);
    const VkFormat fmt = VK_FORMAT_R16G16B16A16_SFLOAT;
    uint32_t lim = g->props.limits.maxImageDimension3D;
    if (!extent[0] || !extent[1] || !extent[2] || extent[0] > lim || extent[1] > lim || extent[2] > lim)
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "a %ux%ux%u image for '%s': the device's 3D images reach %u",
                       extent[0], extent[1], extent[2], label, lim);
    VkImageCreateInfo ii = {.sType = VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO,
                            .imageType = VK_IMAGE_TYPE_3D,
                            .format = fmt,
                            .extent = {extent[0], extent[1], extent[2]},
                            .mipLevels = 1,
                            .arrayLayers = 1,
                            .samples = VK_SAMPLE_COUNT_1_BIT,
                            .tiling = VK_IMAGE_TILING_OPTIMAL,
                            .usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                            .sharingMode = VK_SHARING_MODE_EXCLUSIVE,
                            .initialLayout = VK_IMAGE_LAYOUT_UNDEFINED};
    VX__VK(vkCreateImage(g->device, &ii, NULL, &out->image), "vkCreateImage");
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(g->device, out->image, &req);
    uint32_t type = 0;
    if (!find_type(g, req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, &type) &&
        !find_type(g, req.memoryTypeBits, 0, &type)) {
        vx__buffer_destroy(g, out);
        return vx_fail(err, VX_ERR_GPU, VX_NO_OFFSET, "no suitable memory type for image '%s'", label);
    }
    VkMemoryAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO, .allocationSize = req.size, .memoryTypeIndex = type};
    VkResult r = vkAllocateMemory(g->device, &ai, NULL, &out->mem);
    if (r == VK_SUCCESS) r = vkBindImageMemory(g->device, out->image, out->mem, 0);
    if (r == VK_SUCCESS) {
        VkImageViewCreateInfo vi = {.sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO,
                                    .image = out->image,
                                    .viewType = VK_IMAGE_VIEW_TYPE_3D,
                                    .format = fmt,
                                    .subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1}};
        r = vkCreateImageView(g->device, &vi, NULL, &out->view);
    }
    if (r == VK_SUCCESS) {
        VkSamplerCreateInfo si = {.sType = VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO,
                                  .magFilter = VK_FILTER_LINEAR,
                                  .minFilter = VK_FILTER_LINEAR,
                                  .mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST,
                                  .addressModeU = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_BORDER,
                                  .addressModeV = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_BORDER,
                                  .addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_BORDER,
                                  .borderColor = VK_BORDER_COLOR_FLOAT_TRANSPARENT_BLACK};
        r = vkCreateSampler(g->device, &si, NULL, &out->sampler);
    }
    if (r != VK_SUCCESS) {
        vx__buffer_destroy(g, out);
        char what[96];
        snprintf(what, sizeof what, "creating a %ux%ux%u image for '%s'", extent[0], extent[1], extent[2], label);
        return vx__vk_fail(err, r, what);
    }
    out->size = req.size;
    vx__gpu_name(g, VK_OBJECT_TYPE_IMAGE, (uint64_t)out->image, label);
    /* to the general layout, cleared */
    vx_result res = vx__cmd_begin(g, err);
    if (!res) {
        VkImageSubresourceRange range = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        VkImageMemoryBarrier b = {.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER,
                                  .srcAccessMask = 0,
                                  .dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
                                  .oldLayout = VK_IMAGE_LAYOUT_UNDEFINED,
                                  .newLayout = VK_IMAGE_LAYOUT_GENERAL,
                                  .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                                  .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                                  .image = out->image,
                                  .subresourceRange = range};
        vkCmdPipelineBarrier(g->cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, NULL, 0, NULL, 1, &b);
        VkClearColorValue zero = {{0, 0, 0, 0}};
        vkCmdClearColorImage(g->cmd, out->image, VK_IMAGE_LAYOUT_GENERAL, &zero, 1, &range);
        b.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        b.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;
        b.oldLayout = VK_IMAGE_LAYOUT_GENERAL;
        vkCmdPipelineBarrier(g->cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 0, NULL, 0, NULL, 1, &b);
        res = vx__cmd_submit_wait(g, err);
    }
    if (res) vx__buffer_destroy(g, out);
    return res;
}
