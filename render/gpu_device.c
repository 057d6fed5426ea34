/* render/gpu_device.c - the one place that creates the Vulkan instance, picks
 * the physical device and creates the logical device and its compute queue. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/render_internal.h"
#include "render/spirv_opt.h"

const char* vx__vk_str(VkResult r) {
    switch (r) {
#define C(x) case x: return #x;
        C(VK_SUCCESS) C(VK_NOT_READY) C(VK_TIMEOUT) C(VK_INCOMPLETE) C(VK_ERROR_OUT_OF_HOST_MEMORY)
        C(VK_ERROR_OUT_OF_DEVICE_MEMORY) C(VK_ERROR_INITIALIZATION_FAILED) C(VK_ERROR_DEVICE_LOST)
        C(VK_ERROR_MEMORY_MAP_FAILED) C(VK_ERROR_LAYER_NOT_PRESENT) C(VK_ERROR_EXTENSION_NOT_PRESENT)
        C(VK_ERROR_FEATURE_NOT_PRESENT) C(VK_ERROR_INCOMPATIBLE_DRIVER) C(VK_ERROR_TOO_MANY_OBJECTS)
        C(VK_ERROR_FORMAT_NOT_SUPPORTED) C(VK_ERROR_FRAGMENTED_POOL) C(VK_ERROR_UNKNOWN)
#undef C
    default: return "VkResult(unknown)";
    }
}

vx_result vx__vk_fail(vx_error* err, VkResult r, const char* what) {
    return vx_fail(err, VX_ERR_GPU, VX_NO_OFFSET, "%s failed: %s (%d)", what, vx__vk_str(r), (int)r);
}

static VKAPI_ATTR VkBool32 VKAPI_CALL debug_cb(VkDebugUtilsMessageSeverityFlagBitsEXT sev,
                                               VkDebugUtilsMessageTypeFlagsEXT type,
                                               const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
    (void)type;
    vx_gpu* g = user;
    if (sev & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
        g->validation_errors++;
        vx_log(g->logger, VX_LOG_WARN, "gpu.validation", "%s", data && data->pMessage ? data->pMessage : "?");
    } else if (sev & VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
        vx_log(g->logger, VX_LOG_INFO, "gpu.validation_warning", "%s",
               data && data->pMessage ? data->pMessage : "?");
    }
    return VK_FALSE;
}

static bool layer_available(const char* name) {
    uint32_t n = 0;
    if (vkEnumerateInstanceLayerProperties(&n, NULL) != VK_SUCCESS || n == 0) return false;
    VkLayerProperties* p = calloc(n, sizeof *p);
    if (!p) return false;
    bool found = false;
    if (vkEnumerateInstanceLayerProperties(&n, p) == VK_SUCCESS)
        for (uint32_t i = 0; i < n; i++)
            if (strcmp(p[i].layerName, name) == 0) found = true;
    free(p);
    return found;
}

static bool instance_ext_available(const char* name) {
    uint32_t n = 0;
    if (vkEnumerateInstanceExtensionProperties(NULL, &n, NULL) != VK_SUCCESS || n == 0) return false;
    VkExtensionProperties* p = calloc(n, sizeof *p);
    if (!p) return false;
    bool found = false;
    if (vkEnumerateInstanceExtensionProperties(NULL, &n, p) == VK_SUCCESS)
        for (uint32_t i = 0; i < n; i++)
            if (strcmp(p[i].extensionName, name) == 0) found = true;
    free(p);
    return found;
}

static const char* type_name(VkPhysicalDeviceType t) {
    switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "cpu";
    default: return "other";
    }
}

static int type_rank(VkPhysicalDeviceType t) {
    switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return 3;
    default: return 4;
    }
}

/* A family with a compute queue (compute queues also transfer) that
 * family_ok accepts, preferring one with timestamps. */
