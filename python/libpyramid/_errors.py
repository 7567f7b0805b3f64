"""Exceptions: a failing C call raises an Error carrying its status and the C API's message."""

from . import _capi


class Error(Exception):
    """A libpyramid call failed.

    ``status`` is the C API's status code (``pyramid_status``), ``status_name`` its name
    ("argument", "file", "memory", "internal", "not_found", "cancelled"), and ``message`` the
    C API's one-line message (``pyramid_last_error``), which names the file and the problem.
    ``str(error)`` is the message.
    """

    def __init__(self, message, status=_capi.ERROR_INTERNAL, status_name="internal"):
        super().__init__(message)
        self.message = message
        self.status = status
        self.status_name = status_name


class ArgumentError(Error, ValueError):
    """PYRAMID_ERROR_ARGUMENT: an option out of range, a buffer or tile size the file cannot serve."""


class FileError(Error):
    """PYRAMID_ERROR_FILE: a file missing, unreadable or not a valid pyramid; a read that failed."""


class NotFoundError(Error, LookupError):
    """PYRAMID_ERROR_NOT_FOUND: a tile the pyramid does not hold."""


class CancelledError(Error):
    """PYRAMID_ERROR_CANCELLED: an encoding stopped by its ``cancel`` callable."""


_BY_STATUS = {
    _capi.ERROR_ARGUMENT: ArgumentError,
    _capi.ERROR_FILE: FileError,
    _capi.ERROR_NOT_FOUND: NotFoundError,
    _capi.ERROR_CANCELLED: CancelledError,
}


def from_status(status, lib=None, message=None, where=None):
    """The exception for a failed call's status. Call it on the thread that made the call: the C
    API's message is thread-local. `lib` is the library that failed (the runtime by default);
    `where` (a path) prefixes a message that does not name it already."""
    lib = lib or _capi.runtime
    if message is None:
        message = lib.pyramid_last_error().decode("utf-8", "replace")
    if where and message and where not in message:
        message = f"{where}: {message}"
    name = lib.pyramid_status_name(status).decode()
    return _BY_STATUS.get(status, Error)(message or f"libpyramid call failed ({name})", status, name)


def check(status, lib=None, where=None):
    """Raises the exception of a non-OK status (see from_status)."""
    if status != _capi.OK:
        raise from_status(status, lib, where=where)
