// formats/glb_tinygltf.cpp - the .glb writer of formats/glb.h: a tinygltf
// Model with one buffer, serialized by tinygltf as binary glTF into memory
// and written with vx_file_write_atomic.
#include "formats/glb.h"

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include <cfloat>
#include <cmath>
#include <cstring>
#include <exception>
#include <ostream>
#include <streambuf>
#include <string>
#include <vector>

namespace {

// Appends n bytes to the buffer and returns a buffer view over them.
int add_view(tinygltf::Model& m, const void* data, size_t n, int target) {
    std::vector<unsigned char>& b = m.buffers[0].data;
    while (b.size() % 4) b.push_back(0);
    tinygltf::BufferView v;
    v.buffer = 0;
    v.byteOffset = b.size();
    v.byteLength = n;
    v.target = target;
    const unsigned char* p = static_cast<const unsigned char*>(data);
    b.insert(b.end(), p, p + n);
    m.bufferViews.push_back(v);
    return int(m.bufferViews.size() - 1);
}

int add_accessor(tinygltf::Model& m, int view, int component, int type, size_t count) {
    tinygltf::Accessor a;
    a.bufferView = view;
    a.byteOffset = 0;
    a.componentType = component;
    a.type = type;
    a.count = count;
    m.accessors.push_back(a);
    return int(m.accessors.size() - 1);
}

bool finite(double x) { return std::isfinite(x) && std::fabs(x) <= 1e30; }

// The extension's rules (glb.h), so that a file we write is one the
// validator and other readers accept.
vx_result check_light(const vx_glb_light& l, uint32_t i, vx_error* err) {
    const char* name = l.name ? l.name : "";
    if ((unsigned)l.type >= VX_GLB_LIGHT_TYPE_COUNT)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "glb: light %u ('%.60s'): unknown type %u", i, name,
                       (unsigned)l.type);
    for (int k = 0; k < 3; k++)
        if (!(l.color[k] >= 0 && l.color[k] <= 1))
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "glb: light %u ('%.60s'): colour %g outside [0, 1]",
                           i, name, l.color[k]);
    if (!(l.intensity >= 0 && finite(l.intensity)) || !(l.range >= 0 && finite(l.range)))
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                       "glb: light %u ('%.60s'): intensity %g and range %g must be finite and >= 0", i, name,
                       l.intensity, l.range);
    if (l.type == VX_GLB_LIGHT_SPOT &&
        !(l.inner_cone >= 0 && l.inner_cone < l.outer_cone && l.outer_cone <= 1.5707963267948966))
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                       "glb: light %u ('%.60s'): spot cones %g, %g must satisfy 0 <= inner < outer <= pi/2", i, name,
                       l.inner_cone, l.outer_cone);
    for (int k = 0; k < 16; k++)
        if (!finite(l.matrix[k]))
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "glb: light %u ('%.60s'): a matrix entry is not finite",
                           i, name);
    return VX_OK;
}

// nlohmann's JSON as tinygltf's Value (a light's extras); false past a depth
// of 32 (the caller's text, but still no unbounded recursion).
bool to_value(const nlohmann::json& j, tinygltf::Value* out, int depth) {
    if (depth > 32) return false;
    if (j.is_object()) {
        tinygltf::Value::Object o;
        for (auto it = j.begin(); it != j.end(); ++it)
            if (!to_value(it.value(), &o[it.key()], depth + 1)) return false;
        *out = tinygltf::Value(std::move(o));
    } else if (j.is_array()) {
        tinygltf::Value::Array a(j.size());
        for (size_t k = 0; k < j.size(); k++)
            if (!to_value(j[k], &a[k], depth + 1)) return false;
        *out = tinygltf::Value(std::move(a));
    } else if (j.is_string()) {
        *out = tinygltf::Value(j.get<std::string>());
    } else if (j.is_boolean()) {
        *out = tinygltf::Value(j.get<bool>());
    } else if (j.is_number_integer() && j.get<double>() >= -2147483648.0 && j.get<double>() <= 2147483647.0) {
        *out = tinygltf::Value(int(j.get<int64_t>()));
    } else if (j.is_number()) {
        *out = tinygltf::Value(j.get<double>());
    } else {
        *out = tinygltf::Value(); // null
    }
    return true;
}

