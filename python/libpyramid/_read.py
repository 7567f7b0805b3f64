"""Reading: a pyramid file or region set as a Dem or an Ortho, tiles as numpy arrays.

Tiles keep the C API's layout: row-major, row 0 = the tile's south row (``np.flipud`` gives
north up). Every call below is one or a few C calls, during which the GIL is released; the
handles are the C API's, which several threads may share.
"""

import ctypes
import os
import threading

import numpy as np

from . import _capi
from ._errors import ArgumentError, NotFoundError, check
from ._paths import read_georeference

_lib = _capi.runtime
_KIND_NAMES = {_capi.KIND_RESIDUAL: "residual", _capi.KIND_ORTHO: "ortho"}
_INFO_FIELDS = ("max_level", "tile_size", "root_level", "root_tx", "root_ty", "min_level", "scale", "channels",
                "border", "dxt", "tile_count", "source_size", "data_offset", "stored_tiles", "distinct_tiles")


def _path_source(path):
    src = _capi.sized(_capi.pyramid_source)
    src.kind = _capi.SOURCE_PATH
    src.path = _capi.fspath(path)
    return src


def _sources(resolved):
    """A set's main file and its regions as path sources (a pointer array, its sources kept)."""
    main = _path_source(resolved.main)
    keep = [_path_source(r.path) for r in resolved.regions]
    regions = (ctypes.POINTER(_capi.pyramid_source) * max(len(keep), 1))(*[ctypes.pointer(k) for k in keep])
    regions._keep = keep
    return main, regions


class _File:
    """One pyramid file opened with pyramid_open: its header and its stored tiles."""

    def __init__(self, path):
        self.path = os.fspath(path)
        handle = ctypes.c_void_p()
        check(_lib.pyramid_open(_capi.fspath(path), ctypes.byref(handle)))
        self.handle = handle
        info = _capi.sized(_capi.pyramid_file_info)
        check(_lib.pyramid_get_file_info(handle, ctypes.byref(info)))
        self.info = {"kind": _KIND_NAMES.get(info.kind, str(info.kind))}
        self.info.update({name: getattr(info, name) for name in _INFO_FIELDS})
        self.info["scale"] = float(str(np.float32(info.scale)))  # the header's float32, as written

    def close(self):
        if self.handle:
            _lib.pyramid_close(self.handle)
            self.handle = None

    def read(self, level, tx, ty, dtype):
        """The decoded tile: int16 residuals (side, side) or bytes (side, side, channels)."""
        side = ctypes.c_int()
        check(_lib.pyramid_tile_side(self.handle, level, ctypes.byref(side)), where=self.path)
        n = side.value
        shape = (n, n) if dtype == np.int16 else (n, n, self.info["channels"])
        out = np.empty(shape, dtype)
        check(_lib.pyramid_read_tile(self.handle, level, tx, ty, out.ctypes.data, out.nbytes, None), where=self.path)
        return out

    def read_bytes(self, level, tx, ty):
        """The tile as stored (a TIFF file, or DXT blocks)."""
        needed = ctypes.c_size_t()
        check(_lib.pyramid_read_tile_bytes(self.handle, level, tx, ty, None, 0, ctypes.byref(needed)), where=self.path)
        buf = ctypes.create_string_buffer(needed.value)
        check(_lib.pyramid_read_tile_bytes(self.handle, level, tx, ty, buf, needed.value, None), where=self.path)
        return buf.raw


