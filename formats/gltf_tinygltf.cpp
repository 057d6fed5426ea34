// formats/gltf_tinygltf.cpp - the C face of formats/gltf.h over Debian's
// shared tinygltf (-ltinygltf). tinygltf parses the JSON and loads buffers;
// every index, offset and length it hands back is checked again here before
// use, because tinygltf does not validate accessor or buffer-view ranges.
#include "formats/gltf.h"

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>
#ifdef VX_GLTF_STB
#include <stb/stb_image.h>
#endif

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <sys/stat.h>
#include <cstring>
#include <exception>
#include <memory>
#include <string>
#include <vector>

namespace {

// Marks an image whose encoded bytes were kept (decoding is deferred until we
// know the image is a texture the voxels sample: base colour, and
// metallic-roughness or emissive where the factors let them matter; the
// normal and occlusion maps of a model such as DamagedHelmet would cost as
// much to decode as the voxelization itself).
const int kRawImage = -77;

bool keep_encoded_image(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                        const unsigned char* bytes, int size, void*) {
    // Images from a buffer view are fetched (with range checks) later; only
    // bytes tinygltf owns (data URIs, external files) are copied here.
    image->component = kRawImage;
    if (image->bufferView < 0 && bytes && size > 0) image->image.assign(bytes, bytes + size);
    return true;
}

// tinygltf takes a data URI of a media type it does not decode (image/webp,
// image/ktx2) for a file name and warns "File not found : data:image/webp;
// base64,..." (the payload after it), then "Failed to load external 'uri'
// for image[N]": the user learns neither what nor why. Those two lines are
// left out; the image then reaches add_image without bytes, whose warning
// (gltf.image_unreadable) names the image and its media type. Other lines
// stay tinygltf's.
std::string plain_warnings(const std::string& w) {
    static const std::string key = "File not found : data:", ext = "Failed to load external 'uri' for image[";
    std::string out;
    size_t at = 0;
    bool after_data = false;
    while (at < w.size()) {
        size_t nl = w.find('\n', at);
        std::string line = w.substr(at, nl == std::string::npos ? std::string::npos : nl - at);
        at = nl == std::string::npos ? w.size() : nl + 1;
        bool data = line.find(key) != std::string::npos;
        bool skip = data || (after_data && line.compare(0, ext.size(), ext) == 0) || line.empty();
        after_data = data;
        if (skip) continue;
        if (!out.empty()) out += '\n';
        out += line;
    }
    return out;
}

// How a warning names an image's URI: a data URI by its media type only (not
// its payload), a file by its name.
std::string uri_label(const std::string& uri) {
    if (uri.compare(0, 5, "data:") != 0) return "'" + uri + "'";
    size_t e = uri.find_first_of(";,", 5);
    size_t n = e == std::string::npos ? uri.size() - 5 : e - 5;
    return "a data URI of media type '" + uri.substr(5, n < 40 ? n : 40) + "'";
}

bool no_file_exists(const std::string&, void*) { return false; }
std::string same_path(const std::string& p, void*) { return p; }
bool no_file_read(std::vector<unsigned char>*, std::string* err, const std::string& path, void*) {
    if (err) *err += "external file '" + path + "' refused (no_external)\n";
    return false;
}
// External files: only regular files. tinygltf's own reader opens a
// directory (a URI that decodes to "" names the base directory), takes the
// size its stream reports (2^63 - 1) and allocates it.
bool regular_file(const std::string& path) {
    struct stat st;
    return stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}
bool file_exists(const std::string& path, void*) { return regular_file(path); }
bool file_read(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
    if (!regular_file(path)) {
        if (err) *err += "'" + path + "' is not a regular file\n";
        return false;
    }
    return tinygltf::ReadWholeFile(out, err, path, user);
}
bool no_file_write(std::string*, const std::string&, const std::vector<unsigned char>&, void*) { return false; }

struct Ctx {
    const vx_gltf_read_desc* desc;
    const tinygltf::Model* m;
    vx_error* err;
    std::vector<float> pos, col;
    std::vector<uint32_t> mat;
    // per texture slot (kSlots: base colour, metallic-roughness, emissive): the
    // uv of every corner, and per material whether it samples that slot, its
    // KHR_texture_transform as u' = a0 u + a1 v + a2, v' = a3 u + a4 v + a5,
    // and the TEXCOORD set it samples
    std::vector<float> uv[3];
    std::vector<bool> mat_textured[3];
    std::vector<std::array<double, 6>> mat_uvx[3];
    std::vector<int> mat_texcoord[3];
    std::vector<vx_gltf_light> lights;
    bool any_color = false;
    bool origin_set = false;
    double origin[3] = {0, 0, 0}; // vx_gltf_mesh.origin
    // the largest rounding step a world position took on the way (gltf.h:
    // the warning gltf.position_precision)
    double wstep = 0;
    uint64_t max_tris;
    uint32_t instances = 0;
};

vx_result fail(Ctx& c, vx_result r, const char* fmt, ...) {
    if (c.err) {
        char buf[192];
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(buf, sizeof buf, fmt, ap);
        va_end(ap);
        vx_fail(c.err, r, VX_NO_OFFSET, "%s", buf);
    }
    return r;
}

// A checked view of an accessor's elements.
struct Acc {
    const uint8_t* base = nullptr; // nullptr: no buffer view, every value is 0
    std::shared_ptr<std::vector<uint8_t>> dense; // a sparse accessor's values, materialised
    size_t stride = 0, count = 0;
    int comps = 0, ctype = 0;
    bool norm = false;
    double get(size_t i, int c) const {
        if (!base) return 0.0;
        const uint8_t* p = base + i * stride;
        switch (ctype) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT: { float v; memcpy(&v, p + 4 * c, 4); return v; }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: { double v = p[c]; return norm ? v / 255.0 : v; }
        case TINYGLTF_COMPONENT_TYPE_BYTE: { double v = (int8_t)p[c]; return norm ? std::fmax(v / 127.0, -1.0) : v; }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { uint16_t v; memcpy(&v, p + 2 * c, 2); return norm ? v / 65535.0 : v; }
        case TINYGLTF_COMPONENT_TYPE_SHORT: { int16_t v; memcpy(&v, p + 2 * c, 2); return norm ? std::fmax(v / 32767.0, -1.0) : v; }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { uint32_t v; memcpy(&v, p + 4 * c, 4); return v; }
        default: return 0.0;
        }
    }
    uint32_t index(size_t i) const {
        if (!base) return 0;
        const uint8_t* p = base + i * stride;
        if (ctype == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) return p[0];
        if (ctype == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) { uint16_t v; memcpy(&v, p, 2); return v; }
        uint32_t v;
        memcpy(&v, p, 4);
        return v;
    }
};

size_t comp_size(int ctype) {
    switch (ctype) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT: case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_FLOAT: case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return 4;
    default: return 0;
    }
}

// The bytes [offset, offset + n) of buffer view bv, or nullptr.
const uint8_t* view_bytes(const tinygltf::Model& m, int bv, size_t offset, size_t n) {
    if (bv < 0 || (size_t)bv >= m.bufferViews.size()) return nullptr;
    const tinygltf::BufferView& v = m.bufferViews[(size_t)bv];
    if (v.buffer < 0 || (size_t)v.buffer >= m.buffers.size()) return nullptr;
    const std::vector<unsigned char>& d = m.buffers[(size_t)v.buffer].data;
    size_t end;
    if (v.byteOffset > d.size() || v.byteLength > d.size() - v.byteOffset || !vx_add_size(offset, n, &end) ||
        end > v.byteLength)
        return nullptr;
    return d.data() + v.byteOffset + offset;
}

