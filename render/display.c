/* render/display.c - the pass pipeline's image to display bytes on the GPU (see display.h). */
#include "render/display.h"

#include <string.h>

#include "render/gpu.h"
#include "display.comp.h"
#include "display_image.comp.h"

/* Descriptor sets: one per frame slot (a slot's is written again only after
 * its last frame ran), one for the calls outside frames. */
#define SETS (VX_DISPLAY_SLOTS + 1)
_Static_assert(VX_FRAME_SLOTS >= VX_DISPLAY_SLOTS, "a display slot is a frame renderer's slot");
#define OUTSIDE VX_DISPLAY_SLOTS /* the set and slot index of calls outside frames */

typedef struct dslot {
    VkCommandBuffer cmd;
    VkFence fence;
    bool pending; /* submitted, not yet waited for */
    int overlay;  /* the host overlay its frame copies from (-1: none) */
    vx_frame_renderer* fr; /* the renderer whose passes vx_display_record_frame recorded (a cancel tells it) */
    int fence_of; /* the slot whose fence signals this frame's end (a batch: its last frame's) */
    bool held;    /* recorded and ended, not yet submitted (a batch being gathered) */
    VkSemaphore wait_sem, signal_sem; /* a held frame's */
} dslot;

struct vx_display {
    vx_gpu* g;
    VkDescriptorPool pool;
    /* [0]: the conversion into the bytes buffer, [1]: into an image */
    VkDescriptorSet set[2][SETS];
    VkDescriptorSetLayout set_layout[2][SETS]; /* the layout each set was allocated with */
    /* two overlays, host-visible (the CPU draws into them): a redraw goes to
     * the one no frame in flight copies from, and becomes overlay[ov]; the
     * next frame copies it into overlay_dev, device-local, which the frames
     * read (host memory read by every frame cost 0.16 ms at 1920x1080 on an
     * H200: 8 MB over PCIe) */
    vx__buffer overlay[2];
    uint32_t ow[2], oh[2];
    int ov;
    vx__buffer overlay_dev;
    bool ov_dirty; /* overlay[ov] is newer than overlay_dev */
    vx__buffer out;   /* the display bytes */
    vx__buffer dummy; /* bound as the overlay when there is none */
    /* frames in flight */
    VkCommandPool cmd_pool;
    dslot slot[VX_DISPLAY_SLOTS];
    uint32_t depth;   /* frames in flight (vx_display_set_queue; default VX_DISPLAY_FRAMES) */
    uint32_t batch;   /* frames per vkQueueSubmit */
    bool one_info;    /* a batch's command buffers in one VkSubmitInfo */
    int held[VX_DISPLAY_SLOTS]; /* the held frames' slots, oldest first */
    uint32_t nheld;
    uint64_t begins_waited; /* frame_begin found its slot's frame not yet done */
    uint64_t frames_submitted, submits;
    uint32_t next; /* the slot the next frame takes */
    int cur;       /* the slot being recorded, -1: none */
    VkQueryPool qp; /* two timestamps per slot: the command buffer's start and end */
    bool untimed;   /* vx_display_set_timestamps(false): frames begun from now on write none */
    bool timed[VX_DISPLAY_SLOTS]; /* the slot's frame wrote its two */
    double last_gpu_ms, last_start_ms;
    uint64_t frames_done;
    /* off-screen images (vx_display_image_create) and their memory */
    VkImage images[VX_DISPLAY_IMAGES];
    VkDeviceMemory image_mem[VX_DISPLAY_IMAGES];
    VkImageView image_view[VX_DISPLAY_IMAGES]; /* with storage usage (vx_display_image_storage) */
    bool image_storage;
};

static vx_result flush(vx_display* d, vx_error* err);

typedef struct push_block {
    uint32_t n, bgra, overlay, row, width, iw, ih;
} push_block;

static void image_barrier(VkCommandBuffer cmd, VkImage img, VkImageLayout from, VkImageLayout to, VkAccessFlags src,
                          VkAccessFlags dst, VkPipelineStageFlags s0, VkPipelineStageFlags s1) {
    VkImageMemoryBarrier b = {.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER,
                              .srcAccessMask = src,
                              .dstAccessMask = dst,
                              .oldLayout = from,
                              .newLayout = to,
                              .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                              .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                              .image = img,
                              .subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1}};
    vkCmdPipelineBarrier(cmd, s0, s1, 0, 0, NULL, 0, NULL, 1, &b);
}

/* The shown image before a frame's last pass writes it: its contents are
 * not kept (UNDEFINED to GENERAL, after the work of stages `after` before
 * it: a swapchain's acquire is waited for at the transfer stage), black
 * where the fw x fh frame does not cover the iw x ih image. */
