// formats/image_oiio.cpp - the OpenImageIO shim behind formats/image.h, built
// as its own module (libvoxkit_oiio.so) that formats/image.c loads the first
// time an image other than .pfm/.ppm/.pgm is read or written: OpenImageIO
// brings some 250 shared libraries (OpenCV, FFmpeg, GDAL, ...), and linking it
// into the tools cost every svo_render, svo_bake and svo_view process 0.35 s of
// dynamic loading before main on this machine, whatever it wrote.
// Exceptions never cross into C: every call is wrapped.
#include <OpenImageIO/imageio.h>

#include <cstdio>
#include <cstring>
#include <memory>
#include <string>

extern "C" {
#include "formats/image.h"
}

using namespace OIIO;

static std::string tmp_name(const std::string& path) {
    // keep the extension last so OpenImageIO picks the same format
    size_t slash = path.find_last_of('/');
    size_t dot = path.find_last_of('.');
    std::string ext = (dot != std::string::npos && (slash == std::string::npos || dot > slash)) ? path.substr(dot) : "";
    std::string stem = path.substr(0, path.size() - ext.size());
    return stem + ".tmp" + std::to_string((unsigned long)std::hash<std::string>{}(path) % 100000) + ext;
}

// The module's two entry points, looked up by these names with dlsym (formats/image.c module_symbol, whose
// oiio_write_fn / oiio_read_fn are their types); the arguments are checked and .pfm/.ppm/.pgm/.png handled there.
extern "C" __attribute__((visibility("default"))) vx_result vx__image_oiio_write(const char* path,
                                                                                  const vx_image_desc* img,
                                                                                  vx_error* err) {
    try {
        std::string tmp = tmp_name(path);
        auto out = ImageOutput::create(path);
        if (!out)
            return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "%s: no image writer for this extension", path);
        TypeDesc td = img->type == VX_IMAGE_F32 ? TypeDesc::FLOAT : TypeDesc::UINT8;
        ImageSpec spec((int)img->width, (int)img->height, (int)img->channels, td);
        if (img->channels == 1 && img->type == VX_IMAGE_F32) spec.channelnames = {"Z"};
        /* the same pixels give the same bytes (OpenEXR would stamp the write
         * time): outputs of a distributed render compare with cmp */
        spec.attribute("DateTime", "");
        if (!out->open(tmp, spec)) {
            std::string e = out->geterror();
            return vx_fail(err, VX_ERR_IO, VX_NO_OFFSET, "%s: %s", path, e.c_str());
        }
        bool ok = out->write_image(td, img->pixels);
        std::string e = ok ? "" : out->geterror();
        ok = out->close() && ok;
        if (!ok) {
            std::remove(tmp.c_str());
            return vx_fail(err, VX_ERR_IO, VX_NO_OFFSET, "%s: %s", path, e.c_str());
        }
        if (std::rename(tmp.c_str(), path) != 0) {
            std::remove(tmp.c_str());
            return vx_fail(err, VX_ERR_IO, VX_NO_OFFSET, "%s: rename failed: %s", path, std::strerror(errno));
        }
    } catch (const std::exception& ex) {
        return vx_fail(err, VX_ERR_IO, VX_NO_OFFSET, "%s: %s", path, ex.what());
    }
    return VX_OK;
}

extern "C" __attribute__((visibility("default"))) vx_result vx__image_oiio_read(const char* path, vx_image_type type,
                                                                                 uint32_t max_dim, uint32_t* width,
                                                                                 uint32_t* height, uint32_t* channels,
                                                                                 void** out_pixels, vx_error* err) {
    try {
        auto in = ImageInput::open(path);
        if (!in) return vx_fail(err, VX_ERR_IO, VX_NO_OFFSET, "%s: %s", path, OIIO::geterror().c_str());
        const ImageSpec& spec = in->spec();
        if (spec.width <= 0 || spec.height <= 0 || (uint32_t)spec.width > max_dim || (uint32_t)spec.height > max_dim ||
            spec.nchannels < 1 || spec.nchannels > 16)
            return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "%s: image %dx%dx%d outside the limits", path, spec.width,
                           spec.height, spec.nchannels);
        size_t n = (size_t)spec.width * spec.height * spec.nchannels;
        size_t bytes;
        if (!vx_mul_size(n, type == VX_IMAGE_F32 ? 4 : 1, &bytes))
            return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "%s: too large", path);
        void* p = vx_alloc(NULL, bytes);
        if (!p) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "%s: out of memory", path);
        TypeDesc td = type == VX_IMAGE_F32 ? TypeDesc::FLOAT : TypeDesc::UINT8;
        if (!in->read_image(0, 0, 0, spec.nchannels, td, p)) {
            vx_free(NULL, p);
            return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "%s: %s", path, in->geterror().c_str());
        }
        *width = (uint32_t)spec.width;
        *height = (uint32_t)spec.height;
        *channels = (uint32_t)spec.nchannels;
        *out_pixels = p;
    } catch (const std::exception& ex) {
        return vx_fail(err, VX_ERR_IO, VX_NO_OFFSET, "%s: %s", path, ex.what());
    }
    return VX_OK;
}
