// `preprocessDem`: the `pyramid dem` command as a program of its own.
#include <CLI/CLI.hpp>

#include "cli/cli_common.hpp"

int main(int argc, char** argv) {
    using namespace pyramid::cli;
    CLI::App app{"preprocessDem: Build a residual (DEM) pyramid file from an elevation raster", "preprocessDem"};
    addVersionFlag(app);
    NamedRunner runner{&app, setupDemCommand(app)};
    return runProgram(app, argc, argv, &runner, 1);
}
