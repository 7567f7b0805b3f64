"""Ctrl-C: SIGINT to a Python process in the middle of an encoding stops it, raises
KeyboardInterrupt, and leaves no output and no temporary file behind."""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import libpyramid

CHILD = """
import sys, time
import numpy as np
import libpyramid

source, out = sys.argv[1], sys.argv[2]
started = []

def progress(done, total):
    if not started:
        started.append(done)
        print("started", total, flush=True)
    time.sleep(0.01)  # a slow source: the encoding lasts seconds, whatever the machine

if source == "array":
    source = np.random.default_rng(0).random((2049, 2049), dtype=np.float32) * 1000
try:
    libpyramid.encode_dem(source, out, threads=1, progress=progress)
    print("finished", flush=True)
except KeyboardInterrupt:
    print("interrupted", flush=True)
    sys.exit(130)
"""


def interrupt_child(tmp_path, source):
    out_dir = tmp_path / "out"
    scratch = tmp_path / "scratch"
    out_dir.mkdir()
    scratch.mkdir()
    env = dict(os.environ, TMPDIR=str(scratch),
               PYTHONPATH=str(Path(libpyramid.__file__).resolve().parents[1]))
    child = subprocess.Popen([sys.executable, "-c", CHILD, str(source), str(out_dir / "DEM.dat")], env=env,
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        first = child.stdout.readline()
        assert first.startswith("started"), first + child.stderr.read()
        sent = time.monotonic()
        child.send_signal(signal.SIGINT)
        rest, err = child.communicate(timeout=60)
    finally:
        if child.poll() is None:
            child.kill()
            child.wait()
    stopped_in = time.monotonic() - sent
    assert rest.strip() == "interrupted" and child.returncode == 130, (rest, err)
    assert stopped_in < 10
    left = sorted(str(p.relative_to(tmp_path)) for p in tmp_path.rglob("*") if p.is_file())
    return left


def test_sigint_stops_an_array_encoding_and_leaves_nothing(tmp_path):
    assert interrupt_child(tmp_path, "array") == []


def test_sigint_stops_a_program_encoding_and_leaves_nothing(tmp_path, big_hgt):
    assert interrupt_child(tmp_path, big_hgt) == []


@pytest.mark.parametrize("source", ["array", "program"])
def test_a_cancel_callable_leaves_nothing(tmp_path, source, big_hgt):
    progress = []
    data = big_hgt if source == "program" else np.zeros((1025, 1025), np.float32)
    with pytest.raises(libpyramid.CancelledError):
        libpyramid.encode_dem(data, tmp_path / "DEM.dat", threads=1, progress=lambda d, t: progress.append(d),
                              cancel=lambda: len(progress) > 2)
    assert list(tmp_path.iterdir()) == []