// A sparse accessor (glTF 2.0, 3.6.2.3): its base values (from the buffer
// view, or zeros) with `count` elements replaced at strictly increasing
// indices, materialised tightly packed in the accessor's component type.
vx_result apply_sparse(Ctx& c, int idx, const char* what, Acc* out) {
    const tinygltf::Model& m = *c.m;
    const tinygltf::Accessor& a = m.accessors[(size_t)idx];
    size_t cs = comp_size(out->ctype), elem = (size_t)out->comps * cs, total;
    if (!vx_mul_size(elem, out->count, &total) || total > ((size_t)1 << 31))
        return fail(c, VX_ERR_LIMIT, "%s: sparse accessor %d: %zu elements are too many", what, idx, out->count);
    size_t n = a.sparse.count > 0 ? (size_t)a.sparse.count : 0;
    if (a.sparse.count < 1 || n > out->count)
        return fail(c, VX_ERR_BAD_FORMAT, "%s: sparse accessor %d: %d replaced elements of %zu", what, idx,
                    a.sparse.count, out->count);
    size_t ics = a.sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE    ? 1
                 : a.sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 2
                 : a.sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT   ? 4
                                                                                            : 0;
    if (ics == 0)
        return fail(c, VX_ERR_BAD_FORMAT, "%s: sparse accessor %d: indices of component type %d", what, idx,
                    a.sparse.indices.componentType);
    const uint8_t* ib = a.sparse.indices.byteOffset >= 0
                            ? view_bytes(m, a.sparse.indices.bufferView, (size_t)a.sparse.indices.byteOffset, n * ics)
                            : nullptr;
    const uint8_t* vb = a.sparse.values.byteOffset >= 0
                            ? view_bytes(m, a.sparse.values.bufferView, (size_t)a.sparse.values.byteOffset, n * elem)
                            : nullptr;
    if (!ib || !vb)
        return fail(c, VX_ERR_BAD_FORMAT, "%s: sparse accessor %d: its %s lie outside their buffer view", what, idx,
                    !ib ? "indices" : "values");
    auto dense = std::make_shared<std::vector<uint8_t>>(total, 0);
    if (out->base)
        for (size_t i = 0; i < out->count; i++) memcpy(dense->data() + i * elem, out->base + i * out->stride, elem);
    uint64_t prev = 0;
    for (size_t k = 0; k < n; k++) {
        uint64_t at = 0;
        if (ics == 1) at = ib[k];
        else if (ics == 2) { uint16_t v; memcpy(&v, ib + 2 * k, 2); at = v; }
        else { uint32_t v; memcpy(&v, ib + 4 * k, 4); at = v; }
        if (at >= out->count || (k > 0 && at <= prev))
            return fail(c, VX_ERR_BAD_FORMAT,
                        "%s: sparse accessor %d: index %llu (element %zu) is out of range or not increasing", what,
                        idx, (unsigned long long)at, k);
        memcpy(dense->data() + at * elem, vb + k * elem, elem);
        prev = at;
    }
    out->dense = dense;
    out->base = dense->data();
    out->stride = elem;
    return VX_OK;
}

vx_result get_acc(Ctx& c, int idx, const char* what, Acc* out) {
    const tinygltf::Model& m = *c.m;
    if (idx < 0 || (size_t)idx >= m.accessors.size())
        return fail(c, VX_ERR_BAD_FORMAT, "%s: accessor %d out of range (%zu accessors)", what, idx, m.accessors.size());
    const tinygltf::Accessor& a = m.accessors[(size_t)idx];
    int comps = tinygltf::GetNumComponentsInType((uint32_t)a.type);
    size_t cs = comp_size(a.componentType);
    if (comps <= 0 || comps > 4 || cs == 0)
        return fail(c, VX_ERR_BAD_FORMAT, "%s: accessor %d has type %d / component type %d", what, idx, a.type,
                    a.componentType);
    out->comps = comps;
    out->ctype = a.componentType;
    out->norm = a.normalized;
    out->count = a.count;
    out->base = nullptr;
    out->dense.reset();
    if (a.bufferView < 0) return a.sparse.isSparse ? apply_sparse(c, idx, what, out) : VX_OK;
    if ((size_t)a.bufferView >= m.bufferViews.size())
        return fail(c, VX_ERR_BAD_FORMAT, "%s: accessor %d names buffer view %d of %zu", what, idx, a.bufferView,
                    m.bufferViews.size());
    const tinygltf::BufferView& bv = m.bufferViews[(size_t)a.bufferView];
    if (bv.buffer < 0 || (size_t)bv.buffer >= m.buffers.size())
        return fail(c, VX_ERR_BAD_FORMAT, "%s: buffer view %d names buffer %d of %zu", what, a.bufferView, bv.buffer,
                    m.buffers.size());
    const std::vector<unsigned char>& data = m.buffers[(size_t)bv.buffer].data;
    if (bv.byteOffset > data.size() || bv.byteLength > data.size() - bv.byteOffset)
        return fail(c, VX_ERR_BAD_FORMAT, "buffer view %d: bytes %zu + %zu outside buffer %d of %zu bytes",
                    a.bufferView, bv.byteOffset, bv.byteLength, bv.buffer, data.size());
    size_t elem = (size_t)comps * cs;
    size_t stride = bv.byteStride ? bv.byteStride : elem;
    if (stride < elem || stride > 252 + elem)
        return fail(c, VX_ERR_BAD_FORMAT, "buffer view %d: byte stride %zu for %zu-byte elements", a.bufferView,
                    stride, elem);
    if (a.count > 0) {
        size_t need, span;
        if (!vx_mul_size(stride, a.count - 1, &span) || !vx_add_size(span, elem, &need) ||
            !vx_add_size(need, a.byteOffset, &need) || need > bv.byteLength)
            return fail(c, VX_ERR_BAD_FORMAT, "%s: accessor %d: %zu elements at offset %zu overrun buffer view %d (%zu bytes)",
                        what, idx, a.count, a.byteOffset, a.bufferView, bv.byteLength);
    }
    out->base = data.data() + bv.byteOffset + a.byteOffset;
    out->stride = stride;
    return a.sparse.isSparse ? apply_sparse(c, idx, what, out) : VX_OK;
}

typedef double Mat[16]; // column-major like glTF

void mat_mul(const double* a, const double* b, double* o) {
    double r[16];
    for (int col = 0; col < 4; col++)
        for (int row = 0; row < 4; row++) {
            double s = 0;
            for (int k = 0; k < 4; k++) s += a[k * 4 + row] * b[col * 4 + k];
            r[col * 4 + row] = s;
        }
    memcpy(o, r, sizeof r);
}

void node_local(const tinygltf::Node& n, double* out) {
    if (n.matrix.size() == 16) {
        for (int i = 0; i < 16; i++) out[i] = n.matrix[(size_t)i];
        return;
    }
    double t[3] = {0, 0, 0}, q[4] = {0, 0, 0, 1}, s[3] = {1, 1, 1};
    if (n.translation.size() == 3) for (int i = 0; i < 3; i++) t[i] = n.translation[(size_t)i];
    if (n.rotation.size() == 4) for (int i = 0; i < 4; i++) q[i] = n.rotation[(size_t)i];
    if (n.scale.size() == 3) for (int i = 0; i < 3; i++) s[i] = n.scale[(size_t)i];
    double x = q[0], y = q[1], z = q[2], w = q[3];
    double r[9] = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w),     2 * (x * z - y * w),
                   2 * (x * y - z * w),     1 - 2 * (x * x + z * z), 2 * (y * z + x * w),
                   2 * (x * z + y * w),     2 * (y * z - x * w),     1 - 2 * (x * x + y * y)}; // column-major
    for (int col = 0; col < 3; col++) {
        for (int row = 0; row < 3; row++) out[col * 4 + row] = r[col * 3 + row] * s[col];
        out[col * 4 + 3] = 0;
    }
    out[12] = t[0];
    out[13] = t[1];
    out[14] = t[2];
    out[15] = 1;
}

