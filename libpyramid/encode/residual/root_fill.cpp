#include "libpyramid/encode/residual/root_fill.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "formats/error.hpp"
#include "libpyramid/support/parallel.hpp"

namespace pyramid {

std::pair<double, int64_t> sumValidHeights(const HeightSource& heights, int64_t N, int64_t stride, int threads) {
    constexpr int64_t kBlock = 256;
    double sum = 0.0;
    int64_t count = 0;
    if (!heights.mayHaveHeights(0, 0, N, N)) {
        return {sum, count};
    }
    const int64_t samples = N / stride + 1;
    const int64_t blocks = (samples - 1) / kBlock + 1;
    std::vector<double> sums(static_cast<size_t>(blocks));
    std::vector<int64_t> counts(static_cast<size_t>(blocks));
    for (int64_t by = 0; by < blocks; ++by) {
        parallelFor(blocks, threads, [&](int64_t bx) {
            SourceGrid block;
            block.stride = stride;
            block.x0 = bx * kBlock * stride;
            block.y0 = by * kBlock * stride;
            block.nx = std::min(samples, (bx + 1) * kBlock) - bx * kBlock;
            block.ny = std::min(samples, (by + 1) * kBlock) - by * kBlock;
            double s = 0.0;
            int64_t c = 0;
            if (heights.mayHaveHeights(block.x0, block.y0, block.x0 + (block.nx - 1) * stride,
                                       block.y0 + (block.ny - 1) * stride)) {
                heights.sample(block);
                for (size_t k = 0; k < block.valid.size(); ++k) {
                    if (block.valid[k]) {
                        s += block.height[k];
                        ++c;
                    }
                }
            }
            sums[static_cast<size_t>(bx)] = s;
            counts[static_cast<size_t>(bx)] = c;
        });
        for (int64_t bx = 0; bx < blocks; ++bx) {
            sum += sums[static_cast<size_t>(bx)];
            count += counts[static_cast<size_t>(bx)];
        }
    }
    return {sum, count};
}

void fillRootNodata(const ResidualPlan& plan, SourceGrid& grid, const HeightSource& heights, int threads,
                    const std::function<const GivenRootFill&()>& givenFill, const std::string& input) {
    const int64_t border = plan.rootBorder();
    const int64_t side = plan.R + 1 + 2 * border;
    const int64_t unit = int64_t{1} << plan.M;
    std::vector<size_t> idx(static_cast<size_t>(side * side));
    double sum = 0.0;
    int64_t valid = 0;
    for (int64_t q = 0; q < side; ++q) {
        for (int64_t p = 0; p < side; ++p) {
            const size_t s = grid.index((p - border) * unit, (q - border) * unit);
            idx[static_cast<size_t>(p + q * side)] = s;
            if (grid.valid[s]) {
                sum += grid.height[s];
                ++valid;
            }
        }
    }
    if (valid == static_cast<int64_t>(idx.size())) {
        return;
    }
    const GivenRootFill* given = givenFill ? &givenFill() : nullptr;
    if (given && given->value.size() != idx.size()) {
        fail(input, "internal error: a given root fill of " + std::to_string(given->value.size()) +
                        " values for a root grid of " + std::to_string(idx.size()));
    }
    if (given) {
        sum = given->start;
        valid = 1;
    } else if (valid == 0) {
        for (size_t s = 0; s < grid.valid.size(); ++s) {
            if (grid.valid[s]) {
                sum += grid.height[s];
                ++valid;
            }
        }
        if (valid == 0 && grid.stride > 1) {
            // The grid holds every stride-th sample: valid heights between them count too.
            std::tie(sum, valid) = sumValidHeights(heights, plan.N, 1, threads);
        }
        if (valid == 0) {
            fail(input, "no valid height anywhere (everything is nodata)");
        }
    }
    const float mean = static_cast<float>(sum / static_cast<double>(valid));
    std::vector<double> v(idx.size());
    std::vector<bool> fixed(idx.size());
    std::vector<bool> filled(idx.size()); // nodata, given a value or solved here
    bool sweeps = false;
    for (size_t k = 0; k < idx.size(); ++k) {
        fixed[k] = grid.valid[idx[k]] != 0;
        filled[k] = !fixed[k];
        v[k] = fixed[k] ? grid.height[idx[k]] : mean;
        if (!fixed[k] && given && !std::isnan(given->value[k])) {
            v[k] = given->value[k];
            fixed[k] = true;
        }
        sweeps = sweeps || !fixed[k];
    }
    for (int sweep = 0; sweeps && sweep < 500; ++sweep) {
        for (int64_t q = 0; q < side; ++q) {
            for (int64_t p = 0; p < side; ++p) {
                const size_t k = static_cast<size_t>(p + q * side);
                if (fixed[k]) {
                    continue;
                }
                const double l = v[static_cast<size_t>(std::max<int64_t>(p - 1, 0) + q * side)];
                const double r = v[static_cast<size_t>(std::min<int64_t>(p + 1, side - 1) + q * side)];
                const double d = v[static_cast<size_t>(p + std::max<int64_t>(q - 1, 0) * side)];
                const double u = v[static_cast<size_t>(p + std::min<int64_t>(q + 1, side - 1) * side)];
                v[k] = (l + r + d + u) * 0.25;
            }
        }
    }
    for (size_t k = 0; k < idx.size(); ++k) {
        if (filled[k]) {
            grid.height[idx[k]] = static_cast<float>(v[k]);
            grid.valid[idx[k]] = 2;
        }
    }
}

} // namespace pyramid
