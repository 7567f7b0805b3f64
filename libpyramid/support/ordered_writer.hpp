// Writing work items in their order while later ones are still being computed: the one
// mechanism of the encoders (residual subtrees, ortho groups) for a file whose tile order must
// not depend on the thread count.
//
// Items 0, 1, 2, ... are delivered by any threads in any order and written strictly in index
// order by a thread of the writer's own, so that no producing thread stops to write. At most
// `window` items are admitted but not yet written: admit(m) waits for that, which bounds the
// memory the delivered items hold. A failure stops the run: a producer that fails calls
// stopAt(its index); a write that throws stops the writer; admit() then answers false for every
// item at or beyond the end, and finish() rethrows the writer's error.
//
// A thread is woken only when what it waits for may have come: the writer when the item it
// writes next is delivered (or the run ends), a producer waiting in admit() when the writer has
// moved on. Items may be small (a blank subtree of a face the map does not reach): waking every
// thread at every delivery and every write made the futex calls most of such a run's time.
#pragma once
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <limits>
#include <map>
#include <mutex>
#include <thread>
#include <utility>

namespace pyramid {

template <typename Item>
class OrderedWriter {
public:
    // `write(index, item)` is called on the writer's thread, once per item, in index order.
    OrderedWriter(int64_t window, std::function<void(int64_t, Item&)> write)
        : window_(window), write_(std::move(write)), thread_([this] { run(); }) {}

    // Stops the writer (items not yet written are dropped) and waits for it.
    ~OrderedWriter() {
        stopAt(next());
        join();
    }

    OrderedWriter(const OrderedWriter&) = delete;
    OrderedWriter& operator=(const OrderedWriter&) = delete;

    // Waits until item m is within the window of the oldest unwritten item. False when the run
    // has stopped before m: the item must not be computed.
    bool admit(int64_t m) {
        std::unique_lock<std::mutex> lock(mutex_);
        const auto admitted = [&] { return m < next_ + window_ || m >= end_; };
        if (!admitted()) {
            ++admitting_;
            moved_.wait(lock, admitted);
            --admitting_;
        }
        return m < end_;
    }

    // Hands item m over to be written in its turn.
    void deliver(int64_t m, Item item) {
        std::lock_guard<std::mutex> lock(mutex_);
        if (m < end_) {
            ready_.emplace(m, std::move(item));
            if (m == next_) {
                delivered_.notify_one(); // the writer waits for no other item
            }
        }
    }

    // No item from `end` on is written (a failed producer, an overflow found by the writer).
    // May be called from the write callback.
    void stopAt(int64_t end) {
        std::lock_guard<std::mutex> lock(mutex_);
        if (end < end_) {
            end_ = end;
            delivered_.notify_one();
            moved_.notify_all();
        }
    }

    // Ends the run after item count - 1 and waits until every item before the end is written.
    // Rethrows the writer's error.
    void finish(int64_t count) {
        stopAt(count);
        join();
        if (error_) {
            std::rethrow_exception(error_);
        }
    }

    // The items written so far.
    int64_t next() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return next_;
    }

private:
    void run() {
        std::unique_lock<std::mutex> lock(mutex_);
        for (;;) {
            delivered_.wait(lock, [&] { return next_ >= end_ || ready_.count(next_) != 0; });
            if (next_ >= end_) {
                return;
            }
            auto node = ready_.extract(next_);
            lock.unlock();
            try {
                write_(node.key(), node.mapped());
            } catch (...) {
                lock.lock();
                error_ = std::current_exception();
                end_ = next_;
                ready_.clear();
                moved_.notify_all();
                return;
            }
            lock.lock();
            ++next_;
            if (admitting_ > 0) {
                moved_.notify_all();
            }
        }
    }

    void join() {
        if (thread_.joinable()) {
            thread_.join();
        }
    }

    const int64_t window_;
    std::function<void(int64_t, Item&)> write_;
    mutable std::mutex mutex_;
    std::condition_variable delivered_; // the writer's: item next_ has come, or the end
    std::condition_variable moved_;     // the producers': next_ or the end has moved
    int admitting_ = 0;                 // producers waiting in admit()
    std::map<int64_t, Item> ready_;
    int64_t next_ = 0;                                    // the oldest unwritten item
    int64_t end_ = std::numeric_limits<int64_t>::max();   // items from here on are not written
    std::exception_ptr error_;
    std::thread thread_; // last: started once everything above is set up
};

} // namespace pyramid