vx_result add_primitive(Ctx& c, const tinygltf::Primitive& p, const double* M, uint32_t mesh_idx) {
    const tinygltf::Model& m = *c.m;
    if (p.mode != TINYGLTF_MODE_TRIANGLES && p.mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        p.mode != TINYGLTF_MODE_TRIANGLE_FAN) {
        vx_log(c.desc->logger, VX_LOG_WARN, "gltf.skip_primitive", "mesh %u: primitive mode %d (points/lines) skipped",
               mesh_idx, p.mode);
        return VX_OK;
    }
    auto pit = p.attributes.find("POSITION");
    if (pit == p.attributes.end()) return fail(c, VX_ERR_BAD_FORMAT, "mesh %u: primitive without POSITION", mesh_idx);
    Acc pos, idx, uv[3], col;
    vx_result r = get_acc(c, pit->second, "POSITION", &pos);
    if (r) return r;
    if (pos.comps != 3) return fail(c, VX_ERR_BAD_FORMAT, "mesh %u: POSITION has %d components", mesh_idx, pos.comps);
    uint32_t mat = UINT32_MAX;
    if (p.material >= 0) {
        if ((size_t)p.material >= m.materials.size())
            return fail(c, VX_ERR_BAD_FORMAT, "mesh %u: material %d of %zu", mesh_idx, p.material, m.materials.size());
        mat = (uint32_t)p.material;
    }
    bool has_uv[3] = {false, false, false}, has_col = false;
    for (int sl = 0; sl < 3; sl++) {
        if (mat == UINT32_MAX || !c.mat_textured[sl][mat]) continue;
        int set = c.mat_texcoord[sl][mat];
        auto it = p.attributes.find("TEXCOORD_" + std::to_string(set));
        if (it != p.attributes.end()) {
            if ((r = get_acc(c, it->second, "TEXCOORD", &uv[sl]))) return r;
            if (uv[sl].comps != 2 || uv[sl].count != pos.count)
                return fail(c, VX_ERR_BAD_FORMAT, "mesh %u: TEXCOORD_%d has %d components, %zu of %zu vertices",
                            mesh_idx, set, uv[sl].comps, uv[sl].count, pos.count);
            has_uv[sl] = true;
        }
    }
    auto cit = p.attributes.find("COLOR_0");
    if (cit != p.attributes.end()) {
        if ((r = get_acc(c, cit->second, "COLOR_0", &col))) return r;
        if ((col.comps != 3 && col.comps != 4) || col.count != pos.count)
            return fail(c, VX_ERR_BAD_FORMAT, "mesh %u: COLOR_0 has %d components, %zu of %zu vertices", mesh_idx,
                        col.comps, col.count, pos.count);
        has_col = true;
        c.any_color = true;
    }
    size_t n = pos.count;
    bool indexed = p.indices >= 0;
    if (indexed) {
        if ((r = get_acc(c, p.indices, "indices", &idx))) return r;
        if (idx.comps != 1 || (idx.ctype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
                               idx.ctype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
                               idx.ctype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
            return fail(c, VX_ERR_BAD_FORMAT, "mesh %u: indices of component type %d", mesh_idx, idx.ctype);
        n = idx.count;
    }
    size_t tris = 0;
    if (p.mode == TINYGLTF_MODE_TRIANGLES) tris = n / 3;
    else if (n >= 3) tris = n - 2;
    if (tris > c.max_tris || c.mat.size() > c.max_tris - tris)
        return fail(c, VX_ERR_LIMIT, "more than %llu triangles", (unsigned long long)c.max_tris);
    // negative determinant: mirrored instance, flip winding so normals stay outward
    double det = M[0] * (M[5] * M[10] - M[6] * M[9]) - M[4] * (M[1] * M[10] - M[2] * M[9]) +
                 M[8] * (M[1] * M[6] - M[2] * M[5]);
    bool flip = det < 0;
    for (size_t t = 0; t < tris; t++) {
        size_t k[3];
        if (p.mode == TINYGLTF_MODE_TRIANGLES) { k[0] = 3 * t; k[1] = 3 * t + 1; k[2] = 3 * t + 2; }
        else if (p.mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
            k[0] = t; k[1] = t + 1 + (t & 1); k[2] = t + 2 - (t & 1);
        } else { k[0] = t + 1; k[1] = t + 2; k[2] = 0; }
        if (flip) { size_t s = k[1]; k[1] = k[2]; k[2] = s; }
        for (int v = 0; v < 3; v++) {
            size_t vi = indexed ? idx.index(k[v]) : k[v];
            if (vi >= pos.count)
                return fail(c, VX_ERR_BAD_FORMAT, "mesh %u: index %zu out of range (%zu vertices)", mesh_idx, vi,
                            pos.count);
            double x = pos.get(vi, 0), y = pos.get(vi, 1), z = pos.get(vi, 2), w[3];
            for (int a = 0; a < 3; a++) {
                w[a] = M[a] * x + M[4 + a] * y + M[8 + a] * z + M[12 + a];
                if (!std::isfinite(w[a]) || std::fabs(w[a]) > 3.0e38)
                    return fail(c, VX_ERR_BAD_FORMAT, "mesh %u: vertex %zu has a non-finite position", mesh_idx, vi);
                // rounding: the file's float coordinates (2^-24 of each
                // term of the linear part) and the double sum (2^-52 of
                // every term, the translation's too); the float store of
                // w - origin below is near the origin and keeps 2^-24 of
                // the scene's own size
                double lin = std::fabs(M[a] * x) + std::fabs(M[4 + a] * y) + std::fabs(M[8 + a] * z);
                double st = (pos.ctype == TINYGLTF_COMPONENT_TYPE_FLOAT ? lin * 0x1p-24 : 0.0) +
                            (lin + std::fabs(M[12 + a])) * 0x1p-52;
                if (st > c.wstep) c.wstep = st;
            }
            if (!c.origin_set) { // gltf.h: vx_gltf_mesh.origin
                c.origin_set = true;
                for (int a = 0; a < 3; a++)
                    c.origin[a] = std::fabs(w[a]) >= VX_GLTF_ORIGIN_FAR ? 1024.0 * std::nearbyint(w[a] / 1024.0) : 0.0;
            }
            for (int a = 0; a < 3; a++) c.pos.push_back((float)(w[a] - c.origin[a]));
            for (int sl = 0; sl < 3; sl++) {
                if (has_uv[sl]) {
                    const std::array<double, 6>& x = c.mat_uvx[sl][mat];
                    double u0 = uv[sl].get(vi, 0), v0 = uv[sl].get(vi, 1);
                    c.uv[sl].push_back((float)(x[0] * u0 + x[1] * v0 + x[2]));
                    c.uv[sl].push_back((float)(x[3] * u0 + x[4] * v0 + x[5]));
                } else {
                    c.uv[sl].push_back(0.f);
                    c.uv[sl].push_back(0.f);
                }
            }
            for (int ch = 0; ch < 4; ch++)
                c.col.push_back(has_col ? (ch < col.comps ? (float)col.get(vi, ch) : 1.f) : 1.f);
        }
        c.mat.push_back(mat);
    }
    return VX_OK;
}

bool ext_number(const tinygltf::Value& v, double* out);

// n numbers of extras member `key` into out, each in [lo, hi] (hi_open: below
// hi); false when the member is not that (an array for n > 1).
bool extras_numbers(const tinygltf::Value& v, const char* key, int n, double lo, double hi, bool hi_open, double* out) {
    const tinygltf::Value& x = v.Get(key);
    if (n > 1 && (!x.IsArray() || x.ArrayLen() != (size_t)n)) return false;
    for (int k = 0; k < n; k++) {
        double d = 0;
        if (!ext_number(n > 1 ? x.Get(k) : x, &d) || !(d >= lo && (hi_open ? d < hi : d <= hi))) return false;
        out[k] = d;
    }
    return true;
}

// voxkit's record of the light in its extras (gltf.h: vx_gltf_light, written
// by svo_info --to-glb), over the punctual values in *g; M the node's world
// matrix (a rect's tangent is its +X axis).
vx_result voxkit_light(Ctx& c, const tinygltf::Light& L, const std::string& who, const double* M, vx_gltf_light* g) {
    if (c.desc->punctual_only || !L.extras.IsObject() || !L.extras.Has("voxkit_light")) return VX_OK;
    const tinygltf::Value& v = L.extras.Get("voxkit_light");
    if (!v.IsObject() || !v.Has("type") || !v.Get("type").IsString())
        return fail(c, VX_ERR_BAD_FORMAT, "%s: extras.voxkit_light must be an object with a type string", who.c_str());
    static const char* const names[5] = {"directional", "point", "spot", "sphere", "rect"};
    // the punctual type svo_info writes each as
    static const uint32_t punctual[5] = {VX_GLTF_LIGHT_DIRECTIONAL, VX_GLTF_LIGHT_POINT, VX_GLTF_LIGHT_SPOT,
                                         VX_GLTF_LIGHT_POINT, VX_GLTF_LIGHT_SPOT};
    const std::string& t = v.Get("type").Get<std::string>();
    uint32_t type = 5;
    for (uint32_t k = 0; k < 5; k++)
        if (t == names[k]) type = k;
    if (type == 5 || punctual[type] != g->type) {
        // a newer voxkit's type, or a light retyped by an editor that kept
        // its extras: the punctual light is what the file says
        vx_log(c.desc->logger, VX_LOG_WARN, "gltf.light_extras",
               "%s: extras.voxkit_light of type '%.20s' does not fit a %s light: ignored", who.c_str(), t.c_str(),
               names[g->type]);
        return VX_OK;
    }
    vx_gltf_light x = *g;
    x.type = type;
    x.voxkit = true;
    const double big = 1e30, half_pi = 1.5707963267948966;
    struct member {
        const char* key;
        bool used, required; // by this type
        int n;
        double lo, hi;
        bool hi_open;
        double* out;
        const char* rule;
    };
    bool sphere = type == VX_GLTF_LIGHT_SPHERE, rect = type == VX_GLTF_LIGHT_RECT;
    bool area = sphere || rect;
    double cones[2] = {g->inner_cone, g->outer_cone};
    const member ms[] = {
        {"radiance", area, area, 1, 0, big, false, &x.intensity, "a number >= 0"},
        {"intensity", !area, false, 1, 0, big, false, &x.intensity, "a number >= 0"},
        {"radius", sphere || type == VX_GLTF_LIGHT_POINT || type == VX_GLTF_LIGHT_SPOT, sphere, 1, 0, big, false,
         &x.radius, "a number >= 0"},
        {"size", rect, rect, 2, 0, big, false, x.size, "two numbers >= 0"},
        {"angular_diameter", type == VX_GLTF_LIGHT_DIRECTIONAL, false, 1, 0, 3.141592653589793, true,
         &x.angular_diameter, "a number in [0, pi)"},
        {"inner_cone", type == VX_GLTF_LIGHT_SPOT, false, 1, 0, half_pi, false, &cones[0], "a number in [0, pi/2]"},
        {"outer_cone", type == VX_GLTF_LIGHT_SPOT, false, 1, 0, half_pi, false, &cones[1], "a number in [0, pi/2]"},
        {"color", true, false, 3, 0, big, false, x.color, "three numbers >= 0"},
    };
    for (const member& m : ms) {
        if (!m.used) continue;
        if (!v.Has(m.key)) {
            if (m.required)
                return fail(c, VX_ERR_BAD_FORMAT, "%s: extras.voxkit_light of type %s needs \"%s\"", who.c_str(),
                            names[type], m.key);
            continue;
        }
        if (!extras_numbers(v, m.key, m.n, m.lo, m.hi, m.hi_open, m.out))
            return fail(c, VX_ERR_BAD_FORMAT, "%s: extras.voxkit_light's \"%s\" must be %s", who.c_str(), m.key, m.rule);
    }
    if (type == VX_GLTF_LIGHT_SPOT) {
        if (!(cones[0] <= cones[1]))
            return fail(c, VX_ERR_BAD_FORMAT, "%s: extras.voxkit_light's cones %g, %g must satisfy inner <= outer",
                        who.c_str(), cones[0], cones[1]);
        x.inner_cone = cones[0], x.outer_cone = cones[1];
    }
    if (area) { // the punctual light's range and cones are the approximation's
        x.range = 0;
        x.inner_cone = x.outer_cone = 0;
    }
    if (rect) {
        double len = 0;
        for (int k = 0; k < 3; k++) len += M[k] * M[k];
        len = std::sqrt(len);
        if (!(len > 0 && std::isfinite(len)))
            return fail(c, VX_ERR_BAD_FORMAT, "%s: the node's transform leaves the rect light no tangent (+X)", who.c_str());
        for (int k = 0; k < 3; k++) x.tangent[k] = M[k] / len;
    }
    *g = x;
    return VX_OK;
}

// A KHR_lights_punctual light placed by node (world matrix M, column-major).
vx_result add_light(Ctx& c, int node, int li, const double* M) {
    const tinygltf::Model& m = *c.m;
    if (li < 0 || (size_t)li >= m.lights.size())
        return fail(c, VX_ERR_BAD_FORMAT, "node %d: KHR_lights_punctual light %d of %zu", node, li, m.lights.size());
    const tinygltf::Light& L = m.lights[(size_t)li];
    std::string who = "light " + std::to_string(li);
    if (!L.name.empty()) who += " ('" + L.name.substr(0, 60) + "')";
    who += " on node " + std::to_string(node);
    vx_gltf_light g;
    memset(&g, 0, sizeof g);
    g.index = (uint32_t)li;
    g.node = (uint32_t)node;
    snprintf(g.name, sizeof g.name, "%s", L.name.c_str());
    if (L.type == "directional") g.type = VX_GLTF_LIGHT_DIRECTIONAL;
    else if (L.type == "point") g.type = VX_GLTF_LIGHT_POINT;
    else if (L.type == "spot") g.type = VX_GLTF_LIGHT_SPOT;
    else return fail(c, VX_ERR_BAD_FORMAT, "%s: unknown type '%.40s'", who.c_str(), L.type.c_str());
    if (!L.color.empty() && L.color.size() != 3) return fail(c, VX_ERR_BAD_FORMAT, "%s: color has %zu values", who.c_str(), L.color.size());
    for (int k = 0; k < 3; k++) {
        g.color[k] = L.color.empty() ? 1.0 : L.color[(size_t)k];
        if (!(g.color[k] >= 0 && g.color[k] <= 1e30))
            return fail(c, VX_ERR_BAD_FORMAT, "%s: colour %g is negative or not finite", who.c_str(), g.color[k]);
    }
    g.intensity = L.intensity;
    if (!(g.intensity >= 0 && g.intensity <= 1e30))
        return fail(c, VX_ERR_BAD_FORMAT, "%s: negative or non-finite intensity %g", who.c_str(), g.intensity);
    g.range = L.range; // tinygltf: 0 when absent
    if (!(g.range >= 0 && g.range <= 1e30))
        return fail(c, VX_ERR_BAD_FORMAT, "%s: range %g must be positive", who.c_str(), g.range);
    if (g.type == VX_GLTF_LIGHT_SPOT) {
        g.inner_cone = L.spot.innerConeAngle, g.outer_cone = L.spot.outerConeAngle;
        if (!(g.inner_cone >= 0 && g.inner_cone < g.outer_cone && g.outer_cone <= 1.5707963267948966))
            return fail(c, VX_ERR_BAD_FORMAT, "%s: spot cones %g, %g must satisfy 0 <= inner < outer <= pi/2", who.c_str(),
                        g.inner_cone, g.outer_cone);
    }
    double len = 0;
    for (int k = 0; k < 3; k++) {
        g.position[k] = M[12 + k];
        g.direction[k] = -M[8 + k]; // the node's -Z axis
        len += g.direction[k] * g.direction[k];
        if (!std::isfinite(g.position[k]) || std::fabs(g.position[k]) > 1e30)
            return fail(c, VX_ERR_BAD_FORMAT, "%s: the node puts it at a non-finite position", who.c_str());
    }
    len = std::sqrt(len);
    if (g.type != VX_GLTF_LIGHT_POINT && !(len > 0 && std::isfinite(len)))
        return fail(c, VX_ERR_BAD_FORMAT, "%s: the node's transform leaves it no direction", who.c_str());
    for (int k = 0; k < 3; k++) g.direction[k] = len > 0 && std::isfinite(len) ? g.direction[k] / len : 0.0;
    vx_result r = voxkit_light(c, L, who, M, &g);
    if (r) return r;
    c.lights.push_back(g);
    return VX_OK;
}

vx_result visit(Ctx& c, int node, const double* parent, std::vector<char>& on_path, int depth) {
    const tinygltf::Model& m = *c.m;
    if (node < 0 || (size_t)node >= m.nodes.size())
        return fail(c, VX_ERR_BAD_FORMAT, "node %d out of range (%zu nodes)", node, m.nodes.size());
    if (on_path[(size_t)node] || depth > 256) return fail(c, VX_ERR_BAD_FORMAT, "node %d: cycle in the node hierarchy", node);
    on_path[(size_t)node] = 1;
    const tinygltf::Node& n = m.nodes[(size_t)node];
    double local[16], world[16];
    node_local(n, local);
    mat_mul(parent, local, world);
    vx_result r = VX_OK;
    if (n.mesh >= 0) {
        if ((size_t)n.mesh >= m.meshes.size()) {
            r = fail(c, VX_ERR_BAD_FORMAT, "node %d: mesh %d of %zu", node, n.mesh, m.meshes.size());
        } else {
            c.instances++;
            for (const tinygltf::Primitive& p : m.meshes[(size_t)n.mesh].primitives)
                if ((r = add_primitive(c, p, world, (uint32_t)n.mesh))) break;
        }
    }
    auto le = n.extensions.find("KHR_lights_punctual");
    if (!r && le != n.extensions.end()) {
        const tinygltf::Value& v = le->second;
        double li = -1;
        if (!v.IsObject() || !v.Has("light") || !ext_number(v.Get("light"), &li) || li != std::floor(li) || li < 0 || li > 1e9)
            r = fail(c, VX_ERR_BAD_FORMAT, "node %d: KHR_lights_punctual needs a light index", node);
        else
            r = add_light(c, node, (int)li, world);
    }
    for (size_t i = 0; !r && i < n.children.size(); i++) r = visit(c, n.children[i], world, on_path, depth + 1);
    on_path[(size_t)node] = 0;
    return r;
}

uint32_t be32(const uint8_t* p) { return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3]; }

// Image size from the PNG or JPEG header, so a forged size never reaches the
// decoder's allocation. false: not a PNG/JPEG we can size.
bool sniff_size(const uint8_t* b, size_t n, uint32_t* w, uint32_t* h) {
    static const uint8_t png[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    if (n >= 24 && memcmp(b, png, 8) == 0 && memcmp(b + 12, "IHDR", 4) == 0) {
        *w = be32(b + 16);
        *h = be32(b + 20);
        return true;
    }
    if (n >= 4 && b[0] == 0xFF && b[1] == 0xD8) {
        size_t i = 2;
        while (i + 4 <= n) {
            if (b[i] != 0xFF) return false;
            uint8_t mk = b[i + 1];
            if (mk == 0xFF) { i++; continue; }
            if (mk == 0xD8 || mk == 0x01 || (mk >= 0xD0 && mk <= 0xD7)) { i += 2; continue; }
            size_t len = (size_t)b[i + 2] << 8 | b[i + 3];
            if (len < 2) return false;
            if (mk >= 0xC0 && mk <= 0xCF && mk != 0xC4 && mk != 0xC8 && mk != 0xCC) {
                if (i + 9 > n || len < 7) return false;
                *h = (uint32_t)b[i + 5] << 8 | b[i + 6];
                *w = (uint32_t)b[i + 7] << 8 | b[i + 8];
                return true;
            }
            if (len > n - i - 2) return false;
            i += 2 + len;
        }
    }
    return false;
}

// A number of an extension object: absent keeps *out; present must be a finite number.
bool ext_number(const tinygltf::Value& v, double* out) {
    if (!v.IsNumber() && !v.IsInt()) return false;
    double d = v.IsInt() ? (double)v.GetNumberAsInt() : v.GetNumberAsDouble();
    if (!std::isfinite(d)) return false;
    *out = d;
    return true;
}

// KHR_texture_transform on a texture info: uv' = T R S uv with
// T the offset, R the rotation in radians with rows [cos sin; -sin cos]
// (the extension's matrix read row by row, as viewers that pass Khronos'
// TextureTransformTest apply it) and S the scale, and an optional texCoord
// that replaces the texture info's.
vx_result texture_transform(Ctx& c, size_t mat, const tinygltf::Value& ext, std::array<double, 6>* x, int* texcoord) {
    double off[2] = {0, 0}, sc[2] = {1, 1}, rot = 0;
    bool ok = ext.IsObject();
    if (ok && ext.Has("offset")) {
        const tinygltf::Value& o = ext.Get("offset");
        ok = o.IsArray() && o.ArrayLen() == 2 && ext_number(o.Get(0), &off[0]) && ext_number(o.Get(1), &off[1]);
    }
    if (ok && ext.Has("scale")) {
        const tinygltf::Value& o = ext.Get("scale");
        ok = o.IsArray() && o.ArrayLen() == 2 && ext_number(o.Get(0), &sc[0]) && ext_number(o.Get(1), &sc[1]);
    }
    if (ok && ext.Has("rotation")) ok = ext_number(ext.Get("rotation"), &rot);
    if (ok && ext.Has("texCoord")) {
        double t = 0;
        ok = ext_number(ext.Get("texCoord"), &t) && t >= 0 && t <= 255 && t == std::floor(t);
        if (ok) *texcoord = (int)t;
    }
    if (!ok)
        return fail(c, VX_ERR_BAD_FORMAT,
                    "material %zu: KHR_texture_transform: offset and scale must be two numbers, rotation a number, "
                    "texCoord a set index",
                    mat);
    double cs = std::cos(rot), sn = std::sin(rot);
    *x = {cs * sc[0], sn * sc[1], off[0], -sn * sc[0], cs * sc[1], off[1]};
    return VX_OK;
}

vx_result decode_image(Ctx& c, int img_idx, vx_gltf_image* out) {
    const tinygltf::Model& m = *c.m;
    const tinygltf::Image& im = m.images[(size_t)img_idx];
    const uint8_t* bytes = nullptr;
    size_t n = 0;
    if (im.bufferView >= 0) {
        if ((size_t)im.bufferView >= m.bufferViews.size())
            return fail(c, VX_ERR_BAD_FORMAT, "image %d: buffer view %d of %zu", img_idx, im.bufferView, m.bufferViews.size());
        const tinygltf::BufferView& bv = m.bufferViews[(size_t)im.bufferView];
        if (bv.buffer < 0 || (size_t)bv.buffer >= m.buffers.size())
            return fail(c, VX_ERR_BAD_FORMAT, "image %d: buffer %d of %zu", img_idx, bv.buffer, m.buffers.size());
        const std::vector<unsigned char>& d = m.buffers[(size_t)bv.buffer].data;
        if (bv.byteOffset > d.size() || bv.byteLength > d.size() - bv.byteOffset)
            return fail(c, VX_ERR_BAD_FORMAT, "image %d: buffer view %d outside its buffer", img_idx, im.bufferView);
        bytes = d.data() + bv.byteOffset;
        n = bv.byteLength;
    } else if (im.component == kRawImage) {
        bytes = im.image.data();
        n = im.image.size();
    }
    uint32_t w = 0, h = 0;
    uint64_t maxpix = c.desc->max_image_pixels ? c.desc->max_image_pixels : (1ull << 26);
    if (!bytes || n == 0 || n > INT32_MAX || !sniff_size(bytes, n, &w, &h) || w == 0 || h == 0) {
        vx_log(c.desc->logger, VX_LOG_WARN, "gltf.image_unreadable",
               "image %d (%s): missing or not a PNG/JPEG, texture ignored", img_idx, uri_label(im.uri).c_str());
        return VX_OK;
    }
    if ((uint64_t)w * h > maxpix)
        return fail(c, VX_ERR_LIMIT, "image %d: %ux%u pixels exceeds the limit of %llu", img_idx, w, h,
                    (unsigned long long)maxpix);
#ifdef VX_GLTF_STB
    // stb_image straight into our block: tinygltf's LoadImageData makes the
    // same calls (16 bits per channel when the file has them, else 8; four
    // channels) and then zero-fills and copies the pixels into a vector of
    // its own, 16 MiB of fresh pages per 2048^2 image (docs/PERFORMANCE.md
    // section 3, per-cell materials)
    int iw = 0, ih = 0, comp = 0;
    bool b16 = stbi_is_16_bit_from_memory(bytes, (int)n) != 0;
    void* dec = b16 ? (void*)stbi_load_16_from_memory(bytes, (int)n, &iw, &ih, &comp, 4) : nullptr;
    if (!dec) b16 = false, dec = stbi_load_from_memory(bytes, (int)n, &iw, &ih, &comp, 4);
    if (!dec || iw <= 0 || ih <= 0 || (uint32_t)iw != w || (uint32_t)ih != h) {
        stbi_image_free(dec);
        vx_log(c.desc->logger, VX_LOG_WARN, "gltf.image_undecodable", "image %d: cannot decode, texture ignored",
               img_idx);
        return VX_OK;
    }
    size_t px = (size_t)w * h;
    uint8_t* rgba = (uint8_t*)vx_alloc(c.desc->alloc, px * 4);
    if (!rgba) {
        stbi_image_free(dec);
        return fail(c, VX_ERR_NOMEM, "image %d: %zu bytes", img_idx, px * 4);
    }
    if (!b16) memcpy(rgba, dec, px * 4);
    else for (size_t i = 0; i < px * 4; i++) rgba[i] = (uint8_t)(((const uint16_t*)dec)[i] >> 8); // the high byte
    stbi_image_free(dec);
#else // without stb's header (libstb-dev): through tinygltf, one copy more
    tinygltf::Image dec;
    std::string e, wn;
    if (!tinygltf::LoadImageData(&dec, img_idx, &e, &wn, 0, 0, bytes, (int)n, nullptr) || dec.width <= 0 ||
        dec.height <= 0 || (uint32_t)dec.width != w || (uint32_t)dec.height != h || dec.component != 4) {
        vx_log(c.desc->logger, VX_LOG_WARN, "gltf.image_undecodable", "image %d: cannot decode, texture ignored",
               img_idx);
        return VX_OK;
    }
    size_t px = (size_t)w * h, bpc = dec.bits == 16 ? 2 : 1;
    if (dec.image.size() != px * 4 * bpc) return VX_OK;
    uint8_t* rgba = (uint8_t*)vx_alloc(c.desc->alloc, px * 4);
    if (!rgba) return fail(c, VX_ERR_NOMEM, "image %d: %zu bytes", img_idx, px * 4);
    if (bpc == 1) memcpy(rgba, dec.image.data(), px * 4);
    else for (size_t i = 0; i < px * 4; i++) rgba[i] = dec.image[2 * i + 1]; // little-endian 16-bit: high byte
#endif
    out->width = w;
    out->height = h;
    out->rgba = rgba;
    return VX_OK;
}

template <typename T>
T* copy_out(const vx_allocator* a, const std::vector<T>& v) {
    T* p = (T*)vx_alloc(a, v.size() * sizeof(T));
    if (p && !v.empty()) memcpy(p, v.data(), v.size() * sizeof(T));
    return p;
}

uint8_t wrap_mode(int w) {
    if (w == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE) return VX_GLTF_WRAP_CLAMP;
    if (w == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT) return VX_GLTF_WRAP_MIRROR;
    return VX_GLTF_WRAP_REPEAT;
}

// Required extensions we can honour (the others change what the data means
// or how it is stored, so the file cannot be read without them).
const char* const kSupported[] = {"KHR_mesh_quantization", "KHR_texture_transform", "KHR_materials_emissive_strength",
                                  "KHR_materials_unlit", "KHR_materials_ior",
                                  "KHR_materials_specular", "KHR_materials_transmission",
                                  "KHR_materials_volume", "KHR_materials_clearcoat",
                                  "KHR_materials_sheen", "KHR_lights_punctual"};

bool ext_supported(const std::string& e) {
    for (const char* s : kSupported)
        if (e == s) return true;
    return false;
}

// The major and minor numbers of an asset version string ("2.0"), or false.
bool version_numbers(const nlohmann::json& v, long* major, long* minor) {
    if (!v.is_string()) return false;
    const std::string& s = v.get_ref<const std::string&>();
    char* end = nullptr;
    *major = strtol(s.c_str(), &end, 10);
    if (end == s.c_str() || *end != '.') return false;
    const char* m = end + 1;
    *minor = strtol(m, &end, 10);
    return end != m;
}

// Compressed geometry (KHR_draco_mesh_compression) that a file uses without
// requiring it must come with an uncompressed fallback: a primitive whose
// POSITION accessor has neither a buffer view nor sparse values has none.
// The primitive's index, or -1 (the mesh's in *mesh).
long draco_without_fallback(const nlohmann::json& j, long* mesh) {
    auto ms = j.find("meshes");
    auto as = j.find("accessors");
    if (ms == j.end() || !ms->is_array()) return -1;
    for (size_t mi = 0; mi < ms->size(); mi++) {
        const nlohmann::json& mj = (*ms)[mi];
        if (!mj.is_object() || !mj.contains("primitives") || !mj["primitives"].is_array()) continue;
        const nlohmann::json& prims = mj["primitives"];
        for (size_t pi = 0; pi < prims.size(); pi++) {
            const nlohmann::json& pj = prims[pi];
            if (!pj.is_object() || !pj.contains("extensions") || !pj["extensions"].is_object() ||
                !pj["extensions"].contains("KHR_draco_mesh_compression"))
                continue;
            const nlohmann::json* pos = nullptr;
            if (pj.contains("attributes") && pj["attributes"].is_object() && pj["attributes"].contains("POSITION"))
                pos = &pj["attributes"]["POSITION"];
            if (!pos || !pos->is_number_unsigned() || as == j.end() || !as->is_array()) continue;
            size_t ai = pos->get<size_t>();
            if (ai >= as->size() || !(*as)[ai].is_object()) continue;
            if (!(*as)[ai].contains("bufferView") && !(*as)[ai].contains("sparse")) {
                *mesh = (long)mi;
                return (long)pi;
            }
        }
    }
    return -1;
}

// Looks at the version and extensionsRequired before tinygltf does:
// tinygltf fails on a Draco or meshopt file with an unrelated message (an
// accessor without a buffer view), reads much of a glTF 1.0 file as an empty
// 2.0 one, and the user should learn what is not supported.
vx_result check_required(const unsigned char* b, size_t size, bool glb, vx_error* err) {
    const unsigned char* js = b;
    size_t jn = size;
    if (glb) {
        vx_rd r = vx_rd_make(b, size);
        uint32_t magic, version, length, clen, ctype;
        if (vx_rd_u32le(&r, &magic) && vx_rd_u32le(&r, &version) && version != 2)
            return vx_fail(err, VX_ERR_UNSUPPORTED, 4,
                           "glb: binary glTF version %u is not supported (version 1 is glTF 1.0's KHR_binary_glTF; "
                           "this reader implements glTF 2.0)", version);
        if (!vx_rd_u32le(&r, &length) || !vx_rd_u32le(&r, &clen) || !vx_rd_u32le(&r, &ctype) ||
            ctype != 0x4E4F534Au || clen > vx_rd_left(&r))
            return VX_OK; // tinygltf reports the malformed header
        js = b + r.off;
        jn = clen;
    }
    nlohmann::json j = nlohmann::json::parse(js, js + jn, nullptr, false);
    if (j.is_discarded() || !j.is_object()) return VX_OK;
    auto as = j.find("asset");
    if (as != j.end() && as->is_object()) {
        long major = 0, minor = 0;
        auto v = as->find("version");
        if (v != as->end() && version_numbers(*v, &major, &minor) && major != 2)
            return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET,
                           "glTF version %s is not supported (this reader implements glTF 2.0)",
                           v->get_ref<const std::string&>().c_str());
        auto mv = as->find("minVersion");
        if (mv != as->end() && version_numbers(*mv, &major, &minor) && (major != 2 || minor > 0))
            return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET,
                           "glTF minVersion %s is not supported (this reader implements glTF 2.0)",
                           mv->get_ref<const std::string&>().c_str());
    }
    auto it = j.find("extensionsRequired");
    if (it != j.end() && it->is_array())
        for (const auto& e : *it)
            if (e.is_string() && !ext_supported(e.get<std::string>()))
                return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "required glTF extension %s is not supported",
                               e.get<std::string>().c_str());
    long mesh = -1, prim = draco_without_fallback(j, &mesh);
    if (prim >= 0)
        return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET,
                       "mesh %ld primitive %ld: KHR_draco_mesh_compression (not supported) without an uncompressed "
                       "fallback (its POSITION accessor has no bufferView)", mesh, prim);
    return VX_OK;
}

