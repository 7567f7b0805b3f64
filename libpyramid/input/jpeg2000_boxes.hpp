// What libpyramid reads itself of a JPEG 2000 file, whose samples OpenImageIO decodes (through
// the image I/O module): a JP2 file's boxes (ISO/IEC 15444-1 annex I: a length, a type, the
// contents) or a bare codestream (`.j2k`, `.j2c`), for two things OpenImageIO does not give:
//   - where the file lies: the GeoJP2 box (a `uuid` box of UUID b14bf8bd-083d-4b43-a5ae-
//     8cd7d5a6ce03) holding a GeoTIFF of one pixel whose GeoKeys and tie point or transform place
//     the JPEG 2000 image, read as a GeoTIFF's own (georeference.hpp). GDAL writes it by default.
//     Else the GMLJP2 document (the `xml ` box in an `asoc` box labelled "gml.root-instance":
//     gml_jp2.hpp), which Sentinel-2's granules carry;
//   - whether its samples are signed (the codestream's SIZ marker: Ssiz's top bit for each
//     component). OpenImageIO 2.4 reads signed samples shifted (a signed 16-bit height h as the
//     unsigned h + 128), so such a file is refused, naming it, rather than read wrong.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace pyramid {

struct Jpeg2000Boxes {
    std::vector<uint8_t> geoTiff; // the GeoJP2 box's GeoTIFF; empty without one
    std::string gml;              // the GMLJP2 document; empty without one
};

// Nothing when `path` is neither a JP2 file nor a bare codestream (by their signatures).
// Throws Error naming the file for signed samples, and for a GeoJP2 or GMLJP2 box beyond 1 MB (no
// GeoTIFF of one pixel, nor a grid's GML, is that large).
std::optional<Jpeg2000Boxes> readJpeg2000Boxes(const std::string& path);

} // namespace pyramid
