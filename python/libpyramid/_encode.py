"""Encoding: a DEM or ortho pyramid from a numpy array, an array-like read by windows, a
callable, or input files.

* Arrays and callables go through the C API's encode functions (libpyramid-encode.so). A
  float32 C-contiguous DEM array (a uint8 one for ortho) is passed as it is; other arrays and
  array-likes (np.memmap, h5py or zarr datasets) are read by windows as the encoder asks for
  them, so data larger than memory never has to be loaded whole.
* Input paths (what the programs take: GeoTIFF, .hgt, PNG, mosaics) run the installed
  preprocessDem / preprocessOrtho with ``--report -``: the C API has no path entry.

Rows are north first (row 0 = north), as in an image and as the C API's encode sources take them.
"""

import ctypes
import os
import time

import numpy as np

from . import _capi
from ._read import _File
from ._runner import Call, run_program

_COMPRESSION = {"deflate": _capi.RESIDUAL_DEFLATE, "smallest": _capi.RESIDUAL_SMALLEST,
                "context": _capi.RESIDUAL_CONTEXT}
_ORTHO_OUTPUTS = {"tiff": _capi.ORTHO_TIFF, "dxt": _capi.ORTHO_DXT, "residuals": _capi.ORTHO_RESIDUALS}
_ORTHO_FILES = {"tiff": "{name}.dat", "dxt": "dxt/{name}.dat", "residuals": "residuals/{name}.dat"}


def _is_path(source):
    if isinstance(source, (str, bytes, os.PathLike)):
        return True
    return isinstance(source, (list, tuple)) and source and all(isinstance(s, (str, os.PathLike)) for s in source)


def _program_args(program, source, flag_output, output, options):
    """The command line of an installed program: inputs, -o, then --kebab-case options."""
    inputs = [os.fspath(source)] if isinstance(source, (str, bytes, os.PathLike)) else [os.fspath(s) for s in source]
    args = [_capi.program(program)] + [os.fsdecode(i) for i in inputs] + [flag_output, os.fspath(output)]
    for key, value in options.items():
        if value is None or value is False:
            continue
        flag = "--" + key.replace("_", "-")
        if value is True:
            args.append(flag)
        elif isinstance(value, (list, tuple)):
            args += [flag, ",".join(str(v) for v in value)]
        else:
            args += [flag, str(value)]
    return args


class _Windows:
    """A read callback over an array-like or a callable: the encoder's windows, checked and
    copied into the C buffer (several encoder threads call it, one at a time under the GIL)."""

    def __init__(self, call, fetch, shape_of, dtype, what):
        self.call, self.fetch, self.shape_of, self.dtype, self.what = call, fetch, shape_of, dtype, what

    def __call__(self, user, x0, y0, x1, y1, out):
        try:
            block = np.asarray(self.fetch(x0, y0, x1, y1))
            want = self.shape_of(x1 - x0, y1 - y0)
            if block.shape != want and not (block.ndim == 2 and want[2:] == (1,) and block.shape == want[:2]):
                raise ValueError(f"{self.what}: the window of columns {x0}..{x1 - 1}, rows {y0}..{y1 - 1} has shape "
                                 f"{block.shape}, not {want}")
            _check_dtype(block, self.dtype, self.what)
            dst = np.ctypeslib.as_array(out, shape=(int(np.prod(want)),)).reshape(block.shape)
            np.copyto(dst, block, casting="unsafe")
            return 0
        except BaseException as e:  # noqa: B902 - carried to the caller by Call.run
            self.call.fail(e)
            return -1


def _check_dtype(array, dtype, what):
    if dtype == np.float32:
        if array.dtype.kind not in "fiu":
            raise TypeError(f"{what}: heights must be real numbers (float or integer), not {array.dtype}")
    elif array.dtype != np.uint8:
        raise TypeError(f"{what}: pixels must be uint8, not {array.dtype}")