// A finite number clamped to [lo, hi], else def.
float clampf(double v, double lo, double hi, double def) {
    if (!std::isfinite(v)) return (float)def;
    return (float)std::fmin(std::fmax(v, lo), hi);
}
// A number field of a material extension, or def.
double ext_field(const tinygltf::Material& mt, const char* ext, const char* key, double def) {
    auto it = mt.extensions.find(ext);
    double v = def;
    if (it != mt.extensions.end() && it->second.IsObject() && it->second.Has(key) && ext_number(it->second.Get(key), &v)) return v;
    return def;
}

// The metallic-roughness model beyond the base colour (gltf.h: vx_gltf_material).
void pbr_rest(const tinygltf::Material& mt, vx_gltf_material* g) {
    const tinygltf::PbrMetallicRoughness& pbr = mt.pbrMetallicRoughness;
    g->metallic = clampf(pbr.metallicFactor, 0, 1, 1); // 0 below when its texture is not decoded
    g->roughness = clampf(pbr.roughnessFactor, 0, 1, 1);
    double strength = ext_field(mt, "KHR_materials_emissive_strength", "emissiveStrength", 1.0);
    if (!(strength >= 0)) strength = 1.0;
    for (int k = 0; k < 3; k++)
        g->emissive[k] = clampf((mt.emissiveFactor.size() == 3 ? mt.emissiveFactor[(size_t)k] : 0.0) * strength, 0, 1e30, 0);
    g->transmission = clampf(ext_field(mt, "KHR_materials_transmission", "transmissionFactor", 0.0), 0, 1, 0);
    g->ior = clampf(ext_field(mt, "KHR_materials_ior", "ior", 1.5), 1, 4, 1.5);
}

