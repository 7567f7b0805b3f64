#include "libpyramid/encode/residual/root_fill.hpp"

#include <algorithm>
#include <vector>

#include "formats/error.hpp"

namespace pyramid {

void fillRootNodata(const ResidualPlan& plan, SourceGrid& grid, std::optional<float> emptyFill, const std::string& input) {
    const int64_t border = plan.folded ? 2 : 0;
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
    if (valid == 0) {
        for (size_t s = 0; s < grid.valid.size(); ++s) {
            if (grid.valid[s]) {
                sum += grid.height[s];
                ++valid;
            }
        }
        if (valid == 0 && !emptyFill) {
            fail(input, "no valid height anywhere (everything is nodata)");
        }
        if (valid == 0) {
            sum = *emptyFill;
            valid = 1;
        }
    }
    const float mean = static_cast<float>(sum / static_cast<double>(valid));
    std::vector<double> v(idx.size());
    std::vector<bool> fixed(idx.size());
    for (size_t k = 0; k < idx.size(); ++k) {
        fixed[k] = grid.valid[idx[k]] != 0;
        v[k] = fixed[k] ? grid.height[idx[k]] : mean;
    }
    for (int sweep = 0; sweep < 500; ++sweep) {
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
        if (!fixed[k]) {
            grid.height[idx[k]] = static_cast<float>(v[k]);
            grid.valid[idx[k]] = 2;
        }
    }
}

} // namespace pyramid
