#include "formats/residual_codec.hpp"

#include <algorithm>

#include "formats/error.hpp"
#include "formats/residual_context.hpp"
#include "formats/residual_tiff_plain.hpp"
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

namespace {

// A context-coded blob, or any TIFF through libtiff (the reference, with its errors).
std::vector<int16_t> decodeAnyResidualBlob(std::span<const uint8_t> blob, int size, const std::string& where,
                                           std::span<const int32_t> parentPlane) {
    return isContextResidualBlob(blob) ? decodeContextResiduals(blob, size, where, parentPlane)
                                       : decodeResidualTiff(blob, size, where);
}

} // namespace

void decodeResidualBlobInto(std::span<const uint8_t> blob, int size, const std::string& where, std::span<int16_t> out,
                            std::span<const int32_t> parentPlane) {
    if (out.size() != static_cast<size_t>(size) * static_cast<size_t>(size)) {
        fail(where, "residual tile buffer of " + std::to_string(out.size()) + " samples for a tile of " +
                        std::to_string(size) + "x" + std::to_string(size));
    }
    if (!isContextResidualBlob(blob)) {
        switch (decodePlainResidualTiff(blob, size, out)) {
        case PlainDecode::Decoded:
            return;
        case PlainDecode::Damaged:
            fail(where, "truncated or corrupt TIFF data: its Deflate data is corrupt or fails its checksum (Adler-32)");
        case PlainDecode::Declined:
            break;
        }
    }
    const std::vector<int16_t> samples = decodeAnyResidualBlob(blob, size, where, parentPlane);
    std::copy(samples.begin(), samples.end(), out.begin());
}

std::vector<int16_t> decodeResidualBlob(std::span<const uint8_t> blob, int size, const std::string& where,
                                        std::span<const int32_t> parentPlane) {
    if (size < 1) {
        return decodeAnyResidualBlob(blob, size, where, parentPlane); // which names the size's problem
    }
    std::vector<int16_t> out(static_cast<size_t>(size) * static_cast<size_t>(size));
    decodeResidualBlobInto(blob, size, where, out, parentPlane);
    return out;
}

std::string describeResidualBlob(std::span<const uint8_t> blob) {
    return isContextResidualBlob(blob) ? std::string("context") : describeTiff(blob);
}

} // namespace pyramid
