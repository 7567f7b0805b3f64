// TIFF and context-coded tiles through every decoder, with small size limits so that each run
// stays fast.
#include <cstdint>
#include <span>

#include "formats/error.hpp"
#include "formats/residual_codec.hpp"
#include "formats/residual_context.hpp"
#include "formats/tiff_tile.hpp"

namespace {
template <class Decode>
void attempt(Decode decode) {
    try {
        decode();
    } catch (const pyramid::Error&) {
    }
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::span<const uint8_t> blob(data, size);
    pyramid::describeTiff(blob);
    attempt([&] { pyramid::decodeTiff(blob, 64, 64, "fuzz"); });
    attempt([&] { pyramid::decodeResidualTiff(blob, 13, "fuzz"); });
    pyramid::describeResidualBlob(blob);
    attempt([&] { pyramid::decodeResidualBlob(blob, 13, "fuzz"); });
    attempt([&] { pyramid::decodeContextResiduals(blob, 3, "fuzz"); });
    for (int channels = 1; channels <= 4; ++channels) {
        attempt([&] { pyramid::decodeOrthoTiff(blob, 16, channels, "fuzz"); });
    }
    return 0;
}
