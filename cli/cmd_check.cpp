#include <CLI/CLI.hpp>

#include "cli/cli_common.hpp"
#include "formats/error.hpp"

namespace pyramid::cli {

CommandRunner setupCheckCommand(CLI::App& app) {
    (void)app;
    return [] () -> int { fail("check", "not implemented yet"); };
}

} // namespace pyramid::cli