// Texture slot sl (0 base colour, 1 metallic-roughness, 2 emissive) of
// material mat: its image decoded (once per image), its sampler's wraps, and
// the uv set and transform the corners of its triangles take (Ctx.uv[sl]).
// out->image stays -1 when the material has no such texture, when images are
// not decoded or when the image cannot be (then warned).
vx_result texture_slot(Ctx& c, size_t mat, int sl, const tinygltf::TextureInfo& info, std::vector<vx_gltf_image>& imgs,
                       std::vector<char>& decoded, vx_gltf_tex* out) {
    const tinygltf::Model& m = *c.m;
    int ti = info.index;
    if (ti < 0 || c.desc->no_images) return VX_OK;
    if ((size_t)ti >= m.textures.size())
        return fail(c, VX_ERR_BAD_FORMAT, "material %zu: texture %d of %zu", mat, ti, m.textures.size());
    const tinygltf::Texture& tex = m.textures[(size_t)ti];
    if (tex.source < 0 || (size_t)tex.source >= m.images.size()) {
        vx_log(c.desc->logger, VX_LOG_WARN, "gltf.texture_no_source", "texture %d has no usable image", ti);
        return VX_OK;
    }
    c.mat_texcoord[sl][mat] = info.texCoord;
    auto tt = info.extensions.find("KHR_texture_transform");
    vx_result r;
    if (tt != info.extensions.end() &&
        (r = texture_transform(c, mat, tt->second, &c.mat_uvx[sl][mat], &c.mat_texcoord[sl][mat])))
        return r;
    if (tex.sampler >= 0 && (size_t)tex.sampler < m.samplers.size()) {
        out->wrap_s = wrap_mode(m.samplers[(size_t)tex.sampler].wrapS);
        out->wrap_t = wrap_mode(m.samplers[(size_t)tex.sampler].wrapT);
    }
    if (!decoded[(size_t)tex.source]) {
        decoded[(size_t)tex.source] = 1;
        if ((r = decode_image(c, tex.source, &imgs[(size_t)tex.source]))) return r;
    }
    if (imgs[(size_t)tex.source].rgba) {
        out->image = tex.source;
        c.mat_textured[sl][mat] = true;
    }
    return VX_OK;
}

