// DTED (Digital Terrain Elevation Data, MIL-PRF-89020B: `.dt0`, `.dt1`, `.dt2`; whatever the
// name, a file whose first record is a UHL, after VOL and HDR tape labels if any): a header of
// three records (UHL, DSI, ACC: 80, 648 and 2700 bytes), then one record per longitude line,
// west to east, each holding its column's heights south to north: a sentinel byte 0xAA, the
// block and column numbers, big-endian 16-bit heights in metres as sign and magnitude (-32767: a
// void, nodata), and a checksum (the sum of the record's bytes before it).
//
// The UHL places the grid: the south-west post's longitude and latitude, the spacing of the
// posts in tenths of a second of arc (so 30" for level 0, 3" for level 1 and 1" for level 2, and
// wider east to west towards the poles), the counts of columns and rows. The posts are points
// (PixelIsPoint), on the DSI's horizontal datum: WGS 84 (EPSG:4326) or WGS 72 (EPSG:4322); the
// heights are metres.
//
// The columns are read a band of rows at a time (one pread per column and band, a band about 4
// MB), turned into rows of int16, north first, and decoded once, whole, by DecodedRows
// (decoded_rows.hpp: in memory within the input cache, else a scratch file). Every record's
// sentinel, column number and checksum are checked as its last band is read: a damaged file is
// an error naming the file and the column. Negative heights written in two's complement, as
// some producers do, are read as GDAL reads them: a sign-and-magnitude value below -16000 other
// than the void is taken as two's complement.
#pragma once
#include <memory>
#include <optional>
#include <string>

#include "libpyramid/input/decoded_rows.hpp"

namespace pyramid {

// What openDted would open, from the header alone; nothing when the file is no DTED file.
// Throws Error naming the file when its header cannot be read or its size does not fit it.
std::optional<RasterInfo> describeDted(const std::string& path);
// Null when the file is no DTED file. Throws as describeDted.
std::unique_ptr<DecodedRows> openDted(const std::string& path, int cacheMegabytes);

} // namespace pyramid
