// `preprocessOrtho`: the `pyramid ortho` command as a program of its own.
#include <CLI/CLI.hpp>

#include "cli/cli_common.hpp"

int main(int argc, char** argv) {
    using namespace pyramid::cli;
    CLI::App app{"preprocessOrtho: Build ortho pyramid files (TIFF, DXT, colour residuals) from imagery", "preprocessOrtho"};
    addVersionFlag(app);
    NamedRunner runner{&app, setupOrthoCommand(app)};
    return runProgram(app, argc, argv, &runner, 1);
}
