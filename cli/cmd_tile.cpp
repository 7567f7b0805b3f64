#include <CLI/CLI.hpp>

#include "cli/cli_common.hpp"
#include "formats/error.hpp"

namespace pyramid::cli {

CommandRunner setupTileCommand(CLI::App& app) {
    (void)app;
    return [] () -> int { fail("tile", "not implemented yet"); };
}

} // namespace pyramid::cli