def _source_reader(source, width, height, what, dtype):
    """(direct array or None, window fetch function or None, width, height, source kind)."""
    if isinstance(source, np.ndarray):
        if source.ndim not in (2, 3) or (dtype == np.float32 and source.ndim != 2):
            raise ValueError(f"{what}: an array of shape {source.shape}: expected (height, width)"
                             + ("" if dtype == np.float32 else " or (height, width, channels)"))
        _check_dtype(source, dtype, what)
        h, w = source.shape[:2]
        if source.dtype == dtype and source.flags.c_contiguous:
            return source, None, w, h, "array"
        return None, (lambda x0, y0, x1, y1: source[y0:y1, x0:x1]), w, h, "array windows"
    if callable(source):
        if width is None or height is None:
            raise TypeError(f"{what}: a callable source needs width= and height=")
        return None, source, int(width), int(height), "callable"
    if hasattr(source, "shape") and hasattr(source, "__getitem__"):
        h, w = source.shape[:2]
        return None, (lambda x0, y0, x1, y1: source[y0:y1, x0:x1]), w, h, "array windows"
    raise TypeError(f"{what}: a numpy array, an array-like with shape and slicing, a callable "
                    f"(x0, y0, x1, y1) -> array, or input paths, not {type(source).__name__}")


def _report_from(call_started, source_kind, width, height, extra):
    report = {"ok": True, "seconds": time.monotonic() - call_started,
              "input": {"source": source_kind, "width": width, "height": height}}
    report.update(extra)
    return report


def encode_dem(source, output, *, scale=None, tile_size=None, root_tile_size=None, max_level=None, threads=None,
               compression=None, deflate_level=None, nodata=None, width=None, height=None, progress=None,
               cancel=None, **program_options):
    """Encodes a residual (DEM) pyramid file `output`; returns the report as a dict.

    `source`: a 2-D array of heights (row 0 north; float32 C-contiguous arrays are used in
    place, other real dtypes are read by windows), an array-like with ``shape`` and slicing, a
    callable ``(x0, y0, x1, y1) -> array (y1 - y0, x1 - x0)`` with `width` and `height`, or
    input path(s) as preprocessDem takes them (which then runs, with `program_options` as its
    ``--kebab-case`` options).

    Options (None: the C API's, the program's, defaults): `scale` (height units per residual
    unit, or "auto"), `tile_size` (or "auto": tiles fitted to the map's grid),
    `root_tile_size`, `max_level`, `threads`, `compression` ("deflate", "smallest", "context"),
    `deflate_level`, `nodata` (a value marking missing heights, NaN allowed). `progress(done,
    total)` is called after every tile (from a worker thread); `cancel()` returning true stops the
    encoding (CancelledError). Ctrl-C (KeyboardInterrupt) stops it too. Either way the file is
    written whole or not at all.
    """
    started = time.monotonic()
    if _is_path(source):
        opts = dict(scale=scale, tile_size=tile_size, root_tile_size=root_tile_size, max_level=max_level,
                    threads=threads, compression=compression, deflate_level=deflate_level, nodata=nodata)
        opts.update(program_options)
        return run_program(_program_args("preprocessDem", source, "-o", output, opts), progress, cancel)
    if program_options:
        raise TypeError(f"encode_dem: options {sorted(program_options)} apply to input files only")
    array, fetch, w, h, kind = _source_reader(source, width, height, "encode_dem", np.float32)
    lib = _capi.encode_library()
    call = Call(lib, progress, cancel)
    src = _capi.sized(_capi.pyramid_height_source)
    src.width, src.height = w, h
    if array is not None:
        src.heights = array.ctypes.data_as(_capi.c_float_p)
    else:
        reader = _capi.READ_HEIGHTS_FN(_Windows(call, fetch, lambda cw, ch: (ch, cw), np.float32, "encode_dem"))
        src.read = reader
    if nodata is not None:
        src.has_nodata, src.nodata = 1, float(nodata)
    o = _capi.sized(_capi.pyramid_dem_encode_options)
    lib.pyramid_dem_encode_defaults(ctypes.byref(o))
    if tile_size == "auto":
        o.fit_tiles = 1
    elif tile_size is not None:
        o.tile_size = tile_size
    if root_tile_size is not None:
        o.root_tile_size = root_tile_size
    if max_level is not None:
        o.max_level = max_level
    if scale is not None:
        o.scale = 0.0 if scale == "auto" else float(scale)
    if threads is not None:
        o.threads = threads
    if compression is not None:
        if compression not in _COMPRESSION:
            raise ValueError(f"encode_dem: compression {compression!r} is not one of {sorted(_COMPRESSION)}")
        o.compression = _COMPRESSION[compression]
    if deflate_level is not None:
        o.deflate_level = deflate_level
    o.progress, o.cancel = call.c_progress, call.c_cancel
    call.run(lib.pyramid_encode_dem, ctypes.byref(src), ctypes.byref(o), _capi.fspath(output))
    f = _File(output)
    try:
        info = f.info
    finally:
        f.close()
    header = {k: info[k] for k in ("max_level", "min_level", "scale", "tile_size")}
    return _report_from(started, kind, w, h, {
        "output": os.fspath(output), "bytes": os.path.getsize(output), "header": header,
        "tiles": info["tile_count"], "compression": compression or "deflate"})


