// tests/fuzz/make_vdb_seeds.cpp - writes the vdb_fuzz seeds (tests/fuzz/vdb_seeds/).
//
// Small grids in one root child each (a grid spanning the origin has up to 8
// root children of 32^3 values each, which made the former seeds 40-80 KB and
// 0.5 s an input): a level-set sphere (zip; half floats with blosc), a fog
// volume with a tile and a vec3 colour grid "Cd" (zip; only the active
// mask compression), a double grid
// under a rotated, scaled transform. Not built by CMake (run once by hand):
//   g++ -std=c++17 -O1 tests/fuzz/make_vdb_seeds.cpp -o /tmp/mkseeds \
//       -lopenvdb -ltbb -lImath-3_1 && /tmp/mkseeds tests/fuzz/vdb_seeds
#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetSphere.h>
#include <openvdb/io/Stream.h>
#include <fstream>
using namespace openvdb;
static void write(const char* path, GridPtrVec grids, uint32_t comp) {
    std::ofstream os(path, std::ios::binary);
    io::Stream s(os);
    s.setCompression(comp);
    s.write(grids);
}
int main(int argc, char** argv) {
    openvdb::initialize();
    std::string dir = argc > 1 ? argv[1] : ".";
    {   // level set sphere, radius 3 voxels, zip
        auto g = tools::createLevelSetSphere<FloatGrid>(3.0f, Vec3f(12.5f, 11.5f, 13.0f), 1.0f, 2.0f);
        g->setName("surface");
        write((dir + "/sphere_zip.vdb").c_str(), {g}, io::COMPRESS_ZIP | io::COMPRESS_ACTIVE_MASK);
        g->setSaveFloatAsHalf(true);
        write((dir + "/sphere_half_blosc.vdb").c_str(), {g}, io::COMPRESS_BLOSC | io::COMPRESS_ACTIVE_MASK);
    }
    {   // fog: a tile of 8^3 cells, a few voxels, a colour grid Cd
        auto g = FloatGrid::create(0.0f);
        g->setName("density");
        g->setGridClass(GRID_FOG_VOLUME);
        g->setTransform(math::Transform::createLinearTransform(0.25));
        auto acc = g->getAccessor();
        acc.setValue(Coord(3, 2, 1), 0.5f);
        acc.setValue(Coord(9, 9, 9), 1.0f);
        acc.setValue(Coord(20, 0, 5), 0.25f);
        g->tree().addTile(1, Coord(16, 0, 0), 0.75f, true);
        auto c = Vec3SGrid::create(Vec3s(0));
        c->setName("Cd");
        auto ca = c->getAccessor();
        ca.setValue(Coord(3, 2, 1), Vec3s(1, 0, 0));
        ca.setValue(Coord(9, 9, 9), Vec3s(0, 1, 0.5f));
        
        write((dir + "/fog_tile_cd_zip.vdb").c_str(), {g, c}, io::COMPRESS_ZIP | io::COMPRESS_ACTIVE_MASK);
        write((dir + "/fog_tile_cd_mask.vdb").c_str(), {g, c}, io::COMPRESS_ACTIVE_MASK); // values not deflated
    }
    {   // double grid with a rotated transform
        auto g = DoubleGrid::create(0.0);
        g->setName("d");
        math::Mat4d m = math::Mat4d::identity();
        m.setToRotation(math::Vec3d(0, 0, 1), 0.5);
        m.preScale(math::Vec3d(0.5, 0.5, 0.5));
        m.setTranslation(math::Vec3d(1, 2, 3));
        g->setTransform(math::Transform::createLinearTransform(m));
        auto acc = g->getAccessor();
        for (int i = 0; i < 5; i++) acc.setValue(Coord(i, i * 2, 7 - i), 0.2 * (i + 1));
        write((dir + "/double_rot.vdb").c_str(), {g}, io::COMPRESS_ZIP);
    }
    return 0;
}
