// tests/convert/vdb_test.cpp - OpenVDB -> svo conversion checked against
// OpenVDB itself: grids are made (or read) here through OpenVDB, the
// expected cells are classified by brute force through OpenVDB accessors,
// and the built scene is decoded cell by cell and compared.
#include <openvdb/io/File.h>
#include <openvdb/io/Stream.h>
#include <openvdb/math/Transform.h>
#include <openvdb/openvdb.h>
#include <openvdb/points/PointConversion.h>
#include <openvdb/tools/LevelSetSphere.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "convert/volume.h"
#include "formats/vdb.h"
#include "svo/svo.h"
#include "tests/test.h"

namespace {

using Cell = std::array<int64_t, 3>;

struct Decoded {
    std::vector<Cell> cells;
    std::map<Cell, uint32_t> rgba;
    std::map<Cell, float> density;
};

struct DecodeCtx {
    const vx_svo_scene* s;
    const vx_svo_model* m;
    int64_t t[3];
    Decoded* out;
    bool keep_attrs;
};

bool on_cell(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    DecodeCtx* c = static_cast<DecodeCtx*>(user);
    Cell g = {int64_t(x) + c->t[0], int64_t(y) + c->t[1], int64_t(z) + c->t[2]};
    c->out->cells.push_back(g);
    if (c->keep_attrs) {
        if (c->m->attrs & VX_ATTR_RGBA8) c->out->rgba[g] = c->m->rgba[attr];
        if (c->m->attrs & VX_ATTR_DENSITY) c->out->density[g] = c->m->density[attr];
    }
    return true;
}

// Grid cells of every shown instance (instances must be integer translations).
bool decode(const vx_svo_scene& s, Decoded* out, bool keep_attrs = false) {
    for (uint32_t i = 0; i < s.instance_count; i++) {
        const vx_svo_instance& in = s.instances[i];
        if (in.flags & VX_SVO_INSTANCE_HIDDEN) continue;
        const double id[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
        for (int k = 0; k < 12; k++)
            if (k % 4 != 3 && in.xform[k] != id[k]) return false;
        DecodeCtx c = {&s, &s.models[in.model], {int64_t(in.xform[3]), int64_t(in.xform[7]), int64_t(in.xform[11])},
                       out, keep_attrs};
        for (int k = 0; k < 3; k++)
            if (double(c.t[k]) != in.xform[k * 4 + 3]) return false;
        vx_error err = {};
        if (vx_svo_decode_model(c.m, on_cell, &c, &err) != VX_OK) {
            fprintf(stderr, "decode: %s\n", err.msg);
            return false;
        }
    }
    std::sort(out->cells.begin(), out->cells.end());
    return true;
}

std::string to_bytes(const openvdb::GridPtrVec& grids) {
    std::ostringstream os(std::ios_base::binary);
    openvdb::io::Stream(os).write(grids);
    return os.str();
}

bool convert(const std::string& bytes, const vx_conv_vdb_desc& d, vx_svo_scene* s, vx_conv_stats* st = nullptr) {
    vx_error err = {};
    vx_result r = vx_conv_vdb_memory(&d, bytes.data(), bytes.size(), s, st, &err);
    if (r != VX_OK) fprintf(stderr, "convert: %s: %s\n", vx_result_str(r), err.msg);
    return r == VX_OK;
}

template <class GridT>
std::vector<Cell> brute_fog(const GridT& g, double thr, bool thr_set) {
    std::vector<Cell> v;
    for (auto it = g.tree().cbeginValueOn(); it; ++it) {
        double x = *it;
        if (thr_set ? !(x >= thr) : !(x > 0)) continue;
        openvdb::CoordBBox b = it.getBoundingBox();
        for (auto p = b.begin(); p; ++p) v.push_back({(*p).x(), (*p).y(), (*p).z()});
    }
    std::sort(v.begin(), v.end());
    return v;
}

// The documented shell: active voxels with value < 0 having a face neighbour
// with value >= 0, tested cell by cell through an accessor.
std::vector<Cell> brute_surface(const openvdb::FloatGrid& g) {
    std::vector<Cell> v;
    auto acc = g.getConstAccessor();
    for (auto it = g.tree().cbeginValueOn(); it; ++it) {
        if (!(*it < 0)) continue;
        openvdb::CoordBBox b = it.getBoundingBox();
        for (auto p = b.begin(); p; ++p) {
            const openvdb::Coord c = *p;
            bool edge = false;
            for (int a = 0; a < 3 && !edge; a++)
                for (int s = -1; s <= 1; s += 2) {
                    openvdb::Coord n = c;
                    n[a] += s;
                    if (!(acc.getValue(n) < 0)) edge = true;
                }
            if (edge) v.push_back({c.x(), c.y(), c.z()});
        }
    }
    std::sort(v.begin(), v.end());
    return v;
}

// Every cell of the tree's bounding box (active or not) with value < 0.
std::vector<Cell> brute_solid(const openvdb::FloatGrid& g) {
    std::vector<Cell> v;
    openvdb::CoordBBox b;
    g.tree().evalLeafBoundingBox(b);
    auto acc = g.getConstAccessor();
    for (auto p = b.begin(); p; ++p)
        if (acc.getValue(*p) < 0) v.push_back({(*p).x(), (*p).y(), (*p).z()});
    std::sort(v.begin(), v.end());
    return v;
}

uint64_t model_voxels(const vx_svo_scene& s) {
    uint64_t n = 0;
    for (uint32_t i = 0; i < s.model_count; i++) n += s.models[i].voxel_count;
    return n;
}

// ---------------------------------------------------------------------------

void test_sphere_surface_and_solid(void) {
    const float r = 12.0f, vs = 0.5f;
    openvdb::FloatGrid::Ptr g =
        openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(r, openvdb::Vec3f(1.5f, -3.0f, 2.25f), vs, 3.0f);
    g->setName("ls");
    std::string bytes = to_bytes({g});

    vx_svo_scene s = {};
    vx_conv_vdb_desc d = {};
    REQUIRE(convert(bytes, d, &s));
    Decoded got;
    REQUIRE(decode(s, &got));
    std::vector<Cell> want = brute_surface(*g);
    CHECKF(got.cells == want, "surface: %zu cells, expected %zu", got.cells.size(), want.size());
    // The shell of a sphere of radius r/vs = 24 voxels: close to its area.
    const double area = 4.0 * M_PI * (r / vs) * (r / vs);
    CHECKF(want.size() > 0.8 * area && want.size() < 1.6 * area, "shell %zu vs area %.0f", want.size(), area);

    // world_from_grid maps the centre of grid cell g (g + 1/2) to OpenVDB's
    // world position of voxel g.
    const openvdb::Coord probe(7, -3, 11);
    const openvdb::Vec3d w = g->transform().indexToWorld(probe);
    for (int row = 0; row < 3; row++) {
        const double* m = &s.world_from_grid[row * 4];
        double x = m[0] * (probe.x() + 0.5) + m[1] * (probe.y() + 0.5) + m[2] * (probe.z() + 0.5) + m[3];
        CHECKF(std::fabs(x - w[row]) < 1e-9, "world row %d: %g vs %g", row, x, w[row]);
    }
    vx_svo_scene_free(&s);

    d.solid = true;
    REQUIRE(convert(bytes, d, &s));
    Decoded solid;
    REQUIRE(decode(s, &solid));
    std::vector<Cell> want_solid = brute_solid(*g);
    CHECKF(solid.cells == want_solid, "solid: %zu cells, expected %zu", solid.cells.size(), want_solid.size());
    const double vol = 4.0 / 3.0 * M_PI * std::pow(r / vs, 3.0);
    CHECKF(std::fabs(double(want_solid.size()) - vol) < 0.05 * vol, "solid %zu vs volume %.0f", want_solid.size(), vol);
    // the surface is exactly the solid's cells with an outside face neighbour
    CHECK(std::includes(want_solid.begin(), want_solid.end(), want.begin(), want.end()));
    vx_svo_scene_free(&s);
}

// Active interior tiles in a level set: only their face cells with an
// outside neighbour are surface (found square by square, not cell by cell).
void test_level_set_active_tiles(void) {
    openvdb::FloatGrid::Ptr g = openvdb::FloatGrid::create(2.0f);
    g->setGridClass(openvdb::GRID_LEVEL_SET);
    g->tree().addTile(1, openvdb::Coord(0, 0, 0), -1.0f, true);
    g->tree().addTile(1, openvdb::Coord(8, 0, 0), -1.0f, true);   // shares a face with the first
    g->tree().addTile(2, openvdb::Coord(128, 0, 0), -1.0f, true); // 128^3
    g->tree().setValue(openvdb::Coord(0, -1, 0), -0.5f);          // inside, below a tile cell
    g->tree().setValue(openvdb::Coord(200, 128, 5), -0.5f);       // touches the big tile's top face
    std::string bytes = to_bytes({g});
    vx_svo_scene s = {};
    REQUIRE(convert(bytes, vx_conv_vdb_desc{}, &s));
    Decoded got;
    REQUIRE(decode(s, &got));
    std::vector<Cell> want = brute_surface(*g);
    CHECKF(got.cells == want, "%zu cells, expected %zu", got.cells.size(), want.size());
    const Cell open_x = {0, 0, 0}, covered = {200, 127, 5}, top = {201, 127, 5};
    CHECK(std::binary_search(want.begin(), want.end(), open_x)); // still open towards -x
    CHECK(!std::binary_search(want.begin(), want.end(), covered)); // its only outside side is covered
    CHECK(std::binary_search(want.begin(), want.end(), top));
    vx_svo_scene_free(&s);
}

// The shim reports what OpenVDB reports.
void test_shim_info(void) {
    openvdb::FloatGrid::Ptr g = openvdb::FloatGrid::create(0.5f);
    g->setName("fog");
    g->setGridClass(openvdb::GRID_FOG_VOLUME);
    g->setSaveFloatAsHalf(true);
    g->setTransform(openvdb::math::Transform::createLinearTransform(0.125));
    g->transform().postTranslate(openvdb::Vec3d(1, 2, 3));
    g->tree().setValue(openvdb::Coord(-5, 6, 7), 1.0f);
    g->tree().addTile(1, openvdb::Coord(64, 64, 64), 1.0f, true);
    std::string bytes = to_bytes({g});
    vx_vdb_file* f = nullptr;
    vx_error err = {};
    REQUIRE(vx_vdb_read(bytes.data(), bytes.size(), &f, &err) == VX_OK);
    REQUIRE(vx_vdb_grid_count(f) == 1);
    vx_vdb_grid_info info;
    REQUIRE(vx_vdb_grid_get_info(f, 0, &info, &err) == VX_OK);
    CHECK(std::string(info.name) == "fog");
    CHECK(info.value_type == VX_VDB_TYPE_FLOAT && info.components == 1);
    CHECK(info.grid_class == VX_VDB_CLASS_FOG_VOLUME);
    CHECK(info.saved_as_half);
    CHECK(info.linear);
    CHECK(info.active_voxels == g->activeVoxelCount() && info.active_voxels == 513u);
    CHECK(info.active_tiles == 1u);
    CHECK(info.background[0] == 0.5);
    CHECK(info.bbox_min[0] == -5 && info.bbox_max[2] == 71);
    const openvdb::Vec3d w = g->transform().indexToWorld(openvdb::Coord(3, -4, 5));
    for (int r = 0; r < 3; r++) {
        const double* m = &info.index_to_world[r * 4];
        CHECK(std::fabs(m[0] * 3 + m[1] * -4 + m[2] * 5 + m[3] - w[r]) < 1e-12);
    }
    const int32_t in_tile[3] = {70, 65, 64}, in_leaf[3] = {-5, 6, 7}, outside[3] = {100000, 0, 0};
    double v[3];
    bool active = false;
    uint32_t l2 = 99;
    CHECK(vx_vdb_probe(f, 0, in_tile, v, &active, &l2) && v[0] == 1.0 && active && l2 == 3);
    CHECK(vx_vdb_probe(f, 0, in_leaf, v, &active, &l2) && v[0] == 1.0 && active && l2 == 0);
    CHECK(vx_vdb_probe(f, 0, outside, v, &active, &l2) && v[0] == 0.5 && !active && l2 == 12);
    CHECK(!vx_vdb_probe(f, 1, outside, v, &active, &l2));
    CHECK(vx_vdb_iterate(f, 1, VX_VDB_ITER_ACTIVE, [](void*, const int32_t*, uint32_t, bool, const double*) { return true; },
                         nullptr, &err) == VX_ERR_INVALID_ARG);
    CHECK(!std::strcmp(err.msg, "vdb: grid 1 out of range (1 grids)"));
    // the grid calls' one argument check (grid_arg): a missing output or callback, a grid past the count
    CHECK(vx_vdb_grid_get_info(f, 1, &info, &err) == VX_ERR_INVALID_ARG &&
          !std::strcmp(err.msg, "vdb: grid 1 out of range (1 grids)"));
    CHECK(vx_vdb_grid_get_info(f, 0, nullptr, &err) == VX_ERR_INVALID_ARG && !std::strcmp(err.msg, "vdb: NULL argument"));
    CHECK(vx_vdb_grid_get_info(nullptr, 0, &info, &err) == VX_ERR_INVALID_ARG);
    CHECK(vx_vdb_iterate(f, 0, VX_VDB_ITER_ACTIVE, nullptr, nullptr, &err) == VX_ERR_INVALID_ARG &&
          !std::strcmp(err.msg, "vdb: NULL argument"));
    vx_vdb_file_free(f);
}

void test_fog_thresholds_and_density(void) {
    // A fog volume with a ramp of values, a filled region (tiles) and
    // negative / zero values that must be skipped by default.
    openvdb::FloatGrid::Ptr g = openvdb::FloatGrid::create(0.0f);
    g->setName("density");
    g->setGridClass(openvdb::GRID_FOG_VOLUME);
    g->setTransform(openvdb::math::Transform::createLinearTransform(0.25));
    g->transform().postTranslate(openvdb::Vec3d(10, -2, 3));
    auto acc = g->getAccessor();
    for (int x = -20; x < 20; x++)
        for (int y = -5; y < 9; y++)
            for (int z = 0; z < 7; z++) acc.setValue(openvdb::Coord(x, y, z), float((x + 20) * 0.025 - 0.1));
    g->tree().fill(openvdb::CoordBBox(openvdb::Coord(64, 64, 64), openvdb::Coord(79, 79, 79)), 0.75f, true);
    std::string bytes = to_bytes({g});

    const double thr[] = {0.0, 0.3, 0.75, 0.9};
    for (int k = -1; k < 4; k++) {
        vx_svo_scene s = {};
        vx_conv_vdb_desc d = {};
        if (k >= 0) {
            d.threshold_set = true;
            d.threshold = thr[k];
        }
        d.density = true;
        REQUIRE(convert(bytes, d, &s));
        Decoded got;
        REQUIRE(decode(s, &got, true));
        std::vector<Cell> want = brute_fog(*g, k >= 0 ? thr[k] : 0.0, k >= 0);
        CHECKF(got.cells == want, "threshold %d: %zu cells, expected %zu", k, got.cells.size(), want.size());
        CHECK(model_voxels(s) == want.size());
        auto ca = g->getConstAccessor();
        size_t bad = 0;
        for (auto& e : got.density)
            if (e.second != ca.getValue(openvdb::Coord(int(e.first[0]), int(e.first[1]), int(e.first[2])))) bad++;
        CHECKF(bad == 0 && got.density.size() == want.size(), "%zu density mismatches", bad);
        vx_svo_scene_free(&s);
    }
}

void test_tiles_collapse(void) {
    openvdb::FloatGrid::Ptr g = openvdb::FloatGrid::create(0.0f);
    g->setGridClass(openvdb::GRID_FOG_VOLUME);
    // One 128^3 tile of an upper internal node, some 8^3 tiles plus voxels
    // from an unaligned fill, and a lone voxel.
    g->tree().addTile(2, openvdb::Coord(128, 0, -128), 1.0f, true);
    g->tree().fill(openvdb::CoordBBox(openvdb::Coord(-20, -20, -20), openvdb::Coord(-5, -5, -5)), 0.5f, true);
    g->tree().setValue(openvdb::Coord(3, 4, 5), 2.0f);
    REQUIRE(g->tree().activeTileCount() > 1);
    std::string bytes = to_bytes({g});

    vx_svo_scene s = {};
    vx_conv_stats st = {};
    REQUIRE(convert(bytes, vx_conv_vdb_desc{}, &s, &st));
    Decoded got;
    REQUIRE(decode(s, &got));
    std::vector<Cell> want = brute_fog(*g, 0, false);
    CHECK(want.size() == 128u * 128u * 128u + 16u * 16u * 16u + 1u);
    CHECKF(got.cells == want, "%zu cells, expected %zu", got.cells.size(), want.size());
    // Tiles were handed over whole (not voxel by voxel) and stay collapsed.
    CHECKF(st.build.input_voxels < 4096, "%llu input entries", (unsigned long long)st.build.input_voxels);
    uint32_t words = 0;
    for (uint32_t i = 0; i < s.model_count; i++) words += s.models[i].node_count;
    CHECKF(words < 200, "%u node words", words);
    vx_svo_scene_free(&s);
}

void test_split_regions(void) {
    openvdb::FloatGrid::Ptr g = openvdb::FloatGrid::create(0.0f);
    g->setGridClass(openvdb::GRID_FOG_VOLUME);
    auto acc = g->getAccessor();
    const int pts[][3] = {{0, 0, 0},         {63, 63, 63},     {64, 0, 0},        {1000, -5000, 70000},
                          {-300000, 2, 3},   {-1, -1, -1},     {-64, -65, 200},   {1 << 30, -(1 << 30), 5},
                          {-(1 << 30), 0, 0}, {2000000, 3, -2000000}};
    for (auto& p : pts) acc.setValue(openvdb::Coord(p[0], p[1], p[2]), 1.0f);
    g->tree().addTile(1, openvdb::Coord(-1024, 512, 8), 3.0f, true); // an 8^3 tile
    std::string bytes = to_bytes({g});
    std::vector<Cell> want = brute_fog(*g, 0, false);

    const uint32_t depths[] = {0, 6, 2};
    for (uint32_t depth : depths) {
        vx_svo_scene s = {};
        vx_conv_vdb_desc d = {};
        d.max_model_depth = depth;
        REQUIRE(convert(bytes, d, &s));
        const uint32_t D = depth ? depth : VX_SVO_MAX_DEPTH;
        CHECKF(s.model_count > 1, "depth %u: %u models", depth, s.model_count);
        for (uint32_t i = 0; i < s.model_count; i++)
            CHECKF(s.models[i].depth <= D, "depth %u: model %u has depth %u", depth, i, s.models[i].depth);
        Decoded got;
        REQUIRE(decode(s, &got));
        CHECKF(got.cells == want, "depth %u: %zu cells, expected %zu", depth, got.cells.size(), want.size());
        vx_svo_scene_free(&s);
    }
}

void test_color_grid(void) {
    openvdb::FloatGrid::Ptr g = openvdb::FloatGrid::create(0.0f);
    g->setName("density");
    openvdb::Vec3SGrid::Ptr c = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.2f, 0.2f, 0.2f));
    c->setName("Cd");
    auto ga = g->getAccessor();
    auto ca = c->getAccessor();
    for (int i = 0; i < 10; i++) {
        ga.setValue(openvdb::Coord(i, 2 * i, -i), 1.0f);
        ca.setValue(openvdb::Coord(i, 2 * i, -i), openvdb::Vec3s(i * 0.125f, 1.5f, -0.5f)); // clamped
    }
    ga.setValue(openvdb::Coord(50, 50, 50), 1.0f); // colour from the background
    g->tree().addTile(1, openvdb::Coord(64, 0, 0), 1.0f, true);
    c->tree().addTile(1, openvdb::Coord(64, 0, 0), openvdb::Vec3s(1, 0, 0.5f), true); // uniform over the tile
    g->tree().addTile(1, openvdb::Coord(128, 0, 0), 1.0f, true);
    ca.setValue(openvdb::Coord(130, 1, 2), openvdb::Vec3s(0, 1, 0)); // varies inside this tile
    std::string bytes = to_bytes({g, c});

