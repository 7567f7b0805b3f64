// `pyramid serve` run by a test: started on a free port, its URL read from its first line, stopped
// (SIGTERM) when the test is done with it.
#pragma once
#include <string>
#include <vector>

namespace pyramid::test {

class ServedProgram {
public:
    // Runs `pyramid serve ARGS...` (add "--port", "0" for a free port). Fails the test (an
    // assertion in the constructor's caller: check ok()) when the URL line does not come within
    // 60 s; `error` then holds what the program said on stderr.
    explicit ServedProgram(const std::vector<std::string>& args);
    ~ServedProgram();
    ServedProgram(const ServedProgram&) = delete;
    ServedProgram& operator=(const ServedProgram&) = delete;

    bool ok() const { return port_ > 0; }
    const std::string& line() const { return line_; } // "pyramid serve: http://HOST:PORT/"
    const std::string& host() const { return host_; }
    int port() const { return port_; }
    int pid() const { return pid_; }
    const std::string& error() const { return error_; }
    // Sends SIGTERM and waits: the exit code (128 + signal for a signal's end).
    int stop();

private:
    int pid_ = -1;
    int port_ = 0;
    std::string line_, host_, error_, errFile_;
};

// A raw HTTP/1.1 request (`request` as sent, "\r\n" line ends and all) to 127.0.0.1:port: the
// whole answer as received (the server closes it: "Connection: close" is added). For paths a
// client library would clean up ("/files/../x").
std::string rawRequest(int port, const std::string& method, const std::string& target);

// An 8-bit PNG's pixels as stored (rows top first, `channels` bytes each: 1 grey .. 4 RGBA);
// empty when the bytes are not such a PNG.
struct DecodedPng {
    int width = 0, height = 0, channels = 0;
    std::vector<unsigned char> pixels;
};
DecodedPng decodePng(const std::string& bytes);

// What differs between the server's ortho PNG `png` and the C API's tile `pixels` (side x side
// pixels of `channels` bytes, row 0 south; the PNG is north up): "" when it is that tile.
std::string orthoPngMismatch(const std::string& png, const std::vector<unsigned char>& pixels, int side, int channels);

} // namespace pyramid::test