static bool pick_family(VkPhysicalDevice pd, bool (*family_ok)(void*, const void*, uint32_t), void* user,
                        uint32_t* out) {
    uint32_t n = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, NULL);
    if (n == 0 || n > 64) return false;
    VkQueueFamilyProperties q[64];
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, q);
    int best = -1;
    for (uint32_t i = 0; i < n; i++) {
        if (!(q[i].queueFlags & VK_QUEUE_COMPUTE_BIT)) continue;
        if (family_ok && !family_ok(user, (const void*)pd, i)) continue;
        if (best < 0 || (q[i].timestampValidBits && !q[best].timestampValidBits)) best = (int)i;
    }
    if (best < 0) return false;
    *out = (uint32_t)best;
    return true;
}

vx_result vx_gpu_pick_device(const void* instance, const char* want,
                             bool (*family_ok)(void* user, const void* physical_device, uint32_t family), void* user,
                             const char* needs, const void** physical_device, uint32_t* family, vx_error* err) {
    VkInstance inst = (VkInstance)instance;
    uint32_t n = 0;
    VX__VK(vkEnumeratePhysicalDevices(inst, &n, NULL), "vkEnumeratePhysicalDevices");
    if (n == 0) return vx_fail(err, VX_ERR_GPU, VX_NO_OFFSET, "no Vulkan device found");
    if (n > 32) n = 32;
    VkPhysicalDevice pds[32];
    VkResult r = vkEnumeratePhysicalDevices(inst, &n, pds);
    if (r != VK_SUCCESS && r != VK_INCOMPLETE) return vx__vk_fail(err, r, "vkEnumeratePhysicalDevices");
    bool named = want && *want;
    char* end = NULL;
    long idx = named ? strtol(want, &end, 10) : -1;
    bool by_index = named && end && *end == 0;
    if (named && !strncmp(want, "gpu:", 4)) {
        /* "gpu:K": the (K mod G)-th GPU, counted as vx_gpu_list_devices's callers count them */
        long k = strtol(want + 4, &end, 10);
        if (end == want + 4 || *end || k < 0)
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "bad device '%s' (gpu:K, K >= 0)", want);
        uint32_t gpus[32], ng = 0;
        for (uint32_t i = 0; i < n; i++) {
            VkPhysicalDeviceProperties p;
            vkGetPhysicalDeviceProperties(pds[i], &p);
            if (type_rank(p.deviceType) <= 2) gpus[ng++] = i;
        }
        named = ng > 0; /* no GPU: the default pick */
        by_index = named;
        if (named) idx = (long)gpus[(unsigned long)k % ng];
    }
    if (by_index && (idx < 0 || (uint32_t)idx >= n))
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "device %ld does not exist (%u devices)", idx, n);
    int pick = -1, best_rank = 99;
    bool matched = false;
    uint32_t fam = 0;
    for (uint32_t i = 0; i < n; i++) {
        VkPhysicalDeviceProperties p;
        vkGetPhysicalDeviceProperties(pds[i], &p);
        if (by_index ? (long)i != idx : (named && !strstr(p.deviceName, want))) continue;
        matched = true;
        if (!pick_family(pds[i], family_ok, user, &fam)) continue;
        int rank = type_rank(p.deviceType);
        if (rank < best_rank) best_rank = rank, pick = (int)i;
        if (named) break; /* the first device the name or index selects */
    }
    if (!matched) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "no Vulkan device named like '%s'", want);
    if (pick < 0)
        return vx_fail(err, VX_ERR_GPU, VX_NO_OFFSET, "no Vulkan device%s%s has %s", named ? " matching " : "",
                       named ? want : "", needs ? needs : "a compute queue");
    pick_family(pds[pick], family_ok, user, family);
    *physical_device = (const void*)pds[pick];
    return VX_OK;
}

