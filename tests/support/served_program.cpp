// `pyramid serve` run by a test (served_program.hpp).
#include "served_program.hpp"

#include <algorithm>
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <png.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "paths.hpp"

namespace pyramid::test {

ServedProgram::ServedProgram(const std::vector<std::string>& args) {
    int out[2];
    if (pipe(out) != 0) {
        error_ = "pipe failed";
        return;
    }
    char name[] = "/tmp/pyramid-serve-err-XXXXXX";
    const int errFd = mkstemp(name);
    errFile_ = name;
    const std::string program = programPath("pyramid");
    std::vector<std::string> all = {program, "serve"};
    all.insert(all.end(), args.begin(), args.end());
    pid_ = fork();
    if (pid_ == 0) {
        dup2(out[1], 1);
        dup2(errFd, 2);
        close(out[0]);
        close(out[1]);
        std::vector<char*> argv;
        for (std::string& a : all) {
            argv.push_back(a.data());
        }
        argv.push_back(nullptr);
        execv(program.c_str(), argv.data());
        _exit(127);
    }
    close(out[1]);
    close(errFd);
    // The first line, within 60 s.
    pollfd p{out[0], POLLIN, 0};
    char c = 0;
    while (line_.empty() || line_.back() != '\n') {
        if (poll(&p, 1, 60000) <= 0 || read(out[0], &c, 1) != 1) {
            break;
        }
        line_ += c;
    }
    close(out[0]);
    const std::string prefix = "pyramid serve: http://";
    const size_t colon = line_.rfind(':');
    if (line_.rfind(prefix, 0) == 0 && colon != std::string::npos && colon > prefix.size()) {
        host_ = line_.substr(prefix.size(), colon - prefix.size());
        port_ = std::atoi(line_.c_str() + colon + 1);
    }
    if (port_ <= 0) {
        std::ifstream in(errFile_);
        std::stringstream s;
        s << in.rdbuf();
        error_ = "no URL line (got '" + line_ + "'); stderr: " + s.str();
    }
}

int ServedProgram::stop() {
    if (pid_ <= 0) {
        return -1;
    }
    kill(pid_, SIGTERM);
    int status = 0;
    waitpid(pid_, &status, 0);
    pid_ = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

ServedProgram::~ServedProgram() {
    stop();
    if (!errFile_.empty()) {
        std::remove(errFile_.c_str());
    }
}

std::string rawRequest(int port, const std::string& method, const std::string& target) {
    const int fd = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<uint16_t>(port));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    std::string answer;
    if (connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0) {
        const std::string request =
            method + " " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n";
        if (write(fd, request.data(), request.size()) == static_cast<ssize_t>(request.size())) {
            char buffer[65536];
            ssize_t n = 0;
            while ((n = read(fd, buffer, sizeof buffer)) > 0) {
                answer.append(buffer, static_cast<size_t>(n));
            }
        }
    }
    close(fd);
    return answer;
}

DecodedPng decodePng(const std::string& bytes) {
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    DecodedPng d;
    if (!png_image_begin_read_from_memory(&image, bytes.data(), bytes.size())) {
        return d;
    }
    // The image's own format: no conversion.
    if ((image.format & PNG_FORMAT_FLAG_LINEAR) != 0 || (image.format & PNG_FORMAT_FLAG_COLORMAP) != 0) {
        png_image_free(&image);
        return d;
    }
    d.width = static_cast<int>(image.width);
    d.height = static_cast<int>(image.height);
    d.channels = static_cast<int>(PNG_IMAGE_PIXEL_CHANNELS(image.format));
    d.pixels.resize(PNG_IMAGE_SIZE(image));
    if (!png_image_finish_read(&image, nullptr, d.pixels.data(), 0, nullptr)) {
        return DecodedPng{};
    }
    return d;
}

std::string orthoPngMismatch(const std::string& png, const std::vector<unsigned char>& pixels, int side, int channels) {
    const DecodedPng image = decodePng(png);
    if (image.width != side || image.height != side || image.channels != channels) {
        return "a PNG of " + std::to_string(image.width) + " x " + std::to_string(image.height) + " x " +
               std::to_string(image.channels) + ", not " + std::to_string(side) + " x " + std::to_string(side) +
               " x " + std::to_string(channels);
    }
    const size_t row = static_cast<size_t>(side) * static_cast<size_t>(channels);
    for (size_t y = 0; y < static_cast<size_t>(side); ++y) {
        const unsigned char* expected = pixels.data() + (static_cast<size_t>(side) - 1 - y) * row;
        if (!std::equal(expected, expected + row, image.pixels.data() + y * row)) {
            return "the PNG's row " + std::to_string(y) + " (from the top) differs";
        }
    }
    return "";
}

} // namespace pyramid::test
