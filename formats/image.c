/* formats/image.c - formats/image.h: .pfm, .ppm and .pgm by voxkit's own code
 * (image_pnm.c), every other format through OpenImageIO in its own module,
 * libvoxkit_oiio.so (image_oiio.cpp), loaded at the first such image.
 *
 * Why a module: OpenImageIO brings some 250 shared libraries (OpenCV, FFmpeg,
 * GDAL, ...); linked into the tools they cost every svo_render, svo_bake and
 * svo_view process 0.35 s of dynamic loading before main on a 2-core machine,
 * whether it wrote a PNG or nothing (--help), and libvoxkit's users the same at
 * load. Loaded with dlopen, only a process that reads or writes such an image
 * pays it.
 *
 * Where the module is: beside the code that calls it, found with dladdr: the
 * library (libvoxkit.so in <libdir>, the build tree's top folder) has it in
 * voxkit/ below its folder; a tool (<bindir>, the build tree's bin/) in the
 * library folder's voxkit/ (VX_IMAGE_MODULE_FROM_BIN), or the build tree's
 * ../voxkit; last, the installed <libdir>/voxkit (VX_IMAGE_MODULE_DIR), for a
 * tool copied elsewhere. Nothing is kept between calls: dlopen of a loaded
 * module returns it again (RTLD_NODELETE keeps it loaded).
 *
 * 8-bit PNGs, the tools' usual output, are written by libpng's simplified API
 * without the module where libpng is there (VX_IMAGE_PNG): the same pixels
 * (other bytes than OpenImageIO's encoder writes: no oFFs chunk), and a process
 * that writes a PNG does not load OpenImageIO's libraries (0.3 s of each
 * svo_render's 2.7 on lavapipe). */
#define _GNU_SOURCE
#include "formats/image.h"

#include <stdio.h>
#include <string.h>

#include "formats/image_pnm.h"

#ifdef VX_IMAGE_PNG
#include <png.h>

/* A name ending in .png (either case). */
static bool is_png(const char* path) {
    const char* dot = strrchr(path, '.');
    const char* slash = strrchr(path, '/');
    return dot && (!slash || dot > slash) && (!strcmp(dot, ".png") || !strcmp(dot, ".PNG"));
}

/* An 8-bit PNG, encoded in memory and written with vx_file_write_atomic (a failure leaves nothing). */
static vx_result png_write(const char* path, const vx_image_desc* img, vx_error* err) {
    static const png_uint_32 formats[5] = {0, PNG_FORMAT_GRAY, PNG_FORMAT_GA, PNG_FORMAT_RGB, PNG_FORMAT_RGBA};
    png_image pi;
    memset(&pi, 0, sizeof pi);
    pi.version = PNG_IMAGE_VERSION;
    pi.width = img->width, pi.height = img->height, pi.format = formats[img->channels];
    png_int_32 stride = (png_int_32)(img->width * img->channels); /* at most 65536 * 4 */
    png_alloc_size_t size = 0;
    void* mem = NULL;
    /* the first call sizes the encoding, the second writes it */
    int ok = png_image_write_to_memory(&pi, NULL, &size, 0, img->pixels, stride, NULL);
    if (ok && !(mem = vx_alloc(NULL, size))) {
        png_image_free(&pi);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "%s: out of memory", path);
    }
    if (ok) ok = png_image_write_to_memory(&pi, mem, &size, 0, img->pixels, stride, NULL);
    vx_result r = ok ? vx_file_write_atomic(path, NULL, mem, size, err)
                     : vx_fail(err, VX_ERR_IO, VX_NO_OFFSET, "%s: %s", path, pi.message);
    png_image_free(&pi);
    vx_free(NULL, mem);
    return r;
}
#endif

#ifdef VX_IMAGE_OIIO
#include <dlfcn.h>
#include <limits.h>

/* The module's entry points (image_oiio.cpp): the same arguments as formats/image.h's, checked here. */
typedef vx_result (*oiio_write_fn)(const char* path, const vx_image_desc* img, vx_error* err);
typedef vx_result (*oiio_read_fn)(const char* path, vx_image_type type, uint32_t max_dim, uint32_t* width,
                                  uint32_t* height, uint32_t* channels, void** out_pixels, vx_error* err);

