// Inputs for the ortho encoder tests: a smooth colour image with some texture, and the encoder's
// options with small tiles.
#pragma once
#include <cstdint>
#include <vector>

#include "libpyramid/encode/ortho/ortho_encoder.hpp"

namespace pyramid::test {

// A smooth colour image with some texture, row 0 = north: w x h pixels of `channels` samples of
// at most about `maxValue`.
std::vector<uint16_t> orthoImage(int w, int h, int channels, int maxValue);

// The encoder's defaults with 16-pixel tiles.
OrthoEncodeOptions smallOrtho();

} // namespace pyramid::test