    vx_svo_scene s = {};
    vx_conv_vdb_desc d = {};
    d.color_grid = "Cd";
    REQUIRE(convert(bytes, d, &s));
    Decoded got;
    REQUIRE(decode(s, &got, true));
    auto srgb = [](double v) -> uint32_t {
        v = std::min(1.0, std::max(0.0, v));
        double e = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055;
        return uint32_t(std::lround(e * 255.0));
    };
    auto cc = c->getConstAccessor();
    size_t bad = 0;
    for (const Cell& p : got.cells) {
        openvdb::Vec3s v = cc.getValue(openvdb::Coord(int(p[0]), int(p[1]), int(p[2])));
        uint32_t want = srgb(v[0]) | (srgb(v[1]) << 8) | (srgb(v[2]) << 16) | 0xFF000000u;
        if (got.rgba[p] != want) bad++;
    }
    CHECK(got.cells.size() == 11u + 2u * 512u);
    CHECKF(bad == 0, "%zu colour mismatches", bad);
    vx_svo_scene_free(&s);
}

void test_half_and_grid_choice(void) {
    openvdb::Vec3SGrid::Ptr v = openvdb::Vec3SGrid::create();
    v->setName("vel");
    openvdb::DoubleGrid::Ptr dg = openvdb::DoubleGrid::create(0.0);
    dg->setName("d");
    dg->tree().setValue(openvdb::Coord(1, 2, 3), 0.5);
    openvdb::FloatGrid::Ptr h = openvdb::FloatGrid::create(0.0f);
    h->setName("h");
    h->setSaveFloatAsHalf(true);
    h->tree().setValue(openvdb::Coord(-4, 5, 6), 0.1f);
    h->tree().setValue(openvdb::Coord(-4, 5, 7), 0.00001f);
    std::string bytes = to_bytes({v, dg, h});

    vx_svo_scene s = {};
    vx_conv_vdb_desc d = {};
    REQUIRE(convert(bytes, d, &s)); // first scalar grid: the double grid
    Decoded a;
    REQUIRE(decode(s, &a));
    const std::vector<Cell> want_d = {{1, 2, 3}};
    CHECK(a.cells == want_d);
    vx_svo_scene_free(&s);

    d.grid = "h";
    d.density = true;
    REQUIRE(convert(bytes, d, &s));
    Decoded b;
    REQUIRE(decode(s, &b, true));
    CHECK(b.cells.size() == 2);
    // stored as half: 0.1 comes back as the nearest half value
    const Cell hc = {-4, 5, 6};
    CHECK(b.density[hc] == float(openvdb::math::half(0.1f)));
    vx_svo_scene_free(&s);

    vx_error err = {};
    d.grid = "vel";
    CHECK(vx_conv_vdb_memory(&d, bytes.data(), bytes.size(), &s, nullptr, &err) == VX_ERR_UNSUPPORTED);
    CHECK(std::strstr(err.msg, "vel") != nullptr);
    d.grid = "nope";
    CHECK(vx_conv_vdb_memory(&d, bytes.data(), bytes.size(), &s, nullptr, &err) == VX_ERR_INVALID_ARG);
    CHECK(std::strstr(err.msg, "'h'") != nullptr); // the message lists the grids
    d.grid = "h";
    d.color_grid = "d";
    CHECK(vx_conv_vdb_memory(&d, bytes.data(), bytes.size(), &s, nullptr, &err) == VX_ERR_UNSUPPORTED);
}

