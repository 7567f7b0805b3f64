// JPEG files decoded without the image I/O module, with the same samples as OpenImageIO's: by
// libjpeg on a thread of their own (grey, YCbCr subsampled or not, RGB, progressive; beyond the
// cache through the scratch file). Damaged JPEG data is refused with one line naming the file;
// JPEGs of other colour spaces are left to OpenImageIO. The rows decoded into memory are given
// back in blocks once their reader says it is past them.
#include <gtest/gtest.h>

// jpeglib.h needs FILE and size_t declared first.
#include <cstddef>
#include <cstdio>
#include <jpeglib.h>

#include <cstdint>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "formats/error.hpp"
#include "libpyramid/input/decoded_rows.hpp"
#include "libpyramid/input/jpeg_raster_reader.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "tests/support/oiio_reference.hpp"
#include "tests/support/paths.hpp"

namespace pyramid {
namespace {

using test::expectSameAsOpenImageIO;

// A JPEG file written with libjpeg: `components` 1 (grey), 3 (YCbCr, or RGB stored as RGB) or 4
// (CMYK); chroma subsampled 2 x 2 or not; baseline or progressive.
struct JpegFile {
    std::string name;
    int components;
    J_COLOR_SPACE stored; // JCS_GRAYSCALE, JCS_YCbCr, JCS_RGB or JCS_CMYK
    bool subsampled, progressive;
    int w = 61, h = 37, cacheMegabytes = 256;
};

void writeJpegFile(const std::string& path, const JpegFile& j) {
    FILE* file = std::fopen(path.c_str(), "wb");
    ASSERT_TRUE(file);
    jpeg_compress_struct c{};
    jpeg_error_mgr errors{};
    c.err = jpeg_std_error(&errors);
    jpeg_create_compress(&c);
    jpeg_stdio_dest(&c, file);
    c.image_width = static_cast<JDIMENSION>(j.w);
    c.image_height = static_cast<JDIMENSION>(j.h);
    c.input_components = j.components;
    c.in_color_space = j.components == 1 ? JCS_GRAYSCALE : j.components == 4 ? JCS_CMYK : JCS_RGB;
    jpeg_set_defaults(&c);
    jpeg_set_colorspace(&c, j.stored);
    jpeg_set_quality(&c, 85, TRUE);
    for (int k = 0; k < c.num_components; ++k) {
        c.comp_info[k].h_samp_factor = c.comp_info[k].v_samp_factor = k == 0 && j.subsampled ? 2 : 1;
    }
    if (j.progressive) {
        jpeg_simple_progression(&c);
    }
    jpeg_start_compress(&c, TRUE);
    std::vector<uint8_t> row(static_cast<size_t>(j.w * j.components));
    for (int y = 0; y < j.h; ++y) {
        for (int x = 0; x < j.w; ++x) {
            for (int ch = 0; ch < j.components; ++ch) {
                // Smooth colours with some detail, as photographs have.
                row[static_cast<size_t>(x * j.components + ch)] =
                    static_cast<uint8_t>((x * (3 + ch) + y * (5 - ch) + ((x * y + 7 * ch) % 23) * 3) & 255);
            }
        }
        JSAMPROW rows[1] = {row.data()};
        jpeg_write_scanlines(&c, rows, 1);
    }
    jpeg_finish_compress(&c);
    jpeg_destroy_compress(&c);
    std::fclose(file);
}

TEST(RasterReaders, JpegFilesAreDecodedAsOpenImageIODecodesThem) {
    test::TempDir dir;
    const std::vector<JpegFile> files = {
        {"grey.jpg", 1, JCS_GRAYSCALE, false, false},
        {"ycbcr-420.jpg", 3, JCS_YCbCr, true, false},
        {"ycbcr-444.jpg", 3, JCS_YCbCr, false, false},
        {"rgb.jpg", 3, JCS_RGB, false, false},
        {"progressive.jpg", 3, JCS_YCbCr, true, true},
        // Beyond the cache: decoded into the scratch file, read back by window.
        {"ycbcr-420-large.jpg", 3, JCS_YCbCr, true, false, 700, 530, 1},
    };
    for (const JpegFile& j : files) {
        SCOPED_TRACE(j.name);
        const std::string path = dir.file(j.name);
        writeJpegFile(path, j);
        EXPECT_NE(openJpegRaster(path, j.cacheMegabytes), nullptr);
        expectSameAsOpenImageIO(path, j.cacheMegabytes);
    }
    // CMYK is left to OpenImageIO, which converts it.
    const JpegFile cmyk{"cmyk.jpg", 4, JCS_CMYK, false, false};
    writeJpegFile(dir.file(cmyk.name), cmyk);
    EXPECT_EQ(openJpegRaster(dir.file(cmyk.name), 256), nullptr);
    EXPECT_EQ(RasterSource::describe(dir.file(cmyk.name)).channels, 3);
}

// A truncated JPEG and one whose entropy-coded data is damaged fail the reads of their rows
// with one line naming the file (libjpeg decodes on past both, with a warning); a progressive
// JPEG larger than the cache is described but refused when opened, naming the cache it needs.
TEST(RasterReaders, DamagedJpegFilesAreRefused) {
    test::TempDir dir;
    const JpegFile j{"photo.jpg", 3, JCS_YCbCr, true, false, 400, 300};
    const std::string path = dir.file(j.name);
    writeJpegFile(path, j);
    const std::string bytes = test::readFile(path);
    const std::string truncated = dir.file("truncated.jpg"), corrupt = dir.file("corrupt.jpg");
    std::ofstream(truncated, std::ios::binary) << bytes.substr(0, bytes.size() * 2 / 3);
    std::string damaged = bytes;
    for (size_t k = bytes.size() / 2; k < bytes.size() / 2 + 40; ++k) {
        damaged[k] = static_cast<char>(0xFF); // markers where data belongs
    }
    std::ofstream(corrupt, std::ios::binary) << damaged;
    for (const auto& [file, why] : {std::pair{truncated, "Premature end of JPEG file"},
                                    std::pair{corrupt, "Corrupt JPEG data"}}) {
        const auto source = RasterSource::open(file, 256);
        std::vector<uint8_t> pixels(static_cast<size_t>(j.w * j.h * 3));
        try {
            source->readUInt8(0, 0, j.w, j.h, 0, 3, pixels.data(), j.w * 3);
            ADD_FAILURE() << file << " was read";
        } catch (const Error& e) {
            const std::string expected = file + ": cannot read: damaged or truncated JPEG (" + why;
            EXPECT_EQ(std::string(e.what()).rfind(expected, 0), 0u) << e.what();
        }
    }
    const JpegFile progressive{"progressive-large.jpg", 3, JCS_YCbCr, true, true, 700, 530};
    writeJpegFile(dir.file(progressive.name), progressive);
    // Described from its header, whatever the budget (mosaics describe their inputs first).
    const RasterInfo described = RasterSource::describe(dir.file(progressive.name));
    EXPECT_EQ(described.width, 700);
    EXPECT_EQ(described.height, 530);
    EXPECT_EQ(described.channels, 3);
    try {
        openJpegRaster(dir.file(progressive.name), 1);
        ADD_FAILURE() << "a progressive JPEG beyond the cache was opened";
    } catch (const OptionError& e) {
        EXPECT_EQ(e.option(), "cacheMegabytes");
        EXPECT_NE(e.problem().find("progressive-large.jpg: a progressive JPEG is held whole while it is decoded, 3 MB, "
                                   "more than a cache of 1 MB"),
                  std::string::npos)
            << e.problem();
    }
}

// Rows of 3,000 bytes, each sample (y * 7 + x) mod 256.
class CountingRows final : public DecodedRows::Decoder {
public:
    void readRow(uint8_t* row) override {
        for (int x = 0; x < 3000; ++x) {
            row[x] = static_cast<uint8_t>((y_ * 7 + x) & 0xff);
        }
        ++y_;
    }
    void finish() override {}

private:
    int y_ = 0;
};

// 2,000 rows of 3,000 bytes come in blocks of 699 rows (the most within 2 MB, so that each block
// takes one huge page): rows above 1,000 give back the first block only; a read of its rows is
// then an error, the others still read.
TEST(RasterReaders, DecodedRowsGiveBackTheBlocksAboveARow) {
    RasterInfo info;
    info.width = 1000;
    info.height = 2000;
    info.channels = 3;
    info.type = SampleType::UInt8;
    DecodedRows rows("counting", info, 256, 0);
    rows.start(std::make_unique<CountingRows>());
    std::vector<uint8_t> last(3);
    ASSERT_TRUE(rows.readUInt8(0, 1999, 1, 2000, 0, 3, last.data(), 3)); // waits for every row
    EXPECT_EQ(last[0], (1999 * 7) & 0xff);
    EXPECT_EQ(rows.bytesHeld(), size_t{6000000});
    rows.releaseRowsAbove(1000);
    EXPECT_EQ(rows.bytesHeld(), size_t{6000000 - 699 * 3000});
    std::vector<uint8_t> row(3);
    ASSERT_TRUE(rows.readUInt8(2, 699, 3, 700, 0, 3, row.data(), 3));
    EXPECT_EQ(row[0], (699 * 7 + 6) & 0xff);
    EXPECT_THROW(rows.readUInt8(2, 698, 3, 699, 0, 3, row.data(), 3), std::logic_error);
    rows.releaseRowsAbove(2000);
    EXPECT_EQ(rows.bytesHeld(), size_t{0});
}

} // namespace
} // namespace pyramid