static void target_begin(VkCommandBuffer cmd, VkImage img, uint32_t fw, uint32_t fh, uint32_t iw, uint32_t ih,
                         VkPipelineStageFlags after) {
    image_barrier(cmd, img, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL, 0,
                  VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT, after,
                  VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT);
    if (fw < iw || fh < ih) {
        VkClearColorValue black = {{0, 0, 0, 1}};
        VkImageSubresourceRange range = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        vkCmdClearColorImage(cmd, img, VK_IMAGE_LAYOUT_GENERAL, &black, 1, &range);
        image_barrier(cmd, img, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_GENERAL, VK_ACCESS_TRANSFER_WRITE_BIT,
                      VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
    }
}

vx_result vx_display_create(vx_gpu* g, vx_display** out, vx_error* err) {
    if (!g || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    vx_display* d = vx_calloc(&g->alloc, 1, sizeof *d);
    if (!d) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    d->g = g;
    d->cur = -1;
    d->depth = VX_DISPLAY_FRAMES, d->batch = 1;
    for (int i = 0; i < VX_DISPLAY_SLOTS; i++) d->slot[i].overlay = -1, d->slot[i].fence_of = i;
    VkDescriptorPoolSize size[2] = {{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 3 * 2 * SETS},
                                    {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, SETS}};
    VkDescriptorPoolCreateInfo pci = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO,
                                      .flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT,
                                      .maxSets = 2 * SETS,
                                      .poolSizeCount = 2,
                                      .pPoolSizes = size};
    VkResult vr = vkCreateDescriptorPool(g->device, &pci, NULL, &d->pool);
    vx_result r = vr != VK_SUCCESS ? vx__vk_fail(err, vr, "vkCreateDescriptorPool") : VX_OK;
    if (!r) r = vx__buffer_create(g, 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, "display dummy", &d->dummy, err);
    VkCommandPoolCreateInfo cpi = {.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
                                   .flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT,
                                   .queueFamilyIndex = g->queue_family};
    if (!r && (vr = vkCreateCommandPool(g->device, &cpi, NULL, &d->cmd_pool)) != VK_SUCCESS)
        r = vx__vk_fail(err, vr, "vkCreateCommandPool");
    for (int i = 0; !r && i < VX_DISPLAY_SLOTS; i++) {
        VkCommandBufferAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
                                          .commandPool = d->cmd_pool,
                                          .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
                                          .commandBufferCount = 1};
        VkFenceCreateInfo fci = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        if ((vr = vkAllocateCommandBuffers(g->device, &ai, &d->slot[i].cmd)) != VK_SUCCESS)
            r = vx__vk_fail(err, vr, "vkAllocateCommandBuffers");
        else if ((vr = vkCreateFence(g->device, &fci, NULL, &d->slot[i].fence)) != VK_SUCCESS)
            r = vx__vk_fail(err, vr, "vkCreateFence");
    }
    /* the off-screen images take the conversion's writes where the device can (a B,G,R,A storage image) */
    VkFormatProperties fp;
    vkGetPhysicalDeviceFormatProperties(g->phys, VK_FORMAT_B8G8R8A8_UNORM, &fp);
    d->image_storage = g->has_storage_write && (fp.optimalTilingFeatures & VK_FORMAT_FEATURE_STORAGE_IMAGE_BIT);
    if (!r && g->has_timestamps) {
        VkQueryPoolCreateInfo qi = {.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO,
                                    .queryType = VK_QUERY_TYPE_TIMESTAMP,
                                    .queryCount = 2 * VX_DISPLAY_SLOTS};
        if ((vr = vkCreateQueryPool(g->device, &qi, NULL, &d->qp)) != VK_SUCCESS) r = vx__vk_fail(err, vr, "vkCreateQueryPool");
    }
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
    flush(d, &(vx_error){0}); /* held frames: their command buffers go with the pool */
    if (g->held_user == d) g->held_submit = NULL, g->held_user = NULL;
    vkDeviceWaitIdle(g->device);
    if (d->pool) vkDestroyDescriptorPool(g->device, d->pool, NULL);
    for (int i = 0; i < VX_DISPLAY_SLOTS; i++)
        if (d->slot[i].fence) vkDestroyFence(g->device, d->slot[i].fence, NULL);
    if (d->cmd_pool) vkDestroyCommandPool(g->device, d->cmd_pool, NULL);
    if (d->qp) vkDestroyQueryPool(g->device, d->qp, NULL);
    for (int i = 0; i < VX_DISPLAY_IMAGES; i++) {
        if (d->image_view[i]) vkDestroyImageView(g->device, d->image_view[i], NULL);
        if (d->images[i]) vkDestroyImage(g->device, d->images[i], NULL);
        if (d->image_mem[i]) vkFreeMemory(g->device, d->image_mem[i], NULL);
    }
    vx__buffer_destroy(g, &d->overlay[0]);
    vx__buffer_destroy(g, &d->overlay[1]);
    vx__buffer_destroy(g, &d->overlay_dev);
    vx__buffer_destroy(g, &d->out);
    vx__buffer_destroy(g, &d->dummy);
    vx_allocator a = g->alloc;
    vx_free(&a, d);
}