// Several grids may share a name (Arnold's and Houdini's writers do: three
// fog grids all named "density"). OpenVDB's io::File selects the N-th
// repeat as "NAME[N]"; so does vx_conv_vdb, and its list of grids names
// them so. A grid literally named with brackets is still matched as is.
void test_repeated_grid_names(void) {
    openvdb::GridPtrVec grids;
    for (int i = 0; i < 3; i++) {
        openvdb::FloatGrid::Ptr g = openvdb::FloatGrid::create(0.0f);
        g->setName("density");
        g->setGridClass(openvdb::GRID_FOG_VOLUME);
        g->tree().setValue(openvdb::Coord(i, 2 * i, 3 * i), 1.0f);
        grids.push_back(g);
    }
    openvdb::FloatGrid::Ptr lit = openvdb::FloatGrid::create(0.0f);
    lit->setName("x[1]");
    lit->tree().setValue(openvdb::Coord(7, 7, 7), 1.0f);
    grids.push_back(lit);
    const std::string bytes = to_bytes(grids);
    const char* names[] = {"density", "density[1]", "density[2]", "density[0]"};
    const int which[] = {0, 1, 2, 0};
    for (int k = 0; k < 4; k++) {
        vx_svo_scene s = {};
        vx_conv_vdb_desc d = {};
        d.grid = names[k];
        REQUIRE(convert(bytes, d, &s));
        Decoded got;
        REQUIRE(decode(s, &got));
        const int i = which[k];
        const std::vector<Cell> want = {{i, 2 * i, 3 * i}};
        CHECKF(got.cells == want, "%s: %zu cells", names[k], got.cells.size());
        vx_svo_scene_free(&s);
    }
    {
        vx_svo_scene s = {};
        vx_conv_vdb_desc d = {};
        d.grid = "x[1]";
        REQUIRE(convert(bytes, d, &s));
        Decoded got;
        REQUIRE(decode(s, &got));
        const std::vector<Cell> want = {{7, 7, 7}};
        CHECK(got.cells == want);
        vx_svo_scene_free(&s);
    }
    vx_svo_scene s = {};
    vx_conv_vdb_desc d = {};
    vx_error err = {};
    d.grid = "density[3]";
    CHECK(vx_conv_vdb_memory(&d, bytes.data(), bytes.size(), &s, nullptr, &err) == VX_ERR_INVALID_ARG);
    CHECKF(std::strstr(err.msg, "'density[2]'") != nullptr, "%s", err.msg); // the list names the repeats
    d.grid = "density[";
    CHECK(vx_conv_vdb_memory(&d, bytes.data(), bytes.size(), &s, nullptr, &err) == VX_ERR_INVALID_ARG);
}

