/* bake4_floor: the Vulkan driver's own floor in one process (issue 21, branch bake4; a bench helper, not
 * part of the toolkit, after bench/results/ptbake_vkstart.c): vkCreateInstance, vkEnumeratePhysicalDevices,
 * vkCreateDevice (one queue of the first family with compute), then two trivial compute pipelines (one
 * storage buffer, a specialisation constant: 1, then 2, so that each is a compile of its own), then
 * vkDestroyDevice and vkDestroyInstance, each timed (CLOCK_MONOTONIC); the first pipeline pays the
 * driver's compiler start (its libraries loaded, its shader cache opened), the second a bare compile.
 * Build: glslangValidator -V --target-env vulkan1.1 --vn floor_spv -o floor.comp.h bake4_floor.comp;
 *        cc -O2 -I. bake4_floor.c -o bake4_floor -lvulkan */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <string.h>
#include <time.h>
#include <vulkan/vulkan.h>

#include "floor.comp.h"

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int pipeline(VkDevice dev, uint32_t value, double* seconds) {
    VkDescriptorSetLayoutBinding b = {.binding = 0, .descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                                      .descriptorCount = 1, .stageFlags = VK_SHADER_STAGE_COMPUTE_BIT};
    VkDescriptorSetLayoutCreateInfo dl = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO,
                                          .bindingCount = 1, .pBindings = &b};
    VkDescriptorSetLayout dsl;
    if (vkCreateDescriptorSetLayout(dev, &dl, NULL, &dsl) != VK_SUCCESS) return 1;
    VkPipelineLayoutCreateInfo pl = {.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO, .setLayoutCount = 1,
                                     .pSetLayouts = &dsl};
    VkPipelineLayout lay;
    if (vkCreatePipelineLayout(dev, &pl, NULL, &lay) != VK_SUCCESS) return 1;
    VkShaderModuleCreateInfo sm = {.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO, .codeSize = sizeof floor_spv,
                                   .pCode = floor_spv};
    VkShaderModule mod;
    if (vkCreateShaderModule(dev, &sm, NULL, &mod) != VK_SUCCESS) return 1;
    VkSpecializationMapEntry me = {.constantID = 0, .offset = 0, .size = 4};
    VkSpecializationInfo si = {.mapEntryCount = 1, .pMapEntries = &me, .dataSize = 4, .pData = &value};
    VkComputePipelineCreateInfo ci = {.sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO,
                                      .stage = {.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
                                                .stage = VK_SHADER_STAGE_COMPUTE_BIT, .module = mod, .pName = "main",
                                                .pSpecializationInfo = &si},
                                      .layout = lay};
    VkPipeline pipe;
    double t = now();
    VkResult r = vkCreateComputePipelines(dev, VK_NULL_HANDLE, 1, &ci, NULL, &pipe);
    *seconds = now() - t;
    if (r != VK_SUCCESS) return 1;
    vkDestroyPipeline(dev, pipe, NULL);
    vkDestroyShaderModule(dev, mod, NULL);
    vkDestroyPipelineLayout(dev, lay, NULL);
    vkDestroyDescriptorSetLayout(dev, dsl, NULL);
    return 0;
}

int main(void) {
    double t0 = now();
    VkApplicationInfo app = {.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO, .apiVersion = VK_API_VERSION_1_1};
    VkInstanceCreateInfo ci = {.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO, .pApplicationInfo = &app};
    VkInstance inst;
    if (vkCreateInstance(&ci, NULL, &inst) != VK_SUCCESS) return 1;
    double t1 = now();
    uint32_t n = 1;
    VkPhysicalDevice pd;
    VkResult r = vkEnumeratePhysicalDevices(inst, &n, &pd);
    if ((r != VK_SUCCESS && r != VK_INCOMPLETE) || n == 0) return 1;
    double t2 = now();
    uint32_t nq = 16;
    VkQueueFamilyProperties q[16];
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &nq, q);
    uint32_t fam = 0;
    for (uint32_t i = 0; i < nq; i++)
        if (q[i].queueFlags & VK_QUEUE_COMPUTE_BIT) {
            fam = i;
            break;
        }
    float prio = 1.0f;
    VkDeviceQueueCreateInfo qci = {.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO, .queueFamilyIndex = fam,
                                   .queueCount = 1, .pQueuePriorities = &prio};
    VkDeviceCreateInfo dci = {.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, .queueCreateInfoCount = 1,
                              .pQueueCreateInfos = &qci};
    VkDevice dev;
    if (vkCreateDevice(pd, &dci, NULL, &dev) != VK_SUCCESS) return 1;
    double t3 = now(), p1 = 0, p2 = 0;
    if (pipeline(dev, 1, &p1) || pipeline(dev, 2, &p2)) return 1;
    double t4 = now();
    vkDestroyDevice(dev, NULL);
    double t5 = now();
    vkDestroyInstance(inst, NULL);
    double t6 = now();
    printf("floor: instance %.4f s, enumerate %.4f s, device %.4f s, pipeline 1 %.4f s, pipeline 2 %.4f s "
           "(both with layouts %.4f s), destroy device %.4f s, destroy instance %.4f s; in all %.4f s\n",
           t1 - t0, t2 - t1, t3 - t2, p1, p2, t4 - t3, t5 - t4, t6 - t5, t6 - t0);
    return 0;
}
