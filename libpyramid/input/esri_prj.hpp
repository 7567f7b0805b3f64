// ESRI's old .prj, of keyword lines rather than WKT, as GTOPO30, SRTM30 and older ArcInfo grids
// ship it:
//     Projection    GEOGRAPHIC        (or UTM, with a Zone line)
//     Datum         WGS84             (NAD83, NAD27)
//     Units         DD                (decimal degrees; DS: seconds; METERS for UTM)
//     Yshift        0.0               (10000000: a UTM zone south of the equator)
//     Parameters
// Only the CRSs of the EPSG database those lines name are known: geographic WGS 84, NAD83 and
// NAD27, and their UTM zones.
#pragma once
#include <optional>
#include <string>

namespace pyramid {

struct OldStylePrj {
    int epsg = 0;                // 0: a CRS the lines name but the EPSG database has no code for here
    double unitsPerCrsUnit = 1.0; // what one of the CRS's units is in the file's (3600: seconds of arc)
};

// Nothing when `text` is not of that form (WKT, or empty).
std::optional<OldStylePrj> readOldStylePrj(const std::string& text);

} // namespace pyramid
