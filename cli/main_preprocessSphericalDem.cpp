// `preprocessSphericalDem`: the `pyramid sphere-dem` command as a program of its own.
#include <CLI/CLI.hpp>

#include "cli/cli_common.hpp"

int main(int argc, char** argv) {
    using namespace pyramid::cli;
    CLI::App app{"preprocessSphericalDem: Build six cube-face residual (DEM) pyramids from a global elevation map",
                 "preprocessSphericalDem"};
    addVersionFlag(app);
    NamedRunner runner{&app, setupSphereDemCommand(app)};
    return runProgram(app, argc, argv, &runner, 1);
}
