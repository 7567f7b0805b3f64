// The range coder of context-coded residual tiles (doc/format.md, 1.8), shared by the tile's
// versions: 32-bit range, 64-bit low with carry propagation, bytes out most significant first.
// Every version codes symbols of adaptive frequency tables (encode/decodeFrequency) and equally
// likely bits; version 2 also binary decisions of adaptive probabilities (BitModel).
#pragma once
#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "formats/error.hpp"

namespace pyramid::context_coding {

inline constexpr uint32_t kTop = 1u << 24; // the coder renormalises below this range

// An adaptive binary probability (version 2's signs and escape bits): two 16-bit estimates of
// the probability of a 0, one fast (shift 4) and one slow (shift 7); a decision is coded with
// their mean in 12 bits, q = (fast + slow) >> 5, which stays within 4..4091 (doc/format.md, 1.8).
struct BitModel {
    uint16_t fast = 32768;
    uint16_t slow = 32768;
    uint32_t probability() const { return (static_cast<uint32_t>(fast) + slow) >> 5; }
    // Both ways computed and one kept by a mask (no branch: a sign is about as likely one way as
    // the other).
    void update(int bit) {
        const uint32_t one = 0u - static_cast<uint32_t>(bit);
        const uint32_t f = fast;
        const uint32_t s = slow;
        fast = static_cast<uint16_t>(((f + ((65536u - f) >> 4)) & ~one) | ((f - (f >> 4)) & one));
        slow = static_cast<uint16_t>(((s + ((65536u - s) >> 7)) & ~one) | ((s - (s >> 7)) & one));
    }
};

class RangeEncoder {
public:
    explicit RangeEncoder(std::vector<uint8_t>& out) : out_(out) {}
    // The interval [cum, cum + freq) of a total (at most 2^16).
    void encode(uint32_t cum, uint32_t freq, uint32_t total) {
        const uint32_t r = range_ / total;
        low_ += static_cast<uint64_t>(r) * cum;
        range_ = r * freq;
        normalise();
    }
    // `bits` (at most 16) equally likely bits, as one interval of a total 2^bits (version 0).
    void encodeBits(uint32_t value, int bits) {
        if (bits > 0) {
            encode(value, 1, 1u << bits);
        }
    }
    // One binary decision (version 2).
    int encodeBit(BitModel& m, int bit) {
        const uint32_t bound = (range_ >> 12) * m.probability();
        if (bit == 0) {
            range_ = bound;
        } else {
            low_ += bound;
            range_ -= bound;
        }
        m.update(bit);
        normalise();
        return bit;
    }
    // `bits` equally likely bits, most significant first, each halving the range (no version uses them).
    uint32_t encodeEqualBits(uint32_t value, int bits) {
        for (int k = bits - 1; k >= 0; --k) {
            range_ >>= 1;
            if (((value >> k) & 1u) != 0) {
                low_ += range_;
            }
            normalise();
        }
        return value;
    }
    void finish() {
        for (int k = 0; k < 5; ++k) {
            shiftLow();
        }
    }

private:
    void normalise() {
        while (range_ < kTop) {
            range_ <<= 8;
            shiftLow();
        }
    }
    void shiftLow() {
        if (static_cast<uint32_t>(low_) < 0xFF000000u || (low_ >> 32) != 0) {
            const auto carry = static_cast<uint8_t>(low_ >> 32);
            uint8_t byte = cache_;
            do {
                out_.push_back(static_cast<uint8_t>(byte + carry));
                byte = 0xFF;
            } while (--pending_ != 0);
            cache_ = static_cast<uint8_t>(low_ >> 24);
        }
        ++pending_;
        low_ = (low_ & 0x00FFFFFFu) << 8;
    }

    std::vector<uint8_t>& out_;
    uint64_t low_ = 0;
    uint32_t range_ = 0xFFFFFFFFu;
    uint8_t cache_ = 0;
    uint64_t pending_ = 1;
};

class RangeDecoder {
public:
    RangeDecoder(std::span<const uint8_t> bytes, const std::string& where) : in_(bytes), where_(where) {
        if (in_.size() < 5 || in_[0] != 0) {
            fail(where_, "context-coded residual tile: damaged stream start");
        }
        for (int k = 0; k < 5; ++k) {
            code_ = (code_ << 8) | next();
        }
    }
    uint32_t decodeFrequency(uint32_t total) {
        r_ = range_ / total;
        return std::min(code_ / r_, total - 1);
    }
    // The symbol of the table `count` (total `total`) whose interval holds the code, consumed:
    // the same as decodeFrequency, a search and consume, without dividing the code (version 2).
    template <size_t N>
    uint32_t decodeSymbol(const std::array<uint32_t, N>& count, uint32_t total) {
        const uint32_t r = range_ / total;
        uint32_t s = 0;
        uint32_t low = 0;
        uint32_t width = r * count[0];
        while (s + 1 < N && low + width <= code_) {
            low += width;
            ++s;
            width = r * count[s];
        }
        code_ -= low;
        range_ = width;
        normalise();
        return s;
    }
    void consume(uint32_t cum, uint32_t freq) {
        code_ -= r_ * cum;
        range_ = r_ * freq;
        normalise();
    }
    uint32_t decodeBits(int bits) {
        if (bits == 0) {
            return 0;
        }
        const uint32_t v = decodeFrequency(1u << bits);
        consume(v, 1);
        return v;
    }
    int decodeBit(BitModel& m) {
        const uint32_t bound = (range_ >> 12) * m.probability();
        const int bit = code_ >= bound ? 1 : 0;
        const uint32_t mask = 0u - static_cast<uint32_t>(bit);
        code_ -= bound & mask;
        range_ = (bound & ~mask) | ((range_ - bound) & mask);
        m.update(bit);
        normalise();
        return bit;
    }
    // The second argument mirrors the encoder's (unused): one loop serves both.
    int encodeBit(BitModel& m, int /*bit*/) { return decodeBit(m); }
    uint32_t encodeEqualBits(uint32_t /*value*/, int bits) {
        uint32_t v = 0;
        for (int k = 0; k < bits; ++k) {
            range_ >>= 1;
            const uint32_t bit = code_ >= range_ ? 1u : 0u;
            code_ -= bit * range_;
            v = (v << 1) | bit;
            normalise();
        }
        return v;
    }
    // Every byte read, none beyond the end.
    void finish() const {
        if (overrun_) {
            fail(where_, "context-coded residual tile: the stream ends early");
        }
        if (pos_ != in_.size()) {
            fail(where_, "context-coded residual tile: " + std::to_string(in_.size() - pos_) +
                             " bytes after the end of the stream");
        }
    }

private:
    void normalise() {
        while (range_ < kTop) {
            range_ <<= 8;
            code_ = (code_ << 8) | next();
        }
    }
    uint32_t next() {
        if (pos_ < in_.size()) {
            return in_[pos_++];
        }
        overrun_ = true;
        return 0;
    }

    std::span<const uint8_t> in_;
    const std::string& where_;
    size_t pos_ = 0;
    bool overrun_ = false;
    uint32_t code_ = 0;
    uint32_t range_ = 0xFFFFFFFFu;
    uint32_t r_ = 1;
};

} // namespace pyramid::context_coding
