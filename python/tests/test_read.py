"""Reading the original tools' DEM.dat and RGB.dat: values pinned from the C test suite and the
docs, and every array equal to what the C API gives a C program (tile_dump.c)."""

import json
import subprocess

import numpy as np
import pytest

import libpyramid
from conftest import DEM, RGB, SAMPLES

TILES = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (1, 0, 1), (1, 1, 1), (2, 3, 1), (3, 5, 2), (4, 9, 14)]


def test_info_is_the_header(dem):
    info = dem.info
    assert info["kind"] == "residual"
    assert (info["min_level"], info["max_level"], info["tile_size"]) == (3, 5, 192)
    assert np.float32(info["scale"]) == np.float32(0.1)
    assert info["tile_count"] == 24 and info["regions"] == []
    assert info["elevation_side"] == 197 and info["georeference"] is None
    assert isinstance(dem, libpyramid.Dem) and list(dem.levels) == [0, 1, 2]


def test_pinned_values():
    # tests/c_api_test.c: the root residual tile and the elevations of tile size 24.
    with libpyramid.open(DEM, tile_size=24) as d:
        r = d.residual(0, 0, 0)
        assert r.dtype == np.int16 and r.shape == (29, 29)
        assert r[0, 0] == 1400 and r[14, 14] == 1470
        zf = d.elevation(0, 0, 0)
        assert zf.dtype == np.float32 and zf.shape == (29, 29)
        assert zf[0, 0] == np.float32(1400) * np.float32(0.1)
        assert zf[14, 14] == np.float32(1470) * np.float32(0.1)
        assert d.height(0.5, 0.5, level=0) == float(zf[14, 14])
        # Half-way east between two samples: their mean.
        assert abs(d.height(0.5 + 0.5 / 24, 0.5, level=0) - (float(zf[14, 14]) + float(zf[14, 15])) / 2) < 1e-9


def test_pinned_loader_output(dem):
    # doc/c-api.md's loader: the height ranges of the root tile and its children.
    expected = {(0, 0, 0): (74.97, 201.98), (1, 0, 0): (78.98, 202.04), (1, 1, 0): (73.01, 204.00),
                (1, 0, 1): (74.03, 203.01), (1, 1, 1): (78.02, 205.01)}
    for (level, tx, ty), (lo, hi) in expected.items():
        inner = dem.elevation(level, tx, ty)[2:-2, 2:-2]
        assert (round(float(inner.min()), 2), round(float(inner.max()), 2)) == (lo, hi)
    # tests/install/install_test.sh: the loader's height at the centre.
    assert f"{dem.height(u=0.5, v=0.5):.3f}" == "147.000"


def test_elevation_tiles_equal_the_c_api(dem, tile_dump):
    ref = tile_dump("elevation", DEM, *[f"{l},{x},{y}" for l, x, y in TILES], dtype=np.float32)
    mine = np.concatenate([dem.elevation(*t).ravel() for t in TILES])
    assert ref.size == len(TILES) * 197 * 197
    assert np.array_equal(ref, mine)
    zf, zc = dem.elevation(2, 3, 1, coarse=True)
    assert np.array_equal(zf, dem.elevation(2, 3, 1)) and not np.array_equal(zf, zc)


def test_residuals_normals_heights_equal_the_c_api(dem, tile_dump):
    stored = [(0, 0, 0), (3, 0, 0), (4, 1, 0), (5, 3, 2)]
    ref = tile_dump("residual", DEM, *[f"{l},{x},{y}" for l, x, y in stored], dtype=np.int16)
    assert np.array_equal(ref, np.concatenate([dem.residual(*t).ravel() for t in stored]))
    ref = tile_dump("normals", DEM, 24000, *[f"{l},{x},{y}" for l, x, y in TILES[:5]], dtype=np.float32)
    mine = [dem.normals(*t, size=24000) for t in TILES[:5]]
    assert mine[0].shape == (193, 193, 4) and np.array_equal(ref, np.concatenate([n.ravel() for n in mine]))
    points = [(0.5, 0.5), (0.1, 0.9), (0.3337, 0.71), (1.0, 0.0)]
    ref = tile_dump("height", DEM, *[f"{u!r},{v!r}" for u, v in points], dtype=np.float64)
    assert ref.tolist() == [dem.height(u, v) for u, v in points]


def test_ortho_tiles_equal_the_c_api(rgb, tile_dump):
    assert rgb.info["kind"] == "ortho" and (rgb.side, rgb.channels) == (196, 4)
    tiles = [(0, 0, 0), (1, 0, 0), (1, 1, 1)]
    ref = tile_dump("ortho", RGB, *[f"{l},{x},{y}" for l, x, y in tiles], dtype=np.uint8)
    mine = [rgb.tile(*t) for t in tiles]
    assert mine[0].dtype == np.uint8 and mine[0].shape == (196, 196, 4)
    assert np.array_equal(ref, np.concatenate([m.ravel() for m in mine]))
    assert np.array_equal(rgb.tile(1, 1, 1), rgb.stored_tile(1, 1, 1))


