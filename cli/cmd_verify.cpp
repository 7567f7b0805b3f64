#include <CLI/CLI.hpp>

#include "cli/cli_common.hpp"
#include "formats/error.hpp"

namespace pyramid::cli {

CommandRunner setupVerifyCommand(CLI::App& app) {
    (void)app;
    return [] () -> int { fail("verify", "not implemented yet"); };
}

} // namespace pyramid::cli
