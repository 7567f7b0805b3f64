#include "formats/tiff_memory.hpp"

#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <cstring>

namespace pyramid {

namespace {

tmsize_t streamRead(thandle_t h, void* buf, tmsize_t n) {
    auto* s = static_cast<MemoryStream*>(h);
    const size_t available = s->out ? s->out->size() : s->size;
    const uint8_t* base = s->out ? s->out->data() : s->data;
    if (n < 0 || s->pos >= available) {
        return 0;
    }
    const size_t count = std::min(static_cast<size_t>(n), static_cast<size_t>(available - s->pos));
    std::memcpy(buf, base + s->pos, count);
    s->pos += count;
    return static_cast<tmsize_t>(count);
}

tmsize_t streamWrite(thandle_t h, void* buf, tmsize_t n) {
    auto* s = static_cast<MemoryStream*>(h);
    if (!s->out || n < 0) {
        return -1;
    }
    const size_t end = static_cast<size_t>(s->pos) + static_cast<size_t>(n);
    if (end > s->out->size()) {
        s->out->resize(end);
    }
    std::memcpy(s->out->data() + s->pos, buf, static_cast<size_t>(n));
    s->pos = end;
    return n;
}

toff_t streamSeek(thandle_t h, toff_t offset, int whence) {
    auto* s = static_cast<MemoryStream*>(h);
    const uint64_t size = s->out ? s->out->size() : s->size;
    uint64_t base = 0;
    if (whence == SEEK_CUR) {
        base = s->pos;
    } else if (whence == SEEK_END) {
        base = size;
    }
    s->pos = base + offset;
    return s->pos;
}

int streamClose(thandle_t) { return 0; }

toff_t streamSize(thandle_t h) {
    auto* s = static_cast<MemoryStream*>(h);
    return s->out ? s->out->size() : s->size;
}

int noMap(thandle_t, void**, toff_t*) { return 0; }
void noUnmap(thandle_t, void*, toff_t) {}

// libtiff reports through these per-handle handlers (thread-safe: no global state). Warnings,
// such as the missing ExtraSamples tag of the original 4-channel tiles, are dropped; the first
// error is kept for our own message.
int onError(TIFF*, void* user, const char*, const char* fmt, va_list ap) {
    auto* s = static_cast<MemoryStream*>(user);
    if (s->firstError.empty()) {
        char buf[256];
        std::vsnprintf(buf, sizeof buf, fmt, ap);
        s->firstError = buf;
        std::replace(s->firstError.begin(), s->firstError.end(), '\n', ' ');
    }
    return 1;
}

int onWarning(TIFF*, void*, const char*, const char*, va_list) { return 1; }

} // namespace

TiffHandle::TiffHandle(MemoryStream& stream, const char* mode, tmsize_t maxAlloc) {
    TIFFOpenOptions* opts = TIFFOpenOptionsAlloc();
    TIFFOpenOptionsSetErrorHandlerExtR(opts, onError, &stream);
    TIFFOpenOptionsSetWarningHandlerExtR(opts, onWarning, &stream);
    TIFFOpenOptionsSetMaxSingleMemAlloc(opts, maxAlloc);
    tif_ = TIFFClientOpenExt("tile", mode, &stream, streamRead, streamWrite, streamSeek, streamClose,
                             streamSize, noMap, noUnmap, opts);
    TIFFOpenOptionsFree(opts);
}

std::string withCause(const std::string& what, const MemoryStream& s) {
    return s.firstError.empty() ? what : what + " (" + s.firstError + ")";
}

} // namespace pyramid