// Grid names are matched whole: vx_vdb_grid_info.name keeps 127 bytes, and a
// longer name cut there must neither hide its grid nor stand for a grid
// whose whole name is the cut one.
void test_long_grid_names(void) {
    const std::string long_name(200, 'a'), cut(127, 'a');
    openvdb::FloatGrid::Ptr g = openvdb::FloatGrid::create(0.0f);
    g->setName(long_name);
    g->tree().setValue(openvdb::Coord(1, 2, 3), 1.0f);
    openvdb::FloatGrid::Ptr h = openvdb::FloatGrid::create(0.0f);
    h->setName(cut);
    h->tree().setValue(openvdb::Coord(4, 5, 6), 1.0f);
    const std::string bytes = to_bytes({g, h});
    const std::string* names[] = {&long_name, &cut};
    const std::vector<Cell> want[] = {{{1, 2, 3}}, {{4, 5, 6}}};
    for (int k = 0; k < 2; k++) {
        vx_svo_scene s = {};
        vx_conv_vdb_desc d = {};
        d.grid = names[k]->c_str();
        REQUIRE(convert(bytes, d, &s));
        Decoded got;
        REQUIRE(decode(s, &got));
        CHECKF(got.cells == want[k], "name of %zu bytes: %zu cells", names[k]->size(), got.cells.size());
        vx_svo_scene_free(&s);
    }
}

