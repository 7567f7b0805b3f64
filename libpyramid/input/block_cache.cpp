#include "libpyramid/input/block_cache.hpp"

#include <algorithm>

#include "formats/error.hpp"

namespace pyramid {

BlockCache::BlockCache(size_t budgetBytes, size_t blockBytes)
    : blockBytes_(blockBytes), capacity_(std::max<size_t>(1, budgetBytes / std::max<size_t>(1, blockBytes))) {}

size_t BlockCache::buffers() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return buffers_;
}

// A buffer for a new decode: a free one, a new one within the capacity, or the least recently
// used decoded block that no reader holds; a new one beyond the capacity when every buffer is
// held.
std::shared_ptr<BlockCache::Block> BlockCache::takeBuffer(std::unique_lock<std::mutex>&) {
    if (!free_.empty()) {
        std::shared_ptr<Block> b = std::move(free_.back());
        free_.pop_back();
        return b;
    }
    if (buffers_ < capacity_) {
        ++buffers_;
        return std::make_shared<Block>(blockBytes_);
    }
    for (auto it = recent_.end(); it != recent_.begin();) {
        --it;
        auto found = entries_.find(*it);
        // Held only by the cache (use_count 1, read under the lock that every copy is made
        // under): no reader can be using it.
        if (found->second.block.use_count() == 1) {
            std::shared_ptr<Block> b = std::move(found->second.block);
            entries_.erase(found);
            recent_.erase(it);
            return b;
        }
    }
    ++buffers_;
    return std::make_shared<Block>(blockBytes_);
}

std::shared_ptr<const BlockCache::Block> BlockCache::get(uint32_t index, const std::function<void(Block&)>& decode) {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
        auto it = entries_.find(index);
        if (it == entries_.end()) {
            break;
        }
        if (it->second.block) {
            recent_.splice(recent_.begin(), recent_, it->second.recent);
            return it->second.block;
        }
        decoded_.wait(lock); // another thread decodes it; then look again
    }
    entries_.emplace(index, Entry{});
    std::shared_ptr<Block> buffer = takeBuffer(lock);
    lock.unlock();
    try {
        buffer->resize(blockBytes_);
        decode(*buffer);
    } catch (...) {
        lock.lock();
        entries_.erase(index);
        free_.push_back(std::move(buffer));
        decoded_.notify_all();
        throw;
    }
    lock.lock();
    recent_.push_front(index);
    Entry& e = entries_.at(index);
    e.block = buffer;
    e.recent = recent_.begin();
    decoded_.notify_all();
    return buffer;
}

void failBlocksBeyondCache(const std::string& path, const std::string& blocks, size_t blockBytes, int cacheMegabytes) {
    const size_t megabytes = (blockBytes + (size_t{1} << 20) - 1) >> 20;
    failOption("cacheMegabytes", path + ": " + blocks + " (" + std::to_string(megabytes) +
                                     " MB decoded) need a cache of at least " + std::to_string(4 * megabytes) +
                                     " MB, not " + std::to_string(cacheMegabytes));
}

} // namespace pyramid