/* Waits for slot i's frame and takes its timestamps (a held frame is
 * submitted first, with the rest of its batch). */
static vx_result slot_wait(vx_display* d, int i, vx_error* err) {
    dslot* s = &d->slot[i];
    if (s->held) {
        vx_result r = flush(d, err);
        if (r) return r;
    }
    if (!s->pending) return VX_OK;
    vx_gpu* g = d->g;
    VkFence f = d->slot[s->fence_of].fence;
    if (vkGetFenceStatus(g->device, f) == VK_NOT_READY) d->begins_waited++;
    VX__VK(vkWaitForFences(g->device, 1, &f, VK_TRUE, UINT64_C(600) * 1000000000u), "vkWaitForFences");
    s->pending = false;
    uint64_t ts[2];
    if (d->qp && d->timed[i] && vkGetQueryPoolResults(g->device, d->qp, 2 * (uint32_t)i, 2, sizeof ts, ts, 8, VK_QUERY_RESULT_64_BIT) ==
                     VK_SUCCESS) {
        double per = g->props.limits.timestampPeriod * 1e-6;
        d->last_gpu_ms = (double)(ts[1] - ts[0]) * per;
        d->last_start_ms = (double)ts[0] * per;
    }
    d->frames_done++;
    return VX_OK;
}

vx_result vx_display_wait(vx_display* d, vx_error* err) {
    if (!d) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    vx_result r0 = flush(d, err);
    if (r0) return r0;
    /* oldest first, so that the last frame's times are the ones kept */
    for (int k = 0; k < (int)d->depth; k++) {
        vx_result r = slot_wait(d, (int)((d->next + (uint32_t)k) % d->depth), err);
        if (r) return r;
    }
    return VX_OK;
}

uint8_t* vx_display_overlay(vx_display* d, uint32_t w, uint32_t h, vx_error* err) {
    if (!d || !w || !h) {
        vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "no display or an empty frame");
        return NULL;
    }
    int t = d->ov ^ 1; /* the overlay the next frames do not read */
    for (int i = 0; i < VX_DISPLAY_SLOTS; i++)
        if ((d->slot[i].pending || d->slot[i].held) && d->slot[i].overlay == t && slot_wait(d, i, err)) return NULL;
    VkDeviceSize bytes = (VkDeviceSize)w * h * 4;
    vx__buffer* o = &d->overlay[t];
    if (o->size < bytes) {
        vkDeviceWaitIdle(d->g->device); /* a submission outside frames may still read the old one */
        vx__buffer_destroy(d->g, o);
        if (vx__buffer_create(d->g, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true, "display overlay", o, err)) return NULL;
        if (!o->map) {
            vx_fail(err, VX_ERR_GPU, VX_NO_OFFSET, "the overlay buffer is not host visible");
            vx__buffer_destroy(d->g, o);
            return NULL;
        }
    }
    d->ow[t] = w, d->oh[t] = h, d->ov = t, d->ov_dirty = true;
    memset(o->map, 0, (size_t)bytes);
    return o->map;
}

/* The device copy of the overlay for a frame of n pixels recorded into cmd
 * (slot si; OUTSIDE: a submission outside frames): made or grown,
 * and the overlay drawn since the last frame copied into it (after the
 * frames before read it; the host's writes before the submission are
 * visible to the copy without a barrier: vkQueueSubmit's guarantee). The
 * readers' barrier after the copy is the caller's. */
static vx_result overlay_prepare(vx_display* d, VkCommandBuffer cmd, const vx_display_desc* desc, uint64_t n, int si,
                                 vx_error* err) {
    vx_gpu* g = d->g;
    if (desc->overlay && d->overlay_dev.size < n * 4) {
        vkDeviceWaitIdle(g->device); /* frames in flight read the old one */
        vx_result r = vx__buffer_ensure(g, &d->overlay_dev, n * 4, "display overlay (device)", err);
        if (r) return r;
        d->ov_dirty = true;
    }
    bool copy = desc->overlay && d->ov_dirty;
    if (si < OUTSIDE) d->slot[si].overlay = copy ? d->ov : -1;
    if (!copy) return VX_OK;
    VkMemoryBarrier cb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER, .dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT};
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &cb, 0, NULL, 0,
                         NULL);
    VkBufferCopy c = {.size = n * 4};
    vkCmdCopyBuffer(cmd, d->overlay[d->ov].buf, d->overlay_dev.buf, 1, &c);
    d->ov_dirty = false;
    return VX_OK;
}

/* The conversion into d->out (view NULL), or into image `img` through its
 * storage view (iw x ih, left in final_layout). */