// OpenVDB points grids (Tree_ptdataidx32, e.g. from Houdini or Cortex) are
// not converted: the error says so rather than only naming the tree type.
void test_points_grid_refused(void) {
    std::vector<openvdb::Vec3R> pos = {{0, 0, 0}, {1.5, 0, 0}, {0, 2.5, 1}};
    openvdb::points::PointAttributeVector<openvdb::Vec3R> wrapper(pos);
    openvdb::math::Transform::Ptr xf = openvdb::math::Transform::createLinearTransform(0.5);
    openvdb::points::PointDataGrid::Ptr p = openvdb::points::createPointDataGrid<openvdb::points::NullCodec,
                                                                                  openvdb::points::PointDataGrid>(pos, *xf);
    p->setName("points");
    const std::string bytes = to_bytes({p});
    vx_svo_scene s = {};
    vx_conv_vdb_desc d = {};
    vx_error err = {};
    CHECK(vx_conv_vdb_memory(&d, bytes.data(), bytes.size(), &s, nullptr, &err) == VX_ERR_UNSUPPORTED);
    CHECKF(std::strstr(err.msg, "points grid") != nullptr, "%s", err.msg);
    d.grid = "points";
    CHECK(vx_conv_vdb_memory(&d, bytes.data(), bytes.size(), &s, nullptr, &err) == VX_ERR_UNSUPPORTED);
    CHECKF(std::strstr(err.msg, "points grid") != nullptr, "%s", err.msg);
    (void)wrapper;
}

