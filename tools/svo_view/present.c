/* tools/svo_view/present.c - GLFW window, Vulkan device and swapchain (see present.h). */
#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include "tools/svo_view/present.h"

#include <stdlib.h>
#include <string.h>

#define VP_MAX_IMAGES 8

struct vp {
    GLFWwindow* win;
    bool glfw_init;
    VkInstance inst;
    VkPhysicalDevice phys;
    VkDevice dev;
    uint32_t family;
    VkQueue queue;
    bool float64;
    VkSurfaceKHR surface;
    VkSwapchainKHR sc;
    VkFormat format;
    VkExtent2D extent;
    uint32_t image_count;
    VkImage images[VP_MAX_IMAGES];
    VkImageView views[VP_MAX_IMAGES]; /* storage views when the swapchain takes the conversion's writes */
    VkSemaphore done[VP_MAX_IMAGES];
    bool storage_write; /* the device has shaderStorageImageWriteWithoutFormat (vx_gpu_make_device) */
    bool storage;       /* the swapchain images are storage images (frames in flight write them directly) */
    bool colour;        /* ... and colour attachments (the panels drawn over them on the GPU) */
    VkSemaphore acquired;
    /* frames in flight (vp_acquire): an acquire semaphore per frame slot, the
     * image the frame being recorded took */
    VkSemaphore slot_acquired[VX_DISPLAY_SLOTS];
    uint32_t frame_image;
    bool frame_acquired;
    /* batches (vp_desc.batch): presents queued until their frame is submitted */
    uint32_t batch;
    uint64_t frame_number; /* of the frame being recorded */
    uint32_t npend;
    uint32_t pend_image[VP_MAX_IMAGES];
    uint64_t pend_frame[VP_MAX_IMAGES];
    uint64_t presented, out_of_order, last_presented; /* vp_get_present_counts */
    VkFence fence;
    VkCommandPool pool;
    VkCommandBuffer cmd;
    VkBuffer staging;
    VkDeviceMemory staging_mem;
    VkDeviceSize staging_size;
    void* staging_map;
    bool vsync, dirty;
    /* validation: the window's instance is the tracer's (external), so the
     * messenger that counts errors lives here */
    VkDebugUtilsMessengerEXT messenger;
    struct vp_valid {
        uint32_t* errors;
        const vx_logger* logger;
    } valid;
};

static VKAPI_ATTR VkBool32 VKAPI_CALL debug_cb(VkDebugUtilsMessageSeverityFlagBitsEXT sev,
                                               VkDebugUtilsMessageTypeFlagsEXT type,
                                               const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
    (void)type;
    const struct vp_valid* v = user;
    const char* msg = data && data->pMessage ? data->pMessage : "?";
    if (sev & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
        if (v->errors) ++*v->errors;
        vx_log(v->logger, VX_LOG_WARN, "gpu.validation", "%s", msg);
    } else {
        vx_log(v->logger, VX_LOG_INFO, "gpu.validation_warning", "%s", msg);
    }
    return VK_FALSE;
}

static vx_result vk_fail(vx_error* err, VkResult r, const char* what) {
    return vx_fail(err, VX_ERR_GPU, VX_NO_OFFSET, "%s failed: VkResult %d", what, (int)r);
}
#define VP_VK(call, what)                                \
    do {                                                 \
        VkResult vp__r = (call);                         \
        if (vp__r != VK_SUCCESS) return vk_fail(err, vp__r, what); \
    } while (0)

/* The window's user pointer belongs to the application, so a resize is
 * noticed by comparing the framebuffer with the swapchain. */
static void check_resize(vp* p) {
    int fw = 0, fh = 0;
    glfwGetFramebufferSize(p->win, &fw, &fh);
    if ((uint32_t)fw != p->extent.width || (uint32_t)fh != p->extent.height) p->dirty = true;
}

/* The viewer computes and presents on one queue (compute queues also do the
 * transfers the presentation path needs). */
static bool can_present(void* user, const void* pd, uint32_t family) {
    vp* p = (vp*)user;
    VkBool32 ok = VK_FALSE;
    return vkGetPhysicalDeviceSurfaceSupportKHR((VkPhysicalDevice)pd, family, p->surface, &ok) == VK_SUCCESS && ok;
}