class Pyramid:
    """What Dem and Ortho share: the header (``info``), stored tiles, the files of a set.

    Levels and tile coordinates of ``stored_tile``/``tile_bytes``/``residual`` are the files'
    (pyramid_read_tile): absolute (the main file's) for a region set, whose tiles come from the
    deepest file holding them. The producers' (``elevation``, ``normals``, ``tile``) are the
    quadtree's, levels 0..30.
    """

    def __init__(self, resolved, main_file):
        self.path = os.fspath(resolved.path)
        self._resolved = resolved
        self._main = main_file
        self._regions = None  # [(region, _File)], opened on first use
        self._lock = threading.Lock()
        self.info = dict(main_file.info)
        self.info["path"] = self.path
        self.info["file"] = os.fspath(resolved.main)
        self.info["regions"] = [{"file": os.fspath(r.path), "root": list(r.root)} for r in resolved.regions]

    # -- lifetime
    def close(self):
        """Closes the C handles (also done when the object is collected)."""
        self._close_producers()
        if self._regions:
            for _, f in self._regions:
                f.close()
        self._regions = None
        if self._main is not None:
            self._main.close()
            self._main = None

    def _close_producers(self):
        pass

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __del__(self):
        try:
            self.close()
        except Exception:
            pass

    def __repr__(self):
        return f"<libpyramid.{type(self).__name__} {self.path!r} levels {self.info['min_level']}..{self.max_level}>"

    # -- stored tiles
    def _file_of(self, level, tx, ty):
        """(the file holding stored tile (level, tx, ty), its coordinates in that file)."""
        if not self._resolved.regions:
            return self._main, level, tx, ty
        with self._lock:
            if self._regions is None:
                regions = sorted(self._resolved.regions, key=lambda r: -r.root[0])
                self._regions = [(r, _File(r.path)) for r in regions]
        for region, f in self._regions:
            rl, rx, ry = region.root
            d = level - rl
            if d >= 0 and tx >> d == rx and ty >> d == ry and d <= f.info["max_level"]:
                return f, d, tx - (rx << d), ty - (ry << d)
        return self._main, level, tx, ty

    def tile_bytes(self, level, tx, ty):
        """A stored tile's bytes as the file holds them (a TIFF file, or raw DXT blocks)."""
        self._check_tile(level, tx, ty)
        f, level, tx, ty = self._file_of(level, tx, ty)
        return f.read_bytes(level, tx, ty)

    def tile_info(self, level, tx, ty):
        """pyramid_tile_stat of a stored tile as a dict: exists, side, channels, stored_bytes,
        decoded_bytes, offset, and the file holding it."""
        self._check_tile(level, tx, ty)
        f, level, tx, ty = self._file_of(level, tx, ty)
        info = _capi.sized(_capi.pyramid_tile_info)
        check(_lib.pyramid_tile_stat(f.handle, level, tx, ty, ctypes.byref(info)), where=f.path)
        names = ("exists", "side", "channels", "stored_bytes", "decoded_bytes", "offset")
        return dict({n: getattr(info, n) for n in names}, file=f.path)

    @property
    def max_level(self):
        """The deepest stored level, absolute (a region set's deepest region included)."""
        deepest = self.info["max_level"]
        for r in self._resolved.regions:
            f = self._file_of(r.root[0], r.root[1], r.root[2])[0]
            deepest = max(deepest, r.root[0] + f.info["max_level"])
        return deepest

    @property
    def closed(self):
        """True once close() has run."""
        return self._main is None

    def _check_open(self):
        if self._main is None:
            raise ValueError(f"{self.path}: the pyramid is closed")

    def _check_tile(self, level, tx, ty):
        self._check_open()
        for name, v in (("level", level), ("tx", tx), ("ty", ty)):
            if not isinstance(v, (int, np.integer)) or isinstance(v, bool):
                raise TypeError(f"{name} must be an integer, not {type(v).__name__}")
            if not -2**31 <= v < 2**31:
                raise NotFoundError(f"tile ({level}, {tx}, {ty}): {name} {v} is outside any pyramid",
                                    _capi.ERROR_NOT_FOUND, "not_found")


