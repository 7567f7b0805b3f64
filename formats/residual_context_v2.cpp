#include "formats/residual_context_v2.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstdlib>
#include <memory>

#include "formats/error.hpp"
#include "formats/residual_context.hpp"
#include "formats/residual_context_models.hpp"
#include "formats/residual_context_parent.hpp"
#include "formats/residual_context_state.hpp"
#include "formats/residual_context_values.hpp"
#include "formats/residual_range_coder.hpp"

namespace pyramid::context_coding {

namespace {

template <int Mode>
[[gnu::always_inline]] inline Context contextOf(const Planes& planes, size_t i, int x, int y) {
    const size_t s = planes.stride;
    const int32_t* r = planes.residual.data();
    const int parity = (x & 1) + 2 * (y & 1);
    int32_t p = 0;
    if constexpr (Mode == 1) { // the median predictor, with its own rules on the first row and column
        const int32_t a = x > 0 ? r[i - 1] : (y > 0 ? r[i - s] : 0);
        const int32_t b = y > 0 ? r[i - s] : a;
        const int32_t c = x > 0 && y > 0 ? r[i - s - 1] : a;
        p = static_cast<int32_t>(median(a, b, c));
    } else if constexpr (Mode == 4) {
        p = clampedGridPrediction(planes, i, x, y, parity);
    } else if constexpr (Mode >= 2) {
        if (parity != 0) {
            const int* w = kPredictionWeights[parity - 1];
            p = (w[0] * r[i - 1] + w[1] * r[i - s] + w[2] * r[i - s - 1] + w[3] * r[i - s + 1] + w[4] * r[i - 2] +
                 w[5] * r[i - 2 * s] + 8) >> 4;
        }
    }
    const uint32_t* m = planes.magnitude.data();
    uint32_t activity = 2 * m[i - 1] + 2 * m[i - s] + m[i - s - 1] + m[i - s + 1] + m[i - 2] + m[i - 2 * s];
    if constexpr (Mode >= 3) {
        return parentContext<Mode>(planes, i, x, y, p, activity);
    }
    if constexpr (Mode == 2) {
        activity += static_cast<uint32_t>(std::abs(p));
    }
    Context c;
    c.prediction = p;
    c.table = static_cast<size_t>(tableOf(activity, x, y));
    c.pattern = static_cast<size_t>((parity * 3 + signOf(planes.value[i - 1]) + 1) * 3 + signOf(planes.value[i - s]) + 1);
    c.sign = signModel(c.pattern, p, 0);
    return c;
}

template <int Mode>
using ModelsOf = Models<Mode == 4 ? 5 : (Mode == 3 ? 3 : 1)>;

template <int Mode>
void encodeSamples(std::span<const int16_t> residuals, int size, const int32_t* parent, RangeEncoder& coder) {
    const PlanesLease lease(size, Mode);
    Planes& planes = *lease;
    planes.parent = parent;
    if constexpr (Mode == 4) {
        clampParentPlane(planes);
    }
    const auto models = std::make_unique<ModelsOf<Mode>>();
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            const size_t i = planes.at(x, y);
            const int32_t residual = residuals[static_cast<size_t>(y) * static_cast<size_t>(size) + static_cast<size_t>(x)];
            planes.residual[i] = residual;
            Context c = contextOf<Mode>(planes, i, x, y);
            if constexpr (Mode == 4) {
                if (c.step >= 0) { // the side nearer the residual, the low one on a tie
                    const int high = std::abs(residual - c.high) < std::abs(residual - c.low) ? 1 : 0;
                    resolveStep(c, coder.encodeBit(models->steps[static_cast<size_t>(c.step)], high), x, y);
                }
            }
            const int32_t v = residual - c.prediction;
            planes.value[i] = v;
            planes.magnitude[i] = static_cast<uint32_t>(std::abs(v));
            if constexpr (Mode >= 3) {
                keepParentState(planes, i, x, y, residual, c);
            }
            encodeValue(coder, *models, c.table, c.sign, v);
        }
    }
}