static vx_result pick_device(vp* p, const char* want, vx_error* err) {
    const void* pd = NULL;
    vx_result r = vx_gpu_pick_device((const void*)p->inst, want, can_present, p,
                                     "a queue that computes and presents to this window", &pd, &p->family, err);
    if (r == VX_OK) p->phys = (VkPhysicalDevice)pd;
    return r;
}

static vx_result create_device(vp* p, vx_error* err) {
    const char* exts[] = {VK_KHR_SWAPCHAIN_EXTENSION_NAME};
    const void* dev = NULL;
    vx_result r = vx_gpu_make_device((const void*)p->phys, p->family, exts, 1, &dev, &p->float64, err);
    if (r) return r;
    p->dev = (VkDevice)dev;
    vkGetDeviceQueue(p->dev, p->family, 0, &p->queue);
    VkPhysicalDeviceFeatures have;
    vkGetPhysicalDeviceFeatures(p->phys, &have); /* vx_gpu_make_device enabled it where offered */
    p->storage_write = have.shaderStorageImageWriteWithoutFormat == VK_TRUE;
    VkCommandPoolCreateInfo pci = {.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
                                   .flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT,
                                   .queueFamilyIndex = p->family};
    VP_VK(vkCreateCommandPool(p->dev, &pci, NULL, &p->pool), "vkCreateCommandPool");
    VkCommandBufferAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
                                      .commandPool = p->pool,
                                      .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
                                      .commandBufferCount = 1};
    VP_VK(vkAllocateCommandBuffers(p->dev, &ai, &p->cmd), "vkAllocateCommandBuffers");
    VkFenceCreateInfo fci = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VP_VK(vkCreateFence(p->dev, &fci, NULL, &p->fence), "vkCreateFence");
    VkSemaphoreCreateInfo sci = {.sType = VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    VP_VK(vkCreateSemaphore(p->dev, &sci, NULL, &p->acquired), "vkCreateSemaphore");
    for (int i = 0; i < VX_DISPLAY_SLOTS; i++)
        VP_VK(vkCreateSemaphore(p->dev, &sci, NULL, &p->slot_acquired[i]), "vkCreateSemaphore");
    return VX_OK;
}

static void destroy_swapchain_parts(vp* p) {
    for (uint32_t i = 0; i < VP_MAX_IMAGES; i++) {
        if (p->done[i]) vkDestroySemaphore(p->dev, p->done[i], NULL), p->done[i] = VK_NULL_HANDLE;
        if (p->views[i]) vkDestroyImageView(p->dev, p->views[i], NULL), p->views[i] = VK_NULL_HANDLE;
    }
}

