// The two input rows a separable bilinear interpolation combines for one output row, each
// interpolated along x once and kept while the next output rows still need it. Output rows go
// through the input in order, so two slots are enough: an input row is computed again only if
// it comes back after two others.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace pyramid {

class RowPairCache {
public:
    explicit RowPairCache(size_t length) : rows_{std::vector<double>(length), std::vector<double>(length)} {}

    // Input row r interpolated: held, or computed by fill(r, out) into the slot that does not
    // hold input row `keep` (the other row of the pair being formed; -1 for none).
    template <typename Fill>
    const double* row(int64_t r, int64_t keep, Fill&& fill) {
        for (int k = 0; k < 2; ++k) {
            if (rowOf_[k] == r) {
                return rows_[k].data();
            }
        }
        const int k = rowOf_[0] == keep ? 1 : 0;
        fill(r, rows_[k].data());
        rowOf_[k] = r;
        return rows_[k].data();
    }

private:
    std::vector<double> rows_[2];
    int64_t rowOf_[2] = {-1, -1};
};

} // namespace pyramid