static vx_result record(vx_display* d, void* cmd_handle, const vx_display_desc* desc, VkImage img, VkImageView view,
                        uint32_t iw, uint32_t ih, VkImageLayout final_layout, uint64_t* out_buffer, vx_error* err) {
    if (!d || !cmd_handle || !desc || !desc->fr)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    vx_gpu* g = d->g;
    int to_image = view != VK_NULL_HANDLE;
    VkCommandBuffer cmd = (VkCommandBuffer)cmd_handle;
    uint32_t fw = 0, fh = 0;
    vx__buffer* src = vx__frame_renderer_image(desc->fr, &fw, &fh);
    if (!src) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "the frame renderer has rendered no frame");
    if (fw != desc->width || fh != desc->height)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "display of %ux%u, the last frame is %ux%u", desc->width,
                       desc->height, fw, fh);
    int ov = d->ov;
    if (desc->overlay && (d->ow[ov] != fw || d->oh[ov] != fh))
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "the overlay is %ux%u, the frame %ux%u", d->ow[ov], d->oh[ov],
                       fw, fh);
    /* a frame in flight records with its slot's set; other calls wait for their submission */
    int si = d->cur >= 0 && cmd == d->slot[d->cur].cmd ? d->cur : OUTSIDE;
    uint64_t n = (uint64_t)fw * fh;
    vx_result r = VX_OK;
    if (!to_image && d->out.size < n * 4) {
        vkDeviceWaitIdle(g->device);
        vx__buffer_destroy(g, &d->out);
        r = vx__buffer_create(g, n * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT, false,
                              "display bytes", &d->out, err);
        if (r) return r;
    }
    vx_gpu_compute_pipeline_desc pd = {.spirv = vx__display_spv_arr, .spirv_size = sizeof vx__display_spv_arr,
                                       .push_constant_size = sizeof(push_block), .binding_count = 3,
                                       .label = "display"};
    if (to_image)
        pd.spirv = vx__display_image_spv_arr, pd.spirv_size = sizeof vx__display_image_spv_arr, pd.label = "display image";
    for (int i = 0; i < 3; i++) pd.bindings[i] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    if (to_image) pd.bindings[2] = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
    vx__pipeline* p;
    if ((r = vx__pipeline_get(g, 0xD15B1A70u + (uint64_t)to_image, &pd, &p, err))) return r;
    /* the set follows the pipeline's layout (a cached pipeline may have been made again) */
    VkDescriptorSet* set = &d->set[to_image][si];
    if (!*set || d->set_layout[to_image][si] != p->dsl) {
        if (*set) vkFreeDescriptorSets(g->device, d->pool, 1, set), *set = VK_NULL_HANDLE;
        VkDescriptorSetAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO,
                                          .descriptorPool = d->pool,
                                          .descriptorSetCount = 1,
                                          .pSetLayouts = &p->dsl};
        VX__VK(vkAllocateDescriptorSets(g->device, &ai, set), "vkAllocateDescriptorSets");
        d->set_layout[to_image][si] = p->dsl;
    }
    if ((r = overlay_prepare(d, cmd, desc, n, si, err))) return r;
    const vx__buffer* ovb = desc->overlay ? &d->overlay_dev : &d->dummy;
    VkDescriptorBufferInfo bi[3] = {{src->buf, 0, n * 16}, {ovb->buf, 0, desc->overlay ? n * 4 : VK_WHOLE_SIZE},
                                    {d->out.buf, 0, n * 4}};
    VkDescriptorImageInfo ii = {.imageView = view, .imageLayout = VK_IMAGE_LAYOUT_GENERAL};
    VkWriteDescriptorSet w[3];
    for (int i = 0; i < 3; i++)
        w[i] = (VkWriteDescriptorSet){.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
                                      .dstSet = *set,
                                      .dstBinding = (uint32_t)i,
                                      .descriptorCount = 1,
                                      .descriptorType = pd.bindings[i],
                                      .pBufferInfo = i == 2 && to_image ? NULL : &bi[i],
                                      .pImageInfo = i == 2 && to_image ? &ii : NULL};
    vkUpdateDescriptorSets(g->device, 3, w, 0, NULL);
    /* the frame's passes ran earlier on this queue (this or earlier submissions); the overlay's copy just before */
    VkMemoryBarrier mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
                          .srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                          .dstAccessMask = VK_ACCESS_SHADER_READ_BIT};
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 1, &mb, 0, NULL, 0, NULL);
    if (to_image) {
        /* its contents are not kept; black where the frame does not cover it */
        target_begin(cmd, img, fw, fh, iw, ih, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT);
    }
    uint64_t groups = (n + 255) / 256;
    uint32_t row = groups < 65535 ? (uint32_t)groups : 65535u;
    push_block pc = {.n = (uint32_t)n, .bgra = desc->bgra, .overlay = desc->overlay, .row = row, .width = fw, .iw = iw,
                     .ih = ih};
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p->pipe);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p->layout, 0, 1, set, 0, NULL);
    vkCmdPushConstants(cmd, p->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof pc, &pc);
    vkCmdDispatch(cmd, row, (uint32_t)((groups + row - 1) / row), 1);
    if (to_image) {
        /* a later reader (presentation, a readback) brings its own wait: its semaphore or barrier */
        image_barrier(cmd, img, VK_IMAGE_LAYOUT_GENERAL, final_layout, VK_ACCESS_SHADER_WRITE_BIT, 0,
                      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT);
        return VX_OK;
    }
    VkMemoryBarrier tb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
                          .srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT,
                          .dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT};
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &tb, 0, NULL, 0,
                         NULL);
    *out_buffer = (uint64_t)(uintptr_t)d->out.buf;
    return VX_OK;
}