static vx_result create_swapchain(vp* p, vx_error* err) {
    vkDeviceWaitIdle(p->dev);
    p->npend = 0; /* the old swapchain's images (the caller presented them first: vp_stale) */
    destroy_swapchain_parts(p);
    VkSurfaceCapabilitiesKHR caps;
    VP_VK(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(p->phys, p->surface, &caps), "vkGetPhysicalDeviceSurfaceCapabilitiesKHR");
    if (!(caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_DST_BIT))
        return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "the swapchain images cannot be copied to");
    int fw = 0, fh = 0;
    glfwGetFramebufferSize(p->win, &fw, &fh);
    VkExtent2D ext = caps.currentExtent;
    if (ext.width == UINT32_MAX) {
        ext.width = (uint32_t)(fw > 0 ? fw : 1), ext.height = (uint32_t)(fh > 0 ? fh : 1);
        if (ext.width < caps.minImageExtent.width) ext.width = caps.minImageExtent.width;
        if (ext.height < caps.minImageExtent.height) ext.height = caps.minImageExtent.height;
        if (ext.width > caps.maxImageExtent.width) ext.width = caps.maxImageExtent.width;
        if (ext.height > caps.maxImageExtent.height) ext.height = caps.maxImageExtent.height;
    }
    p->dirty = false;
    if (ext.width == 0 || ext.height == 0) { /* minimised: keep the old swapchain until it has a size */
        p->extent = ext;
        return VX_OK;
    }
    uint32_t nf = 0;
    VP_VK(vkGetPhysicalDeviceSurfaceFormatsKHR(p->phys, p->surface, &nf, NULL), "vkGetPhysicalDeviceSurfaceFormatsKHR");
    VkSurfaceFormatKHR fmts[64];
    if (nf > 64) nf = 64;
    if (nf == 0) return vx_fail(err, VX_ERR_GPU, VX_NO_OFFSET, "the surface offers no formats");
    VkResult vr = vkGetPhysicalDeviceSurfaceFormatsKHR(p->phys, p->surface, &nf, fmts);
    if (vr != VK_SUCCESS && vr != VK_INCOMPLETE) return vk_fail(err, vr, "vkGetPhysicalDeviceSurfaceFormatsKHR");
    /* UNORM first: the bytes are already display-encoded (as in the PNG) */
    VkSurfaceFormatKHR fmt = fmts[0];
    bool found = false;
    VkFormat prefer[] = {VK_FORMAT_B8G8R8A8_UNORM, VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_B8G8R8A8_SRGB,
                         VK_FORMAT_R8G8B8A8_SRGB};
    for (size_t k = 0; k < 4 && !found; k++)
        for (uint32_t i = 0; i < nf && !found; i++)
            if (fmts[i].format == prefer[k]) fmt = fmts[i], found = true;
    if (!found) return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "the surface offers no 8-bit RGBA/BGRA format");
    uint32_t npm = 0;
    VkPresentModeKHR modes[16];
    VP_VK(vkGetPhysicalDeviceSurfacePresentModesKHR(p->phys, p->surface, &npm, NULL), "vkGetPhysicalDeviceSurfacePresentModesKHR");
    if (npm > 16) npm = 16;
    vr = vkGetPhysicalDeviceSurfacePresentModesKHR(p->phys, p->surface, &npm, modes);
    if (vr != VK_SUCCESS && vr != VK_INCOMPLETE) return vk_fail(err, vr, "vkGetPhysicalDeviceSurfacePresentModesKHR");
    VkPresentModeKHR mode = VK_PRESENT_MODE_FIFO_KHR;
    if (!p->vsync) {
        for (uint32_t i = 0; i < npm; i++)
            if (modes[i] == VK_PRESENT_MODE_IMMEDIATE_KHR) mode = modes[i];
        for (uint32_t i = 0; i < npm; i++)
            if (modes[i] == VK_PRESENT_MODE_MAILBOX_KHR) mode = modes[i];
    }
    /* a batch's images are acquired before the first of them is presented */
    uint32_t count = caps.minImageCount + (p->batch > 1 ? p->batch : 1);
    if (caps.maxImageCount && count > caps.maxImageCount) count = caps.maxImageCount;
    if (count > VP_MAX_IMAGES) count = VP_MAX_IMAGES;
    VkCompositeAlphaFlagBitsKHR alpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
    VkCompositeAlphaFlagBitsKHR alphas[] = {VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR, VK_COMPOSITE_ALPHA_INHERIT_BIT_KHR,
                                            VK_COMPOSITE_ALPHA_PRE_MULTIPLIED_BIT_KHR,
                                            VK_COMPOSITE_ALPHA_POST_MULTIPLIED_BIT_KHR};
    for (int k = 3; k >= 0; k--)
        if (caps.supportedCompositeAlpha & alphas[k]) alpha = alphas[k];
    /* storage usage where the surface and the format allow it: frames in flight write the image itself */
    VkFormatProperties fp;
    vkGetPhysicalDeviceFormatProperties(p->phys, fmt.format, &fp);
    p->storage = p->storage_write && (caps.supportedUsageFlags & VK_IMAGE_USAGE_STORAGE_BIT) &&
                 (fp.optimalTilingFeatures & VK_FORMAT_FEATURE_STORAGE_IMAGE_BIT);
    p->colour = p->storage && (caps.supportedUsageFlags & VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT) &&
                (fp.optimalTilingFeatures & VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BLEND_BIT);
    VkSwapchainKHR old = p->sc;
    VkSwapchainCreateInfoKHR ci = {.sType = VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR,
                                   .surface = p->surface,
                                   .minImageCount = count,
                                   .imageFormat = fmt.format,
                                   .imageColorSpace = fmt.colorSpace,
                                   .imageExtent = ext,
                                   .imageArrayLayers = 1,
                                   .imageUsage = VK_IMAGE_USAGE_TRANSFER_DST_BIT | (p->storage ? VK_IMAGE_USAGE_STORAGE_BIT : 0) |
                                                 (p->colour ? VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT : 0),
                                   .imageSharingMode = VK_SHARING_MODE_EXCLUSIVE,
                                   .preTransform = caps.currentTransform,
                                   .compositeAlpha = alpha,
                                   .presentMode = mode,
                                   .clipped = VK_TRUE,
                                   .oldSwapchain = old};
    VP_VK(vkCreateSwapchainKHR(p->dev, &ci, NULL, &p->sc), "vkCreateSwapchainKHR");
    if (old) vkDestroySwapchainKHR(p->dev, old, NULL);
    p->format = fmt.format;
    p->extent = ext;
    uint32_t ni = 0;
    VP_VK(vkGetSwapchainImagesKHR(p->dev, p->sc, &ni, NULL), "vkGetSwapchainImagesKHR");
    if (ni > VP_MAX_IMAGES) return vx_fail(err, VX_ERR_GPU, VX_NO_OFFSET, "swapchain has %u images", ni);
    VP_VK(vkGetSwapchainImagesKHR(p->dev, p->sc, &ni, p->images), "vkGetSwapchainImagesKHR");
    p->image_count = ni;
    VkSemaphoreCreateInfo sci = {.sType = VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    /* one per image: a present may still wait on its semaphore when the next frame signals */
    for (uint32_t i = 0; i < ni; i++) VP_VK(vkCreateSemaphore(p->dev, &sci, NULL, &p->done[i]), "vkCreateSemaphore");
    for (uint32_t i = 0; p->storage && i < ni; i++) {
        VkImageViewCreateInfo vi = {.sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO,
                                    .image = p->images[i],
                                    .viewType = VK_IMAGE_VIEW_TYPE_2D,
                                    .format = fmt.format,
                                    .subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1}};
        VP_VK(vkCreateImageView(p->dev, &vi, NULL, &p->views[i]), "vkCreateImageView");
    }
    return VX_OK;
}

