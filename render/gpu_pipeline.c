/* render/gpu_pipeline.c - compute pipelines described by structs, created
 * once per (shader, specialisation) key and cached in the vx_gpu. The SPIR-V
 * is compiled at build time by glslangValidator and embedded here. */
#include <pthread.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/render_internal.h"
#include "render/spirv_opt.h"

#include "trace.comp.h"
#include "beam.comp.h"
#include "dense.comp.h"
#include "trace_precise.comp.h"

const uint32_t* vx__spirv_trace(size_t* bytes) {
    *bytes = sizeof vx__trace_spv_arr;
    return vx__trace_spv_arr;
}
const uint32_t* vx__spirv_beam(size_t* bytes) {
    *bytes = sizeof vx__beam_spv_arr;
    return vx__beam_spv_arr;
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
    if (d->binding_count > VX_GPU_MAX_BINDINGS || d->spec_count > sizeof d->spec / sizeof d->spec[0])
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "pipeline '%s': too many bindings or constants",
                       d->label);
    return VX_OK;
}
#endif

/* gpu_device.c: VX_GPU_SHADER_STATS=1 and the device has
 * VK_KHR_pipeline_executable_properties (then created with it). */
bool vx__gpu_shader_stats_wanted(VkPhysicalDevice pd);

/* Logs the driver's statistics of each executable of p ("gpu.shader_stats",
 * info): one line per executable, "LABEL [spec a,b,..] NAME: stat=value; ...",
 * e.g. registers, local memory and instruction counts, in the driver's words.
 * Benchmarks ask for it (render_bench --shader-stats); failures only skip. */
static void log_stats(vx_gpu* g, const vx_gpu_compute_pipeline_desc* d, VkPipeline pipe) {
    PFN_vkGetPipelineExecutablePropertiesKHR get_props =
        (PFN_vkGetPipelineExecutablePropertiesKHR)vkGetDeviceProcAddr(g->device, "vkGetPipelineExecutablePropertiesKHR");
    PFN_vkGetPipelineExecutableStatisticsKHR get_stats =
        (PFN_vkGetPipelineExecutableStatisticsKHR)vkGetDeviceProcAddr(g->device, "vkGetPipelineExecutableStatisticsKHR");
    if (!get_props || !get_stats) return;
    VkPipelineInfoKHR pi = {.sType = VK_STRUCTURE_TYPE_PIPELINE_INFO_KHR, .pipeline = pipe};
    VkPipelineExecutablePropertiesKHR props[4];
    uint32_t ne = 4;
    for (uint32_t i = 0; i < ne; i++) props[i] = (VkPipelineExecutablePropertiesKHR){.sType = VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_PROPERTIES_KHR};
    VkResult r = get_props(g->device, &pi, &ne, props);
    if (r != VK_SUCCESS && r != VK_INCOMPLETE) return;
    char spec[64] = "";
    for (uint32_t i = 0, o = 0; i < d->spec_count && o < sizeof spec - 12; i++)
        o += (uint32_t)snprintf(spec + o, sizeof spec - o, "%s%u", i ? "," : "", d->spec[i]);
    for (uint32_t e = 0; e < ne; e++) {
        VkPipelineExecutableInfoKHR ei = {.sType = VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_INFO_KHR,
                                          .pipeline = pipe,
                                          .executableIndex = e};
        VkPipelineExecutableStatisticKHR st[32];
        uint32_t ns = 32;
        for (uint32_t i = 0; i < ns; i++) st[i] = (VkPipelineExecutableStatisticKHR){.sType = VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_STATISTIC_KHR};
        r = get_stats(g->device, &ei, &ns, st);
        if (r != VK_SUCCESS && r != VK_INCOMPLETE) continue;
        char line[1536];
        int o = snprintf(line, sizeof line, "%s [spec %s] %s (subgroup %u):", d->label ? d->label : "?", spec,
                         props[e].name, props[e].subgroupSize);
        for (uint32_t i = 0; i < ns && o > 0 && (size_t)o < sizeof line; i++) {
            size_t left = sizeof line - (size_t)o;
            switch (st[i].format) {
            case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_BOOL32_KHR:
                o += snprintf(line + o, left, " %s=%s;", st[i].name, st[i].value.b32 ? "true" : "false");
                break;
            case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_INT64_KHR:
                o += snprintf(line + o, left, " %s=%lld;", st[i].name, (long long)st[i].value.i64);
                break;
            case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_UINT64_KHR:
                o += snprintf(line + o, left, " %s=%llu;", st[i].name, (unsigned long long)st[i].value.u64);
                break;
            default: o += snprintf(line + o, left, " %s=%g;", st[i].name, st[i].value.f64); break;
            }
        }
        vx_log(g->logger, VX_LOG_INFO, "gpu.shader_stats", "%s", line);
    }
}