void test_frustum_refused(void) {
    openvdb::FloatGrid::Ptr g = openvdb::FloatGrid::create(0.0f);
    g->tree().setValue(openvdb::Coord(1, 1, 1), 1.0f);
    g->setTransform(openvdb::math::Transform::createFrustumTransform(
        openvdb::BBoxd(openvdb::Vec3d(0, 0, 0), openvdb::Vec3d(10, 10, 10)), 0.5, 2.0, 1.0));
    std::string bytes = to_bytes({g});
    vx_svo_scene s = {};
    vx_error err = {};
    CHECK(vx_conv_vdb_memory(nullptr, bytes.data(), bytes.size(), &s, nullptr, &err) == VX_ERR_UNSUPPORTED);
    CHECK(std::strstr(err.msg, "frustum") != nullptr);
}

void test_bad_input(void) {
    openvdb::FloatGrid::Ptr g =
        openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(4.0f, openvdb::Vec3f(0, 0, 0), 0.5f, 2.0f);
    const std::string bytes = to_bytes({g});
    vx_svo_scene s = {};
    vx_error err = {};
    // every truncation is an error, never a crash or a silent partial grid
    for (size_t n = 0; n < bytes.size(); n += 1 + n / 8) {
        vx_result r = vx_conv_vdb_memory(nullptr, bytes.data(), n, &s, nullptr, &err);
        CHECKF(r != VX_OK, "truncated to %zu of %zu bytes: accepted", n, bytes.size());
        if (r == VX_OK) vx_svo_scene_free(&s);
    }
    CHECK(vx_conv_vdb_memory(nullptr, "not a vdb file at all", 21, &s, nullptr, &err) != VX_OK);
    CHECK(err.msg[0] != 0);
    // garbled bytes: any result but no crash (ASan watches)
    std::string m = bytes;
    uint64_t rng = 12345;
    for (int i = 0; i < 200; i++) {
        m = bytes;
        for (int e = 0; e < 4; e++) {
            rng = rng * 6364136223846793005ull + 1442695040888963407ull;
            m[size_t(rng >> 33) % m.size()] ^= char(1 + (rng >> 20) % 255);
        }
        if (vx_conv_vdb_memory(nullptr, m.data(), m.size(), &s, nullptr, &err) == VX_OK) vx_svo_scene_free(&s);
    }
    CHECK(vx_conv_vdb_file(nullptr, "/nonexistent/x.vdb", &s, nullptr, &err) == VX_ERR_IO);
}


// A length field past the end is refused before OpenVDB reads (it would
// allocate and zero what the field says: docs/RELIABILITY.md), naming the field.
static void put_u32(std::string& b, size_t at, uint32_t v) {
    for (int k = 0; k < 4; k++) b[at + k] = char((v >> (8 * k)) & 0xFF);
}

void test_length_caps(void) {
    openvdb::FloatGrid::Ptr g =
        openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(4.0f, openvdb::Vec3f(0, 0, 0), 0.5f, 2.0f);
    g->setName("ball");
    const std::string bytes = to_bytes({g});
    vx_svo_scene s = {};
    vx_error err = {};
    CHECK(vx_conv_vdb_memory(nullptr, bytes.data(), bytes.size(), &s, nullptr, &err) == VX_OK);
    vx_svo_scene_free(&s);
    // header 57 bytes, file metadata count, grid count, then grid 0's name
    std::string m = bytes;
    put_u32(m, 57, 0x10000000u);
    CHECK(vx_conv_vdb_memory(nullptr, m.data(), m.size(), &s, nullptr, &err) == VX_ERR_LIMIT);
    CHECKF(strstr(err.msg, "file metadata entries"), "%s", err.msg);
    size_t meta = 57;
    uint32_t file_meta = uint8_t(bytes[meta]) | uint32_t(uint8_t(bytes[meta + 1])) << 8;
    CHECK(file_meta == 0); // what to_bytes writes: no file metadata
    size_t name = 57 + 4 + 4;
    CHECK(bytes.compare(name + 4, 4, "ball") == 0);
    m = bytes;
    put_u32(m, name, 1701147220u); // the 1.7 GB of the fuzz finding
    CHECK(vx_conv_vdb_memory(nullptr, m.data(), m.size(), &s, nullptr, &err) == VX_ERR_LIMIT);
    CHECKF(strstr(err.msg, "grid 0's name of 1701147220 bytes"), "%s", err.msg);
    m = bytes;
    put_u32(m, 57 + 4, 0xFFFFFFF0u);
    CHECK(vx_conv_vdb_memory(nullptr, m.data(), m.size(), &s, nullptr, &err) == VX_ERR_LIMIT);
    CHECKF(strstr(err.msg, "grids cannot fit"), "%s", err.msg);
    // a grid metadata value: after "class" (length 5) and its type "string"
    size_t cls = bytes.find(std::string("\x05\0\0\0class\x06\0\0\0string", 19));
    CHECK(cls != std::string::npos);
    if (cls != std::string::npos) {
        m = bytes;
        put_u32(m, cls + 19, 2998055602u); // the 3 GB finding
        CHECK(vx_conv_vdb_memory(nullptr, m.data(), m.size(), &s, nullptr, &err) == VX_ERR_LIMIT);
        CHECKF(strstr(err.msg, "value of grid 0's metadata entry"), "%s", err.msg);
    }
    // an old format version is refused by name
    m = bytes;
    put_u32(m, 8, 221);
    CHECK(vx_conv_vdb_memory(nullptr, m.data(), m.size(), &s, nullptr, &err) == VX_ERR_UNSUPPORTED);
    CHECKF(strstr(err.msg, "file format 221"), "%s", err.msg);
}

