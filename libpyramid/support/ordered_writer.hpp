// Writing work items in their order while later ones are still being computed: the one
// mechanism of the encoders (residual subtrees, ortho groups) for a file whose tile order must
// not depend on the thread count.
//
// Items 0, 1, 2, ... are delivered by any threads in any order and written strictly in index
// order. The producer that delivers the item written next writes it, then every item after it
// that is already delivered, while the other producers go on computing; one producer writes at
// a time. There is no thread of the writer's own: on two cores it was a third runnable thread,
// preempted now and then while it held the heap's lock (the programs run one heap,
// cli_program.cpp) and every producer waited for it; writing on the producers took the
// context switches of an ortho run from about 460 to 180. At most `window` items are admitted
// but not yet written: admit(m) waits for that, which bounds the memory the delivered items
// hold. A failure stops the run: a producer that fails calls stopAt(its index); a write that
// throws stops the writing; admit() then answers false for every item at or beyond the end,
// and finish() rethrows the write's error.
//
// A thread is woken only when what it waits for may have come: a producer waiting in admit()
// when the writing has moved on, finish() when the last item is written. Items may be small (a
// blank subtree of a face the map does not reach): waking every thread at every delivery and
// every write made the futex calls most of such a run's time.
#pragma once
#include <algorithm>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <limits>
#include <map>
#include <mutex>
#include <utility>

namespace pyramid {

template <typename Item>
class OrderedWriter {
public:
    // `write(index, item)` is called once per item, in index order, by one producer at a time.
    OrderedWriter(int64_t window, std::function<void(int64_t, Item&)> write)
        : window_(window), write_(std::move(write)) {}

    // Stops the run (items not yet written are dropped) and waits for a write under way.
    ~OrderedWriter() {
        std::unique_lock<std::mutex> lock(mutex_);
        end_ = std::min(end_, next_);
        ready_.clear();
        idle_.wait(lock, [&] { return !writing_; });
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

    // Hands item m over to be written in its turn: written here, with the delivered items after
    // it, when it is the next one and no other producer is writing.
    void deliver(int64_t m, Item item) {
        std::unique_lock<std::mutex> lock(mutex_);
        if (m < end_) {
            ready_.emplace(m, std::move(item));
            if (m == next_ && !writing_) {
                writeReady(lock);
            }
        }
    }

    // No item from `end` on is written (a failed producer, an overflow found by a write). May be
    // called from the write callback.
    void stopAt(int64_t end) {
        std::lock_guard<std::mutex> lock(mutex_);
        if (end < end_) {
            end_ = end;
            moved_.notify_all();
            idle_.notify_all();
        }
    }

    // Ends the run after item count - 1 and waits until every item before the end is written.
    // Rethrows a write's error.
    void finish(int64_t count) {
        stopAt(count);
        std::unique_lock<std::mutex> lock(mutex_);
        idle_.wait(lock, [&] { return !writing_ && next_ >= end_; });
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
    // Writes item next_ and the delivered items after it, the lock released during each write.
    void writeReady(std::unique_lock<std::mutex>& lock) {
        writing_ = true;
        while (next_ < end_ && ready_.count(next_) != 0) {
            auto node = ready_.extract(next_);
            lock.unlock();
            try {
                write_(node.key(), node.mapped());
            } catch (...) {
                node = {}; // the item's memory is released outside the lock
                lock.lock();
                error_ = std::current_exception();
                end_ = next_;
                ready_.clear();
                moved_.notify_all(); // admit() answers false from here on
                break;
            }
            node = {};
            lock.lock();
            ++next_;
            if (admitting_ > 0) {
                moved_.notify_all();
            }
        }
        writing_ = false;
        idle_.notify_all();
    }

    const int64_t window_;
    std::function<void(int64_t, Item&)> write_;
    mutable std::mutex mutex_;
    std::condition_variable moved_; // the producers': next_ or the end has moved
    std::condition_variable idle_;  // finish()'s: a producer has stopped writing, or the end has moved
    int admitting_ = 0;             // producers waiting in admit()
    bool writing_ = false;          // a producer is writing
    std::map<int64_t, Item> ready_;
    int64_t next_ = 0;                                  // the oldest unwritten item
    int64_t end_ = std::numeric_limits<int64_t>::max(); // items from here on are not written
    std::exception_ptr error_;
};

} // namespace pyramid
