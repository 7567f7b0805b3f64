"""Encoding from arrays, array-likes, callables and input files; read back through the package."""

import numpy as np
import pytest

import libpyramid
from conftest import SAMPLES, smooth_heights


def finest_grid(dem):
    """The finest level's elevations assembled north up: (2^L n + 1) samples per side."""
    level = dem.levels[-1]
    n = dem.tile_size
    count = 1 << level
    grid = np.empty((count * n + 1, count * n + 1), np.float32)
    for tx, ty, zf in dem.tiles(level):
        grid[ty * n:ty * n + n + 1, tx * n:tx * n + n + 1] = zf[2:-2, 2:-2]
    return grid[::-1]


def finest_image(ortho):
    level = ortho.levels[-1]
    n = ortho.side - 2 * ortho.info["border"]
    b = ortho.info["border"]
    image = np.zeros(((1 << level) * n, (1 << level) * n, ortho.channels), np.uint8)
    for tx, ty, pixels in ortho.tiles(level):
        image[ty * n:ty * n + n, tx * n:tx * n + n] = pixels[b:-b or None, b:-b or None]
    return image[::-1]


@pytest.fixture(scope="module")
def heights():
    return smooth_heights(385, 385)


def test_encode_dem_round_trip_within_half_a_step(tmp_path, heights):
    out = tmp_path / "DEM.dat"
    report = libpyramid.encode_dem(heights, out, scale=0.25)
    assert report["ok"] and report["output"] == str(out) and report["input"]["source"] == "array"
    assert report["header"] == {"max_level": 4, "min_level": 3, "scale": 0.25, "tile_size": 192}
    assert report["bytes"] == out.stat().st_size and report["tiles"] > 0
    with libpyramid.open(out) as dem:
        grid = finest_grid(dem)
        assert grid.shape == heights.shape
        error = np.abs(grid.astype(np.float64) - heights)
        assert error.max() <= 0.25 / 2 + 1e-3, error.max()
        assert error.max() > 0.01  # a real quantisation, not a copy
    assert not list(tmp_path.glob("*tmp*"))


def test_other_dtypes_array_likes_and_callables_give_the_same_bytes(tmp_path, heights):
    """float64 and int arrays are read by windows, as an array-like or a callable is: same file."""
    ref = tmp_path / "ref.dat"
    libpyramid.encode_dem(heights, ref, scale=0.5)
    as_int = heights.round().astype(np.int16)
    libpyramid.encode_dem(as_int.astype(np.float32), tmp_path / "int_ref.dat", scale=0.5)
    windows = []

    def read(x0, y0, x1, y1):
        windows.append((x0, y0, x1, y1))
        return heights[y0:y1, x0:x1]

    class Lazy:  # an array-like: shape and slicing only (h5py, zarr, np.memmap)
        shape = heights.shape

        def __getitem__(self, key):
            return heights[key]

    cases = {"f64": heights.astype(np.float64), "fortran": np.asfortranarray(heights), "lazy": Lazy(),
             "callable": read}
    for name, source in cases.items():
        out = tmp_path / f"{name}.dat"
        extra = {"width": 385, "height": 385} if name == "callable" else {}
        report = libpyramid.encode_dem(source, out, scale=0.5, **extra)
        assert out.read_bytes() == ref.read_bytes(), name
        assert report["input"]["source"] in ("array windows", "callable")
    assert windows and all(x1 - x0 <= 385 and y1 - y0 <= 385 for x0, y0, x1, y1 in windows)
    raw = tmp_path / "heights.i16"
    as_int.tofile(raw)
    mapped = np.memmap(raw, np.int16, "r", shape=as_int.shape)  # data larger than memory, read by windows
    libpyramid.encode_dem(mapped, tmp_path / "mapped.dat", scale=0.5)
    assert (tmp_path / "mapped.dat").read_bytes() == (tmp_path / "int_ref.dat").read_bytes()


def test_callable_errors_propagate_and_leave_nothing(tmp_path, heights):
    def broken(x0, y0, x1, y1):
        if y0 > 100:
            raise RuntimeError("the disk went away")
        return heights[y0:y1, x0:x1]

    with pytest.raises(RuntimeError, match="the disk went away"):
        libpyramid.encode_dem(broken, tmp_path / "DEM.dat", width=385, height=385)
    with pytest.raises(ValueError, match=r"has shape \(1, 1\)"):
        libpyramid.encode_dem(lambda *w: np.zeros((1, 1)), tmp_path / "DEM.dat", width=385, height=385)
    assert list(tmp_path.iterdir()) == []


def test_options_auto_scale_fit_and_codecs(tmp_path):
    heights = smooth_heights(201, 201) * 40  # too tall for int16 steps of 1
    report = libpyramid.encode_dem(heights, tmp_path / "a.dat", scale="auto", tile_size="auto",
                                   compression="context", threads=1)
    scale = report["header"]["scale"]
    assert scale > 1 and str(scale)[0] in "125"
    with libpyramid.open(tmp_path / "a.dat") as dem:
        grid = finest_grid(dem)
        assert grid.shape == heights.shape  # tiles fitted to the map's own grid
        assert np.abs(grid - heights).max() <= scale / 2 * 1.001
    with pytest.raises(libpyramid.ArgumentError, match="tileSize: 7"):
        libpyramid.encode_dem(heights, tmp_path / "b.dat", tile_size=7)
    with pytest.raises(ValueError, match="compression 'zip'"):
        libpyramid.encode_dem(heights, tmp_path / "b.dat", compression="zip")
    assert not (tmp_path / "b.dat").exists()


