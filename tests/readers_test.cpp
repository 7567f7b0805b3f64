// The readers' costs and coordinates: opening a pyramid file (with the readers or pyramid_open)
// reads its offset table once, into one allocation of the table's size; a region file's place
// is found at levels where its root's coordinates pass 2^31.
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <new>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "formats/ortho_file.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/capi/pyramid.h"
#include "libpyramid/runtime/region_lookup.hpp"
#include "tests/support/paths.hpp"

// Every allocation of at least `gLargeBytes` bytes is counted, with its size: the offset tables
// of the files below are the only blocks that large. The replacement operators allocate with
// malloc and free, which GCC takes for a mismatch where it inlines them.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
namespace {
std::atomic<size_t> gLargeBytes{SIZE_MAX};
std::atomic<int64_t> gLargeCount{0};
std::atomic<uint64_t> gLargeTotal{0};
} // namespace

void* operator new(std::size_t n) {
    if (n >= gLargeBytes.load(std::memory_order_relaxed)) {
        gLargeCount.fetch_add(1);
        gLargeTotal.fetch_add(n);
    }
    if (void* p = std::malloc(n == 0 ? 1 : n)) {
        return p;
    }
    throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace pyramid {
namespace {

void storeI32(std::string& bytes, size_t at, uint32_t v) {
    for (int k = 0; k < 4; ++k) {
        bytes[at + static_cast<size_t>(k)] = static_cast<char>(v >> (8 * k));
    }
}

// A file of `header` and a table of `tableBytes` zero bytes (every tile empty: valid, missing).
void writeFile(const std::string& path, const std::string& header, uint64_t tableBytes) {
    std::FILE* f = std::fopen(path.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    std::fwrite(header.data(), 1, header.size(), f);
    const std::vector<char> zeros(1 << 20, 0);
    for (uint64_t left = tableBytes; left > 0;) {
        const size_t n = static_cast<size_t>(std::min<uint64_t>(left, zeros.size()));
        std::fwrite(zeros.data(), 1, n, f);
        left -= n;
    }
    std::fclose(f);
}

// Residual: levels 0..10 of 4-interval tiles, 1,398,101 tiles, 8 bytes of table each.
uint64_t writeResidual(const std::string& path) {
    ResidualHeader h;
    h.maxLevel = 10;
    h.tileSize = 4;
    std::string header(ResidualHeader::kBytes, '\0');
    storeI32(header, 4, 10);
    storeI32(header, 8, 4);
    const float one = 1.0f;
    uint32_t bits = 0;
    std::memcpy(&bits, &one, 4);
    storeI32(header, 24, bits);
    const uint64_t tableBytes = static_cast<uint64_t>(h.tileCount()) * 8u;
    writeFile(path, header, tableBytes);
    return tableBytes;
}

// Ortho: levels 0..10 of 4-pixel RGB tiles, 16 bytes of table each.
uint64_t writeOrtho(const std::string& path) {
    OrthoHeader h;
    h.maxLevel = 10;
    std::string header(OrthoHeader::kBytes, '\0');
    storeI32(header, 0, 10);
    storeI32(header, 4, 4);
    storeI32(header, 8, 3);
    const uint64_t tableBytes = static_cast<uint64_t>(h.tileCount()) * 16u;
    writeFile(path, header, tableBytes);
    return tableBytes;
}

struct LargeAllocations {
    int64_t count = 0;
    uint64_t bytes = 0;
};

// The allocations of at least half of `tableBytes` that `open` makes.
template <class Open>
LargeAllocations largeAllocationsOf(uint64_t tableBytes, Open open) {
    gLargeCount = 0;
    gLargeTotal = 0;
    gLargeBytes = static_cast<size_t>(tableBytes / 2);
    open();
    gLargeBytes = SIZE_MAX;
    return {gLargeCount.load(), gLargeTotal.load()};
}

TEST(Readers, TheOffsetTableIsOneAllocationOfItsSize) {
    test::TempDir dir;
    const uint64_t residualTable = writeResidual(dir.file("DEM.dat"));
    ASSERT_EQ(residualTable, 1398101u * 8u);
    const LargeAllocations residual = largeAllocationsOf(residualTable, [&] {
        const auto reader = ResidualFileReader::open(dir.file("DEM.dat"));
        EXPECT_EQ(reader->table().tileCount(), 1398101);
        EXPECT_EQ(reader->table().range(1398100).size(), 0u);
    });
    EXPECT_EQ(residual.count, 1);
    EXPECT_EQ(residual.bytes, residualTable);

    const uint64_t orthoTable = writeOrtho(dir.file("RGB.dat"));
    const LargeAllocations ortho = largeAllocationsOf(orthoTable, [&] { OrthoFileReader::open(dir.file("RGB.dat")); });
    EXPECT_EQ(ortho.count, 1);
    EXPECT_EQ(ortho.bytes, orthoTable);
}

TEST(Readers, PyramidOpenReadsTheTableOnce) {
    test::TempDir dir;
    const uint64_t residualTable = writeResidual(dir.file("DEM.dat"));
    const uint64_t orthoTable = writeOrtho(dir.file("RGB.dat"));
    for (const auto& [name, tableBytes] : {std::pair{"DEM.dat", residualTable}, std::pair{"RGB.dat", orthoTable}}) {
        const std::string path = dir.file(name);
        pyramid_file* file = nullptr;
        const LargeAllocations opened = largeAllocationsOf(tableBytes, [&] {
            ASSERT_EQ(pyramid_open(path.c_str(), &file), PYRAMID_OK) << pyramid_last_error();
        });
        EXPECT_EQ(opened.count, 1) << name;
        EXPECT_EQ(opened.bytes, tableBytes) << name;
        pyramid_info info;
        ASSERT_EQ(pyramid_get_info(file, &info), PYRAMID_OK);
        EXPECT_EQ(info.max_level, 10);
        EXPECT_EQ(info.tile_count, 1398101);
        pyramid_close(file);
    }
}

// A stand-in for a file reader: the header fields deepestHolder reads.
struct FakeHeader {
    int rootLevel = 0, rootTx = 0, rootTy = 0, maxLevel = 0;
    bool contains(int level, int tx, int ty) const {
        return level >= 0 && level <= maxLevel && tx >= 0 && ty >= 0 && tx < (int64_t{1} << level) &&
               ty < (int64_t{1} << level);
    }
};
struct FakeReader {
    FakeHeader h;
    const FakeHeader& header() const { return h; }
};

TEST(RegionLookup, DeepLevelsDoNotWrapAround) {
    std::vector<std::unique_ptr<FakeReader>> readers;
    readers.push_back(std::make_unique<FakeReader>(FakeReader{{0, 0, 0, 30}}));
    // A region rooted at level 20, at (2^19, 2^19), 20 levels deep.
    readers.push_back(std::make_unique<FakeReader>(FakeReader{{20, 1 << 19, 1 << 19, 20}}));
    RelativeTile rel;
    // Level 30: the region's root lies at (2^29, 2^29), inside int.
    ASSERT_EQ(deepestHolder(readers, 30, (1 << 29) + 5, (1 << 29) + 7, rel), 1);
    EXPECT_EQ(rel.level, 10);
    EXPECT_EQ(rel.tx, 5);
    EXPECT_EQ(rel.ty, 7);
    EXPECT_EQ(deepestHolder(readers, 30, 5, 7, rel), 0);
    EXPECT_EQ(rel.level, 30);
    // Levels 39 and 40: the root lies at 2^38 or 2^39 on both axes, whose low 32 bits are 0;
    // tile (5, 7) is far west and south of it, and belongs to no file (the main file stops at
    // level 30).
    EXPECT_EQ(deepestHolder(readers, 40, 5, 7, rel), -1);
    EXPECT_EQ(deepestHolder(readers, 39, 5, 7, rel), -1);
}

} // namespace
} // namespace pyramid