vx_result check(const vx_glb_scene* s, vx_error* err) {
    uint64_t bytes = 0;
    for (uint32_t i = 0; i < s->mesh_count; i++) {
        const vx_glb_mesh& me = s->meshes[i];
        if (!me.vertex_count || !me.pos || me.index_count < 3 || me.index_count % 3 || !me.index)
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "glb: mesh %u has no triangles", i);
        if (me.vertex_count > UINT32_MAX)
            return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "glb: mesh %u has %zu vertices (32-bit indices)", i,
                           me.vertex_count);
        for (size_t k = 0; k < me.index_count; k++)
            if (me.index[k] >= me.vertex_count)
                return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "glb: mesh %u index %zu is %u of %zu vertices", i,
                               k, me.index[k], me.vertex_count);
        bytes += (uint64_t)me.vertex_count * (12 + (me.normal ? 12 : 0) + (me.color ? 8 : 0)) +
                 (uint64_t)me.index_count * 4 + 16 + (uint64_t)me.primitive_count * 4;
    }
    for (uint32_t i = 0; i < s->mesh_count; i++) {
        const vx_glb_mesh& me = s->meshes[i];
        if (me.primitive_count && !me.primitives)
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "glb: mesh %u has no primitive array", i);
        for (uint32_t k = 0; k < me.primitive_count; k++) {
            const vx_glb_primitive& p = me.primitives[k];
            if (p.index_count < 3 || p.index_count % 3 || p.index_first % 3 || p.index_first > me.index_count ||
                p.index_count > me.index_count - p.index_first)
                return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                               "glb: mesh %u primitive %u: indices %zu+%zu of %zu", i, k, p.index_first,
                               p.index_count, me.index_count);
            if (p.material >= (s->material_count ? s->material_count : 1))
                return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "glb: mesh %u primitive %u names material %u",
                               i, k, p.material);
        }
    }
    if (s->material_count && !s->materials)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "glb: NULL materials");
    if (s->light_count && !s->lights) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "glb: NULL lights");
    for (uint32_t i = 0; i < s->light_count; i++) {
        vx_result r = check_light(s->lights[i], i, err);
        if (r) return r;
    }
    for (uint32_t i = 0; i < s->node_count; i++)
        if (s->nodes[i].mesh < -1 || s->nodes[i].mesh >= (int64_t)s->mesh_count)
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "glb: node %u names mesh %d of %u", i,
                           s->nodes[i].mesh, s->mesh_count);
    // the GLB header's lengths are 32-bit; leave room for the JSON chunk
    if (bytes > (uint64_t)UINT32_MAX - ((uint64_t)1 << 28))
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "glb: %llu bytes of geometry, more than a .glb holds",
                       (unsigned long long)bytes);
    return VX_OK;
}

void add_ext(tinygltf::Model& m, const char* name) {
    for (const std::string& e : m.extensionsUsed)
        if (e == name) return;
    m.extensionsUsed.push_back(name);
}

tinygltf::Material make_material(tinygltf::Model& m, const vx_glb_material& g) {
    tinygltf::Material mat;
    if (g.name) mat.name = g.name;
    mat.pbrMetallicRoughness.baseColorFactor = {g.base_color[0], g.base_color[1], g.base_color[2], g.base_color[3]};
    mat.pbrMetallicRoughness.metallicFactor = g.metallic;
    mat.pbrMetallicRoughness.roughnessFactor = g.roughness;
    if (g.emissive[0] > 0 || g.emissive[1] > 0 || g.emissive[2] > 0) {
        mat.emissiveFactor = {g.emissive[0], g.emissive[1], g.emissive[2]};
        if (g.emissive_strength > 1) {
            tinygltf::Value::Object o;
            o["emissiveStrength"] = tinygltf::Value(double(g.emissive_strength));
            mat.extensions["KHR_materials_emissive_strength"] = tinygltf::Value(o);
            add_ext(m, "KHR_materials_emissive_strength");
        }
    }
    if (g.transmission > 0) {
        tinygltf::Value::Object o;
        o["transmissionFactor"] = tinygltf::Value(double(g.transmission));
        mat.extensions["KHR_materials_transmission"] = tinygltf::Value(o);
        add_ext(m, "KHR_materials_transmission");
        if (g.ior > 0 && g.ior != 1.5f) {
            tinygltf::Value::Object io;
            io["ior"] = tinygltf::Value(double(g.ior));
            mat.extensions["KHR_materials_ior"] = tinygltf::Value(io);
            add_ext(m, "KHR_materials_ior");
        }
    }
    return mat;
}

