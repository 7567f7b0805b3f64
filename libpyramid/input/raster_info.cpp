#include "libpyramid/input/raster_info.hpp"

namespace pyramid {

const char* sampleTypeName(SampleType type) {
    switch (type) {
    case SampleType::UInt8:
        return "uint8";
    case SampleType::Int8:
        return "int8";
    case SampleType::UInt16:
        return "uint16";
    case SampleType::Int16:
        return "int16";
    case SampleType::UInt32:
        return "uint32";
    case SampleType::Int32:
        return "int32";
    case SampleType::Float16:
        return "float16";
    case SampleType::Float32:
        return "float32";
    case SampleType::Float64:
        return "float64";
    case SampleType::Other:
        break;
    }
    return "other";
}

} // namespace pyramid
