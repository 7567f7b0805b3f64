// The pyramid file readers open paths: the fuzz input is written to an in-memory file
// (memfd, reused across runs) and its /proc/self/fd path handed to them.
#pragma once
#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <string>

namespace pyramid::fuzz {

inline std::string inputFile(const uint8_t* data, size_t size) {
    static const int fd = memfd_create("pyramid-fuzz-input", MFD_CLOEXEC);
    if (fd < 0 || ftruncate(fd, 0) != 0) {
        std::abort();
    }
    for (size_t done = 0; done < size;) {
        const ssize_t n = pwrite(fd, data + done, size - done, static_cast<off_t>(done));
        if (n <= 0) {
            std::abort();
        }
        done += static_cast<size_t>(n);
    }
    return "/proc/self/fd/" + std::to_string(fd);
}

} // namespace pyramid::fuzz
