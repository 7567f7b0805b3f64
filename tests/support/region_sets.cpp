#include "tests/support/region_sets.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>

#include "libpyramid/encode/dem/dem_encoder.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid::test {

void copyResidual(const ResidualFileReader& single, const std::string& path, const ResidualHeader& h) {
    ResidualFileWriter w(path, h);
    for (int l = 0; l <= h.maxLevel; ++l) {
        const int64_t side = h.tilesPerSide(l);
        for (int64_t y = 0; y < side; ++y) {
            for (int64_t x = 0; x < side; ++x) {
                const int ax = static_cast<int>((int64_t{h.rootTx} << l) + x);
                const int ay = static_cast<int>((int64_t{h.rootTy} << l) + y);
                w.writeTileBytes(l, static_cast<int>(x), static_cast<int>(y),
                                 single.readTileBytes(h.rootLevel + l, ax, ay));
            }
        }
    }
    w.commit();
}

ResidualHeader regionHeader(const ResidualHeader& single, RegionRoot root, int maxLevel) {
    ResidualHeader h = single;
    h.minLevel = 0;
    h.maxLevel = maxLevel;
    h.rootLevel = root.level;
    h.rootTx = root.tx;
    h.rootTy = root.ty;
    return h;
}

SplitDem::SplitDem() {
    std::filesystem::create_directories(dir.file("single"));
    std::filesystem::create_directories(setDir);
    writeFloatRaster(input, 257, 257, syntheticHeights(257, 257));
    DemEncodeOptions o;
    o.tileSize = 8;
    o.rootTileSize = 4;
    o.scale = 0.25;
    header = encodeDem(input, single, o).header;
    const auto reader = ResidualFileReader::open(single);
    ResidualHeader m = header;
    m.maxLevel = 2;
    copyResidual(*reader, main, m);
    for (int ty = 0; ty < 4; ++ty) {
        for (int tx = 0; tx < 4; ++tx) {
            const RegionRoot r{3, tx, ty};
            copyResidual(*reader, regionFilePath(main, r), regionHeader(header, r, header.maxLevel - 3));
            roots.push_back(r);
        }
    }
    const RegionRoot n{5, 5, 9};
    copyResidual(*reader, nested, regionHeader(header, n, 1));
    roots.push_back(n);
    writeRegionIndex(index, makeRegionIndex(main, PyramidKind::Residual, roots));
}

void expectProblem(const std::vector<std::string>& problems, const std::string& file, const std::string& words) {
    ASSERT_FALSE(problems.empty()) << "no problem: expected " << words;
    bool found = false;
    for (const std::string& p : problems) {
        found = found || (p.rfind(file + ": ", 0) == 0 && p.find(words) != std::string::npos);
    }
    EXPECT_TRUE(found) << "expected '" << file << ": ..." << words << "', got: " << problems.front();
}

} // namespace pyramid::test
