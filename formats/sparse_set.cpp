#include "formats/sparse_set.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <limits>
#include <string_view>
#include <tuple>
#include <unordered_map>

#include "formats/atomic_file.hpp"
#include "formats/error.hpp"
#include "formats/file_io.hpp"
#include "formats/temporaries.hpp"
#include "formats/tile_table.hpp"

namespace pyramid {

// The spool: blobs appended to a temporary that is never committed, identical ones once.
struct SparseTileLog::Spool {
    AtomicFile file;
    uint64_t end = 0;
    std::unordered_multimap<size_t, std::pair<uint64_t, uint32_t>> byHash;

    explicit Spool(const std::string& path) : file(path) {}

    std::vector<uint8_t> read(uint64_t offset, uint32_t size) const {
        std::vector<uint8_t> bytes(size);
        if (!readFully(file.fd(), bytes.data(), bytes.size(), offset)) {
            fail(outputName(file.path()), errno ? std::string("cannot read the spooled tiles: ") + std::strerror(errno)
                                                : "the spooled tiles end early");
        }
        return bytes;
    }

    std::pair<uint64_t, uint32_t> put(std::span<const uint8_t> blob) {
        const size_t hash =
            std::hash<std::string_view>{}(std::string_view(reinterpret_cast<const char*>(blob.data()), blob.size()));
        auto [first, last] = byHash.equal_range(hash);
        for (auto it = first; it != last; ++it) {
            if (it->second.second == blob.size()) {
                const std::vector<uint8_t> stored = read(it->second.first, it->second.second);
                if (std::memcmp(stored.data(), blob.data(), blob.size()) == 0) {
                    return it->second;
                }
            }
        }
        const std::pair<uint64_t, uint32_t> at{end, static_cast<uint32_t>(blob.size())};
        file.writeAt(end, blob.data(), blob.size());
        end += blob.size();
        byHash.emplace(hash, at);
        return at;
    }
};

SparseTileLog::SparseTileLog(const std::string& spoolPath, std::vector<uint8_t> emptyBlob)
    : spool_(std::make_unique<Spool>(spoolPath)), emptyBlob_(std::move(emptyBlob)) {}

SparseTileLog::~SparseTileLog() = default;

void SparseTileLog::add(int level, int tx, int ty, std::span<const uint8_t> blob) {
    if (blob.empty() || blob.size() > std::numeric_limits<uint32_t>::max()) {
        fail(outputName(spool_->file.path()), "tile " + tileCoordinates(level, tx, ty) + " has " +
                                                  std::to_string(blob.size()) + " bytes");
    }
    Item item;
    item.level = static_cast<int8_t>(level);
    item.tx = tx;
    item.ty = ty;
    item.empty = blob.size() == emptyBlob_.size() && std::equal(blob.begin(), blob.end(), emptyBlob_.begin());
    std::tie(item.offset, item.size) = spool_->put(blob);
    dataTiles_ += item.empty ? 0 : 1;
    items_.push_back(item);
}

void SparseTileLog::addEmptySubtree(int level, int tx, int ty) {
    Item item;
    item.level = static_cast<int8_t>(level);
    item.tx = tx;
    item.ty = ty;
    item.empty = true;
    items_.push_back(item);
}

void SparseTileLog::addLeftOutSubtree(int level, int tx, int ty) {
    addEmptySubtree(level, tx, ty);
    items_.back().leftOut = true;
}

std::vector<uint8_t> SparseTileLog::read(const Item& item) const {
    return item.size == 0 ? emptyBlob_ : spool_->read(item.offset, item.size);
}

namespace {

uint64_t tileKey(int tx, int ty) { return (static_cast<uint64_t>(static_cast<uint32_t>(tx)) << 32) | static_cast<uint32_t>(ty); }

// Tiles in a file of levels 0..d below its root: a full quadtree from the root, or for the main
// file one tile per level below minLevel first.
double fileTiles(int rootLevel, int last, int minLevel) {
    if (rootLevel > 0) {
        return (std::pow(4.0, last - rootLevel + 1) - 1.0) / 3.0;
    }
    return minLevel + (std::pow(4.0, last - minLevel + 1) - 1.0) / 3.0;
}

// The stored tiles of a log, by level, with what the layout needs of each.
struct TileTree {
    struct Node {
        int tx = 0, ty = 0;
        uint64_t bytes = 0;   // its blob (0 for an empty tile: the empty blob is counted once a file)
        bool wanted = false;  // it or a tile below holds data
        int deepest = -1;     // the deepest level of a wanted tile at or below it
        int last = -1;        // the chosen last level of a file rooted here
    };
    std::vector<std::vector<Node>> levels;
    std::vector<std::unordered_map<uint64_t, size_t>> at;

