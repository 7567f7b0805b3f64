// What a run writes (cli_common.hpp): its outputs' checks before any work, outputs kept apart
// from its inputs and its report, the report as JSON, the format an output's extension names.
#include "cli/cli_common.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "formats/atomic_file.hpp"
#include "formats/error.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid::cli {

std::string lowerExtension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), lowerAscii);
    return ext;
}

OutputPreflight::OutputPreflight(const std::string& output, bool isDirectory, const std::string& report) {
    if (isDirectory) {
        prepareOutputDirectory(output);
    } else {
        prepareOutputFile(output, output_);
    }
    if (!report.empty() && report != "-") {
        prepareOutputFile(report, report_);
    }
}

void OutputPreflight::keep() {
    output_.keep();
    report_.keep();
}

void writeJson(const nlohmann::json& json, const std::string& path) {
    nlohmann::json report = json;
    if (report.is_object() && !report.contains("ok")) {
        report["ok"] = true; // every report says whether its run succeeded
    }
    const std::string text = report.dump(2) + "\n";
    if (path == "-") {
        std::fwrite(text.data(), 1, text.size(), stdout);
        std::fflush(stdout);
        return;
    }
    AtomicFile out(path);
    out.writeAt(0, text.data(), text.size());
    out.commit();
}

void checkOutputsApart(const InputArgs& input, const std::vector<OutputFile>& writes, std::string& report) {
    namespace fs = std::filesystem;
    // The same file: the same inode when both exist, else the same path once resolved.
    const auto same = [](const std::string& a, const std::string& b) {
        std::error_code ec, ed;
        if (fs::exists(a, ec) && fs::exists(b, ed)) {
            return fs::equivalent(a, b, ec) && !ec;
        }
        return fs::weakly_canonical(a, ec) == fs::weakly_canonical(b, ed) && !ec && !ed;
    };
    std::vector<std::string> inputs = input.inputs;
    if (!input.list.empty()) {
        inputs.push_back(input.list);
    }
    std::error_code ec;
    const auto reportNames = [&](const std::string& what) {
        // Not even the failure report goes there.
        const std::string named = report;
        report.clear();
        fail("--report", "'" + named + "' is " + what + "; name the report otherwise");
    };
    for (const std::string& in : inputs) {
        if (!fs::is_regular_file(in, ec)) {
            continue; // a directory or a glob: its files are not outputs' names
        }
        if (!report.empty() && report != "-" && same(report, in)) {
            reportNames("an input");
        }
        for (const OutputFile& out : writes) {
            if (same(out.path, in)) {
                fail("-o", "'" + out.path + "' is an input; name the output otherwise");
            }
        }
    }
    for (const OutputFile& out : writes) {
        if (!report.empty() && report != "-" && same(report, out.path)) {
            reportNames(out.what);
        }
    }
}

void printGeoreferenceSummary(const std::optional<PyramidGeoreference>& georeference, const std::string& sidecar) {
    if (!georeference) {
        return;
    }
    const Georeference& crs = georeference->crs;
    std::string heights;
    if (const std::optional<HeightUnit>& unit = crs.heightUnit) {
        heights = "; heights in " + (unit->name.empty() ? std::string("an unknown unit") : unit->name) + " (" +
                  unit->source + ")";
        if (const double scale = crs.heightsToGround(); scale != 1.0) {
            char factor[32];
            std::snprintf(factor, sizeof factor, "%.10g", scale);
            heights += std::string(", read in ") + (crs.projected ? "the CRS's unit" : "metres") + " (x" + factor + ")";
        }
    }
    std::fprintf(stderr, "%s: placement in %s%s\n", sidecar.c_str(), crs.crsText().c_str(), heights.c_str());
}

} // namespace pyramid::cli
