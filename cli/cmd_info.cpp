#include <CLI/CLI.hpp>

#include "cli/cli_common.hpp"
#include "formats/error.hpp"

namespace pyramid::cli {

CommandRunner setupInfoCommand(CLI::App& app) {
    (void)app;
    return [] () -> int { fail("info", "not implemented yet"); };
}

} // namespace pyramid::cli
