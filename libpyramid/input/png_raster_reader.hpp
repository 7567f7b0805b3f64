// PNG inputs decoded with libpng alone (no OpenImageIO): every colour type and depth, decoded
// once, whole, by DecodedRows (decoded_rows.hpp: in memory or a scratch file, on a thread of its
// own while the rows decoded so far are read). The last 16 rows come only once the whole file
// has been read and every chunk's CRC checked. An interlaced image, whose passes need it whole,
// is decoded at once and must fit the budget.
// Samples are the stored values: no gamma or colour-profile conversion, alpha not multiplied
// into colour. A palette, grey of 1, 2 or 4 bits and a transparency chunk are widened as
// OpenImageIO's PNG reader widens them: to the palette's RGB colours, to 8-bit grey (scaled),
// and to an alpha channel.
#pragma once
#include <memory>
#include <optional>
#include <string>

#include "libpyramid/input/decoded_rows.hpp"

namespace pyramid {

// Null when the file is not a PNG. Throws Error("PATH: ...") when its header cannot be read, or
// it is too large to hold; OptionError("cacheMegabytes") for an interlaced image larger than the
// budget. Reads of a damaged image throw Error("PATH: cannot read: damaged or truncated PNG
// (...)").
std::unique_ptr<DecodedRows> openPngRaster(const std::string& path, int cacheMegabytes);
// What openPngRaster would open, from the header alone (nothing decoded, no budget applied).
std::optional<RasterInfo> describePngRaster(const std::string& path);

} // namespace pyramid
