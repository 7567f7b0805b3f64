// Decoded blocks of an input (TIFF strips or tiles), shared by every reading thread, in
// bounded memory.
//
// * Bounded: the cache owns at most max(1, budget / blockBytes) block buffers. A block is
//   decoded into a buffer recycled from an evicted one (least recently used first), so the
//   buffers are allocated once and reused: the memory stays the budget, with no growth from
//   the allocator's free lists. Blocks a reader still holds are never recycled; when every
//   buffer is held, a new one is allocated, so the excess is at most one block per reading
//   thread.
// * Shared: a block being decoded by one thread is waited for by the others that need it,
//   never decoded twice at once.
#pragma once
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>
#include <vector>

namespace pyramid {

class BlockCache {
public:
    using Block = std::vector<uint8_t>; // a block's decoded bytes, laid out as its reader wants

    BlockCache(size_t budgetBytes, size_t blockBytes);

    // Block `index`: from the cache, from a decoding in progress (waits for it), or decoded now
    // by `decode`, which fills the buffer it is given (sized blockBytes). A decode that throws
    // leaves no entry (the next request decodes again) and its error goes to this caller.
    // Thread-safe.
    std::shared_ptr<const Block> get(uint32_t index, const std::function<void(Block&)>& decode);

    // Buffers owned (cached, being decoded, held by readers or free): for tests.
    size_t buffers() const;

private:
    struct Entry {
        std::shared_ptr<Block> block; // null while being decoded
        std::list<uint32_t>::iterator recent; // in recent_ once decoded
    };
    std::shared_ptr<Block> takeBuffer(std::unique_lock<std::mutex>& lock);

    const size_t blockBytes_;
    const size_t capacity_; // buffers within the budget
    mutable std::mutex mutex_;
    std::condition_variable decoded_;
    std::unordered_map<uint32_t, Entry> entries_;
    std::list<uint32_t> recent_;              // decoded blocks, most recently used first
    std::vector<std::shared_ptr<Block>> free_; // recycled buffers
    size_t buffers_ = 0;
};

// Refuses blocks a cache of `cacheMegabytes` cannot hold four of (a read across block boundaries
// needs them): throws OptionError("cacheMegabytes", "PATH: BLOCKS (N MB decoded) need a cache of
// at least 4N MB, not M"), `blocks` saying which ("tiles of 1024 x 1024 samples").
[[noreturn]] void failBlocksBeyondCache(const std::string& path, const std::string& blocks, size_t blockBytes,
                                        int cacheMegabytes);

} // namespace pyramid
