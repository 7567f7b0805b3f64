// `preprocessSphericalAperture`: the `pyramid sphere-aperture` command as a program of its own.
#include <CLI/CLI.hpp>

#include "cli/cli_common.hpp"

int main(int argc, char** argv) {
    using namespace pyramid::cli;
    CLI::App app{"preprocessSphericalAperture: Build the ambient-aperture faces (APERTURE1..6.dat) of a planet's six "
                 "DEM faces, for terrain shading",
                 "preprocessSphericalAperture"};
    addVersionFlag(app);
    NamedRunner runner{&app, setupSphereApertureCommand(app)};
    return runProgram(app, argc, argv, &runner, 1);
}
