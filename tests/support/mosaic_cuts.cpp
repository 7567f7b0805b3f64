#include "tests/support/mosaic_cuts.hpp"

#include <vector>

#include "tests/support/geotiffs.hpp"

namespace pyramid::test {

float heightAt(int x, int y) {
    return 800.0f + static_cast<float>(x * 3 - y * 5) + 0.5f * static_cast<float>((x * 7 + y * 3) % 11);
}

std::string cut(const TempDir& dir, const std::string& name, const Grid& g, int x0, int y0, int w, int h) {
    std::vector<float> v(static_cast<size_t>(w * h));
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            v[static_cast<size_t>(x + y * w)] = heightAt(x0 + x, y0 + y);
        }
    }
    const std::string path = dir.file(name);
    writeGeoTiff(path, w, h, v, geographicTags(4326, g.west + x0 * g.step, g.north - y0 * g.step, g.step));
    return path;
}

} // namespace pyramid::test
