/* tests/gpu_test.h - the device set-up the GPU tests share: pins the Vulkan
 * loader, lavapipe and the validation layer, then opens a device (with
 * validation where asked and the layer is installed, else without).
 *
 * Why pin: vkDestroyInstance unloads the driver, and LeakSanitizer then sees
 * lavapipe's internal caches through an unloaded module, cannot attribute
 * them, and tests/render/lsan.supp cannot name them. RTLD_NODELETE keeps the
 * modules mapped and their frames symbolised (no effect on other drivers). */
#ifndef VX_TESTS_GPU_TEST_H
#define VX_TESTS_GPU_TEST_H
#include <dlfcn.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "render/render.h"

/* Opens *out from desc (validation first when `validate`); prints the
 * device's name. Returns NULL, or the reason to skip the GPU tests (no
 * device; *out NULL then), which stays valid for the process. */
static inline const char* vx_test_gpu_open(vx_gpu_desc desc, bool validate, vx_gpu** out) {
    static const char* pin[] = {"libvulkan.so.1", "libvulkan_lvp.so", "libVkLayer_khronos_validation.so"};
    for (size_t i = 0; i < sizeof pin / sizeof pin[0]; i++) dlopen(pin[i], RTLD_NOW | RTLD_NODELETE);
    vx_error err = {0};
    vx_result r = VX_ERR_UNSUPPORTED;
    if (validate) {
        vx_gpu_desc v = desc;
        v.validate = true;
        r = vx_gpu_create(&v, out, &err);
        if (r) fprintf(stderr, "validation layer unavailable (%s); running without\n", err.msg);
    }
    if (r) r = vx_gpu_create(&desc, out, &err);
    if (r) {
        static char why[256];
        *out = NULL;
        snprintf(why, sizeof why, "no Vulkan device: %s", err.msg);
        return why;
    }
    printf("device: %s\n", vx_gpu_device_name(*out));
    return NULL;
}

/* A logger for vx_gpu_desc.logger that counts the validation layer's
 * messages into *(int*)user and prints the first four, so that a failure
 * says what: vx_logger lg = {.func = vx_test_validation_log, .user_data = &n}. */
static inline void vx_test_validation_log(void* user, vx_log_level level, const char* id, const char* msg) {
    (void)level;
    int* n = user;
    if (!strcmp(id, "gpu.validation") && (*n)++ < 4) fprintf(stderr, "  validation: %s\n", msg);
}

#endif
