// tests/glb/glb_check.cpp - checks a .glb written by svo_info --to-glb
// against the .svo it came from, reading the .glb back with tinygltf:
//   glb_check FILE.svo FILE.glb [--all]
//   glb_check --self-test        (vx_voxmesh on random voxel sets)
// For every model the exposed voxel faces are counted by brute force (a face
// whose neighbour cell is empty); the model's mesh must cover each of them
// exactly once with quads (two triangles each, counter-clockwise from
// outside, tiling an axis-aligned rectangle) of the voxel's colour, and
// nothing else (no interior faces): the quads' total area equals the
// brute-force face count. Each node must carry its instance's world matrix (turned +Y up)
// and its model's mesh; accessors must lie inside their buffer views and
// POSITION's min/max must be the real bounds. After the instances' nodes, one
// node per stored light (check_lights: KHR_lights_punctual type, place and
// aim turned +Y up, a rotation, intensities by glb.h's rules). Exit 0 when
// all holds.
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <random>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

extern "C" {
#include "formats/voxmesh.h"
#include "svo/svo.h"
}

static int failures;
#define FAIL(...)                                                                                                      \
    do {                                                                                                               \
        if (failures++ < 20) {                                                                                         \
            fprintf(stderr, "glb_check: ");                                                                            \
            fprintf(stderr, __VA_ARGS__);                                                                              \
            fprintf(stderr, "\n");                                                                                     \
        }                                                                                                              \
    } while (0)

static uint64_t key(uint32_t x, uint32_t y, uint32_t z) { return (uint64_t)x | (uint64_t)y << 21 | (uint64_t)z << 42; }
// a face: the cell's key and its direction (axis * 2 + positive)
static uint64_t face_id(uint64_t cell, int dir) { return cell << 3 | (uint64_t)dir; }

struct Model {
    std::unordered_map<uint64_t, uint32_t> cells; // key -> rgba
    std::unordered_map<uint64_t, uint32_t> faces; // exposed face -> rgba
};

// exposed faces by brute force
static void exposed(Model& m) {
    for (const auto& c : m.cells) {
        uint32_t p[3] = {uint32_t(c.first & 0x1FFFFF), uint32_t(c.first >> 21 & 0x1FFFFF), uint32_t(c.first >> 42)};
        for (int a = 0; a < 3; a++)
            for (int pos = 0; pos < 2; pos++) {
                int64_t n[3] = {p[0], p[1], p[2]};
                n[a] += pos ? 1 : -1;
                bool empty = n[a] < 0 || n[a] >= (1 << 21) || !m.cells.count(key(uint32_t(n[0]), uint32_t(n[1]), uint32_t(n[2])));
                if (empty) m.faces[face_id(c.first, a * 2 + pos)] = c.second;
            }
    }
}

