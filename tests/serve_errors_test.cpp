// `pyramid serve`'s refusals and its files: 404 for unknown paths, faces, kinds and formats, 400
// for bad tile coordinates, JSON error bodies; /files/ with HEAD and Range (206, 416) and no way
// out of the served directory (.., encoded .., absolute paths, symbolic links); the viewer's
// files; the request log; the default address (this machine only).
#include <gtest/gtest.h>
#include <httplib.h>

#include <arpa/inet.h>
#include <ifaddrs.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "support/paths.hpp"
#include "support/served_program.hpp"

namespace {

using pyramid::test::ServedProgram;

class ServeErrors : public ::testing::Test {
protected:
    void SetUp() override {
        build = dir.file("build");
        std::filesystem::create_directories(build);
        std::filesystem::copy_file(pyramid::test::dataPath("proland/DEM.dat"), build + "/DEM.dat");
        dem = pyramid::test::readFile(build + "/DEM.dat");
    }
    pyramid::test::TempDir dir;
    std::string build, dem;
};

void expectError(httplib::Client& client, const std::string& path, int status) {
    const auto answer = client.Get(path);
    ASSERT_TRUE(answer) << path;
    EXPECT_EQ(answer->status, status) << path;
    EXPECT_EQ(answer->get_header_value("Content-Type"), "application/json") << path;
    const nlohmann::json j = nlohmann::json::parse(answer->body, nullptr, false);
    ASSERT_TRUE(j.is_object()) << path << ": " << answer->body;
    EXPECT_TRUE(j.at("error").is_string()) << path;
}

TEST_F(ServeErrors, UnknownPathsAre404AndBadCoordinates400) {
    ServedProgram served({build, "--port", "0", "-q"});
    ASSERT_TRUE(served.ok()) << served.error();
    httplib::Client client(served.host(), served.port());
    for (const char* path : {"/nope", "/api/nope.json", "/tiles/0/elevation/0/0/0.jpg", "/tiles/1/elevation/0/0/0.f32",
                             "/tiles/0/ortho/0/0/0.png", "/tiles/0/ortho/0/0/0.f32", "/tiles/0/normals/0/0/0.f32",
                             "/files/", "/files/none.dat"}) {
        expectError(client, path, 404);
    }
    // DEM.dat's elevation levels are 0..2.
    for (const char* path : {"/tiles/x/elevation/0/0/0.f32", "/tiles/0/elevation/3/0/0.f32",
                             "/tiles/0/elevation/1/2/0.f32", "/tiles/0/elevation/1/0/2.png",
                             "/tiles/0/elevation/a/0/0.f32", "/tiles/0/elevation/-1/0/0.f32",
                             "/tiles/0/elevation/0/0/+0.f32", "/tiles/0/elevation/99999999999/0/0.f32",
                             "/tiles/0/elevation/2/0/4294967296.f32"}) {
        expectError(client, path, 400);
    }
    const auto good = client.Get("/tiles/0/elevation/2/3/3.f32");
    ASSERT_TRUE(good);
    EXPECT_EQ(good->status, 200);
}

TEST_F(ServeErrors, FilesAreServedWholeOrByRangeAndHead) {
    ServedProgram served({build, "--port", "0", "-q"});
    ASSERT_TRUE(served.ok()) << served.error();
    httplib::Client client(served.host(), served.port());
    const auto whole = client.Get("/files/DEM.dat");
    ASSERT_TRUE(whole);
    EXPECT_EQ(whole->status, 200);
    EXPECT_TRUE(whole->body == dem);
    EXPECT_EQ(whole->get_header_value("Accept-Ranges"), "bytes");
    const auto head = client.Head("/files/DEM.dat");
    ASSERT_TRUE(head);
    EXPECT_EQ(head->status, 200);
    EXPECT_EQ(head->get_header_value("Content-Length"), std::to_string(dem.size()));
    EXPECT_TRUE(head->body.empty());
    const std::string size = std::to_string(dem.size());
    struct Part {
        std::string range;
        size_t offset, length;
    };
    const size_t n = dem.size();
    for (const Part& p : {Part{"bytes=0-27", 0, 28}, Part{"bytes=1000-1999", 1000, 1000}, Part{"bytes=-5", n - 5, 5},
                          Part{"bytes=" + std::to_string(n - 10) + "-", n - 10, 10},
                          Part{"bytes=" + std::to_string(n - 3) + "-" + std::to_string(n + 100), n - 3, 3}}) {
        const auto part = client.Get("/files/DEM.dat", {{"Range", p.range}});
        ASSERT_TRUE(part);
        EXPECT_EQ(part->status, 206) << p.range;
        EXPECT_TRUE(part->body == dem.substr(p.offset, p.length)) << p.range;
        EXPECT_EQ(part->get_header_value("Content-Range"), "bytes " + std::to_string(p.offset) + "-" +
                                                                std::to_string(p.offset + p.length - 1) + "/" + size);
    }
    for (const std::string& range :
         std::vector<std::string>{"bytes=" + size + "-", "bytes=10-5", "bytes=-0", "bytes=x-y", "lines=1-2"}) {
        const auto refused = client.Get("/files/DEM.dat", {{"Range", range}});
        ASSERT_TRUE(refused);
        EXPECT_EQ(refused->status, 416) << range;
        EXPECT_EQ(refused->body.find("DEM"), std::string::npos) << range;
    }
    // Several ranges: the whole file (HTTP lets a server ignore Range).
    const auto several = client.Get("/files/DEM.dat", {{"Range", "bytes=0-1,4-5"}});
    ASSERT_TRUE(several);
    EXPECT_EQ(several->status, 200);
    EXPECT_TRUE(several->body == dem);
}

TEST_F(ServeErrors, NothingOutsideTheServedDirectoryIsEverServed) {
    const std::string secret = "the bytes outside: 7f3a9c";
    {
        std::FILE* f = std::fopen(dir.file("secret.txt").c_str(), "w");
        ASSERT_NE(f, nullptr);
        std::fputs(secret.c_str(), f);
        std::fclose(f);
    }
    std::filesystem::create_symlink("../secret.txt", build + "/link.txt");
    std::filesystem::create_directory_symlink("..", build + "/up");
    std::filesystem::create_symlink(dir.file("secret.txt"), build + "/absolute.txt");
    std::filesystem::create_directories(build + "/sub");
    std::filesystem::copy_file(build + "/DEM.dat", build + "/sub/inner.dat");
    ServedProgram served({build, "--port", "0", "-q"});
    ASSERT_TRUE(served.ok()) << served.error();
    for (const char* target : {"/files/../secret.txt", "/files/%2e%2e/secret.txt", "/files/%2E%2E%2Fsecret.txt",
                               "/files/sub/../../secret.txt", "/files/sub/%2e%2e/%2e%2e/secret.txt",
                               "/files/link.txt", "/files/up/secret.txt", "/files/absolute.txt",
                               "/files//etc/passwd", "/files/%2fetc%2fpasswd", "/files/..%5csecret.txt",
                               "/files/./DEM.dat", "/files/sub//inner.dat",
                               "/viewer/../secret.txt", "/viewer/%2e%2e%2fsecret.txt"}) {
        const std::string answer = pyramid::test::rawRequest(served.port(), "GET", target);
        ASSERT_FALSE(answer.empty()) << target;
        EXPECT_TRUE(answer.rfind("HTTP/1.1 404", 0) == 0 || answer.rfind("HTTP/1.1 400", 0) == 0)
            << target << ": " << answer.substr(0, answer.find('\r'));
        EXPECT_EQ(answer.find(secret), std::string::npos) << target;
    }
    // What lies inside is served, through a subdirectory too.
    const std::string inner = pyramid::test::rawRequest(served.port(), "GET", "/files/sub/inner.dat");
    EXPECT_EQ(inner.rfind("HTTP/1.1 200", 0), 0u);
    EXPECT_EQ(inner.substr(inner.size() - dem.size()), dem);
}

TEST_F(ServeErrors, TheViewerFilesAndTheRequestLog) {
    const std::string viewer = dir.file("viewer");
    std::filesystem::create_directories(viewer);
    const std::string log = dir.file("requests.log");
    {
        ServedProgram served({build, "--port", "0", "-q", "--viewer-dir", viewer, "--log", log});
        ASSERT_TRUE(served.ok()) << served.error();
        httplib::Client client(served.host(), served.port());
        const auto none = client.Get("/");
        ASSERT_TRUE(none);
        EXPECT_EQ(none->status, 404);
        EXPECT_EQ(none->body, "no viewer: " + viewer + "/index.html is not there\n");
        std::FILE* f = std::fopen((viewer + "/index.html").c_str(), "w");
        ASSERT_NE(f, nullptr);
        std::fputs("<html>viewer</html>", f);
        std::fclose(f);
        const auto index = client.Get("/");
        ASSERT_TRUE(index);
        EXPECT_EQ(index->status, 200);
        EXPECT_EQ(index->body, "<html>viewer</html>");
        EXPECT_EQ(index->get_header_value("Content-Type"), "text/html; charset=utf-8");
        const auto same = client.Get("/viewer/index.html");
        ASSERT_TRUE(same);
        EXPECT_EQ(same->body, index->body);
        EXPECT_EQ(client.Get("/viewer/.hidden")->status, 404);
        EXPECT_EQ(client.Get("/viewer/nope.js")->status, 404);
        EXPECT_EQ(client.Get("/tiles/0/elevation/0/0/0.f32")->status, 200);
        EXPECT_EQ(client.Get("/tiles/0/elevation/9/0/0.f32")->status, 400);
        // A request is logged once its answer is sent: the client may have it first. The log
        // is read once the last line is in (or after 10 s), before the server is stopped.
        for (int k = 0; k < 1000 && pyramid::test::readFile(log).find("9/0/0.f32 400 ") == std::string::npos; ++k) {
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
    }
    const std::string lines = pyramid::test::readFile(log);
    EXPECT_NE(lines.find("GET / 404 "), std::string::npos) << lines;
    EXPECT_NE(lines.find("GET / 200 19\n"), std::string::npos) << lines;
    EXPECT_NE(lines.find("GET /tiles/0/elevation/0/0/0.f32 200 " + std::to_string(197 * 197 * 4) + "\n"),
              std::string::npos)
        << lines;
    EXPECT_NE(lines.find("GET /tiles/0/elevation/9/0/0.f32 400 "), std::string::npos) << lines;
}

// A non-loopback IPv4 address of this machine, or "" when it has none.
std::string otherAddress() {
    ifaddrs* list = nullptr;
    if (getifaddrs(&list) != 0) {
        return "";
    }
    std::string found;
    for (const ifaddrs* a = list; a != nullptr && found.empty(); a = a->ifa_next) {
        if (a->ifa_addr != nullptr && a->ifa_addr->sa_family == AF_INET) {
            const auto* in = reinterpret_cast<const sockaddr_in*>(a->ifa_addr);
            if ((ntohl(in->sin_addr.s_addr) >> 24) != 127) {
                char text[INET_ADDRSTRLEN] = {};
                inet_ntop(AF_INET, &in->sin_addr, text, sizeof text);
                found = text;
            }
        }
    }
    freeifaddrs(list);
    return found;
}

TEST_F(ServeErrors, ItListensOnThisMachineOnlyByDefault) {
    ServedProgram served({build, "--port", "0", "-q"});
    ASSERT_TRUE(served.ok()) << served.error();
    EXPECT_EQ(served.line(), "pyramid serve: http://127.0.0.1:" + std::to_string(served.port()) + "/\n");
    EXPECT_EQ(served.host(), "127.0.0.1");
    EXPECT_EQ(pyramid::test::rawRequest(served.port(), "GET", "/api/pyramid.json").rfind("HTTP/1.1 200", 0), 0u);
    const std::string other = otherAddress();
    if (other.empty()) {
        GTEST_SKIP() << "no non-loopback IPv4 address on this machine";
    }
    const int fd = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<uint16_t>(served.port()));
    inet_pton(AF_INET, other.c_str(), &a.sin_addr);
    EXPECT_NE(connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a), 0) << other << " accepted a connection";
    close(fd);
}

TEST_F(ServeErrors, SigtermStopsIt) {
    ServedProgram served({build, "--port", "0", "-q"});
    ASSERT_TRUE(served.ok()) << served.error();
    EXPECT_EQ(served.stop(), 143);
}

} // namespace
