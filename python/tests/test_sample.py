"""samples/python_pipeline.py runs against the installed package: from an array, and from input
files through the installed programs (the Rainier GeoTIFF when the shared fixtures are there)."""

import pytest

from conftest import RAINIER, SAMPLES, SOURCE, run_python

SCRIPT = SOURCE / "samples" / "python_pipeline.py"
INPUTS = [None, SAMPLES / "dem.tif"] + ([RAINIER] if RAINIER.exists() else [])


@pytest.mark.parametrize("source", INPUTS, ids=lambda p: p.name if p else "array")
def test_pipeline_sample(tmp_path, source):
    args = [str(tmp_path / "out")] + ([str(source)] if source else [])
    run = run_python(f"import runpy, sys; sys.argv = [{str(SCRIPT)!r}] + sys.argv[1:]; "
                     f"runpy.run_path({str(SCRIPT)!r}, run_name='__main__')", *args, timeout=120)
    assert run.returncode == 0, run.stderr
    lines = run.stdout.splitlines()
    assert lines[-1] == "pipeline ok" and lines[0].startswith("DEM: "), run.stdout
    assert (tmp_path / "out" / "DEM.dat").exists() and (tmp_path / "out" / "ortho" / "RGB.dat").exists()


def test_pipeline_sample_usage():
    run = run_python(f"import runpy, sys; sys.argv = [{str(SCRIPT)!r}]; runpy.run_path({str(SCRIPT)!r}, "
                     f"run_name='__main__')")
    assert run.returncode == 2 and "python_pipeline.py OUT_DIR [INPUT.tif]" in run.stderr, run.stderr