def encode_ortho(source, directory, *, tile_size=None, max_level=None, name=None, outputs=None, threads=None,
                 width=None, height=None, channels=None, progress=None, cancel=None, **program_options):
    """Encodes ortho pyramids into `directory` (NAME.dat, dxt/NAME.dat, residuals/NAME.dat);
    returns the report as a dict.

    `source`: a uint8 array (height, width) or (height, width, channels), channels 1..4, row 0
    north; an array-like with ``shape`` and slicing; a callable ``(x0, y0, x1, y1) -> uint8
    array`` with `width`, `height` and `channels`; or input path(s) as preprocessOrtho takes
    them (`program_options` as its ``--kebab-case`` options).

    Options (None: the defaults): `tile_size` ("auto", the default: fitted to the image, as
    preprocessOrtho --tile-size auto; 192 when only `max_level` is given), `max_level`, `name` ("RGB"), `outputs` (some of
    "tiff", "dxt", "residuals"; all three by default), `threads`; `progress`, `cancel` and Ctrl-C
    as for encode_dem: the files appear together, or none does.
    """
    started = time.monotonic()
    wanted = list(outputs) if outputs is not None and not isinstance(outputs, str) else \
        (outputs.split(",") if outputs else list(_ORTHO_OUTPUTS))
    unknown = [o for o in wanted if o not in _ORTHO_OUTPUTS]
    if unknown or not wanted:
        raise ValueError(f"encode_ortho: outputs {unknown or wanted!r}: choose among {list(_ORTHO_OUTPUTS)}")
    if _is_path(source):
        opts = dict(tile_size=tile_size, max_level=max_level, name=name, threads=threads,
                    outputs=wanted if outputs is not None else None)
        opts.update(program_options)
        return run_program(_program_args("preprocessOrtho", source, "-o", directory, opts), progress, cancel)
    if program_options:
        raise TypeError(f"encode_ortho: options {sorted(program_options)} apply to input files only")
    array, fetch, w, h, kind = _source_reader(source, width, height, "encode_ortho", np.uint8)
    lib = _capi.encode_library()
    call = Call(lib, progress, cancel)
    if array is not None or kind == "array windows":
        shape = source.shape
        c = shape[2] if len(shape) == 3 else 1
    else:
        if channels is None:
            raise TypeError("encode_ortho: a callable source needs channels=")
        c = int(channels)
    src = _capi.sized(_capi.pyramid_colour_source)
    src.width, src.height, src.channels = w, h, c
    if array is not None:
        src.pixels = array.ctypes.data_as(_capi.c_ubyte_p)
    else:
        src.read = _capi.READ_COLOURS_FN(_Windows(call, fetch, lambda cw, ch: (ch, cw, c), np.uint8, "encode_ortho"))
    o = _capi.sized(_capi.pyramid_ortho_encode_options)
    lib.pyramid_ortho_encode_defaults(ctypes.byref(o))
    if tile_size == "auto" or (tile_size is None and max_level is None):  # preprocessOrtho's default
        o.fit_tiles = 1
    elif tile_size is not None:
        o.tile_size = tile_size
    if max_level is not None:
        o.max_level = max_level
    name = name or "RGB"
    o.name = name.encode()
    o.outputs = sum(_ORTHO_OUTPUTS[k] for k in set(wanted))
    if threads is not None:
        o.threads = threads
    o.progress, o.cancel = call.c_progress, call.c_cancel
    call.run(lib.pyramid_encode_ortho, ctypes.byref(src), ctypes.byref(o), _capi.fspath(directory))
    files = {k: os.path.join(os.fspath(directory), _ORTHO_FILES[k].format(name=name)) for k in wanted}
    f = _File(next(iter(files.values())))
    try:
        info = f.info
    finally:
        f.close()
    return _report_from(started, kind, w, h, {
        "directory": os.fspath(directory), "outputs": files, "bytes": {k: os.path.getsize(p) for k, p in files.items()},
        "header": {"tile_size": info["tile_size"], "max_level": info["max_level"], "channels": c,
                   "border": info["border"]}, "tiles": info["tile_count"]})
