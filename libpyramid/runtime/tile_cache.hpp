// A thread-safe least-recently-used cache of immutable tiles, bounded in entries.
// Values are shared_ptr<const T>: a tile evicted while a caller still holds it stays alive
// for that caller, so eviction never invalidates what was handed out.
#pragma once
#include <cstddef>
#include <cstdint>
#include <list>
#include <memory>
#include <mutex>
#include <unordered_map>

namespace pyramid {

// Quadtree tile coordinates as one key.
struct TileKey {
    int level = 0, tx = 0, ty = 0;
    bool operator==(const TileKey&) const = default;
};

struct TileKeyHash {
    size_t operator()(const TileKey& k) const {
        uint64_t h = static_cast<uint64_t>(static_cast<uint32_t>(k.level));
        h = h * 0x9E3779B97F4A7C15ull ^ static_cast<uint32_t>(k.tx);
        h = h * 0x9E3779B97F4A7C15ull ^ static_cast<uint32_t>(k.ty);
        return static_cast<size_t>(h ^ (h >> 29));
    }
};

template <class T>
class TileCache {
public:
    explicit TileCache(size_t capacity) : capacity_(capacity < 1 ? 1 : capacity) {}

    size_t capacity() const { return capacity_; }

    size_t size() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return map_.size();
    }

    // The cached tile, marked most recently used, or null.
    std::shared_ptr<const T> find(const TileKey& key) {
        std::lock_guard<std::mutex> lock(mutex_);
        auto it = map_.find(key);
        if (it == map_.end()) {
            return nullptr;
        }
        order_.splice(order_.begin(), order_, it->second);
        return it->second->second;
    }

    // Inserts (or keeps the tile another thread inserted first, which is returned), evicting
    // the least recently used tiles beyond capacity.
    std::shared_ptr<const T> insert(const TileKey& key, std::shared_ptr<const T> value) {
        std::lock_guard<std::mutex> lock(mutex_);
        auto it = map_.find(key);
        if (it != map_.end()) {
            order_.splice(order_.begin(), order_, it->second);
            return it->second->second;
        }
        order_.emplace_front(key, std::move(value));
        map_.emplace(key, order_.begin());
        while (map_.size() > capacity_) {
            map_.erase(order_.back().first);
            order_.pop_back();
        }
        return order_.front().second;
    }

private:
    using Entry = std::pair<TileKey, std::shared_ptr<const T>>;
    size_t capacity_;
    mutable std::mutex mutex_;
    std::list<Entry> order_;
    std::unordered_map<TileKey, typename std::list<Entry>::iterator, TileKeyHash> map_;
};

} // namespace pyramid
