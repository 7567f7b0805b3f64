#include "libpyramid/input/hfa_reader.hpp"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstring>
#include <vector>

#include "formats/byte_source.hpp"
#include "formats/error.hpp"
#include "libpyramid/input/datum_epsg.hpp"
#include "libpyramid/input/hfa_blocks.hpp"
#include "libpyramid/input/hfa_dictionary.hpp"
#include "libpyramid/input/hfa_file.hpp"
#include "libpyramid/input/hfa_spill.hpp"
#include "libpyramid/input/sidecar_georeference.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid {

namespace {

constexpr uint64_t kMaxBlockBytes = uint64_t{64} << 20;  // a block, stored or decoded

struct Layer {
    std::string name;
    HfaPixel pixel = HfaPixel::U8;
    int width = 0, height = 0, blockWidth = 0, blockHeight = 0, blocksAcross = 0;
    std::string file; // that holds the blocks: the .img, or its spill file
    std::vector<HfaBlockPlace> blocks;
    std::optional<double> nodata;
};

struct Header {
    RasterInfo info;
    std::vector<Layer> layers;
};

// The ESRI WKT of a ProjectionX node (Eprj_MapProjection842): a MIF object of its own dictionary.
std::string peString(const HfaFile& f, const HfaNode& n, const std::string& path) {
    const std::vector<uint8_t> data = f.data(n);
    const HfaDictionary& d = f.dictionary();
    const std::optional<HfaValue> projection = d.field(n.type, data, "projection");
    if (!projection || projection->count < 1 || projection->field->type != 'x') {
        return {};
    }
    const std::string mif = projection->field->object;
    const std::span<const uint8_t> object = d.object(*projection);
    const std::string type = d.stringField(mif, object, "type");
    const std::string dictionary = d.stringField(mif, object, "MIFDictionary");
    const std::optional<HfaValue> bytes = d.field(mif, object, "MIFObject");
    if (type.empty() || dictionary.empty() || !bytes) {
        return {};
    }
    const HfaDictionary inner(dictionary, path);
    return inner.stringField(type, bytes->bytes.first(std::min<size_t>(bytes->bytes.size(), bytes->count)), "coordSys");
}

// The layer's placement: Map_Info in the CRS of ProjectionX or of Projection and its Datum.
std::optional<Georeference> placement(const HfaFile& f, const HfaNode& layer, const std::string& path) {
    const HfaDictionary& d = f.dictionary();
    const std::optional<HfaNode> mapInfo = f.child(layer, "Map_Info");
    if (!mapInfo) {
        return std::nullopt;
    }
    const std::vector<uint8_t> info = f.data(*mapInfo);
    const auto coordinate = [&](const char* field, const char* type, const char* a, const char* b) {
        const std::optional<HfaValue> v = d.field(mapInfo->type, info, field);
        if (!v || v->count < 1 || v->field->object != type) {
            fail(path, std::string("its ERDAS Imagine Map_Info has no ") + field);
        }
        const std::span<const uint8_t> o = d.object(*v);
        const std::optional<HfaValue> va = d.field(type, o, a), vb = d.field(type, o, b);
        if (!va || !vb) {
            fail(path, std::string("its ERDAS Imagine Map_Info's ") + field + " has no " + a + " or " + b);
        }
        return std::array<double, 2>{d.number(*va), d.number(*vb)};
    };
    const std::array<double, 2> corner = coordinate("upperLeftCenter", "Eprj_Coordinate", "x", "y");
    const std::array<double, 2> size = coordinate("pixelSize", "Eprj_Size", "width", "height");
    if (!std::isfinite(corner[0]) || !std::isfinite(corner[1]) || !(size[0] > 0) || !(size[1] > 0) ||
        !std::isfinite(size[0]) || !std::isfinite(size[1])) {
        fail(path, "its ERDAS Imagine Map_Info's corner or pixel size is no finite position and positive size");
    }
    const std::array<double, 6> t = {corner[0] - size[0] / 2, size[0], 0.0, corner[1] + size[1] / 2, 0.0, -size[1]};
    if (const std::optional<HfaNode> x = f.child(layer, "ProjectionX")) {
        if (const std::string wkt = peString(f, *x, path); !wkt.empty()) {
            if (std::optional<Georeference> g = placedInWktCrs(wkt, t, path)) {
                return g;
            }
        }
    }
    const std::optional<HfaNode> projection = f.child(layer, "Projection");
    if (!projection) {
        return std::nullopt;
    }
    const std::vector<uint8_t> p = f.data(*projection);
    const std::optional<HfaValue> number = d.field(projection->type, p, "proNumber");
    const std::optional<HfaValue> zone = d.field(projection->type, p, "proZone");
    const std::optional<HfaValue> params = d.field(projection->type, p, "proParams");
    NamedDatum datum = NamedDatum::Other;
    if (const std::optional<HfaNode> datumNode = f.child(*projection, "Datum")) {
        const std::vector<uint8_t> bytes = f.data(*datumNode);
        if (const std::optional<HfaValue> name = d.field(datumNode->type, bytes, "datumname")) {
            datum = namedDatum(d.text(*name).c_str());
        }
    }
    int epsg = 0;
    if (number && d.integer(*number) == 0) {
        epsg = geographicEpsg(datum);
    } else if (number && d.integer(*number) == 1 && zone && params && params->count > 3) {
        epsg = utmEpsg(static_cast<int>(d.integer(*zone)), d.number(*params, 3) < 0, datum);
    }
    return epsg ? placedInEpsgCrs(epsg, t, path) : std::nullopt;
}

// The blocks a RasterDMS node lists (Edms_State's block info), in the .img itself.
void readBlockList(const HfaFile& f, const HfaNode& dms, const std::string& path, const std::string& where,
                   uint64_t blocks, Layer& l) {
    const HfaDictionary& d = f.dictionary();
    const std::vector<uint8_t> state = f.data(dms);
    const std::optional<HfaValue> info = d.field(dms.type, state, "blockinfo");
    if (!info || static_cast<uint64_t>(info->count) != blocks) {
        fail(path, where + " lists " + std::to_string(info ? info->count : 0) + " blocks, not the " +
                       std::to_string(blocks) + " its size in blocks of " + std::to_string(l.blockWidth) + " x " +
                       std::to_string(l.blockHeight) + " makes");
    }
    const std::string& type = info->field->object;
    const auto integer = [&](std::span<const uint8_t> o, const char* name) {
        const std::optional<HfaValue> v = d.field(type, o, name);
        if (!v) {
            fail(path, where + "'s blocks have no " + name);
        }
        return d.integer(*v);
    };
    l.file = path;
    l.blocks.resize(static_cast<size_t>(blocks));
    for (size_t k = 0; k < l.blocks.size(); ++k) {
        const std::span<const uint8_t> o = d.object(*info, static_cast<int>(k));
        l.blocks[k].offset = static_cast<uint32_t>(integer(o, "offset"));
        l.blocks[k].size = static_cast<uint32_t>(integer(o, "size"));
        l.blocks[k].valid = integer(o, "logvalid") != 0;
        l.blocks[k].compressed = integer(o, "compressionType") != 0;
    }
}

Layer readLayer(const HfaFile& f, const HfaNode& n, const std::string& path) {
    const HfaDictionary& d = f.dictionary();
    const std::vector<uint8_t> data = f.data(n);
    const auto integer = [&](const std::string& type, std::span<const uint8_t> bytes, const char* name) {
        const std::optional<HfaValue> v = d.field(type, bytes, name);
        if (!v) {
            fail(path, "its ERDAS Imagine layer \"" + printableText(n.name) + "\" has no " + name);
        }
        return d.integer(*v);
    };
    Layer l;
    l.name = n.name;
    const int64_t width = integer(n.type, data, "width"), height = integer(n.type, data, "height");
    const int64_t bw = integer(n.type, data, "blockWidth"), bh = integer(n.type, data, "blockHeight");
    const int64_t pixel = integer(n.type, data, "pixelType");
    const std::string where = "its layer \"" + printableText(n.name) + "\"";
    if (width < 1 || height < 1 || width > INT_MAX || height > INT_MAX || bw < 1 || bh < 1 ||
        pixel < 0 || pixel > 12) {
        fail(path, where + " has a size, block size or pixel type out of range");
    }
    l.pixel = static_cast<HfaPixel>(pixel);
    if (hfaSampleType(l.pixel) == SampleType::Other) {
        fail(path, where + " holds complex pixels, which are no heights or colours");
    }
    if (static_cast<uint64_t>(bw) * static_cast<uint64_t>(bh) * 8 > kMaxBlockBytes) {
        fail(path, where + "'s blocks of " + std::to_string(bw) + " x " + std::to_string(bh) + " pixels exceed 64 MB");
    }
    l.width = static_cast<int>(width);
    l.height = static_cast<int>(height);
    l.blockWidth = static_cast<int>(bw);
    l.blockHeight = static_cast<int>(bh);
    l.blocksAcross = static_cast<int>((width + bw - 1) / bw);
    const uint64_t blocks = static_cast<uint64_t>(l.blocksAcross) * static_cast<uint64_t>((height + bh - 1) / bh);
    const std::optional<HfaNode> dms = f.child(n, "RasterDMS");
    if (!dms) {
        const std::optional<HfaNode> external = f.child(n, "ExternalRasterDMS");
        if (!external) {
            fail(path, where + " has no RasterDMS node of pixel blocks");
        }
        HfaSpillBlocks spill = readHfaSpill(f, *external, path, where, l.pixel, l.blocksAcross,
                                            static_cast<int>((height + bh - 1) / bh),
                                            static_cast<size_t>(bw) * static_cast<size_t>(bh));
        l.file = std::move(spill.path);
        l.blocks = std::move(spill.blocks);
    } else {
        readBlockList(f, *dms, path, where, blocks, l);
    }
    if (const std::optional<HfaNode> nodata = f.child(n, "Eimg_NonInitializedValue")) {
        const std::vector<uint8_t> bytes = f.data(*nodata);
        if (const std::optional<HfaValue> v = d.field(nodata->type, bytes, "valueBD"); v && v->count > 0) {
            l.nodata = d.firstBaseValue(*v);
        }
    }
    return l;
}

std::optional<Header> readHeader(const std::string& path) {
    const std::unique_ptr<HfaFile> file = HfaFile::open(path, openFileSource(path));
    if (!file) {
        return std::nullopt;
    }
    const HfaFile& f = *file;
    const HfaNode root = f.root();
    Header h;
    std::optional<HfaNode> first;
    for (const HfaNode& n : f.children(root)) {
        if (n.type == "Eimg_Layer") {
            h.layers.push_back(readLayer(f, n, path));
            first = first ? first : n;
        }
    }
    if (h.layers.empty()) {
        fail(path, "this ERDAS Imagine file holds no raster layer (Eimg_Layer)");
    }
    const Layer& l = h.layers.front();
    for (const Layer& other : h.layers) {
        if (other.width != l.width || other.height != l.height || other.pixel != l.pixel ||
            other.blockWidth != l.blockWidth || other.blockHeight != l.blockHeight) {
            fail(path, "its layers \"" + printableText(l.name) + "\" and \"" + printableText(other.name) +
                           "\" differ in size, pixel type or blocks: give each as a file of its own");
        }
    }
    if (h.layers.size() > 4) {
        fail(path, "holds " + std::to_string(h.layers.size()) + " layers; a DEM has 1, imagery 3 or 4");
    }
    RasterInfo& info = h.info;
    info.width = l.width;
    info.height = l.height;
    info.channels = static_cast<int>(h.layers.size());
    info.type = hfaSampleType(l.pixel);
    info.formatName = "hfa";
    info.nodata = l.nodata;
    info.georeference = placement(f, *first, path);
    return h;
}

size_t sampleBytes(SampleType t) { return t == SampleType::UInt8 ? 1 : t == SampleType::Float32 ? 4 : 2; }

// A row of blocks at a time: every layer's blocks, decoded and interleaved into rows.
class HfaDecoder : public DecodedRows::Decoder {
public:
    explicit HfaDecoder(Header header) : header_(std::move(header)), bytes_(sampleBytes(header_.info.type)) {
        for (const Layer& layer : header_.layers) { // each layer's file: the .img, or a spill file
            const auto same = [&](const Layer& other) { return other.file == layer.file; };
            const auto first = std::find_if(header_.layers.begin(), header_.layers.end(), same);
            files_.push_back(&*first == &layer ? openFileSource(layer.file)
                                               : files_[static_cast<size_t>(first - header_.layers.begin())]);
        }
        const Layer& l = header_.layers.front();
        rowBytes_ = static_cast<size_t>(l.width) * header_.layers.size() * bytes_;
        band_.resize(rowBytes_ * static_cast<size_t>(l.blockHeight));
        block_.resize(static_cast<size_t>(l.blockWidth) * static_cast<size_t>(l.blockHeight) * bytes_);
    }

