// `preprocessAperture`: the `pyramid aperture` command as a program of its own.
#include <CLI/CLI.hpp>

#include "cli/cli_common.hpp"

int main(int argc, char** argv) {
    using namespace pyramid::cli;
    CLI::App app{"preprocessAperture: Build the ambient-aperture pyramid of a residual (DEM) pyramid, for terrain "
                 "shading",
                 "preprocessAperture"};
    addVersionFlag(app);
    NamedRunner runner{&app, setupApertureCommand(app)};
    return runProgram(app, argc, argv, &runner, 1);
}