vx_result vp_create(const vp_desc* desc_in, vp** out, vx_error* err) {
    vp_desc d = desc_in ? *desc_in : (vp_desc){0};
    if (!d.width) d.width = 1280;
    if (!d.height) d.height = 800;
    vp* p = calloc(1, sizeof *p);
    if (!p) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    p->vsync = d.vsync;
    p->batch = d.batch;
    vx_result r = VX_OK;
    if (!glfwInit()) {
        const char* why = NULL;
        glfwGetError(&why);
        r = vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "cannot open a window: %s", why ? why : "glfwInit failed");
        goto fail;
    }
    p->glfw_init = true;
    if (!glfwVulkanSupported()) {
        r = vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "GLFW finds no Vulkan loader with window-system support");
        goto fail;
    }
    uint32_t next = 0;
    const char** gexts = glfwGetRequiredInstanceExtensions(&next);
    if (!gexts || next > 15) {
        r = vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "Vulkan cannot present to this window system");
        goto fail;
    }
    const char* exts[17];
    memcpy(exts, gexts, next * sizeof *exts);
    p->valid.errors = d.validate ? d.validation_errors : NULL;
    p->valid.logger = d.logger;
    /* chained into the instance info as well, so creating and destroying the
     * instance are validated too (the layer provides the extension) */
    VkDebugUtilsMessengerCreateInfoEXT dbg = {
        .sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT,
        .messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT,
        .messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT,
        .pfnUserCallback = debug_cb,
        .pUserData = &p->valid};
    if (d.validate) exts[next++] = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
    const char* layers[1] = {"VK_LAYER_KHRONOS_validation"};
    VkApplicationInfo app = {.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO,
                             .pApplicationName = "svo_view",
                             .pEngineName = "voxkit",
                             .apiVersion = VK_API_VERSION_1_1};
    VkInstanceCreateInfo ici = {.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO,
                                .pNext = d.validate ? &dbg : NULL,
                                .pApplicationInfo = &app,
                                .enabledLayerCount = d.validate ? 1 : 0,
                                .ppEnabledLayerNames = layers,
                                .enabledExtensionCount = next,
                                .ppEnabledExtensionNames = exts};
    VkResult vr = vkCreateInstance(&ici, NULL, &p->inst);
    if (vr != VK_SUCCESS) {
        r = vk_fail(err, vr, d.validate ? "vkCreateInstance (with VK_LAYER_KHRONOS_validation)" : "vkCreateInstance");
        goto fail;
    }
    if (d.validate) {
        PFN_vkCreateDebugUtilsMessengerEXT create =
            (PFN_vkCreateDebugUtilsMessengerEXT)vkGetInstanceProcAddr(p->inst, "vkCreateDebugUtilsMessengerEXT");
        vr = create ? create(p->inst, &dbg, NULL, &p->messenger) : VK_ERROR_EXTENSION_NOT_PRESENT;
        if (vr != VK_SUCCESS) {
            r = vk_fail(err, vr, "vkCreateDebugUtilsMessengerEXT");
            goto fail;
        }
    }
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    glfwWindowHint(GLFW_VISIBLE, d.hidden ? GLFW_FALSE : GLFW_TRUE);
    glfwWindowHint(GLFW_SCALE_TO_MONITOR, GLFW_TRUE);
    p->win = glfwCreateWindow((int)d.width, (int)d.height, d.title ? d.title : "svo_view", NULL, NULL);
    if (!p->win) {
        const char* why = NULL;
        glfwGetError(&why);
        r = vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "cannot create a window: %s", why ? why : "unknown");
        goto fail;
    }
    vr = glfwCreateWindowSurface(p->inst, p->win, NULL, &p->surface);
    if (vr != VK_SUCCESS) {
        r = vk_fail(err, vr, "glfwCreateWindowSurface");
        goto fail;
    }
    if ((r = pick_device(p, d.device, err)) || (r = create_device(p, err)) || (r = create_swapchain(p, err))) goto fail;
    *out = p;
    return VX_OK;