/* How a pipeline was made, for its log line: vkCreateComputePipelines' time, and where the module was specialised
 * on the host (vx_gpu.specialise) that step's time and the module's size after it, or its error (the module as
 * built was then given to the driver). */
typedef struct made_info {
    double seconds;
    double host_seconds;
    size_t host_bytes;
    char host_error[sizeof((vx_error){0}.msg)];
} made_info;

/* Makes p (no logging: it may run on a thread of vx__pipeline_ahead; logged() logs it on the vx_gpu's own
 * thread). */
static vx_result create_pipeline(vx_gpu* g, const vx_gpu_compute_pipeline_desc* d, vx__pipeline* p, made_info* made,
                                 vx_error* err) {
    VkDescriptorSetLayoutBinding b[VX_GPU_MAX_BINDINGS];
    p->binding_count = d->binding_count;
    memcpy(p->bindings, d->bindings, sizeof p->bindings);
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
    /* the desc's constants (ids 0..spec_count-1), then the device's node form (VX__SPEC_NODES_FILE), which
     * modules that do not declare it ignore */
    enum { NSPEC = sizeof d->spec / sizeof d->spec[0] };
    VkSpecializationMapEntry me[NSPEC + 1];
    uint32_t ids[NSPEC + 1], sv[NSPEC + 1];
    uint32_t ns = d->spec_count < NSPEC ? d->spec_count : NSPEC;
    for (uint32_t i = 0; i < ns; i++) {
        me[i] = (VkSpecializationMapEntry){.constantID = i, .offset = 4 * i, .size = 4};
        ids[i] = i;
        sv[i] = d->spec[i];
    }
    me[ns] = (VkSpecializationMapEntry){.constantID = VX__SPEC_NODES_FILE, .offset = 4 * ns, .size = sizeof(VkBool32)};
    ids[ns] = VX__SPEC_NODES_FILE;
    sv[ns] = g->nodes_file ? VK_TRUE : VK_FALSE;
    /* specialised on the host (render/spirv_opt.h says why); the constants then stay in the pipeline's info,
     * where the driver ignores ids the module no longer declares. A module the optimizer refuses goes to the
     * driver as built (logged() says so): slower to make, the same kernel. */
    const uint32_t* code = d->spirv;
    size_t code_size = d->spirv_size;
    uint32_t* host = NULL;
    if (g->specialise) {
        double t = vx_time_now();
        size_t words = 0;
        vx_error e = {0};
        if (vx__spirv_specialise(d->spirv, d->spirv_size / 4, ids, sv, ns + 1, &host, &words, &e) == VX_OK) {
            code = host;
            code_size = 4 * words;
            made->host_bytes = code_size;
        } else {
            snprintf(made->host_error, sizeof made->host_error, "%s", e.msg);
        }
        made->host_seconds = vx_time_now() - t;
    }
    VkShaderModuleCreateInfo sm = {.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO,
                                   .codeSize = code_size,
                                   .pCode = code};
    VkShaderModule mod;
    VkResult mr = vkCreateShaderModule(g->device, &sm, NULL, &mod);
    free(host);
    if (mr != VK_SUCCESS) return vx__vk_fail(err, mr, "vkCreateShaderModule");
    VkSpecializationInfo si = {.mapEntryCount = ns + 1, .pMapEntries = me, .dataSize = 4u * (ns + 1), .pData = sv};
    bool stats = !g->external && vx__gpu_shader_stats_wanted(g->phys);
    VkComputePipelineCreateInfo ci = {.sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO,
                                      .flags = stats ? VK_PIPELINE_CREATE_CAPTURE_STATISTICS_BIT_KHR : 0u,
                                      .stage = {.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
                                                .stage = VK_SHADER_STAGE_COMPUTE_BIT,
                                                .module = mod,
                                                .pName = d->entry ? d->entry : "main",
                                                .pSpecializationInfo = &si},
                                      .layout = p->layout};
    double t0 = vx_time_now();
    VkResult r = vkCreateComputePipelines(g->device, VK_NULL_HANDLE, 1, &ci, NULL, &p->pipe);
    made->seconds = vx_time_now() - t0;
    vkDestroyShaderModule(g->device, mod, NULL);
    if (r != VK_SUCCESS) return vx__vk_fail(err, r, "vkCreateComputePipelines");
    vx__gpu_name(g, VK_OBJECT_TYPE_PIPELINE, (uint64_t)p->pipe, d->label);
    return VX_OK;
}

