// Things opened by index (the files of a mosaic), at most `limit` kept open at once: the least
// recently used is closed first, once its last holder lets it go. Opening runs outside the lock,
// so threads open different things at once; two that open the same one keep the first.
#pragma once
#include <cstddef>
#include <list>
#include <memory>
#include <mutex>
#include <vector>

namespace pyramid {

template <typename T>
class OpenSet {
public:
    OpenSet(size_t count, size_t limit) : open_(count), limit_(limit) {}

    // Thing k: the one kept open, or `open()`'s. Thread-safe.
    template <typename Open>
    std::shared_ptr<const T> get(size_t k, Open open) const {
        std::unique_lock<std::mutex> lock(mutex_);
        if (open_[k]) {
            recent_.remove(k);
            recent_.push_front(k);
            return open_[k];
        }
        lock.unlock();
        std::shared_ptr<const T> opened = open();
        lock.lock();
        if (open_[k]) {
            return open_[k]; // opened by another thread meanwhile
        }
        open_[k] = opened;
        recent_.push_front(k);
        while (recent_.size() > limit_) {
            open_[recent_.back()].reset();
            recent_.pop_back();
        }
        return opened;
    }

private:
    mutable std::mutex mutex_;
    mutable std::vector<std::shared_ptr<const T>> open_; // by index; null when closed
    mutable std::list<size_t> recent_;                   // open ones, most recently used first
    size_t limit_;
};

} // namespace pyramid
