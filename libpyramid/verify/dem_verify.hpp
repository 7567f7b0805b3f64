// `pyramid verify DEM.dat --source INPUT`: every level of a residual file rebuilt with the CPU
// elevation producer and compared with the source heights, sampled by the same rule as
// preprocessDem (libpyramid/encode/dem/dem_sampling.hpp).
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "libpyramid/sphere/planar_mosaic.hpp"

namespace pyramid {

struct DemVerifyOptions {
    int band = 0;
    std::optional<double> nodata;
    bool ignoreDeclaredNodata = false;
    bool stretch = false;
    int threads = 0;
    PlanarTarget target; // as the pyramid was built (--crs, --extent)
};

struct DemVerifyLevel {
    int level = 0;
    int64_t tiles = 0;
    int64_t samples = 0;
    double maxError = 0.0;
    double rmsError = 0.0;
    int64_t beyondBound = 0; // samples whose error passes scale/2 (+ float32 rounding)
    // Samples whose rebuilt or source height is NaN or infinite: never within any bound, and
    // left out of maxError and rmsError so that those stay numbers.
    int64_t nonFinite = 0;
};

struct DemVerifyReport {
    std::string file;
    std::string source;
    double scale = 0.0;
    double bound = 0.0; // scale / 2
    std::vector<DemVerifyLevel> levels;
    // Every sample within the bound, and none non-finite.
    bool ok() const;
};

DemVerifyReport verifyDem(const std::string& file, const std::string& source, const DemVerifyOptions& options);

nlohmann::json toJson(const DemVerifyReport& report);

} // namespace pyramid