static vx_result create_instance(vx_gpu* g, bool validate, vx_error* err) {
    const char* layers[1];
    uint32_t layer_count = 0;
    const char* exts[2];
    uint32_t ext_count = 0;
    /* Debug utils (object names, labels) asked for without enumerating the instance's extensions first, unless
     * validating (the messenger needs it): each enumeration makes the loader load and unload the drivers
     * (lavapipe: 0.23 -> 0.20 s to the device; bake5, docs/PERFORMANCE.md); where the instance refuses it, it is
     * made again without. */
    bool probe = validate;
    bool debug_utils = !probe || instance_ext_available(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    if (validate) {
        if (!layer_available("VK_LAYER_KHRONOS_validation"))
            return vx_fail(err, VX_ERR_GPU, VX_NO_OFFSET,
                           "validation requested but VK_LAYER_KHRONOS_validation is not installed");
        layers[layer_count++] = "VK_LAYER_KHRONOS_validation";
    }
    if (debug_utils) exts[ext_count++] = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;

    VkApplicationInfo app = {.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO,
                             .pApplicationName = "voxkit",
                             .pEngineName = "voxkit",
                             .apiVersion = VK_API_VERSION_1_1};
    /* Chained into the instance create info so that vkCreateInstance and
     * vkDestroyInstance themselves are covered by validation (cube.c). */
    VkDebugUtilsMessengerCreateInfoEXT dbg = {
        .sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT,
        .messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT,
        .messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT,
        .pfnUserCallback = debug_cb,
        .pUserData = g};
    VkInstanceCreateInfo ci = {.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO,
                               .pNext = (validate && debug_utils) ? &dbg : NULL,
                               .pApplicationInfo = &app,
                               .enabledLayerCount = layer_count,
                               .ppEnabledLayerNames = layers,
                               .enabledExtensionCount = ext_count,
                               .ppEnabledExtensionNames = exts};
    VkResult vr = vkCreateInstance(&ci, NULL, &g->instance);
    if (vr == VK_ERROR_EXTENSION_NOT_PRESENT && !probe) {
        debug_utils = false;
        ci.enabledExtensionCount = 0;
        vr = vkCreateInstance(&ci, NULL, &g->instance);
    }
    if (vr != VK_SUCCESS) return vx__vk_fail(err, vr, "vkCreateInstance");
    if (debug_utils) {
        g->set_name = (PFN_vkSetDebugUtilsObjectNameEXT)vkGetInstanceProcAddr(g->instance, "vkSetDebugUtilsObjectNameEXT");
        g->begin_label =
            (PFN_vkCmdBeginDebugUtilsLabelEXT)vkGetInstanceProcAddr(g->instance, "vkCmdBeginDebugUtilsLabelEXT");
        g->end_label = (PFN_vkCmdEndDebugUtilsLabelEXT)vkGetInstanceProcAddr(g->instance, "vkCmdEndDebugUtilsLabelEXT");
    }
    if (validate && debug_utils) {
        PFN_vkCreateDebugUtilsMessengerEXT create =
            (PFN_vkCreateDebugUtilsMessengerEXT)vkGetInstanceProcAddr(g->instance, "vkCreateDebugUtilsMessengerEXT");
        if (create) VX__VK(create(g->instance, &dbg, NULL, &g->messenger), "vkCreateDebugUtilsMessengerEXT");
    }
    return VX_OK;
}

static vx_result select_device(vx_gpu* g, const char* want, vx_error* err) {
    const void* pd = NULL;
    vx_result r = vx_gpu_pick_device((const void*)g->instance, want, NULL, NULL, NULL, &pd, &g->queue_family, err);
    if (r == VX_OK) g->phys = (VkPhysicalDevice)pd;
    return r;
}

vx_result vx_gpu_make_device(const void* physical_device, uint32_t family, const char* const* extensions,
                             uint32_t extension_count, const void** device, bool* float64, vx_error* err) {
    VkPhysicalDevice pd = (VkPhysicalDevice)physical_device;
    /* float64 only serves the precise trace variant (deep models); scenes
     * that need it are refused at load on devices without it */
    VkPhysicalDeviceFeatures have, want = {0};
    vkGetPhysicalDeviceFeatures(pd, &have);
    want.shaderFloat64 = have.shaderFloat64;
    /* vx_display's conversion into a B,G,R,A image (render/display.h): a storage image without a format */
    want.shaderStorageImageWriteWithoutFormat = have.shaderStorageImageWriteWithoutFormat;
    float prio = 1.0f;
    VkDeviceQueueCreateInfo qci = {.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO,
                                   .queueFamilyIndex = family,
                                   .queueCount = 1,
                                   .pQueuePriorities = &prio};
    /* shader statistics (VX_GPU_SHADER_STATS=1, gpu_pipeline.c): the
     * extension's feature is enabled with the extension */
    VkPhysicalDevicePipelineExecutablePropertiesFeaturesKHR pep = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PIPELINE_EXECUTABLE_PROPERTIES_FEATURES_KHR,
        .pipelineExecutableInfo = VK_TRUE};
    bool stats = false;
    for (uint32_t i = 0; i < extension_count; i++)
        stats |= strcmp(extensions[i], VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME) == 0;
    VkDeviceCreateInfo dci = {.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO,
                              .pNext = stats ? &pep : NULL,
                              .queueCreateInfoCount = 1,
                              .pQueueCreateInfos = &qci,
                              .enabledExtensionCount = extension_count,
                              .ppEnabledExtensionNames = extensions,
                              .pEnabledFeatures = &want};
    VkDevice dev = VK_NULL_HANDLE;
    VX__VK(vkCreateDevice(pd, &dci, NULL, &dev), "vkCreateDevice");
    *device = (const void*)dev;
    if (float64) *float64 = have.shaderFloat64 == VK_TRUE;
    return VX_OK;
}

