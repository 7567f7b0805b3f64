#include "tests/support/dxt_blocks.hpp"

#include <stb/stb_dxt.h>

#include "formats/dxt_colour_fit.hpp"

namespace pyramid::test {

void referenceDxtBlock(const uint8_t* block, bool dxt5, int quality, uint8_t* out) {
    if (dxt5) {
        uint8_t alpha[16];
        for (int k = 0; k < 16; ++k) {
            alpha[k] = block[4 * k + 3];
        }
        stb_compress_bc4_block(out, alpha);
    }
    const uint8_t* in[1] = {block};
    uint8_t* colour[1] = {out + (dxt5 ? 8 : 0)};
    encodeDxtColourBlocks(in, colour, 1, quality + 1);
}

} // namespace pyramid::test