/* The module's symbol `name` into *out; else the reason, for `path` (the image). */
static vx_result module_symbol(const char* name, const char* path, void** out, vx_error* err) {
    Dl_info info;
    char self[PATH_MAX] = ".", why[160] = "not found";
    /* the object holding this code: libvoxkit.so or the executable */
    if (dladdr((const void*)module_symbol, &info) && info.dli_fname && strlen(info.dli_fname) < sizeof self) {
        snprintf(self, sizeof self, "%s", info.dli_fname);
        char* slash = strrchr(self, '/');
        if (slash) *slash = 0;
        else snprintf(self, sizeof self, ".");
    }
    const char* rel[] = {"voxkit", VX_IMAGE_MODULE_FROM_BIN, "../voxkit"};
    enum { NREL = sizeof rel / sizeof rel[0] };
    for (size_t i = 0; i <= NREL; i++) {
        char file[PATH_MAX];
        int n = i < NREL ? snprintf(file, sizeof file, "%s/%s/libvoxkit_oiio.so", self, rel[i])
                         : snprintf(file, sizeof file, "%s/libvoxkit_oiio.so", VX_IMAGE_MODULE_DIR);
        if (n < 0 || (size_t)n >= sizeof file) continue;
        void* h = dlopen(file, RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE);
        if (!h) {
            /* the first failure other than a missing file says most (a library the module needs, say) */
            const char* e = dlerror();
            if (!strcmp(why, "not found") && e && !strstr(e, "No such file")) snprintf(why, sizeof why, "%s", e);
            continue;
        }
        if ((*out = dlsym(h, name))) return VX_OK;
        return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "%s: %s has no %s", path, file, name);
    }
    return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET,
                   "%s: no OpenImageIO module (libvoxkit_oiio.so beside %s or in %s: %s); .pfm/.ppm/.pgm need none",
                   path, self, VX_IMAGE_MODULE_DIR, why);
}
#endif

vx_result vx_image_write(const char* path, const vx_image_desc* img, vx_error* err) {
    vx_result r = vx__image_desc_check(path, img, err);
    if (r) return r;
    /* PFM/PPM/PGM by our own code in every build (the same bytes with and without OpenImageIO; Debian's has no
     * PFM writer) */
    if (vx__image_pnm_kind(path)) return vx__image_pnm_write(path, img, err);
#ifdef VX_IMAGE_PNG
    if (img->type == VX_IMAGE_U8 && is_png(path)) return png_write(path, img, err);
#endif
#ifdef VX_IMAGE_OIIO
    void* f = NULL;
    r = module_symbol("vx__image_oiio_write", path, &f, err);
    return r ? r : ((oiio_write_fn)f)(path, img, err);
#else
    return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET,
                   "%s: built without OpenImageIO: images are written as .pfm (float), .ppm or .pgm (8 bits)%s", path,
#ifdef VX_IMAGE_PNG
                   " and 8-bit .png"
#else
                   ""
#endif
    );
#endif
}

vx_result vx_image_read(const char* path, vx_image_type type, uint32_t max_dim, uint32_t* width, uint32_t* height,
                        uint32_t* channels, void** out_pixels, vx_error* err) {
    if (!path || !width || !height || !channels || !out_pixels)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    if (!max_dim) max_dim = 16384;
    if (vx__image_pnm_kind(path))
        return vx__image_pnm_read(path, type, max_dim, width, height, channels, out_pixels, err);
#ifdef VX_IMAGE_OIIO
    void* f = NULL;
    vx_result r = module_symbol("vx__image_oiio_read", path, &f, err);
    return r ? r : ((oiio_read_fn)f)(path, type, max_dim, width, height, channels, out_pixels, err);
#else
    return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET,
                   "%s: built without OpenImageIO: images are read from .pfm, .ppm or .pgm", path);
#endif
}
