#include "formats/residual_codec.hpp"

#include "formats/error.hpp"
#include "formats/residual_context.hpp"
#include "formats/tiff_tile.hpp"

namespace pyramid {

const char* residualCodecName(ResidualCodec codec) {
    switch (codec) {
    case ResidualCodec::Smallest:
        return "smallest";
    case ResidualCodec::Context:
        return "context";
    case ResidualCodec::Deflate:
        break;
    }
    return "deflate";
}

std::optional<ResidualCodec> parseResidualCodec(const std::string& name) {
    for (const ResidualCodec c : {ResidualCodec::Deflate, ResidualCodec::Smallest, ResidualCodec::Context}) {
        if (name == residualCodecName(c)) {
            return c;
        }
    }
    return std::nullopt;
}

int ResidualTileCoding::effectiveDeflateLevel() const {
    if (deflateLevel != 0) {
        return deflateLevel;
    }
    return codec == ResidualCodec::Smallest ? 12 : 2;
}

void ResidualTileCoding::validate() const {
    if (deflateLevel < 0 || deflateLevel > 12) {
        failOption("deflateLevel", std::to_string(deflateLevel) + " is not 1..12");
    }
    if (deflateLevel != 0 && codec == ResidualCodec::Context) {
        failOption("deflateLevel", "context-coded tiles have no Deflate level");
    }
}

std::vector<uint8_t> encodeResidualBlob(std::span<const int16_t> residuals, int size, const ResidualTileCoding& coding) {
    const int level = coding.effectiveDeflateLevel();
    switch (coding.codec) {
    case ResidualCodec::Context:
        return encodeContextResiduals(residuals, size);
    case ResidualCodec::Smallest: {
        // In this order, the first of equal sizes kept: the same bytes on every machine.
        std::vector<uint8_t> best = encodeResidualTiff(residuals, size, level);
        for (const auto& [layout, predictor] : {std::pair{ResidualTiffLayout::TwoBytes, true},
                                                std::pair{ResidualTiffLayout::OneShort, true}}) {
            std::vector<uint8_t> other = encodeResidualTiff(residuals, size, level, layout, predictor);
            if (other.size() < best.size()) {
                best = std::move(other);
            }
        }
        return best;
    }
    case ResidualCodec::Deflate:
        break;
    }
    return encodeResidualTiff(residuals, size, level);
}

std::vector<int16_t> decodeResidualBlob(std::span<const uint8_t> blob, int size, const std::string& where) {
    if (isContextResidualBlob(blob)) {
        return decodeContextResiduals(blob, size, where);
    }
    return decodeResidualTiff(blob, size, where);
}

std::string describeResidualBlob(std::span<const uint8_t> blob) {
    return isContextResidualBlob(blob) ? std::string("context") : describeTiff(blob);
}

} // namespace pyramid
