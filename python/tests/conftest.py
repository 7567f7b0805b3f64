"""Fixtures of the Python package's tests, which run against an installed copy (run_tests.sh):
PYRAMID_TEST_PREFIX is the prefix holding the libraries, the programs and the package;
PYRAMID_TEST_SOURCE the source tree (its tests/data and samples)."""

import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import libpyramid

SOURCE = Path(os.environ.get("PYRAMID_TEST_SOURCE", Path(__file__).resolve().parents[2]))
PREFIX = os.environ.get("PYRAMID_TEST_PREFIX")
DATA = SOURCE / "tests" / "data"
DEM = DATA / "proland" / "DEM.dat"
RGB = DATA / "proland" / "RGB.dat"
SAMPLES = SOURCE / "samples"
RAINIER = SOURCE.parent / "shared" / "fixtures" / "inputs" / "mt_rainier_90m.tif"
REQUIRED = os.environ.get("PYRAMID_REQUIRE_PYTHON") == "1"


def pytest_configure(config):
    # The installed copy, never the source tree's python/libpyramid.
    package = Path(libpyramid.__file__).resolve()
    if SOURCE / "python" in package.parents:
        raise pytest.UsageError(f"libpyramid imported from the source tree ({package}): run python/run_tests.sh")
    if PREFIX is None:
        raise pytest.UsageError("PYRAMID_TEST_PREFIX is not set: run python/run_tests.sh")


@pytest.fixture(scope="session")
def prefix():
    return Path(PREFIX)


@pytest.fixture(scope="session")
def bin_dir(prefix):
    return prefix / "bin"


def run_python(code, *args, env=None, **kwargs):
    """Runs `code` in a child interpreter that imports the same installed package."""
    full_env = dict(os.environ, **(env or {}))
    full_env["PYTHONPATH"] = str(Path(libpyramid.__file__).resolve().parents[1])
    return subprocess.run([sys.executable, "-c", code, *args], env=full_env, capture_output=True, text=True, **kwargs)


@pytest.fixture(scope="session")
def tile_dump(prefix, tmp_path_factory):
    """A function running tests/tile_dump.c, built against the installed prefix with the system C
    compiler and pkg-config: returns the bytes the C API gave."""
    cc = shutil.which(os.environ.get("CC", "cc"))
    if cc is None or shutil.which("pkg-config") is None:
        if REQUIRED:
            pytest.fail("PYRAMID_REQUIRE_PYTHON=1 but no C compiler or pkg-config for the C reference")
        pytest.skip("no C compiler or pkg-config: the C reference cannot be built")
    pc = next(prefix.glob("**/pkgconfig/libpyramid-runtime.pc")).parent
    flags = subprocess.run(["pkg-config", "--cflags", "--libs", "libpyramid-runtime"], capture_output=True, text=True,
                           check=True, env=dict(os.environ, PKG_CONFIG_PATH=str(pc))).stdout.split()
    exe = tmp_path_factory.mktemp("tile_dump") / "tile_dump"
    libdir = next(prefix.glob("**/libpyramid-runtime.so")).parent
    subprocess.run([cc, "-std=c99", "-O1", "-o", str(exe), str(Path(__file__).with_name("tile_dump.c")), *flags,
                    f"-Wl,-rpath,{libdir}"], check=True)
    out_dir = tmp_path_factory.mktemp("dumps")

    def run(kind, path, *args, dtype):
        out = out_dir / "dump.bin"
        subprocess.run([str(exe), kind, str(path), str(out), *[str(a) for a in args]], check=True)
        return np.fromfile(out, dtype)

    return run


@pytest.fixture
def dem():
    with libpyramid.open(DEM) as d:
        yield d


@pytest.fixture
def rgb():
    with libpyramid.open(RGB) as o:
        yield o


def smooth_heights(height, width, seed=7):
    """A smooth terrain with some noise, float32, row 0 north."""
    rng = np.random.default_rng(seed)
    x = np.arange(width, dtype=np.float32)[None, :]
    y = np.arange(height, dtype=np.float32)[:, None]
    z = 800 + 300 * np.sin(x / 37) * np.cos(y / 23) + np.float32(0.02 / max(width, 1)) * x * y
    z += rng.standard_normal((height, width), dtype=np.float32) * 2
    return z


def write_hgt(directory, side=1201, name="N46W122.hgt"):
    """An SRTM .hgt file (big-endian int16, georeferenced by its name) of smooth terrain."""
    path = Path(directory) / name
    smooth_heights(side, side).round().astype(">i2").tofile(path)
    return path


@pytest.fixture(scope="session")
def hgt(tmp_path_factory):
    return write_hgt(tmp_path_factory.mktemp("hgt"))


@pytest.fixture(scope="session")
def big_hgt(tmp_path_factory):
    """An SRTM1-sized .hgt (3601 x 3601): its encoding lasts long enough to be interrupted."""
    return write_hgt(tmp_path_factory.mktemp("big_hgt"), side=3601)
