#include <CLI/CLI.hpp>

#include "cli/cli_common.hpp"
#include "formats/error.hpp"

namespace pyramid::cli {

CommandRunner setupOrthoCommand(CLI::App& app) {
    (void)app;
    return [] () -> int { fail("ortho", "not implemented yet"); };
}

} // namespace pyramid::cli
