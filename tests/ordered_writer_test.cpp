// The ordered writer of the encoders: items delivered in any order by many threads are written
// in index order, at most `window` items are admitted ahead of the oldest unwritten one, and a
// failure (a producer's, or the writer's) stops the run without hanging.
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
