// `pyramid check FILE [--json]`: the structure validated, every tile decoded.
#include <algorithm>
#include <cstdio>
#include <functional>
#include <memory>
#include <thread>

#include <CLI/CLI.hpp>

#include "cli/cli_common.hpp"
#include "formats/error.hpp"
#include "formats/ortho_file.hpp"
#include "formats/pyramid_kind.hpp"
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
std::vector<std::string> decodeAll(const Reader& reader, const std::vector<TileRef>& tiles, int threads) {
    std::vector<std::string> errors(tiles.size());
    parallelFor(static_cast<int64_t>(tiles.size()), threads, [&](int64_t k) {
        const TileRef& t = tiles[static_cast<size_t>(k)];
        try {
            reader.readTile(t.level, t.tx, t.ty);
        } catch (const Error& e) {
            errors[static_cast<size_t>(k)] = e.what();
        }
    });
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
std::string reasonLine(const std::string& file, const std::vector<std::string>& problems) {
    std::string line = problems.front();
    if (line.rfind(file + ": ", 0) != 0) {
        line = file + ": " + line;
    }
    if (problems.size() > 1) {
        const size_t more = problems.size() - 1;
        line += " (and " + std::to_string(more) + " more problem" + (more == 1 ? "" : "s") + ")";
    }
    return line;
}

} // namespace

CommandRunner setupCheckCommand(CLI::App& app) {
    auto file = std::make_shared<std::string>();
    auto json = std::make_shared<bool>(false);
    auto threads = std::make_shared<int>(0);
    app.add_option("FILE", *file, "Residual (DEM) or ortho pyramid file")->required();
    app.add_flag("--json", *json, "Print the result as JSON");
    app.add_option("--threads", *threads, "Worker threads (default: all cores)");
    const std::string program = app.get_parent() ? app.get_parent()->get_name() : app.get_name();
    return [file, json, threads, program]() {
        std::vector<std::string> problems;
        std::string kind = "unknown";
        int64_t checked = 0;
        try {
            const OpenedPyramid opened = openPyramid(*file);
            const PyramidKind k = opened.kind;
            kind = kindName(k);
            const int n = *threads > 0 ? *threads : 0;
            const int t = n > 0 ? n : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
            if (k == PyramidKind::Residual) {
                const auto& reader = opened.residual;
                const auto& h = reader->header();
                const auto tiles = allTiles(h, [&](int l) { return h.tilesPerSide(l); });
                checkOverlaps(reader->table(), problems);
                auto decoded = decodeAll(*reader, tiles, t);
                problems.insert(problems.end(), decoded.begin(), decoded.end());
                checked = static_cast<int64_t>(tiles.size());
            } else {
                const auto& reader = opened.ortho;
                const auto& h = reader->header();
                const auto tiles = allTiles(h, [](int l) { return int64_t{1} << l; });
                checkOverlaps(reader->table(), problems);
                auto decoded = decodeAll(*reader, tiles, t);
                problems.insert(problems.end(), decoded.begin(), decoded.end());
                checked = static_cast<int64_t>(tiles.size());
            }
        } catch (const Error& e) {
            problems.push_back(e.what());
        }
        if (*json) {
            writeJson({{"file", *file}, {"kind", kind}, {"tiles_checked", checked}, {"problems", problems},
                       {"ok", problems.empty()}},
                      "-");
        } else {
            for (const std::string& p : problems) {
                std::printf("%s\n", p.c_str());
            }
            std::printf("%s: %s, %lld tiles decoded, %zu problem%s\n", file->c_str(), kind.c_str(),
                        static_cast<long long>(checked), problems.size(), problems.size() == 1 ? "" : "s");
        }
        if (problems.empty()) {
            return kExitOk;
        }
        std::fflush(stdout);
        std::fprintf(stderr, "%s: %s\n", program.c_str(), reasonLine(*file, problems).c_str());
        return kExitFailure;
    };
}

} // namespace pyramid::cli
