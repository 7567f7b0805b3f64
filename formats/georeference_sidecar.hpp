// The georeference sidecar beside a planar pyramid ("DEM.dat.georef.json"): its name, and what a
// reader needs from it to place points on the pyramid. The encoders write it
// (libpyramid/input/pyramid_georeference.hpp); the runtime reads it (height queries by CRS
// coordinates or longitude and latitude).
#pragma once
#include <array>
#include <string>

namespace pyramid {

// The sidecar file of an output `path` ("DEM.dat" -> "DEM.dat.georef.json": reports are named
// by the user and never end so).
std::string georeferenceSidecarPath(const std::string& path);

// What a reader of a sidecar needs to place points on the pyramid: its CRS's kind and its root
// quad's extent, as writeGeoreferenceSidecar wrote them.
struct SidecarPlacement {
    bool geographic = false;
    std::array<double, 4> rootExtent{}; // min x, min y, max x, max y
    double unitInDegrees = 1.0;         // geographic: one CRS unit
    double unitInMetres = 1.0;          // projected: one CRS unit
    double primeMeridian = 0.0;         // geographic: degrees east of Greenwich
    bool rotated = false;               // the input's transform turns its pixels off north-up
};
// Throws Error naming `sidecar` when it is missing or is not such a file.
SidecarPlacement readGeoreferenceSidecar(const std::string& sidecar);

} // namespace pyramid
