// The reference the reader tests compare with: a file's samples as OpenImageIO's ImageInput
// reads them, in the file's own sample type, and the check that RasterSource reads the same
// (every read function, a window and the whole image).
#pragma once
#include <OpenImageIO/imageio.h>

#include <string>
#include <vector>

namespace pyramid::test {

// The file's samples as OpenImageIO reads them in their own type, widened to double; `spec`
// and `formatName` receive its description.
std::vector<double> referenceSamples(const std::string& path, OIIO::ImageSpec& spec, std::string& formatName);

// RasterSource::open(path, cacheMegabytes) describes the file as OpenImageIO does and reads the
// same samples with readFloat, readUInt16 (8- and 16-bit files) and readUInt8 (8-bit files).
void expectSameAsOpenImageIO(const std::string& path, int cacheMegabytes = 256);

} // namespace pyramid::test