// voxkit's record of the sky in the used scene's extras (gltf.h:
// vx_gltf_mesh.sky, written by svo_info --to-glb) into *out; none (or
// punctual_only) leaves *out as it is. Unlike a light's record, whose
// punctual light stands when the record is not understood, the record is
// the only sky the file has: a type this reader does not know is an error,
// not a silently dropped sky.
vx_result voxkit_sky(Ctx& c, const tinygltf::Value& extras, uint32_t scene, vx_sky* out) {
    if (c.desc->punctual_only || !extras.IsObject() || !extras.Has("voxkit_sky")) return VX_OK;
    char who[48];
    snprintf(who, sizeof who, "scene %u extras voxkit_sky", scene);
    const tinygltf::Value& v = extras.Get("voxkit_sky");
    if (!v.IsObject() || !v.Has("type") || !v.Get("type").IsString())
        return fail(c, VX_ERR_BAD_FORMAT, "%s: must be an object with a type string", who);
    static const char* const names[3] = {"constant", "gradient", "envmap"};
    const std::string& t = v.Get("type").Get<std::string>();
    vx_sky k;
    memset(&k, 0, sizeof k); // what the type does not use stays zero (vx_sky_validate's one form)
    for (int i = 0; i < 3; i++)
        if (t == names[i]) k.type = (vx_sky_type)(VX_SKY_CONSTANT + i);
    if (k.type == VX_SKY_DEFAULT)
        return fail(c, VX_ERR_BAD_FORMAT, "%s: unknown type '%.20s' (constant, gradient or envmap)", who, t.c_str());
    bool grad = k.type == VX_SKY_GRADIENT, env = k.type == VX_SKY_ENVMAP;
    struct member {
        const char* key;
        bool used; // by this type, and then required
        int n;
        double lo, hi;
        double* out;
        const char* rule;
    };
    const member ms[] = {
        {"color", !env, 3, 0, 1e30, k.color, "three numbers in [0, 1e30]"},
        {"horizon", grad, 3, 0, 1e30, k.horizon, "three numbers in [0, 1e30]"},
        {"ground", grad, 3, 0, 1e30, k.ground, "three numbers in [0, 1e30]"},
        {"intensity", env, 1, 0, 1e30, &k.intensity, "a number in [0, 1e30]"},
        {"rotation", env, 1, -1e6, 1e6, &k.rotation, "a number of radians within 1e6 of 0"},
    };
    for (const member& mb : ms) {
        if (!mb.used) continue; // other members are ignored, as in a light's record
        if (!v.Has(mb.key)) return fail(c, VX_ERR_BAD_FORMAT, "%s: a %s sky needs \"%s\"", who, t.c_str(), mb.key);
        if (!extras_numbers(v, mb.key, mb.n, mb.lo, mb.hi, false, mb.out))
            return fail(c, VX_ERR_BAD_FORMAT, "%s: \"%s\" must be %s", who, mb.key, mb.rule);
    }
    if (env) {
        if (!v.Has("path")) return fail(c, VX_ERR_BAD_FORMAT, "%s: an envmap sky needs \"path\"", who);
        const tinygltf::Value& p = v.Get("path");
        // a NUL inside (JSON's \u0000) would cut the path where voxkit reads it
        if (!p.IsString() || p.Get<std::string>().empty() || p.Get<std::string>().size() > VX_SKY_PATH_MAX ||
            p.Get<std::string>().find('\0') != std::string::npos)
            return fail(c, VX_ERR_BAD_FORMAT, "%s: \"path\" must be a string of 1 to %u bytes without NUL", who,
                        VX_SKY_PATH_MAX);
        memcpy(k.path, p.Get<std::string>().data(), p.Get<std::string>().size());
    }
    vx_error e = {};
    if (vx_sky_validate(&k, &e) != VX_OK) return fail(c, VX_ERR_BAD_FORMAT, "%s: %s", who, e.msg);
    *out = k;
    return VX_OK;
}

