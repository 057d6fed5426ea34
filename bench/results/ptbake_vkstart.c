/* vkstart: the Vulkan driver's fixed cost in one process (issue 21, branch ptbake; a bench helper, not
 * part of the toolkit): vkCreateInstance, vkEnumeratePhysicalDevices, vkCreateDevice (one queue of the
 * first family with compute), vkDestroyDevice, vkDestroyInstance, each timed (CLOCK_MONOTONIC).
 * "vkstart enum": first the instance extensions enumerated twice (count, then list), as voxkit's
 * vx_gpu_create did before it asked for VK_EXT_debug_utils. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <string.h>
#include <time.h>
#include <vulkan/vulkan.h>

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int main(int argc, char** argv) {
    double te = now(), enum_s = 0;
    if (argc > 1 && !strcmp(argv[1], "enum")) {
        uint32_t ne = 0;
        VkExtensionProperties ep[64];
        vkEnumerateInstanceExtensionProperties(NULL, &ne, NULL);
        if (ne > 64) ne = 64;
        vkEnumerateInstanceExtensionProperties(NULL, &ne, ep);
        enum_s = now() - te;
    }
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
        if (q[i].queueFlags & VK_QUEUE_COMPUTE_BIT) { fam = i; break; }
    float prio = 1.0f;
    VkDeviceQueueCreateInfo qci = {.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO, .queueFamilyIndex = fam,
                                   .queueCount = 1, .pQueuePriorities = &prio};
    VkDeviceCreateInfo dci = {.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, .queueCreateInfoCount = 1,
                              .pQueueCreateInfos = &qci};
    VkDevice dev;
    if (vkCreateDevice(pd, &dci, NULL, &dev) != VK_SUCCESS) return 1;
    double t3 = now();
    vkDestroyDevice(dev, NULL);
    double t4 = now();
    vkDestroyInstance(inst, NULL);
    double t5 = now();
    printf("vkstart: enumerate extensions %.3f s, instance %.3f s, enumerate %.4f s, device %.3f s, destroy device %.3f s, destroy instance %.3f s\n",
           enum_s, t1 - t0, t2 - t1, t3 - t2, t4 - t3, t5 - t4);
    return 0;
}