fail:
    vp_destroy(p);
    return r;
}

void vp_destroy(vp* p) {
    if (!p) return;
    if (p->dev) {
        vkDeviceWaitIdle(p->dev);
        destroy_swapchain_parts(p);
        if (p->staging) vkDestroyBuffer(p->dev, p->staging, NULL);
        if (p->staging_mem) vkFreeMemory(p->dev, p->staging_mem, NULL);
        if (p->sc) vkDestroySwapchainKHR(p->dev, p->sc, NULL);
        if (p->acquired) vkDestroySemaphore(p->dev, p->acquired, NULL);
        for (int i = 0; i < VX_DISPLAY_SLOTS; i++)
            if (p->slot_acquired[i]) vkDestroySemaphore(p->dev, p->slot_acquired[i], NULL);
        if (p->fence) vkDestroyFence(p->dev, p->fence, NULL);
        if (p->pool) vkDestroyCommandPool(p->dev, p->pool, NULL);
        vkDestroyDevice(p->dev, NULL);
    }
    if (p->surface) vkDestroySurfaceKHR(p->inst, p->surface, NULL);
    if (p->win) glfwDestroyWindow(p->win);
    if (p->messenger) {
        PFN_vkDestroyDebugUtilsMessengerEXT destroy =
            (PFN_vkDestroyDebugUtilsMessengerEXT)vkGetInstanceProcAddr(p->inst, "vkDestroyDebugUtilsMessengerEXT");
        if (destroy) destroy(p->inst, p->messenger, NULL);
    }
    if (p->inst) vkDestroyInstance(p->inst, NULL);
    if (p->glfw_init) glfwTerminate();
    free(p);
}

GLFWwindow* vp_window(vp* p) { return p->win; }

void vp_external(vp* p, vx_gpu_desc* gd) {
    gd->external.instance = p->inst;
    gd->external.physical_device = p->phys;
    gd->external.device = p->dev;
    gd->external.queue = p->queue;
    gd->external.queue_family = p->family;
    gd->external.float64 = p->float64;
    gd->external.storage_write = p->storage_write;
}

void vp_frame_size(vp* p, uint32_t* w, uint32_t* h) {
    check_resize(p);
    if (p->dirty) {
        vx_error e;
        create_swapchain(p, &e); /* a failure shows as a zero size and is retried */
    }
    *w = p->extent.width;
    *h = p->extent.height;
}

bool vp_storage(const vp* p) { return p->storage; }
bool vp_colour(const vp* p) { return p->colour; }
int vp_format(const vp* p) { return (int)p->format; }

bool vp_frame_bgra(const vp* p) { return p->format == VK_FORMAT_B8G8R8A8_UNORM || p->format == VK_FORMAT_B8G8R8A8_SRGB; }