class Dem(Pyramid):
    """A residual (DEM) pyramid: a file or a region set, with its elevation producer.

    ``tile_size``, ``grid_size``, ``cache_tiles`` and ``scale`` are pyramid_elevation_options'
    (0: the file's tile size, the tile size, 1 and 1).
    """

    def __init__(self, resolved, main_file, tile_size=0, grid_size=0, cache_tiles=64, scale=0.0):
        super().__init__(resolved, main_file)
        handle = ctypes.c_void_p()
        if not scale:
            # The path open takes a file or a region set (main file, index or directory) and
            # checks the set's rules.
            check(_lib.pyramid_elevation_open(_capi.fspath(resolved.path), tile_size, grid_size, cache_tiles,
                                              ctypes.byref(handle)))
        else:
            # The scale option exists with sources only, which take a set's files one by one.
            opts = _capi.sized(_capi.pyramid_elevation_options)
            opts.tile_size, opts.grid_size, opts.cache_tiles, opts.scale = tile_size, grid_size, cache_tiles, scale
            main, regions = _sources(resolved)
            check(_lib.pyramid_elevation_open_sources(ctypes.byref(main), regions, len(regions._keep),
                                                      ctypes.byref(opts), ctypes.byref(handle)))
        self._elevation = handle
        self._normals = {}
        self.side = _lib.pyramid_elevation_side(handle)
        self.tile_size = self.side - 5
        # Producer level p holds the residuals of file level p + delta (doc/c-api.md).
        k = (self.info["tile_size"] // self.tile_size).bit_length() - 1
        self.level_delta = self.info["min_level"] - k
        self.georeference = read_georeference(resolved.main)
        self.info["elevation_side"] = self.side
        self.info["georeference"] = self.georeference

    def _close_producers(self):
        for h in getattr(self, "_normals", {}).values():
            _lib.pyramid_normal_close(h)
        self._normals = {}
        if getattr(self, "_elevation", None):
            _lib.pyramid_elevation_close(self._elevation)
            self._elevation = None

    @property
    def levels(self):
        """The producer's levels that hold residuals: range(0, deepest + 1)."""
        return range(0, self.max_level - self.level_delta + 1)

    def residual(self, level, tx, ty):
        """A stored tile's int16 residuals, (side, side), unscaled (times info["scale"] are
        heights), in the files' levels (pyramid_read_tile)."""
        self._check_tile(level, tx, ty)
        f, level, tx, ty = self._file_of(level, tx, ty)
        return f.read(level, tx, ty, np.int16)

    def elevation(self, level, tx, ty, coarse=False):
        """Quadtree tile (level, tx, ty)'s float32 elevations zf, (side, side), side = n + 5,
        row 0 south; with coarse=True, (zf, zc), zc the coarse elevations (pyramid_elevation_tile)."""
        self._check_tile(level, tx, ty)
        n = self.side * self.side
        zf = np.empty((self.side, self.side), np.float32)
        zc = np.empty((self.side, self.side), np.float32) if coarse else None
        check(_lib.pyramid_elevation_tile(self._elevation, level, tx, ty, zf.ctypes.data,
                                          zc.ctypes.data if coarse else None, None, n), where=self.path)
        return (zf, zc) if coarse else zf

    def tiles(self, level, coarse=False):
        """Every tile of a producer level, in row order from the south: (tx, ty, elevation)."""
        for ty in range(1 << level):
            for tx in range(1 << level):
                yield tx, ty, self.elevation(level, tx, ty, coarse)

    def normals(self, level, tx, ty, size, deformation="plane", cache_tiles=16):
        """Quadtree tile (level, tx, ty)'s normals, float32 (n + 1, n + 1, 4): nx, ny, ncx, ncy per
        vertex (doc/shading.md). `size` is the root quad's side ("plane") or the sphere's radius
        ("sphere"), in height units."""
        self._check_tile(level, tx, ty)
        deform = {"plane": _capi.DEFORM_PLANE, "sphere": _capi.DEFORM_SPHERE}.get(deformation)
        if deform is None:
            raise ValueError(f"deformation must be 'plane' or 'sphere', not {deformation!r}")
        key = (deform, float(size))
        with self._lock:
            handle = self._normals.get(key)
            if handle is None:
                opts = _capi.sized(_capi.pyramid_normal_options)
                opts.deformation, opts.size, opts.cache_tiles = deform, float(size), cache_tiles
                handle = ctypes.c_void_p()
                check(_lib.pyramid_normal_open(self._elevation, ctypes.byref(opts), ctypes.byref(handle)), where=self.path)
                self._normals[key] = handle
        side = _lib.pyramid_normal_side(handle)
        out = np.empty((side, side, 4), np.float32)
        check(_lib.pyramid_normal_tile(handle, level, tx, ty, out.ctypes.data, out.size), where=self.path)
        return out

    def height(self, u=None, v=None, *, x=None, y=None, lon=None, lat=None, level=-1):
        """The height at a point (pyramid_elevation_height, double precision), given as

        * ``u, v``: fractions of the root quad, east and north from its south-west corner;
        * ``x=, y=``: the input's CRS units, placed by the georeference sidecar preprocessDem wrote;
        * ``lon=, lat=``: degrees, for a file whose sidecar's CRS is geographic.

        ``level`` -1 is the deepest level with residuals.
        """
        if lon is not None or lat is not None:
            g = self._georeference("lon=, lat=")
            if g.get("crs", {}).get("kind") != "geographic":
                raise ArgumentError(f"{self.path}: lon=, lat= need a geographic CRS; its sidecar's is "
                                    f"{g.get('crs', {}).get('name')!r}: give x=, y=", _capi.ERROR_ARGUMENT, "argument")
            x, y = lon, lat
        if x is not None or y is not None:
            if x is None or y is None:
                raise TypeError("height() needs both x= and y= (or lon= and lat=)")
            g = self._georeference("x=, y=")
            e = g["root_extent"]
            u = (float(x) - e["min_x"]) / (e["max_x"] - e["min_x"])
            v = (float(y) - e["min_y"]) / (e["max_y"] - e["min_y"])
        if u is None or v is None:
            raise TypeError("height() needs u, v, or x=, y=, or lon=, lat=")
        self._check_open()
        h = ctypes.c_double()
        check(_lib.pyramid_elevation_height(self._elevation, level, float(u), float(v), ctypes.byref(h)), where=self.path)
        return h.value

    def _georeference(self, what):
        g = self.georeference
        if g is None:
            raise ArgumentError(f"{self.path}: {what} need the georeference sidecar "
                                f"{self.info['file']}.georef.json, which is not there", _capi.ERROR_ARGUMENT,
                                "argument")
        if g.get("rotated"):
            raise ArgumentError(f"{self.path}: a rotated georeference: give u, v", _capi.ERROR_ARGUMENT, "argument")
        return g


class Ortho(Pyramid):
    """An ortho (imagery) pyramid: a file or a region set, with its ortho producer.

    ``colour_residuals``: the file holds colour residuals (``residuals/RGB.dat``) and tiles are
    rebuilt by the colour upsample; None takes it from the path (a file in a ``residuals``
    directory).
    """

    def __init__(self, resolved, main_file, colour_residuals=None, cache_tiles=64):
        super().__init__(resolved, main_file)
        if colour_residuals is None:
            colour_residuals = os.path.basename(os.path.dirname(os.path.abspath(resolved.main))) == "residuals"
        handle = ctypes.c_void_p()
        check(_lib.pyramid_ortho_open(_capi.fspath(resolved.path), int(bool(colour_residuals)), cache_tiles,
                                      ctypes.byref(handle)))
        self._ortho = handle
        side, channels = ctypes.c_int(), ctypes.c_int()
        check(_lib.pyramid_ortho_layout(handle, ctypes.byref(side), ctypes.byref(channels)))
        self.side, self.channels = side.value, channels.value
        self.colour_residuals = bool(colour_residuals)
        self.info["colour_residuals"] = self.colour_residuals

    def _close_producers(self):
        if getattr(self, "_ortho", None):
            _lib.pyramid_ortho_close(self._ortho)
            self._ortho = None

    @property
    def levels(self):
        """The stored levels: range(0, deepest + 1)."""
        return range(0, self.max_level + 1)

    def tile(self, level, tx, ty):
        """Quadtree tile (level, tx, ty)'s pixels, uint8 (side, side, channels), row 0 south
        (pyramid_ortho_tile: decoded, DXT as RGB(A), or rebuilt from colour residuals)."""
        self._check_tile(level, tx, ty)
        out = np.empty((self.side, self.side, self.channels), np.uint8)
        check(_lib.pyramid_ortho_tile(self._ortho, level, tx, ty, out.ctypes.data, out.nbytes), where=self.path)
        return out

    def stored_tile(self, level, tx, ty):
        """A stored tile as the file decodes it (pyramid_read_tile): residuals as stored."""
        self._check_tile(level, tx, ty)
        f, level, tx, ty = self._file_of(level, tx, ty)
        return f.read(level, tx, ty, np.uint8)

    def tiles(self, level):
        """The tiles of a level that exist, in row order from the south: (tx, ty, pixels)."""
        for ty in range(1 << level):
            for tx in range(1 << level):
                try:
                    pixels = self.tile(level, tx, ty)
                except NotFoundError:
                    continue
                yield tx, ty, pixels
