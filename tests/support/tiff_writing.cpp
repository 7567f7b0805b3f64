#include "tests/support/tiff_writing.hpp"

namespace pyramid::test {

TIFF* createTiff(const std::string& path, const TiffFields& f) {
    TIFF* tif = TIFFOpen(path.c_str(), "w");
    if (!tif) {
        return nullptr;
    }
    TIFFSetField(tif, TIFFTAG_IMAGEWIDTH, f.width);
    TIFFSetField(tif, TIFFTAG_IMAGELENGTH, f.height);
    TIFFSetField(tif, TIFFTAG_SAMPLESPERPIXEL, f.channels);
    TIFFSetField(tif, TIFFTAG_BITSPERSAMPLE, f.bits);
    TIFFSetField(tif, TIFFTAG_SAMPLEFORMAT, f.format);
    TIFFSetField(tif, TIFFTAG_PLANARCONFIG, f.planar);
    TIFFSetField(tif, TIFFTAG_COMPRESSION, f.compression);
    TIFFSetField(tif, TIFFTAG_PHOTOMETRIC,
                 f.photometric != 0 ? f.photometric : f.channels >= 3 ? PHOTOMETRIC_RGB : PHOTOMETRIC_MINISBLACK);
    if (f.channels == 2 || f.channels == 4) {
        const uint16_t alpha = EXTRASAMPLE_UNASSALPHA;
        TIFFSetField(tif, TIFFTAG_EXTRASAMPLES, 1, &alpha);
    }
    return tif;
}

} // namespace pyramid::test