/* True when VX_GPU_SHADER_STATS=1 and the device has
 * VK_KHR_pipeline_executable_properties: the device is then created with it,
 * and gpu_pipeline.c logs each pipeline's statistics (the same test there). */
bool vx__gpu_shader_stats_wanted(VkPhysicalDevice pd) {
    const char* env = getenv("VX_GPU_SHADER_STATS");
    if (!env || strcmp(env, "1") != 0) return false;
    uint32_t n = 0;
    if (vkEnumerateDeviceExtensionProperties(pd, NULL, &n, NULL) != VK_SUCCESS || n == 0) return false;
    VkExtensionProperties* p = calloc(n, sizeof *p);
    if (!p) return false;
    bool found = false;
    if (vkEnumerateDeviceExtensionProperties(pd, NULL, &n, p) == VK_SUCCESS)
        for (uint32_t i = 0; i < n; i++)
            if (strcmp(p[i].extensionName, VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME) == 0) found = true;
    free(p);
    if (!found) return false;
    VkPhysicalDevicePipelineExecutablePropertiesFeaturesKHR pep = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PIPELINE_EXECUTABLE_PROPERTIES_FEATURES_KHR};
    VkPhysicalDeviceFeatures2 f2 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, .pNext = &pep};
    vkGetPhysicalDeviceFeatures2(pd, &f2);
    return pep.pipelineExecutableInfo == VK_TRUE;
}

static vx_result create_device(vx_gpu* g, vx_error* err) {
    const void* dev = NULL;
    const char* stats_ext = VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME;
    bool stats = vx__gpu_shader_stats_wanted(g->phys);
    vx_result r = vx_gpu_make_device((const void*)g->phys, g->queue_family, stats ? &stats_ext : NULL, stats ? 1u : 0u,
                                     &dev, &g->has_float64, err);
    if (!r) {
        VkPhysicalDeviceFeatures have;
        vkGetPhysicalDeviceFeatures(g->phys, &have); /* vx_gpu_make_device enables it where offered */
        g->has_storage_write = have.shaderStorageImageWriteWithoutFormat == VK_TRUE;
    }
    if (r) return r;
    g->device = (VkDevice)dev;
    vkGetDeviceQueue(g->device, g->queue_family, 0, &g->queue);
    return VX_OK;
}

