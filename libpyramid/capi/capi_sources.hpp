// The byte sources a C caller's descriptors name (pyramid_source: a path, memory, I/O callbacks),
// made for one open call and armed once it succeeds, so that a failed open leaves the callbacks
// to the caller; shared by the opens of a file and of the producers.
#pragma once
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "formats/byte_source.hpp"
#include "formats/error.hpp"
#include "libpyramid/capi/capi_sized.hpp"
#include "libpyramid/capi/capi_status.hpp"
#include "libpyramid/capi/pyramid.h"

namespace pyramid::capi {

// A caller's I/O callbacks. release() is called by the destructor only once the open that made
// the source succeeded (arm()): a failed open leaves the callbacks to the caller.
class IoSource final : public pyramid::ByteSource {
public:
    IoSource(std::string name, const pyramid_io& io) : ByteSource(std::move(name)), io_(io) {}
    ~IoSource() override {
        if (armed_.load(std::memory_order_acquire) && io_.release) {
            io_.release(io_.user);
        }
    }
    void arm() { armed_.store(true, std::memory_order_release); }

    uint64_t size() const override { return io_.size; }

    void readAt(uint64_t offset, void* out, size_t size) const override {
        pyramid::checkRange(*this, io_.size, offset, size);
        if (size == 0) {
            return;
        }
        size_t got = 0;
        const int status = io_.read(io_.user, offset, out, size, &got);
        if (status != 0) {
            pyramid::fail(name(), "read of " + std::to_string(size) + " bytes at offset " + std::to_string(offset) +
                                      " failed (the read callback returned " + std::to_string(status) + ")");
        }
        if (got != size) {
            pyramid::fail(name(), "read of " + std::to_string(size) + " bytes at offset " + std::to_string(offset) +
                                      " returned " + std::to_string(got) + " bytes");
        }
    }

private:
    pyramid_io io_;
    std::atomic<bool> armed_{false};
};

// The sources of one open call: made from the caller's descriptors, armed once the open succeeds.
struct SourceSet {
    std::vector<std::shared_ptr<IoSource>> io;

    void arm() {
        for (const auto& s : io) {
            s->arm();
        }
    }

    // The byte source a descriptor names; false (with the message set) for a bad descriptor.
    // Throws Error when a file cannot be opened.
    bool make(const pyramid_source* in, const char* what, std::shared_ptr<const pyramid::ByteSource>& out) {
        if (!in) {
            failWith(PYRAMID_ERROR_ARGUMENT, std::string(what) + ": null source");
            return false;
        }
        pyramid_source d{};
        if (!readSized(in, d, what)) {
            return false;
        }
        // A C caller may store any int in the enum: read it as one (a value outside the enum is
        // no valid pyramid_source_kind in C++).
        int kind = 0;
        static_assert(sizeof kind == sizeof d.kind);
        std::memcpy(&kind, &d.kind, sizeof kind);
        switch (kind) {
        case PYRAMID_SOURCE_PATH:
            if (!d.path) {
                failWith(PYRAMID_ERROR_ARGUMENT, std::string(what) + ": a path source without a path");
                return false;
            }
            out = pyramid::openFileSource(d.path);
            return true;
        case PYRAMID_SOURCE_MEMORY:
            if (!d.data && d.size > 0) {
                failWith(PYRAMID_ERROR_ARGUMENT, std::string(what) + ": a memory source of " + std::to_string(d.size) +
                                                     " bytes without data");
                return false;
            }
            out = pyramid::memorySource(d.name ? d.name : "(memory)", d.data, d.size);
            return true;
        case PYRAMID_SOURCE_IO: {
            if (!d.io.read) {
                failWith(PYRAMID_ERROR_ARGUMENT, std::string(what) + ": an I/O source without a read callback");
                return false;
            }
            auto s = std::make_shared<IoSource>(d.name ? d.name : "(io)", d.io);
            io.push_back(s);
            out = std::move(s);
            return true;
        }
        }
        failWith(PYRAMID_ERROR_ARGUMENT, std::string(what) + ": unknown source kind " + std::to_string(kind));
        return false;
    }

    // The main source and the region sources of a producer.
    bool makeAll(const pyramid_source* main, const pyramid_source* const* regions, size_t count, const char* what,
                 std::shared_ptr<const pyramid::ByteSource>& mainOut,
                 std::vector<std::shared_ptr<const pyramid::ByteSource>>& regionsOut) {
        if (count > 0 && !regions) {
            failWith(PYRAMID_ERROR_ARGUMENT, std::string(what) + ": null region array");
            return false;
        }
        if (!make(main, what, mainOut)) {
            return false;
        }
        for (size_t k = 0; k < count; ++k) {
            std::shared_ptr<const pyramid::ByteSource> r;
            if (!make(regions[k], what, r)) {
                return false;
            }
            regionsOut.push_back(std::move(r));
        }
        return true;
    }
};

inline pyramid_source pathSource(const char* path) {
    pyramid_source s{};
    s.struct_size = sizeof s;
    s.kind = PYRAMID_SOURCE_PATH;
    s.path = path;
    return s;
}

} // namespace pyramid::capi