def test_iteration_over_a_level(dem, rgb):
    seen = [(tx, ty) for tx, ty, _ in dem.tiles(1)]
    assert seen == [(0, 0), (1, 0), (0, 1), (1, 1)]
    for tx, ty, zf in dem.tiles(1):
        assert np.array_equal(zf, dem.elevation(1, tx, ty))
    assert [(tx, ty) for tx, ty, _ in rgb.tiles(1)] == seen
    assert list(rgb.tiles(2)) == []  # RGB.dat stops at level 1


def test_stored_tile_bytes_and_stat(dem):
    stat = dem.tile_info(0, 0, 0)
    assert stat["exists"] == 1 and stat["side"] == 29
    raw = dem.tile_bytes(0, 0, 0)
    assert len(raw) == stat["stored_bytes"] and raw[:2] in (b"II", b"MM")  # a TIFF file


def _encode_sample(tmp_path, name, *extra):
    out = tmp_path / name
    out.parent.mkdir(parents=True, exist_ok=True)
    report = libpyramid.encode_dem(SAMPLES / "dem.tif", out, **dict(extra))
    return out, report


def test_region_set_by_main_file_index_and_directory(tmp_path):
    """A region set (preprocessDem --max-file-bytes) gives the single file's tiles, however named."""
    single, _ = _encode_sample(tmp_path, "single/DEM.dat")
    sharded, report = _encode_sample(tmp_path, "set/DEM.dat", ("max_file_bytes", "60K"))
    assert report["ok"] and "levels" in report
    index = sharded.with_name("DEM.dat.regions.json")
    assert index.exists() and json.loads(index.read_text())["regions"], "the sample did not split into regions"
    with libpyramid.open(single) as ref:
        for path in (sharded, index, sharded.parent):
            with libpyramid.open(path) as s:
                assert s.info["regions"] and s.max_level == ref.max_level
                for level in ref.levels:
                    for tx, ty, zf in ref.tiles(level):
                        assert np.array_equal(zf, s.elevation(level, tx, ty)), (path, level, tx, ty)
                deepest = ref.max_level
                for tx in range(1 << (deepest - 3)):
                    assert np.array_equal(ref.residual(deepest, tx, 0), s.residual(deepest, tx, 0))


def test_height_by_crs_coordinates_equals_pyramid_height(tmp_path, bin_dir, hgt):
    """x=, y= and lon=, lat= through the georeference sidecar, as `pyramid height` places them."""
    out = tmp_path / "DEM.dat"
    libpyramid.encode_dem(hgt, out)
    with libpyramid.open(out) as d:
        g = d.info["georeference"]
        assert g is not None and g["crs"]["kind"] == "geographic", "an .hgt file is placed by its name"
        e = g["root_extent"]
        lon = e["min_x"] + 0.37 * (e["max_x"] - e["min_x"])
        lat = e["min_y"] + 0.61 * (e["max_y"] - e["min_y"])
        for flag in ("--xy", "--lonlat"):
            run = subprocess.run([str(bin_dir / "pyramid"), "height", str(out), flag, f"{lon!r},{lat!r}"], check=True,
                                 capture_output=True, text=True)
            assert abs(d.height(lon=lon, lat=lat) - float(run.stdout)) < 1e-6
        assert d.height(x=lon, y=lat) == d.height(lon=lon, lat=lat)
        assert abs(d.height(x=lon, y=lat) - d.height(0.37, 0.61)) < 1e-6
        with pytest.raises(libpyramid.ArgumentError, match="outside|range|\\[0, 1\\]"):
            d.height(lon=e["max_x"] + 1.0, lat=lat)
    with libpyramid.open(DEM) as d:
        with pytest.raises(libpyramid.ArgumentError, match="georef.json"):
            d.height(x=1.0, y=2.0)


def test_planet_directories(tmp_path, bin_dir):
    """The six faces of the spherical preprocessors; a geodetic height lands on the face and at
    the point `pyramid height --lonlat` names, and that face gives the same height."""
    subprocess.run([str(bin_dir / "preprocessSphericalDem"), "-q", str(SAMPLES / "srtm.png"), "-o",
                    str(tmp_path / "dem"), "--max-level", "3", "--threads", "1"], check=True)
    subprocess.run([str(bin_dir / "preprocessSphericalOrtho"), "-q", str(SAMPLES / "bluemarble.png"), "-o",
                    str(tmp_path / "rgb"), "--max-level", "1", "--threads", "1"], check=True)
    with libpyramid.open(tmp_path / "dem") as planet:
        assert isinstance(planet, libpyramid.Planet) and len(planet) == 6 and planet.info["face_kind"] == "residual"
        for lon, lat in [(-121.7, 46.8), (10.0, -80.0), (135.0, 0.5)]:
            found = planet.height(lon=lon, lat=lat, details=True)
            assert planet.height(lon=lon, lat=lat) == found["height"]
            assert abs(planet[found["face"]].height(found["u"], found["v"]) - found["height"]) < 1e-9
    with libpyramid.open(tmp_path / "rgb") as planet:
        assert planet.info["face_kind"] == "ortho" and planet[6].tile(1, 1, 0).shape == (196, 196, 3)
    with libpyramid.open(tmp_path / "rgb" / "residuals") as planet:
        assert all(face.colour_residuals for face in planet)
    with pytest.raises(IndexError):
        libpyramid.open(tmp_path / "dem")[0]
