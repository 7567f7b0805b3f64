#include "libpyramid/input/height_unit.hpp"

#include <geotiff/geokeys.h>
#include <geotiff/geovalues.h>

#include <map>
#include <memory>
#include <mutex>
#include <utility>

#include "libpyramid/input/geotiff_library.hpp"

namespace pyramid {

namespace {

// A PROJ context of its own for each lookup, and a lookup once per code in a process (a mosaic of
// a thousand tiles names one vertical CRS a thousand times).
HeightUnit lookUp(const GeoTiffLibrary& lib, bool crs, int code) {
    static std::mutex mutex;
    static std::map<std::pair<bool, int>, HeightUnit> known;
    const std::lock_guard lock(mutex);
    if (const auto it = known.find({crs, code}); it != known.end()) {
        return it->second;
    }
    HeightUnit u;
    const std::string epsg = "EPSG:" + std::to_string(code);
    const std::unique_ptr<PJ_CONTEXT, decltype(lib.projContextDestroy)> ctx(lib.projContextCreate(),
                                                                            lib.projContextDestroy);
    const std::string text = std::to_string(code);
    if (crs) {
        u.source = "VerticalCSTypeGeoKey " + epsg;
        auto destroy = [&lib](PJ* p) { lib.projDestroy(p); };
        const std::unique_ptr<PJ, decltype(destroy)> vertical(
            ctx ? lib.projCreateFromDatabase(ctx.get(), "EPSG", text.c_str(), PJ_CATEGORY_CRS, 0, nullptr) : nullptr,
            destroy);
        if (vertical && lib.projGetType(vertical.get()) == PJ_TYPE_VERTICAL_CRS) {
            const char* name = lib.projGetName(vertical.get());
            u.source = epsg + " (" + (name ? name : "") + ")";
            const std::unique_ptr<PJ, decltype(destroy)> cs(lib.projCrsGetCoordinateSystem(ctx.get(), vertical.get()),
                                                            destroy);
            const char* unit = nullptr;
            double factor = 0.0;
            if (cs && lib.projCsGetAxisInfo(ctx.get(), cs.get(), 0, nullptr, nullptr, nullptr, &factor, &unit, nullptr,
                                            nullptr) &&
                factor > 0.0) {
                u.name = unit ? unit : "";
                u.metres = factor;
            }
        }
    } else {
        u.source = "VerticalUnitsGeoKey " + epsg;
        const char* name = nullptr;
        const char* category = nullptr;
        double factor = 0.0;
        if (ctx && lib.projUomGetInfoFromDatabase(ctx.get(), "EPSG", text.c_str(), &name, &factor, &category) &&
            category && std::string(category) == "linear" && factor > 0.0) {
            u.name = name ? name : "";
            u.metres = factor;
        }
    }
    if (u.metres <= 0.0) {
        u.source += crs ? ", which the EPSG database does not hold as a vertical CRS"
                        : ", which the EPSG database does not hold as a unit of length";
    }
    known[{crs, code}] = u;
    return u;
}

} // namespace

std::optional<HeightUnit> readHeightUnit(const GeoTiffLibrary& lib, GTIF* gtif) {
    unsigned short units = 0, vertical = 0;
    if (lib.keyGet(gtif, VerticalUnitsGeoKey, &units, 0, 1) == 1 && units != 0 && units != KvUserDefined) {
        return lookUp(lib, false, units);
    }
    if (lib.keyGet(gtif, VerticalCSTypeGeoKey, &vertical, 0, 1) == 1 && vertical != 0 && vertical != KvUserDefined) {
        return lookUp(lib, true, vertical);
    }
    return std::nullopt;
}

} // namespace pyramid