static float srgb_to_linear(uint32_t b) {
    double c = b / 255.0;
    return float(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
}

// Covers the rectangle [u0,u1) x [v0,v1) at plane on axis a, direction pos.
static void cover(const Model& m, std::unordered_set<uint64_t>& seen, int a, bool pos, uint32_t plane, uint32_t u0,
                  uint32_t u1, uint32_t v0, uint32_t v1, const float* rgba, const char* what) {
    if (!pos && plane >= (1u << 21)) {
        FAIL("%s: face plane %u out of range", what, plane);
        return;
    }
    if (pos && plane == 0) {
        FAIL("%s: +axis face at plane 0", what);
        return;
    }
    int ua = (a + 1) % 3, va = (a + 2) % 3;
    for (uint32_t v = v0; v < v1; v++)
        for (uint32_t u = u0; u < u1; u++) {
            uint32_t c[3];
            c[a] = pos ? plane - 1 : plane;
            c[ua] = u;
            c[va] = v;
            uint64_t f = face_id(key(c[0], c[1], c[2]), a * 2 + pos);
            auto it = m.faces.find(f);
            if (it == m.faces.end()) {
                FAIL("%s: face of cell (%u %u %u) axis %d %s is not an exposed face (interior or empty)", what, c[0],
                     c[1], c[2], a, pos ? "+" : "-");
                continue;
            }
            if (!seen.insert(f).second) FAIL("%s: face of cell (%u %u %u) covered twice", what, c[0], c[1], c[2]);
            if (rgba) {
                uint32_t col = it->second;
                float want[4] = {srgb_to_linear(col & 0xFF), srgb_to_linear(col >> 8 & 0xFF),
                                 srgb_to_linear(col >> 16 & 0xFF), float(col >> 24) / 255.0f};
                for (int k = 0; k < 4; k++)
                    if (std::fabs(rgba[k] - want[k]) > 0.6f / 65535) {
                        FAIL("%s: cell (%u %u %u) colour %g, voxel %g (channel %d)", what, c[0], c[1], c[2], rgba[k],
                             want[k], k);
                        break;
                    }
            }
        }
}

// An accessor's data, checked against its buffer view and buffer.
template <typename T>
static const T* accessor_data(const tinygltf::Model& g, int ai, int comp, int type, int ncomp, size_t* count,
                              const char* what) {
    if (ai < 0 || ai >= int(g.accessors.size())) {
        FAIL("%s: accessor %d missing", what, ai);
        return nullptr;
    }
    const tinygltf::Accessor& a = g.accessors[ai];
    if (a.componentType != comp || a.type != type || a.sparse.isSparse || a.bufferView < 0) {
        FAIL("%s: accessor %d has component %d type %d", what, ai, a.componentType, a.type);
        return nullptr;
    }
    const tinygltf::BufferView& v = g.bufferViews[a.bufferView];
    const tinygltf::Buffer& b = g.buffers[v.buffer];
    size_t stride = v.byteStride ? v.byteStride : sizeof(T) * ncomp;
    if (stride != sizeof(T) * ncomp || a.byteOffset % sizeof(T) || (v.byteOffset + a.byteOffset) % sizeof(T) ||
        v.byteOffset + v.byteLength > b.data.size() || a.byteOffset + a.count * stride > v.byteLength) {
        FAIL("%s: accessor %d does not fit its buffer view", what, ai);
        return nullptr;
    }
    *count = a.count;
    return reinterpret_cast<const T*>(b.data.data() + v.byteOffset + a.byteOffset);
}

// Checks one mesh against one model; returns the number of quads.
static size_t check_mesh(const tinygltf::Model& g, int mi, const Model& m, const char* what) {
    std::unordered_set<uint64_t> seen;
    uint64_t area = 0;
    size_t quads = 0;
    const tinygltf::Mesh& mesh = g.meshes[mi];
    for (const tinygltf::Primitive& p : mesh.primitives) {
        if (p.mode != TINYGLTF_MODE_TRIANGLES) FAIL("%s: primitive mode %d", what, p.mode);
        size_t np = 0, nc = 0, ni = 0;
        auto pit = p.attributes.find("POSITION");
        auto cit = p.attributes.find("COLOR_0");
        if (pit == p.attributes.end()) {
            FAIL("%s: no POSITION", what);
            continue;
        }
        const float* pos = accessor_data<float>(g, pit->second, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, 3,
                                                &np, what);
        const uint16_t* col = cit == p.attributes.end()
                                  ? nullptr
                                  : accessor_data<uint16_t>(g, cit->second, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                                                            TINYGLTF_TYPE_VEC4, 4, &nc, what);
        if (col && !g.accessors[cit->second].normalized) FAIL("%s: COLOR_0 not normalized", what);
        const uint32_t* idx = accessor_data<uint32_t>(g, p.indices, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                                                      TINYGLTF_TYPE_SCALAR, 1, &ni, what);
        if (!pos || !idx || !col || nc != np) {
            FAIL("%s: missing positions, colours or indices", what);
            continue;
        }
        // POSITION min/max are required and must be the bounds
        const tinygltf::Accessor& pa = g.accessors[pit->second];
        double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
        for (size_t v = 0; v < np; v++)
            for (int a = 0; a < 3; a++) lo[a] = std::fmin(lo[a], pos[3 * v + a]), hi[a] = std::fmax(hi[a], pos[3 * v + a]);
        if (pa.minValues.size() != 3 || pa.maxValues.size() != 3)
            FAIL("%s: POSITION has no min/max", what);
        else
            for (int a = 0; a < 3; a++)
                if (pa.minValues[a] != lo[a] || pa.maxValues[a] != hi[a]) FAIL("%s: POSITION min/max wrong", what);
        if (ni % 6) FAIL("%s: %zu indices, not two triangles per quad", what, ni);
        for (size_t i = 0; i < ni; i++)
            if (idx[i] >= np) {
                FAIL("%s: index %u of %zu vertices", what, idx[i], np);
                return 0;
            }
        for (size_t q = 0; q + 6 <= ni; q += 6) {
            // the two triangles' corners: an axis-aligned rectangle in one plane
            double mn[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, mx[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
            for (int k = 0; k < 6; k++)
                for (int a = 0; a < 3; a++)
                    mn[a] = std::fmin(mn[a], pos[3 * idx[q + k] + a]), mx[a] = std::fmax(mx[a], pos[3 * idx[q + k] + a]);
            int axis = -1, flat = 0;
            for (int a = 0; a < 3; a++)
                if (mn[a] == mx[a]) axis = a, flat++;
            if (flat != 1) {
                FAIL("%s: quad %zu is not a rectangle in an axis plane", what, q / 6);
                continue;
            }
            int ua = (axis + 1) % 3, va = (axis + 2) % 3;
            double tri_area = 0;
            int sign = 0;
            bool bad = false;
            for (int t = 0; t < 2; t++) {
                const float* A = pos + 3 * idx[q + 3 * t];
                const float* B = pos + 3 * idx[q + 3 * t + 1];
                const float* C = pos + 3 * idx[q + 3 * t + 2];
                double cr = (double(B[ua]) - A[ua]) * (double(C[va]) - A[va]) - (double(B[va]) - A[va]) * (double(C[ua]) - A[ua]);
                int s = cr > 0 ? 1 : cr < 0 ? -1 : 0;
                if (!s || (sign && s != sign)) bad = true;
                sign = s;
                tri_area += std::fabs(cr) / 2;
                for (const float* P : {A, B, C})
                    for (int a = 0; a < 3; a++)
                        if (P[a] != std::floor(P[a]) || P[a] < 0) bad = true;
            }
            double rect = (mx[ua] - mn[ua]) * (mx[va] - mn[va]);
            if (bad || tri_area != rect) {
                FAIL("%s: quad %zu: triangles do not tile one rectangle with one winding", what, q / 6);
                continue;
            }
            // every corner of the quad has the same colour
            const uint16_t* c0 = col + 4 * idx[q];
            for (int k = 1; k < 6; k++)
                if (memcmp(c0, col + 4 * idx[q + k], 8) != 0) bad = true;
            float c0f[4] = {c0[0] / 65535.0f, c0[1] / 65535.0f, c0[2] / 65535.0f, c0[3] / 65535.0f};
            if (bad) FAIL("%s: quad %zu has more than one colour", what, q / 6);
            // counter-clockwise seen from outside: the winding's normal points out
            cover(m, seen, axis, sign > 0, uint32_t(mn[axis]), uint32_t(mn[ua]), uint32_t(mx[ua]), uint32_t(mn[va]),
                  uint32_t(mx[va]), c0f, what);
            area += uint64_t(rect);
            quads++;
        }
    }
    if (area != m.faces.size())
        FAIL("%s: quads cover %llu faces, the voxels expose %zu", what, (unsigned long long)area, m.faces.size());
    if (seen.size() != m.faces.size())
        FAIL("%s: %zu of %zu exposed faces covered", what, seen.size(), m.faces.size());
    return quads;
}

static bool collect(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    auto* c = static_cast<std::pair<const vx_svo_scene*, std::pair<const vx_svo_model*, Model*>>*>(user);
    c->second.second->cells[key(x, y, z)] = vx_svo_attr_rgba(c->first, c->second.first, attr);
    return true;
}

// voxkit's +Z up to glTF's +Y up
static void turn(const double v[3], double o[3]) { o[0] = v[0], o[1] = v[2], o[2] = -v[1]; }
static void unit(double v[3]) {
    double l = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int k = 0; k < 3; k++) v[k] /= l;
}

// The light nodes from node `first` on, one per stored light in order: the
// KHR_lights_punctual light it names, its type (sphere: point, rect: spot)
// and intensity (sphere L pi r^2, rect L A, a colour over 1 folded into it),
// its matrix a rotation placing it at the position turned +Y up with -Z
// where it shines (and a rect's +X along its tangent), voxkit's record in
// extras where the punctual light is not the light.
static void check_lights(const tinygltf::Model& g, const vx_svo_scene& s, size_t first) {
    static const char* const type[VX_LIGHT_TYPE_COUNT] = {"directional", "point", "spot", "point", "spot"};
    size_t n = first, j = 0;
    for (uint32_t i = 0; i < s.light_count; i++) {
        const vx_light& l = s.lights[i];
        if (l.flags & VX_LIGHT_FROM_VOXELS) continue;
        const tinygltf::Node& node = g.nodes[n++];
        auto e = node.extensions.find("KHR_lights_punctual");
        if (e == node.extensions.end() || !e->second.Has("light") || e->second.Get("light").GetNumberAsInt() != int(j) ||
            j >= g.lights.size()) {
            FAIL("node %zu: not light %zu's node", n - 1, j);
            return;
        }
        const tinygltf::Light& L = g.lights[j++];
        if (L.type != type[l.type]) FAIL("light %u: a %s, written as '%s'", i, type[l.type], L.type.c_str());
        double big = std::max(l.color[0], std::max(l.color[1], l.color[2])), scale = big > 1 ? big : 1;
        double want = l.intensity * scale;
        if (l.type == VX_LIGHT_SPHERE) want *= 3.141592653589793 * l.radius * l.radius;
        if (l.type == VX_LIGHT_RECT) want *= l.size[0] * l.size[1];
        if (std::fabs(L.intensity - want) > 1e-12 * want) FAIL("light %u: intensity %g, expected %g", i, L.intensity, want);
        for (int k = 0; k < 3 && L.color.size() == 3; k++)
            if (std::fabs(L.color[size_t(k)] - l.color[k] / scale) > 1e-15) FAIL("light %u: colour %g", i, L.color[size_t(k)]);
        bool record = l.type == VX_LIGHT_SPHERE || l.type == VX_LIGHT_RECT;
        if (record && !(L.extras.IsObject() && L.extras.Has("voxkit_light")))
            FAIL("light %u: no extras.voxkit_light for a %s light", i, l.type == VX_LIGHT_SPHERE ? "sphere" : "rect");
        std::vector<double> M = node.matrix;
        if (M.empty()) M = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
        if (M.size() != 16) {
            FAIL("light node %zu: matrix of %zu values", n - 1, M.size());
            continue;
        }
        double p[3];
        turn(l.position, p);
        for (int a = 0; a < 3; a++)
            if (std::fabs(M[size_t(12 + a)] - p[a]) > 1e-9 * (1 + std::fabs(p[a])))
                FAIL("light %u: at %g %g %g, expected %g %g %g", i, M[12], M[13], M[14], p[0], p[1], p[2]);
        for (int a = 0; a < 3; a++) // the columns: orthonormal and right-handed
            for (int b = 0; b < 3; b++) {
                double d = 0;
                for (int k = 0; k < 3; k++) d += M[size_t(4 * a + k)] * M[size_t(4 * b + k)];
                if (std::fabs(d - (a == b)) > 1e-12) FAIL("light %u: the node's matrix is no rotation", i);
            }
        double det = M[0] * (M[5] * M[10] - M[6] * M[9]) - M[4] * (M[1] * M[10] - M[2] * M[9]) +
                     M[8] * (M[1] * M[6] - M[2] * M[5]);
        if (std::fabs(det - 1) > 1e-12) FAIL("light %u: the node's rotation has determinant %g", i, det);
        if (l.type == VX_LIGHT_POINT || l.type == VX_LIGHT_SPHERE) continue;
        double d[3], v[3];
        for (int k = 0; k < 3; k++) v[k] = l.type == VX_LIGHT_DIRECTIONAL ? -l.direction[k] : l.direction[k];
        turn(v, d);
        unit(d);
        for (int k = 0; k < 3; k++)
            if (std::fabs(-M[size_t(8 + k)] - d[k]) > 1e-12)
                FAIL("light %u: shines along %g %g %g, expected %g %g %g", i, -M[8], -M[9], -M[10], d[0], d[1], d[2]);
        if (l.type == VX_LIGHT_RECT) {
            double t[3];
            turn(l.tangent, t);
            double tn = t[0] * d[0] + t[1] * d[1] + t[2] * d[2];
            for (int k = 0; k < 3; k++) t[k] -= tn * d[k];
            unit(t);
            for (int k = 0; k < 3; k++)
                if (std::fabs(M[size_t(k)] - t[k]) > 1e-12) FAIL("light %u: +X %g %g %g, not the tangent", i, M[0], M[1], M[2]);
        }
    }
}

static int check_files(const char* svo_path, const char* glb_path, bool all) {
    vx_svo_scene s;
    vx_error err = {};
    if (vx_svo_read_file(nullptr, svo_path, &s, &err) != VX_OK) {
        fprintf(stderr, "glb_check: %s: %s\n", svo_path, err.msg);
        return 1;
    }
    tinygltf::TinyGLTF loader;
    tinygltf::Model g;
    std::string e, w;
    if (!loader.LoadBinaryFromFile(&g, &e, &w, glb_path)) {
        fprintf(stderr, "glb_check: %s: %s\n", glb_path, e.c_str());
        vx_svo_scene_free(&s);
        return 1;
    }
    if (!w.empty()) FAIL("%s: tinygltf warns: %s", glb_path, w.c_str());
    if (g.asset.version != "2.0") FAIL("asset.version %s", g.asset.version.c_str());
    if (g.scenes.size() != 1 || g.defaultScene != 0) FAIL("%zu scenes, default %d", g.scenes.size(), g.defaultScene);
    if (!g.scenes.empty() && g.scenes[0].nodes.size() != g.nodes.size()) FAIL("not every node is in the scene");

    // nodes: one per shown instance, in order
    std::vector<uint32_t> shown;
    for (uint32_t i = 0; i < s.instance_count; i++)
        if (s.instances[i].model < s.model_count && (all || vx_svo_instance_visible(&s, i))) shown.push_back(i);
    size_t lit = 0; // stored lights (those of emissive voxels are never stored)
    for (uint32_t i = 0; i < s.light_count; i++) lit += !(s.lights[i].flags & VX_LIGHT_FROM_VOXELS);
    if (g.nodes.size() != shown.size() + lit)
        FAIL("%zu nodes for %zu shown instances and %zu lights", g.nodes.size(), shown.size(), lit);
    else
        check_lights(g, s, shown.size());
    std::map<uint32_t, int> mesh_of; // model -> mesh
    for (size_t n = 0; n < g.nodes.size() && n < shown.size(); n++) {
        const vx_svo_instance& in = s.instances[shown[n]];
        double wm[12];
        vx_svo_instance_world(&s, &in, wm);
        // column-major, with voxkit's +Z up turned to glTF's +Y up: rows x, z, -y
        double want[16] = {wm[0], wm[8], -wm[4], 0, wm[1], wm[9], -wm[5], 0,
                           wm[2], wm[10], -wm[6], 0, wm[3], wm[11], -wm[7], 1};
        std::vector<double> got = g.nodes[n].matrix;
        if (got.empty()) got = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
        if (got.size() != 16) FAIL("node %zu: matrix of %zu values", n, got.size());
        else
            for (int k = 0; k < 16; k++)
                if (std::fabs(got[k] - want[k]) > 1e-9 * (1 + std::fabs(want[k]))) {
                    FAIL("node %zu: matrix[%d] %g, instance %u has %g", n, k, got[k], shown[n], want[k]);
                    break;
                }
        int mesh = g.nodes[n].mesh;
        if (s.models[in.model].voxel_count == 0) {
            if (mesh != -1) FAIL("node %zu: empty model %u has mesh %d", n, in.model, mesh);
            continue;
        }
        if (mesh < 0 || mesh >= int(g.meshes.size())) {
            FAIL("node %zu: mesh %d for model %u", n, mesh, in.model);
            continue;
        }
        auto it = mesh_of.find(in.model);
        if (it == mesh_of.end()) mesh_of[in.model] = mesh;
        else if (it->second != mesh) FAIL("model %u drawn with meshes %d and %d", in.model, it->second, mesh);
    }
    // every mesh is drawn by a node (an unused one is a glTF validator info)
    if (g.meshes.size() != mesh_of.size()) FAIL("%zu meshes, %zu of them used by nodes", g.meshes.size(), mesh_of.size());
    uint64_t faces = 0, quads = 0;
    for (const auto& mm : mesh_of) {
        Model m;
        auto ctx = std::make_pair((const vx_svo_scene*)&s, std::make_pair((const vx_svo_model*)&s.models[mm.first], &m));
        if (vx_svo_decode_model(&s.models[mm.first], collect, &ctx, &err) != VX_OK) FAIL("decode: %s", err.msg);
        exposed(m);
        char what[64];
        snprintf(what, sizeof what, "model %u (mesh %d)", mm.first, mm.second);
        quads += check_mesh(g, mm.second, m, what);
        faces += m.faces.size();
    }
    printf("%s: %zu nodes, %zu meshes checked: %llu exposed faces, %llu quads (%.2f faces per quad): %s\n", glb_path,
           g.nodes.size(), mesh_of.size(), (unsigned long long)faces, (unsigned long long)quads,
           quads ? double(faces) / double(quads) : 0.0, failures ? "FAILED" : "each covered once, nothing else");
    vx_svo_scene_free(&s);
    return failures ? 1 : 0;
}

// vx_voxmesh alone on random sets: exact cover of the exposed faces.
static int self_test() {
    std::mt19937 rng(19);
    uint64_t total_faces = 0, total_quads = 0;
    // sets 0..199: one small block; 200..259: eight blocks 3000 cells apart;
    // 260..269: blocks of 60..96 cells a side across the mesher's 64^3
    // bricks, at odd offsets and at the top of the coordinate range, half
    // of them given in shuffled order (not grouped by brick); 270: 300 k
    // cells of one colour (the multi-threaded path)
    for (int t = 0; t < 271; t++) {
        uint32_t n = t < 260 ? 1 + t % 13 : t < 270 ? 60 + 4 * (t - 260) : 100;
        double density = t < 260 ? (t % 7 + 1) / 8.0 : t < 270 ? 0.2 + 0.07 * (t - 260) : 0.3;
        int colours = t < 270 ? 1 + t % 3 : 1;
        uint32_t base = t % 5 == 0 ? (1u << 21) - 3000 - n : 0; // touch the top of the coordinate range
        if (t >= 260) base = t % 2 ? 37 : (1u << 21) - n;
        std::vector<uint32_t> xyz, rgba;
        Model m;
        for (uint32_t b = 0; b < (t < 200 || t >= 260 ? 1u : 8u); b++) {
            uint32_t o[3] = {base + 3000 * (b & 1), base + 3000 * (b >> 1 & 1), base + 3000 * (b >> 2)};
            for (uint32_t z = 0; z < n; z++)
                for (uint32_t y = 0; y < n; y++)
                    for (uint32_t x = 0; x < n; x++)
                        if (std::uniform_real_distribution<double>(0, 1)(rng) < density) {
                            uint32_t c = 0xFF000000u | (rng() % colours) * 0x404040u;
                            xyz.insert(xyz.end(), {o[0] + x, o[1] + y, o[2] + z});
                            rgba.push_back(c);
                            m.cells[key(o[0] + x, o[1] + y, o[2] + z)] = c;
                        }
        }
        if (t >= 260 && t % 4 < 2) { // shuffled: the mesher must group the cells itself
            for (size_t i = rgba.size(); i > 1; i--) {
                size_t j = rng() % i;
                std::swap(rgba[i - 1], rgba[j]);
                for (int k = 0; k < 3; k++) std::swap(xyz[3 * (i - 1) + k], xyz[3 * j + k]);
            }
        }
        exposed(m);
        vx_voxmesh vm;
        vx_error err = {};
        if (vx_voxmesh_build(nullptr, xyz.data(), rgba.data(), rgba.size(), &vm, &err) != VX_OK) {
            FAIL("self-test %d: %s", t, err.msg);
            continue;
        }
        std::unordered_set<uint64_t> seen;
        uint64_t area = 0;
        for (size_t q = 0; q < vm.quad_count; q++) {
            const vx_voxmesh_quad& Q = vm.quads[q];
            uint32_t c = Q.rgba;
            float lin[4] = {srgb_to_linear(c & 0xFF), srgb_to_linear(c >> 8 & 0xFF), srgb_to_linear(c >> 16 & 0xFF),
                            float(c >> 24) / 255.0f};
            char what[64];
            snprintf(what, sizeof what, "self-test %d quad %zu", t, q);
            cover(m, seen, Q.axis, Q.positive, Q.plane, Q.u0, Q.u1, Q.v0, Q.v1, lin, what);
            area += uint64_t(Q.u1 - Q.u0) * (Q.v1 - Q.v0);
        }
        if (area != m.faces.size() || seen.size() != m.faces.size() || vm.faces != m.faces.size())
            FAIL("self-test %d: area %llu, covered %zu, faces %llu, exposed %zu", t, (unsigned long long)area,
                 seen.size(), (unsigned long long)vm.faces, m.faces.size());
        total_faces += m.faces.size();
        total_quads += vm.quad_count;
        vx_voxmesh_free(&vm);
    }
    // a cell given twice, a coordinate out of range
    uint32_t twice[6] = {1, 2, 3, 1, 2, 3}, far[3] = {1u << 21, 0, 0};
    vx_voxmesh vm;
    vx_error err = {};
    if (vx_voxmesh_build(nullptr, twice, nullptr, 2, &vm, &err) != VX_ERR_INVALID_ARG) FAIL("duplicate cell accepted");
    if (vx_voxmesh_build(nullptr, far, nullptr, 1, &vm, &err) != VX_ERR_INVALID_ARG) FAIL("coordinate 2^21 accepted");
    // one full 8^3 block of one colour: 6 quads
    std::vector<uint32_t> cube;
    for (uint32_t i = 0; i < 512; i++) cube.insert(cube.end(), {i & 7, i >> 3 & 7, i >> 6});
    if (vx_voxmesh_build(nullptr, cube.data(), nullptr, 512, &vm, &err) != VX_OK || vm.quad_count != 6 ||
        vm.faces != 6 * 64)
        FAIL("8^3 block: %zu quads, %llu faces", vm.quad_count, (unsigned long long)vm.faces);
    vx_voxmesh_free(&vm);
    printf("self-test: 271 random sets, %llu exposed faces covered once by %llu quads\n",
           (unsigned long long)total_faces, (unsigned long long)total_quads);
    return failures ? 1 : 0;
}

int main(int argc, char** argv) {
    if (argc == 2 && !strcmp(argv[1], "--self-test")) return self_test();
    if (argc < 3 || argc > 4 || (argc == 4 && strcmp(argv[3], "--all"))) {
        fprintf(stderr, "usage: glb_check FILE.svo FILE.glb [--all] | glb_check --self-test\n");
        return 2;
    }
    return check_files(argv[1], argv[2], argc == 4);
}
