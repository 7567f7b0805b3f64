// The C API's thread-local last error (pyramid_last_error), shared by its two halves: the
// runtime's functions (pyramid_capi.cpp) and the encoding ones (pyramid_encode.cpp).
#pragma once
#include <string>

namespace pyramid::capi {

void setLastError(const std::string& message);

} // namespace pyramid::capi
