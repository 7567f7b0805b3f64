// TIFFs the reader tests write with libtiff's own calls, for layouts OpenImageIO's writer does not
// make: a file opened with its image fields set, the blocks left to the test.
#pragma once
#include <tiffio.h>

#include <cstdint>
#include <string>

namespace pyramid::test {

// The image fields: size, samples (an unassociated alpha as the last of 2 or 4), their bits and
// format, the planar configuration, the photometric interpretation (0: RGB from 3 samples, else
// grey) and the compression.
struct TiffFields {
    int width, height, channels, bits;
    uint16_t format = SAMPLEFORMAT_UINT, planar = PLANARCONFIG_CONTIG, photometric = 0,
             compression = COMPRESSION_NONE;
};

// The file opened for writing (mode "w") with those fields set; null when it cannot be created.
TIFF* createTiff(const std::string& path, const TiffFields& f);

} // namespace pyramid::test
