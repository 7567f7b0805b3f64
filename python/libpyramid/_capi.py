"""The C API through ctypes: finding the installed libraries, their structs and prototypes.

Two libraries of an installed libpyramid are used:

* ``libpyramid-runtime.so`` (``pyramid.h``): opening files and producing tiles; loaded on import.
* ``libpyramid-encode.so`` (``pyramid_encode.h``): encoding from arrays and callbacks; loaded on
  the first encode.

Where they are looked for, in order:

1. ``PYRAMID_LIBRARY``: the runtime library's path, or the directory holding it;
   ``PYRAMID_ENCODE_LIBRARY`` likewise for the encode library (default: beside the runtime).
2. The prefix the package is installed in: ``lib/`` (or ``lib64/``, ``lib/<multiarch>/``) of
   every directory above the package (``pip install --prefix P`` after ``cmake --install
   --prefix P``).
3. The system loader: ``ctypes.util.find_library`` (ldconfig's cache), then the plain soname
   (``LD_LIBRARY_PATH``).

ctypes releases the GIL for the duration of every foreign call, so threads read in parallel.
"""

import ctypes
import ctypes.util
import os
import sysconfig
from pathlib import Path

# The ABI this package is written against: soname libpyramid-*.so.0.2, at least 0.2.2.
SONAME_VERSION = "0.2"
MIN_VERSION_NUMBER = 202

OK = 0
ERROR_ARGUMENT = 1
ERROR_FILE = 2
ERROR_MEMORY = 3
ERROR_INTERNAL = 4
ERROR_NOT_FOUND = 5
ERROR_CANCELLED = 6

KIND_RESIDUAL = 1
KIND_ORTHO = 2

SOURCE_PATH = 1

DEFORM_PLANE = 0
DEFORM_SPHERE = 1

RESIDUAL_DEFLATE = 0
RESIDUAL_SMALLEST = 1
RESIDUAL_CONTEXT = 2

ORTHO_TIFF = 1
ORTHO_DXT = 2
ORTHO_RESIDUALS = 4

c_size_t = ctypes.c_size_t
c_int = ctypes.c_int
c_float_p = ctypes.POINTER(ctypes.c_float)
c_ubyte_p = ctypes.POINTER(ctypes.c_ubyte)


# ---- Structs (pyramid.h, pyramid_encode.h), member for member --------------------------------

class pyramid_io(ctypes.Structure):
    _fields_ = [("read", ctypes.c_void_p), ("release", ctypes.c_void_p), ("user", ctypes.c_void_p),
                ("size", ctypes.c_uint64)]


class pyramid_source(ctypes.Structure):
    _fields_ = [("struct_size", c_size_t), ("kind", c_int), ("name", ctypes.c_char_p),
                ("path", ctypes.c_char_p), ("data", ctypes.c_void_p), ("size", c_size_t), ("io", pyramid_io)]


class pyramid_file_info(ctypes.Structure):
    _fields_ = [("struct_size", c_size_t), ("kind", c_int), ("max_level", c_int), ("tile_size", c_int),
                ("root_level", c_int), ("root_tx", c_int), ("root_ty", c_int), ("min_level", c_int),
                ("scale", ctypes.c_float), ("channels", c_int), ("border", c_int), ("dxt", c_int),
                ("tile_count", ctypes.c_longlong), ("source_size", ctypes.c_uint64),
                ("data_offset", ctypes.c_uint64), ("stored_tiles", ctypes.c_longlong),
                ("distinct_tiles", ctypes.c_longlong)]


class pyramid_tile_info(ctypes.Structure):
    _fields_ = [("struct_size", c_size_t), ("exists", c_int), ("side", c_int), ("channels", c_int),
                ("stored_bytes", c_size_t), ("decoded_bytes", c_size_t), ("offset", ctypes.c_uint64)]


class pyramid_elevation_options(ctypes.Structure):
    _fields_ = [("struct_size", c_size_t), ("tile_size", c_int), ("grid_size", c_int),
                ("cache_tiles", c_size_t), ("scale", ctypes.c_float)]


class pyramid_normal_options(ctypes.Structure):
    _fields_ = [("struct_size", c_size_t), ("deformation", c_int), ("size", ctypes.c_double),
                ("cache_tiles", c_size_t)]


class pyramid_ortho_options(ctypes.Structure):
    _fields_ = [("struct_size", c_size_t), ("colour_residuals", c_int), ("cache_tiles", c_size_t)]


READ_HEIGHTS_FN = ctypes.CFUNCTYPE(c_int, ctypes.c_void_p, c_int, c_int, c_int, c_int, c_float_p)
READ_COLOURS_FN = ctypes.CFUNCTYPE(c_int, ctypes.c_void_p, c_int, c_int, c_int, c_int, c_ubyte_p)
PROGRESS_FN = ctypes.CFUNCTYPE(None, ctypes.c_void_p, ctypes.c_longlong, ctypes.c_longlong)
CANCEL_FN = ctypes.CFUNCTYPE(c_int, ctypes.c_void_p)