vx_result vx_display_record(vx_display* d, void* cmd, const vx_display_desc* desc, uint64_t* out_buffer, vx_error* err) {
    if (!out_buffer) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    return record(d, cmd, desc, VK_NULL_HANDLE, VK_NULL_HANDLE, 0, 0, VK_IMAGE_LAYOUT_UNDEFINED, out_buffer, err);
}

bool vx_display_image_storage(const vx_display* d) { return d && d->image_storage; }

bool vx_display_can_store(const vx_display* d, int format) {
    if (!d || !d->g->has_storage_write) return false;
    VkFormatProperties fp;
    vkGetPhysicalDeviceFormatProperties(d->g->phys, (VkFormat)format, &fp);
    return (fp.optimalTilingFeatures & VK_FORMAT_FEATURE_STORAGE_IMAGE_BIT) != 0;
}

vx_result vx_display_record_image(vx_display* d, void* cmd, const vx_display_desc* desc, uint64_t image, uint64_t view,
                                  uint32_t iw, uint32_t ih, int final_layout, vx_error* err) {
    if (!d) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    if (view)
        return record(d, cmd, desc, (VkImage)(uintptr_t)image, (VkImageView)(uintptr_t)view, iw, ih,
                      (VkImageLayout)final_layout, NULL, err);
    for (int k = 0; k < VX_DISPLAY_IMAGES; k++)
        if (d->images[k] && (uint64_t)(uintptr_t)d->images[k] == image && d->image_view[k] && d->image_storage)
            return record(d, cmd, desc, d->images[k], d->image_view[k], iw, ih, (VkImageLayout)final_layout, NULL, err);
    return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                   "not an off-screen image of this display with storage (vx_display_image_storage)");
}

vx_result vx_display_record_frame(vx_display* d, vx_frame_renderer* fr, const vx_frame_desc* fd,
                                  const vx_display_desc* desc, uint64_t image, uint64_t view, uint32_t iw, uint32_t ih,
                                  int final_layout, vx_frame_result* out, vx_error* err) {
    if (!d || !fr || !fd || !desc || !out || !image || !iw || !ih)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument or an empty image");
    if (desc->fr != fr) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "the display desc names another renderer");
    if (d->cur < 0) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "no frame is being recorded");
    vx_gpu* g = d->g;
    if (!g->has_storage_write)
        return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "%s cannot write images without a format (storage)",
                       g->props.deviceName);
    VkImage img = (VkImage)(uintptr_t)image;
    VkImageView iv = (VkImageView)(uintptr_t)view;
    for (int k = 0; !iv && d->image_storage && k < VX_DISPLAY_IMAGES; k++)
        if (d->images[k] == img) iv = d->image_view[k];
    if (!iv)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                       "no storage view: not an off-screen image of this display with storage (vx_display_image_storage)");
    uint32_t fw = desc->width, fh = desc->height;
    if (fd->base.width != fw || fd->base.height != fh)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "display of %ux%u, the frame is %ux%u", fw, fh,
                       fd->base.width, fd->base.height);
    int ov = d->ov;
    if (desc->overlay && (d->ow[ov] != fw || d->oh[ov] != fh))
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "the overlay is %ux%u, the frame %ux%u", d->ow[ov], d->oh[ov],
                       fw, fh);
    int si = d->cur;
    VkCommandBuffer cmd = d->slot[si].cmd;
    /* before the passes: the overlay's copy (the frame's table barrier orders it before the passes' reads) and
     * the image in the layout the last pass writes it in (a swapchain's acquire, waited for at the transfer
     * stage, comes first through this barrier); its contents are not kept, black where the frame does not cover it */
    vx_result r = overlay_prepare(d, cmd, desc, (uint64_t)fw * fh, si, err);
    if (r) return r;
    /* after the acquire (transfer stage) only, not the frames before: their image is another, and waiting for
     * their compute work would keep this frame's passes from starting while the last one's tail runs */
    target_begin(cmd, img, fw, fh, iw, ih, VK_PIPELINE_STAGE_TRANSFER_BIT);
    vx__display_target t = {.view = iv, .iw = iw, .ih = ih, .overlay = desc->overlay ? &d->overlay_dev : NULL,
                            .bgra = desc->bgra};
    d->slot[si].fr = fr;
    if ((r = vx__frame_record_display(fr, fd, cmd, (uint32_t)si, &t, out, err))) return r;
    /* a later reader (presentation, a readback) brings its own wait: its semaphore or barrier; a render pass
     * drawing over the image (the panels: COLOR_ATTACHMENT_OPTIMAL) gets the scene's writes here */
    if (final_layout == VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL)
        image_barrier(cmd, img, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_ACCESS_SHADER_WRITE_BIT,
                      VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
                      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT);
    else
        image_barrier(cmd, img, VK_IMAGE_LAYOUT_GENERAL, (VkImageLayout)final_layout, VK_ACCESS_SHADER_WRITE_BIT, 0,
                      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT);
    return VX_OK;
}

