// Things opened by index (the files of a mosaic), at most `limit` kept open at once: the least
// recently used is closed first, once its last holder lets it go. Opening runs outside the lock,
// so threads open different things at once; a thread that wants a thing another thread is
// opening waits for it rather than opening it again (a PNG, JPEG, DTED or XYZ member is decoded
// whole when it opens: a second opening would decode it twice). When an opening fails, a waiting
// thread opens the thing itself (and meets the same error).
#pragma once
#include <condition_variable>
#include <cstddef>
#include <list>
#include <memory>
#include <mutex>
#include <vector>

namespace pyramid {

template <typename T>
class OpenSet {
public:
    OpenSet(size_t count, size_t limit) : open_(count), opening_(count, 0), limit_(limit) {}

    // Thing k: the one kept open, or `open()`'s. Thread-safe.
    template <typename Open>
    std::shared_ptr<const T> get(size_t k, Open open) const {
        std::unique_lock<std::mutex> lock(mutex_);
        opened_.wait(lock, [&] { return open_[k] || !opening_[k]; });
        if (open_[k]) {
            recent_.remove(k);
            recent_.push_front(k);
            return open_[k];
        }
        opening_[k] = 1;
        lock.unlock();
        std::shared_ptr<const T> opened;
        try {
            opened = open();
        } catch (...) {
            lock.lock();
            opening_[k] = 0;
            opened_.notify_all();
            throw;
        }
        lock.lock();
        opening_[k] = 0;
        open_[k] = opened;
        recent_.push_front(k);
        while (recent_.size() > limit_) {
            open_[recent_.back()].reset();
            recent_.pop_back();
        }
        opened_.notify_all();
        return opened;
    }

private:
    mutable std::mutex mutex_;
    mutable std::condition_variable opened_;             // an opening ended
    mutable std::vector<std::shared_ptr<const T>> open_; // by index; null when closed
    mutable std::vector<char> opening_;                  // by index: a thread opens it now
    mutable std::list<size_t> recent_;                   // open ones, most recently used first
    size_t limit_;
};

} // namespace pyramid
