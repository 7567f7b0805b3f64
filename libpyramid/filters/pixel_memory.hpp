// Memory for pixel buffers: the images, windows and decoded rasters the encoders fill whole.
//
// Buffers are not cleared first (DefaultInitAllocator), and buffers of 2 MB and more start on a
// 2 MB boundary and ask the kernel for transparent huge pages (madvise(MADV_HUGEPAGE); Linux's
// default THP mode, "madvise", grants them only to such ranges). A buffer's first touch then
// costs one page fault per 2 MB instead of one per 4 KB: the ortho run on a 2700 x 1350 image
// takes about 2,500 faults instead of 6,500 (bench/ortho_bench.md). Where the kernel has no huge
// page to give, or THP is off, the hint is ignored and the memory is the same as before. The
// bytes a buffer holds never depend on it. Only whole 2 MB pages inside a buffer are huge: the
// resident memory is what the buffer touches, as with small pages, give or take its last 2 MB.
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <utility>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace pyramid {

inline constexpr size_t kHugePageBytes = size_t{1} << 21;

// `bytes` of uninitialised memory; give it back with releasePixelMemory(p, bytes).
inline void* allocatePixelMemory(size_t bytes) {
    if (bytes < kHugePageBytes) {
        return ::operator new(bytes);
    }
    void* p = ::operator new(bytes, std::align_val_t{kHugePageBytes});
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    // A hint: its failure (THP not built in, or the range not mapped as the kernel expects) leaves
    // small pages, the same memory.
    (void)::madvise(p, bytes, MADV_HUGEPAGE);
#endif
    return p;
}

inline void releasePixelMemory(void* p, size_t bytes) noexcept {
    if (bytes < kHugePageBytes) {
        ::operator delete(p);
    } else {
        ::operator delete(p, std::align_val_t{kHugePageBytes});
    }
}

// An allocator whose containers leave new elements uninitialised (default-initialised) unless a
// value is given, for buffers about to be overwritten whole, and whose large blocks are
// pixel memory (above).
template <class T>
struct DefaultInitAllocator {
    using value_type = T;
    DefaultInitAllocator() = default;
    template <class U>
    DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept {}
    T* allocate(size_t n) {
        if (n > static_cast<size_t>(-1) / sizeof(T)) {
            throw std::bad_array_new_length();
        }
        return static_cast<T*>(allocatePixelMemory(n * sizeof(T)));
    }
    void deallocate(T* p, size_t n) noexcept { releasePixelMemory(p, n * sizeof(T)); }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        if constexpr (sizeof...(Args) == 0) {
            ::new (static_cast<void*>(p)) U;
        } else {
            ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
        }
    }
    template <class U>
    bool operator==(const DefaultInitAllocator<U>&) const noexcept {
        return true;
    }
};

// Pixel memory owned by one pointer, for a buffer that never changes size.
struct PixelMemoryDeleter {
    size_t bytes = 0;
    void operator()(uint8_t* p) const noexcept { releasePixelMemory(p, bytes); }
};
using PixelMemory = std::unique_ptr<uint8_t[], PixelMemoryDeleter>;

inline PixelMemory makePixelMemory(size_t bytes) {
    return PixelMemory(static_cast<uint8_t*>(allocatePixelMemory(bytes)), PixelMemoryDeleter{bytes});
}

} // namespace pyramid