class pyramid_height_source(ctypes.Structure):
    _fields_ = [("struct_size", c_size_t), ("width", c_int), ("height", c_int), ("heights", c_float_p),
                ("read", READ_HEIGHTS_FN), ("user", ctypes.c_void_p), ("has_nodata", c_int),
                ("nodata", ctypes.c_double)]


class pyramid_dem_encode_options(ctypes.Structure):
    _fields_ = [("struct_size", c_size_t), ("tile_size", c_int), ("root_tile_size", c_int),
                ("max_level", c_int), ("scale", ctypes.c_double), ("threads", c_int),
                ("progress", PROGRESS_FN), ("cancel", CANCEL_FN), ("user", ctypes.c_void_p),
                ("fit_tiles", c_int), ("compression", c_int), ("deflate_level", c_int)]


class pyramid_colour_source(ctypes.Structure):
    _fields_ = [("struct_size", c_size_t), ("width", c_int), ("height", c_int), ("channels", c_int),
                ("pixels", c_ubyte_p), ("read", READ_COLOURS_FN), ("user", ctypes.c_void_p)]


class pyramid_ortho_encode_options(ctypes.Structure):
    _fields_ = [("struct_size", c_size_t), ("tile_size", c_int), ("max_level", c_int),
                ("name", ctypes.c_char_p), ("outputs", c_int), ("threads", c_int),
                ("progress", PROGRESS_FN), ("cancel", CANCEL_FN), ("user", ctypes.c_void_p),
                ("fit_tiles", c_int)]


def sized(struct_type):
    """A zeroed struct with its struct_size set, as the C API's size-prefixed structs want."""
    s = struct_type()
    s.struct_size = ctypes.sizeof(struct_type)
    return s


# ---- Prototypes --------------------------------------------------------------------------------

P = ctypes.POINTER
_RUNTIME_PROTOTYPES = {
    "pyramid_version_number": (c_int, []),
    "pyramid_version_string": (ctypes.c_char_p, []),
    "pyramid_last_error": (ctypes.c_char_p, []),
    "pyramid_status_name": (ctypes.c_char_p, [c_int]),
    "pyramid_open": (c_int, [ctypes.c_char_p, P(ctypes.c_void_p)]),
    "pyramid_close": (None, [ctypes.c_void_p]),
    "pyramid_get_file_info": (c_int, [ctypes.c_void_p, P(pyramid_file_info)]),
    "pyramid_tile_side": (c_int, [ctypes.c_void_p, c_int, P(c_int)]),
    "pyramid_tile_stat": (c_int, [ctypes.c_void_p, c_int, c_int, c_int, P(pyramid_tile_info)]),
    "pyramid_read_tile": (c_int, [ctypes.c_void_p, c_int, c_int, c_int, ctypes.c_void_p, c_size_t, P(c_size_t)]),
    "pyramid_read_tile_bytes": (c_int, [ctypes.c_void_p, c_int, c_int, c_int, ctypes.c_void_p, c_size_t,
                                        P(c_size_t)]),
    "pyramid_elevation_open": (c_int, [ctypes.c_char_p, c_int, c_int, c_size_t, P(ctypes.c_void_p)]),
    "pyramid_ortho_open": (c_int, [ctypes.c_char_p, c_int, c_size_t, P(ctypes.c_void_p)]),
    "pyramid_elevation_open_sources": (c_int, [P(pyramid_source), ctypes.c_void_p, c_size_t,
                                               P(pyramid_elevation_options), P(ctypes.c_void_p)]),
    "pyramid_elevation_close": (None, [ctypes.c_void_p]),
    "pyramid_elevation_side": (c_int, [ctypes.c_void_p]),
    # Buffers are passed as addresses (numpy's array.ctypes.data): the cheapest conversion.
    "pyramid_elevation_tile": (c_int, [ctypes.c_void_p, c_int, c_int, c_int, ctypes.c_void_p, ctypes.c_void_p,
                                       ctypes.c_void_p, c_size_t]),
    "pyramid_elevation_height": (c_int, [ctypes.c_void_p, c_int, ctypes.c_double, ctypes.c_double,
                                         P(ctypes.c_double)]),
    "pyramid_normal_open": (c_int, [ctypes.c_void_p, P(pyramid_normal_options), P(ctypes.c_void_p)]),
    "pyramid_normal_close": (None, [ctypes.c_void_p]),
    "pyramid_normal_side": (c_int, [ctypes.c_void_p]),
    "pyramid_normal_tile": (c_int, [ctypes.c_void_p, c_int, c_int, c_int, ctypes.c_void_p, c_size_t]),
    "pyramid_ortho_open_sources": (c_int, [P(pyramid_source), ctypes.c_void_p, c_size_t,
                                           P(pyramid_ortho_options), P(ctypes.c_void_p)]),
    "pyramid_ortho_close": (None, [ctypes.c_void_p]),
    "pyramid_ortho_layout": (c_int, [ctypes.c_void_p, P(c_int), P(c_int)]),
    "pyramid_ortho_tile": (c_int, [ctypes.c_void_p, c_int, c_int, c_int, ctypes.c_void_p, c_size_t]),
}
_ENCODE_PROTOTYPES = {
    "pyramid_version_number": (c_int, []),
    "pyramid_last_error": (ctypes.c_char_p, []),
    "pyramid_status_name": (ctypes.c_char_p, [c_int]),
    "pyramid_dem_encode_defaults": (None, [P(pyramid_dem_encode_options)]),
    "pyramid_encode_dem": (c_int, [P(pyramid_height_source), P(pyramid_dem_encode_options), ctypes.c_char_p]),
    "pyramid_ortho_encode_defaults": (None, [P(pyramid_ortho_encode_options)]),
    "pyramid_encode_ortho": (c_int, [P(pyramid_colour_source), P(pyramid_ortho_encode_options), ctypes.c_char_p]),
}