vx_result convert(const vx_gltf_read_desc* desc, const tinygltf::Model& m, vx_gltf_mesh* out, vx_error* err) {
    Ctx c;
    c.desc = desc;
    c.m = &m;
    c.err = err;
    c.max_tris = desc->max_triangles ? desc->max_triangles : (1ull << 28);
    for (const std::string& ext : m.extensionsRequired) {
        if (!ext_supported(ext)) return fail(c, VX_ERR_UNSUPPORTED, "required glTF extension %s is not supported", ext.c_str());
    }
    vx_result r = VX_OK;
    std::vector<vx_gltf_material> mats(m.materials.size());
    std::vector<vx_gltf_image> imgs(m.images.size());
    std::vector<char> decoded(m.images.size(), 0);
    for (int sl = 0; sl < 3; sl++) {
        c.mat_textured[sl].assign(m.materials.size(), false);
        c.mat_uvx[sl].assign(m.materials.size(), std::array<double, 6>{1, 0, 0, 0, 1, 0});
        c.mat_texcoord[sl].assign(m.materials.size(), 0);
    }
    for (size_t i = 0; i < m.materials.size(); i++) {
        const tinygltf::PbrMetallicRoughness& pbr = m.materials[i].pbrMetallicRoughness;
        vx_gltf_material& g = mats[i];
        for (int k = 0; k < 4; k++) {
            double v = pbr.baseColorFactor.size() == 4 ? pbr.baseColorFactor[(size_t)k] : 1.0;
            g.base_color[k] = std::isfinite(v) ? (float)std::fmin(std::fmax(v, 0.0), 1.0) : 1.f;
        }
        g.image = g.metal_rough.image = g.emissive_tex.image = -1;
        g.wrap_s = g.wrap_t = VX_GLTF_WRAP_REPEAT;
        pbr_rest(m.materials[i], &g);
        vx_gltf_tex base = {-1, VX_GLTF_WRAP_REPEAT, VX_GLTF_WRAP_REPEAT};
        const tinygltf::TextureInfo* infos[3] = {&pbr.baseColorTexture, &pbr.metallicRoughnessTexture,
                                                 &m.materials[i].emissiveTexture};
        vx_gltf_tex* outs[3] = {&base, &g.metal_rough, &g.emissive_tex};
        // a texture whose factor makes it moot is not decoded: metallic-roughness
        // when neither metal nor emission nor transmission can make a record
        // (roughness alone is diffuse), emissive under a zero factor
        bool emits = g.emissive[0] > 0 || g.emissive[1] > 0 || g.emissive[2] > 0;
        bool need[3] = {true, g.metallic > 0 || emits || g.transmission > 0, emits};
        for (int sl = 0; sl < 3 && !r; sl++)
            if (need[sl]) r = texture_slot(c, i, sl, *infos[sl], imgs, decoded, outs[sl]);
        if (r) break;
        g.image = base.image;
        g.wrap_s = base.wrap_s;
        g.wrap_t = base.wrap_t;
        // gltf.h: a texture that is not sampled says where the material is
        // metal or glows; its factor alone would make all of it so (the
        // corpus's DamagedHelmet a white lamp, 23,203 emitting voxels)
        if (pbr.metallicRoughnessTexture.index >= 0 && g.metal_rough.image < 0) g.metallic = 0;
        if (m.materials[i].emissiveTexture.index >= 0 && g.emissive_tex.image < 0 &&
            (g.emissive[0] > 0 || g.emissive[1] > 0 || g.emissive[2] > 0)) {
            vx_log(desc->logger, VX_LOG_WARN, "gltf.emissive_texture",
                   "material %zu ('%.40s'): its emissiveTexture is not decoded, so its emission is left out (the "
                   "factor alone would light the whole material)",
                   i, m.materials[i].name.c_str());
            for (int k = 0; k < 3; k++) g.emissive[k] = 0;
        }
    }
    uint32_t scene_used = UINT32_MAX;
    vx_sky sky; // DEFAULT unless the used scene's extras hold voxkit's record (no scene: none)
    memset(&sky, 0, sizeof sky);
    if (!r) {
        std::vector<char> on_path(m.nodes.size(), 0);
        double I[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
        int sc = desc->scene_set ? (int)desc->scene : m.defaultScene;
        if (desc->scene_set && desc->scene >= m.scenes.size()) {
            r = fail(c, VX_ERR_INVALID_ARG, "scene %u requested, the file has %zu", desc->scene, m.scenes.size());
        } else if (sc < 0 && !m.scenes.empty()) {
            sc = 0; // no default scene: the first one
        }
        if (!r && sc >= 0 && (size_t)sc >= m.scenes.size())
            r = fail(c, VX_ERR_BAD_FORMAT, "default scene %d of %zu", sc, m.scenes.size());
        if (!r && sc >= 0) {
            scene_used = (uint32_t)sc;
            r = voxkit_sky(c, m.scenes[(size_t)sc].extras, scene_used, &sky);
            for (int nd : m.scenes[(size_t)sc].nodes)
                if (r || (r = visit(c, nd, I, on_path, 0))) break;
        } else if (!r) {
            // no scenes at all: every root node (not a child of another)
            std::vector<char> child(m.nodes.size(), 0);
            for (const tinygltf::Node& n : m.nodes)
                for (int ch : n.children)
                    if (ch >= 0 && (size_t)ch < m.nodes.size()) child[(size_t)ch] = 1;
            for (size_t i = 0; !r && i < m.nodes.size(); i++)
                if (!child[i]) r = visit(c, (int)i, I, on_path, 0);
        }
    }
    if (!r && !c.mat.empty()) {
        // gltf.h: a scene whose positions rounding moved by more than a
        // quarter of a cell at the default resolution (2^-10 of its
        // extent) has lost its shape before voxelization; far translations
        // (1e30) collapsed a small model to one cell without a word
        // the extent and the farthest coordinate from the stored positions
        // (origin + pos: the float store keeps 2^-24 of the scene's size)
        double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (size_t i = 0; i < c.pos.size(); i++) {
            int a = (int)(i % 3);
            lo[a] = std::min(lo[a], (double)c.pos[i]);
            hi[a] = std::max(hi[a], (double)c.pos[i]);
        }
        double ext = 0, mag = 0;
        for (int a = 0; a < 3; a++) {
            ext = std::max(ext, hi[a] - lo[a]);
            mag = std::max(mag, std::max(std::fabs(c.origin[a] + lo[a]), std::fabs(c.origin[a] + hi[a])));
        }
        if (ext == 0)
            vx_log(desc->logger, VX_LOG_WARN, "gltf.position_precision",
                   "all %zu triangles lie at one point (%.9g %.9g %.9g): the scene has no extent", c.mat.size(),
                   c.origin[0] + lo[0], c.origin[1] + lo[1], c.origin[2] + lo[2]);
        else if (c.wstep > ext * 0x1p-10)
            vx_log(desc->logger, VX_LOG_WARN, "gltf.position_precision",
                   "positions up to %.3g from 0 are rounded by up to %.3g, more than 1/1024 of the scene's extent "
                   "%.3g: its shape is lost to rounding (a node translation or vertex coordinates far from the "
                   "scene's own size)",
                   mag, c.wstep, ext);
    }
    if (!r) {
        bool any_tex[3] = {false, false, false};
        for (int sl = 0; sl < 3; sl++)
            for (bool t : c.mat_textured[sl]) any_tex[sl] = any_tex[sl] || t;
        vx_gltf_mesh o;
        memset(&o, 0, sizeof o);
        o.alloc = desc->alloc;
        o.tri_count = c.mat.size();
        o.scene = scene_used;
        o.sky = sky;
        o.instance_count = c.instances;
        for (int a = 0; a < 3; a++) o.origin[a] = c.origin[a];
        o.pos = copy_out(desc->alloc, c.pos);
        o.material = copy_out(desc->alloc, c.mat);
        float** uvs[3] = {&o.uv, &o.uv_mr, &o.uv_emissive};
        bool uv_nomem = false;
        for (int sl = 0; sl < 3; sl++)
            if (any_tex[sl]) uv_nomem |= !(*uvs[sl] = copy_out(desc->alloc, c.uv[sl]));
        if (c.any_color) o.color = copy_out(desc->alloc, c.col);
        o.material_count = (uint32_t)mats.size();
        o.materials = copy_out(desc->alloc, mats);
        o.image_count = (uint32_t)imgs.size();
        o.images = copy_out(desc->alloc, imgs);
        o.light_count = (uint32_t)c.lights.size();
        o.lights = copy_out(desc->alloc, c.lights);
        if (!o.pos || !o.material || uv_nomem || (c.any_color && !o.color) || !o.materials || !o.images || !o.lights) {
            for (vx_gltf_image& im : imgs) vx_free(desc->alloc, im.rgba);
            imgs.clear();
            if (o.images) o.image_count = 0;
            vx_gltf_mesh_free(&o);
            return fail(c, VX_ERR_NOMEM, "%zu triangles", c.mat.size());
        }
        *out = o;
        return VX_OK;
    }
    for (vx_gltf_image& im : imgs) vx_free(desc->alloc, im.rgba);
    return r;
}

} // namespace

