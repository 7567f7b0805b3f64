#include "tests/support/c_api_sources.hpp"

#include <cstring>

#include "formats/residual_file.hpp"

namespace pyramid::test {

int MemoryIo::read(void* user, uint64_t offset, void* buffer, size_t size, size_t* bytesRead) {
    auto* io = static_cast<MemoryIo*>(user);
    const long n = ++io->reads;
    if ((io->failAt != 0 && n >= io->failAt) || offset > io->data.size() || size > io->data.size() - offset) {
        return 1;
    }
    std::memcpy(buffer, io->data.data() + offset, size);
    *bytesRead = size;
    return 0;
}

void MemoryIo::release(void* user) { ++static_cast<MemoryIo*>(user)->released; }

pyramid_source pathSource(const std::string& path) {
    pyramid_source s{};
    s.struct_size = sizeof s;
    s.kind = PYRAMID_SOURCE_PATH;
    s.path = path.c_str();
    return s;
}

pyramid_source memorySource(const std::vector<uint8_t>& bytes, const char* name) {
    pyramid_source s{};
    s.struct_size = sizeof s;
    s.kind = PYRAMID_SOURCE_MEMORY;
    s.name = name;
    s.data = bytes.data();
    s.size = bytes.size();
    return s;
}

pyramid_source ioSource(MemoryIo& io, const char* name) {
    pyramid_source s{};
    s.struct_size = sizeof s;
    s.kind = PYRAMID_SOURCE_IO;
    s.name = name;
    s.io.read = &MemoryIo::read;
    s.io.release = &MemoryIo::release;
    s.io.user = &io;
    s.io.size = io.data.size();
    return s;
}

namespace {

// Residual tile whose every sample is `base + i + 3 j`.
std::vector<int16_t> ramp(int size, int base) {
    std::vector<int16_t> r(static_cast<size_t>(size) * size);
    for (int j = 0; j < size; ++j) {
        for (int i = 0; i < size; ++i) {
            r[static_cast<size_t>(i + j * size)] = static_cast<int16_t>(base + i + 3 * j);
        }
    }
    return r;
}

} // namespace

void writeResidualSet(const TempDir& dir) {
    auto write = [&](const std::string& name, int rootLevel, int rootTx, int rootTy, int maxLevel, float scale,
                     int base) {
        ResidualHeader h;
        h.minLevel = rootLevel == 0 ? 1 : 0;
        h.maxLevel = maxLevel;
        h.tileSize = 4;
        h.rootLevel = rootLevel;
        h.rootTx = rootTx;
        h.rootTy = rootTy;
        h.scale = scale;
        ResidualFileWriter w(dir.file(name), h);
        for (int l = 0; l <= maxLevel; ++l) {
            const int side = l < h.minLevel ? 1 : 1 << (l - h.minLevel);
            for (int t = 0; t < side * side; ++t) {
                w.writeTile(l, t % side, t / side, ramp(h.tileSamples(l), base + 10 * l + t));
            }
        }
        w.commit();
    };
    write("main.dat", 0, 0, 0, 2, 0.5f, 100);
    write("a.dat", 2, 1, 1, 1, 0.25f, 200);
    write("b.dat", 3, 2, 2, 1, 0.125f, 300);
}

} // namespace pyramid::test