/* The log of a pipeline made: the driver's compile (on a machine whose shader cache is empty) or its cache's
 * hit, and with VX_GPU_SHADER_STATS its statistics. */
static void logged(vx_gpu* g, const vx_gpu_compute_pipeline_desc* d, const vx__pipeline* p, const made_info* made,
                   bool ahead) {
    char host[sizeof((vx_error){0}.msg) + 64] = "";
    if (made->host_error[0])
        snprintf(host, sizeof host, "; not specialised on the host: %s", made->host_error);
    else if (made->host_bytes)
        snprintf(host, sizeof host, "; specialised on the host in %.4f s to %zu bytes", made->host_seconds,
                 made->host_bytes);
    vx_log(g->logger, VX_LOG_INFO, "gpu.pipeline", "%s (%zu bytes of SPIR-V, %u constants) made in %.4f s%s%s",
           d->label ? d->label : "?", d->spirv_size, d->spec_count, made->seconds, ahead ? " ahead" : "", host);
    if (!g->external && vx__gpu_shader_stats_wanted(g->phys)) log_stats(g, d, p->pipe);
}

static void destroy_pipeline(vx_gpu* g, vx__pipeline* p) {
    if (p->pipe) vkDestroyPipeline(g->device, p->pipe, NULL);
    if (p->layout) vkDestroyPipelineLayout(g->device, p->layout, NULL);
    if (p->dsl) vkDestroyDescriptorSetLayout(g->device, p->dsl, NULL);
    memset(p, 0, sizeof *p);
}

/* A pipeline being made ahead (vx__pipeline_ahead): the thread writes p, r and err; the vx_gpu's thread
 * reads them after the join. */
typedef struct vx__pipeline_pending {
    struct vx__pipeline_pending* next;
    uint64_t key;
    vx_gpu* g;
    vx_gpu_compute_pipeline_desc d;
    vx__pipeline p;
    vx_result r;
    vx_error err;
    made_info made;
    atomic_bool done; /* p, r, err and made are written (vx__pipeline_state) */
    pthread_t thread;
} vx__pipeline_pending;

static void* ahead_main(void* arg) {
    vx__pipeline_pending* q = arg;
    /* vkCreate* of one device may run on several threads at once (no external synchronisation asked) */
    q->r = create_pipeline(q->g, &q->d, &q->p, &q->made, &q->err);
    atomic_store_explicit(&q->done, true, memory_order_release);
    return NULL;
}

static vx__pipeline* cached(vx_gpu* g, uint64_t key) {
    for (vx__pipeline_block* b = g->pipelines; b; b = b->next)
        for (uint32_t i = 0; i < b->count; i++)
            if (b->p[i].key == key) return &b->p[i];
    return NULL;
}

