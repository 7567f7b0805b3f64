"""Errors: exceptions carrying the C API's status and message; hostile files never crash."""

import numpy as np
import pytest

import libpyramid
from conftest import DEM, RGB, run_python


def test_missing_file(tmp_path):
    with pytest.raises(libpyramid.FileError) as e:
        libpyramid.open(tmp_path / "none.dat")
    assert e.value.status == 2 and e.value.status_name == "file"
    assert str(e.value) == f"{tmp_path / 'none.dat'}: cannot open: No such file or directory"
    assert isinstance(e.value, libpyramid.Error) and "\n" not in str(e.value)


def test_bad_tile_coordinates(dem, rgb):
    with pytest.raises(libpyramid.NotFoundError) as e:
        dem.elevation(1, 2, 0)
    assert e.value.status == 5 and str(DEM) in str(e.value) and "(1,2,0)" in str(e.value)
    for bad in [(31, 0, 0), (-1, 0, 0), (0, 0, 1 << 40)]:
        with pytest.raises(libpyramid.NotFoundError):
            dem.elevation(*bad)
    with pytest.raises(libpyramid.NotFoundError):
        dem.residual(2, 1, 0)  # below minLevel: one tile per level
    with pytest.raises(libpyramid.NotFoundError):
        rgb.tile(2, 0, 0)  # RGB.dat stops at level 1
    with pytest.raises(TypeError, match="level must be an integer"):
        dem.elevation(0.5, 0, 0)
    with pytest.raises(libpyramid.ArgumentError) as e:
        dem.height(1.5, 0.5)
    assert e.value.status == 1 and isinstance(e.value, ValueError)
    with pytest.raises(TypeError, match="needs u, v"):
        dem.height()


def test_closed_pyramids():
    d = libpyramid.open(DEM)
    d.close()
    assert d.closed
    for call in (lambda: d.elevation(0, 0, 0), lambda: d.residual(0, 0, 0), lambda: d.height(0.5, 0.5),
                 lambda: d.normals(0, 0, 0, size=1)):
        with pytest.raises(ValueError, match="closed"):
            call()
    d.close()  # twice is fine


def test_bad_producer_options():
    with pytest.raises(libpyramid.ArgumentError, match=str(DEM)):
        libpyramid.open(DEM, tile_size=100)  # not 192 / 2^k
    with pytest.raises(libpyramid.ArgumentError, match="size"):
        libpyramid.open(DEM).normals(0, 0, 0, size=0)
    with pytest.raises(ValueError, match="deformation"):
        libpyramid.open(DEM).normals(0, 0, 0, size=1, deformation="torus")


def test_wrong_dtype_or_shape(tmp_path):
    out = tmp_path / "DEM.dat"
    with pytest.raises(TypeError, match="real numbers"):
        libpyramid.encode_dem(np.zeros((10, 10), complex), out)
    with pytest.raises(TypeError, match="real numbers"):
        libpyramid.encode_dem(np.zeros((10, 10), bool), out)
    with pytest.raises(ValueError, match=r"shape \(10, 10, 2\)"):
        libpyramid.encode_dem(np.zeros((10, 10, 2), np.float32), out)
    with pytest.raises(ValueError, match=r"shape \(10,\)"):
        libpyramid.encode_dem(np.zeros(10, np.float32), out)
    with pytest.raises(TypeError, match="not dict"):
        libpyramid.encode_dem({}, out)
    with pytest.raises(TypeError, match="width= and height="):
        libpyramid.encode_dem(lambda *w: None, out)
    with pytest.raises(TypeError, match="apply to input files only"):
        libpyramid.encode_dem(np.zeros((10, 10), np.float32), out, max_file_bytes="1M")
    assert list(tmp_path.iterdir()) == []


HOSTILE = {
    "empty": lambda data: b"",
    "truncated header": lambda data: data[:40],
    "truncated tiles": lambda data: data[: len(data) // 2],
    "garbage": lambda data: np.random.default_rng(9).integers(0, 256, len(data), dtype=np.uint8).tobytes(),
    "garbage tiles": lambda data: data[:300] + np.random.default_rng(2).integers(0, 256, len(data) - 300,
                                                                                 dtype=np.uint8).tobytes(),
}


@pytest.mark.parametrize("name", sorted(HOSTILE))
@pytest.mark.parametrize("original", [DEM, RGB], ids=["DEM", "RGB"])
def test_hostile_files_raise_not_crash(tmp_path, original, name):
    bad = tmp_path / "bad.dat"
    bad.write_bytes(HOSTILE[name](original.read_bytes()))
    # In a child: a crash there fails the test instead of ending the run.
    code = """
import sys, libpyramid
try:
    p = libpyramid.open(sys.argv[1])
except libpyramid.FileError as e:
    print("open:", e); sys.exit(0)
failures = 0
for level in p.levels:
    for tx in range(1 << level):
        for ty in range(1 << level):
            try:
                p.elevation(level, tx, ty) if isinstance(p, libpyramid.Dem) else p.tile(level, tx, ty)
            except (libpyramid.FileError, libpyramid.NotFoundError) as e:
                failures += 1
                assert sys.argv[1] in str(e) or "(" in str(e), e
print("tiles failed:", failures)
"""
    run = run_python(code, str(bad), timeout=60)
    assert run.returncode == 0, run.stderr
    if name == "garbage tiles":  # the header and offset table hold: the tiles fail one by one
        assert run.stdout.startswith("tiles failed:") and run.stdout.split()[-1] != "0", run.stdout
    else:
        assert run.stdout.startswith("open: " + str(bad)), run.stdout


def test_library_not_found_is_a_clear_import_error(tmp_path):
    run = run_python("import libpyramid", env={"PYRAMID_LIBRARY": str(tmp_path / "nothing.so")})
    assert run.returncode != 0 and "PYRAMID_LIBRARY=" in run.stderr and "does not exist" in run.stderr


def test_library_named_by_environment(prefix):
    lib = next(prefix.glob("**/libpyramid-runtime.so.0.2"))
    run = run_python("import libpyramid; print(libpyramid.library_paths()['runtime'])",
                     env={"PYRAMID_LIBRARY": str(lib.parent)})
    assert run.returncode == 0 and run.stdout.strip() == str(lib)
    # Without it the installed prefix is found from the package's own place.
    run = run_python("import libpyramid; print(libpyramid.library_paths()['runtime'])", env={"PYRAMID_LIBRARY": ""})
    assert run.returncode == 0 and run.stdout.strip().startswith(str(prefix))
