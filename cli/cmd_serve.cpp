// `pyramid serve PATH [--port N] [--bind ADDRESS] [--ortho PATH] [--log FILE|-]`: an HTTP server
// over a build, for the web viewer and remote loaders (doc/cli/pyramid-serve.md). The options
// are read here; libpyramid/serve/ serves.
#include <csignal>
#include <cstdio>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "cli/cli_common.hpp"
#include "libpyramid/serve/http_server.hpp"
#include "libpyramid/serve/served_build.hpp"

namespace pyramid::cli {

namespace {

struct ServeArgs {
    serve::ServeSource source;
    serve::ServerOptions server;
    bool quiet = false;
};

std::string summary(const serve::ServedBuild& build) {
    std::string text = build.planet ? "a planet of " + std::to_string(build.faces.size()) + " face(s)"
                                    : "a plane, " + build.faces.front().elevationPath;
    const serve::ServedFace& first = build.faces.front();
    text += ", levels 0.." + std::to_string(first.maxLevel);
    text += first.ortho ? ", with the ortho " + first.ortho->path() : ", without ortho";
    return text;
}

} // namespace

CommandRunner setupServeCommand(CLI::App& app) {
    auto a = std::make_shared<ServeArgs>();
    app.add_option("PATH", a->source.path,
                   "A DEM file or region set (its main file, index or directory), or a planet: a directory of six "
                   "cube faces NAME1.dat .. NAME6.dat")
        ->required();
    app.add_option("--ortho", a->source.ortho,
                   "The ortho pyramid to drape (a file or set; planets: the directory of its faces). Default: "
                   "RGB.dat, residuals/RGB.dat or dxt/RGB.dat beside the DEM, if there is one");
    app.add_option("--port", a->server.port, "The TCP port (0: any free port, printed)")
        ->capture_default_str()
        ->check(CLI::Range(0, 65535));
    app.add_option("--bind", a->server.bind,
                   "The address to listen on; the default serves this machine only (0.0.0.0: every network, "
                   "to anyone who can reach it)")
        ->capture_default_str();
    app.add_option("--name", a->source.name, "A planet's DEM faces: NAME1.dat .. NAME6.dat")->capture_default_str();
    app.add_option("--body", a->source.body, "Planets: the body the faces were built on (its radius is reported)")
        ->capture_default_str();
    app.add_option("--viewer-dir", a->server.viewerDir,
                   "The web viewer's files (default: the installed share/libpyramid/viewer, or the build's viewer/)");
    app.add_option("--cache-tiles", a->source.cacheTiles, "Tiles each producer keeps")
        ->capture_default_str()
        ->check(CLI::Range(1, 1 << 20));
    app.add_option("--threads", a->server.threads, "Threads serving requests (0: 8, or one per core if more)")
        ->capture_default_str()
        ->check(CLI::Range(0, 256));
    app.add_option("--log", a->server.log, "Write METHOD PATH STATUS BYTES per request to this file ('-': stderr)");
    app.add_flag("-q,--quiet", a->quiet, "No summary on stderr (the URL line on stdout is always printed)");
    return [a]() {
        // A client that goes away mid-answer is that answer's failure, not the server's end.
        std::signal(SIGPIPE, SIG_IGN);
        const serve::ServedBuild build = serve::openServedBuild(a->source);
        serve::serveBuild(build, a->server, [&](const std::string& url) {
            std::printf("pyramid serve: %s\n", url.c_str());
            std::fflush(stdout);
            if (speaks(a->quiet)) {
                std::fprintf(stderr, "pyramid serve: %s (Ctrl-C stops)\n", summary(build).c_str());
            }
        });
        return kExitOk;
    };
}

} // namespace pyramid::cli
