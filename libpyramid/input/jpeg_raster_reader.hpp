// JPEG inputs decoded with libjpeg alone (no OpenImageIO): grey and colour images (YCbCr, or
// RGB, given as RGB: libjpeg converts them as it decodes, as OpenImageIO's JPEG reader does), of
// 8 bits, decoded once, whole, by DecodedRows (decoded_rows.hpp: in memory or a scratch file, on
// a thread of its own while the rows decoded so far are read). The last 16 rows come only once
// the whole file has been read. A progressive image, which libjpeg holds whole (its
// coefficients) before its first row, must fit the budget. Corrupt data, which libjpeg decodes
// on with a warning (a truncated file, a bad Huffman code, a lost marker), is an error naming
// the file. CMYK and YCCK images, and 12-bit ones, are left to OpenImageIO. Samples are the
// decoded values: no colour-profile conversion, EXIF orientation not applied (as OpenImageIO
// reads them).
#pragma once
#include <memory>
#include <optional>
#include <string>

#include "libpyramid/input/decoded_rows.hpp"

namespace pyramid {

// Null when the file is not a JPEG, or one of the kinds left to OpenImageIO. Throws
// Error("PATH: ...") when its header cannot be read; OptionError("cacheMegabytes") for a
// progressive image larger than the budget. Reads of a damaged image throw
// Error("PATH: cannot read: damaged or truncated JPEG (...)").
std::unique_ptr<DecodedRows> openJpegRaster(const std::string& path, int cacheMegabytes);
// What openJpegRaster would open, from the header alone (nothing decoded, no budget applied).
std::optional<RasterInfo> describeJpegRaster(const std::string& path);

} // namespace pyramid
