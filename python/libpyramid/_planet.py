"""A planet directory: the six cube faces of the spherical preprocessors, each a Dem or an Ortho."""

import json
import os
import subprocess

from . import _capi
from ._errors import Error, from_status


class Planet:
    """The faces ``NAME1.dat`` .. ``NAME6.dat`` of a directory (``planet[1]`` .. ``planet[6]``,
    or ``planet.faces``), each opened as open() opens a file (its region set included).

    ``height(lon=, lat=)`` runs the installed ``pyramid height DIR --lonlat``: the C API has no
    call that places a geodetic point on a cube face (doc/spherical.md).
    """

    def __init__(self, resolved, open_face):
        self.path = os.fspath(resolved.path)
        self.name = resolved.name
        self.faces = []
        try:
            for f in resolved.faces:
                self.faces.append(open_face(f))
        except BaseException:
            self.close()
            raise
        kinds = {face.info["kind"] for face in self.faces}
        self.info = {"kind": "planet", "path": self.path, "name": self.name, "face_kind": kinds.pop(),
                     "faces": [face.info for face in self.faces]}

    def __getitem__(self, face):
        """Face 1..6."""
        if not isinstance(face, int) or not 1 <= face <= 6:
            raise IndexError(f"a planet's faces are 1..6, not {face!r}")
        return self.faces[face - 1]

    def __iter__(self):
        return iter(self.faces)

    def __len__(self):
        return len(self.faces)

    def close(self):
        """Closes every face."""
        for face in self.faces:
            face.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __repr__(self):
        return f"<libpyramid.Planet {self.path!r} {self.name}1..6>"

    def height(self, *, lon, lat, body=None, details=False):
        """The height at geodetic (lon, lat) in degrees on `body` (default wgs84); with
        details=True, the program's report as a dict (height, face, level, tile, u, v)."""
        args = [_capi.program("pyramid"), "height", self.path, "--lonlat", f"{float(lon)!r},{float(lat)!r}",
                "--name", self.name, "--report", "-"]
        if body:
            args += ["--body", body]
        run = subprocess.run(args, capture_output=True, text=True)
        if run.returncode != 0:
            message = run.stderr.strip().splitlines()[-1] if run.stderr.strip() else f"exit {run.returncode}"
            raise from_status(_capi.ERROR_FILE if run.returncode == 1 else _capi.ERROR_ARGUMENT, message=message)
        try:
            report = json.loads(run.stdout)
        except ValueError:
            raise Error(f"pyramid height: unreadable report: {run.stdout[:200]!r}") from None
        return report if details else report["height"]
