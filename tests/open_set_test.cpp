// The mosaics' set of open files (support/open_set.hpp): a thing wanted by several threads at
// once is opened once (the others wait for it), a failed opening is retried by the next call,
// and at most `limit` things stay open, the least recently used closed first.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

#include "libpyramid/support/open_set.hpp"

namespace pyramid {
namespace {

TEST(OpenSet, ThreadsWantingOneThingOpenItOnce) {
    OpenSet<int> set(4, 4);
    std::atomic<int> openings{0};
    std::vector<std::shared_ptr<const int>> got(8);
    std::vector<std::thread> threads;
    for (size_t t = 0; t < got.size(); ++t) {
        threads.emplace_back([&, t] {
            got[t] = set.get(2, [&] {
                ++openings;
                std::this_thread::sleep_for(std::chrono::milliseconds(50)); // the others arrive meanwhile
                return std::make_shared<const int>(42);
            });
        });
    }
    for (std::thread& t : threads) {
        t.join();
    }
    EXPECT_EQ(openings.load(), 1);
    for (const auto& g : got) {
        EXPECT_EQ(g, got[0]);
    }
}

TEST(OpenSet, AFailedOpeningIsTriedAgain) {
    OpenSet<int> set(2, 2);
    int openings = 0;
    EXPECT_THROW(set.get(0, [&]() -> std::shared_ptr<const int> {
        ++openings;
        throw std::runtime_error("cannot open");
    }),
                 std::runtime_error);
    EXPECT_EQ(*set.get(0, [&] {
        ++openings;
        return std::make_shared<const int>(7);
    }),
              7);
    EXPECT_EQ(openings, 2);
}

TEST(OpenSet, TheLeastRecentlyUsedIsClosedFirst) {
    OpenSet<int> set(3, 2);
    std::vector<int> openings(3, 0);
    const auto get = [&](size_t k) {
        return *set.get(k, [&] {
            ++openings[k];
            return std::make_shared<const int>(static_cast<int>(k));
        });
    };
    get(0);
    get(1);
    get(0); // 1 is now the least recently used
    get(2); // closes 1
    get(0);
    EXPECT_EQ(openings, (std::vector<int>{1, 1, 1}));
    get(1);
    EXPECT_EQ(openings, (std::vector<int>{1, 2, 1}));
}

} // namespace
} // namespace pyramid