void vp_set_vsync(vp* p, bool vsync) {
    if (p->vsync != vsync) p->vsync = vsync, p->dirty = true;
}
bool vp_vsync(const vp* p) { return p->vsync; }

static vx_result ensure_staging(vp* p, VkDeviceSize size, vx_error* err) {
    if (p->staging && p->staging_size >= size) return VX_OK;
    if (p->staging) vkDestroyBuffer(p->dev, p->staging, NULL), p->staging = VK_NULL_HANDLE;
    if (p->staging_mem) vkFreeMemory(p->dev, p->staging_mem, NULL), p->staging_mem = VK_NULL_HANDLE;
    VkBufferCreateInfo bi = {.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO,
                             .size = size,
                             .usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                             .sharingMode = VK_SHARING_MODE_EXCLUSIVE};
    VP_VK(vkCreateBuffer(p->dev, &bi, NULL, &p->staging), "vkCreateBuffer");
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(p->dev, p->staging, &req);
    VkPhysicalDeviceMemoryProperties mp;
    vkGetPhysicalDeviceMemoryProperties(p->phys, &mp);
    uint32_t type = UINT32_MAX;
    VkMemoryPropertyFlags want = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    for (uint32_t i = 0; i < mp.memoryTypeCount && type == UINT32_MAX; i++)
        if ((req.memoryTypeBits & (1u << i)) && (mp.memoryTypes[i].propertyFlags & want) == want) type = i;
    if (type == UINT32_MAX) return vx_fail(err, VX_ERR_GPU, VX_NO_OFFSET, "no host-visible coherent memory");
    VkMemoryAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
                               .allocationSize = req.size,
                               .memoryTypeIndex = type};
    VP_VK(vkAllocateMemory(p->dev, &ai, NULL, &p->staging_mem), "vkAllocateMemory");
    VP_VK(vkBindBufferMemory(p->dev, p->staging, p->staging_mem, 0), "vkBindBufferMemory");
    VP_VK(vkMapMemory(p->dev, p->staging_mem, 0, VK_WHOLE_SIZE, 0, &p->staging_map), "vkMapMemory");
    p->staging_size = size;
    return VX_OK;
}

/* Queues the present of swapchain image idx once done[idx] is signalled; the present's own result (for
 * present_status). */
static VkResult queue_present(vp* p, uint32_t idx) {
    VkPresentInfoKHR pi = {.sType = VK_STRUCTURE_TYPE_PRESENT_INFO_KHR,
                           .waitSemaphoreCount = 1,
                           .pWaitSemaphores = &p->done[idx],
                           .swapchainCount = 1,
                           .pSwapchains = &p->sc,
                           .pImageIndices = &idx};
    return vkQueuePresentKHR(p->queue, &pi);
}

/* Ends the frame's command buffer, submits it (waiting on the acquire
 * semaphore, signalling done[idx]), queues the present of image idx and waits
 * for the submission: the staging buffer, command buffer and acquire
 * semaphore are reused next frame. The present's own result goes to *vr for
 * present_status, after the caller has read back what it needs. */
static vx_result submit_present(vp* p, uint32_t idx, VkResult* vr_out, vx_error* err) {
    VP_VK(vkEndCommandBuffer(p->cmd), "vkEndCommandBuffer");
    VkPipelineStageFlags wait_stage = VK_PIPELINE_STAGE_TRANSFER_BIT;
    VkSubmitInfo si = {.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO,
                       .waitSemaphoreCount = 1,
                       .pWaitSemaphores = &p->acquired,
                       .pWaitDstStageMask = &wait_stage,
                       .commandBufferCount = 1,
                       .pCommandBuffers = &p->cmd,
                       .signalSemaphoreCount = 1,
                       .pSignalSemaphores = &p->done[idx]};
    VP_VK(vkResetFences(p->dev, 1, &p->fence), "vkResetFences");
    VP_VK(vkQueueSubmit(p->queue, 1, &si, p->fence), "vkQueueSubmit");
    *vr_out = queue_present(p, idx);
    VkResult fr = vkWaitForFences(p->dev, 1, &p->fence, VK_TRUE, UINT64_MAX);
    if (fr != VK_SUCCESS) return vk_fail(err, fr, "vkWaitForFences");
    return VX_OK;
}

