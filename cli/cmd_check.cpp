// `pyramid check SET [--report FILE|-]`: the structure validated, every tile decoded; for a region set
// (its main file, index or directory) every file, and the set's own rules.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>

#include <CLI/CLI.hpp>

#include "cli/cli_common.hpp"
#include "formats/error.hpp"
#include "formats/ortho_file.hpp"
#include "formats/pyramid_kind.hpp"
#include "formats/pyramid_set.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/support/parallel.hpp"

namespace pyramid::cli {

namespace {

struct TileRef {
    int level, tx, ty;
    int64_t index;
};

template <class Header>
std::vector<TileRef> allTiles(const Header& h, const std::function<int64_t(int)>& side) {
    std::vector<TileRef> tiles;
    for (int l = 0; l <= h.maxLevel; ++l) {
        const int64_t s = side(l);
        for (int64_t ty = 0; ty < s; ++ty) {
            for (int64_t tx = 0; tx < s; ++tx) {
                tiles.push_back({l, static_cast<int>(tx), static_cast<int>(ty),
                                 h.tileIndex(l, static_cast<int>(tx), static_cast<int>(ty))});
            }
        }
    }
    return tiles;
}

// Distinct byte ranges must be identical or disjoint: a partial overlap means a corrupt table.
void checkOverlaps(const TileTable& table, std::vector<std::string>& problems) {
    std::vector<std::pair<TileTable::Range, int64_t>> ranges;
    for (int64_t i = 0; i < table.tileCount(); ++i) {
        if (table.range(i).size()) {
            ranges.push_back({table.range(i), i});
        }
    }
    std::sort(ranges.begin(), ranges.end(), [](const auto& a, const auto& b) {
        return a.first.begin != b.first.begin ? a.first.begin < b.first.begin : a.first.end < b.first.end;
    });
    for (size_t k = 1; k < ranges.size(); ++k) {
        const auto& [a, ia] = ranges[k - 1];
        const auto& [b, ib] = ranges[k];
        const bool same = a.begin == b.begin && a.end == b.end;
        if (!same && b.begin < a.end) {
            problems.push_back("tiles " + std::to_string(ia) + " and " + std::to_string(ib) +
                               " have overlapping byte ranges");
        }
    }
}

template <class Reader>
std::vector<std::string> decodeAll(const std::string& file, const Reader& reader, const std::vector<TileRef>& tiles,
                                   int threads, bool quiet) {
    std::vector<std::string> errors(tiles.size());
    Progress progress(file, static_cast<int64_t>(tiles.size()), quiet, Progress::OffTerminal::Silent);
    parallelFor(static_cast<int64_t>(tiles.size()), threads, [&](int64_t k) {
        const TileRef& t = tiles[static_cast<size_t>(k)];
        try {
            reader.readTile(t.level, t.tx, t.ty);
        } catch (const Error& e) {
            errors[static_cast<size_t>(k)] = e.what();
        }
        progress.advance();
    });
    progress.finish();
    std::vector<std::string> problems;
    for (std::string& e : errors) {
        if (!e.empty()) {
            problems.push_back(std::move(e));
        }
    }
    return problems;
}

// The one line a failed check prints on stderr, as every failure does: the first problem,
// naming the file, and how many more there are.
// (A set's problems each name their own file: `file` empty.)
std::string reasonLine(const std::string& file, const std::vector<std::string>& problems) {
    std::string line = problems.front();
    if (!file.empty() && line.rfind(file + ": ", 0) != 0) {
        line = file + ": " + line;
    }
    if (problems.size() > 1) {
        const size_t more = problems.size() - 1;
        line += " (and " + std::to_string(more) + " more problem" + (more == 1 ? "" : "s") + ")";
    }
    return line;
}

// One file checked: its structure validated and every tile decoded. Problems are appended;
// returns the tiles checked (each decoded, or found broken). Throws Error when the file cannot be opened as a pyramid.
int64_t checkFile(const std::string& file, int threads, bool quiet, std::string& kind,
                  std::vector<std::string>& problems) {
    const OpenedPyramid opened = openPyramid(file);
    const PyramidKind k = opened.kind;
    kind = kindName(k);
    if (k == PyramidKind::Residual) {
        const auto& reader = opened.residual;
        const auto& h = reader->header();
        const auto tiles = allTiles(h, [&](int l) { return h.tilesPerSide(l); });
        checkOverlaps(reader->table(), problems);
        auto decoded = decodeAll(file, *reader, tiles, threads, quiet);
        problems.insert(problems.end(), decoded.begin(), decoded.end());
        return static_cast<int64_t>(tiles.size());
    }
    const auto& reader = opened.ortho;
    const auto& h = reader->header();
    const auto tiles = allTiles(h, [](int l) { return int64_t{1} << l; });
    checkOverlaps(reader->table(), problems);
    auto decoded = decodeAll(file, *reader, tiles, threads, quiet);
    problems.insert(problems.end(), decoded.begin(), decoded.end());
    return static_cast<int64_t>(tiles.size());
}

// A region set: the set's rules (formats/pyramid_set.hpp), then every file as checkFile does.
int checkSet(const std::string& path, const std::string& report, int threads, bool quiet) {
    std::vector<std::string> problems;
    std::string kind = "unknown";
    std::string name = path;
    int64_t checked = 0;
    size_t listed = 0;
    nlohmann::json files = nlohmann::json::array();
    try {
        const PyramidSet set = resolvePyramidSet(path);
        listed = 1 + set.regions.size();
        name = set.name();
        kind = kindName(set.kind);
        problems = pyramidSetProblems(set);
        std::vector<std::string> all{set.main};
        all.insert(all.end(), set.regions.begin(), set.regions.end());
        for (const std::string& file : all) {
            std::error_code ec;
            if (!std::filesystem::is_regular_file(file, ec)) {
                continue; // the set's rules said so
            }
            std::vector<std::string> own;
            std::string fileKind = "unknown";
            int64_t tiles = 0;
            try {
                tiles = checkFile(file, threads, quiet, fileKind, own);
            } catch (const Error& e) {
                own.push_back(e.what());
            }
            for (std::string& p : own) {
                if (p.rfind(file + ": ", 0) != 0) {
                    p = file + ": " + p;
                }
            }
            checked += tiles;
            files.push_back({{"file", file}, {"kind", fileKind}, {"tiles_checked", tiles}, {"problems", own}});
            problems.insert(problems.end(), own.begin(), own.end());
        }
    } catch (const Error& e) {
        problems.push_back(e.what());
    }
    if (!report.empty()) {
        writeJson({{"file", path}, {"set", name}, {"kind", kind}, {"files", files}, {"tiles_checked", checked},
                   {"problems", problems}, {"ok", problems.empty()}},
                  report);
    }
    if (report != "-") {
        for (const std::string& p : problems) {
            std::printf("%s\n", p.c_str());
        }
        std::printf("%s: %s set of %zu file%s, %lld tiles checked, %zu problem%s\n", name.c_str(), kind.c_str(),
                    listed, listed == 1 ? "" : "s", static_cast<long long>(checked), problems.size(),
                    problems.size() == 1 ? "" : "s");
    }
    if (problems.empty()) {
        return kExitOk;
    }
    sayFailure(reasonLine("", problems));
    return kExitFailure;
}

} // namespace

CommandRunner setupCheckCommand(CLI::App& app) {
    auto file = std::make_shared<std::string>();
    auto report = std::make_shared<std::string>();
    auto threads = std::make_shared<int>(0);
    auto quiet = std::make_shared<bool>(false);
    app.add_option("FILE", *file,
                   "Residual (DEM) or ortho pyramid file, or a region set (its main file, index or directory)")
        ->required();
    addReportOption(app, *report, "the result");
    addThreadsOption(app, *threads);
    app.add_flag("-q,--quiet", *quiet, "No progress on stderr (a failure's line stays)");
    addProgressOption(app);
    return [file, report, threads, quiet]() {
        const int workers = workerThreads(*threads); // before any file: a bad count is the command line's fault
        bool set = false;
        try {
            set = !findRegionIndex(*file).empty();
        } catch (const Error&) {
            set = true; // a directory without one index: reported as the set's problem
        }
        if (set) {
            return checkSet(*file, *report, workers, *quiet);
        }
        std::vector<std::string> problems;
        std::string kind = "unknown";
        int64_t checked = 0;
        try {
            checked = checkFile(*file, workers, *quiet, kind, problems);
        } catch (const Error& e) {
            problems.push_back(e.what());
        }
        if (!report->empty()) {
            writeJson({{"file", *file}, {"kind", kind}, {"tiles_checked", checked}, {"problems", problems},
                       {"ok", problems.empty()}},
                      *report);
        }
        if (*report != "-") {
            for (const std::string& p : problems) {
                std::printf("%s\n", p.c_str());
            }
            std::printf("%s: %s, %lld tiles checked, %zu problem%s\n", file->c_str(), kind.c_str(),
                        static_cast<long long>(checked), problems.size(), problems.size() == 1 ? "" : "s");
        }
        if (problems.empty()) {
            return kExitOk;
        }
        sayFailure(reasonLine(*file, problems));
        return kExitFailure;
    };
}

} // namespace pyramid::cli