    const Node* find(int level, int tx, int ty) const {
        if (level < 0 || level >= static_cast<int>(levels.size())) {
            return nullptr;
        }
        const auto it = at[static_cast<size_t>(level)].find(tileKey(tx, ty));
        return it == at[static_cast<size_t>(level)].end() ? nullptr : &levels[static_cast<size_t>(level)][it->second];
    }
    Node* find(int level, int tx, int ty) {
        return const_cast<Node*>(static_cast<const TileTree*>(this)->find(level, tx, ty));
    }
};

TileTree treeOf(const SparseTileLog& log, const SparseShape& shape, const std::string& path) {
    TileTree tree;
    tree.levels.resize(static_cast<size_t>(shape.maxLevel) + 1);
    tree.at.resize(tree.levels.size());
    for (const SparseTileLog::Item& item : log.items()) {
        if (item.size == 0) {
            continue; // an empty subtree: nothing wanted there
        }
        if (item.level < 0 || item.level > shape.maxLevel) {
            fail(path, "tile " + tileCoordinates(item.level, item.tx, item.ty) + " is outside the pyramid");
        }
        auto& index = tree.at[static_cast<size_t>(item.level)];
        auto& nodes = tree.levels[static_cast<size_t>(item.level)];
        if (!index.emplace(tileKey(item.tx, item.ty), nodes.size()).second) {
            fail(path, "tile " + tileCoordinates(item.level, item.tx, item.ty) + " is given twice");
        }
        TileTree::Node node;
        node.tx = item.tx;
        node.ty = item.ty;
        node.bytes = item.empty ? 0 : item.size;
        node.wanted = !item.empty || item.level <= shape.minLevel;
        node.deepest = node.wanted ? item.level : -1;
        nodes.push_back(node);
    }
    // Wanted upwards: a wanted tile's parent is wanted, and must have been stored.
    for (int l = shape.maxLevel; l > 0; --l) {
        for (const TileTree::Node& n : tree.levels[static_cast<size_t>(l)]) {
            if (!n.wanted) {
                continue;
            }
            const int pl = l - 1;
            const int px = pl < shape.minLevel ? 0 : n.tx >> 1, py = pl < shape.minLevel ? 0 : n.ty >> 1;
            TileTree::Node* p = tree.find(pl, px, py);
            if (!p) {
                fail(path, "tile " + tileCoordinates(l, n.tx, n.ty) + " holds data but its parent was not stored");
            }
            p->wanted = true;
            p->deepest = std::max(p->deepest, n.deepest);
        }
    }
    return tree;
}

} // namespace

std::vector<SplitFile> chooseSparseFiles(const SparseTileLog& log, const SparseShape& shape, const std::string& output) {
    const std::string path = outputName(output); // the output's name, not its staged file's
    TileTree tree = treeOf(log, shape, path);
    const double entry = 2.0 * shape.offsetBytes;
    const uint64_t emptyBytes = log.emptyBlob().size();
    const auto fits = [&](double tiles, uint64_t data) {
        data += emptyBytes;
        const double bytes = static_cast<double>(shape.headerBytes) + entry * tiles + static_cast<double>(data);
        return data <= shape.maxOffset && (shape.maxFileBytes == 0 || bytes <= static_cast<double>(shape.maxFileBytes));
    };
    // Bottom-up, for each wanted tile below the main file's first levels: the cost of the best
    // file rooted there (with the files nested in it), and per level below it the sums over its
    // wanted descendants of those costs (cost[k]) and of their bytes (bytes[k]).
    struct Sums {
        std::vector<double> cost;    // cost[0]: its own best file; cost[k]: its descendants' at depth k
        std::vector<uint64_t> bytes; // bytes[k]: its descendants' blobs at depth k
    };
    std::vector<std::unordered_map<uint64_t, Sums>> below(2);
    const int firstRoot = std::max(1, shape.minLevel + 1);
    std::vector<double> levelCost(static_cast<size_t>(shape.maxLevel) + 2, 0.0);
    std::vector<uint64_t> levelBytes(static_cast<size_t>(shape.maxLevel) + 2, 0);
    for (int l = shape.maxLevel; l >= firstRoot; --l) {
        std::unordered_map<uint64_t, Sums>& children = below[(l + 1) & 1];
        std::unordered_map<uint64_t, Sums>& here = below[l & 1];
        here.clear();
        for (TileTree::Node& n : tree.levels[static_cast<size_t>(l)]) {
            if (!n.wanted) {
                continue;
            }
            const int depth = n.deepest - l;
            Sums s;
            s.cost.assign(static_cast<size_t>(depth) + 1, 0.0);
            s.bytes.assign(static_cast<size_t>(depth) + 1, 0);
            s.bytes[0] = n.bytes;
            for (int c = 0; c < 4; ++c) {
                const auto it = children.find(tileKey(2 * n.tx + (c & 1), 2 * n.ty + (c >> 1)));
                if (it == children.end()) {
                    continue;
                }
                for (size_t k = 0; k < it->second.cost.size(); ++k) {
                    s.cost[k + 1] += it->second.cost[k];
                    s.bytes[k + 1] += it->second.bytes[k];
                }
            }
            double best = std::numeric_limits<double>::infinity();
            uint64_t data = 0;
            for (int d = 0; d <= depth; ++d) {
                data += s.bytes[static_cast<size_t>(d)];
                const double tiles = fileTiles(l, l + d, 0);
                if (!fits(tiles, data)) {
                    break;
                }
                const double cost = static_cast<double>(kSparseFileCost) + entry * tiles +
                                    (d < depth ? s.cost[static_cast<size_t>(d) + 1] : 0.0);
                if (cost <= best) { // ties: the deeper file, fewer files
                    best = cost;
                    n.last = l + d;
                }
            }
            if (n.last < 0) {
                fail(path, "the tile " + tileCoordinates(l, n.tx, n.ty) + " alone passes the file size limit of " +
                               std::to_string(shape.maxFileBytes ? shape.maxFileBytes : shape.maxOffset) + " bytes");
            }
            s.cost[0] = best;
            levelCost[static_cast<size_t>(l)] += best;
            here.emplace(tileKey(n.tx, n.ty), std::move(s));
        }
        children.clear();
    }
    // The main file: levels 0..c, c from minLevel to the deepest wanted level.
    int deepest = shape.minLevel;
    for (int l = 0; l <= shape.maxLevel; ++l) {
        for (const TileTree::Node& n : tree.levels[static_cast<size_t>(l)]) {
            if (n.wanted) {
                deepest = std::max(deepest, l);
                levelBytes[static_cast<size_t>(l)] += n.bytes;
            }
        }
    }
    double best = std::numeric_limits<double>::infinity();
    int mainLast = -1;
    uint64_t data = 0;
    for (int l = 0; l < shape.minLevel; ++l) {
        data += levelBytes[static_cast<size_t>(l)];
    }
    for (int c = shape.minLevel; c <= deepest; ++c) {
        data += levelBytes[static_cast<size_t>(c)];
        const double tiles = fileTiles(0, c, shape.minLevel);
        if (!fits(tiles, data)) {
            break;
        }
        const double cost = entry * tiles + (c < deepest ? levelCost[static_cast<size_t>(c) + 1] : 0.0);
        if (cost <= best) {
            best = cost;
            mainLast = c;
        }
    }
    if (mainLast < 0) {
        fail(path, "the levels 0.." + std::to_string(shape.minLevel) + " of the main file alone pass the file size limit of " +
                       std::to_string(shape.maxFileBytes ? shape.maxFileBytes : shape.maxOffset) + " bytes");
    }
    // Top-down: a wanted tile roots a file when the file holding its parent ends above it.
    std::vector<SplitFile> files;
    SplitFile main;
    main.last = mainLast;
    files.push_back(main);
    std::vector<std::unordered_map<uint64_t, int>> holderLast(2);
    for (int l = mainLast + 1; l <= deepest; ++l) {
        std::unordered_map<uint64_t, int>& parents = holderLast[(l + 1) & 1];
        std::unordered_map<uint64_t, int>& here = holderLast[l & 1];
        here.clear();
        for (const TileTree::Node& n : tree.levels[static_cast<size_t>(l)]) {
            if (!n.wanted) {
                continue;
            }
            int last = mainLast;
            if (l - 1 > mainLast) {
                const auto it = parents.find(tileKey(n.tx >> 1, n.ty >> 1));
                if (it == parents.end()) {
                    fail(path, "tile " + tileCoordinates(l, n.tx, n.ty) + " is wanted but its parent is not");
                }
                last = it->second;
            }
            if (last < l) {
                SplitFile f;
                f.root = RegionRoot{l, n.tx, n.ty};
                f.last = n.last;
                files.push_back(f);
                last = n.last;
            }
            here.emplace(tileKey(n.tx, n.ty), last);
        }
        parents.clear();
    }
    std::sort(files.begin() + 1, files.end(), [](const SplitFile& a, const SplitFile& b) {
        return std::tie(a.root.level, a.root.tx, a.root.ty) < std::tie(b.root.level, b.root.tx, b.root.ty);
    });
    return files;
}

std::vector<SplitFile> writeSparseSet(const SparseTileLog& log, const SparseShape& shape, std::vector<SplitFile> files,
                                      const std::string& mainName, const SplitHeaderFactory& header,
                                      const std::function<std::string(const std::string&)>& place) {
    // Which file roots where: (level, key) -> file.
    std::vector<std::unordered_map<uint64_t, size_t>> roots(static_cast<size_t>(shape.maxLevel) + 1);
    for (size_t k = 0; k < files.size(); ++k) {
        SplitFile& f = files[k];
        f.name = f.root.level == 0 ? mainName : regionFilePath(mainName, f.root);
        roots[static_cast<size_t>(f.root.level)].emplace(tileKey(f.root.tx, f.root.ty), k);
    }
    // The file holding absolute tile (level, tx, ty): the deepest whose root is at or above it, if
    // its levels reach the tile's; none (SIZE_MAX) otherwise.
    const auto holder = [&](int level, int tx, int ty) -> size_t {
        for (int a = level; a >= 0; --a) {
            const int d = level - a;
            const int rx = a == 0 ? 0 : tx >> d, ry = a == 0 ? 0 : ty >> d;
            const auto it = roots[static_cast<size_t>(a)].find(tileKey(rx, ry));
            if (it != roots[static_cast<size_t>(a)].end()) {
                return files[it->second].last >= level ? it->second : SIZE_MAX;
            }
        }
        return SIZE_MAX;
    };
    // In batches of files open at once (each is a file descriptor and its offset table).
    constexpr size_t kOpenFiles = 128;
    for (size_t first = 0; first < files.size(); first += kOpenFiles) {
        const size_t end = std::min(files.size(), first + kOpenFiles);
        std::vector<std::unique_ptr<TileTableWriter>> out(end - first);
        for (size_t k = first; k < end; ++k) {
            const SplitFile& f = files[k];
            const int minLevel = f.root.level == 0 ? shape.minLevel : 0;
            const auto tiles = static_cast<int64_t>(fileTiles(f.root.level, f.last, minLevel) + 0.5);
            const std::string path = place(f.name);
            out[k - first] = std::make_unique<TileTableWriter>(path, header(path, f), tiles, shape.offsetBytes, shape.maxOffset);
        }
        const auto indexIn = [&](size_t k, int level, int tx, int ty) {
            const SplitFile& f = files[k];
            if (f.root.level == 0) {
                return SetFileLayout{shape.minLevel}.tileIndex(level, tx, ty);
            }
            const RegionRoot r = regionRelativeTile(f.root, level, tx, ty);
            return SetFileLayout{0}.tileIndex(r.level, r.tx, r.ty);
        };
        const auto write = [&](size_t k, int level, int tx, int ty, std::span<const uint8_t> blob) {
            out[k - first]->write(indexIn(k, level, tx, ty), blob);
        };
        const auto leaveOut = [&](size_t k, int level, int tx, int ty) {
            out[k - first]->leaveOut(indexIn(k, level, tx, ty));
        };
        for (const SparseTileLog::Item& item : log.items()) {
            const size_t k = holder(item.level, item.tx, item.ty);
            if (k == SIZE_MAX || k < first || k >= end) {
                continue;
            }
            if (item.size > 0) {
                write(k, item.level, item.tx, item.ty, log.read(item));
                continue;
            }
            // An empty subtree: its tiles down to the file's last level, depth first, in the order
            // the encoder would have given them one by one.
            const int last = files[k].last;
            const std::function<void(int, int, int)> walk = [&](int l, int x, int y) {
                if (item.leftOut) {
                    leaveOut(k, l, x, y);
                } else {
                    write(k, l, x, y, log.emptyBlob());
                }
                if (l < last) {
                    for (int c = 0; c < 4; ++c) {
                        walk(l + 1, 2 * x + (c & 1), 2 * y + (c >> 1));
                    }
                }
            };
            walk(item.level, item.tx, item.ty);
        }
        for (size_t k = first; k < end; ++k) {
            TileTableWriter& w = *out[k - first];
            w.commit();
            const int minLevel = files[k].root.level == 0 ? shape.minLevel : 0;
            files[k].bytes = shape.headerBytes +
                             2 * static_cast<uint64_t>(shape.offsetBytes) *
                                 static_cast<uint64_t>(fileTiles(files[k].root.level, files[k].last, minLevel) + 0.5) +
                             w.bytesWritten();
            files[k].sharedTiles = w.sharedTiles();
        }
    }
    return files;
}

} // namespace pyramid