    void readRow(uint8_t* row) override {
        const int bh = header_.layers.front().blockHeight;
        if (row_ % bh == 0) {
            readBlockRow(row_ / bh);
        }
        std::memcpy(row, &band_[static_cast<size_t>(row_ % bh) * rowBytes_], rowBytes_);
        ++row_;
    }

    void finish() override {}

private:
    void readBlockRow(int by) {
        const size_t channels = header_.layers.size();
        for (size_t c = 0; c < channels; ++c) {
            const Layer& l = header_.layers[c];
            const int rows = std::min(l.blockHeight, l.height - by * l.blockHeight);
            const size_t pixels = static_cast<size_t>(l.blockWidth) * static_cast<size_t>(l.blockHeight);
            for (int bx = 0; bx < l.blocksAcross; ++bx) {
                const size_t k = static_cast<size_t>(by) * static_cast<size_t>(l.blocksAcross) + static_cast<size_t>(bx);
                decodeBlock(l, *files_[c], l.blocks[k], k, pixels);
                const int x0 = bx * l.blockWidth, columns = std::min(l.blockWidth, l.width - x0);
                for (int r = 0; r < rows; ++r) {
                    const uint8_t* from = &block_[static_cast<size_t>(r) * static_cast<size_t>(l.blockWidth) * bytes_];
                    uint8_t* to = &band_[static_cast<size_t>(r) * rowBytes_ + (static_cast<size_t>(x0) * channels + c) * bytes_];
                    if (channels == 1) {
                        std::memcpy(to, from, static_cast<size_t>(columns) * bytes_);
                        continue;
                    }
                    for (int x = 0; x < columns; ++x) {
                        std::memcpy(to + static_cast<size_t>(x) * channels * bytes_, from + static_cast<size_t>(x) * bytes_, bytes_);
                    }
                }
            }
        }
    }

