// bench/anim_bench.cpp - animations (issue 24), docs/PERFORMANCE.md "Animation".
//
//   anim_bench [--frames N] [--res R] [--dir DIR] [--brick D]
//
// Writes N frames of a generated smoke plume at R^3 (OpenVDB fog volumes: a
// column of value noise that rises one cell per frame, density kept) into
// DIR, then converts (1) each frame alone (vx_conv_vdb_file, the
// same options) and (2) the whole sequence into one animation
// (vx_conv_vdb_sequence), and prints the voxel rate of both (voxels
// converted per second, reading included), and the bytes of the animation
// against the largest single frame. A second sequence, the same smoke
// standing still while a small puff moves, shows what frames that share
// most voxels cost.
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "convert/volume.h"
#include "svo/svo.h"

namespace {

double hash3(int x, int y, int z) {
    uint32_t h = (uint32_t)x * 73856093u ^ (uint32_t)y * 19349663u ^ (uint32_t)z * 83492791u;
    h ^= h >> 13, h *= 0x5bd1e995u, h ^= h >> 15;
    return (h & 0xFFFFFF) / double(0xFFFFFF);
}

// Trilinear value noise with 8-cell lattice, in [0, 1].
double noise(double x, double y, double z) {
    int X = (int)std::floor(x / 8), Y = (int)std::floor(y / 8), Z = (int)std::floor(z / 8);
    double fx = x / 8 - X, fy = y / 8 - Y, fz = z / 8 - Z, v = 0;
    for (int c = 0; c < 8; c++) {
        double w = ((c & 1) ? fx : 1 - fx) * ((c & 2) ? fy : 1 - fy) * ((c & 4) ? fz : 1 - fz);
        v += w * hash3(X + (c & 1), Y + (c >> 1 & 1), Z + (c >> 2 & 1));
    }
    return v;
}

// Frame f of the plume: density in a cylinder of radius res/3 around the
// vertical axis, noise advected upwards by `rise` cells per frame; cells
// below 0.45 are left out. puff >= 0: a static plume (rise 0) plus a ball
// of radius res/16 at height puff.
openvdb::FloatGrid::Ptr smoke(int res, int f, int rise, int puff) {
    openvdb::FloatGrid::Ptr g = openvdb::FloatGrid::create(0.0f);
    g->setName("density");
    g->setGridClass(openvdb::GRID_FOG_VOLUME);
    auto acc = g->getAccessor();
    double c = res / 2.0, r2 = (res / 3.0) * (res / 3.0);
    for (int z = 0; z < res; z++)
        for (int y = 0; y < res; y++)
            for (int x = 0; x < res; x++) {
                double dx = x - c, dy = y - c, d2 = dx * dx + dy * dy;
                if (d2 > r2) continue;
                double v = noise(x, y, z - (double)rise * f) * (1.0 - d2 / r2) * 1.6;
                if (v > 0.45) acc.setValueOn(openvdb::Coord(x, y, z), (float)std::round(v * 64) / 64);
            }
    if (puff >= 0) {
        int R = res / 16, px = res / 8;
        for (int z = puff - R; z <= puff + R; z++)
            for (int y = px - R; y <= px + R; y++)
                for (int x = px - R; x <= px + R; x++)
                    if ((x - px) * (x - px) + (y - px) * (y - px) + (z - puff) * (z - puff) <= R * R)
                        acc.setValueOn(openvdb::Coord(x, y, z), 1.0f);
    }
    return g;
}

size_t svo_bytes(const vx_svo_scene& s) {
    uint8_t* d = nullptr;
    size_t n = 0;
    vx_error e = {};
    if (vx_svo_write(&s, nullptr, &d, &n, &e) != VX_OK) {
        fprintf(stderr, "write: %s\n", e.msg);
        exit(1);
    }
    free(d);
    return n;
}

double now() { return vx_time_now(); }

int g_brick = 0; // --brick D: vx_conv_vdb_desc.brick_depth (0: the library's default)

void run(const char* what, const std::string& dir, int frames, int res, int rise, bool puff) {
    std::vector<std::string> names;
    double tg = now();
    for (int f = 0; f < frames; f++) {
        char p[512];
        snprintf(p, sizeof p, "%s/%s_%04d.vdb", dir.c_str(), what, f);
        openvdb::io::File file(p);
        file.write({smoke(res, f, rise, puff ? res / 8 + f * res / (frames + 8) : -1)});
        file.close();
        names.push_back(p);
    }
    tg = now() - tg;
    vx_conv_vdb_desc d = {};
    d.density = true;
    vx_error err = {};
    vx_conv_vdb_desc ds = d; // the sequence's: bricks
    ds.brick_depth = (uint32_t)g_brick;
    // every frame alone (the same options, regions as vox2svo makes them)
    double t1 = 0;
    uint64_t v1 = 0;
    size_t largest = 0;
    uint64_t largest_vox = 0;
    for (int f = 0; f < frames; f++) {
        vx_svo_scene s;
        vx_conv_stats st = {};
        double t0 = now();
        if (vx_conv_vdb_file(&d, names[f].c_str(), &s, &st, &err) != VX_OK) {
            fprintf(stderr, "%s: %s\n", names[f].c_str(), err.msg);
            exit(1);
        }
        double dt = now() - t0;
        t1 += dt, v1 += st.build.voxels;
        size_t b = svo_bytes(s);
        if (b > largest) largest = b, largest_vox = st.build.voxels;
        vx_svo_scene_free(&s);
    }
    std::vector<const char*> paths;
    for (auto& n : names) paths.push_back(n.c_str());
    vx_svo_scene s;
    vx_conv_stats st = {};
    double t0 = now();
    if (vx_conv_vdb_sequence(&ds, paths.data(), (uint32_t)frames, &s, &st, &err) != VX_OK) {
        fprintf(stderr, "sequence: %s\n", err.msg);
        exit(1);
    }
    double ts = now() - t0;
    size_t bytes = svo_bytes(s);
    uint64_t stored = 0;
    for (uint32_t m = 0; m < s.model_count; m++) stored += s.models[m].voxel_count;
    printf("%-8s %u frames at %d^3 (written in %.1f s)\n", what, frames, res, tg);
    printf("  single frames   %.2f M voxels/s (%llu voxels in %.2f s)\n", v1 / t1 * 1e-6, (unsigned long long)v1, t1);
    printf("  sequence        %.2f M voxels/s (%llu voxels in %.2f s) = %.0f%% of the single-frame rate\n",
           st.build.voxels / ts * 1e-6, (unsigned long long)st.build.voxels, ts, 100.0 * (st.build.voxels / ts) / (v1 / t1));
    printf("  bytes           animation %zu, largest frame %zu (%llu voxels): %.2fx; %u models, %u instances, %llu voxels "
           "stored of %llu\n",
           bytes, largest, (unsigned long long)largest_vox, (double)bytes / largest, s.model_count, s.instance_count,
           (unsigned long long)stored, (unsigned long long)st.build.voxels);
    vx_svo_scene_free(&s);
    for (auto& n : names) remove(n.c_str());
}

} // namespace

int main(int argc, char** argv) {
    int frames = 100, res = 256;
    std::string dir = "/tmp";
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--frames") && i + 1 < argc) frames = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--res") && i + 1 < argc) res = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--dir") && i + 1 < argc) dir = argv[++i];
        else if (!strcmp(argv[i], "--brick") && i + 1 < argc) g_brick = atoi(argv[++i]);
        else {
            fprintf(stderr, "usage: %s [--frames N (100)] [--res R (256)] [--dir DIR (/tmp)] [--brick D (%u)]\n", argv[0],
                    VX_CONV_VDB_SEQUENCE_BRICK_DEPTH);
            return 2;
        }
    }
    if (frames < 1 || res < 16) return 2;
    openvdb::initialize();
    char tmpl[600];
    snprintf(tmpl, sizeof tmpl, "%s/anim_benchXXXXXX", dir.c_str());
    if (!mkdtemp(tmpl)) {
        perror(tmpl);
        return 1;
    }
    run("smoke", tmpl, frames, res, 1, false);
    run("puff", tmpl, frames, res, 0, true);
    rmdir(tmpl);
    return 0;
}