static vx_result prepare_commands(vx_gpu* g, vx_error* err) {
    VkCommandPoolCreateInfo pci = {.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
                                   .flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT,
                                   .queueFamilyIndex = g->queue_family};
    VX__VK(vkCreateCommandPool(g->device, &pci, NULL, &g->cmd_pool), "vkCreateCommandPool");
    VkCommandBufferAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
                                      .commandPool = g->cmd_pool,
                                      .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
                                      .commandBufferCount = 1};
    VX__VK(vkAllocateCommandBuffers(g->device, &ai, &g->cmd), "vkAllocateCommandBuffers");
    VkFenceCreateInfo fci = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VX__VK(vkCreateFence(g->device, &fci, NULL, &g->fence), "vkCreateFence");
    return VX_OK;
}

static vx_result prepare_timestamps(vx_gpu* g, vx_error* err) {
    uint32_t n = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(g->phys, &n, NULL);
    VkQueueFamilyProperties q[64];
    if (n > 64) n = 64;
    vkGetPhysicalDeviceQueueFamilyProperties(g->phys, &n, q);
    g->has_timestamps = g->queue_family < n && q[g->queue_family].timestampValidBits > 0 &&
                        g->props.limits.timestampPeriod > 0;
    if (!g->has_timestamps) return VX_OK;
    VkQueryPoolCreateInfo qp = {.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO,
                                .queryType = VK_QUERY_TYPE_TIMESTAMP,
                                .queryCount = 64};
    VX__VK(vkCreateQueryPool(g->device, &qp, NULL, &g->timestamps), "vkCreateQueryPool");
    return VX_OK;
}

void vx__gpu_name(vx_gpu* g, VkObjectType type, uint64_t handle, const char* label) {
    if (!g->set_name || !label || !g->device) return;
    VkDebugUtilsObjectNameInfoEXT ni = {.sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT,
                                        .objectType = type,
                                        .objectHandle = handle,
                                        .pObjectName = label};
    g->set_name(g->device, &ni);
}

static vx_result gpu_prepare(vx_gpu* g, const vx_gpu_desc* desc, vx_error* err) {
    vx_result r;
    if (desc->external.device) {
        g->external = true;
        g->instance = (VkInstance)desc->external.instance;
        g->phys = (VkPhysicalDevice)desc->external.physical_device;
        g->device = (VkDevice)desc->external.device;
        g->queue = (VkQueue)desc->external.queue;
        g->queue_family = desc->external.queue_family;
        if (!g->instance || !g->phys || !g->queue)
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "external device given without instance/queue");
        g->has_float64 = desc->external.float64;
        g->has_storage_write = desc->external.storage_write;
    }
    double t[5];
    t[0] = vx_time_now();
    t[1] = t[2] = t[0];
    if (!desc->external.device) {
        if ((r = create_instance(g, g->validate, err))) return r;
        t[1] = vx_time_now();
        if ((r = select_device(g, desc->device, err))) return r;
        t[2] = vx_time_now();
    }
    vkGetPhysicalDeviceProperties(g->phys, &g->props);
    vkGetPhysicalDeviceMemoryProperties(g->phys, &g->memprops);
    /* the node form (gpu.h's nodes_file): the GPU form on GPUs, the file's on CPU devices (lavapipe's loop loses
     * 25-45% with the GPU form); VX_GPU_NODE_FORM=file|gpu overrides (docs/PERFORMANCE.md, issue 21's sixteenth
     * sitting and the check after it) */
    const char* form = getenv("VX_GPU_NODE_FORM");
    if (form && strcmp(form, "file") == 0)
        g->nodes_file = true;
    else if (form && strcmp(form, "gpu") == 0)
        g->nodes_file = false;
    else
        g->nodes_file = g->props.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
    /* specialisation on the host (gpu.h's specialise) */
    const char* spec = getenv("VX_GPU_SPECIALISE");
    if (spec && strcmp(spec, "0") == 0)
        g->specialise = false;
    else if (spec && strcmp(spec, "1") == 0)
        g->specialise = vx__spirv_can_specialise();
    else
        g->specialise = vx__spirv_can_specialise() && g->props.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
    vx__gpu_log_memory_types(g);
    if (!g->external && (r = create_device(g, err))) return r;
    t[3] = vx_time_now();
    if ((r = prepare_commands(g, err))) return r;
    if ((r = prepare_timestamps(g, err))) return r;
    t[4] = vx_time_now();
    /* the driver's start in its steps (a fresh machine's first process against later ones) */
    vx_log(g->logger, VX_LOG_INFO, "gpu.start", "instance %.4f s, device chosen %.4f s, device %.4f s, commands %.4f s",
           t[1] - t[0], t[2] - t[1], t[3] - t[2], t[4] - t[3]);
    return VX_OK;
}

