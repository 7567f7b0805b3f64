// Size-prefixed structs (doc/c-api.md): every struct of the C API begins with `size_t
// struct_size`, set by the caller to the size it was compiled with, so that the structs can grow.
// The one rule for reading and writing them, shared by the runtime's functions (pyramid_file.cpp,
// pyramid_elevation.cpp, pyramid_ortho.cpp) and the encoding ones (pyramid_encode.cpp).
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstring>
#include <string>

#include "libpyramid/capi/capi_status.hpp"

namespace pyramid::capi {

namespace detail {

// A struct_size too small to hold struct_size itself: an argument error naming `what`.
inline bool sizeHoldsItself(size_t size, const char* what) {
    if (size < sizeof(size_t)) {
        failWith(PYRAMID_ERROR_ARGUMENT, std::string(what) + ": struct_size " + std::to_string(size) +
                                             " is too small (set it to sizeof the struct)");
        return false;
    }
    return true;
}

} // namespace detail

// An input struct as this library knows it: the caller's first struct_size bytes over `out`,
// which holds the defaults of the members a smaller (older) struct lacks. A struct larger than T
// is accepted when the members this library does not know are all zero; anything else is an
// argument error (false, the message naming `what`), as an option the library cannot honour
// must not be dropped silently. A null `in` leaves `out` as it is (every member its default).
// `out.struct_size` is sizeof(T) afterwards.
template <class T>
bool readSized(const T* in, T& out, const char* what) {
    if (!in) {
        out.struct_size = sizeof(T);
        return true;
    }
    const size_t size = in->struct_size;
    if (!detail::sizeHoldsItself(size, what)) {
        return false;
    }
    const auto* bytes = reinterpret_cast<const unsigned char*>(in);
    for (size_t k = sizeof(T); k < size; ++k) {
        if (bytes[k] != 0) {
            failWith(PYRAMID_ERROR_ARGUMENT, std::string(what) + ": members past byte " + std::to_string(sizeof(T)) +
                                                 " are set, and this library version does not know them");
            return false;
        }
    }
    std::memcpy(&out, in, std::min(size, sizeof(T)));
    out.struct_size = sizeof(T);
    return true;
}

// An output struct: `full`'s members that fit in the caller's struct_size bytes at `out`; bytes
// past the library's own struct are zeroed; struct_size is left as the caller set it. False (an
// argument error naming `what`) when struct_size cannot even hold itself.
template <class T>
bool writeSized(const T& full, T* out, const char* what) {
    const size_t size = out->struct_size;
    if (!detail::sizeHoldsItself(size, what)) {
        return false;
    }
    auto* bytes = reinterpret_cast<unsigned char*>(out);
    const auto* from = reinterpret_cast<const unsigned char*>(&full);
    const size_t common = std::min(size, sizeof(T));
    std::memcpy(bytes + sizeof(size_t), from + sizeof(size_t), common - sizeof(size_t));
    if (size > sizeof(T)) {
        std::memset(bytes + sizeof(T), 0, size - sizeof(T));
    }
    return true;
}

} // namespace pyramid::capi
