// Ortho files: open, then decode every tile (TIFF or DXT). Only pyramid::Error may come out.
#include <cstdint>

#include "formats/error.hpp"
#include "formats/ortho_file.hpp"
#include "fuzz/fuzz_input_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    try {
        auto reader = pyramid::OrthoFileReader::open(pyramid::fuzz::inputFile(data, size));
        const int maxLevel = reader->header().maxLevel;
        for (int level = 0; level <= maxLevel; ++level) {
            const int side = 1 << level;
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
