// The file writers' guarantees (tests/support/pyramid_tiles.hpp): identical tiles share one byte
// range, tables of many pieces, a tile given an earlier tile's bytes, atomic output (nothing left
// without a commit or with a missing tile), missing tiles named, no tile written twice, and the
// 32-bit offset limit a clear error, never a wrap; and an output file written past the points
// where its data is made durable in the background (formats/atomic_file.hpp).
#include <gtest/gtest.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <iterator>
#include <optional>
#include <string>
#include <vector>

#include "formats/atomic_file.hpp"
#include "formats/error.hpp"
#include "formats/ortho_file.hpp"
#include "formats/residual_file.hpp"
#include "formats/tiff_tile.hpp"
#include "formats/tile_table.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/pyramid_tiles.hpp"

namespace pyramid {
namespace {

using test::orthoTiles;
using test::residualsFor;
using test::residualTiles;
using test::smoothPixels;
using test::TileId;

size_t entriesIn(const std::string& directory) {
    return static_cast<size_t>(
        std::distance(std::filesystem::directory_iterator(directory), std::filesystem::directory_iterator()));
}

TEST(WriterGuarantees, IdenticalTilesShareOneByteRange) {
    test::TempDir dir;
    OrthoHeader h;
    h.maxLevel = 2; // 21 tiles
    h.tileSize = 12;
    h.channels = 3;
    const std::string path = dir.file("shared.dat");
    const auto same = smoothPixels(h.tilePixels(), 3, {9, 9, 9});
    const auto other = smoothPixels(h.tilePixels(), 3, {0, 0, 0});
    uint64_t blobBytes = 0;
    {
        OrthoFileWriter writer(path, h);
        for (const TileId& t : orthoTiles(h, 5)) {
            writer.writeTile(t.level, t.tx, t.ty, t.level == 0 ? other : same);
        }
        EXPECT_EQ(writer.sharedTiles(), 19); // 20 identical tiles: stored once
        blobBytes = writer.bytesWritten();
        writer.commit();
    }
    const uint64_t headerAndTable = OrthoHeader::kBytes + 21u * 16u;
    EXPECT_EQ(std::filesystem::file_size(path), headerAndTable + blobBytes);
    auto reader = OrthoFileReader::open(path);
    const uint64_t sizeSame = reader->table().range(h.tileIndex(1, 0, 0)).size();
    const uint64_t sizeOther = reader->table().range(h.tileIndex(0, 0, 0)).size();
    EXPECT_EQ(blobBytes, sizeSame + sizeOther);
    EXPECT_EQ(reader->table().distinctRanges(), 2);
    const TileTable::Range first = reader->table().range(h.tileIndex(1, 0, 0));
    for (int64_t i = 1; i < h.tileCount(); ++i) {
        EXPECT_EQ(reader->table().range(i).begin, first.begin);
        EXPECT_EQ(reader->table().range(i).end, first.end);
    }
    EXPECT_EQ(reader->readTile(2, 3, 3), same);
    EXPECT_EQ(reader->readTile(0, 0, 0), other);
}

// The offset table is written in pieces of 65536 entries: every entry of a table of several
// pieces, the last one partial, is the range of its own tile's bytes.
TEST(WriterGuarantees, ATableOfManyPiecesHoldsEveryTilesRange) {
    test::TempDir dir;
    OrthoHeader h;
    h.maxLevel = 8; // 87381 tiles: one piece of the table and part of a second
    h.tileSize = 4;
    h.channels = 1;
    const std::string path = dir.file("many.dat");
    {
        OrthoFileWriter writer(path, h);
        for (int level = h.maxLevel; level >= 0; --level) { // every tile's bytes its own index, finest first
            for (int ty = 0; ty < (1 << level); ++ty) {
                for (int tx = 0; tx < (1 << level); ++tx) {
                    const auto i = static_cast<uint64_t>(h.tileIndex(level, tx, ty));
                    std::vector<uint8_t> blob(8);
                    for (int b = 0; b < 8; ++b) {
                        blob[static_cast<size_t>(b)] = static_cast<uint8_t>(i >> (8 * b));
                    }
                    writer.writeTileBytes(level, tx, ty, blob);
                }
            }
        }
        writer.commit();
    }
    const auto reader = OrthoFileReader::open(path);
    ASSERT_EQ(reader->table().tileCount(), 87381);
    for (int64_t i = 0; i < reader->table().tileCount(); ++i) {
        const std::vector<uint8_t> blob = reader->table().read(i);
        ASSERT_EQ(blob.size(), 8u) << "tile " << i;
        uint64_t value = 0;
        for (int b = 0; b < 8; ++b) {
            value |= static_cast<uint64_t>(blob[static_cast<size_t>(b)]) << (8 * b);
        }
        ASSERT_EQ(value, static_cast<uint64_t>(i)) << "tile " << i;
    }
}

// A tile given an earlier tile's bytes (writeTileSameAs) shares its range, as writing the same
// bytes does: the file is byte for byte the one written with the bytes every time. A tile not
// yet written cannot lend its bytes, and a tile is still written once.
TEST(WriterGuarantees, ATileGivenAnEarlierTilesBytesIsTheFileOfItsBytes) {
    test::TempDir dir;
    OrthoHeader h;
    h.maxLevel = 2; // 21 tiles
    h.tileSize = 8;
    h.channels = 3;
    const auto same = smoothPixels(h.tilePixels(), 3, {9, 9, 9});
    const auto blob = encodeTiff8(same, h.tilePixels(), h.tilePixels(), 3, TiffCompression::Deflate);
    for (const bool byReference : {false, true}) {
        OrthoFileWriter writer(dir.file(byReference ? "reference.dat" : "bytes.dat"), h);
        std::optional<std::array<int, 3>> first;
        for (const TileId& t : orthoTiles(h, 5)) {
            if (t.level == 1) {
                writer.writeTile(t.level, t.tx, t.ty, smoothPixels(h.tilePixels(), 3, t)); // tiles of their own
            } else if (byReference && first) {
                writer.writeTileSameAs(t.level, t.tx, t.ty, *first);
            } else {
                writer.writeTileBytes(t.level, t.tx, t.ty, blob);
                first = std::array<int, 3>{t.level, t.tx, t.ty};
            }
        }
        EXPECT_EQ(writer.sharedTiles(), 16); // 17 alike, stored once
        if (byReference) {
            EXPECT_THROW(writer.writeTileSameAs(2, 0, 0, *first), Error); // written twice
        }
        writer.commit();
    }
    EXPECT_EQ(test::readFile(dir.file("reference.dat")), test::readFile(dir.file("bytes.dat")));
    OrthoFileWriter writer(dir.file("unwritten.dat"), h);
    writer.writeTileBytes(0, 0, 0, blob);
    try {
        writer.writeTileSameAs(1, 0, 0, {2, 1, 1});
        ADD_FAILURE() << "a tile took the bytes of one not written";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("unwritten.dat"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("not written"), std::string::npos) << e.what();
    }
    EXPECT_THROW(writer.writeTileSameAs(1, 0, 0, {3, 0, 0}), Error); // no such tile
}

TEST(WriterGuarantees, ResidualTilesShareToo) {
    test::TempDir dir;
    ResidualHeader h;
    h.maxLevel = 1;
    h.tileSize = 4;
    const std::string path = dir.file("flat.dat");
    const std::vector<int16_t> flat(9 * 9, 0);
    {
        ResidualFileWriter writer(path, h);
        for (const TileId& t : residualTiles(h, 6)) {
            writer.writeTile(t.level, t.tx, t.ty, flat);
        }
        EXPECT_EQ(writer.sharedTiles(), 4);
        writer.commit();
    }
    auto reader = ResidualFileReader::open(path);
    EXPECT_EQ(reader->table().distinctRanges(), 1);
    EXPECT_EQ(std::filesystem::file_size(path), ResidualHeader::kBytes + 5u * 8u + reader->table().range(0).size());
    EXPECT_EQ(reader->readTile(1, 1, 0), flat);
}

TEST(WriterGuarantees, DestroyedWithoutCommitLeavesNothing) {
    test::TempDir dir;
    OrthoHeader h;
    h.maxLevel = 1;
    h.tileSize = 4;
    h.channels = 1;
    {
        OrthoFileWriter writer(dir.file("never.dat"), h);
        writer.writeTile(0, 0, 0, smoothPixels(h.tilePixels(), 1, {0, 0, 0}));
        EXPECT_EQ(entriesIn(dir.path()), 1u); // the temporary, not the destination
        EXPECT_FALSE(test::fileExists(dir.file("never.dat")));
    }
    EXPECT_EQ(entriesIn(dir.path()), 0u);
}

// Bytes that differ from piece to piece and within each, so that a piece written at the wrong
// offset, twice or not at all shows.
std::vector<uint8_t> piece(size_t index, size_t size) {
    std::vector<uint8_t> bytes(size);
    for (size_t i = 0; i < size; ++i) {
        bytes[i] = static_cast<uint8_t>((index * 131 + i * 7 + (i >> 9)) & 0xff);
    }
    return bytes;
}

// 9 MB in 96 KB pieces passes the background fdatasync's step (2 MB) four times, some while the
// one before still runs; half the pieces are written back to front, at their offsets.
TEST(WriterGuarantees, AFileWrittenPastItsBackgroundSyncsHoldsEveryByte) {
    test::TempDir dir;
    constexpr size_t kPiece = 96 << 10, kPieces = 96;
    std::vector<uint8_t> expected(kPiece * kPieces);
    {
        AtomicFile file(dir.file("out.bin"));
        for (size_t k = 0; k < kPieces; ++k) {
            const size_t index = k < kPieces / 2 ? k : kPieces - 1 - (k - kPieces / 2);
            const std::vector<uint8_t> bytes = piece(index, kPiece);
            std::copy(bytes.begin(), bytes.end(), expected.begin() + static_cast<std::ptrdiff_t>(index * kPiece));
            file.writeAt(index * kPiece, bytes.data(), bytes.size());
        }
        EXPECT_FALSE(test::fileExists(dir.file("out.bin")));
        file.commit();
    }
    EXPECT_EQ(test::bytesOf(dir.file("out.bin")), expected);
    EXPECT_EQ(entriesIn(dir.path()), 1u); // no temporary left
}

// Destroyed without a commit right after a background fdatasync started: it is waited for (the
// descriptor stays open until it ends), and the temporary is removed.
TEST(WriterGuarantees, AFileDroppedWhileItsDataIsSyncedLeavesNothing) {
    test::TempDir dir;
    for (int round = 0; round < 4; ++round) {
        AtomicFile file(dir.file("dropped.bin"));
        const std::vector<uint8_t> bytes = piece(static_cast<size_t>(round), size_t{3} << 20);
        file.writeAt(0, bytes.data(), bytes.size());
        EXPECT_EQ(entriesIn(dir.path()), 1u);
    }
    EXPECT_EQ(entriesIn(dir.path()), 0u);
}

TEST(WriterGuarantees, CommitWithAMissingTileThrowsAndLeavesNothing) {
    test::TempDir dir;
    ResidualHeader h;
    h.maxLevel = 1;
    h.tileSize = 4;
    const std::string path = dir.file("holes.dat");
    {
        ResidualFileWriter writer(path, h);
        for (const TileId& t : residualTiles(h, 7)) {
            if (!(t.level == 1 && t.tx == 0 && t.ty == 1)) {
                writer.writeTile(t.level, t.tx, t.ty, residualsFor(h, t));
            }
        }
        try {
            writer.commit();
            ADD_FAILURE() << "commit() accepted a missing tile";
        } catch (const Error& e) {
            EXPECT_EQ(std::string(e.what()), path + ": tile (1,0,1) was never written");
        }
        EXPECT_FALSE(test::fileExists(path));
    }
    EXPECT_EQ(entriesIn(dir.path()), 0u);
}

TEST(WriterGuarantees, MissingTilesAreNamedByEveryWriter) {
    test::TempDir dir;
    OrthoHeader h;
    h.maxLevel = 1;
    h.tileSize = 4;
    h.channels = 1;
    {
        OrthoFileWriter writer(dir.file("ortho.dat"), h);
        writer.writeTile(0, 0, 0, smoothPixels(h.tilePixels(), 1, {0, 0, 0}));
        writer.writeTile(1, 0, 0, smoothPixels(h.tilePixels(), 1, {1, 0, 0}));
        try {
            writer.commit();
            ADD_FAILURE() << "commit() accepted missing tiles";
        } catch (const Error& e) {
            EXPECT_EQ(std::string(e.what()), dir.file("ortho.dat") + ": tile (1,1,0) was never written");
        }
    }
    {
        TileTableWriter writer(dir.file("table.dat"), std::vector<uint8_t>(4, 0), 3, 8, 1000);
        writer.write(0, std::vector<uint8_t>(5, 1));
        writer.write(2, std::vector<uint8_t>(5, 1));
        try {
            writer.commit();
            ADD_FAILURE() << "commit() accepted a missing tile";
        } catch (const Error& e) {
            EXPECT_EQ(std::string(e.what()), dir.file("table.dat") + ": tile 1 was never written");
        }
    }
    EXPECT_EQ(entriesIn(dir.path()), 0u);
}

TEST(WriterGuarantees, SameTileTwiceIsAnError) {
    test::TempDir dir;
    ResidualHeader h;
    h.maxLevel = 0;
    h.tileSize = 4;
    ResidualFileWriter writer(dir.file("twice.dat"), h);
    writer.writeTile(0, 0, 0, residualsFor(h, {0, 0, 0}));
    try {
        writer.writeTile(0, 0, 0, residualsFor(h, {0, 0, 0}));
        ADD_FAILURE() << "a tile was written twice";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("tile 0 written twice"), std::string::npos) << e.what();
    }
    EXPECT_THROW(writer.writeTile(1, 0, 0, residualsFor(h, {0, 0, 0})), Error); // no such tile
}

TEST(WriterGuarantees, OffsetLimitIsAClearErrorNeverAWrap) {
    test::TempDir dir;
    const std::string path = dir.file("limit.dat");
    const std::vector<uint8_t> header(4, 0);
    const std::vector<uint8_t> a(60, 1), b(60, 2), c(40, 3);
    {
        TileTableWriter writer(path, header, 4, 4, 100);
        writer.write(0, a);
        writer.write(1, a); // shared: no new bytes
        try {
            writer.write(2, b); // would end at 120 > 100
            ADD_FAILURE() << "offset limit passed";
        } catch (const Error& e) {
            const std::string what = e.what();
            EXPECT_EQ(what.rfind(path + ": ", 0), 0u) << what;
            EXPECT_NE(what.find("100"), std::string::npos) << what;
        }
        EXPECT_FALSE(writer.written(2));
        writer.write(2, c); // exactly at the limit: fine
        writer.write(3, a);
        EXPECT_EQ(writer.bytesWritten(), 100u);
        writer.commit();
    }
    auto table = TileTable::open(path, header.size(), 4, 4);
    EXPECT_EQ(table->range(2).begin, 60u);
    EXPECT_EQ(table->range(2).end, 100u);
    EXPECT_EQ(table->read(3), a);
}

} // namespace
} // namespace pyramid
