/* bench/startup/vkprobe.c - one process's Vulkan start, step by step
 * (issue 23): vkCreateInstance, vkEnumeratePhysicalDevices (and the devices'
 * UUIDs: which GPUs the driver shows), vkCreateDevice on device K (argument,
 * else the launcher's local rank, mod the count), a first empty submit, the
 * destroys; the start against the launch stamp VX_T0 (`date +%s.%N`) where
 * the caller sets it. Built by hand, needs only libvulkan:
 *   cc -O2 -o vkprobe bench/startup/vkprobe.c -lvulkan
 * (docs/PERFORMANCE.md section 10 has the runs). */
#define _GNU_SOURCE
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <vulkan/vulkan.h>
static double now(void) { struct timespec t; clock_gettime(CLOCK_REALTIME, &t); return t.tv_sec + t.tv_nsec * 1e-9; }
int main(int argc, char** argv) {
    double t0 = now();
    const char* l = getenv("VX_T0");
    double launch = l ? atof(l) : t0;
    const char* lr = getenv("OMPI_COMM_WORLD_LOCAL_RANK");
    int want = argc > 1 ? atoi(argv[1]) : lr ? atoi(lr) : 0;
    VkApplicationInfo app = {.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO, .apiVersion = VK_API_VERSION_1_1};
    VkInstanceCreateInfo ci = {.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO, .pApplicationInfo = &app};
    VkInstance inst;
    VkResult r = vkCreateInstance(&ci, NULL, &inst);
    double t1 = now();
    if (r) { printf("vkCreateInstance %d\n", r); return 1; }
    uint32_t n = 0;
    r = vkEnumeratePhysicalDevices(inst, &n, NULL);
    VkPhysicalDevice pd[16];
    if (n > 16) n = 16;
    if (!r) r = vkEnumeratePhysicalDevices(inst, &n, pd);
    double t2 = now();
    if (r || !n) { printf("vkEnumeratePhysicalDevices %d n %u (start %.3f inst %.3f enum %.3f)\n", r, n, t0 - launch, t1 - t0, t2 - t1); return 1; }
    char uu[16][8];
    for (uint32_t i = 0; i < n; i++) {
        VkPhysicalDeviceIDProperties id = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ID_PROPERTIES};
        VkPhysicalDevicePCIBusInfoPropertiesEXT pci = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PCI_BUS_INFO_PROPERTIES_EXT};
        VkPhysicalDeviceProperties2 p2 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, .pNext = &id};
        vkGetPhysicalDeviceProperties2(pd[i], &p2);
        snprintf(uu[i], 8, "%02x%02x%02x", id.deviceUUID[0], id.deviceUUID[1], id.deviceUUID[2]);
        (void)pci;
    }
    double t3 = now();
    uint32_t k = (uint32_t)want % n;
    float prio = 1;
    VkDeviceQueueCreateInfo q = {.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO, .queueFamilyIndex = 0, .queueCount = 1, .pQueuePriorities = &prio};
    VkDeviceCreateInfo dci = {.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, .queueCreateInfoCount = 1, .pQueueCreateInfos = &q};
    VkDevice dev;
    r = vkCreateDevice(pd[k], &dci, NULL, &dev);
    double t4 = now();
    if (r) { printf("vkCreateDevice %d\n", r); return 1; }
    VkQueue queue;
    vkGetDeviceQueue(dev, 0, 0, &queue);
    VkFence f;
    VkFenceCreateInfo fci = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    vkCreateFence(dev, &fci, NULL, &f);
    vkQueueSubmit(queue, 0, NULL, f);
    vkWaitForFences(dev, 1, &f, VK_TRUE, ~0ull);
    vkDestroyFence(dev, f, NULL);
    double t5 = now();
    vkDestroyDevice(dev, NULL);
    double t6 = now();
    vkDestroyInstance(inst, NULL);
    double t7 = now();
    printf("vk want %d: %u devices [", want, n);
    for (uint32_t i = 0; i < n; i++) printf("%s%s", i ? " " : "", uu[i]);
    printf("] used %s | start %.3f inst %.3f enum %.3f props %.3f device %.3f submit %.3f destroy dev %.3f inst %.3f | total %.3f end %.3f\n",
           uu[k], t0 - launch, t1 - t0, t2 - t1, t3 - t2, t4 - t3, t5 - t4, t6 - t5, t7 - t6, t7 - t0, t7 - launch);
    return 0;
}