vx_result vx_display_run(vx_display* d, const vx_display_desc* desc, uint8_t* bytes, double* seconds, vx_error* err) {
    if (!d || !desc) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    vx_gpu* g = d->g;
    if (d->cur >= 0) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "a frame is being recorded");
    vx_result r = vx_display_wait(d, err);
    if (r) return r;
    double t0 = vx_time_now();
    uint64_t buf;
    r = vx__cmd_begin(g, err);
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

/* ---- frames in flight ---------------------------------------------------------------- */

vx_result vx_display_frame_begin(vx_display* d, uint32_t* slot, void** cmd, vx_error* err) {
    if (!d || !slot || !cmd) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    if (d->cur >= 0) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "frame %d is still being recorded", d->cur);
    int i = (int)d->next;
    vx_result r = slot_wait(d, i, err); /* the frame d->depth before this one */
    if (r) return r;
    dslot* s = &d->slot[i];
    vx_gpu* g = d->g;
    VX__VK(vkResetFences(g->device, 1, &s->fence), "vkResetFences");
    VX__VK(vkResetCommandBuffer(s->cmd, 0), "vkResetCommandBuffer");
    VkCommandBufferBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
                                   .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};
    VX__VK(vkBeginCommandBuffer(s->cmd, &bi), "vkBeginCommandBuffer");
    d->timed[i] = d->qp && !d->untimed;
    if (d->timed[i]) {
        vkCmdResetQueryPool(s->cmd, d->qp, 2 * (uint32_t)i, 2);
        vkCmdWriteTimestamp(s->cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, d->qp, 2 * (uint32_t)i);
    }
    s->overlay = -1;
    s->fr = NULL;
    d->cur = i;
    *slot = (uint32_t)i;
    *cmd = s->cmd;
    return VX_OK;
}

vx_result vx_display_frame_submit(vx_display* d, uint64_t wait_semaphore, uint64_t signal_semaphore, vx_error* err) {
    if (!d) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    if (d->cur < 0) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "no frame is being recorded");
    int i = d->cur;
    dslot* s = &d->slot[i];
    d->cur = -1;
    if (d->timed[i]) vkCmdWriteTimestamp(s->cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, d->qp, 2 * (uint32_t)i + 1);
    VX__VK(vkEndCommandBuffer(s->cmd), "vkEndCommandBuffer");
    s->wait_sem = (VkSemaphore)(uintptr_t)wait_semaphore, s->signal_sem = (VkSemaphore)(uintptr_t)signal_semaphore;
    s->held = true;
    d->held[d->nheld++] = i;
    d->next = (d->next + 1) % d->depth;
    return d->nheld >= d->batch ? flush(d, err) : VX_OK;
}

/* Submits the held frames in one vkQueueSubmit, the last one's fence
 * signalling the end of all of them. */
static vx_result flush(vx_display* d, vx_error* err) {
    if (!d->nheld) return VX_OK;
    VkSubmitInfo si[VX_DISPLAY_SLOTS];
    VkCommandBuffer cbs[VX_DISPLAY_SLOTS];
    /* only the write into the image waits (a swapchain's acquire): the passes start before it */
    static const VkPipelineStageFlags stage = VK_PIPELINE_STAGE_TRANSFER_BIT;
    uint32_t n = d->nheld, ns = 0;
    int last = d->held[n - 1];
    bool one = d->one_info;
    for (uint32_t k = 0; k < n; k++) {
        dslot* s = &d->slot[d->held[k]];
        one = one && !s->wait_sem && !s->signal_sem;
        cbs[k] = s->cmd;
    }
    for (uint32_t k = 0; k < n; k++) {
        dslot* s = &d->slot[d->held[k]];
        if (one && k) continue;
        si[ns++] = (VkSubmitInfo){.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO,
                                  .waitSemaphoreCount = s->wait_sem ? 1 : 0,
                                  .pWaitSemaphores = &s->wait_sem,
                                  .pWaitDstStageMask = &stage,
                                  .commandBufferCount = one ? n : 1,
                                  .pCommandBuffers = one ? cbs : &s->cmd,
                                  .signalSemaphoreCount = s->signal_sem ? 1 : 0,
                                  .pSignalSemaphores = &s->signal_sem};
    }
    d->nheld = 0;
    for (uint32_t k = 0; k < n; k++) {
        dslot* s = &d->slot[d->held[k]];
        s->held = false, s->pending = true, s->fence_of = last;
    }
    VX__VK(vkQueueSubmit(d->g->queue, ns, si, d->slot[last].fence), "vkQueueSubmit");
    d->frames_submitted += n;
    d->submits++;
    return VX_OK;
}

