// `pyramid check SET [--report FILE|-]`: the structure validated, every tile decoded; for a region set
// (its main file, index or directory) every file, and the set's own rules; for a directory that
// is not one set alone, every pyramid under it.
#include <algorithm>
#include <atomic>
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

// Every tile decoded; the problems found. With `leftOut`, a tile left out (an empty byte range:
// imagery beyond the resolution of the parts there, which a reader magnifies from its parent,
// doc/format.md 1.5) is counted there, not a problem, unless it is the root of a file rooted at
// level 0, above which there is nothing to magnify.
template <class Reader>
std::vector<std::string> decodeAll(const std::string& file, const Reader& reader, const std::vector<TileRef>& tiles,
                                   int threads, bool quiet, std::atomic<int64_t>* leftOut = nullptr) {
    std::vector<std::string> errors(tiles.size());
    const bool rootedAtZero = reader.header().rootLevel == 0;
    Progress progress(file, static_cast<int64_t>(tiles.size()), quiet, Progress::OffTerminal::Silent);
    parallelFor(static_cast<int64_t>(tiles.size()), threads, [&](int64_t k) {
        const TileRef& t = tiles[static_cast<size_t>(k)];
        try {
            reader.readTile(t.level, t.tx, t.ty);
        } catch (const MissingTileError& e) {
            if (leftOut && !(rootedAtZero && t.level == 0)) {
                ++*leftOut;
            } else {
                errors[static_cast<size_t>(k)] = e.what();
            }
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
// returns the tiles checked (each decoded, found left out, or found broken), the left-out ones
// (ortho files only) in `leftOut`. Throws Error when the file cannot be opened as a pyramid.
int64_t checkFile(const std::string& file, int threads, bool quiet, std::string& kind,
                  std::vector<std::string>& problems, int64_t& leftOut) {
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
    std::atomic<int64_t> missing{0};
    auto decoded = decodeAll(file, *reader, tiles, threads, quiet, &missing);
    problems.insert(problems.end(), decoded.begin(), decoded.end());
    leftOut = missing.load();
    return static_cast<int64_t>(tiles.size());
}

// "N tiles checked" and, where there are any, how many of them are left out.
std::string tilesChecked(int64_t checked, int64_t leftOut) {
    return std::to_string(checked) + " tiles checked" +
           (leftOut > 0 ? " (" + std::to_string(leftOut) + " left out)" : std::string());
}

// What checking one pyramid (a file alone or a region set) found.
struct Checked {
    nlohmann::json report;             // the command's report for it alone
    std::vector<std::string> problems; // each naming its file
    std::vector<std::string> lines;    // what it prints on stdout: its problems, then its summary
    int64_t tiles = 0;
    int64_t leftOut = 0; // of `tiles`
};

// A file alone: its structure validated and every tile decoded.
Checked checkAlone(const std::string& file, int threads, bool quiet) {
    std::vector<std::string> problems;
    std::string kind = "unknown";
    int64_t checked = 0, leftOut = 0;
    try {
        checked = checkFile(file, threads, quiet, kind, problems, leftOut);
    } catch (const Error& e) {
        problems.push_back(e.what());
    }
    Checked c;
    c.report = {{"file", file},         {"kind", kind},         {"tiles_checked", checked},
                {"tiles_left_out", leftOut}, {"problems", problems}, {"ok", problems.empty()}};
    c.lines = problems;
    c.lines.push_back(file + ": " + kind + ", " + tilesChecked(checked, leftOut) + ", " +
                      std::to_string(problems.size()) + " problem" + (problems.size() == 1 ? "" : "s"));
    for (std::string& p : problems) {
        if (p.rfind(file + ": ", 0) != 0) {
            p = file + ": " + p;
        }
    }
    c.problems = std::move(problems);
    c.tiles = checked;
    c.leftOut = leftOut;
    return c;
}

// A region set: the set's rules (formats/pyramid_set.hpp), then every file as checkFile does.
Checked checkSet(const std::string& path, int threads, bool quiet) {
    std::vector<std::string> problems;
    std::string kind = "unknown";
    std::string name = path;
    int64_t checked = 0, leftOut = 0;
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
            Checked one = checkAlone(file, threads, quiet);
            checked += one.tiles;
            leftOut += one.leftOut;
            files.push_back({{"file", file}, {"kind", one.report["kind"]}, {"tiles_checked", one.tiles},
                             {"tiles_left_out", one.leftOut}, {"problems", one.problems}});
            problems.insert(problems.end(), one.problems.begin(), one.problems.end());
        }
    } catch (const Error& e) {
        problems.push_back(e.what());
    }
    Checked c;
    c.report = {{"file", path},        {"set", name},           {"kind", kind},
                {"files", files},      {"tiles_checked", checked}, {"tiles_left_out", leftOut},
                {"problems", problems}, {"ok", problems.empty()}};
    c.lines = problems;
    c.lines.push_back(name + ": " + kind + " set of " + std::to_string(listed) + " file" + (listed == 1 ? "" : "s") +
                      ", " + tilesChecked(checked, leftOut) + ", " + std::to_string(problems.size()) +
                      " problem" + (problems.size() == 1 ? "" : "s"));
    c.problems = std::move(problems);
    c.tiles = checked;
    c.leftOut = leftOut;
    return c;
}

// Every pyramid under a directory, each checked as it would be alone, and their totals.
Checked checkDirectory(const std::string& directory, const PyramidsUnder& found, int threads, bool quiet) {
    Checked c;
    nlohmann::json pyramids = nlohmann::json::array();
    auto add = [&](Checked one) {
        c.lines.insert(c.lines.end(), one.lines.begin(), one.lines.end());
        c.tiles += one.tiles;
        c.leftOut += one.leftOut;
        c.problems.insert(c.problems.end(), one.problems.begin(), one.problems.end());
        pyramids.push_back(std::move(one.report));
    };
    for (const std::string& index : found.sets) {
        add(checkSet(index, threads, quiet));
    }
    for (const std::string& file : found.files) {
        add(checkAlone(file, threads, quiet));
    }
    const size_t count = found.sets.size() + found.files.size();
    if (count == 0) {
        c.problems.push_back(directory + ": no pyramid (a *.dat file or a *.regions.json index) in this directory");
        c.lines.push_back(c.problems.back());
    }
    c.report = {{"file", directory},          {"pyramids", pyramids},      {"tiles_checked", c.tiles},
                {"tiles_left_out", c.leftOut}, {"problems", c.problems}, {"ok", c.problems.empty()}};
    c.lines.push_back(directory + ": " + std::to_string(count) + " pyramid" + (count == 1 ? "" : "s") + " (" +
                      std::to_string(found.sets.size()) + " region set" + (found.sets.size() == 1 ? "" : "s") +
                      "), " + tilesChecked(c.tiles, c.leftOut) + ", " + std::to_string(c.problems.size()) +
                      " problem" + (c.problems.size() == 1 ? "" : "s"));
    return c;
}

} // namespace

CommandRunner setupCheckCommand(CLI::App& app) {
    auto file = std::make_shared<std::string>();
    auto report = std::make_shared<std::string>();
    auto threads = std::make_shared<int>(0);
    auto quiet = std::make_shared<bool>(false);
    app.add_option("FILE", *file,
                   "Residual (DEM) or ortho pyramid file, a region set (its main file, index or directory), or a "
                   "directory: every pyramid under it")
        ->required();
    addReportOption(app, *report, "the result");
    addThreadsOption(app, *threads);
    app.add_flag("-q,--quiet", *quiet, "No progress on stderr (a failure's line stays)");
    addProgressOption(app);
    return [file, report, threads, quiet]() {
        const int workers = workerThreads(*threads); // before any file: a bad count is the command line's fault
        Checked c;
        std::error_code ec;
        if (std::filesystem::is_directory(*file, ec)) {
            // One set and nothing else: the set as before; else every pyramid under it.
            const PyramidsUnder found = pyramidsUnder(*file);
            const bool oneSet = found.sets.size() == 1 && found.files.empty() &&
                                std::filesystem::equivalent(std::filesystem::path(found.sets[0]).parent_path(), *file, ec);
            c = oneSet ? checkSet(*file, workers, *quiet) : checkDirectory(*file, found, workers, *quiet);
        } else {
            bool set = false;
            try {
                set = !findRegionIndex(*file).empty();
            } catch (const Error&) {
                set = true; // reported as the set's problem
            }
            c = set ? checkSet(*file, workers, *quiet) : checkAlone(*file, workers, *quiet);
        }
        if (!report->empty()) {
            writeJson(c.report, *report);
        }
        if (*report != "-") {
            for (const std::string& line : c.lines) {
                std::printf("%s\n", line.c_str());
            }
        }
        if (c.problems.empty()) {
            return kExitOk;
        }
        sayFailure(reasonLine("", c.problems));
        return kExitFailure;
    };
}

} // namespace pyramid::cli
