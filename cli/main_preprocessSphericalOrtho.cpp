// `preprocessSphericalOrtho`: the `pyramid sphere-ortho` command as a program of its own.
#include <CLI/CLI.hpp>

#include "cli/cli_common.hpp"

int main(int argc, char** argv) {
    using namespace pyramid::cli;
    CLI::App app{"preprocessSphericalOrtho: Build six cube-face ortho pyramids from global imagery",
                 "preprocessSphericalOrtho"};
    addVersionFlag(app);
    NamedRunner runner{&app, setupSphereOrthoCommand(app)};
    return runProgram(app, argc, argv, &runner, 1);
}
