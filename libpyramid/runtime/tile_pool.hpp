// Tiles whose last user let go, kept to be filled again. A producer makes a tile for every one
// its cache evicts, and a new producer (a file opened again, a verification pass) makes all of
// its tiles anew; a fresh tile's buffers would each be allocated, zero-filled and faulted in page
// by page, which costs more than the arithmetic that fills them. One pool per kind of tile
// serves every producer of the process. Thread-safe; bounded in bytes. A tile handed out may
// outlive its pool (it is then simply freed).
#pragma once
#include <cstddef>
#include <functional>
#include <memory>
#include <mutex>
#include <vector>

namespace pyramid {

template <class T>
class TilePool : public std::enable_shared_from_this<TilePool<T>> {
public:
    // `bytes` gives a tile's heap bytes; the pool keeps tiles of at most `maxBytes` in all.
    static std::shared_ptr<TilePool> make(size_t maxBytes, std::function<size_t(const T&)> bytes) {
        return std::shared_ptr<TilePool>(new TilePool(maxBytes, std::move(bytes)));
    }

    // A kept tile (its buffers as the last user left them: the caller overwrites every value it
    // uses), or a new one. When its last shared_ptr goes, it comes back here if there is room.
    std::shared_ptr<T> acquire() {
        std::unique_ptr<T> tile;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            if (!free_.empty()) {
                tile = std::move(free_.back().tile);
                kept_ -= free_.back().bytes;
                free_.pop_back();
            }
        }
        if (!tile) {
            tile = std::make_unique<T>();
        }
        std::weak_ptr<TilePool> pool = this->weak_from_this();
        return std::shared_ptr<T>(tile.release(), [pool](T* raw) {
            std::unique_ptr<T> owned(raw);
            if (const std::shared_ptr<TilePool> alive = pool.lock()) {
                alive->keep(std::move(owned));
            }
        });
    }

private:
    TilePool(size_t maxBytes, std::function<size_t(const T&)> bytes) : maxBytes_(maxBytes), bytes_(std::move(bytes)) {}

    void keep(std::unique_ptr<T> tile) {
        const size_t bytes = bytes_(*tile);
        std::lock_guard<std::mutex> lock(mutex_);
        if (kept_ + bytes <= maxBytes_) {
            kept_ += bytes;
            free_.push_back({std::move(tile), bytes});
        }
    }

    struct Kept {
        std::unique_ptr<T> tile;
        size_t bytes = 0;
    };
    size_t maxBytes_;
    std::function<size_t(const T&)> bytes_;
    std::mutex mutex_;
    size_t kept_ = 0;
    std::vector<Kept> free_;
};

} // namespace pyramid
