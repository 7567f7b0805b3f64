// The ordered writer of the encoders: items delivered in any order by many threads are written
// in index order, by the producer whose item is written next, at most `window` items are
// admitted ahead of the oldest unwritten one, and a failure (a producer's, or a write's) stops
// the run without hanging.
#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <thread>
#include <vector>

#include "libpyramid/support/ordered_writer.hpp"
#include "libpyramid/support/parallel.hpp"

namespace pyramid {
namespace {

TEST(OrderedWriter, WritesInIndexOrderWithinTheWindow) {
    constexpr int64_t kCount = 500;
    constexpr int64_t kWindow = 3;
    std::vector<int64_t> written;
    std::atomic<int64_t> worst{0};
    OrderedWriter<int64_t>* self = nullptr;
    OrderedWriter<int64_t> writer(kWindow, [&](int64_t m, int64_t& item) {
        EXPECT_EQ(item, m * 10);
        written.push_back(m);
    });
    self = &writer;
    parallelFor(kCount, 4, [&](int64_t m) {
        ASSERT_TRUE(self->admit(m));
        // Items admitted but not written: never more than the window.
        const int64_t ahead = m - self->next();
        int64_t seen = worst.load();
        while (ahead > seen && !worst.compare_exchange_weak(seen, ahead)) {
        }
        if (m % 7 == 0) {
            std::this_thread::yield(); // out of order deliveries
        }
        self->deliver(m, m * 10);
    });
    writer.finish(kCount);
    ASSERT_EQ(written.size(), static_cast<size_t>(kCount));
    for (int64_t m = 0; m < kCount; ++m) {
        EXPECT_EQ(written[static_cast<size_t>(m)], m);
    }
    EXPECT_LT(worst.load(), kWindow);
}

TEST(OrderedWriter, TheProducerOfTheNextItemWritesItAndTheDeliveredOnesAfterIt) {
    std::vector<int64_t> written;
    std::vector<std::thread::id> writers;
    OrderedWriter<int> writer(4, [&](int64_t m, int&) {
        written.push_back(m);
        writers.push_back(std::this_thread::get_id());
    });
    writer.deliver(2, 0);
    writer.deliver(1, 0);
    EXPECT_TRUE(written.empty()); // item 0 is not there yet
    writer.deliver(0, 0);
    EXPECT_EQ(written, (std::vector<int64_t>{0, 1, 2})); // before deliver() returned
    EXPECT_EQ(writer.next(), 3);
    std::thread other([&] { writer.deliver(3, 0); });
    other.join();
    writer.finish(4);
    ASSERT_EQ(writers.size(), 4u);
    EXPECT_EQ(writers[0], std::this_thread::get_id());
    EXPECT_NE(writers[3], std::this_thread::get_id()); // the other thread's item, written there
}

TEST(OrderedWriter, AProducerFailureStopsTheRunAtItsItem) {
    std::vector<int64_t> written;
    OrderedWriter<int> writer(2, [&](int64_t m, int&) { written.push_back(m); });
    EXPECT_THROW(parallelFor(100, 3, [&](int64_t m) {
                     if (!writer.admit(m)) {
                         return;
                     }
                     if (m == 10) {
                         writer.stopAt(m);
                         throw std::runtime_error("item 10");
                     }
                     writer.deliver(m, 0);
                 }),
                 std::runtime_error);
    writer.finish(100);
    ASSERT_EQ(written.size(), 10u); // items 0..9, nothing after the failed one
    EXPECT_EQ(written.back(), 9);
}

TEST(OrderedWriter, AWriteFailureIsRethrownAndReleasesTheProducers) {
    OrderedWriter<int> writer(2, [&](int64_t m, int&) {
        if (m == 3) {
            throw std::runtime_error("disk full");
        }
    });
    parallelFor(50, 2, [&](int64_t m) {
        if (writer.admit(m)) {
            writer.deliver(m, 0);
        }
    });
    EXPECT_THROW(writer.finish(50), std::runtime_error);
    EXPECT_EQ(writer.next(), 3);
}

TEST(OrderedWriter, TheWriteCallbackMayEndTheRun) {
    std::vector<int64_t> written;
    OrderedWriter<int>* self = nullptr;
    OrderedWriter<int> writer(4, [&](int64_t m, int&) {
        written.push_back(m);
        if (m == 5) {
            self->stopAt(8); // as an overflow ends a residual pyramid at the end of its group
        }
    });
    self = &writer;
    parallelFor(40, 2, [&](int64_t m) {
        if (writer.admit(m)) {
            writer.deliver(m, 0);
        }
    });
    writer.finish(40);
    EXPECT_EQ(written, (std::vector<int64_t>{0, 1, 2, 3, 4, 5, 6, 7}));
}

} // namespace
} // namespace pyramid
