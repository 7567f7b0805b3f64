// The preprocessors' parsers (cli/programs.hpp): one CLI::App each, over one command of
// cli/commands.hpp (`pyramid`'s, over all of them, is in cli/program_pyramid.cpp).
#include "cli/programs.hpp"

#include <CLI/CLI.hpp>

#include "cli/cli_common.hpp"

namespace pyramid::cli {

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