bool vx__pipeline_ahead(vx_gpu* g, uint64_t key, const vx_gpu_compute_pipeline_desc* d) {
    if (!g || !d || cached(g, key)) return false;
    for (vx__pipeline_pending* q = g->pending; q; q = q->next)
        if (q->key == key) return false;
#ifndef NDEBUG
    if (validate_desc(d, NULL)) return false; /* the get reports it */
#endif
    vx__pipeline_pending* q = vx_calloc(&g->alloc, 1, sizeof *q);
    if (!q) return false;
    q->key = key, q->g = g, q->d = *d;
    atomic_init(&q->done, false);
    if (pthread_create(&q->thread, NULL, ahead_main, q)) {
        vx_free(&g->alloc, q);
        return false;
    }
    q->next = g->pending;
    g->pending = q;
    return true;
}

int vx__pipeline_state(vx_gpu* g, uint64_t key) {
    if (!g) return VX__PIPE_NONE;
    if (cached(g, key)) return VX__PIPE_READY;
    for (vx__pipeline_pending* q = g->pending; q; q = q->next)
        if (q->key == key)
            return atomic_load_explicit(&q->done, memory_order_acquire) ? VX__PIPE_READY : VX__PIPE_PENDING;
    return VX__PIPE_NONE;
}

/* The pending pipeline of key, joined and unlinked (NULL: none). */
static vx__pipeline_pending* take_pending(vx_gpu* g, uint64_t key) {
    for (vx__pipeline_pending** at = &g->pending; *at; at = &(*at)->next)
        if ((*at)->key == key) {
            vx__pipeline_pending* q = *at;
            *at = q->next;
            pthread_join(q->thread, NULL);
            return q;
        }
    return NULL;
}

vx_result vx__pipeline_get(vx_gpu* g, uint64_t key, const vx_gpu_compute_pipeline_desc* d, vx__pipeline** out,
                           vx_error* err) {
    vx__pipeline_block* last = NULL;
    for (vx__pipeline_block* b = g->pipelines; b; last = b, b = b->next)
        for (uint32_t i = 0; i < b->count; i++)
            if (b->p[i].key == key) {
                *out = &b->p[i];
                return VX_OK;
            }
    vx__pipeline_pending* q = take_pending(g, key);
    if (q && q->r) {
        vx_result r = q->r;
        if (err) *err = q->err;
        destroy_pipeline(g, &q->p);
        vx_free(&g->alloc, q);
        return r;
    }
#ifndef NDEBUG
    if (!q) {
        vx_result vr = validate_desc(d, err);
        if (vr) return vr;
    }
#endif
    /* Nothing is evicted: holders keep entries across calls (gpu.h), and
     * the next free slot is after every entry, so none moves. */
    if (!last || last->count == VX__PIPELINE_BLOCK) {
        vx__pipeline_block* b = vx_calloc(&g->alloc, 1, sizeof *b);
        if (!b) {
            if (q) destroy_pipeline(g, &q->p);
            vx_free(&g->alloc, q);
            return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for the pipeline cache");
        }
        if (last) last->next = b;
        else g->pipelines = b;
        last = b;
    }
    vx__pipeline* p = &last->p[last->count];
    memset(p, 0, sizeof *p);
    if (q) { /* made ahead */
        *p = q->p;
        logged(g, &q->d, p, &q->made, true);
        vx_free(&g->alloc, q);
    } else {
        made_info made = {0};
        vx_result r = create_pipeline(g, d, p, &made, err);
        if (r) {
            destroy_pipeline(g, p);
            return r;
        }
        logged(g, d, p, &made, false);
    }
    p->key = key;
    last->count++;
    g->pipeline_count++;
    *out = p;
    return VX_OK;
}

void vx__pipelines_destroy(vx_gpu* g) {
    while (g->pending) { /* made ahead and never asked for */
        vx__pipeline_pending* q = take_pending(g, g->pending->key);
        destroy_pipeline(g, &q->p);
        vx_free(&g->alloc, q);
    }
    for (vx__pipeline_block* b = g->pipelines; b;) {
        vx__pipeline_block* next = b->next;
        for (uint32_t i = b->count; i-- > 0;) destroy_pipeline(g, &b->p[i]);
        vx_free(&g->alloc, b);
        b = next;
    }
    g->pipelines = NULL;
    g->pipeline_count = 0;
}
