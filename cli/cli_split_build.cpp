// A build split over processes (cli_common.hpp, runSplitBuild): --part I/N for batch jobs, or the
// ranks of an MPI run, the build's identity in its part files.
#include "cli/cli_common.hpp"

#include <cstdio>
#include <filesystem>
#include <optional>
#include <string_view>

#include <CLI/CLI.hpp>

#include "formats/error.hpp"
#include "libpyramid/api/encoders.hpp"
#include "libpyramid/distribute/team.hpp"
#include "libpyramid/support/parse_number.hpp"

namespace pyramid::cli {

namespace {

// The build's identity in its part files: the command line without what does not change the
// files (the part, threads, cache, report, quiet, progress).
nlohmann::json buildIdentity(const char* program) {
    std::vector<std::string> kept;
    const std::vector<std::string>& all = commandArguments();
    for (size_t i = 1; i < all.size(); ++i) {
        const std::string& a = all[i];
        if (a == "-q" || a == "--quiet" || a == "--json") {
            continue;
        }
        bool dropped = false;
        for (const std::string flag : {"--part", "--threads", "--cache-mb", "--report", "--progress"}) {
            if (a == flag) {
                ++i; // and its value
                dropped = true;
                break;
            }
            if (a.rfind(flag + "=", 0) == 0) {
                dropped = true;
                break;
            }
        }
        if (!dropped) {
            kept.push_back(a);
        }
    }
    return {{"program", program}, {"arguments", kept}};
}

} // namespace

CLI::Option* addPartOption(CLI::App& app, std::string& part) {
    return app.add_option("--part", part,
                   "Encode only part I of N (0 <= I < N) into OUTPUT.part-I-of-N, for batch schedulers; "
                   "'pyramid merge' assembles the parts into the files one run writes")
        ->type_name("I/N");
}

BuildRole runSplitBuild(const std::string& part, bool quiet, const SplitBuild& build) {
    Team& team = worldTeam();
    if (!part.empty()) {
        const size_t slash = part.find('/');
        const std::string_view text(part);
        const auto index = slash == std::string::npos ? std::nullopt : readWholeNumber<int64_t>(text.substr(0, slash));
        const auto count = slash == std::string::npos ? std::nullopt : readWholeNumber<int64_t>(text.substr(slash + 1));
        if (!index || !count) {
            fail("--part", "must be I/N (part I of N, from 0), not " + part);
        }
        if (*count < 1 || *count > 1000000 || *index < 0 || *index >= *count) {
            fail("--part", "must be I/N with 0 <= I < N, not " + part);
        }
        if (team.size() > 1) {
            fail("--part", "splits a build for batch jobs; under mpirun the ranks split it themselves");
        }
        build.prepare();
        const std::string base = (std::filesystem::path(build.directory) / build.name).string();
        const std::string path = runPart(static_cast<int>(*index), static_cast<int>(*count), base, build.format,
                                         buildIdentity(build.program),
                                         [&](const PartContext& share) { build.encode(&share); });
        if (!quiet) {
            std::fprintf(stderr, "%s: part %lld of %lld written to %s; 'pyramid merge' assembles the parts\n",
                         build.program, static_cast<long long>(*index), static_cast<long long>(*count), path.c_str());
        }
        return BuildRole::Part;
    }
    if (team.size() == 1) {
        build.prepare();
        build.encode(nullptr);
        return BuildRole::Whole;
    }
    runTeam(team, build.directory, build.name, build.format, buildIdentity(build.program), build.prepare,
            [&](const PartContext& share) { build.encode(&share); },
            [&](const std::vector<std::string>& parts) { build.merge(parts); });
    return team.rank() == 0 ? BuildRole::Root : BuildRole::OtherRank;
}

} // namespace pyramid::cli
