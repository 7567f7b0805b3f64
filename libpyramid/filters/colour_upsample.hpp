// The colour-residual upsample of doc/format.md ("Ortho residual arithmetic"): integer
// arithmetic only, shared by the ortho encoder, the CPU ortho residual producer and GLSL.
//
// Tiles are (T+4) x (T+4) pixels of `channels` bytes, row-major, row 0 = bottom, 2-pixel
// borders. Child pixel (x, y) of quadrant (tx%2, ty%2) is predicted from parent pixels
// (bx, by) = ((x+1)/2 + rx, (y+1)/2 + ry) and (bx+1, by+1), rx = (tx%2) * T/2, with weights
// 9, 3, 3, 1 out of 16 (the nearest parent pixel gets 9): along x, an even x weighs
// (bx: 1, bx+1: 3) and an odd x (bx: 3, bx+1: 1); the same along y, tensor product.
// prediction = (sum of weight * pixel) >> 4 (truncated; the sum is non-negative).
#pragma once
#include <cstddef>
#include <cstdint>

namespace pyramid {

// The prediction of one channel of child pixel (x, y).
uint8_t predictColour(const uint8_t* parent, size_t parentRowBytes, int channels, int channel, int rx,
                     int ry, int x, int y);

// The predictions of a whole child row y (side = T + 4 pixels, every channel): out[x * channels
// + c] = predictColour(parent, ..., c, rx, ry, x, y), the same integers summed in another order
// (the rows blended first: wx0 (wy0 a + wy1 c) + wx1 (wy0 b + wy1 d)), which vectorises.
void predictColourRow(const uint8_t* parent, size_t parentRowBytes, int channels, int rx, int ry, int y, int side,
                     uint8_t* out);

// The residual rule before any clamp, one owner for both directions: a value is stored as
// (value - prediction) / 2 + 128 (C division, truncation toward zero) and decoded as
// prediction + 2 * (stored - 128).
inline int colourResidualUnclamped(int value, int prediction) {
    return (value - prediction) / 2 + 128;
}
inline int colourValueUnclamped(int prediction, int stored) {
    return prediction + 2 * (stored - 128);
}

// Decodes a stored colour residual against its prediction:
// value = clamp(prediction + 2 * (stored - 128), 0, 255).
inline uint8_t applyColourResidual(uint8_t prediction, uint8_t stored) {
    const int v = colourValueUnclamped(prediction, stored);
    return static_cast<uint8_t>(v < 0 ? 0 : (v > 255 ? 255 : v));
}

// Encodes value against prediction: (value - prediction) / 2 + 128 (C division, truncation
// toward zero), clamped to 0..255. `clamped` is set when the clamp changed the result.
inline uint8_t encodeColourResidual(uint8_t value, uint8_t prediction, bool* clamped = nullptr) {
    const int r = colourResidualUnclamped(value, prediction);
    const int c = r < 0 ? 0 : (r > 255 ? 255 : r);
    if (clamped) {
        *clamped = (c != r);
    }
    return static_cast<uint8_t>(c);
}

// Whole rows of samples: stored[k] = encodeColourResidual(value[k], prediction[k]) for k <
// count, returning how many were clamped; and in place, values[k] = applyColourResidual(values[k],
// stored[k]) (values holding the predictions on entry). The same integers as the functions
// above, in loops the compiler vectorises at -O2 too. No buffer may overlap another.
int64_t encodeColourResiduals(const uint8_t* value, const uint8_t* prediction, size_t count, uint8_t* stored);
void applyColourResiduals(uint8_t* values, const uint8_t* stored, size_t count);

// Both at once, as the encoder does with residuals that are stored losslessly: stored[k] =
// encodeColourResidual(value[k], rebuilt[k]) and then, in place, rebuilt[k] =
// applyColourResidual(rebuilt[k], stored[k]) (rebuilt holding the predictions on entry). For
// 8-bit values neither step clamps (the difference d is within +-255, so d / 2 + 128 is within
// 1..255, and prediction + 2 (d / 2) lies between prediction and value), so a rebuilt sample is
// its value, or one off where d is odd: `errors` is both the number of errors and the sum of
// their squares. `spread` is the sum of |stored[k] - 128|. One pass over the row, compiled for
// AVX2 too where the CPU has it (the same integers). It calls the unclamped rule above, since
// the clamps cannot act and GCC keeps them in the vector loop otherwise.
struct RebuiltRow {
    int64_t errors = 0;
    int64_t spread = 0;
};
RebuiltRow encodeColourResidualsRebuilt(const uint8_t* value, uint8_t* rebuilt, size_t count, uint8_t* stored);

// Rebuilds a whole child tile: out = applyColourResidual(predictColour(parent...), residual)
// for every pixel and channel. `residual` and `out` are (T+4)^2 x channels bytes; pass
// residual = nullptr for "no residual" (every stored value 128).
void upsampleColour(const uint8_t* parent, int tileSize, int channels, int tx, int ty,
                   const uint8_t* residual, uint8_t* out);

} // namespace pyramid