template <class F>
void with_corpus_grid(const char* rel, F f) {
    const char* path = vx_test_corpus(rel);
    if (!path) return;
    openvdb::io::File file(path);
    file.open(false);
    openvdb::GridBase::Ptr base = file.readGrid(file.beginName().gridName());
    file.close();
    f(path, openvdb::gridPtrCast<openvdb::FloatGrid>(base));
}

void test_corpus_smoke(void) {
    if (!vx_test_corpus("vdb/mjurczyk_smoke.vdb")) SKIP("corpus vdb/mjurczyk_smoke.vdb not found");
    with_corpus_grid("vdb/mjurczyk_smoke.vdb", [](const char* path, openvdb::FloatGrid::Ptr g) {
        REQUIRE(g);
        CHECK(g->activeVoxelCount() == 1049275u);
        const double thr[] = {-1.0, 0.05, 0.5};
        for (int k = 0; k < 3; k++) {
            vx_conv_vdb_desc d = {};
            if (k) {
                d.threshold_set = true;
                d.threshold = thr[k];
            }
            vx_svo_scene s = {};
            vx_conv_stats st = {};
            vx_error err = {};
            vx_result r = vx_conv_vdb_file(&d, path, &s, &st, &err);
            REQUIRE(r == VX_OK);
            std::vector<Cell> want = brute_fog(*g, thr[k], k != 0);
            CHECKF(model_voxels(s) == want.size(), "threshold %g: %llu voxels, expected %zu", thr[k],
                   (unsigned long long)model_voxels(s), want.size());
            if (k == 0) { // full comparison once
                Decoded got;
                REQUIRE(decode(s, &got));
                CHECKF(got.cells == want, "%zu decoded, expected %zu", got.cells.size(), want.size());
            }
            vx_svo_scene_free(&s);
        }
    });
}

void test_corpus_sphere(void) {
    if (!vx_test_corpus("vdb/mjurczyk_sphere.vdb")) SKIP("corpus vdb/mjurczyk_sphere.vdb not found");
    with_corpus_grid("vdb/mjurczyk_sphere.vdb", [](const char* path, openvdb::FloatGrid::Ptr g) {
        REQUIRE(g);
        CHECK(g->activeVoxelCount() == 270638u);
        vx_svo_scene s = {};
        vx_error err = {};
        vx_conv_vdb_desc d = {};
        REQUIRE(vx_conv_vdb_file(&d, path, &s, nullptr, &err) == VX_OK);
        Decoded got;
        REQUIRE(decode(s, &got));
        std::vector<Cell> want =
            g->getGridClass() == openvdb::GRID_LEVEL_SET ? brute_surface(*g) : brute_fog(*g, 0, false);
        CHECKF(got.cells == want, "%zu decoded, expected %zu", got.cells.size(), want.size());
        // the file round trip keeps it
        uint8_t* data = nullptr;
        size_t size = 0;
        REQUIRE(vx_svo_write(&s, nullptr, &data, &size, &err) == VX_OK);
        vx_svo_scene back = {};
        CHECK(vx_svo_read(nullptr, data, size, &back, &err) == VX_OK);
        Decoded again;
        CHECK(decode(back, &again) && again.cells == got.cells);
        vx_svo_scene_free(&back);
        vx_free(nullptr, data);
        vx_svo_scene_free(&s);
        d.solid = true;
        REQUIRE(vx_conv_vdb_file(&d, path, &s, nullptr, &err) == VX_OK);
        CHECK(model_voxels(s) == brute_solid(*g).size());
        vx_svo_scene_free(&s);
    });
}

} // namespace