class LibraryNotFound(ImportError):
    """No installed libpyramid library was found where the package looks (see the module doc)."""


def _candidate_dirs():
    """lib directories of every directory above the installed package, nearest first."""
    multiarch = sysconfig.get_config_var("MULTIARCH") or ""
    here = Path(__file__).resolve().parent
    for parent in here.parents:
        for sub in ("lib", "lib64", os.path.join("lib", multiarch) if multiarch else None):
            if sub:
                yield parent / sub


def _locate(stem, env, beside=None):
    """The path (or soname) to load for library `stem` (e.g. "pyramid-runtime"), and the places tried."""
    soname = f"lib{stem}.so.{SONAME_VERSION}"
    tried = []
    value = os.environ.get(env)
    if value:
        p = Path(value)
        p = p / soname if p.is_dir() else p
        if not p.exists():
            raise LibraryNotFound(f"{env}={value}: {p} does not exist")
        return str(p), tried
    if beside is not None:
        p = Path(beside).parent / soname
        tried.append(str(p))
        if p.exists():
            return str(p), tried
    for d in _candidate_dirs():
        p = d / soname
        tried.append(str(p))
        if p.exists():
            return str(p), tried
    found = ctypes.util.find_library(stem)
    if found:
        return found, tried
    tried.append(soname + " (the system loader's path)")
    return soname, tried


def _load(stem, env, prototypes, beside=None):
    path, tried = _locate(stem, env, beside)
    try:
        lib = ctypes.CDLL(path)
    except OSError as e:
        raise LibraryNotFound(
            f"lib{stem}.so.{SONAME_VERSION} not found (install libpyramid with cmake --install and this package "
            f"into the same prefix, or set {env}); tried: {', '.join(tried)}; last error: {e}") from None
    for name, (restype, argtypes) in prototypes.items():
        fn = getattr(lib, name)
        fn.restype = restype
        fn.argtypes = argtypes
    version = lib.pyramid_version_number()
    if version < MIN_VERSION_NUMBER:
        raise LibraryNotFound(f"{path}: libpyramid {version // 10000}.{version // 100 % 100}.{version % 100} "
                              f"is older than the 0.2.2 this package needs")
    lib._pyramid_path = path
    return lib


runtime = _load("pyramid-runtime", "PYRAMID_LIBRARY", _RUNTIME_PROTOTYPES)
_encode = None


def encode_library():
    """The encode library, loaded on first use (beside the runtime unless PYRAMID_ENCODE_LIBRARY)."""
    global _encode
    if _encode is None:
        beside = runtime._pyramid_path if os.path.sep in runtime._pyramid_path else None
        _encode = _load("pyramid-encode", "PYRAMID_ENCODE_LIBRARY", _ENCODE_PROTOTYPES, beside)
    return _encode


def library_paths():
    """The loaded libraries' paths (the encode library's only once an encode has loaded it)."""
    paths = {"runtime": runtime._pyramid_path}
    if _encode is not None:
        paths["encode"] = _encode._pyramid_path
    return paths


def program(name):
    """The path of an installed program (preprocessDem, pyramid, ...): beside the libraries'
    prefix (<prefix>/bin), then PYRAMID_BIN, then PATH."""
    import shutil
    lib = runtime._pyramid_path
    candidates = []
    if os.environ.get("PYRAMID_BIN"):
        candidates.append(Path(os.environ["PYRAMID_BIN"]) / name)
    if os.path.sep in lib:
        libdir = Path(lib).resolve().parent
        for up in (libdir.parent, libdir.parent.parent):
            candidates.append(up / "bin" / name)
    for c in candidates:
        if c.is_file() and os.access(c, os.X_OK):
            return str(c)
    found = shutil.which(name)
    if found:
        return found
    raise FileNotFoundError(f"{name}: the installed program was not found (looked in "
                            f"{', '.join(str(c.parent) for c in candidates) or 'no prefix'} and PATH; "
                            f"set PYRAMID_BIN)")


def fspath(path):
    """A path argument as the bytes the C API takes."""
    return os.fsencode(os.fspath(path))