template <int Mode>
std::vector<int16_t> decodeSamples(RangeDecoder& coder, int size, const int32_t* parent, const std::string& where) {
    const PlanesLease lease(size, Mode);
    Planes& planes = *lease;
    planes.parent = parent;
    if constexpr (Mode == 4) {
        clampParentPlane(planes);
    }
    const auto models = std::make_unique<ModelsOf<Mode>>();
    std::vector<int16_t> out(static_cast<size_t>(size) * static_cast<size_t>(size));
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            const size_t i = planes.at(x, y);
            Context c = contextOf<Mode>(planes, i, x, y);
            if constexpr (Mode == 4) {
                if (c.step >= 0) {
                    resolveStep(c, coder.decodeBit(models->steps[static_cast<size_t>(c.step)]), x, y);
                }
            }
            const int32_t v = decodeValue(coder, *models, c.table, c.sign);
            const int32_t residual = v + c.prediction;
            if (residual < -32768 || residual > 32767) {
                fail(where, "context-coded residual tile: a residual of " + std::to_string(residual) + " is beyond int16");
            }
            planes.residual[i] = residual;
            planes.value[i] = v;
            planes.magnitude[i] = static_cast<uint32_t>(std::abs(v));
            if constexpr (Mode >= 3) {
                keepParentState(planes, i, x, y, residual, c);
            }
            out[static_cast<size_t>(y) * static_cast<size_t>(size) + static_cast<size_t>(x)] = static_cast<int16_t>(residual);
        }
    }
    return out;
}

} // namespace

std::vector<uint8_t> encodeVersion2(std::span<const int16_t> residuals, int size, uint8_t mode) {
    std::vector<uint8_t> out = {kContextResidualMagic[0], kContextResidualMagic[1], kContextResidualMagic[2],
                                kContextResidualMagic[3], static_cast<uint8_t>(size & 0xff),
                                static_cast<uint8_t>(size >> 8), mode, 2};
    out.reserve(residuals.size() / 2 + kHeaderBytes);
    RangeEncoder coder(out);
    if (mode == 0) {
        encodeSamples<0>(residuals, size, nullptr, coder);
    } else if (mode == 1) {
        encodeSamples<1>(residuals, size, nullptr, coder);
    } else {
        encodeSamples<2>(residuals, size, nullptr, coder);
    }
    coder.finish();
    return out;
}

std::vector<int16_t> decodeVersion2(std::span<const uint8_t> blob, int size, uint8_t mode, const std::string& where) {
    RangeDecoder coder(blob.subspan(kHeaderBytes), where);
    std::vector<int16_t> out = mode == 0   ? decodeSamples<0>(coder, size, nullptr, where)
                               : mode == 1 ? decodeSamples<1>(coder, size, nullptr, where)
                                           : decodeSamples<2>(coder, size, nullptr, where);
    coder.finish();
    return out;
}

namespace {

template <int Mode>
std::vector<uint8_t> encodeParentModeAs(std::span<const int16_t> residuals, int size, std::span<const int32_t> parent) {
    std::vector<uint8_t> out = {kContextResidualMagic[0], kContextResidualMagic[1], kContextResidualMagic[2],
                                kContextResidualMagic[3], static_cast<uint8_t>(size & 0xff),
                                static_cast<uint8_t>(size >> 8), static_cast<uint8_t>(Mode), 3};
    out.reserve(residuals.size() / 2 + kHeaderBytes);
    RangeEncoder coder(out);
    encodeSamples<Mode>(residuals, size, parent.data(), coder);
    coder.finish();
    return out;
}

} // namespace

std::vector<uint8_t> encodeParentMode(std::span<const int16_t> residuals, int size, std::span<const int32_t> parent,
                                      int mode) {
    if (mode == 4) {
        return encodeParentModeAs<4>(residuals, size, parent);
    }
    if (mode == 5) {
        return encodeTerraceMode(residuals, size, parent);
    }
    std::vector<uint8_t> best = encodeParentModeAs<3>(residuals, size, parent);
    const auto keepSmaller = [&best](std::vector<uint8_t> other) {
        if (other.size() < best.size()) {
            best = std::move(other);
        }
    };
    if (mode == -1 && hasShoreSteps(residuals, size, parent)) {
        keepSmaller(encodeParentModeAs<4>(residuals, size, parent));
    }
    if (mode == -1 && isTerraced(residuals, parent)) {
        keepSmaller(encodeTerraceMode(residuals, size, parent));
    }
    return best;
}

std::vector<int16_t> decodeParentMode(std::span<const uint8_t> blob, int size, std::span<const int32_t> parent,
                                      const std::string& where) {
    if (blob[6] == 5) {
        return decodeTerraceMode(blob, size, parent, where);
    }
    RangeDecoder coder(blob.subspan(kHeaderBytes), where);
    std::vector<int16_t> out = blob[6] == 4 ? decodeSamples<4>(coder, size, parent.data(), where)
                                            : decodeSamples<3>(coder, size, parent.data(), where);
    coder.finish();
    return out;
}

} // namespace pyramid::context_coding
