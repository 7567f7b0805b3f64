// Residual files: open, then decode every tile. Only pyramid::Error may come out.
#include <cstdint>

#include "formats/error.hpp"
#include "formats/residual_file.hpp"
#include "fuzz/fuzz_input_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    try {
        auto reader = pyramid::ResidualFileReader::open(pyramid::fuzz::inputFile(data, size));
        const pyramid::ResidualHeader& h = reader->header();
        for (int level = 0; level <= h.maxLevel; ++level) {
            const int64_t side = h.tilesPerSide(level);
            for (int ty = 0; ty < side; ++ty) {
                for (int tx = 0; tx < side; ++tx) {
                    try {
                        reader->readTile(level, tx, ty);
                    } catch (const pyramid::Error&) {
                        // A bad tile does not stop the others from being tried.
                    }
                }
            }
        }
    } catch (const pyramid::Error&) {
    }
    return 0;
}
