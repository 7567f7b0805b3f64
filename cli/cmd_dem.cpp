#include <CLI/CLI.hpp>

#include "cli/cli_common.hpp"
#include "formats/error.hpp"

namespace pyramid::cli {

CommandRunner setupDemCommand(CLI::App& app) {
    (void)app;
    return [] () -> int { fail("dem", "not implemented yet"); };
}

} // namespace pyramid::cli
