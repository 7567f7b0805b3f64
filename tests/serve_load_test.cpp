// `pyramid serve` under load: 10,000 tile requests from 8 clients at once on this machine, every
// answer checked against the bytes one client fetched alone (which serve_tiles_test checks
// against the C API). The producers are shared by the server's threads.
#include <gtest/gtest.h>
#include <httplib.h>

#include <atomic>
#include <chrono>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "support/paths.hpp"
#include "support/served_program.hpp"

namespace {

TEST(ServeLoad, TenThousandRequestsFromEightClientsAreAllAnsweredRight) {
    pyramid::test::ServedProgram served({pyramid::test::dataPath("proland/DEM.dat"), "--port", "0", "-q"});
    ASSERT_TRUE(served.ok()) << served.error();
    // Every tile of the plane: elevation levels 0..2 (21 tiles) as .f32 and .png, ortho levels
    // 0..1 (5 tiles), and a range of a file.
    std::vector<std::string> urls;
    for (int level = 0; level <= 2; ++level) {
        for (int ty = 0; ty < (1 << level); ++ty) {
            for (int tx = 0; tx < (1 << level); ++tx) {
                const std::string tile = std::to_string(level) + "/" + std::to_string(tx) + "/" + std::to_string(ty);
                urls.push_back("/tiles/0/elevation/" + tile + ".f32");
                urls.push_back("/tiles/0/elevation/" + tile + ".png");
                if (level <= 1) {
                    urls.push_back("/tiles/0/ortho/" + tile + ".png");
                }
            }
        }
    }
    std::map<std::string, std::string> expected;
    {
        httplib::Client client(served.host(), served.port());
        for (const std::string& url : urls) {
            const auto answer = client.Get(url);
            ASSERT_TRUE(answer) << url;
            ASSERT_EQ(answer->status, 200) << url;
            expected[url] = answer->body;
        }
    }
    constexpr int kClients = 8, kRequests = 10000;
    std::atomic<int> wrong{0}, failed{0}, done{0};
    const auto start = std::chrono::steady_clock::now();
    std::vector<std::thread> clients;
    for (int c = 0; c < kClients; ++c) {
        clients.emplace_back([&, c] {
            httplib::Client client(served.host(), served.port());
            client.set_keep_alive(true);
            // Each client its own order through the tiles: the same tiles asked at once by several.
            for (int k = c; k < kRequests; k += kClients) {
                const std::string& url = urls[static_cast<size_t>((k * 7 + c * 13) % static_cast<int>(urls.size()))];
                const auto answer = client.Get(url);
                if (!answer || answer->status != 200) {
                    ++failed;
                } else if (answer->body != expected.at(url)) {
                    ++wrong;
                }
                ++done;
            }
        });
    }
    for (std::thread& t : clients) {
        t.join();
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_EQ(done.load(), kRequests);
    EXPECT_EQ(failed.load(), 0);
    EXPECT_EQ(wrong.load(), 0);
    std::printf("%d requests from %d clients in %.2f s (%.0f per second)\n", kRequests, kClients, seconds,
                kRequests / seconds);
}

} // namespace
