// The bytes the DXT encoder must give one gathered RGBA block at quality 0 or 1, built from
// direct calls of the encoders it stands on: stb_dxt's BC4 alpha block (DXT5) followed by the
// colour fit's block, alone in its lanes.
#pragma once
#include <cstdint>

namespace pyramid::test {

// `block`: 16 RGBA pixels; writes 8 (DXT1) or 16 (DXT5) bytes to `out`.
void referenceDxtBlock(const uint8_t* block, bool dxt5, int quality, uint8_t* out);

} // namespace pyramid::test
