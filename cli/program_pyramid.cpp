// `pyramid`'s parser (cli/programs.hpp): every command of cli/commands.hpp as a subcommand. The
// only program with `verify` (and its OpenGL producers) and `serve` (an HTTP server): the
// preprocessors, built without this file, do not load those libraries when they start.
#include "cli/programs.hpp"

#include <iterator>

#include <CLI/CLI.hpp>

#include "cli/cli_common.hpp"

namespace pyramid::cli {

// `pyramid`: inspect, check, extract and verify pyramid files, and build them.
int pyramidProgram(int argc, char** argv) {
    CLI::App app{"pyramid: build, inspect, check and verify Proland terrain pyramid files", "pyramid"};
    addVersionFlag(app);
    app.require_subcommand(1);
    struct Entry {
        const char* name;
        const char* help;
        CommandRunner (*setup)(CLI::App&);
    };
    const Entry entries[] = {
        {"info", "Print a pyramid file's header, levels and tiles", setupInfoCommand},
        {"tile", "Extract one tile (reconstructed elevations, residuals or decoded pixels)", setupTileCommand},
        {"check", "Validate a pyramid file and decode every tile", setupCheckCommand},
        {"dem", "Build a residual (DEM) pyramid from a raster (same as preprocessDem)", setupDemCommand},
        {"ortho", "Build ortho pyramids from imagery (same as preprocessOrtho)", setupOrthoCommand},
        {"sphere-dem", "Build six cube-face DEM pyramids from a global map (same as preprocessSphericalDem)",
         setupSphereDemCommand},
        {"sphere-ortho", "Build six cube-face ortho pyramids from global imagery (same as preprocessSphericalOrtho)",
         setupSphereOrthoCommand},
        {"aperture", "Build the ambient-aperture pyramid of a DEM pyramid (same as preprocessAperture)",
         setupApertureCommand},
        {"sphere-aperture", "Build the ambient-aperture faces of a planet's six DEM faces (same as preprocessSphericalAperture)",
         setupSphereApertureCommand},
        {"verify", "Rebuild every level and compare with the source (or CPU with GL)", setupVerifyCommand},
        {"merge", "Assemble the part files of a split build (--part I/N) into its pyramids", setupMergeCommand},
        {"preview", "Draw one level of a pyramid as a PNG: a hillshade, heights, residuals or the imagery",
         setupPreviewCommand},
        {"recode", "Store a DEM file's residuals with another codec (e.g. context coding, or back to the original's)",
         setupRecodeCommand},
        {"height", "Print the reconstructed height at a point (grid, source pixel, or longitude and latitude)",
         setupHeightCommand},
        {"serve", "Serve a build over HTTP: its tiles, files and description, and the 3D web viewer",
         setupServeCommand},
    };
    NamedRunner runners[std::size(entries)];
    int count = 0;
    for (const Entry& e : entries) {
        CLI::App* sub = app.add_subcommand(e.name, e.help);
        runners[count++] = NamedRunner{sub, e.setup(*sub)};
    }
    return runProgram(app, argc, argv, runners, count);
}

} // namespace pyramid::cli