def test_progress_and_cancel(tmp_path, heights):
    seen = []
    libpyramid.encode_dem(heights, tmp_path / "a.dat", progress=lambda done, total: seen.append((done, total)))
    assert seen and seen[-1][0] == seen[-1][1] and [d for d, _ in seen] == sorted(d for d, _ in seen)
    calls = []
    with pytest.raises(libpyramid.CancelledError) as e:
        libpyramid.encode_dem(heights, tmp_path / "b.dat", cancel=lambda: calls.append(1) or len(calls) > 2)
    assert e.value.status == 6 and e.value.status_name == "cancelled"
    assert not (tmp_path / "b.dat").exists() and sorted(p.name for p in tmp_path.iterdir()) == ["a.dat"]


def test_encode_ortho_round_trip_is_lossless(tmp_path):
    rng = np.random.default_rng(5)
    for channels in (1, 3, 4):
        image = rng.integers(0, 256, (384, 384, channels), dtype=np.uint8)
        if channels == 1:
            image = image[:, :, 0]
        out = tmp_path / f"c{channels}"
        report = libpyramid.encode_ortho(image, out, outputs=["tiff", "residuals"])
        assert set(report["outputs"]) == {"tiff", "residuals"} and report["header"]["channels"] == channels
        assert not (out / "dxt").exists()
        expected = image.reshape(384, 384, channels)
        with libpyramid.open(out / "RGB.dat") as tiff:
            assert np.array_equal(finest_image(tiff), expected)
        with libpyramid.open(out / "residuals" / "RGB.dat") as residuals:
            # Colour residuals are quantised: within 1 of the input (the report's residual_max_error).
            difference = np.abs(finest_image(residuals).astype(int) - expected)
            assert residuals.colour_residuals and difference.max() <= 1


def test_encode_ortho_fits_the_tiles_to_the_image(tmp_path):
    # 512 x 256: 256-tiles, the image pixel for pixel (192-tiles would resample it onto 768), by
    # default as with "auto" (whose fit ignores the C struct's max_level).
    image = np.random.default_rng(7).integers(0, 256, (256, 512, 3), dtype=np.uint8)
    for name, options in (("a", dict(tile_size="auto", max_level=5)), ("b", {})):
        report = libpyramid.encode_ortho(image, tmp_path / name, outputs=["tiff"], **options)
        assert (report["header"]["tile_size"], report["header"]["max_level"]) == (256, 1)
        with libpyramid.open(tmp_path / name / "RGB.dat") as tiff:
            assert np.array_equal(finest_image(tiff)[:256], image)
    # Levels given without a tile size: the original tools' 192, as preprocessOrtho --max-level.
    report = libpyramid.encode_ortho(image, tmp_path / "c", outputs=["tiff"], max_level=2)
    assert (report["header"]["tile_size"], report["header"]["max_level"]) == (192, 2)


def test_encode_ortho_callable_and_errors(tmp_path):
    image = np.random.default_rng(6).integers(0, 256, (200, 300, 3), dtype=np.uint8)
    libpyramid.encode_ortho(image, tmp_path / "a", outputs="tiff")
    libpyramid.encode_ortho(lambda x0, y0, x1, y1: image[y0:y1, x0:x1], tmp_path / "b", outputs="tiff", width=300,
                            height=200, channels=3)
    assert (tmp_path / "a" / "RGB.dat").read_bytes() == (tmp_path / "b" / "RGB.dat").read_bytes()
    with pytest.raises(TypeError, match="uint8"):
        libpyramid.encode_ortho(image.astype(np.float32), tmp_path / "c")
    with pytest.raises(ValueError, match="outputs"):
        libpyramid.encode_ortho(image, tmp_path / "c", outputs=["png"])
    with pytest.raises(libpyramid.ArgumentError, match="channels"):
        libpyramid.encode_ortho(np.zeros((10, 10, 5), np.uint8), tmp_path / "c")
    assert not (tmp_path / "c").exists() or not any((tmp_path / "c").rglob("*.dat"))


def test_encode_from_input_files_runs_the_programs(tmp_path):
    report = libpyramid.encode_dem(SAMPLES / "dem.tif", tmp_path / "DEM.dat", scale=0.5, threads=1)
    assert report["ok"] and report["header"]["scale"] == 0.5 and report["levels"]
    with libpyramid.open(tmp_path / "DEM.dat") as dem:
        assert dem.info["tile_count"] == report["tiles"]
    report = libpyramid.encode_ortho(SAMPLES / "srtm.png", tmp_path / "ortho", outputs=["tiff"], max_level=2)
    assert report["ok"] and report["max_level"] == 2
    with libpyramid.open(tmp_path / "ortho" / "RGB.dat") as ortho:
        assert ortho.channels == report["input"]["channels"]
    with pytest.raises(libpyramid.FileError, match="nothing.tif"):
        libpyramid.encode_dem(tmp_path / "nothing.tif", tmp_path / "x.dat")
    with pytest.raises(libpyramid.ArgumentError, match="--bogus"):
        libpyramid.encode_dem(SAMPLES / "dem.tif", tmp_path / "x.dat", bogus=3)
    assert not (tmp_path / "x.dat").exists()
