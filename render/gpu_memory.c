/* render/gpu_memory.c - buffers: device-local for scene data (staged uploads
 * when the memory is not host visible, as on discrete GPUs), host-visible and
 * persistently mapped for small per-frame tables. */
#include <stdio.h>
#include <string.h>

#include "render/render_internal.h"

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
    if (b->map) vkUnmapMemory(g->device, b->mem);
    if (b->buf) vkDestroyBuffer(g->device, b->buf, NULL);
    if (b->mem) vkFreeMemory(g->device, b->mem, NULL);
    memset(b, 0, sizeof *b);
}

static vx_result staged_copy(vx_gpu* g, vx__buffer* b, void* data, VkDeviceSize size, bool up, vx_error* err) {
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
        if (up)
            vkCmdCopyBuffer(g->cmd, st.buf, b->buf, 1, &c);
        else
            vkCmdCopyBuffer(g->cmd, b->buf, st.buf, 1, &c);
        r = vx__cmd_submit_wait(g, err);
    }
    if (!r && !up) memcpy(data, st.map, size);
    vx__buffer_destroy(g, &st);
    return r;
}

vx_result vx__buffer_upload(vx_gpu* g, vx__buffer* b, const void* data, VkDeviceSize size, vx_error* err) {
    if (size == 0) return VX_OK;
    if (size > b->size) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "upload larger than buffer");
    if (b->map) {
        memcpy(b->map, data, size);
        return VX_OK;
    }
    return staged_copy(g, b, (void*)data, size, true, err);
}

vx_result vx__buffer_download(vx_gpu* g, vx__buffer* b, void* data, VkDeviceSize size, vx_error* err) {
    if (size == 0) return VX_OK;
    if (size > b->size) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "download larger than buffer");
    if (b->map) {
        memcpy(data, b->map, size);
        return VX_OK;
    }
    return staged_copy(g, b, data, size, false, err);
}

vx_result vx__buffer_ensure(vx_gpu* g, vx__buffer* b, VkDeviceSize size, const char* label, vx_error* err) {
    if (b->buf && b->size >= size) return VX_OK;
    vx__buffer_destroy(g, b);
    return vx__buffer_create(g, size, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, label, b, err);
}