/* vx_gpu.held_submit: work recorded after the held frames is about to be
 * submitted, or the queue waited for (a failure shows at the display's next
 * call: its frames' fences never signal, so the device is lost anyway) */
static void held_submit(void* user) {
    vx_display* d = user;
    vx_error err = {0};
    (void)flush(d, &err);
}

vx_result vx_display_set_queue(vx_display* d, uint32_t frames, uint32_t batch, bool one_submit_info, vx_error* err) {
    if (!d) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    if (!frames) frames = VX_DISPLAY_FRAMES;
    if (!batch) batch = 1;
    if (frames > VX_DISPLAY_SLOTS || batch > frames)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "%u frames in flight in batches of %u: at most %d, batch <= frames",
                       frames, batch, VX_DISPLAY_SLOTS);
    if (d->cur >= 0) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "a frame is being recorded");
    vx_result r = vx_display_wait(d, err);
    if (r) return r;
    d->depth = frames, d->batch = batch, d->one_info = one_submit_info, d->next = 0;
    vx_gpu* g = d->g;
    if (batch > 1) g->held_submit = held_submit, g->held_user = d; /* other work on the queue submits ours first */
    else if (g->held_user == d) g->held_submit = NULL, g->held_user = NULL;
    return VX_OK;
}

void vx_display_frame_cancel(vx_display* d) {
    if (!d || d->cur < 0) return;
    dslot* s = &d->slot[d->cur];
    if (s->fr) vx_frame_record_cancel(s->fr); /* the scene's tables recorded there are not written */
    vkEndCommandBuffer(s->cmd);
    vkResetCommandBuffer(s->cmd, 0);
    d->cur = -1;
}

void vx_display_set_timestamps(vx_display* d, bool on) {
    if (d) d->untimed = !on;
}

void vx_display_frame_times(const vx_display* d, vx_display_times* out) {
    memset(out, 0, sizeof *out);
    if (!d) return;
    out->frames_done = d->frames_done;
    out->begins_waited = d->begins_waited;
    out->frames_submitted = d->frames_submitted;
    out->submits = d->submits;
    out->gpu_ms = d->last_gpu_ms;
    out->gpu_start_ms = d->last_start_ms;
}


void vx_display_copy_to_image(void* cmd_handle, uint64_t buffer, uint32_t w, uint32_t h, uint64_t image, uint32_t iw,
                              uint32_t ih, int final_layout) {
    VkCommandBuffer cmd = (VkCommandBuffer)cmd_handle;
    VkImage img = (VkImage)(uintptr_t)image;
    image_barrier(cmd, img, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 0, VK_ACCESS_TRANSFER_WRITE_BIT,
                  VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT);
    uint32_t cw = w < iw ? w : iw, ch = h < ih ? h : ih;
    if (!buffer || cw != iw || ch != ih) {
        VkClearColorValue black = {{0, 0, 0, 1}};
        VkImageSubresourceRange range = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        vkCmdClearColorImage(cmd, img, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &black, 1, &range);
        VkMemoryBarrier mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
                              .srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
                              .dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT};
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &mb, 0, NULL, 0, NULL);
    }
    if (buffer) {
        VkBufferImageCopy region = {.bufferRowLength = w,
                                    .bufferImageHeight = h,
                                    .imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
                                    .imageExtent = {cw, ch, 1}};
        vkCmdCopyBufferToImage(cmd, (VkBuffer)(uintptr_t)buffer, img, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
    }
    /* a later reader (presentation, a readback) brings its own wait: its semaphore or barrier */
    image_barrier(cmd, img, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, (VkImageLayout)final_layout, VK_ACCESS_TRANSFER_WRITE_BIT, 0,
                  VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT);
}

/* ---- off-screen images ---------------------------------------------------------------- */

