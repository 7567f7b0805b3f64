// The programs' parsers (cli/programs.hpp): one CLI::App each, over the commands of cli/commands.hpp.
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

namespace {

// A program that runs one command: `description` is its --help's first line.
int oneCommandProgram(const char* name, const char* description, CommandRunner (*setup)(CLI::App&), int argc,
                      char** argv) {
    CLI::App app{description, name};
    addVersionFlag(app);
    NamedRunner runner{&app, setup(app)};
    return runProgram(app, argc, argv, &runner, 1);
}

} // namespace

// `preprocessDem`: the `pyramid dem` command as a program of its own.
int preprocessDemProgram(int argc, char** argv) {
    return oneCommandProgram("preprocessDem",
                             "preprocessDem: Build a residual (DEM) pyramid file from an elevation raster",
                             setupDemCommand, argc, argv);
}

// `preprocessOrtho`: the `pyramid ortho` command as a program of its own.
int preprocessOrthoProgram(int argc, char** argv) {
    return oneCommandProgram("preprocessOrtho",
                             "preprocessOrtho: Build ortho pyramid files (TIFF, DXT, colour residuals) from imagery",
                             setupOrthoCommand, argc, argv);
}

// `preprocessSphericalDem`: the `pyramid sphere-dem` command as a program of its own.
int preprocessSphericalDemProgram(int argc, char** argv) {
    return oneCommandProgram(
        "preprocessSphericalDem",
        "preprocessSphericalDem: Build six cube-face residual (DEM) pyramids from a global elevation map",
        setupSphereDemCommand, argc, argv);
}

// `preprocessSphericalOrtho`: the `pyramid sphere-ortho` command as a program of its own.
int preprocessSphericalOrthoProgram(int argc, char** argv) {
    return oneCommandProgram("preprocessSphericalOrtho",
                             "preprocessSphericalOrtho: Build six cube-face ortho pyramids from global imagery",
                             setupSphereOrthoCommand, argc, argv);
}

// `preprocessAperture`: the `pyramid aperture` command as a program of its own.
int preprocessApertureProgram(int argc, char** argv) {
    return oneCommandProgram(
        "preprocessAperture",
        "preprocessAperture: Build the ambient-aperture pyramid of a residual (DEM) pyramid, for terrain shading",
        setupApertureCommand, argc, argv);
}

// `preprocessSphericalAperture`: the `pyramid sphere-aperture` command as a program of its own.
int preprocessSphericalApertureProgram(int argc, char** argv) {
    return oneCommandProgram("preprocessSphericalAperture",
                             "preprocessSphericalAperture: Build the ambient-aperture faces (APERTURE1..6.dat) of a "
                             "planet's six DEM faces, for terrain shading",
                             setupSphereApertureCommand, argc, argv);
}

} // namespace pyramid::cli