// A 24-frame fog sequence written by OpenVDB: a fixed box (density 1) and a
// sphere (density 2 + f/100) moving through it. Every frame of the one
// animated scene equals OpenVDB's active voxels and values of that frame;
// the box's bricks the sphere never touches are stored once, so the stored
// voxels stay within the box plus, per frame, the bricks the sphere touches.
static void test_sequence(void) {
    char dir[] = "/tmp/vx_vdb_seqXXXXXX";
    REQUIRE(mkdtemp(dir));
    enum { F = 24, B = 32 }; // B: the sequence's brick, 2^VX_CONV_VDB_SEQUENCE_BRICK_DEPTH
    static_assert(B == 1 << VX_CONV_VDB_SEQUENCE_BRICK_DEPTH, "brick size");
    std::vector<std::string> names;
    std::vector<openvdb::FloatGrid::Ptr> grids;
    uint64_t frame_voxels = 0, bound = 0;
    std::map<Cell, int> box_brick_touched; // brick -> frames in which the sphere touches it
    const openvdb::CoordBBox box(openvdb::Coord(0, 0, 0), openvdb::Coord(69, 39, 19));
    for (int f = 0; f < F; f++) {
        openvdb::FloatGrid::Ptr g = openvdb::FloatGrid::create(0.0f);
        g->setName("density");
        g->setGridClass(openvdb::GRID_FOG_VOLUME);
        auto acc = g->getAccessor();
        for (auto p = box.begin(); p; ++p) acc.setValueOn(*p, 1.0f);
        const int cx = 4 + 3 * f, cy = 20, cz = 10, R = 6;
        for (int x = cx - R; x <= cx + R; x++)
            for (int y = cy - R; y <= cy + R; y++)
                for (int z = cz - R; z <= cz + R; z++)
                    if ((x - cx) * (x - cx) + (y - cy) * (y - cy) + (z - cz) * (z - cz) <= R * R)
                        acc.setValueOn(openvdb::Coord(x, y, z), 2.0f + f / 100.0f);
        char path[256];
        snprintf(path, sizeof path, "%s/smoke_%04d.vdb", dir, f);
        openvdb::io::File file(path);
        file.write({g});
        file.close();
        names.push_back(path);
        grids.push_back(g);
        // the bricks the sphere touches in this frame are stored for this frame
        std::map<Cell, uint64_t> in_brick;
        for (auto it = g->tree().cbeginValueOn(); it; ++it) {
            openvdb::CoordBBox b = it.getBoundingBox();
            for (auto p = b.begin(); p; ++p) {
                Cell br = {(*p).x() >> 5, (*p).y() >> 5, (*p).z() >> 5};
                in_brick[br]++;
                frame_voxels++;
            }
        }
        for (int bx = (cx - R) >> 5; bx <= (cx + R) >> 5; bx++)
            for (int by = (cy - R) >> 5; by <= (cy + R) >> 5; by++)
                for (int bz = (cz - R) >> 5; bz <= (cz + R) >> 5; bz++) {
                    bound += in_brick[{bx, by, bz}];
                    box_brick_touched[{bx, by, bz}]++;
                }
    }
    // box voxels of bricks the sphere leaves alone in some frame: once
    for (auto p = box.begin(); p; ++p) {
        auto t = box_brick_touched.find({(*p).x() >> 5, (*p).y() >> 5, (*p).z() >> 5});
        if (t == box_brick_touched.end() || t->second < F) bound++;
    }
    std::vector<const char*> paths;
    for (auto& n : names) paths.push_back(n.c_str());
    vx_conv_vdb_desc d = {};
    d.density = true;
    vx_svo_scene s;
    vx_conv_stats st = {};
    vx_error err = {};
    vx_result r = vx_conv_vdb_sequence(&d, paths.data(), F, &s, &st, &err);
    CHECKF(r == VX_OK, "%s", err.msg);
    if (r) return;
    CHECK(vx_svo_scene_frames(&s) == F && st.frames == F);
    // through the file: FRMS and shared models survive
    uint8_t* data = nullptr;
    size_t size = 0; // kept: the bytes of the animation
    vx_svo_scene back;
    REQUIRE(vx_svo_write(&s, nullptr, &data, &size, &err) == VX_OK);
    REQUIRE(vx_svo_read(nullptr, data, size, &back, &err) == VX_OK);
    free(data);
    for (int f = 0; f < F; f++) {
        vx_svo_scene v;
        REQUIRE(vx_svo_scene_frame(&back, (uint32_t)f, &v));
        Decoded got;
        REQUIRE(decode(v, &got, true));
        std::vector<Cell> want = brute_fog(*grids[f], 0, false);
        CHECKF(got.cells == want, "frame %d: %zu cells, OpenVDB has %zu", f, got.cells.size(), want.size());
        auto acc = grids[f]->getConstAccessor();
        size_t bad = 0;
        for (const Cell& c : got.cells)
            bad += got.density[c] != acc.getValue(openvdb::Coord((int)c[0], (int)c[1], (int)c[2]));
        CHECKF(bad == 0, "frame %d: %zu densities differ", f, bad);
    }
    uint64_t stored = 0;
    for (uint32_t m = 0; m < back.model_count; m++) stored += back.models[m].voxel_count;
    fprintf(stderr, "  24 frames, %llu voxels in all; %llu stored in %u models (bound %llu)\n", (unsigned long long)frame_voxels,
            (unsigned long long)stored, back.model_count, (unsigned long long)bound);
    CHECKF(stored <= bound, "%llu voxels stored, the static box alone would allow %llu", (unsigned long long)stored,
           (unsigned long long)bound);
    CHECK(stored * 2 < frame_voxels);
    // bytes: the animation against its largest frame converted alone
    size_t largest = 0;
    for (int f = 0; f < F; f++) {
        vx_svo_scene one;
        REQUIRE(vx_conv_vdb_file(&d, paths[f], &one, nullptr, &err) == VX_OK);
        uint8_t* b = nullptr;
        size_t n = 0;
        REQUIRE(vx_svo_write(&one, nullptr, &b, &n, &err) == VX_OK);
        free(b);
        largest = std::max(largest, n);
        vx_svo_scene_free(&one);
    }
    fprintf(stderr, "  %zu bytes, the largest frame alone %zu (%.2fx)\n", size, largest, (double)size / largest);
    vx_svo_scene_free(&back);
    vx_svo_scene_free(&s);
    // a frame whose transform differs is refused, naming the frame and file
    openvdb::FloatGrid::Ptr g2 = grids[0]->deepCopy();
    g2->setTransform(openvdb::math::Transform::createLinearTransform(0.5));
    {
        openvdb::io::File file(names[5]);
        file.write({g2});
        file.close();
    }
    CHECK(vx_conv_vdb_sequence(&d, paths.data(), F, &s, &st, &err) == VX_ERR_UNSUPPORTED && strstr(err.msg, "frame 5") &&
          strstr(err.msg, "smoke_0005.vdb"));
    remove(names[7].c_str());
    CHECK(vx_conv_vdb_sequence(&d, paths.data(), F, &s, &st, &err) != VX_OK && strstr(err.msg, "frame 5"));
    for (auto& n : names) remove(n.c_str());
    rmdir(dir);
}

int main() {
    openvdb::initialize();
    RUN(test_sphere_surface_and_solid);
    RUN(test_level_set_active_tiles);
    RUN(test_shim_info);
    RUN(test_fog_thresholds_and_density);
    RUN(test_tiles_collapse);
    RUN(test_split_regions);
    RUN(test_color_grid);
    RUN(test_half_and_grid_choice);
    RUN(test_repeated_grid_names);
    RUN(test_points_grid_refused);
    RUN(test_long_grid_names);
    RUN(test_frustum_refused);
    RUN(test_bad_input);
    RUN(test_length_caps);
    RUN(test_sequence);
    RUN(test_corpus_smoke);
    RUN(test_corpus_sphere);
    return vx_test_finish();
}