vx_result vx_display_image_create(vx_display* d, uint32_t w, uint32_t h, uint64_t* out, vx_error* err) {
    if (!d || !out || !w || !h) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument or an empty image");
    int k = 0;
    while (k < VX_DISPLAY_IMAGES && d->images[k]) k++;
    if (k == VX_DISPLAY_IMAGES) return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "%d off-screen images at most", VX_DISPLAY_IMAGES);
    vx_gpu* g = d->g;
    VkImageCreateInfo ii = {.sType = VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO,
                            .imageType = VK_IMAGE_TYPE_2D,
                            .format = VK_FORMAT_B8G8R8A8_UNORM,
                            .extent = {w, h, 1},
                            .mipLevels = 1,
                            .arrayLayers = 1,
                            .samples = VK_SAMPLE_COUNT_1_BIT,
                            .tiling = VK_IMAGE_TILING_OPTIMAL,
                            .usage = VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                                     VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT |
                                     (d->image_storage ? VK_IMAGE_USAGE_STORAGE_BIT : 0),
                            .sharingMode = VK_SHARING_MODE_EXCLUSIVE};
    VX__VK(vkCreateImage(g->device, &ii, NULL, &d->images[k]), "vkCreateImage");
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(g->device, d->images[k], &req);
    uint32_t type = UINT32_MAX;
    for (int pass = 0; pass < 2 && type == UINT32_MAX; pass++)
        for (uint32_t t = 0; t < g->memprops.memoryTypeCount && type == UINT32_MAX; t++)
            if ((req.memoryTypeBits & (1u << t)) &&
                (pass || (g->memprops.memoryTypes[t].propertyFlags & VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT)))
                type = t;
    VkMemoryAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO, .allocationSize = req.size,
                               .memoryTypeIndex = type};
    VkResult vr = type == UINT32_MAX ? VK_ERROR_OUT_OF_DEVICE_MEMORY : vkAllocateMemory(g->device, &ai, NULL, &d->image_mem[k]);
    if (vr == VK_SUCCESS) vr = vkBindImageMemory(g->device, d->images[k], d->image_mem[k], 0);
    if (vr == VK_SUCCESS) { /* the storage view where the device can, a colour attachment's always */
        VkImageViewCreateInfo vi = {.sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO,
                                    .image = d->images[k],
                                    .viewType = VK_IMAGE_VIEW_TYPE_2D,
                                    .format = VK_FORMAT_B8G8R8A8_UNORM,
                                    .subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1}};
        vr = vkCreateImageView(g->device, &vi, NULL, &d->image_view[k]);
    }
    if (vr != VK_SUCCESS) {
        vx_display_image_destroy(d, (uint64_t)(uintptr_t)d->images[k]);
        return vx__vk_fail(err, vr, "allocating an off-screen image");
    }
    *out = (uint64_t)(uintptr_t)d->images[k];
    return VX_OK;
}

void vx_display_image_destroy(vx_display* d, uint64_t image) {
    if (!d || !image) return;
    for (int k = 0; k < VX_DISPLAY_IMAGES; k++) {
        if ((uint64_t)(uintptr_t)d->images[k] != image) continue;
        vkDeviceWaitIdle(d->g->device);
        if (d->image_view[k]) vkDestroyImageView(d->g->device, d->image_view[k], NULL);
        vkDestroyImage(d->g->device, d->images[k], NULL);
        if (d->image_mem[k]) vkFreeMemory(d->g->device, d->image_mem[k], NULL);
        d->images[k] = VK_NULL_HANDLE, d->image_mem[k] = VK_NULL_HANDLE, d->image_view[k] = VK_NULL_HANDLE;
    }
}

uint64_t vx_display_image_view(const vx_display* d, uint64_t image) {
    for (int k = 0; d && image && k < VX_DISPLAY_IMAGES; k++)
        if ((uint64_t)(uintptr_t)d->images[k] == image) return (uint64_t)(uintptr_t)d->image_view[k];
    return 0;
}

vx_result vx_display_image_read(vx_display* d, uint64_t image, uint32_t w, uint32_t h, uint8_t* bytes, vx_error* err) {
    if (!d || !image || !bytes) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    vx_gpu* g = d->g;
    vx_result r = vx_display_wait(d, err);
    if (r) return r;
    vx__buffer st;
    VkDeviceSize size = (VkDeviceSize)w * h * 4;
    if ((r = vx__buffer_create(g, size, 0, true, "image readback", &st, err))) return r;
    if (!st.map) r = vx_fail(err, VX_ERR_GPU, VX_NO_OFFSET, "the readback buffer is not host visible");
    if (!r) r = vx__cmd_begin(g, err);
    if (!r) {
        VkCommandBuffer cmd = g->cmd;
        VkImage img = (VkImage)(uintptr_t)image;
        image_barrier(cmd, img, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                      VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_SHADER_WRITE_BIT, VK_ACCESS_TRANSFER_READ_BIT,
                      VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT);
        VkBufferImageCopy c = {.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1}, .imageExtent = {w, h, 1}};
        vkCmdCopyImageToBuffer(cmd, img, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, st.buf, 1, &c);
        VkMemoryBarrier mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
                              .srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
                              .dstAccessMask = VK_ACCESS_HOST_READ_BIT};
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &mb, 0, NULL, 0, NULL);
        r = vx__cmd_submit_wait(g, err);
    }
    if (!r) memcpy(bytes, st.map, (size_t)size);
    vx__buffer_destroy(g, &st);
    return r;
}