extern "C" vx_result vx_gltf_read(const vx_gltf_read_desc* desc_in, const void* data, size_t size,
                                  const char* base_dir, vx_gltf_mesh* out, vx_error* err) {
    vx_gltf_read_desc desc = {};
    if (desc_in) desc = *desc_in;
    if (!out || (!data && size)) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "gltf: NULL argument");
    if (size > UINT32_MAX)
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "gltf: %zu bytes is more than tinygltf reads", size);
    if (size < 4) return vx_fail(err, VX_ERR_TRUNCATED, 0, "gltf: %zu bytes is not a glTF file", size);
    try {
        tinygltf::TinyGLTF loader;
        tinygltf::Model model;
        std::string e, w;
        loader.SetImageLoader(keep_encoded_image, nullptr);
        tinygltf::FsCallbacks fs = {};
        if (desc.no_external || !base_dir) {
            fs.FileExists = no_file_exists;
            fs.ReadWholeFile = no_file_read;
        } else {
            fs.FileExists = file_exists;
            fs.ReadWholeFile = file_read;
        }
        fs.ExpandFilePath = same_path;
        fs.WriteWholeFile = no_file_write;
        loader.SetFsCallbacks(fs);
        std::string base = base_dir ? base_dir : "";
        const unsigned char* b = (const unsigned char*)data;
        bool glb = memcmp(b, "glTF", 4) == 0;
        vx_result rr = check_required(b, size, glb, err);
        if (rr) return rr;
        bool ok = glb ? loader.LoadBinaryFromMemory(&model, &e, &w, b, (unsigned)size, base)
                      : loader.LoadASCIIFromString(&model, &e, &w, (const char*)b, (unsigned)size, base);
        if (!ok) {
            while (!e.empty() && (e.back() == '\n' || e.back() == ' ')) e.pop_back();
            size_t nl = e.find('\n');
            if (nl != std::string::npos) e = e.substr(0, nl);
            return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "%s: %s", glb ? "glb" : "gltf",
                           e.empty() ? "tinygltf could not parse the file" : e.c_str());
        }
        if (!w.empty()) {
            std::string pw = plain_warnings(w);
            if (!pw.empty()) vx_log(desc.logger, VX_LOG_WARN, "gltf.tinygltf_warning", "%.200s", pw.c_str());
        }
        return convert(&desc, model, out, err);
    } catch (const std::bad_alloc&) {
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "gltf: out of memory");
    } catch (const std::exception& ex) {
        return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "gltf: %s", ex.what());
    }
}

extern "C" vx_result vx_gltf_read_file(const vx_gltf_read_desc* desc, const char* path, vx_gltf_mesh* out,
                                       vx_error* err) {
    if (!path || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "gltf: NULL argument");
    const vx_allocator* a = desc ? desc->alloc : nullptr;
    uint8_t* data = nullptr;
    size_t size = 0;
    vx_result r = vx_file_read(path, a, 0, &data, &size, err);
    if (r) return r;
    std::string dir = path;
    size_t slash = dir.find_last_of('/');
    dir = slash == std::string::npos ? std::string(".") : dir.substr(0, slash);
    r = vx_gltf_read(desc, data, size, dir.c_str(), out, err);
    vx_free(a, data);
    return r;
}

extern "C" void vx_gltf_mesh_free(vx_gltf_mesh* m) {
    if (!m) return;
    const vx_allocator* a = m->alloc;
    vx_free(a, m->pos);
    vx_free(a, m->uv);
    vx_free(a, m->uv_mr);
    vx_free(a, m->uv_emissive);
    vx_free(a, m->color);
    vx_free(a, m->material);
    vx_free(a, m->materials);
    vx_free(a, m->lights);
    if (m->images)
        for (uint32_t i = 0; i < m->image_count; i++) vx_free(a, m->images[i].rgba);
    vx_free(a, m->images);
    memset(m, 0, sizeof *m);
}
