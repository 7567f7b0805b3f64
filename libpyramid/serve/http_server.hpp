// `pyramid serve`'s HTTP server (doc/cli/pyramid-serve.md): a build's description, tiles and
// files, and the web viewer, over cpp-httplib, requests served by a pool of threads.
#pragma once
#include <functional>
#include <string>

#include "libpyramid/serve/served_build.hpp"

namespace pyramid::serve {

struct ServerOptions {
    std::string bind = "127.0.0.1"; // the address listened on (127.0.0.1: this machine only)
    int port = 8080;                // 0: a free port
    std::string viewerDir;          // "" = viewer_files.hpp's viewerDirectory
    std::string log;                // "" none, "-" stderr, else a file: METHOD PATH STATUS BYTES per request
    int threads = 0;                // request threads; 0 = cpp-httplib's default (8 or more)
};

// Listens, calls `started` with the server's URL ("http://HOST:PORT/") once it accepts
// connections, and serves until the process ends (the programs' signal thread ends it). Throws
// Error when it cannot listen or open the log.
void serveBuild(const ServedBuild& build, const ServerOptions& options,
                const std::function<void(const std::string& url)>& started);

} // namespace pyramid::serve