/* An out-of-date or suboptimal swapchain is made again before the next frame. */
static vx_result present_status(vp* p, VkResult vr, vx_error* err) {
    if (vr == VK_ERROR_OUT_OF_DATE_KHR || vr == VK_SUBOPTIMAL_KHR) p->dirty = true;
    else if (vr != VK_SUCCESS) return vk_fail(err, vr, "vkQueuePresentKHR");
    return VX_OK;
}

/* The start of a waited frame: the swapchain made again when the window
 * changed, the next image acquired (signalling p->acquired) and the command
 * buffer begun. *idx UINT32_MAX: no image this time (minimised, or out of
 * date: the next frame renders at the new size), nothing begun. */
static vx_result begin_present(vp* p, uint32_t* idx, vx_error* err) {
    *idx = UINT32_MAX;
    check_resize(p);
    if (p->dirty) {
        vx_result r = create_swapchain(p, err);
        if (r) return r;
    }
    if (!p->sc || !p->extent.width || !p->extent.height) return VX_OK; /* minimised */
    uint32_t i;
    VkResult vr = vkAcquireNextImageKHR(p->dev, p->sc, UINT64_MAX, p->acquired, VK_NULL_HANDLE, &i);
    if (vr == VK_ERROR_OUT_OF_DATE_KHR) {
        p->dirty = true;
        return VX_OK;
    }
    if (vr != VK_SUCCESS && vr != VK_SUBOPTIMAL_KHR) return vk_fail(err, vr, "vkAcquireNextImageKHR");
    VP_VK(vkResetCommandBuffer(p->cmd, 0), "vkResetCommandBuffer");
    VkCommandBufferBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
                                   .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};
    VP_VK(vkBeginCommandBuffer(p->cmd, &bi), "vkBeginCommandBuffer");
    *idx = i;
    return VX_OK;
}

vx_result vp_present(vp* p, const uint8_t* px, uint32_t w, uint32_t h, vx_error* err) {
    vx_result r = ensure_staging(p, (VkDeviceSize)w * h * 4, err);
    if (r) return r;
    memcpy(p->staging_map, px, (size_t)w * h * 4);
    uint32_t idx;
    if ((r = begin_present(p, &idx, err)) || idx == UINT32_MAX) return r;
    vx_display_copy_to_image(p->cmd, (uint64_t)(uintptr_t)p->staging, w, h, (uint64_t)(uintptr_t)p->images[idx],
                             p->extent.width, p->extent.height, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR);
    VkResult vr;
    if ((r = submit_present(p, idx, &vr, err))) return r;
    return present_status(p, vr, err);
}

/* The GPU path: the frame renderer's image, converted and overlaid by
 * vx_display in this submission, copied to the acquired swapchain image
 * (and, for a grab, to the staging buffer, read back after the wait). */
vx_result vp_present_display(vp* p, vx_display* disp, const vx_display_desc* desc, uint8_t* grab, vx_error* err) {
    uint32_t w = desc->width, h = desc->height;
    vx_result r = grab ? ensure_staging(p, (VkDeviceSize)w * h * 4, err) : VX_OK;
    uint32_t idx;
    if (r || (r = begin_present(p, &idx, err)) || idx == UINT32_MAX) return r;
    uint64_t bytes = 0;
    /* a failed conversion still presents the acquired image (its semaphore is waited for): cleared */
    vx_result failed = vx_display_record(disp, p->cmd, desc, &bytes, err);
    if (failed) {
        VP_VK(vkEndCommandBuffer(p->cmd), "vkEndCommandBuffer");
        VP_VK(vkResetCommandBuffer(p->cmd, 0), "vkResetCommandBuffer");
        VkCommandBufferBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
                                       .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};
        VP_VK(vkBeginCommandBuffer(p->cmd, &bi), "vkBeginCommandBuffer");
        bytes = 0, grab = NULL;
    }
    if (grab) {
        VkBufferCopy c = {.size = (VkDeviceSize)w * h * 4};
        vkCmdCopyBuffer(p->cmd, (VkBuffer)(uintptr_t)bytes, p->staging, 1, &c);
        VkMemoryBarrier hb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
                              .srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
                              .dstAccessMask = VK_ACCESS_HOST_READ_BIT};
        vkCmdPipelineBarrier(p->cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &hb, 0, NULL, 0, NULL);
    }
    vx_display_copy_to_image(p->cmd, bytes, w, h, (uint64_t)(uintptr_t)p->images[idx], p->extent.width, p->extent.height,
                             VK_IMAGE_LAYOUT_PRESENT_SRC_KHR);
    VkResult vr;
    vx_result sr = submit_present(p, idx, &vr, err);
    if (sr) return sr;
    if (failed) return failed;
    if (grab) memcpy(grab, p->staging_map, (size_t)w * h * 4);
    return present_status(p, vr, err);
}

