// `pyramid recode FILE -o OUT --compression C`: a residual file's tiles in another codec.
#include <cstdio>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "cli/cli_common.hpp"
#include "libpyramid/api/encoders.hpp"

namespace pyramid::cli {

CommandRunner setupRecodeCommand(CLI::App& app) {
    struct Args {
        std::string input, output, report;
        ResidualCodingArgs coding;
        int threads = 0;
        bool quiet = false;
    };
    auto args = std::make_shared<Args>();
    app.add_option("input", args->input, "A residual (DEM) file")->required();
    app.add_option("-o,--output", args->output, "The recoded file (may be the input: replaced once complete)")
        ->required();
    addResidualCodingOptions(app, args->coding);
    addThreadsOption(app, args->threads);
    addReportOption(app, args->report, "the report");
    app.add_flag("-q,--quiet", args->quiet, "No progress or summary on stderr");
    addProgressOption(app);
    return [args]() {
        ResidualRecodeOptions options;
        options.tiles = args->coding.resolve(args->quiet);
        options.threads = args->threads;
        options.progress = progressCallback("pyramid recode", args->quiet);
        const ResidualRecodeReport r = recodeResidualFile(args->input, args->output, options);
        if (speaks(args->quiet)) {
            std::fprintf(stderr, "%s: %lld tiles (%lld shared), %s tiles, %llu bytes (%.3f of %s), %.1f s\n",
                         r.output.c_str(), static_cast<long long>(r.tiles), static_cast<long long>(r.sharedTiles),
                         residualCodecName(r.coding.codec), static_cast<unsigned long long>(r.bytes),
                         r.inputBytes ? static_cast<double>(r.bytes) / static_cast<double>(r.inputBytes) : 0.0,
                         r.input.c_str(), r.seconds);
        }
        if (!args->report.empty()) {
            writeJson(toJson(r), args->report);
        }
        return kExitOk;
    };
}

} // namespace pyramid::cli