    void decodeBlock(const Layer& l, const ByteSource& file, const HfaBlockPlace& b, size_t k, size_t pixels) {
        if (!b.valid) {
            fillHfaBlock(l.pixel, l.nodata, pixels, block_.data());
            return;
        }
        const std::string name = "layer \"" + printableText(l.name) + "\"'s block " + std::to_string(k);
        const size_t needed = hfaStoredBytes(l.pixel, pixels);
        if (b.compressed ? b.size > kMaxBlockBytes : b.size < needed) {
            fail(l.file, name + " holds " + std::to_string(b.size) + " bytes, not the " +
                             (b.compressed ? "at most 64 MB of a compressed block" : std::to_string(needed) + " of its pixels"));
        }
        const uint64_t bytes = b.compressed ? b.size : needed;
        if (b.offset > file.size() || file.size() - b.offset < bytes) {
            fail(l.file, name + " lies beyond the end of the file (" + std::to_string(file.size()) +
                             " bytes): a file cut short or damaged");
        }
        stored_.resize(static_cast<size_t>(bytes));
        file.readAt(b.offset, stored_.data(), stored_.size()); // throws naming the file
        decodeHfaBlock(l.pixel, b.compressed, stored_, pixels, block_.data(), l.file, name);
    }

    Header header_;
    std::vector<std::shared_ptr<const ByteSource>> files_; // each layer's
    size_t bytes_;
    size_t rowBytes_ = 0;
    int row_ = 0;
    std::vector<uint8_t> band_;   // a row of blocks, interleaved
    std::vector<uint8_t> block_;  // one block decoded
    std::vector<uint8_t> stored_; // one block as stored
};

} // namespace

std::optional<RasterInfo> describeHfa(const std::string& path) {
    const std::optional<Header> h = readHeader(path);
    return h ? std::optional<RasterInfo>(h->info) : std::nullopt;
}

std::unique_ptr<DecodedRows> openHfa(const std::string& path, int cacheMegabytes) {
    std::optional<Header> h = readHeader(path);
    if (!h) {
        return nullptr;
    }
    auto rows = std::make_unique<DecodedRows>(path, h->info, cacheMegabytes, 1);
    rows->start(std::make_unique<HfaDecoder>(std::move(*h)));
    return rows;
}

} // namespace pyramid
