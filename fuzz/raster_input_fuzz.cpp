// Hostile bytes through the input readers (libpyramid/input/): the dispatcher opens the input
// as TIFF (strips, tiles, huge strips, BigTIFF, every predictor, an internal mask), PNG or ESRI
// ASCII grid, with a small cache so that the block cache's recycling, the strip stream and the
// scratch files are exercised, then reads a few windows of every channel from two threads.
// Images declaring more than 2^22 samples are only described (reading them whole would be the
// fuzzer's time, not a finding).
#include <algorithm>
#include <cstdint>
#include <thread>
#include <vector>

#include "formats/error.hpp"
#include "fuzz/fuzz_input_file.hpp"
#include "libpyramid/input/raster_source.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    try {
        const auto source = pyramid::RasterSource::open(pyramid::fuzz::inputFile(data, size), 1);
        const pyramid::RasterInfo& info = source->info();
        if (static_cast<int64_t>(info.width) * info.height > (int64_t{1} << 22) || info.channels > 4) {
            return 0;
        }
        const auto reads = [&](int part) {
            try {
                const int w = info.width, h = info.height;
                const int x0 = part * w / 3, y0 = (2 - part) * h / 3;
                const int x1 = std::max(x0 + 1, std::min(w, x0 + 40)), y1 = std::max(y0 + 1, std::min(h, y0 + 40));
                std::vector<float> f(static_cast<size_t>(x1 - x0) * static_cast<size_t>(y1 - y0));
                for (int c = 0; c < info.channels; ++c) {
                    source->readFloat(x0, y0, x1, y1, c, f.data());
                }
                // Every channel, and a TIFF's internal mask after them.
                const int stored = info.channels + (info.mask ? 1 : 0);
                std::vector<uint16_t> u(f.size() * static_cast<size_t>(stored));
                source->readUInt16(x0, y0, x1, y1, 0, stored, u.data());
            } catch (const pyramid::Error&) {
            }
        };
        std::thread other(reads, 2);
        reads(0);
        other.join();
    } catch (const pyramid::Error&) {
    }
    return 0;
}
