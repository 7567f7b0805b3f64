// `pyramid serve`'s routes over cpp-httplib (http_server.hpp): the answers of answers.hpp, the
// files under the served directory with Range, and the viewer's files.
#include "libpyramid/serve/http_server.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <httplib.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <mutex>
#include <system_error>
#include <vector>

#include "formats/error.hpp"
#include "formats/file_io.hpp"
#include "libpyramid/serve/answers.hpp"
#include "libpyramid/serve/file_access.hpp"
#include "libpyramid/serve/viewer_files.hpp"

namespace pyramid::serve {

namespace {

namespace fs = std::filesystem;

void send(httplib::Response& res, const Answer& a) {
    res.status = a.status;
    for (const auto& [name, value] : a.headers) {
        res.set_header(name, value);
    }
    res.set_content(a.body, a.contentType);
}

// The log: one line per request, written whole and flushed, from any thread.
class RequestLog {
public:
    explicit RequestLog(const std::string& target) {
        if (target == "-") {
            file_ = stderr;
        } else if (!target.empty()) {
            file_ = std::fopen(target.c_str(), "a");
            if (file_ == nullptr) {
                fail(target, std::string("cannot open the log: ") + std::strerror(errno));
            }
            owned_ = true;
        }
    }
    ~RequestLog() {
        if (owned_) {
            std::fclose(file_);
        }
    }
    RequestLog(const RequestLog&) = delete;
    RequestLog& operator=(const RequestLog&) = delete;
    bool on() const { return file_ != nullptr; }
    void line(const std::string& text) {
        const std::lock_guard<std::mutex> lock(mutex_);
        std::fputs(text.c_str(), file_);
        std::fflush(file_);
    }

private:
    std::FILE* file_ = nullptr;
    bool owned_ = false;
    std::mutex mutex_;
};

// An open file, closed when the last answer reading it is done.
struct OpenFile {
    int fd = -1;
    ~OpenFile() {
        if (fd >= 0) {
            ::close(fd);
        }
    }
};

// GET or HEAD /files/RELATIVE: the file's bytes, or the part a Range header asks (206), read as
// they are sent.
void sendFile(const fs::path& root, const std::string& relative, const httplib::Request& req,
              httplib::Response& res) {
    const auto file = servedFile(root, relative);
    if (!file) {
        return send(res, errorAnswer(404, "no file '" + relative + "' here"));
    }
    auto open = std::make_shared<OpenFile>();
    open->fd = ::open(file->c_str(), O_RDONLY | O_CLOEXEC);
    std::error_code ec;
    const uint64_t size = fs::file_size(*file, ec);
    if (open->fd < 0 || ec) {
        return send(res, errorAnswer(404, "cannot read '" + relative + "'"));
    }
    const RangeAnswer range = answerRange(req.get_header_value("Range"), size);
    res.set_header("Accept-Ranges", "bytes");
    if (range.kind == RangeAnswer::Unsatisfiable) {
        res.status = 416;
        res.set_header("Content-Range", contentRange(range, size));
        return;
    }
    if (range.kind == RangeAnswer::Part) {
        res.status = 206;
        res.set_header("Content-Range", contentRange(range, size));
    }
    const uint64_t start = range.offset;
    res.set_content_provider(static_cast<size_t>(range.length), contentTypeOf(file->filename().string()),
                             [open, start](size_t offset, size_t length, httplib::DataSink& sink) {
                                 std::vector<char> buffer(std::min<size_t>(length, size_t{1} << 20));
                                 while (length > 0) {
                                     const size_t n = std::min(length, buffer.size());
                                     if (!readFully(open->fd, buffer.data(), n, start + offset)) {
                                         return false;
                                     }
                                     if (!sink.write(buffer.data(), n)) {
                                         return false;
                                     }
                                     offset += n;
                                     length -= n;
                                 }
                                 return true;
                             });
}

void sendViewerFile(const fs::path& directory, const std::string& name, httplib::Response& res) {
    const fs::path file = viewerFile(directory, name);
    if (file.empty()) {
        if (name == "index.html") { // GET /: one line of text, for a person at a browser
            res.status = 404;
            res.set_content("no viewer: " + (directory / name).string() + " is not there\n", "text/plain; charset=utf-8");
            return;
        }
        return send(res, errorAnswer(404, "no viewer file '" + name + "'"));
    }
    // Small files, read whole for each request.
    std::string bytes;
    if (std::FILE* in = std::fopen(file.c_str(), "rb")) {
        char buffer[65536];
        size_t n = 0;
        while ((n = std::fread(buffer, 1, sizeof buffer, in)) > 0) {
            bytes.append(buffer, n);
        }
        std::fclose(in);
    }
    res.set_content(bytes, contentTypeOf(name));
}

std::string hostInUrl(const std::string& host) {
    return host.find(':') != std::string::npos ? "[" + host + "]" : host;
}

} // namespace

void serveBuild(const ServedBuild& build, const ServerOptions& options,
                const std::function<void(const std::string& url)>& started) {
    RequestLog log(options.log);
    const fs::path viewer = viewerDirectory(options.viewerDir);
    const std::string description = describeBuild(build);
    httplib::Server server;
    if (options.threads > 0) {
        const auto threads = static_cast<size_t>(options.threads);
        server.new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
    }
    server.set_keep_alive_max_count(1000);
    // Without it an answer's last segment can wait for the client's delayed ACK (40 ms a tile).
    server.set_tcp_nodelay(true);
    // cpp-httplib 0.11 cuts every answer to a Range header's ranges, unchecked against the
    // answer's length (a range past the end reads past it). Ranges are answered here, by /files
    // alone (answerRange); every other answer is whole, as HTTP allows. The request object is the
    // server's own, not const: its parsed ranges are dropped before routing.
    server.set_pre_routing_handler([](const httplib::Request& req, httplib::Response&) {
        const_cast<httplib::Request&>(req).ranges.clear();
        return httplib::Server::HandlerResponse::Unhandled;
    });
    server.Get("/", [&viewer](const httplib::Request&, httplib::Response& res) {
        sendViewerFile(viewer, "index.html", res);
    });
    server.Get(R"(/viewer/(.*))", [&viewer](const httplib::Request& req, httplib::Response& res) {
        sendViewerFile(viewer, req.matches[1], res);
    });
    server.Get("/api/pyramid.json", [&description](const httplib::Request&, httplib::Response& res) {
        res.set_header("Cache-Control", "no-cache");
        res.set_content(description, "application/json");
    });
    server.Get(R"(/tiles/([^/]*)/([^/]*)/([^/]*)/([^/]*)/([^/]*)\.([^/.]*))",
               [&build](const httplib::Request& req, httplib::Response& res) {
                   send(res, tileAnswer(build, req.matches[1], req.matches[2], req.matches[3], req.matches[4],
                                        req.matches[5], req.matches[6]));
               });
    server.Get(R"(/files/(.*))", [&build](const httplib::Request& req, httplib::Response& res) {
        sendFile(build.root, req.matches[1], req, res);
    });
    // Errors without a body of their own (no route, a refused request): {"error": ...} too.
    const httplib::Server::HandlerWithResponse errorBody = [](const httplib::Request& req, httplib::Response& res) {
        if (res.body.empty() && !res.content_provider_) {
            const std::string what = res.status == 404   ? "no such path: " + req.path
                                     : res.status == 416 ? "range not satisfiable"
                                                         : "HTTP status " + std::to_string(res.status);
            res.set_content(errorAnswer(res.status, what).body, "application/json");
        }
        return httplib::Server::HandlerResponse::Handled;
    };
    server.set_error_handler(errorBody);
    server.set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr error) {
        std::string what = "internal error";
        try {
            std::rethrow_exception(error);
        } catch (const std::exception& e) {
            what = e.what();
        } catch (...) {
        }
        send(res, errorAnswer(500, what));
    });
    if (log.on()) {
        server.set_logger([&log](const httplib::Request& req, const httplib::Response& res) {
            const std::string length = res.get_header_value("Content-Length");
            log.line(req.method + " " + req.path + " " + std::to_string(res.status) + " " +
                     (length.empty() ? std::to_string(res.body.size()) : length) + "\n");
        });
    }
    const int port = options.port == 0 ? server.bind_to_any_port(options.bind)
                                       : (server.bind_to_port(options.bind, options.port) ? options.port : -1);
    if (port < 0) {
        fail(options.bind + ":" + std::to_string(options.port),
             "cannot listen there (address in use, or not an address of this machine)");
    }
    started("http://" + hostInUrl(options.bind) + ":" + std::to_string(port) + "/");
    if (!server.listen_after_bind()) {
        fail(options.bind + ":" + std::to_string(port), "the server stopped listening");
    }
}

} // namespace pyramid::serve