// An output stream buffer that appends to a vx_atomic_file, so tinygltf
// serializes straight into the temporary file (no copy of the whole .glb in
// memory).
class atomic_buf : public std::streambuf {
  public:
    explicit atomic_buf(vx_atomic_file* f) : f_(f) { setp(buf_, buf_ + sizeof buf_); }
    int sync() override { return flush() ? 0 : -1; }

  protected:
    int_type overflow(int_type c) override {
        if (!flush()) return traits_type::eof();
        if (!traits_type::eq_int_type(c, traits_type::eof())) {
            *pptr() = traits_type::to_char_type(c);
            pbump(1);
        }
        return traits_type::not_eof(c);
    }
    std::streamsize xsputn(const char* s, std::streamsize n) override {
        if (!flush()) return 0;
        if (n >= std::streamsize(sizeof buf_)) return vx_atomic_write(f_, s, size_t(n)) ? n : 0;
        return std::streambuf::xsputn(s, n);
    }

  private:
    bool flush() {
        size_t n = size_t(pptr() - pbase());
        setp(buf_, buf_ + sizeof buf_);
        return n == 0 || vx_atomic_write(f_, buf_, n);
    }
    vx_atomic_file* f_;
    char buf_[1 << 16];
};

} // namespace

extern "C" vx_result vx_glb_write_file(const vx_write_desc* desc, const vx_glb_scene* s, const char* path,
                                       vx_error* err) {
    if (!s || !path || (s->mesh_count && !s->meshes) || (s->node_count && !s->nodes))
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "glb: NULL argument");
    vx_result r = check(s, err);
    if (r) return r;
    vx_atomic_file f = {};
    bool open = false;
    try {
        tinygltf::Model m;
        m.asset.version = "2.0";
        m.asset.generator = s->generator ? s->generator : "voxkit";
        m.buffers.resize(1);
        for (uint32_t i = 0; i < s->material_count; i++) m.materials.push_back(make_material(m, s->materials[i]));
        if (s->mesh_count && !s->material_count) {
            // the default (glb.h): white, metallic 0, roughness 1, no emission
            const vx_glb_material voxel = {"voxel", {1, 1, 1, 1}, 0, 1, {0, 0, 0}, 0, 0, 0};
            m.materials.push_back(make_material(m, voxel));
        }
        for (uint32_t i = 0; i < s->mesh_count; i++) {
            const vx_glb_mesh& me = s->meshes[i];
            tinygltf::Primitive prim;
            prim.mode = TINYGLTF_MODE_TRIANGLES;
            prim.material = 0;
            int pos = add_accessor(m, add_view(m, me.pos, me.vertex_count * 12, TINYGLTF_TARGET_ARRAY_BUFFER),
                                   TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, me.vertex_count);
            std::vector<double> lo(3, DBL_MAX), hi(3, -DBL_MAX);
            for (size_t v = 0; v < me.vertex_count; v++)
                for (int a = 0; a < 3; a++) {
                    double x = me.pos[3 * v + a];
                    if (x < lo[a]) lo[a] = x;
                    if (x > hi[a]) hi[a] = x;
                }
            m.accessors[pos].minValues = lo;
            m.accessors[pos].maxValues = hi;
            prim.attributes["POSITION"] = pos;
            if (me.normal)
                prim.attributes["NORMAL"] =
                    add_accessor(m, add_view(m, me.normal, me.vertex_count * 12, TINYGLTF_TARGET_ARRAY_BUFFER),
                                 TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, me.vertex_count);
            if (me.color) {
                int c = add_accessor(m, add_view(m, me.color, me.vertex_count * 8, TINYGLTF_TARGET_ARRAY_BUFFER),
                                     TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_VEC4, me.vertex_count);
                m.accessors[c].normalized = true;
                prim.attributes["COLOR_0"] = c;
            }
            tinygltf::Mesh mesh;
            if (me.name) mesh.name = me.name;
            if (!me.primitive_count) {
                prim.indices =
                    add_accessor(m, add_view(m, me.index, me.index_count * 4, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
                                 TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR, me.index_count);
                mesh.primitives.push_back(prim);
            }
            // the primitives share the mesh's vertex accessors, each with its own indices
            for (uint32_t k = 0; k < me.primitive_count; k++) {
                const vx_glb_primitive& p = me.primitives[k];
                tinygltf::Primitive pk = prim;
                pk.material = int(p.material);
                pk.indices = add_accessor(
                    m, add_view(m, me.index + p.index_first, p.index_count * 4, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
                    TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR, p.index_count);
                mesh.primitives.push_back(pk);
            }
            m.meshes.push_back(mesh);
        }
        tinygltf::Scene scene;
        for (uint32_t i = 0; i < s->node_count; i++) {
            const vx_glb_node& n = s->nodes[i];
            tinygltf::Node node;
            if (n.name) node.name = n.name;
            node.mesh = n.mesh;
            static const double id[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
            if (memcmp(n.matrix, id, sizeof id) != 0) node.matrix.assign(n.matrix, n.matrix + 16);
            m.nodes.push_back(node);
            scene.nodes.push_back(int(i));
        }
        static const char* const type_name[VX_GLB_LIGHT_TYPE_COUNT] = {"directional", "point", "spot"};
        for (uint32_t i = 0; i < s->light_count; i++) {
            const vx_glb_light& g = s->lights[i];
            tinygltf::Light L;
            if (g.name) L.name = g.name;
            L.type = type_name[g.type];
            L.color.assign(g.color, g.color + 3);
            L.intensity = g.intensity;
            if (g.type != VX_GLB_LIGHT_DIRECTIONAL) L.range = g.range; // tinygltf writes it when > 0
            if (g.type == VX_GLB_LIGHT_SPOT) {
                L.spot.innerConeAngle = g.inner_cone;
                L.spot.outerConeAngle = g.outer_cone;
            }
            if (g.extras) {
                nlohmann::json j = nlohmann::json::parse(g.extras, nullptr, false);
                if (j.is_discarded() || !j.is_object() || !to_value(j, &L.extras, 0))
                    return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                                   "glb: light %u ('%.60s'): extras is not a JSON object", i, g.name ? g.name : "");
            }
            m.lights.push_back(L); // tinygltf declares KHR_lights_punctual in extensionsUsed
            tinygltf::Node node;
            if (g.name) node.name = g.name;
            static const double id[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
            if (memcmp(g.matrix, id, sizeof id) != 0) node.matrix.assign(g.matrix, g.matrix + 16);
            tinygltf::Value::Object ext;
            ext["light"] = tinygltf::Value(int(i));
            node.extensions["KHR_lights_punctual"] = tinygltf::Value(ext);
            m.nodes.push_back(node);
            scene.nodes.push_back(int(m.nodes.size() - 1));
        }
        if (s->scene_extras) {
            nlohmann::json j = nlohmann::json::parse(s->scene_extras, nullptr, false);
            if (j.is_discarded() || !j.is_object() || !to_value(j, &scene.extras, 0))
                return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "glb: scene_extras is not a JSON object");
        }
        m.scenes.push_back(scene);
        m.defaultScene = 0;
        if (m.buffers[0].data.empty()) m.buffers.clear();

        tinygltf::TinyGLTF writer;
        r = vx_atomic_open(&f, path, desc ? desc->alloc : NULL, err);
        if (r) return r;
        open = true;
        bool ok;
        {
            atomic_buf sb(&f);
            std::ostream os(&sb);
            ok = writer.WriteGltfSceneToStream(&m, os, false, true);
            os.flush();
        }
        open = false;
        if (!ok) {
            vx_atomic_abort(&f);
            return vx_fail(err, VX_ERR_IO, VX_NO_OFFSET, "%s: tinygltf could not serialize the scene", path);
        }
        return vx_atomic_commit(&f, err);
    } catch (const std::bad_alloc&) {
        if (open) vx_atomic_abort(&f);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "glb: out of memory");
    } catch (const std::exception& ex) {
        if (open) vx_atomic_abort(&f);
        return vx_fail(err, VX_ERR_IO, VX_NO_OFFSET, "glb: %s", ex.what());
    }
}