/* ---- frames in flight ----------------------------------------------------------------- */

vx_result vp_acquire(vp* p, uint32_t slot, vp_image* out, vx_error* err) {
    memset(out, 0, sizeof *out);
    p->frame_acquired = false;
    if (slot >= VX_DISPLAY_SLOTS) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "slot %u", slot);
    check_resize(p);
    if (p->dirty) {
        vx_result r = create_swapchain(p, err); /* waits for the device: no frame is in flight after it */
        if (r) return r;
    }
    if (!p->sc || !p->extent.width || !p->extent.height) return VX_OK; /* minimised */
    uint32_t idx;
    /* the slot's semaphore: the submission that waited on it last (this
     * slot's previous frame) has finished, vx_display_frame_begin saw to it */
    VkResult vr = vkAcquireNextImageKHR(p->dev, p->sc, UINT64_MAX, p->slot_acquired[slot], VK_NULL_HANDLE, &idx);
    if (vr == VK_ERROR_OUT_OF_DATE_KHR) {
        p->dirty = true;
        return VX_OK;
    }
    if (vr != VK_SUCCESS && vr != VK_SUBOPTIMAL_KHR) return vk_fail(err, vr, "vkAcquireNextImageKHR");
    if (vr == VK_SUBOPTIMAL_KHR) p->dirty = true;
    p->frame_image = idx, p->frame_acquired = true;
    *out = (vp_image){.image = (uint64_t)(uintptr_t)p->images[idx], .width = p->extent.width, .height = p->extent.height,
                      .acquired = (uint64_t)(uintptr_t)p->slot_acquired[slot],
                      .rendered = (uint64_t)(uintptr_t)p->done[idx], .layout = VK_IMAGE_LAYOUT_PRESENT_SRC_KHR,
                      .view = (uint64_t)(uintptr_t)p->views[idx]};
    return VX_OK;
}

static vx_result present_one(vp* p, uint32_t idx, vx_error* err) {
    return present_status(p, queue_present(p, idx), err);
}

/* A frame in flight's present: counted, and its order checked. */
static vx_result present_frame(vp* p, uint32_t idx, uint64_t frame, vx_error* err) {
    if (p->presented && frame <= p->last_presented) p->out_of_order++;
    p->presented++, p->last_presented = frame;
    return present_one(p, idx, err);
}

void vp_get_present_counts(const vp* p, vp_present_counts* out) {
    *out = (vp_present_counts){.presented = p->presented, .out_of_order = p->out_of_order, .queued = p->npend};
}

vx_result vp_present_acquired(vp* p, vx_error* err) {
    if (!p->frame_acquired) return VX_OK;
    p->frame_acquired = false;
    if (p->batch <= 1) return present_frame(p, p->frame_image, p->frame_number, err);
    if (p->npend == VP_MAX_IMAGES) return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "%d presents queued", VP_MAX_IMAGES);
    p->pend_image[p->npend] = p->frame_image, p->pend_frame[p->npend] = p->frame_number;
    p->npend++;
    return VX_OK;
}

void vp_set_frame_number(vp* p, uint64_t frame) { p->frame_number = frame; }

vx_result vp_present_submitted(vp* p, uint64_t submitted, vx_error* err) {
    uint32_t k = 0;
    vx_result r = VX_OK;
    for (; k < p->npend && p->pend_frame[k] < submitted; k++) {
        vx_result rk = present_frame(p, p->pend_image[k], p->pend_frame[k], err);
        if (!r) r = rk;
    }
    memmove(p->pend_image, p->pend_image + k, (p->npend - k) * sizeof p->pend_image[0]);
    memmove(p->pend_frame, p->pend_frame + k, (p->npend - k) * sizeof p->pend_frame[0]);
    p->npend -= k;
    return r;
}

bool vp_stale(vp* p) {
    check_resize(p);
    return p->dirty;
}
