// Writes the NanoVDB files the tests read, with NanoVDB's own builder and
// writer (Debian's libnanovdb-dev), so that gmonrt's reader and lookups are
// checked against the library rather than against themselves:
//   box.nvdb, box-zip.nvdb, box-blosc.nvdb (no, zlib, Blosc compression):
//     "density" 1 in voxels [0, 15]^3 (0 elsewhere) and "temperature"
//     3000 everywhere (its background), voxels of 1/16 from (-0.5, -0.5,
//     -0.5): the box [-0.5, 0.5]^3;
//   lumpy.nvdb: "density" of pseudo-random values in a sparse region that
//     spans several leaves, lower and upper nodes, voxels of 0.05 from
//     (1, 2, 3); lumpy-samples.txt: world points and NanoVDB's trilinear
//     sample there (SampleFromVoxels, as pbrt-v4 looks grids up);
//   vector.nvdb: a "density" grid of 3-vectors (not floats; class unknown).
// Usage: write_nvdb DIRECTORY
#define NANOVDB_USE_ZIP
#define NANOVDB_USE_BLOSC
#include <nanovdb/util/GridBuilder.h>
#include <nanovdb/util/IO.h>
#include <nanovdb/util/SampleFromVoxels.h>

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

static float hash_value(int i, int j, int k)
{
    uint32_t h = uint32_t(i) * 73856093u ^ uint32_t(j) * 19349663u ^ uint32_t(k) * 83492791u;
    h ^= h >> 13;
    h *= 0x5bd1e995u;
    h ^= h >> 15;
    return float(h % 1000u) / 250.0f; // 0 to 4
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        std::fprintf(stderr, "usage: write_nvdb DIRECTORY\n");
        return 2;
    }
    const std::string dir = argv[1];
    using nanovdb::Coord;
    using nanovdb::Vec3d;

    // Voxels [0, 15]^3 at `value` over `background`, voxels of 1/16 from -0.5.
    auto box_grid = [](float background, float value, const char *name) {
        nanovdb::GridBuilder<float> builder(background, nanovdb::GridClass::FogVolume);
        auto acc = builder.getAccessor();
        for (int i = 0; i < 16; ++i)
            for (int j = 0; j < 16; ++j)
                for (int k = 0; k < 16; ++k)
                    acc.setValue(Coord(i, j, k), value);
        return builder.getHandle(1.0 / 16, Vec3d(-0.5), name);
    };
    std::vector<nanovdb::GridHandle<>> box;
    box.push_back(box_grid(0.0f, 1.0f, "density"));
    box.push_back(box_grid(3000.0f, 3000.0f, "temperature"));
    nanovdb::io::writeGrids(dir + "/box.nvdb", box, nanovdb::io::Codec::NONE);
    nanovdb::io::writeGrids(dir + "/box-zip.nvdb", box, nanovdb::io::Codec::ZIP);
    nanovdb::io::writeGrids(dir + "/box-blosc.nvdb", box, nanovdb::io::Codec::BLOSC);

    nanovdb::GridBuilder<float> lumpy(0.0f, nanovdb::GridClass::FogVolume);
    auto acc = lumpy.getAccessor();
    for (int i = -140; i < 40; ++i)
        for (int j = -12; j < 30; ++j)
            for (int k = -9; k < 20; ++k)
                if ((i * 7 + j * 3 + k) % 5 != 0)
                    acc.setValue(Coord(i, j, k), hash_value(i, j, k));
    auto handle = lumpy.getHandle(0.05, Vec3d(1.0, 2.0, 3.0), "density");
    const nanovdb::FloatGrid *grid = handle.grid<float>();
    std::FILE *samples = std::fopen((dir + "/lumpy-samples.txt").c_str(), "w");
    if (!samples)
        return 1;
    using Sampler = nanovdb::SampleFromVoxels<nanovdb::FloatGrid::TreeType, 1, false>;
    uint32_t state = 12345u;
    auto next = [&state]() {
        state = state * 1664525u + 1013904223u;
        return float(state >> 8) / float(1u << 24);
    };
    for (int n = 0; n < 400; ++n) {
        nanovdb::Vec3f world(1.0f + 0.05f * (-142.0f + 184.0f * next()), 2.0f + 0.05f * (-14.0f + 46.0f * next()),
                             3.0f + 0.05f * (-11.0f + 33.0f * next()));
        float value = Sampler(grid->tree())(grid->worldToIndexF(world));
        std::fprintf(samples, "%.9g %.9g %.9g %.9g\n", world[0], world[1], world[2], value);
    }
    std::fclose(samples);
    nanovdb::io::writeGrid(dir + "/lumpy.nvdb", handle, nanovdb::io::Codec::NONE);

    nanovdb::GridBuilder<nanovdb::Vec3f> vector(nanovdb::Vec3f(0.0f), nanovdb::GridClass::Unknown);
    vector.getAccessor().setValue(Coord(0, 0, 0), nanovdb::Vec3f(1.0f));
    nanovdb::io::writeGrid(dir + "/vector.nvdb", vector.getHandle(1.0, Vec3d(0.0), "density"),
                           nanovdb::io::Codec::NONE);
    return 0;
}