vx_result vx_gpu_create(const vx_gpu_desc* desc_in, vx_gpu** out, vx_error* err) {
    vx_gpu_desc desc = desc_in ? *desc_in : (vx_gpu_desc){0};
    if (!out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "out is NULL");
    vx_gpu* g = vx_calloc(desc.alloc, 1, sizeof *g);
    if (!g) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    if (desc.alloc) g->alloc = *desc.alloc;
    g->logger = desc.logger;
    const char* env = getenv("VX_GPU_VALIDATION");
    g->validate = desc.validate || (env && strcmp(env, "1") == 0);
    env = getenv("VX_GPU_MEMORY_LOG");
    g->memory_log = env && strcmp(env, "1") == 0;
    vx_result r = gpu_prepare(g, &desc, err);
    if (r) {
        vx_gpu_destroy(g);
        return r;
    }
    *out = g;
    return VX_OK;
}

void vx_gpu_destroy(vx_gpu* g) {
    if (!g) return;
    if (g->device) vkDeviceWaitIdle(g->device);
    vx__pipelines_destroy(g);
    if (g->timestamps) vkDestroyQueryPool(g->device, g->timestamps, NULL);
    if (g->fence) vkDestroyFence(g->device, g->fence, NULL);
    if (g->cmd_pool) vkDestroyCommandPool(g->device, g->cmd_pool, NULL);
    if (!g->external) {
        if (g->device) vkDestroyDevice(g->device, NULL);
        if (g->messenger) {
            PFN_vkDestroyDebugUtilsMessengerEXT destroy = (PFN_vkDestroyDebugUtilsMessengerEXT)vkGetInstanceProcAddr(
                g->instance, "vkDestroyDebugUtilsMessengerEXT");
            if (destroy) destroy(g->instance, g->messenger, NULL);
        }
        if (g->instance) vkDestroyInstance(g->instance, NULL);
    }
    vx_allocator a = g->alloc;
    vx_free(&a, g);
}

const char* vx_gpu_device_name(const vx_gpu* g) { return g ? g->props.deviceName : ""; }
bool vx_gpu_is_cpu(const vx_gpu* g) { return g && g->props.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU; }
uint32_t vx_gpu_validation_errors(const vx_gpu* g) { return g ? g->validation_errors : 0; }

vx_result vx_gpu_list_devices(void (*fn)(void* user, uint32_t index, const char* name, const char* type), void* user,
                              vx_error* err) {
    VkApplicationInfo app = {.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO, .apiVersion = VK_API_VERSION_1_1};
    VkInstanceCreateInfo ci = {.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO, .pApplicationInfo = &app};
    VkInstance inst;
    VX__VK(vkCreateInstance(&ci, NULL, &inst), "vkCreateInstance");
    uint32_t n = 0;
    VkResult r = vkEnumeratePhysicalDevices(inst, &n, NULL);
    VkPhysicalDevice pds[32];
    if (n > 32) n = 32;
    if (r == VK_SUCCESS && n) r = vkEnumeratePhysicalDevices(inst, &n, pds);
    if (r != VK_SUCCESS && r != VK_INCOMPLETE) {
        vkDestroyInstance(inst, NULL);
        return vx__vk_fail(err, r, "vkEnumeratePhysicalDevices");
    }
    for (uint32_t i = 0; i < n; i++) {
        VkPhysicalDeviceProperties p;
        vkGetPhysicalDeviceProperties(pds[i], &p);
        fn(user, i, p.deviceName, type_name(p.deviceType));
    }
    vkDestroyInstance(inst, NULL);
    return VX_OK;
}
