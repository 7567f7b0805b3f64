"""libpyramid for Python: Proland-style terrain tile pyramids as numpy arrays.

Reading (libpyramid-runtime.so)::

    import libpyramid
    with libpyramid.open("DEM.dat") as dem:        # a file, a region set, or a planet directory
        print(dem.info)                           # the header, as a dict
        zf = dem.elevation(0, 0, 0)               # float32 (n + 5, n + 5), row 0 south
        h = dem.height(u=0.5, v=0.5)              # or x=, y= / lon=, lat= through the sidecar

Encoding (libpyramid-encode.so, or the installed programs for input files)::

    report = libpyramid.encode_dem(heights, "DEM.dat", scale=0.1)   # heights: 2-D, row 0 north
    report = libpyramid.encode_ortho(pixels, "ortho/")              # uint8 (h, w[, channels])

Failures raise libpyramid.Error (status, status_name, message: the C API's). See doc/python.md.
"""

from . import _capi
from ._capi import LibraryNotFound, library_paths
from ._errors import ArgumentError, CancelledError, Error, FileError, NotFoundError
from ._paths import resolve as _resolve
from ._planet import Planet
from ._read import Dem, Ortho, Pyramid, _File
from ._encode import encode_dem, encode_ortho

__version__ = "0.2.2"
__all__ = ["open", "Dem", "Ortho", "Planet", "Pyramid", "encode_dem", "encode_ortho", "Error", "ArgumentError",
           "FileError", "NotFoundError", "CancelledError", "LibraryNotFound", "library_paths", "version"]


def version():
    """The loaded C library's version text ("0.2.2")."""
    return _capi.runtime.pyramid_version_string().decode()


def open(path, *, tile_size=0, grid_size=0, cache_tiles=64, scale=0.0, colour_residuals=None, name=None):
    """Opens a pyramid: a Dem (residual file), an Ortho (ortho file) or a Planet (directory).

    `path` is a pyramid file, a region set (its main file with its index beside it, its index
    ``NAME.dat.regions.json``, or the directory holding it), or a planet directory of faces
    ``NAME1.dat`` .. ``NAME6.dat`` (`name`: "DEM" or "RGB" by default). The kind of a file comes
    from its content.

    Dem options (pyramid_elevation_options): `tile_size` (0: the file's), `grid_size`,
    `cache_tiles`, `scale` (0: 1). Ortho options: `colour_residuals` (None: a file under a
    ``residuals`` directory holds colour residuals), `cache_tiles`.
    """
    resolved = _resolve(path, name)
    if resolved.kind == "planet":
        return Planet(resolved, lambda face: open(face, tile_size=tile_size, grid_size=grid_size,
                                                  cache_tiles=cache_tiles, scale=scale,
                                                  colour_residuals=colour_residuals))
    main = _File(resolved.main)
    try:
        if main.info["kind"] == "residual":
            return Dem(resolved, main, tile_size=tile_size, grid_size=grid_size, cache_tiles=cache_tiles, scale=scale)
        return Ortho(resolved, main, colour_residuals=colour_residuals, cache_tiles=cache_tiles)
    except BaseException:
        main.close()
        raise
